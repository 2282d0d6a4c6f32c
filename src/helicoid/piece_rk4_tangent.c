/* One helicoid piece traced by RK4 together with the derivatives of its points with
 * respect to its parameters (k_T, k_N, k_B, alpha): forward-mode differentiation through
 * the RK4 steps, one tangent of the state (x, y, z, psi) per parameter propagated beside
 * the trace with the same steps and substeps (the derivative of the discrete trace, not
 * of the exact streamline, so that it is the Jacobian of what the fitter compares). The
 * sines and cosines of each field evaluation serve the trace and all four tangents:
 * about twice the cost of a trace, where forward differences cost four more traces.
 * Piuze et al. 2011 §3 (eq. 1-2), §5 (fitting). */
#include <string.h>

#include "rk4_field.h"

/* The field's directional derivatives at the point f was evaluated at (state u), for a
 * state tangent du and the unit change of parameter j (0..3 = k_T, k_N, k_B, alpha):
 * eq. 1-2 differentiated term by term, as rk4_field computes them. */
static inline __attribute__((always_inline)) Deriv field_tangent(const hk_Helicoid *k, const FieldPoint *f, double x,
                                                                 double y, double z, Deriv du, int j)
{
    const double dkt = j == 0, dkn = j == 1, dkb = j == 2, dal = j == 3;
    const hk_HelicoidAngles *a = &f->a;
    const double wr = f->wr, wi = f->wi, ir = f->ir;
    const double dwr = dkn * x + k->kn * du.x - dkt * y - k->kt * du.y;
    const double dwi = dkt * x + k->kt * du.x + dkn * y + k->kn * du.y;
    const double dbz = dkb * z + k->kb * du.z; /* d (k_B z) */
    const double dt = du.psi + dbz;            /* d theta */
    double dct, dst, dir = 0.0;
    if (f->off_axis) {
        dir = -(wr * dwr + wi * dwi) * ir * ir * ir;
        const double dcz = -f->sz * dbz, dsz = f->cz * dbz;
        dct = (dwr * f->cz + wr * dcz - dwi * f->sz - wi * dsz) * ir + (wr * f->cz - wi * f->sz) * dir;
        dst = (dwi * f->cz + wi * dcz + dwr * f->sz + wr * dsz) * ir + (wi * f->cz + wr * f->sz) * dir;
    } else {
        dct = -a->st * dt;
        dst = a->ct * dt;
    }
    const double dphi = dal * a->theta + k->alpha * dt;
    const double dcp = -a->sp * dphi, dsp = a->cp * dphi;
    Deriv d;
    d.x = dcp * a->ct + a->cp * dct;
    d.y = dcp * a->st + a->cp * dst;
    d.z = dsp;
    /* psi' = Im(w' conj w) / |w|^2 with w' = c (x' + i y'), c = k_N + i k_T */
    const double vr = k->kn * f->d.x - k->kt * f->d.y, vi = k->kt * f->d.x + k->kn * f->d.y;
    const double dvr = dkn * f->d.x + k->kn * d.x - dkt * f->d.y - k->kt * d.y;
    const double dvi = dkt * f->d.x + k->kt * d.x + dkn * f->d.y + k->kn * d.y;
    const double num = vi * wr - vr * wi, dnum = dvi * wr + vi * dwr - dvr * wi - vr * dwi;
    d.psi = dnum * (ir * ir) + num * 2.0 * ir * dir;
    return d;
}

/* The field and its four tangents at state u with state tangents du. */
static inline __attribute__((always_inline)) void eval_all(const hk_Helicoid *k, Deriv u, const Deriv *du,
                                                           FieldPoint *f, Deriv *dd)
{
    rk4_field(k, u.x, u.y, u.z, u.psi, f);
    /* Written out so that each call's parameter direction is a constant the compiler
     * folds (the terms of the three other parameters vanish). */
    dd[0] = field_tangent(k, f, u.x, u.y, u.z, du[0], 0);
    dd[1] = field_tangent(k, f, u.x, u.y, u.z, du[1], 1);
    dd[2] = field_tangent(k, f, u.x, u.y, u.z, du[2], 2);
    dd[3] = field_tangent(k, f, u.x, u.y, u.z, du[3], 3);
}

static inline Deriv axpy(Deriv u, double h, Deriv d)
{
    return (Deriv){u.x + h * d.x, u.y + h * d.y, u.z + h * d.z, u.psi + h * d.psi};
}

static inline Deriv rk4_sum(Deriv u, double h6, Deriv d1, Deriv d2, Deriv d3, Deriv d4)
{
    u.x += h6 * (d1.x + 2.0 * (d2.x + d3.x) + d4.x);
    u.y += h6 * (d1.y + 2.0 * (d2.y + d3.y) + d4.y);
    u.z += h6 * (d1.z + 2.0 * (d2.z + d3.z) + d4.z);
    u.psi += h6 * (d1.psi + 2.0 * (d2.psi + d3.psi) + d4.psi);
    return u;
}

