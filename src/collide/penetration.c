/* Collision shapes' penetration depth and envelope penalty, exact derivatives (Lansink 2010 §4.1.2).
 * The 3-loops carry `#pragma GCC unroll`: -O2 keeps them rolled; written out they are
 * the same operations (the same bits) without the counters and run-time i == j tests. */
#include <float.h>

#include "collide/collide_internal.h"
#include "hairkit/collide.h"

/* A point closer to the centre than this fraction of the smallest radius counts as
 * the centre. The sphere's Hessian and the ellipsoid's gradient and Hessian grow like
 * 1/|d| and 1/|d|^2 there (the radial measure has no direction at the centre), so a
 * guard relative to the shape's own size keeps them finite whatever the units; 1e-9
 * is small enough that no point a strand can reach is affected, and large enough that
 * the derivatives stay far below overflow (|hess| <~ 1e18 amax / amin^2). */
#define CENTRE_FRACTION 1e-9

/* Corner factor of the rejection test: a cuboid's envelope reaches
 * |(a, b, c) + extra (1, 1, 1)| <= bound + sqrt(3) |extra| from the centre. */
#define SQRT3 1.7320508075688772

static double min3(hk_Vec3 v) { return hk_smaller(v.x, hk_smaller(v.y, v.z)); }

static void set_zero(hk_Vec3 *grad, hk_Mat3 *hess)
{
    if (grad) *grad = hk_v3_zero();
    if (hess) *hess = hk_m3_zero();
}

/* All three kinds take d = p - centre and q2 = |d|^2, which the penalty already
 * computed for its rejection test. */

/* The sphere's and the ellipsoid's dent come in two parts: the value, and the
 * derivatives from what the value computed (Radial). The penalty asks for the value
 * first and for the derivatives only where the point is inside the envelope (one of
 * four samples the dynamics' potential evaluates on examples/guides200), which then
 * need not take the value again. */
typedef struct Radial {
    hk_Vec3 d;  /* p - centre */
    double q;   /* |d| */
    int centre; /* q within CENTRE_FRACTION of the smallest radius: no direction */
    double R;   /* ellipsoid: the distance from the centre to the surface along d */
    double inv2[3], ml[3], iq;
    hk_Vec3 n;
} Radial;

static double sphere_value(const hk_Shape *s, hk_Vec3 d, double q2, Radial *o)
{
    const double r = s->half.x, q = sqrt(q2);
    o->d = d, o->q = q;
    o->centre = q <= CENTRE_FRACTION * r;
    if (o->centre) return r; /* no direction: deepest value, flat */
    return r - q;
}

static void sphere_derivatives(const Radial *o, hk_Vec3 *grad, hk_Mat3 *hess)
{
    if (o->centre) {
        set_zero(grad, hess);
        return;
    }
    const double iq = 1.0 / o->q;
    const hk_Vec3 n = hk_v3_scale(o->d, iq);
    if (grad) *grad = hk_v3_neg(n);
    if (hess) /* d2(-|d|) = -(I - n n^T) / |d| */
#pragma GCC unroll 3
        for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
            for (int j = 0; j < 3; j++) hess->m[i][j] = (hk_v3_get(n, i) * hk_v3_get(n, j) - (i == j)) * iq;
}

/* Thesis §4.1.2.1.1 measures the dent along the ray from the centre: with dist = |d|
 * and ratio = |(pU/a, pV/b, pW/c)|, dent = dist/ratio - dist. Everything is done in
 * world coordinates with the symmetric matrix
 *     A = sum_i U_i U_i^T / a_i^2,       so ratio^2 = d^T A d,
 * which is exact for the definition even when the file's axes are only orthogonal to
 * within the loader's tolerance.
 *
 * Derivation. Let q = |d|, n = d/q, P = I - n n^T, m = A n, s = n^T m. Then
 * ratio = q sqrt(s), so dist/ratio = R(n) = s^(-1/2): the distance from the centre to
 * the surface along n, a function of the direction only (homogeneous of degree 0 in
 * d), and dent = R - q. With dn/dd = P/q and dm/dd = A P/q:
 *     grad s = 2 P m / q
 *     grad R = -1/2 s^(-3/2) grad s = -R^3 P m / q = (R n - R^3 m) / q   (n^T m = R^-2)
 * Write g = R n - R^3 m (so grad R = g/q; n^T g = 0: R is constant along rays). With
 * grad q = n and hess q = P/q:
 *     grad dent = g/q - n.
 * Differentiating g/q:
 *     hess R = (dg/dd) / q - g n^T / q^2,
 *     dg/dd  = n grad R^T + R P/q - 3 R^2 m grad R^T - R^3 A P / q.
 * Substituting R^3 m = R n - g, i.e. n - 3 R^2 m = -2 n + 3 g / R, and
 * (R I - R^3 A) P = R I - R^3 A - g n^T (using A n = m, R^3 m = R n - g):
 *     hess R    = [R I - R^3 A - 2 (n g^T + g n^T) + 3 g g^T / R] / q^2,
 *     hess dent = hess R - P / q.
 * Checks: a sphere (A = I/r^2) gives g = 0 and hess R = 0; Euler's relation for a
 * degree-0 function, (hess R) d = -grad R, holds since n^T g = 0. On a local axis
 * (n = U) g = 0 and hess dent = (a I - a^3 A)/q^2 - P/q, e.g. a (1 - a^2/b^2)/q^2 - 1/q
 * along V. All terms are O(1) multiples of powers of 1/q (|g| <= R <= amax), so
 * nothing under- or overflows away from the guarded centre. */
