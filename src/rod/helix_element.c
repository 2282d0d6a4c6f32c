/* One helical element in closed form with exact first and second derivatives in its
 * curvatures and twist (Bertails et al. 2006 Appendix A, eq. 7; derivation in docs/physics.md).
 *
 * GCC 12's -O2 keeps most of the small loops here rolled (a counter, and tests such as
 * i == j made at run time); `#pragma GCC unroll` writes them out, the same operations
 * in the same order, so the same bits (docs/dynamics.md, "Speed", 6 December 2026,
 * night). The two-lane helpers are always inlined for the same reason: as calls,
 * their lanes went through the stack. */
#include <stddef.h>

#include "helix_local.h"

hk_Mat3 hk_helix_rotation(const double c[HK_CN_COUNT], hk_Vec3 phi)
{
    /* exp(Phi) = I + c1 Phi + c2 Phi^2 with Phi^2 = phi phi^T - |phi|^2 I (Rodrigues). */
    double x = hk_v3_dot(phi, phi);
    hk_Mat3 r = hk_m3_outer(phi, phi);
    hk_Mat3 s = hk_m3_skew(phi);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) {
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) r.m[i][j] = c[1] * s.m[i][j] + c[2] * r.m[i][j];
        r.m[i][i] += 1.0 - c[2] * x;
    }
    return r;
}

void hk_helix_term(const double c[HK_CN_COUNT], int m, double alpha, hk_Vec3 phi, hk_Vec3 w, int order,
                   hk_HelixTerm *out)
{
    const double cm = c[m], cm1 = c[m + 1];
    const double x = hk_v3_dot(phi, phi), pw = hk_v3_dot(phi, w);
    const hk_Vec3 pxw = hk_v3_cross(phi, w);
    /* Q = phi x (phi x w) = phi (phi . w) - x w */
    const hk_Vec3 q = hk_v3_sub(hk_v3_scale(phi, pw), hk_v3_scale(w, x));
    out->value = hk_v3_add(hk_v3_scale(w, alpha), hk_v3_add(hk_v3_scale(pxw, cm), hk_v3_scale(q, cm1)));
    if (order < 1) return;

    /* dc_n/dx = -(c_{n+1} - n c_{n+2}) / 2, and x = phi . phi gives dx/dphi_j = 2 phi_j. */
    const double dm = -0.5 * (c[m + 1] - m * c[m + 2]);
    const double dm1 = -0.5 * (c[m + 2] - (m + 1) * c[m + 3]);
    const double ph[3] = {phi.x, phi.y, phi.z}, wv[3] = {w.x, w.y, w.z};
    hk_Vec3 exw[3], dq[3];
#pragma GCC unroll 3
    for (int j = 0; j < 3; j++) {
        hk_Vec3 ej = hk_v3_unit(j);
        exw[j] = hk_v3_cross(ej, w);
        /* d Q / d phi_j = e_j (phi . w) + phi w_j - 2 phi_j w */
        dq[j] = hk_v3_add(hk_v3_scale(ej, pw), hk_v3_sub(hk_v3_scale(phi, wv[j]), hk_v3_scale(w, 2.0 * ph[j])));
        hk_Vec3 col = hk_v3_scale(pxw, 2.0 * dm * ph[j]);
        col = hk_v3_madd(col, exw[j], cm);
        col = hk_v3_madd(col, q, 2.0 * dm1 * ph[j]);
        col = hk_v3_madd(col, dq[j], cm1);
        out->jac.m[0][j] = col.x;
        out->jac.m[1][j] = col.y;
        out->jac.m[2][j] = col.z;
    }
    if (order < 2) return;

    /* d2c_n/dx2 = (c_{n+2} - (2n+1) c_{n+3} + n (n+2) c_{n+4}) / 4 */
    const double ddm = 0.25 * (c[m + 2] - (2 * m + 1) * c[m + 3] + m * (m + 2) * c[m + 4]);
    const double ddm1 = 0.25 * (c[m + 3] - (2 * m + 3) * c[m + 4] + (m + 1) * (m + 3) * c[m + 5]);
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
#pragma GCC unroll 3
        for (int b = a; b < 3; b++) {
            const double dab = a == b ? 1.0 : 0.0;
            hk_Vec3 v = hk_v3_scale(pxw, 4.0 * ddm * ph[a] * ph[b] + 2.0 * dm * dab);
            v = hk_v3_madd(v, exw[a], 2.0 * dm * ph[b]);
            v = hk_v3_madd(v, exw[b], 2.0 * dm * ph[a]);
            v = hk_v3_madd(v, q, 4.0 * ddm1 * ph[a] * ph[b] + 2.0 * dm1 * dab);
            v = hk_v3_madd(v, dq[a], 2.0 * dm1 * ph[b]);
            v = hk_v3_madd(v, dq[b], 2.0 * dm1 * ph[a]);
            /* d2 Q / d phi_a d phi_b = e_a w_b + e_b w_a - 2 delta_ab w */
            v = hk_v3_madd(v, hk_v3_unit(a), cm1 * wv[b]);
            v = hk_v3_madd(v, hk_v3_unit(b), cm1 * wv[a]);
            v = hk_v3_madd(v, w, -2.0 * cm1 * dab);
            out->hess[a][b] = v;
            out->hess[b][a] = v;
        }
    }
}

