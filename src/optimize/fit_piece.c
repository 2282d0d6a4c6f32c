/* One piece of the piecewise fitter (Piuze et al. 2011 §5.2, eq. 5): the objectives
 * (the normalised Fréchet coupling for Nelder-Mead, point distances and the join term for
 * Levenberg-Marquardt), the root frame's pose and refinement, the minimisers' starts, and
 * the bookkeeping of emitted pieces. */
#include <math.h>
#include <string.h>

#include "core/linalg.h"
#include "optimize/piecewise_internal.h"


/* The root pose turned by the rotation vector r (radians, in the frame's own axes: roll
 * about T, tilts about N and B): frame * exp([r]x), by Rodrigues' formula. */
static hk_CurveStart rotated(const hk_CurveStart *base, const double *r)
{
    hk_CurveStart s = *base;
    const hk_Vec3 v = hk_v3(r[0], r[1], r[2]);
    const double a = hk_v3_norm(v);
    if (!(a > 0.0)) return s;
    const hk_Mat3 k = hk_m3_skew(hk_v3_scale(v, 1.0 / a));
    const hk_Mat3 k2 = hk_m3_mul(&k, &k);
    hk_Mat3 e = hk_m3_identity();
    const hk_Mat3 t1 = hk_m3_scale(&k, sin(a)), t2 = hk_m3_scale(&k2, 1.0 - cos(a));
    e = hk_m3_add(&e, &t1);
    e = hk_m3_add(&e, &t2);
    s.frame = hk_m3_mul(&base->frame, &e);
    return s;
}

/* The pose turned (when rotating, see below) adjusted at the root by the model's rule. */
static hk_CurveStart ruled_pose(const Fit *F, hk_CurveStart s, const double *x, int at_root)
{
    if (at_root && F->opt->root_frame) F->opt->root_frame(F->user, x, &s);
    return s;
}

/* The pose the model starts from for parameters x: the base pose, turned by the root
 * rotation when it is free, and at the root adjusted by the model's own rule
 * (options.root_frame) from the estimated frame to its own. */
static hk_CurveStart start_pose(const Fit *F, const hk_CurveStart *base, const double *x, int rotating, int at_root)
{
    return ruled_pose(F, rotating ? rotated(base, x + F->np) : *base, x, at_root);
}

/* 1 when the points and the end pose are finite (a NaN end pose would poison every
 * later piece). */
static int trace_finite(const hk_Vec3 *pts, int m, const hk_CurveStart *end)
{
    for (int i = 0; i < m; i++)
        if (!hk_v3_isfinite(pts[i])) return 0;
    if (!hk_v3_isfinite(end->pos)) return 0;
    for (int i = 0; i < 3; i++)
        if (!hk_v3_isfinite(hk_m3_row(&end->frame, i))) return 0;
    return 1;
}

/* The remembered trace of these arguments (the fit's model and spacing), or NULL. The
 * key is compared bit for bit: a model is deterministic (hk_CurveModelFn), so a hit
 * gives the bytes a new call would. */
static const TraceEntry *cached_trace(const Fit *F, const double *params, const hk_CurveStart *start, int m)
{
    for (int k = 0; k < TRACE_CACHE; k++) {
        const TraceEntry *e = &F->ws->cache[k];
        if (e->model == F->model && e->m == m && !memcmp(e->params, params, (size_t)F->np * sizeof(double)) &&
            !memcmp(&e->start, start, sizeof *start))
            return e;
    }
    return NULL;
}

/* Remembers a trace in place of the oldest. */
static void remember_trace(Fit *F, const double *params, const hk_CurveStart *start, int m, const hk_Vec3 *out,
                           const hk_CurveStart *end, int status)
{
    hk_CurveFitWorkspace *ws = F->ws;
    const int k = ws->next;
    ws->next = (k + 1) % TRACE_CACHE;
    TraceEntry *e = &ws->cache[k];
    e->model = F->model;
    memcpy(e->params, params, (size_t)F->np * sizeof(double));
    e->start = *start;
    e->m = m;
    e->status = status;
    if (status) return; /* a failed trace's points and pose are never read */
    e->end = *end;
    memcpy(ws->cache_points + (size_t)k * (size_t)ws->capacity, out, (size_t)m * sizeof(hk_Vec3));
}