void hk_helicoid_piece_rk4_tangent(const hk_Helicoid *k, double length, int steps, hk_Vec3 *points, hk_Vec3 *d_points,
                                   hk_HelicoidAngles *end, hk_Vec3 *d_end_tangent)
{
    const double step = length / steps;
    const size_t stride = (size_t)steps + 1;
    double sa, sb;
    hk_helicoid_turn_bound(k, &sa, &sb);
    sa *= step / MAX_TURN_PER_STEP, sb *= step / MAX_TURN_PER_STEP;
    Deriv u = {0.0, 0.0, 0.0, 0.0}, du[4], t2[4], t3[4], t4[4], d2[4], d3[4], d4[4], d1[4];
    for (int j = 0; j < 4; j++) du[j] = u, d_points[(size_t)j * stride] = hk_v3_zero();
    points[0] = hk_v3_zero();
    FieldPoint f1, f;
    eval_all(k, u, du, &f1, d1);
    for (int i = 1; i <= steps; i++) {
        const int sub = rk4_substeps(k, u.x, u.y, sa, sb);
        const double h = step / sub, h2 = 0.5 * h, h6 = h / 6.0;
        for (int s = 0; s < sub; s++) {
            for (int j = 0; j < 4; j++) t2[j] = axpy(du[j], h2, d1[j]);
            eval_all(k, axpy(u, h2, f1.d), t2, &f, d2);
            const Deriv e2 = f.d;
            for (int j = 0; j < 4; j++) t3[j] = axpy(du[j], h2, d2[j]);
            eval_all(k, axpy(u, h2, e2), t3, &f, d3);
            const Deriv e3 = f.d;
            for (int j = 0; j < 4; j++) t4[j] = axpy(du[j], h, d3[j]);
            eval_all(k, axpy(u, h, e3), t4, &f, d4);
            u = rk4_sum(u, h6, f1.d, e2, e3, f.d);
            for (int j = 0; j < 4; j++) du[j] = rk4_sum(du[j], h6, d1[j], d2[j], d3[j], d4[j]);
            eval_all(k, u, du, &f1, d1);
        }
        points[i] = hk_v3(u.x, u.y, u.z);
        for (int j = 0; j < 4; j++) d_points[(size_t)j * stride + (size_t)i] = hk_v3(du[j].x, du[j].y, du[j].z);
    }
    *end = f1.a;
    for (int j = 0; j < 4; j++) d_end_tangent[j] = hk_v3(d1[j].x, d1[j].y, d1[j].z);
}

/* ---- the search's phased trace (rk4_field.h) and its derivatives ---------------------- */

/* The phased field's directional derivative at f (state u) for a state tangent du and
 * the unit change of parameter j (0..3 = k_T, k_N, k_B, alpha): phased_eval
 * differentiated term by term. */
static inline __attribute__((always_inline)) Phased phased_tangent(const hk_Helicoid *k, const PhasedPoint *f,
                                                                   const Phased *u, const Phased *du, int j)
{
    const double dkt = j == 0, dkn = j == 1, dkb = j == 2, dal = j == 3;
    const double wr = f->wr, wi = f->wi, ir = f->ir;
    const double dwr = dkn * u->x + k->kn * du->x - dkt * u->y - k->kt * du->y;
    const double dwi = dkt * u->x + k->kt * du->x + dkn * u->y + k->kn * du->y;
    double dct = du->cz, dst = du->sz, dir = 0.0;
    if (f->off_axis) {
        dir = -(wr * dwr + wi * dwi) * ir * ir * ir;
        dct = (dwr * u->cz + wr * du->cz - dwi * u->sz - wi * du->sz) * ir + (wr * u->cz - wi * u->sz) * dir;
        dst = (dwi * u->cz + wi * du->cz + dwr * u->sz + wr * du->sz) * ir + (wi * u->cz + wr * u->sz) * dir;
    }
    Phased d;
    d.x = du->cp * f->ct + u->cp * dct;
    d.y = du->cp * f->st + u->cp * dst;
    d.z = du->sp;
    const double ddwr = dkn * f->d.x + k->kn * d.x - dkt * f->d.y - k->kt * d.y;
    const double ddwi = dkt * f->d.x + k->kt * d.x + dkn * f->d.y + k->kn * d.y;
    const double dnum = ddwi * wr + f->dwi * dwr - ddwr * wi - f->dwr * dwi;
    const double dq = dkb * f->d.z + k->kb * d.z;
    const double dth = dnum * (ir * ir) + f->num * 2.0 * ir * dir + dq;
    const double dp = dal * f->th + k->alpha * dth;
    d.cz = -du->sz * f->q - u->sz * dq;
    d.sz = du->cz * f->q + u->cz * dq;
    d.cp = -du->sp * f->p - u->sp * dp;
    d.sp = du->cp * f->p + u->cp * dp;
    return d;
}