void hk_helix_term_along(const double c[HK_CN_COUNT], int m, hk_Vec3 phi, hk_Vec3 w, hk_Vec3 e, hk_Vec3 *d1,
                         hk_Vec3 *d2)
{
    const double cm = c[m], cm1 = c[m + 1];
    const double x = hk_v3_dot(phi, phi), pw = hk_v3_dot(phi, w), s = hk_v3_dot(phi, e);
    const hk_Vec3 pxw = hk_v3_cross(phi, w), exw = hk_v3_cross(e, w);
    const hk_Vec3 q = hk_v3_sub(hk_v3_scale(phi, pw), hk_v3_scale(w, x));
    /* Along e, x changes at 2 s, so c_n at 2 s dc_n/dx (hk_helix_term's derivatives of
     * c_n); Q = phi (phi . w) - x w changes at e (phi . w) + phi (e . w) - 2 s w. */
    const double dm = -0.5 * (c[m + 1] - m * c[m + 2]);
    const double dm1 = -0.5 * (c[m + 2] - (m + 1) * c[m + 3]);
    const double ew = hk_v3_dot(e, w);
    const hk_Vec3 dq = hk_v3_add(hk_v3_add(hk_v3_scale(e, pw), hk_v3_scale(phi, ew)), hk_v3_scale(w, -2.0 * s));
    if (d1) {
        hk_Vec3 v = hk_v3_scale(pxw, 2.0 * dm * s);
        v = hk_v3_madd(v, exw, cm);
        v = hk_v3_madd(v, q, 2.0 * dm1 * s);
        *d1 = hk_v3_madd(v, dq, cm1);
    }
    if (!d2) return;
    /* Once more: (c_n)'' = 4 s^2 d2c_n/dx2 + 2 (e . e) dc_n/dx, (phi x w)'' = 0,
     * Q'' = 2 e (e . w) - 2 (e . e) w. */
    const double ddm = 0.25 * (c[m + 2] - (2 * m + 1) * c[m + 3] + m * (m + 2) * c[m + 4]);
    const double ddm1 = 0.25 * (c[m + 3] - (2 * m + 3) * c[m + 4] + (m + 1) * (m + 3) * c[m + 5]);
    const double ee = hk_v3_dot(e, e);
    hk_Vec3 v = hk_v3_scale(pxw, 4.0 * ddm * s * s + 2.0 * dm * ee);
    v = hk_v3_madd(v, exw, 4.0 * dm * s);
    v = hk_v3_madd(v, q, 4.0 * ddm1 * s * s + 2.0 * dm1 * ee);
    v = hk_v3_madd(v, dq, 4.0 * dm1 * s);
    v = hk_v3_madd(v, e, 2.0 * cm1 * ew);
    *d2 = hk_v3_madd(v, w, -2.0 * cm1 * ee);
}

static void set_col(hk_Mat3 *m, int j, hk_Vec3 v)
{
    m->m[0][j] = v.x;
    m->m[1][j] = v.y;
    m->m[2][j] = v.z;
}

/* exp(Phi) = I + c1 Phi + c2 Phi^2 and Lambda = u (I + c2 Phi + c3 Phi^2), with
 * Phi^2 = phi phi^T - x I: both from one outer product (x = phi . phi, c its c_n),
 * instead of one hk_helix_term per column of Lambda. */
static void rotation_and_lambda(const double c[HK_CN_COUNT], hk_Vec3 phi, double x, double u, hk_ElementLocal *out)
{
    const double pv[3] = {phi.x, phi.y, phi.z};
    const hk_Mat3 skew = hk_m3_skew(phi);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) {
            const double sq = pv[i] * pv[j] - (i == j ? x : 0.0);
            out->rot.m[i][j] = (i == j ? 1.0 : 0.0) + c[1] * skew.m[i][j] + c[2] * sq;
            out->lam.m[i][j] = u * ((i == j ? 1.0 : 0.0) + c[2] * skew.m[i][j] + c[3] * sq);
        }
}

