/* Penetration depth of points into collision shapes and the penalty energy of the
 * layered envelopes (thesis 004 §4.1.2), with exact gradients and Hessians. */
#include <float.h>

#include "hairkit/collide.h"

/* Below this fraction of the smallest radius a point counts as the centre, where the
 * radial measures have no direction: dent is the smallest radius, derivatives zero. */
#define CENTRE_FRACTION 1e-9

static double min3(hk_Vec3 v) { return fmin(v.x, fmin(v.y, v.z)); }

/* Rotates a local gradient and Hessian (in the shape's axes U, V, W) to world. */
static void to_world(const hk_Shape *s, hk_Vec3 gl, const hk_Mat3 *hl, hk_Vec3 *grad, hk_Mat3 *hess)
{
    const hk_Mat3 r = hk_m3_from_cols(s->axis[0], s->axis[1], s->axis[2]);
    if (grad) *grad = hk_m3_mul_v3(&r, gl);
    if (hess) {
        hk_Mat3 t = hk_m3_mul(&r, hl), rt = hk_m3_transpose(&r);
        *hess = hk_m3_mul(&t, &rt);
    }
}

static double sphere_dent(const hk_Shape *s, hk_Vec3 d, hk_Vec3 *grad, hk_Mat3 *hess)
{
    const double r = s->half.x, q = hk_v3_norm(d);
    if (q <= CENTRE_FRACTION * r) {
        if (grad) *grad = hk_v3_zero();
        if (hess) *hess = hk_m3_zero();
        return r;
    }
    const hk_Vec3 n = hk_v3_scale(d, 1.0 / q);
    if (grad) *grad = hk_v3_neg(n);
    if (hess) {
        /* d2(-|d|) = -(I - n n^T) / |d| */
        hk_Mat3 o = hk_m3_outer(n, n);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) hess->m[i][j] = ((i == j) - o.m[i][j]) / -q;
    }
    return r - q;
}

/* Thesis §4.1.2.1.1: dent = q / rho - q with q = |p| and rho = |(pU/a, pV/b, pW/c)|,
 * the distance from p to the surface along the ray from the centre. In local axes,
 * with A = diag(1/a^2, 1/b^2, 1/c^2):
 *   grad q = n,              hess q = (I - n n^T) / q
 *   grad rho = A p / rho,    hess rho = A / rho - (A p)(A p)^T / rho^3
 *   grad dent = n (1/rho - 1) - q grad rho / rho^2
 *   hess dent = hess q (1/rho - 1) - (n grad rho^T + grad rho n^T) / rho^2
 *               - q hess rho / rho^2 + 2 q grad rho grad rho^T / rho^3 */
static double ellipsoid_dent(const hk_Shape *s, hk_Vec3 d, hk_Vec3 *grad, hk_Mat3 *hess)
{
    const hk_Vec3 p = hk_v3(hk_v3_dot(d, s->axis[0]), hk_v3_dot(d, s->axis[1]), hk_v3_dot(d, s->axis[2]));
    const double q = hk_v3_norm(p), amin = min3(s->half);
    if (q <= CENTRE_FRACTION * amin) {
        if (grad) *grad = hk_v3_zero();
        if (hess) *hess = hk_m3_zero();
        return amin;
    }
    const hk_Vec3 inv2 = hk_v3(1.0 / (s->half.x * s->half.x), 1.0 / (s->half.y * s->half.y),
                               1.0 / (s->half.z * s->half.z));
    const hk_Vec3 ap = hk_v3(p.x * inv2.x, p.y * inv2.y, p.z * inv2.z);
    const double rho = sqrt(hk_v3_dot(p, ap));
    const double dent = q / rho - q;
    if (!grad && !hess) return dent;
    const hk_Vec3 n = hk_v3_scale(p, 1.0 / q);
    const hk_Vec3 grho = hk_v3_scale(ap, 1.0 / rho);
    const double inv_rho = 1.0 / rho, f = inv_rho - 1.0;
    const hk_Vec3 gl = hk_v3_sub(hk_v3_scale(n, f), hk_v3_scale(grho, q * inv_rho * inv_rho));
    hk_Mat3 hl = hk_m3_zero();
    if (hess) {
        const double nn[3] = {n.x, n.y, n.z}, gr[3] = {grho.x, grho.y, grho.z};
        const double ai[3] = {inv2.x, inv2.y, inv2.z}, apv[3] = {ap.x, ap.y, ap.z};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double hq = ((i == j) - nn[i] * nn[j]) / q;
                double hrho = (i == j ? ai[i] : 0.0) * inv_rho - apv[i] * apv[j] * inv_rho * inv_rho * inv_rho;
                hl.m[i][j] = hq * f - (nn[i] * gr[j] + gr[i] * nn[j]) * inv_rho * inv_rho -
                             q * hrho * inv_rho * inv_rho + 2.0 * q * gr[i] * gr[j] * inv_rho * inv_rho * inv_rho;
            }
    }
    to_world(s, gl, &hl, grad, hess);
    return dent;
}

