/* Time stepping of one Super-Helix: TR-BDF2 with Newton's iteration on every stage,
 * and the error control of hk_strand_dynamics_advance (docs/dynamics.md, "Time
 * stepping").
 *
 * The equations of motion M(q) q'' = f(q, q', t) (paper 000 eq. 4-6) are stepped by
 * TR-BDF2 (R. E. Bank, W. M. Coughran, W. Fichtner, E. H. Grosse, D. J. Rose, R. K.
 * Smith, "Transient simulation of silicon devices and circuits", IEEE Trans. CAD 4(4),
 * 1985; M. E. Hosea, L. F. Shampine, "Analysis and implementation of TR-BDF2", Applied
 * Numerical Mathematics 20, 1996), with g = 2 - sqrt 2:
 *
 *   trapezoidal stage, t -> t + g h:
 *     q_g = q_0 + (g h / 2)(v_0 + v_g),   M(q_g)(v_g - v_0 - (g h / 2) a_0) = (g h / 2) f_g
 *   BDF2 stage through t, t + g h, t + h:
 *     q_1 = w_g q_g + w_0 q_0 + c h v_1,  M(q_1)(v_1 - w_g v_g - w_0 v_0) = c h f_1
 *   w_g = 1 / (g (2 - g)), w_0 = 1 - w_g, c = (1 - g) / (2 - g).
 *
 * Both stages have the form q = aq + ch v, M(q)(v - av) = ch f(q, v) with the same
 * ch = (g / 2) h = c h = (1 - 1/sqrt 2) h. a_0 = q''(t) is the previous step's last
 * stage, (v_1 - av) / ch ("first same as last"), computed afresh only when the state was
 * changed from outside. The method is second order and L-stable: its amplification
 * tends to 0 for stiff modes (the twist of a thin section, contacts), and at the
 * paper's dt = 1/30 s a 4 Hz bounce (7.5 steps a period) keeps 98.8 % of its amplitude
 * per period with a 2.8 % longer period (linearly implicit Euler: 14 % and 20 %).
 *
 * Each stage is solved by Newton's iteration with the matrix M + ch D + ch^2 K of
 * strand_dynamics.c, where the residual holds every force at the iterate: the velocity
 * products, the inertial forces of the head's motion, the change of M, gravity's and
 * the contacts' geometric stiffness. Linearly implicit schemes leave these explicit;
 * with thin hair's stiff twist they fed energy into long strands until the step failed
 * (issue 12: a 1 m wavy strand at dt = 1/30 s). */
#include <math.h>
#include <string.h>

#include "dynamics_internal.h"
#include "collide/collide_internal.h"
#include "core/avx_twins.h"
#include "core/linalg.h"
#include "motion_internal.h"

#define HK_TRAVEL_NODES 64

static const double TR_G = 0.58578643762690495119;  /* 2 - sqrt 2 */
static const double TR_CH = 0.29289321881345247560; /* (1 - 1/sqrt 2): g / 2 = (1 - g) / (2 - g) */

/* The head's state tau seconds before `state`, from its velocities and accelerations
 * (second order, enough for the inner stage of a step given only its end state). */
static hk_RigidState head_before(const hk_RigidState *state, double tau)
{
    hk_RigidState s = *state;
    s.trans = hk_v3_add(hk_v3_madd(state->trans, state->vel, -tau), hk_v3_scale(state->acc, 0.5 * tau * tau));
    s.vel = hk_v3_madd(state->vel, state->acc, -tau);
    s.omega = hk_v3_madd(state->omega, state->alpha, -tau);
    const hk_Vec3 turn = hk_v3_add(hk_v3_scale(state->omega, -tau), hk_v3_scale(state->alpha, 0.5 * tau * tau));
    hk_Mat3 r;
    hk_Vec3 omega, alpha; /* of a constant turn: zero */
    hk_rotation_exp(turn, hk_v3_zero(), hk_v3_zero(), &r, &omega, &alpha);
    s.rot = hk_m3_mul(&r, &state->rot);
    return s;
}