/* hk_helix_term of order 0 or 1 for w = e0, the centreline's and g's direction (x =
 * phi . phi), with its Jacobian scaled by `scale`: with w = e0, phi x w = (0, phi_2,
 * -phi_1), Q = phi phi_0 - x e0 and d Q / d phi_j = e_j phi_0 + phi delta_j0 - 2 phi_j e0,
 * so that the Jacobian is the outer product a phi^T (a = 2 dc_m/dx (phi x e0) +
 * 2 dc_{m+1}/dx Q - 2 c_{m+1} e0) plus c_{m+1} (phi_0 I + phi e0^T) plus c_m's
 * constant [e_j x e0] columns: a dozen products instead of hk_helix_term's general w. */
static hk_Vec3 helix_term_e0(const double c[HK_CN_COUNT], int m, double alpha, hk_Vec3 phi, double x, double scale,
                             hk_Mat3 *jac)
{
    const double cm = c[m], cm1 = c[m + 1];
    const double p[3] = {phi.x, phi.y, phi.z};
    const double q[3] = {p[0] * p[0] - x, p[1] * p[0], p[2] * p[0]};
    const hk_Vec3 value = hk_v3(alpha + cm1 * q[0], cm * p[2] + cm1 * q[1], -cm * p[1] + cm1 * q[2]);
    if (!jac) return value;
    const double dm = -0.5 * (c[m + 1] - m * c[m + 2]);
    const double dm1 = -0.5 * (c[m + 2] - (m + 1) * c[m + 3]);
    const double a[3] = {scale * (2.0 * dm1 * q[0] - 2.0 * cm1), scale * (2.0 * dm * p[2] + 2.0 * dm1 * q[1]),
                         scale * (-2.0 * dm * p[1] + 2.0 * dm1 * q[2])};
    const double diag = scale * cm1 * p[0], side = scale * cm;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) jac->m[i][j] = a[i] * p[j] + (i == j ? diag : 0.0);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) jac->m[i][0] += scale * cm1 * p[i];
    jac->m[2][1] -= side; /* e1 x e0 = -e2 */
    jac->m[1][2] += side; /* e2 x e0 = e1 */
    return value;
}

/* rot, lam and dd of hk_element_local of order 1, from c = the c_n of x = phi . phi. */
static void order_one(const double c[HK_CN_COUNT], hk_Vec3 phi, double x, double u, hk_ElementLocal *out)
{
    rotation_and_lambda(c, phi, x, u, out);
    helix_term_e0(c, 2, 1.0, phi, x, u * u, &out->dd);
}

void hk_element_local(hk_Vec3 k, double u, int order, int with_g, hk_ElementLocal *out)
{
    const hk_Vec3 phi = hk_v3_scale(k, u);
    double c[HK_CN_COUNT];
    const double x = hk_v3_dot(phi, phi);
    hk_helix_cn(x, c);
    const double u2 = u * u, u3 = u2 * u;
    if (order == 1) { /* the whole of Lambda at once, and d's Jacobian */
        order_one(c, phi, x, u, out);
    } else { /* d = Lambda e0 = u h(phi; m = 2, alpha = 1, w = e0); d/dk = u d/dphi */
        out->rot = hk_helix_rotation(c, phi);
        set_col(&out->lam, 0, hk_v3_scale(helix_term_e0(c, 2, 1.0, phi, x, u2, order >= 2 ? &out->dd : NULL), u));
    }
    /* Order 2: the other columns Lambda e_b = u h(phi; w = e_b) with their Jacobians,
     * and d's second derivatives. */
    for (int b = 0; b < (order >= 2 ? 3 : 0); b++) {
        hk_HelixTerm t;
        hk_helix_term(c, 2, 1.0, phi, hk_v3_unit(b), b == 0 ? 2 : 1, &t);
        if (b == 0) {
            out->dlam[0] = out->dd;
#pragma GCC unroll 3
            for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
                for (int j = 0; j < 3; j++) out->d2d[i][j] = hk_v3_scale(t.hess[i][j], u3);
        } else {
            set_col(&out->lam, b, hk_v3_scale(t.value, u));
            out->dlam[b] = hk_m3_scale(&t.jac, u2);
        }
    }
    if (with_g && order <= 1) { /* g = u^2 h(phi; m = 3, alpha = 1/2, w = e0) */
        out->g = hk_v3_scale(helix_term_e0(c, 3, 0.5, phi, x, u3, order == 1 ? &out->dg : NULL), u2);
    } else if (with_g) {
        hk_HelixTerm t;
        hk_helix_term(c, 3, 0.5, phi, hk_v3_unit(0), order > 2 ? 2 : order, &t);
        out->g = hk_v3_scale(t.value, u2);
        if (order >= 1) out->dg = hk_m3_scale(&t.jac, u3);
        if (order >= 2)
#pragma GCC unroll 3
            for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
                for (int j = 0; j < 3; j++) out->d2g[i][j] = hk_v3_scale(t.hess[i][j], u3 * u);
    }
}