static double ellipsoid_value(const hk_Shape *s, hk_Vec3 d, double q2, Radial *o)
{
    const double amin = min3(s->half), q = sqrt(q2);
    o->centre = q <= CENTRE_FRACTION * amin;
    if (o->centre) return amin; /* direction undefined: documented fallback */
    const double iq = 1.0 / q;
    const hk_Vec3 n = hk_v3_scale(d, iq);
    double sn = 0.0;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) {
        const double a = hk_v3_get(s->half, i);
        o->inv2[i] = 1.0 / (a * a);
        const double nl = hk_v3_dot(n, s->axis[i]);
        o->ml[i] = nl * o->inv2[i]; /* local components of m = A n */
        sn += nl * o->ml[i];
    }
    const double R = 1.0 / sqrt(sn);
    o->q = q, o->iq = iq, o->n = n, o->R = R;
    return R - q;
}

static void ellipsoid_derivatives(const hk_Shape *s, const Radial *o, hk_Vec3 *grad, hk_Mat3 *hess)
{
    if (o->centre) {
        set_zero(grad, hess);
        return;
    }
    const double R = o->R, iq = o->iq, *inv2 = o->inv2, *ml = o->ml;
    const hk_Vec3 n = o->n;
    hk_Vec3 m = hk_v3_scale(s->axis[0], ml[0]);
    m = hk_v3_madd(m, s->axis[1], ml[1]);
    m = hk_v3_madd(m, s->axis[2], ml[2]);
    const double R3 = R * R * R;
    const hk_Vec3 g = hk_v3_sub(hk_v3_scale(n, R), hk_v3_scale(m, R3));
    if (grad) *grad = hk_v3_sub(hk_v3_scale(g, iq), n);
    if (hess) {
        const double nv[3] = {n.x, n.y, n.z}, gv[3] = {g.x, g.y, g.z};
        const double iq2 = iq * iq, iR = 1.0 / R;
#pragma GCC unroll 3
        for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
            for (int j = i; j < 3; j++) {
                double aij = 0.0; /* (A)_ij */
#pragma GCC unroll 3
                for (int k = 0; k < 3; k++) aij += inv2[k] * hk_v3_get(s->axis[k], i) * hk_v3_get(s->axis[k], j);
                const double hr =
                    ((i == j) * R - R3 * aij - 2.0 * (nv[i] * gv[j] + gv[i] * nv[j]) + 3.0 * gv[i] * gv[j] * iR) * iq2;
                hess->m[i][j] = hess->m[j][i] = hr - ((i == j) - nv[i] * nv[j]) * iq;
            }
    }
}

/* The sphere's or the ellipsoid's dent (radial_kind), and its derivatives from o. */
static int radial_kind(const hk_Shape *s) { return s->kind == HK_SHAPE_SPHERE || s->kind == HK_SHAPE_ELLIPSOID; }

static double radial_value(const hk_Shape *s, hk_Vec3 d, double q2, Radial *o)
{
    return s->kind == HK_SHAPE_SPHERE ? sphere_value(s, d, q2, o) : ellipsoid_value(s, d, q2, o);
}

static void radial_derivatives(const hk_Shape *s, const Radial *o, hk_Vec3 *grad, hk_Mat3 *hess)
{
    if (s->kind == HK_SHAPE_SPHERE)
        sphere_derivatives(o, grad, hess);
    else
        ellipsoid_derivatives(s, o, grad, hess);
}

/* Thesis §4.1.2.1.3: the smallest of the three face depths. Ties go to the first
 * axis (strict <), and a point on a symmetry plane counts as on the + side, so the
 * gradient is deterministic. Starting from the first term (not DBL_MAX) lets a NaN
 * input come out as NaN. */
