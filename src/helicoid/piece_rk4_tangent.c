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

/* The four tangent columns side by side, two to a vector register: the differentiated
 * search trace is bound by the arithmetic of its four columns (docs/helicoid-fitting.md
 * §7), which the compiler does not pair by itself at -O2 with the columns as separate
 * structures. Element-wise IEEE operations in the same order as phased_tangent's: the
 * same values (a zero's sign aside, see phased_tangent_cols). Column pair c holds
 * parameters 2c and 2c + 1. */
typedef double Pair __attribute__((vector_size(16)));
typedef struct PhasedCols {
    Pair x[2], y[2], z[2], cz[2], sz[2], cp[2], sp[2];
} PhasedCols;

static inline __attribute__((always_inline)) void cols_from(const Phased *du, PhasedCols *c)
{
    for (int p = 0; p < 2; p++) {
        const Phased *a = &du[2 * p], *b = &du[2 * p + 1];
        c->x[p] = (Pair){a->x, b->x}, c->y[p] = (Pair){a->y, b->y}, c->z[p] = (Pair){a->z, b->z};
        c->cz[p] = (Pair){a->cz, b->cz}, c->sz[p] = (Pair){a->sz, b->sz};
        c->cp[p] = (Pair){a->cp, b->cp}, c->sp[p] = (Pair){a->sp, b->sp};
    }
}

static inline __attribute__((always_inline)) void cols_to(const PhasedCols *c, Phased *du)
{
    for (int p = 0; p < 2; p++)
        for (int e = 0; e < 2; e++)
            du[2 * p + e] =
                (Phased){c->x[p][e], c->y[p][e], c->z[p][e], c->cz[p][e], c->sz[p][e], c->cp[p][e], c->sp[p][e]};
}

/* phased_tangent for all four columns, pairwise (the parameter directions as unit
 * pairs). A pair's products with directions that are zero in both its lanes (k_T and k_N
 * for pair 1, k_B and alpha for pair 0) are left out: they add zeros, which change no
 * value but can change a zero's sign (phased_tangent's constant-folded form keeps them).
 * That was 2.3 % of a fit's instructions on Curly's strands of 16-32 points; the fits of
 * Sintel, Bangs and Curly hash the same as with them. */
static inline __attribute__((always_inline)) void
phased_tangent_cols(const hk_Helicoid *k, const PhasedPoint *f, const Phased *u, const PhasedCols *du, PhasedCols *dd)
{
    static const Pair dkt[2] = {{1.0, 0.0}, {0.0, 0.0}}, dkn[2] = {{0.0, 1.0}, {0.0, 0.0}};
    static const Pair dkb[2] = {{0.0, 0.0}, {1.0, 0.0}}, dal[2] = {{0.0, 0.0}, {0.0, 1.0}};
    const double wr = f->wr, wi = f->wi, ir = f->ir;
    for (int p = 0; p < 2; p++) {
        const Pair dwr = p == 0 ? dkn[p] * u->x + k->kn * du->x[p] - dkt[p] * u->y - k->kt * du->y[p]
                                : k->kn * du->x[p] - k->kt * du->y[p];
        const Pair dwi = p == 0 ? dkt[p] * u->x + k->kt * du->x[p] + dkn[p] * u->y + k->kn * du->y[p]
                                : k->kt * du->x[p] + k->kn * du->y[p];
        Pair dct = du->cz[p], dst = du->sz[p], dir = {0.0, 0.0};
        if (f->off_axis) {
            dir = -(wr * dwr + wi * dwi) * ir * ir * ir;
            dct = (dwr * u->cz + wr * du->cz[p] - dwi * u->sz - wi * du->sz[p]) * ir + (wr * u->cz - wi * u->sz) * dir;
            dst = (dwi * u->cz + wi * du->cz[p] + dwr * u->sz + wr * du->sz[p]) * ir + (wi * u->cz + wr * u->sz) * dir;
        }
        const Pair dx = du->cp[p] * f->ct + u->cp * dct;
        const Pair dy = du->cp[p] * f->st + u->cp * dst;
        const Pair dz = du->sp[p];
        const Pair ddwr =
            p == 0 ? dkn[p] * f->d.x + k->kn * dx - dkt[p] * f->d.y - k->kt * dy : k->kn * dx - k->kt * dy;
        const Pair ddwi =
            p == 0 ? dkt[p] * f->d.x + k->kt * dx + dkn[p] * f->d.y + k->kn * dy : k->kt * dx + k->kn * dy;
        const Pair dnum = ddwi * wr + f->dwi * dwr - ddwr * wi - f->dwr * dwi;
        const Pair dq = p == 1 ? dkb[p] * f->d.z + k->kb * dz : k->kb * dz;
        const Pair dth = dnum * (ir * ir) + f->num * 2.0 * ir * dir + dq;
        const Pair dp = p == 1 ? dal[p] * f->th + k->alpha * dth : k->alpha * dth;
        dd->x[p] = dx, dd->y[p] = dy, dd->z[p] = dz;
        dd->cz[p] = -du->sz[p] * f->q - u->sz * dq;
        dd->sz[p] = du->cz[p] * f->q + u->cz * dq;
        dd->cp[p] = -du->sp[p] * f->p - u->sp * dp;
        dd->sp[p] = du->cp[p] * f->p + u->cp * dp;
    }
}