void hk_element_local_rates(hk_Vec3 k, double u, hk_Vec3 kd, hk_ElementLocal *out, hk_Vec3 *spin_rate, hk_Vec3 *curve)
{
    const hk_Vec3 phi = hk_v3_scale(k, u);
    double c[HK_CN_COUNT];
    const double x = hk_v3_dot(phi, phi);
    hk_helix_cn(x, c);
    order_one(c, phi, x, u, out);
    const double u2 = u * u;
    /* Lambda e_b = u h(phi; w = e_b) is linear in w, so sum_b kd_b dlam[b] kd is u^2
     * times h(phi; w = kd)'s derivative along kd (d/dk = u d/dphi); the offset's second
     * derivative along kd is u^3 times h(phi; w = e0)'s. */
    hk_Vec3 d1, d2;
    hk_helix_term_along(c, 2, phi, kd, kd, &d1, NULL);
    *spin_rate = hk_v3_scale(d1, u2);
    hk_helix_term_along(c, 2, phi, hk_v3_unit(0), kd, NULL, &d2);
    *curve = hk_v3_scale(d2, u2 * u);
}

/* ---- two offsets at once (hk_element_local_rates2) ---- */


/* hk_helix_term_along for m = 2, lane by lane (the same operations in the same order). */
static inline __attribute__((always_inline)) void helix_term_along_x2(const hk_Lanes c[HK_CN_COUNT], hk_Vec3x2 phi,
                                                                      hk_Vec3x2 w, hk_Vec3x2 e, hk_Vec3x2 *d1,
                                                                      hk_Vec3x2 *d2)
{
    const hk_Lanes cm = c[2], cm1 = c[3];
    const hk_Lanes x = dot_x2(phi, phi), pw = dot_x2(phi, w), s = dot_x2(phi, e);
    const hk_Vec3x2 pxw = cross_x2(phi, w), exw = cross_x2(e, w);
    const hk_Vec3x2 q0 = scale_x2(phi, pw), q1 = scale_x2(w, x);
    const hk_Vec3x2 q = {q0.x - q1.x, q0.y - q1.y, q0.z - q1.z};
    const hk_Lanes dm = lanes(-0.5) * (c[3] - lanes(2.0) * c[4]);
    const hk_Lanes dm1 = lanes(-0.5) * (c[4] - lanes(3.0) * c[5]);
    const hk_Lanes ew = dot_x2(e, w);
    const hk_Vec3x2 a = scale_x2(e, pw), b = scale_x2(phi, ew), g = scale_x2(w, lanes(-2.0) * s);
    const hk_Vec3x2 dq = {(a.x + b.x) + g.x, (a.y + b.y) + g.y, (a.z + b.z) + g.z};
    if (d1) {
        hk_Vec3x2 v = scale_x2(pxw, lanes(2.0) * dm * s);
        v = madd_x2(v, exw, cm);
        v = madd_x2(v, q, lanes(2.0) * dm1 * s);
        *d1 = madd_x2(v, dq, cm1);
    }
    if (!d2) return;
    const hk_Lanes ddm = lanes(0.25) * (c[4] - lanes(5.0) * c[5] + lanes(8.0) * c[6]);
    const hk_Lanes ddm1 = lanes(0.25) * (c[5] - lanes(7.0) * c[6] + lanes(15.0) * c[7]);
    const hk_Lanes ee = dot_x2(e, e);
    hk_Vec3x2 v = scale_x2(pxw, lanes(4.0) * ddm * s * s + lanes(2.0) * dm * ee);
    v = madd_x2(v, exw, lanes(4.0) * dm * s);
    v = madd_x2(v, q, lanes(4.0) * ddm1 * s * s + lanes(2.0) * dm1 * ee);
    v = madd_x2(v, dq, lanes(4.0) * dm1 * s);
    v = madd_x2(v, e, lanes(2.0) * cm1 * ew);
    *d2 = madd_x2(v, w, lanes(-2.0) * cm1 * ee);
}