/* Traces m samples from `start`; 0 when the model succeeded with finite output. A trace
 * of the same arguments as one of the last TRACE_CACHE is copied instead (and not
 * counted as a model call). */
int hk_cf_trace(Fit *F, const double *params, const hk_CurveStart *start, int m, hk_Vec3 *out, hk_CurveStart *end)
{
    const TraceEntry *e = cached_trace(F, params, start, m);
    if (e && e->status) return e->status;
    if (e) {
        const size_t k = (size_t)(e - F->ws->cache);
        memcpy(out, F->ws->cache_points + k * (size_t)F->ws->capacity, (size_t)m * sizeof(hk_Vec3));
        *end = e->end;
        return e->status;
    }
    F->evaluations++;
    int status = F->model(F->user, params, start, F->h * (double)(m - 1), m, out, end) != 0;
    if (!status) status = !trace_finite(out, m, end);
    remember_trace(F, params, start, m, out, end, status);
    return status;
}

/* The weight of parameter j in the regularisation (options.penalty_weight, 0 = 1). */
double hk_cf_penalty_weight(const hk_CurveFitDef *o, int j)
{
    return o->penalty_weight[j] > 0.0 ? o->penalty_weight[j] : 1.0;
}

/* |W x| over the model's parameters, W the penalty weights: eq. (5)'s |k|. */
static double param_norm(const Fit *F, const double *x)
{
    double s = 0.0;
    for (int j = 0; j < F->np; j++) {
        const double v = hk_cf_penalty_weight(F->opt, j) * x[j];
        s += v * v;
    }
    return sqrt(s);
}

/* The normalised coupling of the fragment and ws->trace (a trace of it). */
static double traced_error(Fit *F)
{
    return hk_frechet_coupling_prefix(F->ws->target + F->i0, F->ws->trace, F->m, F->ws->row, NULL) / (double)F->m;
}

/* The normalised coupling of the fragment and the model at x (traced into ws->trace):
 * what the tolerance is checked against. Model failure: +inf. */
static double coupling_error(const double *x, Fit *F)
{
    hk_CurveStart end;
    const hk_CurveStart s = start_pose(F, &F->base, x, F->rotating, F->i0 == 0);
    if (hk_cf_trace(F, x, &s, F->m, F->ws->trace, &end) != 0) return INFINITY;
    return traced_error(F);
}

/* Eq. (5): normalised coupling + lambda |k| (the root rotation is not penalised).
 * Model failure: +inf, which Nelder-Mead never accepts. */
static double objective(void *user, const double *x)
{
    Fit *F = user;
    return coupling_error(x, F) + F->opt->lambda * param_norm(F, x);
}

void hk_cf_distance_residuals(const hk_Vec3 *model, const hk_Vec3 *target, int m, double *r)
{
    const double w = 1.0 / sqrt((double)m);
    for (int i = 0; i < m; i++) {
        r[3 * i] = w * (model[i].x - target[i].x);
        r[3 * i + 1] = w * (model[i].y - target[i].y);
        r[3 * i + 2] = w * (model[i].z - target[i].z);
    }
}

void hk_cf_penalty_residuals(const Fit *F, const double *x, int count, double *r)
{
    for (int j = 0; j < count; j++) r[j] = F->opt->lambda * hk_cf_penalty_weight(F->opt, j % F->np) * x[j];
}

/* 1 when the fragment being fitted ends before the target does: a later piece joins it
 * (least squares only; the paper's Nelder-Mead fits positions alone). */
static int has_join(const Fit *F)
{
    return F->opt->method == HK_CURVEFIT_LEAST_SQUARES && F->i0 + F->m < F->n && F->m >= 3;
}