static int all_finite(const double *x, int count)
{
    for (int i = 0; i < count; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* Largest turn of an element's frame that the change dq of the coordinates makes:
 * |Lambda(l) dq| <= l |dq|. */
static double turn_of(const hk_SuperHelix *sh, const double *dq, double scale)
{
    double turn = 0.0;
    for (int p = 0; p < sh->n; p++) {
        const double *x = dq + 3 * p;
        turn = fmax(turn, sh->length[p] * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]));
    }
    return turn * fabs(scale);
}

/* Anderson's mixing of Newton's corrections (D. G. Anderson, "Iterative procedures for
 * nonlinear integral equations", J. ACM 12(4), 1965; H. F. Walker, P. Ni, "Anderson
 * acceleration for fixed-point iterations", SIAM J. Numer. Anal. 49(4), 2011). The
 * iteration matrix leaves out terms of the stage's true Jacobian: the velocity
 * products, the change of M, and with the O(N) solver every geometric stiffness (of
 * gravity, the body's penalty and the caller's point forces, whose direction turns with
 * the strand). Newton's iteration v += g, g = -A^-1 F(v), then converges only linearly
 * and overshoots where the missing terms are large: on a head of 1 m guides pressed
 * together by their contacts, 39 % of the stages failed (28 % by growing corrections,
 * 11 % by reaching 12 iterations) and each failure split the step; with the mixing
 * 29 % failed, nearly all by growth, and the evaluations per guide and frame fell from
 * 50 to 35 (an undamped 1 m strand on a still head: 910 to 273). Anderson's step takes the
 * combination of the last corrections whose mixed correction is least,
 *     gamma = argmin | g_k - dG gamma |,   v <- v + g_k - (dX + dG) gamma,
 * with dX, dG the differences of the last iterates and corrections: a secant update of
 * A^-1 over the directions already seen (a multisecant quasi-Newton method, Fang and
 * Saad 2009), which supplies the missing terms there. The norm weighs coordinate j by
 * its element's length, as turn_of does. Returns the mixed correction in g. */
typedef struct Mixing {
    int count, next; /* stored differences (at most HK_ANDERSON_DEPTH), the next slot */
} Mixing;

static void mixing_step(hk_StrandDynamics *d, Mixing *m, int it, double *g)
{
    const hk_SuperHelix *sh = d->sh;
    const int dim = 3 * sh->n, depth = HK_ANDERSON_DEPTH;
    double *dx = d->mixing, *dg = dx + (size_t)depth * (size_t)dim;
    double *last_v = dg + (size_t)depth * (size_t)dim, *last_g = last_v + dim;
    if (it > 0) { /* the newest differences, over the oldest slot */
        double *x = dx + (size_t)m->next * (size_t)dim, *y = dg + (size_t)m->next * (size_t)dim;
        for (int j = 0; j < dim; j++) x[j] = d->v[j] - last_v[j], y[j] = g[j] - last_g[j];
        m->next = (m->next + 1) % depth;
        if (m->count < depth) m->count++;
    }
    memcpy(last_v, d->v, (size_t)dim * sizeof(double));
    memcpy(last_g, g, (size_t)dim * sizeof(double));
    const int k = m->count;
    if (k == 0) return;
    /* Normal equations of the weighted least squares, (dG^T W dG + eps) gamma = dG^T W g,
     * solved by Cholesky; a tiny ridge keeps nearly parallel differences harmless. */
    double a[HK_ANDERSON_DEPTH * HK_ANDERSON_DEPTH], b[HK_ANDERSON_DEPTH], l[HK_ANDERSON_DEPTH * HK_ANDERSON_DEPTH];
    for (int r = 0; r < k; r++) {
        const double *yr = dg + (size_t)r * (size_t)dim;
        double sb = 0.0;
        for (int j = 0; j < dim; j++) sb += sh->length[j / 3] * yr[j] * g[j];
        b[r] = sb;
        for (int c = 0; c <= r; c++) {
            const double *yc = dg + (size_t)c * (size_t)dim;
            double sa = 0.0;
            for (int j = 0; j < dim; j++) sa += sh->length[j / 3] * yr[j] * yc[j];
            a[r * k + c] = a[c * k + r] = sa;
        }
    }
    double trace = 0.0;
    for (int r = 0; r < k; r++) trace += a[r * k + r];
    if (!(trace > 0.0) || !isfinite(trace)) return;
    if (!hk_cholesky_factor(k, a, 1e-10 * trace / k, NULL, l)) return;
    hk_cholesky_solve(k, l, b);
    if (!all_finite(b, k)) return;
    for (int r = 0; r < k; r++) {
        const double *x = dx + (size_t)r * (size_t)dim, *y = dg + (size_t)r * (size_t)dim;
        for (int j = 0; j < dim; j++) g[j] -= b[r] * (x[j] + y[j]);
    }
}