/* helix_term_e0 lane by lane (jac may be NULL). */
static inline __attribute__((always_inline)) hk_Vec3x2 helix_term_e0_x2(const hk_Lanes c[HK_CN_COUNT], int m,
                                                                        double alpha, hk_Vec3x2 phi, hk_Lanes x,
                                                                        hk_Lanes scale, hk_Mat3x2 *jac)
{
    const hk_Lanes cm = c[m], cm1 = c[m + 1], zero = lanes(0.0);
    const hk_Lanes p[3] = {phi.x, phi.y, phi.z};
    const hk_Lanes q[3] = {p[0] * p[0] - x, p[1] * p[0], p[2] * p[0]};
    const hk_Vec3x2 value = {lanes(alpha) + cm1 * q[0], cm * p[2] + cm1 * q[1], -cm * p[1] + cm1 * q[2]};
    if (!jac) return value;
    const hk_Lanes dm = lanes(-0.5) * (c[m + 1] - lanes((double)m) * c[m + 2]);
    const hk_Lanes dm1 = lanes(-0.5) * (c[m + 2] - lanes((double)(m + 1)) * c[m + 3]);
    const hk_Lanes a[3] = {scale * (lanes(2.0) * dm1 * q[0] - lanes(2.0) * cm1),
                           scale * (lanes(2.0) * dm * p[2] + lanes(2.0) * dm1 * q[1]),
                           scale * (lanes(-2.0) * dm * p[1] + lanes(2.0) * dm1 * q[2])};
    const hk_Lanes diag = scale * cm1 * p[0], side = scale * cm;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) jac->m[i][j] = a[i] * p[j] + (i == j ? diag : zero);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) jac->m[i][0] += scale * cm1 * p[i];
    jac->m[2][1] -= side;
    jac->m[1][2] += side;
    return value;
}

void hk_element_local_rates2(hk_Vec3 k, const double u[2], hk_Vec3 kd, hk_ElementRates2 *out)
{
    const hk_Lanes ul = {u[0], u[1]};
    const hk_Vec3x2 phi = scale_x2(lanes3(k), ul);
    const hk_Lanes x = dot_x2(phi, phi);
    hk_Lanes c[HK_CN_COUNT];
    hk_helix_cn_x2(x, c);
    /* rotation_and_lambda */
    const hk_Lanes pv[3] = {phi.x, phi.y, phi.z}, zero = lanes(0.0), one = lanes(1.0);
    const hk_Lanes skew[3][3] = {{zero, -phi.z, phi.y}, {phi.z, zero, -phi.x}, {-phi.y, phi.x, zero}};
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) {
            const hk_Lanes sq = pv[i] * pv[j] - (i == j ? x : zero);
            out->rot.m[i][j] = (i == j ? one : zero) + c[1] * skew[i][j] + c[2] * sq;
            out->lam.m[i][j] = ul * ((i == j ? one : zero) + c[2] * skew[i][j] + c[3] * sq);
        }
    const hk_Lanes scale = ul * ul;
    helix_term_e0_x2(c, 2, 1.0, phi, x, scale, &out->dd);
    /* hk_element_local_rates' two contractions */
    const hk_Vec3x2 kdl = lanes3(kd), e0 = {one, zero, zero};
    hk_Vec3x2 d1, d2;
    helix_term_along_x2(c, phi, kdl, kdl, &d1, NULL);
    out->spin_rate = scale_x2(d1, scale);
    helix_term_along_x2(c, phi, e0, kdl, NULL, &d2);
    out->curve = scale_x2(d2, scale * ul);
}

void hk_element_slide2(hk_Vec3 k, const double u[2], hk_Vec3 kd, hk_Vec3x2 *offset, hk_Vec3x2 *slide)
{
    const hk_Lanes ul = {u[0], u[1]};
    const hk_Vec3x2 phi = scale_x2(lanes3(k), ul);
    const hk_Lanes x = dot_x2(phi, phi);
    hk_Lanes c[HK_CN_COUNT];
    hk_helix_cn_x2(x, c);
    /* helix_term_e0's value for m = 2, alpha = 1 */
    const hk_Lanes q0 = phi.x * phi.x - x, q1 = phi.y * phi.x, q2 = phi.z * phi.x;
    const hk_Vec3x2 value = {lanes(1.0) + c[3] * q0, c[2] * phi.z + c[3] * q1, -c[2] * phi.y + c[3] * q2};
    *offset = scale_x2(value, ul);
    if (!slide) return;
    const hk_Vec3x2 e0 = {lanes(1.0), lanes(0.0), lanes(0.0)};
    hk_Vec3x2 d1;
    helix_term_along_x2(c, phi, e0, lanes3(kd), &d1, NULL);
    *slide = scale_x2(d1, ul * ul);
}