/* The next piece starts along this one's end tangent (§3.4): a tangent off by delta at
 * the join moves the rest of the strand by about delta times its length, which no
 * position inside this fragment sees. The residual is the difference of the end tangent
 * and the target's there (for a smooth model the second-order one-sided difference on
 * the fragment's own points, not across a join where the bend may jump; for a forward
 * Euler model the next segment), weighted by length / sqrt(3), the rms
 * displacement of a straight strand of that length turned by delta about its start:
 * the length of the rest of the target, at most the fragment's own (a piece further on
 * can take up what this one cannot). Metres, like the distances. */
static hk_Vec3 join_residual(const Fit *F, const hk_CurveStart *end)
{
    const int b = F->i0 + F->m - 1;
    const hk_Vec3 *q = F->ws->target;
    /* A model traced by forward Euler (polyline spacing) leaves the join along its
     * next segment, exactly; a smooth one along the curve's tangent there. */
    const hk_Vec3 t =
        F->opt->arc_length
            ? hk_v3_normalize(hk_v3_add(hk_v3_sub(hk_v3_scale(q[b], 3.0), hk_v3_scale(q[b - 1], 4.0)), q[b - 2]))
            : hk_v3_normalize(hk_v3_sub(q[b + 1], q[b]));
    const double rest = F->h * (double)(F->n - 1 - b), own = F->h * (double)(F->m - 1);
    return hk_v3_scale(hk_v3_sub(hk_m3_col(&end->frame, 0), t), (rest < own ? rest : own) / sqrt(3.0));
}

/* The least-squares form of eq. (5): the distances between the fragment's samples and the
 * model's points at the same arc length, weighted 1/sqrt(m) so that the cost is half the
 * mean squared distance, and lambda k_j for the regularisation (the root rotation is not
 * penalised). The model is traced at the samples' spacing, so point i of both is at arc
 * length i h: on clean data the minimum is 0 at the true parameters, as the coupling's. */
static int residuals(void *user, const double *x, double *r)
{
    Fit *F = user;
    hk_CurveStart end;
    const hk_CurveStart s = start_pose(F, &F->base, x, F->rotating, F->i0 == 0);
    if (hk_cf_trace(F, x, &s, F->m, F->ws->trace, &end) != 0) return 1;
    hk_cf_distance_residuals(F->ws->trace, F->ws->target + F->i0, F->m, r);
    hk_cf_penalty_residuals(F, x, F->np, r + 3 * F->m);
    if (has_join(F)) {
        const hk_Vec3 d = join_residual(F, &end);
        r[3 * F->m + F->np] = d.x;
        r[3 * F->m + F->np + 1] = d.y;
        r[3 * F->m + F->np + 2] = d.z;
    }
    return 0;
}

static int residual_count(const Fit *F) { return 3 * F->m + F->np + (has_join(F) ? 3 : 0); }

/* Central-difference step of the start pose's parameters (radians and pure numbers:
 * root rotations, a helicoid's alpha); the pose is cheap to rebuild and smooth in them. */
#define POSE_STEP 1e-6

/* The angular velocity omega[j] of the start pose in the parameters x (the first nx):
 * d frame / d x_j = [omega_j]x frame, so omega_j = (1/2) sum_c f_c x df_c over the
 * frame's columns f_c. Central differences of start_pose (no trace). Zero when the pose
 * does not depend on the parameters (a piece away from the root, its frame unrefined). */
/* start_pose of xt, which differs from the x that `turned` was made for in entry j
 * alone: a model parameter (j < np) leaves the root rotation as it is, turned once. */
static hk_CurveStart moved_pose(const Fit *F, const hk_CurveStart *turned, const double *xt, int j)
{
    return j < F->np ? ruled_pose(F, *turned, xt, F->i0 == 0) : start_pose(F, &F->base, xt, F->rotating, F->i0 == 0);
}