static double cuboid_dent(const hk_Shape *s, hk_Vec3 d, hk_Vec3 *grad, hk_Mat3 *hess)
{
    int best = 0;
    double pb = hk_v3_dot(d, s->axis[0]);
    double dent = s->half.x - fabs(pb);
#pragma GCC unroll 2
    for (int i = 1; i < 3; i++) {
        const double pi = hk_v3_dot(d, s->axis[i]);
        const double di = hk_v3_get(s->half, i) - fabs(pi);
        if (di < dent) {
            dent = di;
            best = i;
            pb = pi;
        }
    }
    if (grad) *grad = hk_v3_scale(s->axis[best], pb < 0.0 ? 1.0 : -1.0);
    if (hess) *hess = hk_m3_zero(); /* piecewise linear */
    return dent;
}

/* A mesh's field: d in the shape's axes is the offset from the grid's centre. */
static double field_dent(const hk_Shape *s, hk_Vec3 d, hk_Vec3 *grad, hk_Mat3 *hess)
{
    const hk_Vec3 local = hk_v3(hk_v3_dot(d, s->axis[0]), hk_v3_dot(d, s->axis[1]), hk_v3_dot(d, s->axis[2]));
    const hk_Vec3 at = hk_v3_add(hk_v3_add(s->field->origin, s->half), local);
    hk_Vec3 g;
    const double value = hk_distance_field_eval(s->field, at, grad ? &g : NULL);
    if (grad)
        *grad = hk_v3_neg(hk_v3_add(hk_v3_add(hk_v3_scale(s->axis[0], g.x), hk_v3_scale(s->axis[1], g.y)),
                                    hk_v3_scale(s->axis[2], g.z)));
    if (hess) *hess = hk_m3_zero(); /* trilinear: zero inside a cell, as the cuboid's */
    return -value;
}

static double dent_at(const hk_Shape *s, hk_Vec3 d, double q2, hk_Vec3 *grad, hk_Mat3 *hess)
{
    switch (s->kind) {
    case HK_SHAPE_FIELD:
        if (s->field) return field_dent(s, d, grad, hess);
        break;
    case HK_SHAPE_SPHERE:
    case HK_SHAPE_ELLIPSOID: {
        Radial o;
        const double dent = radial_value(s, d, q2, &o);
        if (grad || hess) radial_derivatives(s, &o, grad, hess);
        return dent;
    }
    case HK_SHAPE_CUBOID:
        return cuboid_dent(s, d, grad, hess);
    }
    set_zero(grad, hess); /* unknown kind: never in contact */
    return -DBL_MAX;
}

double hk_shape_dent(const hk_Shape *shape, hk_Vec3 p, hk_Vec3 *grad, hk_Mat3 *hess)
{
    const hk_Vec3 d = hk_v3_sub(p, shape->centre);
    return dent_at(shape, d, hk_v3_norm2(d), grad, hess);
}

/* The quick rejection of hk_shape_bound, on squares so no sqrt is spent on the
 * (common) far points. */
static int out_of_reach(const hk_Shape *s, double extra, double q2)
{
    const double reach = hk_shape_bound(s) + SQRT3 * fabs(extra);
    return q2 > reach * reach;
}

/* hk_shape_penalty's rejection: a shape without stiffness or out of reach of p adds
 * nothing. Else d = p - centre, q2 = |d|^2 and the envelope's extra for the rest. Inline
 * in hk_collision_penalty's loop: four of five shapes a sample stop here (examples/guides200),
 * and as calls of hk_shape_penalty they cost more than the test. */
static inline int within_reach(const hk_Shape *shape, double alpha, hk_Vec3 p, double *extra, hk_Vec3 *d, double *q2)
{
    if (!(shape->penalty > 0.0)) return 0; /* zero stiffness: no energy, nothing to differentiate */
    /* §4.1.2.2: the envelope adds extra = alpha v before clipping at zero, so a point
     * just outside the shape can already be inside its envelope. */
    *extra = alpha * shape->volume;
    *d = hk_v3_sub(p, shape->centre);
    *q2 = hk_v3_norm2(*d);
    return !out_of_reach(shape, *extra, *q2);
}