/* hk_helix_term lane by lane for w a basis vector e_wi (the same operations, with its
 * zero and unit components, in the same order). */
static inline __attribute__((always_inline)) void helix_term_x2(const hk_Lanes c[HK_CN_COUNT], int m, double alpha,
                                                                hk_Vec3x2 phi, int wi, int order, hk_Vec3x2 *value,
                                                                hk_Mat3x2 *jac, hk_Vec3x2 hess[3][3])
{
    const hk_Vec3x2 w = lanes3(hk_v3_unit(wi));
    const hk_Lanes cm = c[m], cm1 = c[m + 1];
    const hk_Lanes x = dot_x2(phi, phi), pw = dot_x2(phi, w);
    const hk_Vec3x2 pxw = cross_x2(phi, w);
    const hk_Vec3x2 q0 = scale_x2(phi, pw), q1 = scale_x2(w, x);
    const hk_Vec3x2 q = {q0.x - q1.x, q0.y - q1.y, q0.z - q1.z};
    *value = add_x2(scale_x2(w, lanes(alpha)), add_x2(scale_x2(pxw, cm), scale_x2(q, cm1)));
    if (order < 1) return;
    const hk_Lanes dm = lanes(-0.5) * (c[m + 1] - lanes((double)m) * c[m + 2]);
    const hk_Lanes dm1 = lanes(-0.5) * (c[m + 2] - lanes((double)(m + 1)) * c[m + 3]);
    const hk_Lanes ph[3] = {phi.x, phi.y, phi.z}, wv[3] = {w.x, w.y, w.z};
    hk_Vec3x2 exw[3], dq[3];
#pragma GCC unroll 3
    for (int j = 0; j < 3; j++) {
        const hk_Vec3x2 ej = lanes3(hk_v3_unit(j));
        exw[j] = cross_x2(ej, w);
        const hk_Vec3x2 a = scale_x2(phi, wv[j]), b = scale_x2(w, lanes(2.0) * ph[j]);
        dq[j] = add_x2(scale_x2(ej, pw), (hk_Vec3x2){a.x - b.x, a.y - b.y, a.z - b.z});
        hk_Vec3x2 col = scale_x2(pxw, lanes(2.0) * dm * ph[j]);
        col = madd_x2(col, exw[j], cm);
        col = madd_x2(col, q, lanes(2.0) * dm1 * ph[j]);
        col = madd_x2(col, dq[j], cm1);
        jac->m[0][j] = col.x;
        jac->m[1][j] = col.y;
        jac->m[2][j] = col.z;
    }
    if (order < 2) return;
    const hk_Lanes ddm =
        lanes(0.25) * (c[m + 2] - lanes((double)(2 * m + 1)) * c[m + 3] + lanes((double)(m * (m + 2))) * c[m + 4]);
    const hk_Lanes ddm1 = lanes(0.25) * (c[m + 3] - lanes((double)(2 * m + 3)) * c[m + 4] +
                                         lanes((double)((m + 1) * (m + 3))) * c[m + 5]);
#pragma GCC unroll 3
    for (int a = 0; a < 3; a++) {
#pragma GCC unroll 3
        for (int b = a; b < 3; b++) {
            const hk_Lanes dab = lanes(a == b ? 1.0 : 0.0);
            hk_Vec3x2 v = scale_x2(pxw, lanes(4.0) * ddm * ph[a] * ph[b] + lanes(2.0) * dm * dab);
            v = madd_x2(v, exw[a], lanes(2.0) * dm * ph[b]);
            v = madd_x2(v, exw[b], lanes(2.0) * dm * ph[a]);
            v = madd_x2(v, q, lanes(4.0) * ddm1 * ph[a] * ph[b] + lanes(2.0) * dm1 * dab);
            v = madd_x2(v, dq[a], lanes(2.0) * dm1 * ph[b]);
            v = madd_x2(v, dq[b], lanes(2.0) * dm1 * ph[a]);
            v = madd_x2(v, lanes3(hk_v3_unit(a)), cm1 * wv[b]);
            v = madd_x2(v, lanes3(hk_v3_unit(b)), cm1 * wv[a]);
            v = madd_x2(v, w, lanes(-2.0) * cm1 * dab);
            hess[a][b] = v;
            hess[b][a] = v;
        }
    }
}