static void pose_rates(const Fit *F, const double *x, const hk_CurveStart *s, int nx, hk_Vec3 *omega)
{
    const int at_root = F->i0 == 0 && F->opt->root_frame;
    for (int j = 0; j < nx; j++) omega[j] = hk_v3_zero();
    if (!at_root && !F->rotating) return;
    double xt[MAXP + ROT];
    memcpy(xt, x, (size_t)nx * sizeof(double));
    const hk_CurveStart turned = F->rotating ? rotated(&F->base, x + F->np) : F->base;
    for (int j = 0; j < nx; j++) {
        const double d = POSE_STEP * (fabs(x[j]) > 1.0 ? fabs(x[j]) : 1.0);
        xt[j] = x[j] + d;
        const hk_CurveStart a = moved_pose(F, &turned, xt, j);
        xt[j] = x[j] - d;
        const hk_CurveStart b = moved_pose(F, &turned, xt, j);
        xt[j] = x[j];
        hk_Vec3 w = hk_v3_zero();
        for (int c = 0; c < 3; c++) {
            const hk_Vec3 df = hk_v3_scale(hk_v3_sub(hk_m3_col(&a.frame, c), hk_m3_col(&b.frame, c)), 0.5 / d);
            w = hk_v3_add(w, hk_v3_cross(hk_m3_col(&s->frame, c), df));
        }
        omega[j] = hk_v3_scale(w, 0.5);
    }
}

/* The Jacobian of residuals() from one differentiated trace (options.model_derivative):
 * a point's derivative is the model's own (start held fixed) plus the start pose's turn,
 * omega_j x (p_i - p_0) (an equivariant model turns with its start pose); the end
 * tangent's likewise; the regularisation's is lambda w_j. */
static int residual_jacobian(void *user, const double *x, double *jac)
{
    Fit *F = user;
    const int m = F->m, np = F->np, nx = np + (F->rotating ? ROT : 0), rows = residual_count(F);
    const hk_CurveStart s = start_pose(F, &F->base, x, F->rotating, F->i0 == 0);
    hk_CurveStart end;
    hk_Vec3 dt[MAXP], omega[MAXP + ROT];
    hk_Vec3 *p = F->ws->trace, *dp = F->ws->dtrace;
    F->evaluations++;
    if (F->derivative(F->user, x, &s, F->h * (double)(m - 1), m, p, &end, dp, dt) != 0) return 1;
    pose_rates(F, x, &s, nx, omega);
    const double w = 1.0 / sqrt((double)m);
    const int join = has_join(F);
    const hk_Vec3 tangent = hk_m3_col(&end.frame, 0);
    double join_weight = 0.0;
    if (join) {
        const int b = F->i0 + m - 1;
        const double rest = F->h * (double)(F->n - 1 - b), own = F->h * (double)(m - 1);
        join_weight = (rest < own ? rest : own) / sqrt(3.0);
    }
    for (int j = 0; j < nx; j++) {
        double *col = jac + (size_t)j * (size_t)rows;
        /* A parameter the pose does not turn with (the curvatures, under a root_frame
         * rule of alpha alone) adds a turn of exactly zero: left out, which changes no
         * value (a zero's sign at most). */
        const int still = j < np && omega[j].x == 0.0 && omega[j].y == 0.0 && omega[j].z == 0.0;
        for (int i = 0; i < m; i++) {
            hk_Vec3 d;
            if (still) {
                d = dp[(size_t)j * (size_t)m + (size_t)i];
            } else {
                d = hk_v3_cross(omega[j], hk_v3_sub(p[i], s.pos));
                if (j < np) d = hk_v3_add(d, dp[(size_t)j * (size_t)m + (size_t)i]);
            }
            col[3 * i] = w * d.x;
            col[3 * i + 1] = w * d.y;
            col[3 * i + 2] = w * d.z;
        }
        for (int k = 0; k < np; k++) col[3 * m + k] = k == j ? F->opt->lambda * hk_cf_penalty_weight(F->opt, k) : 0.0;
        if (join) {
            hk_Vec3 d = hk_v3_cross(omega[j], tangent);
            if (j < np) d = hk_v3_add(d, dt[j]);
            col[3 * m + np] = join_weight * d.x;
            col[3 * m + np + 1] = join_weight * d.y;
            col[3 * m + np + 2] = join_weight * d.z;
        }
    }
    return 0;
}