/* The phased field at u and its four tangents for the state tangents du. */
static inline __attribute__((always_inline)) PhasedPoint phased_all(const hk_Helicoid *k, const Phased *u,
                                                                    const Phased *du, Phased *dd)
{
    const PhasedPoint f = phased_eval(k, u);
    dd[0] = phased_tangent(k, &f, u, &du[0], 0);
    dd[1] = phased_tangent(k, &f, u, &du[1], 1);
    dd[2] = phased_tangent(k, &f, u, &du[2], 2);
    dd[3] = phased_tangent(k, &f, u, &du[3], 3);
    return f;
}

/* One RK4 step of length h of the phased state u and its tangents du (d1, dd1: the field
 * and its tangents there; on return those at the new state). */
static inline __attribute__((always_inline)) void phased_step_tangent(const hk_Helicoid *k, double h, Phased *u,
                                                                      Phased *du, Phased *d1, Phased *dd1)
{
    const double h2 = 0.5 * h, h6 = h / 6.0;
    Phased t[4], dd2[4], dd3[4], dd4[4];
    for (int j = 0; j < 4; j++) t[j] = phased_axpy(&du[j], h2, &dd1[j]);
    Phased v = phased_axpy(u, h2, d1);
    const Phased d2 = phased_all(k, &v, t, dd2).d;
    for (int j = 0; j < 4; j++) t[j] = phased_axpy(&du[j], h2, &dd2[j]);
    v = phased_axpy(u, h2, &d2);
    const Phased d3 = phased_all(k, &v, t, dd3).d;
    for (int j = 0; j < 4; j++) t[j] = phased_axpy(&du[j], h, &dd3[j]);
    v = phased_axpy(u, h, &d3);
    const Phased d4 = phased_all(k, &v, t, dd4).d;
    *u = phased_sum(*u, h6, d1, &d2, &d3, &d4);
    for (int j = 0; j < 4; j++) du[j] = phased_sum(du[j], h6, &dd1[j], &dd2[j], &dd3[j], &dd4[j]);
    *d1 = phased_all(k, u, du, dd1).d;
}

static inline void phased_store(hk_Vec3 *points, hk_Vec3 *d_points, size_t stride, int i, const Phased *u,
                                const Phased *du)
{
    points[i] = hk_v3(u->x, u->y, u->z);
    for (int j = 0; j < 4; j++) d_points[(size_t)j * stride + (size_t)i] = hk_v3(du[j].x, du[j].y, du[j].z);
}

static inline Deriv position(const Phased *u) { return (Deriv){u->x, u->y, u->z, 0.0}; }

void hk_helicoid_piece_rk4_tangent_local(const hk_Helicoid *k, double length, int steps, double turn, int span,
                                         hk_Vec3 *points, hk_Vec3 *d_points, hk_HelicoidAngles *end,
                                         hk_Vec3 *d_end_tangent)
{
    const double step = length / steps;
    const size_t stride = (size_t)steps + 1;
    double sa, sb;
    hk_helicoid_turn_bound(k, &sa, &sb);
    sa *= step / turn, sb *= step / turn;
    Phased u = {0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0}, du[4], d1, dd1[4];
    for (int j = 0; j < 4; j++) du[j] = (Phased){0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    phased_store(points, d_points, stride, 0, &u, du);
    d1 = phased_all(k, &u, du, dd1).d;
    for (int i = 0; i < steps;) {
        const int g = rk4_span(k, u.x, u.y, sa, sb, span < steps - i ? span : steps - i);
        if (g > 1) {
            /* one step over g samples, the ones inside interpolated */
            const Phased u0 = u, f0 = d1;
            Phased du0[4], df0[4];
            memcpy(du0, du, sizeof du0);
            memcpy(df0, dd1, sizeof df0);
            const double h = g * step;
            phased_step_tangent(k, h, &u, du, &d1, dd1);
            for (int q = 1; q < g; q++) {
                const double t = (double)q / (double)g;
                const Deriv p = hermite(position(&u0), position(&f0), position(&u), position(&d1), h, t);
                points[i + q] = hk_v3(p.x, p.y, p.z);
                for (int j = 0; j < 4; j++) {
                    const Deriv dp =
                        hermite(position(&du0[j]), position(&df0[j]), position(&du[j]), position(&dd1[j]), h, t);
                    d_points[(size_t)j * stride + (size_t)(i + q)] = hk_v3(dp.x, dp.y, dp.z);
                }
            }
            i += g;
        } else {
            const int sub = rk4_substeps(k, u.x, u.y, sa, sb);
            const double h = step / sub;
            for (int s = 0; s < sub; s++) phased_step_tangent(k, h, &u, du, &d1, dd1);
            i++;
        }
        phased_store(points, d_points, stride, i, &u, du);
    }
    /* The end pose from unit phases (hk_helicoid_piece_rk4_local), its tangent's
     * derivatives those of that pose. */
    const Phased unit = phased_unit(&u, du, 4);
    const PhasedPoint f = phased_eval(k, &unit);
    *end = phased_angles(&f, &unit);
    for (int j = 0; j < 4; j++) {
        const Phased d = phased_tangent(k, &f, &unit, &du[j], j);
        d_end_tangent[j] = hk_v3(d.x, d.y, d.z);
    }
}