/* Newton's iteration for one stage, q = aq + ch v, M(q)(v - av) = ch f(q, v, head),
 * from the guess in d->v, with Anderson's mixing from the second iteration on.
 * Returns 0 when it does not converge. */
static int newton(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces, int force_count,
                  double ch)
{
    hk_SuperHelix *sh = d->sh;
    const int dim = 3 * sh->n;
    double previous = INFINITY;
    Mixing mixing = {0, 0};
    for (int it = 0; it < d->params.newton_iterations; it++) {
        for (int j = 0; j < dim; j++) {
            sh->q[j] = d->aq[j] + ch * d->v[j];
            d->x[j] = d->v[j] - d->av[j];
        }
        hk_dynamics_evaluate(d, head, forces, force_count, ch, d->x);
        for (int j = 0; j < dim; j++) d->rhs[j] *= ch;
        d->stats.iterations++;
        if (!hk_dynamics_solve(d, ch, d->delta) || !all_finite(d->delta, dim)) return 0;
        /* Judged on Newton's own correction: the residual seen through A^-1. */
        const double turn = turn_of(sh, d->delta, ch);
        /* Converged; or stalled within ten times the tolerance, where the residual's
         * small discontinuities (contacts switching between iterates, the quadrature
         * following the curvature) keep the corrections from shrinking: more
         * iterations would not help. */
        if (turn <= d->params.newton_tolerance ||
            (it >= 1 && turn <= 10.0 * d->params.newton_tolerance && turn > 0.5 * previous)) {
            for (int j = 0; j < dim; j++) d->v[j] += d->delta[j];
            for (int j = 0; j < dim; j++) sh->q[j] = d->aq[j] + ch * d->v[j];
            return all_finite(sh->q, dim);
        }
        /* A correction that grows after the first few is a divergence: give up early. */
        if (it >= 2 && turn > previous) return 0;
        previous = turn;
        mixing_step(d, &mixing, it, d->delta);
        if (!all_finite(d->delta, dim)) return 0;
        for (int j = 0; j < dim; j++) d->v[j] += d->delta[j];
    }
    return 0;
}

/* One stage. With the O(N) solver a stage that does not converge is solved again, from
 * the same guess, with the dense matrix and the Hessian of elastic energy and gravity:
 * hair lying on the scalp or held above its root has a negative geometric stiffness
 * that the O(N) matrix lacks, and there Newton's corrections grew three to seven times
 * per iteration. Only then: the dense solve is O(N^3). */
static int solve_stage(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces, int force_count,
                       double ch)
{
    const size_t bytes = (size_t)(3 * d->sh->n) * sizeof(double);
    memcpy(d->start_guess, d->v, bytes);
    if (newton(d, head, forces, force_count, ch)) return 1;
    if (d->params.solver != HK_DYNAMICS_LINEAR || !hk_dynamics_dense_ready(d)) return 0;
    memcpy(d->v, d->start_guess, bytes);
    d->dense_fallback = 1;
    d->stats.dense_stages++;
    const int ok = newton(d, head, forces, force_count, ch);
    d->dense_fallback = 0;
    return ok;
}

static int state_is(const hk_StrandDynamics *d, const double *qv)
{
    const int dim = 3 * d->sh->n;
    const size_t bytes = (size_t)dim * sizeof(double);
    return memcmp(qv, d->sh->q, bytes) == 0 && memcmp(qv + dim, d->v, bytes) == 0;
}

/* q'' at the start of a step: the last stage's (first same as last) when the state is
 * the one it was computed for, else from M a = f. */