/* hk_helix_rotation lane by lane. */
static hk_Mat3x2 helix_rotation_x2(const hk_Lanes c[HK_CN_COUNT], hk_Vec3x2 phi)
{
    const hk_Lanes x = dot_x2(phi, phi), zero = lanes(0.0);
    const hk_Lanes p[3] = {phi.x, phi.y, phi.z};
    const hk_Lanes s[3][3] = {{zero, -phi.z, phi.y}, {phi.z, zero, -phi.x}, {-phi.y, phi.x, zero}};
    hk_Mat3x2 r;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) {
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) r.m[i][j] = c[1] * s[i][j] + c[2] * (p[i] * p[j]);
        r.m[i][i] += lanes(1.0) - c[2] * x;
    }
    return r;
}

static void set_lane_col(hk_Mat3 *m, int j, hk_Vec3x2 v, int l)
{
    m->m[0][j] = v.x[l];
    m->m[1][j] = v.y[l];
    m->m[2][j] = v.z[l];
}

/* d[i][j] = h[i][j] s, lane l */
static inline __attribute__((always_inline)) void lane_scaled_hess(hk_Vec3 d[3][3], hk_Vec3x2 h[3][3], hk_Lanes s,
                                                                   int l)
{
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) d[i][j] = lane_v3(scale_x2(h[i][j], s), l);
}

static hk_Mat3 lane_scaled(const hk_Mat3x2 *a, hk_Lanes s, int l)
{
    hk_Mat3x2 o;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) o.m[i][j] = a->m[i][j] * s;
    return lane_m3(&o, l);
}

void hk_element_local_order2(const hk_Vec3 k[2], const double u[2], hk_ElementLocal out[2])
{
    const hk_Lanes ul = {u[0], u[1]};
    const hk_Vec3x2 phi = {(hk_Lanes){k[0].x, k[1].x} * ul, (hk_Lanes){k[0].y, k[1].y} * ul,
                           (hk_Lanes){k[0].z, k[1].z} * ul};
    const hk_Lanes x = dot_x2(phi, phi);
    hk_Lanes c[HK_CN_COUNT];
    hk_helix_cn_x2(x, c);
    const hk_Lanes u2 = ul * ul, u3 = u2 * ul;
    const hk_Mat3x2 rot = helix_rotation_x2(c, phi);
    hk_Mat3x2 dd, jac[3], gjac;
    const hk_Vec3x2 d = scale_x2(helix_term_e0_x2(c, 2, 1.0, phi, x, u2, &dd), ul);
    hk_Vec3x2 value[3], hess[3][3], g, ghess[3][3];
#pragma GCC unroll 3
    for (int b = 0; b < 3; b++) helix_term_x2(c, 2, 1.0, phi, b, b == 0 ? 2 : 1, &value[b], &jac[b], hess);
    helix_term_x2(c, 3, 0.5, phi, 0, 2, &g, &gjac, ghess);
#pragma GCC unroll 2
    for (int l = 0; l < 2; l++) {
        hk_ElementLocal *o = &out[l];
        o->rot = lane_m3(&rot, l);
        set_lane_col(&o->lam, 0, d, l);
        o->dd = lane_m3(&dd, l);
        o->dlam[0] = o->dd;
        lane_scaled_hess(o->d2d, hess, u3, l);
#pragma GCC unroll 2
        for (int b = 1; b < 3; b++) {
            set_lane_col(&o->lam, b, scale_x2(value[b], ul), l);
            o->dlam[b] = lane_scaled(&jac[b], u2, l);
        }
        o->g = lane_v3(scale_x2(g, u2), l);
        o->dg = lane_scaled(&gjac, u3, l);
        lane_scaled_hess(o->d2g, ghess, u3 * ul, l);
    }
}

void hk_element_offset2(hk_Vec3 k, const double u[2], hk_Vec3x2 *offset, hk_Mat3x2 *dd, hk_Vec3x2 *tangent)
{
    const hk_Lanes ul = {u[0], u[1]};
    const hk_Vec3x2 phi = scale_x2(lanes3(k), ul);
    const hk_Lanes x = dot_x2(phi, phi);
    hk_Lanes c[HK_CN_COUNT];
    hk_helix_cn_x2(x, c);
    *offset = scale_x2(helix_term_e0_x2(c, 2, 1.0, phi, x, ul * ul, dd), ul);
    if (!tangent) return;
    /* column 0 of rotation_and_lambda's rotation, its operations */
    const hk_Lanes zero = lanes(0.0), one = lanes(1.0);
    tangent->x = (one + c[1] * zero) + c[2] * (phi.x * phi.x - x);
    tangent->y = (zero + c[1] * phi.z) + c[2] * (phi.y * phi.x - zero);
    tangent->z = (zero + c[1] * -phi.y) + c[2] * (phi.z * phi.x - zero);
}