/* The cost the method minimises, for choosing where it starts; leaves the trace of x in
 * ws->trace. */
static double start_cost(const double *x, void *user)
{
    Fit *F = user;
    if (F->opt->method == HK_CURVEFIT_NELDER_MEAD) return objective(F, x);
    return residuals(F, x, F->ws->lsq) != 0 ? INFINITY : 0.5 * hk_dot(F->ws->lsq, F->ws->lsq, residual_count(F));
}

/* Relative gain per step below which a fit's cost counts as levelled off (see below). */
#define LEVELLED_OFF 1e-2

/* Predicted relative gain below which a finishing run stops (see below). */
#define FINISH_GAIN 1e-3

/* The Levenberg-Marquardt settings of the fits for nx parameters: the fit's evaluation
 * budget (at least a Jacobian and a step), a step tolerance 1e-3 times the simplex's
 * (quadratic convergence gets there in a step or two), and a stop once the cost levels
 * off: two accepted steps in a row that each gain less than 1% of it. On a target the
 * model cannot follow exactly the run otherwise crawls along a sloppy valley (k_N and
 * k_B drifting together, Piuze et al. 2011 §4b's identifiability) for dozens of steps
 * that gain a few percent of the cost in all: on 114 Sintel strands a run took on average
 * 55 model calls with the old stop at 1e-6 of the cost, 20 with 1e-2, for the same mean
 * error (docs/helicoid-fitting.md §7). A clean target converges quadratically and never
 * meets this stop before it is fitted to a micron. */
hk_LeastSquaresDef hk_cf_least_squares_options(const Fit *F, int nx)
{
    hk_LeastSquaresDef lo = hk_default_least_squares_def();
    lo.max_evaluations = F->opt->max_evaluations > nx + 2 ? F->opt->max_evaluations : nx + 2;
    lo.x_tolerance = 1e-3 * F->opt->param_tolerance;
    lo.f_tolerance = LEVELLED_OFF;
    /* hk_cf_finish_pieces' runs start at the search tracer's minimum, microns from the
     * final model's: a step predicted to gain less than FINISH_GAIN of the cost ends
     * the run. On Curly's strands of 16-32 points 132 of 458 such runs gained less than
     * 0.1 % and spent 24 % of the finishing's evaluations, mostly on trials rejected at
     * rounding level (docs/helicoid-fitting.md §7). */
    if (F->finishing) lo.gain_tolerance = FINISH_GAIN;
    return lo;
}

/* Levenberg-Marquardt over the first nx entries of x. */
static hk_Status minimise_least_squares(Fit *F, int nx, double *x, const double *scale)
{
    const hk_LeastSquaresDef lo = hk_cf_least_squares_options(F, nx);
    hk_MinimizeResult r;
    return hk_least_squares_minimize_jac(nx, residual_count(F), x, scale, residuals,
                                         F->derivative ? residual_jacobian : NULL, F, &lo, F->ws->lsq, &r, NULL);
}

/* Nelder-Mead over the first nx entries of x, restarted from a converged simplex that
 * still misses the tolerance: Nelder-Mead can stall on a non-stationary point (McKinnon
 * 1998); a fresh simplex around it either confirms it or moves on. */
static hk_Status minimise(Fit *F, int nx, double *x, const double *scale)
{
    if (nx == 0) return HK_OK; /* nothing to choose: the model has one shape */
    if (F->opt->method == HK_CURVEFIT_LEAST_SQUARES) return minimise_least_squares(F, nx, x, scale);
    hk_NelderMeadDef nm;
    nm.max_evaluations = F->opt->max_evaluations;
    nm.x_tolerance = F->opt->param_tolerance;
    nm.f_tolerance = F->opt->cost_tolerance;
    hk_MinimizeResult r;
    hk_Status st = hk_nelder_mead_minimize(nx, x, scale, objective, F, &nm, &r, NULL);
    for (int k = 0; st == HK_OK && r.converged && k < F->opt->restarts &&
                    r.f - F->opt->lambda * param_norm(F, x) > F->opt->tolerance;
         k++) {
        const double before = r.f;
        st = hk_nelder_mead_minimize(nx, x, scale, objective, F, &nm, &r, NULL);
        if (st != HK_OK || !(before - r.f > F->opt->cost_tolerance)) break;
    }
    return st;
}