static int start_acceleration(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces,
                              int force_count)
{
    const int dim = 3 * d->sh->n;
    if (d->acc_valid && state_is(d, d->acc_at)) return 1;
    hk_dynamics_evaluate(d, head, forces, force_count, 0.0, NULL);
    d->stats.iterations++;
    return hk_dynamics_solve(d, 0.0, d->acc) && all_finite(d->acc, dim);
}

/* Whether the head stands still through the step: the strand's energy can then only
 * fall (internal friction, air drag, friction on the body) or stay. */
static int head_still(const hk_RigidState heads[3])
{
    for (int i = 0; i < 3; i++) {
        const hk_RigidState *h = &heads[i];
        if (hk_v3_norm2(h->vel) + hk_v3_norm2(h->acc) + hk_v3_norm2(h->omega) + hk_v3_norm2(h->alpha) != 0.0 ||
            memcmp(&h->rot, &heads[0].rot, sizeof h->rot) != 0 ||
            memcmp(&h->trans, &heads[0].trans, sizeof h->trans) != 0)
            return 0;
    }
    return 1;
}

/* The energy guard: on a still head without the caller's forces the total energy
 * (kinetic, elastic, gravity, the body's penalty) cannot rise, yet no implicit
 * Runge-Kutta method conserves or dissipates the energy of a nonlinear system exactly:
 * an undamped whipping strand gained up to 4 % of its available energy over 10 s at
 * dt = 1/30 s with TR-BDF2 alone. A step that ends with more energy than it started
 * with gives the excess back from the kinetic energy, scaling the velocity (an energy
 * projection on the velocity alone, in the spirit of D. Dinev, T. Liu, L. Kavan,
 * "Stabilizing integrators for real-time physics", ACM TOG 37(1), 2018). The scaled
 * velocity keeps its direction, so the motion's shape is unchanged. */
static void energy_start(hk_StrandDynamics *d, const hk_RigidState *head)
{
    if (!(d->energy_valid && state_is(d, d->acc_at))) d->energy = hk_dynamics_total_energy(d, head, NULL);
}

static int energy_guard(hk_StrandDynamics *d, const hk_RigidState *head, double start)
{
    double kinetic;
    const double end = hk_dynamics_total_energy(d, head, &kinetic);
    d->energy = end;
    d->energy_valid = 1;
    /* Rounding in the sums of the energy is not worth a projection (which costs the
     * next step an evaluation of the acceleration): a relative 1e-12 of it passes. */
    if (!(end - start > 1e-12 * (fabs(start) + fabs(end))) || !(kinetic > 0.0)) return 0;
    const double excess = end - start, scale = excess < kinetic ? sqrt((kinetic - excess) / kinetic) : 0.0;
    const int dim = 3 * d->sh->n;
    for (int j = 0; j < dim; j++) d->v[j] *= scale;
    d->energy = end - kinetic * (1.0 - scale * scale);
    d->stats.projections++;
    return 1;
}

/* The value at x of the quadratic through (xa, a), (xb, b), (xc, c): Lagrange's form.
 * Times in steps from the start of the present step. */
static double quadratic_nodes(double a, double b, double c, double xa, double xb, double xc, double x)
{
    return a * (x - xb) * (x - xc) / ((xa - xb) * (xa - xc)) + b * (x - xa) * (x - xc) / ((xb - xa) * (xb - xc)) +
           c * (x - xa) * (x - xb) / ((xc - xa) * (xc - xb));
}

/* One TR-BDF2 step of h from the state in sh->q, d->v, with the head in the states
 * heads[0..2] at t, t + g h and t + h. On failure the state is left changed (callers
 * restore it). */