/* The phased field at u and its four tangents for the state tangents du. */
static inline __attribute__((always_inline)) PhasedPoint phased_all(const hk_Helicoid *k, const Phased *u,
                                                                    const PhasedCols *du, PhasedCols *dd)
{
    const PhasedPoint f = phased_eval(k, u);
    phased_tangent_cols(k, &f, u, du, dd);
    return f;
}

static inline __attribute__((always_inline)) PhasedCols cols_axpy(const PhasedCols *u, double h, const PhasedCols *d)
{
    PhasedCols r;
    for (int p = 0; p < 2; p++) {
        r.x[p] = u->x[p] + h * d->x[p], r.y[p] = u->y[p] + h * d->y[p], r.z[p] = u->z[p] + h * d->z[p];
        r.cz[p] = u->cz[p] + h * d->cz[p], r.sz[p] = u->sz[p] + h * d->sz[p];
        r.cp[p] = u->cp[p] + h * d->cp[p], r.sp[p] = u->sp[p] + h * d->sp[p];
    }
    return r;
}

#define COLS_SUM(m) u->m[p] += h6 * (d1->m[p] + 2.0 * (d2->m[p] + d3->m[p]) + d4->m[p])
/* phased_sum for the columns */
static inline __attribute__((always_inline)) void cols_sum(PhasedCols *u, double h6, const PhasedCols *d1,
                                                           const PhasedCols *d2, const PhasedCols *d3,
                                                           const PhasedCols *d4)
{
    for (int p = 0; p < 2; p++) {
        COLS_SUM(x), COLS_SUM(y), COLS_SUM(z), COLS_SUM(cz), COLS_SUM(sz), COLS_SUM(cp), COLS_SUM(sp);
    }
}
#undef COLS_SUM

/* One RK4 step of length h of the phased state u and its tangents du (d1, dd1: the field
 * and its tangents there; on return those at the new state). */
static inline __attribute__((always_inline)) void phased_step_tangent(const hk_Helicoid *k, double h, Phased *u,
                                                                      PhasedCols *du, Phased *d1, PhasedCols *dd1)
{
    const double h2 = 0.5 * h, h6 = h / 6.0;
    PhasedCols t, dd2, dd3, dd4;
    t = cols_axpy(du, h2, dd1);
    Phased v = phased_axpy(u, h2, d1);
    const Phased d2 = phased_all(k, &v, &t, &dd2).d;
    t = cols_axpy(du, h2, &dd2);
    v = phased_axpy(u, h2, &d2);
    const Phased d3 = phased_all(k, &v, &t, &dd3).d;
    t = cols_axpy(du, h, &dd3);
    v = phased_axpy(u, h, &d3);
    const Phased d4 = phased_all(k, &v, &t, &dd4).d;
    *u = phased_sum(*u, h6, d1, &d2, &d3, &d4);
    cols_sum(du, h6, dd1, &dd2, &dd3, &dd4);
    *d1 = phased_all(k, u, du, dd1).d;
}