/* Copies into x the candidate (rows of cand, nx entries each) with the lowest cost. */
static void pick(Fit *F, double (*cand)[MAXP + ROT], int count, double *x)
{
    double fx = INFINITY;
    for (int c = 0; c < count; c++) {
        const double f = start_cost(cand[c], F);
        if (c == 0 || f < fx) {
            memcpy(x, cand[c], (MAXP + ROT) * sizeof(double));
            fx = f;
        }
    }
}

/* Levenberg-Marquardt runs per fit at most: the best starts in the order of their cost.
 * On 100 groomed strands one run left 8 above the tolerance (largest 0.76 mm), three 4
 * (0.31 mm); a planar lift-off fitted on 3 fixed pieces ends 3.9 mm off with two runs,
 * 0.29 mm with three (test_lift_off_layouts). The cut search's probes run one
 * (single_start, fit_cuts.c): clean two-piece strands cost 2.5 times more when their
 * probes that miss the tolerance ran all three.
 * The root frame's refinement (rare: once per strand at most) runs all its starts: the
 * fit so far, the hints and the three quarter-turn rolls of the seed, since the roll
 * that leads to the right minimum can be any of them. With exact Jacobians the lift-off
 * on 3 fixed pieces ended its first piece against the model's turn limit (1 rad per
 * sample), 0.96 mm off, when the third start was the last one run; 0.32 mm with all.
 * On 12 lift-offs (root bends of 135 to 220 / m, frames varied) the mean error on 2, 3
 * and 4 fixed pieces and split freely went from 2.73, 0.49, 0.26, 0.19 mm (differences,
 * three starts) to 0.61, 0.41, 0.24, 0.17 mm (derivatives, all starts). */
#define MAX_STARTS 3

/* Minimises over the first nx entries from the candidates into x; *error gets the
 * normalised coupling at x. Nelder-Mead (which explores by itself, and costs hundreds of
 * traces a run) starts from the best of them. Levenberg-Marquardt is local and cheap: it
 * runs from the candidates in the order of their cost until one ends within the
 * tolerance (at most MAX_STARTS, one for single_start), keeping the best end. On a
 * target far from any single piece (a tight lift-off bend with waviness on top) the
 * candidates lead to different minima, and the best start is not always the best end;
 * on an easy one the first run is the only one. */
static hk_Status descend(Fit *F, double (*cand)[MAXP + ROT], int count, int nx, double *x, double *error)
{
    if (F->opt->method != HK_CURVEFIT_LEAST_SQUARES || nx == 0) {
        pick(F, cand, count, x);
        const hk_Status st = minimise(F, nx, x, F->scale);
        *error = coupling_error(x, F);
        return st;
    }
    double cost[8];
    int order[8];
    for (int c = 0; c < count; c++) {
        cost[c] = start_cost(cand[c], F);
        int k = c;
        while (k > 0 && cost[order[k - 1]] > cost[c]) order[k] = order[k - 1], k--;
        order[k] = c;
    }
    double best = INFINITY;
    hk_Status result = HK_ERR_NUMERIC;
    const int max_runs = F->rotating ? count : (F->single_start ? 1 : MAX_STARTS);
    for (int r = 0, runs = 0; r < count && runs < max_runs; r++) {
        const int c = order[r];
        int seen = 0;
        for (int d = 0; d < r && !seen; d++) seen = !memcmp(cand[c], cand[order[d]], (size_t)nx * sizeof(double));
        if (seen || !isfinite(cost[c])) continue;
        double y[MAXP + ROT];
        memcpy(y, cand[c], sizeof y);
        runs++;
        if (minimise(F, nx, y, F->scale) != HK_OK) continue;
        const double f = start_cost(y, F);
        if (result == HK_OK && !(f < best)) continue; /* x, kept, was already above the tolerance */
        memcpy(x, y, sizeof y);
        best = f;
        result = HK_OK;
        *error = isfinite(f) ? traced_error(F) : INFINITY; /* start_cost left y's trace */
        if (*error <= F->opt->tolerance) break;
    }
    if (result == HK_OK) return HK_OK;
    pick(F, cand, count, x); /* every start failed: hand back the least bad */
    const hk_Status st = minimise(F, nx, x, F->scale);
    *error = coupling_error(x, F);
    return st;
}