static int tr_bdf2(hk_StrandDynamics *d, const hk_RigidState heads[3], const hk_PointForce *forces, int force_count,
                   double h)
{
    hk_SuperHelix *sh = d->sh;
    const int dim = 3 * sh->n;
    const size_t bytes = (size_t)dim * sizeof(double);
    const double ch = TR_CH * h, wg = 1.0 / (TR_G * (2.0 - TR_G)), w0 = 1.0 - wg;
    const int guard = force_count == 0 && head_still(heads);
    d->prev_at_end = state_is(d, d->acc_at); /* the state is where the last step ended */
    if (guard) energy_start(d, &heads[0]);
    const double energy0 = d->energy;
    d->energy_valid = 0;
    if (!start_acceleration(d, &heads[0], forces, force_count)) return 0;
    memcpy(d->q0, sh->q, bytes);
    memcpy(d->v0, d->v, bytes);
    /* Trapezoidal stage. The guess: with the last step of the same size just before,
     * the velocity's quadratic through that step's start, its first stage and now,
     * continued (the stages are implicit, so the stiff modes cannot spoil it);
     * otherwise the velocity at the start. An explicit predictor, v0 + g h a0, is far
     * off wherever stiff forces make a0 large - contacts just found, the twist of a
     * thin section - and Newton's iteration then starts where the velocity products
     * are huge. */
    const int extrapolate = d->prev_h == h && d->prev_at_end;
    for (int j = 0; j < dim; j++) {
        d->aq[j] = d->q0[j] + ch * d->v0[j];
        d->av[j] = d->v0[j] + ch * d->acc[j];
        if (extrapolate) d->v[j] = quadratic_nodes(d->prev_v0[j], d->prev_vg[j], d->v0[j], -1.0, TR_G - 1.0, 0.0, TR_G);
    }
    if (!solve_stage(d, &heads[1], forces, force_count, ch)) return 0;
    memcpy(d->qg, sh->q, bytes);
    memcpy(d->vg, d->v, bytes);
    /* BDF2 stage; the guess: the quadratic through the last step's first stage, the
     * start and the first stage, or the first stage's velocity. */
    for (int j = 0; j < dim; j++) {
        d->aq[j] = wg * d->qg[j] + w0 * d->q0[j];
        d->av[j] = wg * d->vg[j] + w0 * d->v0[j];
        if (extrapolate) d->v[j] = quadratic_nodes(d->prev_vg[j], d->v0[j], d->vg[j], TR_G - 1.0, 0.0, TR_G, 1.0);
    }
    if (!solve_stage(d, &heads[2], forces, force_count, ch)) return 0;
    for (int j = 0; j < dim; j++) d->acc[j] = (d->v[j] - d->av[j]) / ch;
    memcpy(d->prev_v0, d->v0, bytes);
    memcpy(d->prev_vg, d->vg, bytes);
    d->prev_h = h;
    /* a scaled velocity has another acceleration: computed afresh next step */
    d->acc_valid = !(guard && energy_guard(d, &heads[2], energy0));
    memcpy(d->acc_at, sh->q, bytes);
    memcpy(d->acc_at + dim, d->v, bytes);
    d->stats.steps++;
    return 1;
}

/* out += row j of the dim x dim matrix a times v_j, for j = 0, 1, ... (G+ v in
 * hk_dynamics_euler_delta): each out[i] takes its terms in the order of j, four (wide,
 * the AVX path), two or one entries at a time kept in a register over the rows, instead
 * of loaded and stored for every row. */
static inline __attribute__((always_inline)) void rows_times(const double *a, const double *v, int dim,
                                                             double *restrict out, int wide)
{
    typedef double Quad __attribute__((vector_size(32)));
    typedef double Pair __attribute__((vector_size(16)));
    const size_t stride = (size_t)dim;
    int i = 0;
#define HK_ROWS_TIMES(V)                                                                                               \
    do {                                                                                                               \
        V sum, r;                                                                                                      \
        memcpy(&sum, out + i, sizeof sum);                                                                             \
        for (int j = 0; j < dim; j++) {                                                                                \
            memcpy(&r, a + (size_t)j * stride + (size_t)i, sizeof r);                                                  \
            sum += r * v[j];                                                                                           \
        }                                                                                                              \
        memcpy(out + i, &sum, sizeof sum);                                                                             \
    } while (0)
    if (wide)
        for (; i + 4 <= dim; i += 4) HK_ROWS_TIMES(Quad);
    for (; i + 2 <= dim; i += 2) HK_ROWS_TIMES(Pair);
#undef HK_ROWS_TIMES
    for (; i < dim; i++) {
        double sum = out[i];
        for (int j = 0; j < dim; j++) sum += a[(size_t)j * stride + (size_t)i] * v[j];
        out[i] = sum;
    }
}