/* Thesis §4.1.2.1.3: the smallest of the three face distances (ties: first axis). */
static double cuboid_dent(const hk_Shape *s, hk_Vec3 d, hk_Vec3 *grad, hk_Mat3 *hess)
{
    int best = 0;
    double dent = DBL_MAX, sign = 1.0;
    for (int i = 0; i < 3; i++) {
        const double pi = hk_v3_dot(d, s->axis[i]);
        const double di = hk_v3_get(s->half, i) - fabs(pi);
        if (di < dent) {
            dent = di;
            best = i;
            sign = pi < 0.0 ? -1.0 : 1.0;
        }
    }
    if (grad) *grad = hk_v3_scale(s->axis[best], -sign);
    if (hess) *hess = hk_m3_zero(); /* piecewise linear */
    return dent;
}

double hk_shape_dent(const hk_Shape *shape, hk_Vec3 p, hk_Vec3 *grad, hk_Mat3 *hess)
{
    const hk_Vec3 d = hk_v3_sub(p, shape->centre);
    switch (shape->kind) {
    case HK_SHAPE_SPHERE: return sphere_dent(shape, d, grad, hess);
    case HK_SHAPE_ELLIPSOID: return ellipsoid_dent(shape, d, grad, hess);
    case HK_SHAPE_CUBOID: return cuboid_dent(shape, d, grad, hess);
    }
    if (grad) *grad = hk_v3_zero();
    if (hess) *hess = hk_m3_zero();
    return -DBL_MAX;
}

/* Cheap test that p cannot touch the envelope (see hk_Shape.bound). */
static int far_away(const hk_Shape *s, double extra, hk_Vec3 p)
{
    const double reach = s->bound + 1.7320508075688772 * fabs(extra);
    return hk_v3_norm2(hk_v3_sub(p, s->centre)) > reach * reach;
}

double hk_shape_penalty(const hk_Shape *shape, double alpha, hk_Vec3 p, hk_Vec3 *grad, hk_Mat3 *hess)
{
    /* §4.1.2.2: the envelope adds extra = alpha v before clipping at zero, so a point
     * just outside the shape can already be inside its envelope. */
    const double extra = alpha * shape->volume;
    if (!(shape->penalty > 0.0) || far_away(shape, extra, p)) return 0.0;
    hk_Vec3 g;
    hk_Mat3 h;
    const double phi = hk_shape_dent(shape, p, grad ? &g : NULL, hess ? &h : NULL) + extra;
    if (!(phi > 0.0)) return 0.0;
    const double k = shape->penalty;
    if (grad) *grad = hk_v3_madd(*grad, g, k * phi);
    if (hess) {
        const hk_Mat3 o = hk_m3_outer(g, g);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) hess->m[i][j] += k * (o.m[i][j] + phi * h.m[i][j]);
    }
    return 0.5 * k * phi * phi;
}

double hk_collision_penalty(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p, hk_Vec3 *grad,
                            hk_Mat3 *hess)
{
    if (grad) *grad = hk_v3_zero();
    if (hess) *hess = hk_m3_zero();
    double e = 0.0;
    for (int i = 0; i < count; i++) e += hk_shape_penalty(&shapes[i], alpha, p, grad, hess);
    return e;
}

double hk_collision_depth(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p)
{
    double depth = 0.0;
    for (int i = 0; i < count; i++) {
        const double extra = alpha * shapes[i].volume;
        if (far_away(&shapes[i], extra, p)) continue;
        const double phi = hk_shape_dent(&shapes[i], p, NULL, NULL) + extra;
        if (phi > depth) depth = phi;
    }
    return depth;
}