/* hk_shape_penalty of a shape within reach (within_reach's d, q2 and extra). */
static double penalty_in_reach(const hk_Shape *shape, double extra, hk_Vec3 d, double q2, hk_Vec3 *grad, hk_Mat3 *hess)
{
    const double k = shape->penalty;
    /* The Hessian needs the gradient (k g g^T) even when the caller does not; the
     * cuboid's and the field's own Hessians are zero, so they are not asked for. */
    hk_Vec3 g;
    hk_Mat3 h;
    hk_Mat3 *hp = hess && shape->kind != HK_SHAPE_CUBOID && shape->kind != HK_SHAPE_FIELD ? &h : NULL;
    double phi;
    if ((grad || hess) && radial_kind(shape)) {
        /* Many points within reach stay outside the envelope (examples/guides200: about
         * one of four samples that the dynamics' potential evaluates touches): the
         * ellipsoid's and the sphere's depth alone tells before the derivatives are
         * paid for, and they then start from what the depth computed. */
        Radial o;
        phi = radial_value(shape, d, q2, &o) + extra;
        if (!(phi > 0.0)) return 0.0;
        radial_derivatives(shape, &o, &g, hp);
    } else {
        phi = dent_at(shape, d, q2, grad || hess ? &g : NULL, hp) + extra;
        if (!(phi > 0.0)) return 0.0;
    }
    const double kphi = k * phi;
    if (grad) *grad = hk_v3_madd(*grad, g, kphi);
    if (hess) {
        const double gv[3] = {g.x, g.y, g.z};
#pragma GCC unroll 3
        for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
            for (int j = 0; j < 3; j++) hess->m[i][j] += k * gv[i] * gv[j] + (hp ? kphi * h.m[i][j] : 0.0);
    }
    return 0.5 * kphi * phi;
}

double hk_shape_penalty(const hk_Shape *shape, double alpha, hk_Vec3 p, hk_Vec3 *grad, hk_Mat3 *hess)
{
    double extra, q2;
    hk_Vec3 d;
    if (!within_reach(shape, alpha, p, &extra, &d, &q2)) return 0.0;
    return penalty_in_reach(shape, extra, d, q2, grad, hess);
}

double hk_collision_penalty(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p, hk_Vec3 *grad, hk_Mat3 *hess)
{
    set_zero(grad, hess);
    /* The sum of hk_shape_penalty over the shapes; a shape out of reach is not added (its
     * 0.0 would leave e as it is: e starts at +0 and every term is >= +0). */
    double e = 0.0;
    for (int i = 0; i < count; i++) {
        double extra, q2;
        hk_Vec3 d;
        if (within_reach(&shapes[i], alpha, p, &extra, &d, &q2))
            e += penalty_in_reach(&shapes[i], extra, d, q2, grad, hess);
    }
    return e;
}

/* Whether d (from the centre) is clearly outside the shape itself, dent < 0, without
 * the dent's square roots and divisions: most points of a head of hair lie within a
 * shape's bound yet outside it, and the hair is checked every frame. The ellipsoid's
 * radial dent has the sign of 1 - ratio^2 (§4.1.2.1.1); the small slack leaves points
 * within rounding of the surface to the dent itself, so the answers do not change. The
 * cuboid's dent is as cheap as any test. */
static int clearly_outside(const hk_Shape *s, hk_Vec3 d, double q2)
{
    switch (s->kind) {
    case HK_SHAPE_SPHERE:
        return q2 > s->half.x * s->half.x * (1.0 + 1e-9);
    case HK_SHAPE_ELLIPSOID: {
        double r2 = 0.0;
#pragma GCC unroll 3
        for (int i = 0; i < 3; i++) {
            const double u = hk_v3_dot(d, s->axis[i]) / hk_v3_get(s->half, i);
            r2 += u * u;
        }
        return r2 > 1.0 + 1e-9;
    }
    case HK_SHAPE_CUBOID:
        break;
    case HK_SHAPE_FIELD:
        break;
    }
    return 0;
}

int hk_shape_outside(const hk_Shape *s, hk_Vec3 p)
{
    const hk_Vec3 d = hk_v3_sub(p, s->centre);
    return clearly_outside(s, d, hk_v3_norm2(d));
}

int hk_collision_deepest(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p, double *depth)
{
    int deepest = -1;
    double best = 0.0;
    for (int i = 0; i < count; i++) {
        const double extra = alpha * shapes[i].volume;
        const hk_Vec3 d = hk_v3_sub(p, shapes[i].centre);
        const double q2 = hk_v3_norm2(d);
        if (out_of_reach(&shapes[i], extra, q2) || (extra <= 0.0 && clearly_outside(&shapes[i], d, q2))) continue;
        const double phi = dent_at(&shapes[i], d, q2, NULL, NULL) + extra;
        if (phi > best) {
            best = phi;
            deepest = i;
        }
    }
    if (depth) *depth = best;
    return deepest;
}

double hk_collision_depth(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p)
{
    double depth;
    hk_collision_deepest(shapes, count, alpha, p, &depth);
    return depth;
}