/* Sample i's point of u and derivatives of the columns du. */
static inline void phased_store(hk_Vec3 *points, hk_Vec3 *d_points, size_t stride, int i, const Phased *u,
                                const PhasedCols *du)
{
    points[i] = hk_v3(u->x, u->y, u->z);
    for (int p = 0; p < 2; p++)
        for (int e = 0; e < 2; e++)
            d_points[(size_t)(2 * p + e) * stride + (size_t)i] = hk_v3(du->x[p][e], du->y[p][e], du->z[p][e]);
}

static inline hk_Vec3 position(const Phased *u) { return hk_v3(u->x, u->y, u->z); }

/* Sample i's derivatives interpolated in the columns (hermite_point's sums, pairwise). */
static inline void cols_hermite_store(const Hermite *c, const PhasedCols *u0, const PhasedCols *f0,
                                      const PhasedCols *u1, const PhasedCols *f1, hk_Vec3 *d_points, size_t stride,
                                      int i)
{
    const Pair c0 = {c->c0, c->c0}, c1 = {c->c1, c->c1}, c2 = {c->c2, c->c2}, c3 = {c->c3, c->c3};
    for (int p = 0; p < 2; p++) {
        const Pair x = c0 * u0->x[p] + c1 * f0->x[p] + c2 * u1->x[p] + c3 * f1->x[p];
        const Pair y = c0 * u0->y[p] + c1 * f0->y[p] + c2 * u1->y[p] + c3 * f1->y[p];
        const Pair z = c0 * u0->z[p] + c1 * f0->z[p] + c2 * u1->z[p] + c3 * f1->z[p];
        for (int e = 0; e < 2; e++) d_points[(size_t)(2 * p + e) * stride + (size_t)i] = hk_v3(x[e], y[e], z[e]);
    }
}

void hk_helicoid_piece_rk4_tangent_local(const hk_Helicoid *k, double length, int steps, double turn, int span,
                                         hk_Vec3 *points, hk_Vec3 *d_points, hk_HelicoidAngles *end,
                                         hk_Vec3 *d_end_tangent)
{
    const double step = length / steps;
    const size_t stride = (size_t)steps + 1;
    double sa, sb;
    hk_helicoid_turn_bound(k, &sa, &sb);
    sa *= step / turn, sb *= step / turn;
    /* the tangents as columns (duc, ddc), as structures (du) for the end pose */
    Phased u = {0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0}, du[4], d1;
    for (int j = 0; j < 4; j++) du[j] = (Phased){0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    PhasedCols duc, ddc;
    cols_from(du, &duc);
    phased_store(points, d_points, stride, 0, &u, &duc);
    d1 = phased_all(k, &u, &duc, &ddc).d;
    for (int i = 0; i < steps;) {
        const int g = rk4_span(k, u.x, u.y, sa, sb, span < steps - i ? span : steps - i);
        if (g > 1) {
            /* one step over g samples, the ones inside interpolated */
            const Phased u0 = u, f0 = d1;
            const PhasedCols du0 = duc, df0 = ddc;
            const double h = g * step;
            phased_step_tangent(k, h, &u, &duc, &d1, &ddc);
            for (int q = 1; q < g; q++) {
                const Hermite c = hermite(h, (double)q / (double)g);
                points[i + q] = hermite_point(&c, position(&u0), position(&f0), position(&u), position(&d1));
                cols_hermite_store(&c, &du0, &df0, &duc, &ddc, d_points, stride, i + q);
            }
            i += g;
        } else {
            const int sub = rk4_substeps(k, u.x, u.y, sa, sb);
            const double h = step / sub;
            for (int s = 0; s < sub; s++) phased_step_tangent(k, h, &u, &duc, &d1, &ddc);
            i++;
        }
        phased_store(points, d_points, stride, i, &u, &duc);
    }
    cols_to(&duc, du);
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