/* Four entries a vector on AVX, two in the baseline: the same bits (core/linalg.h,
 * hk_avx_path). */
__attribute__((target("avx"))) static void rows_times_avx(const double *a, const double *v, int dim, double *out)
{
    rows_times(a, v, dim, out, 1);
}

static void rows_times_sse2(const double *a, const double *v, int dim, double *out) { rows_times(a, v, dim, out, 0); }

/* The linearly implicit Euler step of issue 6 (paper 000 §3.4), kept for full heads
 * where its cost matters more than its accuracy:
 *     (M + h D + h^2 K) dv = h (f - h K v),   v += dv,   q += h v,
 * every force at the start of the step, K the iteration matrix's stiffness (with the
 * full stiffness its geometric part G+ too). First order; the velocity products and
 * the negative geometric stiffness explicit. */
int hk_dynamics_euler_delta(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces,
                            int force_count, double h)
{
    HK_AVX_TWIN_RETURN(hk_dynamics_euler_delta, d, head, forces, force_count, h);
    hk_SuperHelix *sh = d->sh;
    const int n = sh->n, dim = 3 * n;
    hk_dynamics_evaluate(d, head, forces, force_count, h, NULL);
    const int full = d->params.stiffness == HK_STIFFNESS_FULL;
    double *restrict geo_v = d->x; /* G+ v */
    memset(geo_v, 0, (size_t)dim * sizeof(double));
    if (full) {
        /* G+ is symmetric to the bit (its rows are its columns), so row j of G+ times
         * v_j added for j = 0, 1, ... gives every entry of G+ v its sum in the order of
         * row i . v, the same bits, with the loop over i contiguous (vectorised). */
        const double *geo = hk_dynamics_geometric_positive(d);
        if (hk_avx_path())
            rows_times_avx(geo, d->v, dim, geo_v);
        else
            rows_times_sse2(geo, d->v, dim, geo_v);
    }
    for (int j = 0; j < dim; j++) {
        const double kl = sh->material.stiffness[j % 3] * sh->length[j / 3];
        d->rhs[j] = h * (d->rhs[j] - h * kl * d->v[j] - h * geo_v[j]);
    }
    d->stats.iterations++;
    return hk_dynamics_solve(d, h, d->delta) && all_finite(d->delta, dim);
}

static int linear_euler(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces, int force_count,
                        double h)
{
    hk_SuperHelix *sh = d->sh;
    const int dim = 3 * sh->n;
    if (!hk_dynamics_euler_delta(d, head, forces, force_count, h)) return 0;
    for (int j = 0; j < dim; j++) {
        d->v[j] += d->delta[j];
        sh->q[j] += h * d->v[j];
    }
    d->acc_valid = 0;
    d->stats.steps++;
    return all_finite(sh->q, dim);
}

/* One step of the chosen integrator. */
static int integrate(hk_StrandDynamics *d, const hk_RigidState heads[3], const hk_PointForce *forces, int force_count,
                     double h)
{
    if (d->params.integrator == HK_INTEGRATOR_LINEAR_EULER) return linear_euler(d, &heads[2], forces, force_count, h);
    return tr_bdf2(d, heads, forces, force_count, h);
}

static void save_state(hk_StrandDynamics *d)
{
    const size_t bytes = (size_t)(3 * d->sh->n) * sizeof(double);
    memcpy(d->saved, d->sh->q, bytes);
    memcpy(d->saved + 3 * d->sh->n, d->v, bytes);
}

static void restore_state(hk_StrandDynamics *d)
{
    const size_t bytes = (size_t)(3 * d->sh->n) * sizeof(double);
    memcpy(d->sh->q, d->saved, bytes);
    memcpy(d->v, d->saved + 3 * d->sh->n, bytes);
    d->acc_valid = 0;
    d->energy_valid = 0;
    d->prev_h = 0.0;
}