static hk_Status make_piece(Fit *F, int i0, int i1, const hk_CurveStart *start, const double *x, Piece *piece);

/* hk_cf_finish_pieces' fit of samples i0..i1 from `start`: one run from the search's
 * parameters (found->params), at the root (refine) with the frame's rotation free as
 * well, from none: the search settled the frame for its own tracer, and the final
 * model's minimum may lie a few microradians away. */
static hk_Status finish_piece(Fit *F, int i0, int i1, const hk_CurveStart *start, int refine, const Piece *found,
                              Piece *piece)
{
    F->rotating = refine;
    const int nx = F->np + (refine ? ROT : 0);
    double x[MAXP + ROT] = {0};
    memcpy(x, found->params, (size_t)F->np * sizeof(double));
    hk_Status st = minimise(F, nx, x, F->scale);
    if (st != HK_OK)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the final model failed on samples %d..%d", i0, i1);
    return make_piece(F, i0, i1, start, x, piece);
}

/* Fits samples i0..i1 from `start`. Nelder-Mead starts at the best of the user's seed
 * and the hints (earlier fits of overlapping ranges, NULL when absent). With
 * refine_start and may_refine, a range at the root is first fitted in the estimated
 * frame, and only when that misses the tolerance is the frame's rotation freed: a good
 * frame (clean data) is kept exactly and costs nothing more. */
hk_Status hk_cf_fit_piece(Fit *F, int i0, int i1, const hk_CurveStart *start, int may_refine, const Piece *hint1,
                          const Piece *hint2, Piece *piece)
{
    const int refine = F->opt->refine_start && i0 == 0 && may_refine;
    const Piece *hints[2] = {hint1, hint2};
    F->i0 = i0;
    F->m = i1 - i0 + 1;
    F->base = *start;
    F->rotating = 0;
    /* a finishing run starts from the search's piece alone: no candidates */
    if (F->finishing) return finish_piece(F, i0, i1, start, refine, hint1, piece);
    double cand[6][MAXP + ROT];
    int count = 0;
    memset(cand, 0, sizeof cand);
    memcpy(cand[count++], F->seed, (size_t)F->np * sizeof(double));
    if (F->opt->fragment_seed && F->m >= 3)
        F->opt->fragment_seed(F->user, F->ws->target + i0, F->m, start, cand[count++]);
    for (int h = 0; h < 2; h++)
        if (hints[h]) memcpy(cand[count++], hints[h]->params, (size_t)F->np * sizeof(double));
    double x[MAXP + ROT], error;
    hk_Status st = descend(F, cand, count, F->np, x, &error);
    /* Least squares refines the frame already at a tenth of the tolerance: it costs a few
     * dozen traces, and the root frame's error, small at the root, is what every later
     * piece inherits through the joins. */
    const double refine_above =
        F->opt->method == HK_CURVEFIT_LEAST_SQUARES ? 0.1 * F->opt->tolerance : F->opt->tolerance;
    if (st == HK_OK && refine && error > refine_above) {
        /* Free the frame: candidates are the fit so far, the hints with their own
         * rotations, and the seed rolled by quarter turns about the tangent, because the
         * normal estimated from noisy first points can be off by any roll (the first
         * bend, h^2 kappa, is comparable to the noise) and the coupling has local minima
         * in the roll. */
        F->base = *start;
        F->rotating = 1;
        memset(cand, 0, sizeof cand);
        count = 0;
        memcpy(cand[count++], x, (size_t)F->np * sizeof(double));
        for (int h = 0; h < 2; h++) {
            if (!hints[h]) continue;
            memcpy(cand[count], hints[h]->params, (size_t)F->np * sizeof(double));
            memcpy(cand[count++] + F->np, hints[h]->rot, sizeof hints[h]->rot);
        }
        for (int q = 1; q < 4; q++) {
            memcpy(cand[count], F->seed, (size_t)F->np * sizeof(double));
            cand[count++][F->np] = q * (HK_PI / 2.0);
        }
        st = descend(F, cand, count, F->np + ROT, x, &error);
    }
    if (st != HK_OK)
        return hk_error_set(F->err, HK_ERR_NUMERIC,
                            "curve fit: the model failed (or gave non-finite points) for every parameter "
                            "vector tried on samples %d..%d",
                            i0, i1);
    return make_piece(F, i0, i1, start, x, piece);
}