void hk_element_offset_derivs2(hk_Vec3 k, const double u[2], hk_Mat3 dd[2], hk_Vec3 d2d0[3][3], hk_Vec3 d2d1[3][3])
{
    const hk_Lanes ul = {u[0], u[1]}, u2 = ul * ul;
    const hk_Vec3x2 phi = scale_x2(lanes3(k), ul);
    const hk_Lanes x = dot_x2(phi, phi);
    hk_Lanes c[HK_CN_COUNT];
    hk_helix_cn_x2(x, c);
    hk_Mat3x2 jac;
    helix_term_e0_x2(c, 2, 1.0, phi, x, u2, &jac);
    dd[0] = lane_m3(&jac, 0);
    dd[1] = lane_m3(&jac, 1);
    if (!d2d0) return;
    hk_Vec3x2 value, hess[3][3];
    helix_term_x2(c, 2, 1.0, phi, 0, 2, &value, &jac, hess);
    lane_scaled_hess(d2d0, hess, u2 * ul, 0);
    lane_scaled_hess(d2d1, hess, u2 * ul, 1);
}

void hk_element_motion(hk_Vec3 k, double u, hk_Vec3 kd, hk_Mat3 *rot, hk_Vec3 *offset, hk_Vec3 *spin, hk_Vec3 *slide)
{
    const hk_Vec3 phi = hk_v3_scale(k, u);
    double c[HK_CN_COUNT];
    const double x = hk_v3_dot(phi, phi);
    hk_helix_cn(x, c);
    hk_ElementLocal el;
    rotation_and_lambda(c, phi, x, u, &el);
    *rot = el.rot;
    *offset = hk_m3_col(&el.lam, 0);
    *spin = hk_m3_mul_v3(&el.lam, kd);
    /* dd kd = u^2 times h(phi; w = e0)'s derivative along kd (d/dk = u d/dphi). */
    hk_Vec3 d1;
    hk_helix_term_along(c, 2, phi, hk_v3_unit(0), kd, &d1, NULL);
    *slide = hk_v3_scale(d1, u * u);
}

void hk_element_slide(hk_Vec3 k, double u, hk_Vec3 kd, hk_Vec3 *offset, hk_Vec3 *slide)
{
    const hk_Vec3 phi = hk_v3_scale(k, u);
    double c[HK_CN_COUNT];
    const double x = hk_v3_dot(phi, phi);
    hk_helix_cn(x, c);
    *offset = hk_v3_scale(helix_term_e0(c, 2, 1.0, phi, x, 0.0, NULL), u);
    hk_Vec3 d1; /* as hk_element_motion's slide */
    hk_helix_term_along(c, 2, phi, hk_v3_unit(0), kd, &d1, NULL);
    *slide = hk_v3_scale(d1, u * u);
}

hk_Vec3 hk_element_offset_begin(hk_Vec3 k, double u, double c[HK_CN_COUNT])
{
    const hk_Vec3 phi = hk_v3_scale(k, u);
    const double x = hk_v3_dot(phi, phi);
    hk_helix_cn(x, c);
    return hk_v3_scale(helix_term_e0(c, 2, 1.0, phi, x, 0.0, NULL), u);
}

void hk_element_offset_derivs(hk_Vec3 k, double u, const double c[HK_CN_COUNT], hk_Mat3 *dd, hk_Vec3 d2d[3][3])
{
    const hk_Vec3 phi = hk_v3_scale(k, u);
    const double u2 = u * u;
    if (dd) helix_term_e0(c, 2, 1.0, phi, hk_v3_dot(phi, phi), u2, dd);
    if (!d2d) return;
    hk_HelixTerm t;
    hk_helix_term(c, 2, 1.0, phi, hk_v3_unit(0), 2, &t);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) d2d[i][j] = hk_v3_scale(t.hess[i][j], u2 * u);
}

hk_Vec3 hk_element_offset(hk_Vec3 k, double u, hk_Mat3 *dd, hk_Vec3 d2d[3][3])
{
    double c[HK_CN_COUNT];
    const hk_Vec3 d = hk_element_offset_begin(k, u, c);
    if (dd || d2d) hk_element_offset_derivs(k, u, c, dd, d2d);
    return d;
}