hk_Status hk_strand_dynamics_step(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces,
                                  int force_count, double dt, hk_Error *err)
{
    HK_AVX_TWIN_RETURN(hk_strand_dynamics_step, d, head, forces, force_count, dt, err);
    if (!(dt > 0.0) || !isfinite(dt)) return hk_error_set(err, HK_ERR_INVALID, "time step must be > 0, got %g", dt);
    const hk_RigidState still = hk_rigid_identity();
    if (!head) head = &still;
    const hk_RigidState heads[3] = {head_before(head, dt), head_before(head, (1.0 - TR_G) * dt), *head};
    hk_Status st = hk_dynamics_anchor_forces(d, &heads[0], forces, force_count, err);
    if (st != HK_OK) return st;
    save_state(d);
    if (!integrate(d, heads, forces, force_count, dt)) {
        restore_state(d);
        d->stats.failures++;
        hk_strand_dynamics_place(d, head);
        return hk_error_set(err, HK_ERR_NUMERIC,
                            "dynamics step failed: Newton's iteration did not converge or the state is "
                            "not finite (time step %g s too large?)",
                            dt);
    }
    hk_strand_dynamics_place(d, head);
    return HK_OK;
}

/* Whether a head-space point lies within `margin` of a body shape's envelope. A shape
 * the point is beyond the reach of (hk_shape_beyond) is passed without its dent: a
 * node near the head is far from the neck, the face or the styling sphere, and the
 * dents were a sixth of the error control's instructions (docs/dynamics.md, "Speed",
 * 7 December 2026); the answer is the same. */
static int near_body(const hk_StrandDynamics *d, hk_Vec3 x, double margin)
{
    for (int k = 0; k < d->contact.shape_count; k++) {
        const hk_Shape *sh = &d->contact.shapes[k];
        const double extra = d->contact.envelope_alpha * sh->volume;
        if (hk_shape_beyond(sh, extra, margin, x)) continue;
        if (hk_shape_dent(sh, x, NULL, NULL) + extra > -margin) return 1;
    }
    return 0;
}

/* Largest displacement over the step, relative to the head, of a node that ends near
 * the body (the strand's shape in head space before and after): contacts are sampled
 * at the iterates of a step, so a node that travels farther than the collision
 * samples' spacing in one step can pass into the body unseen. Far from the body a fast
 * node needs no smaller step. */
static double largest_travel(hk_StrandDynamics *d)
{
    if (d->contact.shape_count == 0) return 0.0;
    hk_SuperHelix *sh = d->sh;
    hk_Vec3 before_buf[HK_TRAVEL_NODES + 1], after_buf[HK_TRAVEL_NODES + 1];
    const hk_Vec3 *before = before_buf, *after = after_buf;
    int n = sh->n;
    if (n > HK_TRAVEL_NODES) { /* long strands: the tip alone */
        n = 1;
        before_buf[1] = hk_dynamics_head_space_tip(d, d->saved);
        after_buf[1] = hk_dynamics_head_space_tip(d, sh->q);
    } else if (d->contact_samples > 0) {
        /* the nodes of the walk that the entry check takes (contact_entry.c): the
         * saved state's are cached from the step that ended there */
        before = hk_dynamics_entry_nodes(d, d->saved);
        after = hk_dynamics_entry_nodes(d, sh->q);
    } else {
        hk_dynamics_head_space_nodes(d, d->saved, before_buf);
        hk_dynamics_head_space_nodes(d, sh->q, after_buf);
    }
    double travel = 0.0;
    for (int i = 1; i <= n; i++) {
        const double step = hk_v3_dist(before[i], after[i]);
        if (step > travel && near_body(d, after[i], step)) travel = step;
    }
    return travel;
}

/* Largest turn of an element's frame over the step (the saved state against now). */
static double largest_turn(hk_StrandDynamics *d)
{
    const int dim = 3 * d->sh->n;
    for (int j = 0; j < dim; j++) d->delta[j] = d->sh->q[j] - d->saved[j];
    return turn_of(d->sh, d->delta, 1.0);
}

/* Whether the step from the saved state to now keeps within the error control's
 * limits (hk_strand_dynamics_advance): no frame turning more than max_turn, no node
 * near the body travelling more than max_travel and, for the linearly implicit Euler
 * step (which sees only the contacts of its start), no point entering the body unfelt
 * by more than max_entry. */
static int step_accepted(hk_StrandDynamics *d)
{
    return largest_turn(d) <= d->params.max_turn && largest_travel(d) <= d->params.max_travel &&
           (d->params.integrator != HK_INTEGRATOR_LINEAR_EULER ||
            hk_dynamics_largest_entry(d, d->saved, d->sh->q) <= d->params.max_entry);
}