/* The piece of parameters x (with the root rotation after them when F->rotating) on
 * samples i0..i1 from `start`: its poses, trace and errors. */
static hk_Status make_piece(Fit *F, int i0, int i1, const hk_CurveStart *start, const double *x, Piece *piece)
{
    memset(piece, 0, sizeof *piece);
    memcpy(piece->params, x, (size_t)F->np * sizeof(double));
    if (F->rotating) memcpy(piece->rot, x + F->np, sizeof piece->rot);
    piece->base = F->rotating ? rotated(start, piece->rot) : *start;
    piece->start = start_pose(F, start, x, F->rotating, i0 == 0);
    if (hk_cf_trace(F, piece->params, &piece->start, F->m, F->ws->best, &piece->end) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed at its own best fit (samples %d..%d)",
                            i0, i1);
    double c, d;
    hk_frechet_both(F->ws->target + i0, F->m, F->ws->best, F->m, F->ws->row, &c, &d);
    piece->error = c / (double)F->m;
    piece->frechet = d;
    piece->join_error = has_join(F) ? hk_v3_norm(join_residual(F, &piece->end)) : 0.0;
    return HK_OK;
}

/* A piece is acceptable when it follows its fragment within the tolerance and, with a
 * successor, leaves it a start tangent that turns the rest by no more. */
int hk_cf_acceptable(const Fit *F, const Piece *p)
{
    return p->error <= F->opt->tolerance && p->join_error <= F->opt->tolerance;
}

void hk_cf_emit(Fit *F, const Piece *p, int i0, int i1)
{
    hk_CurveFit *o = F->out;
    const int k = o->piece_count++;
    memcpy(o->params[k], p->params, sizeof o->params[k]);
    o->length[k] = F->h * (double)(i1 - i0);
    o->first_sample[k] = i0;
    o->piece_error[k] = p->error;
    o->piece_frechet[k] = p->frechet;
    F->starts[k] = p->start;
    if (i0 == 0) F->root_base = p->base;
}

/* Traces pieces [from, to) of `fit` chained from `start` into out (indexed by sample; the
 * last piece ends at sample i_end). 0 on success. */
int hk_cf_trace_chain(hk_CurveModelFn model, void *user, const hk_CurveFit *fit, int from, int to, int i_end, double h,
                      const hk_CurveStart *start, hk_Vec3 *out, long *evaluations)
{
    hk_CurveStart pose = *start, end;
    for (int k = from; k < to; k++) {
        const int a = fit->first_sample[k], b = k + 1 < to ? fit->first_sample[k + 1] : i_end;
        const int m = b - a + 1;
        (*evaluations)++;
        if (model(user, fit->params[k], &pose, h * (double)(m - 1), m, out + a, &end) != 0) return 1;
        if (!trace_finite(out + a, m, &end)) return 1;
        pose = end;
    }
    return 0;
}