typedef struct Interval {
    hk_HeadStateFn head;
    void *user;
    const hk_PointForce *forces;
    int force_count;
} Interval;

static void head_at(const Interval *iv, double t, hk_RigidState *out)
{
    *out = hk_rigid_identity();
    if (iv->head) iv->head(iv->user, t, out);
}

static int advance(hk_StrandDynamics *d, const Interval *iv, double t, double dt, int depth, int *substeps)
{
    hk_RigidState heads[3];
    head_at(iv, t, &heads[0]);
    head_at(iv, t + TR_G * dt, &heads[1]);
    head_at(iv, t + dt, &heads[2]);
    save_state(d);
    const int ok = integrate(d, heads, iv->forces, iv->force_count, dt);
    if (!ok) d->stats.failures++;
    if (ok && (depth >= d->params.max_depth || step_accepted(d))) {
        (*substeps)++;
        return 1;
    }
    restore_state(d);
    if (depth >= d->params.max_depth) return 0;
    /* Undo and take two half steps. */
    d->stats.splits++;
    return advance(d, iv, t, 0.5 * dt, depth + 1, substeps) &&
           advance(d, iv, t + 0.5 * dt, 0.5 * dt, depth + 1, substeps);
}

int hk_dynamics_euler_commit(hk_StrandDynamics *d, const double *v, double h, const hk_RigidState *head_end)
{
    HK_AVX_TWIN_RETURN(hk_dynamics_euler_commit, d, v, h, head_end);
    hk_SuperHelix *sh = d->sh;
    const int dim = 3 * sh->n;
    save_state(d);
    for (int j = 0; j < dim; j++) {
        d->v[j] = v[j];
        sh->q[j] += h * v[j];
    }
    d->acc_valid = 0;
    d->energy_valid = 0;
    d->prev_h = 0.0;
    if (!all_finite(sh->q, dim) || !all_finite(d->v, dim) || !step_accepted(d)) {
        restore_state(d);
        hk_strand_dynamics_place(d, head_end);
        return 0;
    }
    d->stats.steps++;
    hk_strand_dynamics_place(d, head_end);
    return 1;
}

hk_Status hk_strand_dynamics_advance(hk_StrandDynamics *d, hk_HeadStateFn head, void *user, double t, double dt,
                                     const hk_PointForce *forces, int force_count, int *substeps, hk_Error *err)
{
    HK_AVX_TWIN_RETURN(hk_strand_dynamics_advance, d, head, user, t, dt, forces, force_count, substeps, err);
    int count = 0;
    if (substeps) *substeps = 0;
    if (!(dt > 0.0) || !isfinite(dt) || !isfinite(t))
        return hk_error_set(err, HK_ERR_INVALID, "time step must be > 0, got %g", dt);
    const Interval iv = {head, user, forces, force_count};
    hk_RigidState start;
    head_at(&iv, t, &start);
    const hk_Status st = hk_dynamics_anchor_forces(d, &start, forces, force_count, err);
    if (st != HK_OK) return st;
    /* The state at the start, to give back untouched on failure. */
    const size_t bytes = (size_t)(3 * d->sh->n) * sizeof(double);
    memcpy(d->start, d->sh->q, bytes);
    memcpy(d->start + 3 * d->sh->n, d->v, bytes);
    const int ok = advance(d, &iv, t, dt, 0, &count);
    if (!ok) {
        memcpy(d->sh->q, d->start, bytes);
        memcpy(d->v, d->start + 3 * d->sh->n, bytes);
        d->acc_valid = 0;
    }
    if (substeps) *substeps = count;
    hk_RigidState end;
    head_at(&iv, t + dt, &end);
    hk_strand_dynamics_place(d, &end);
    if (!ok)
        return hk_error_set(err, HK_ERR_NUMERIC,
                            "dynamics step failed at t = %g s even split %d times (down to %g s): Newton's "
                            "iteration did not converge or the state is not finite; state left at t",
                            t, d->params.max_depth, dt / (double)(1L << d->params.max_depth));
    return HK_OK;
}
