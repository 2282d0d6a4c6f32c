/* Fitting a chain of curve-model pieces to a polyline (helicoid paper 003 §5.2-5.3).
 *
 * One piece, eq. (5): k0 = argmin_k C(h, H(k, Q, p0, L)) + lambda |k|, with C the
 * discrete Fréchet coupling (here normalised by the sample count so that it and lambda
 * are in metres), minimised by Nelder-Mead from the best of a few seeds. The target is
 * first resampled uniformly by arc length, so that every millimetre of hair weighs the
 * same in the coupling whatever the capture's vertex spacing, and the model is traced
 * with the same spacing (count and length of the fragment).
 *
 * Root frame: Q is estimated from the first points (curve_polyline.c). With
 * refine_start, a fit at the root that misses the tolerance in that frame is redone with
 * three more parameters, a rotation of Q: on noisy captures the first bend is buried in
 * the noise and the estimated normal can be off by any angle.
 *
 * Pieces, §5.3 (recursive): fit the whole range; accept it if its coupling is within
 * the tolerance; otherwise
 *  - upper limit (Fréchet threshold): grow a fragment from the start of the range while
 *    the coupling of the fragment against the same stretch of the fit stays within
 *    split_threshold (60% in the paper) of the whole fit's coupling; at 100% the whole
 *    range is one fragment, as the paper says. Fit that fragment; while its fit is
 *    still within tolerance, grow it by half and fit again, so that the limit lies past
 *    the change the split is looking for;
 *  - backtracking (curvature): compare the bend of the target and of the fragment's fit
 *    vertex by vertex (turning and twisting angles, which do not depend on where the
 *    fit has drifted to) and cut where the target stops agreeing with the fit: the
 *    minimum of the cumulative sum of (difference - its mean) over the fragment (a CUSUM
 *    change point), no closer to the start than the minimal fragment;
 *  - fit the first part (recursively: it may split again), start the second part at the
 *    end pose of the first (frames continuous across the join, §3.4) and recurse;
 *  - if the chained pieces fit the range worse than the unsplit fit, undo the split.
 * See docs/helicoid-fitting.md for why these choices. */
#include <math.h>
#include <string.h>

#include "hairkit/linalg.h"
#include "helicoid/curvefit_internal.h"

#define MAXP HK_CURVEFIT_MAX_PARAMS
#define ROT 3 /* parameters of the root frame's rotation when it is refined */
/* Least-squares residuals of a fragment of m samples: 3 per sample and one per model
 * parameter (the regularisation). */
#define RESIDUALS(m) (3 * (size_t)(m) + MAXP + 3)
/* The polish of a whole chain (least squares): all pieces' parameters at once, up to the
 * minimiser's limit; 3 residuals per sample and one per parameter. */
#define POLISH_PARAMS HK_LEAST_SQUARES_MAX_PARAMS
#define CHAIN_RESIDUALS(n) (3 * (size_t)(n) + POLISH_PARAMS)

struct hk_CurveFitWorkspace {
    int capacity;
    hk_Vec3 *target; /* the resampled target */
    hk_Vec3 *trace;  /* the objective's model output */
    hk_Vec3 *best;   /* a fit's trace kept for the split heuristics */
    hk_Vec3 *chain;  /* chained pieces, for the error of a split and of the result */
    double *row;     /* 2 * capacity: dynamic programming rows */
    double *prefix;  /* coupling of growing fragments */
    double *diff;    /* bend differences */
    double *lsq;     /* Levenberg-Marquardt work memory */
};

hk_CurveFitOptions hk_default_curve_fit_options(void)
{
    hk_CurveFitOptions o;
    memset(&o, 0, sizeof o);
    o.method = HK_CURVEFIT_LEAST_SQUARES;
    o.lambda = 1e-7;
    o.tolerance = 2e-4;
    o.split_threshold = 0.6;
    o.min_fragment_length = 0.005;
    o.max_pieces = 16;
    o.max_evaluations = 1000;
    o.samples = 0;
    o.restarts = 1;
    o.param_tolerance = 1e-5;
    o.cost_tolerance = 1e-8;
    o.use_start = 0;
    o.refine_start = 1;
    o.start.pos = hk_v3_zero();
    o.start.frame = hk_m3_identity();
    return o;
}

hk_CurveFitWorkspace *hk_curve_fit_workspace_create(int max_samples, hk_Error *err)
{
    if (max_samples < 2 || max_samples > HK_CURVEFIT_MAX_SAMPLES) {
        hk_error_set(err, HK_ERR_INVALID, "curve fit: workspace for %d samples, expected 2..%d", max_samples,
                     HK_CURVEFIT_MAX_SAMPLES);
        return NULL;
    }
    hk_CurveFitWorkspace *ws = hk_calloc_array(1, sizeof *ws, err);
    if (!ws) return NULL;
    const size_t n = (size_t)max_samples;
    ws->capacity = max_samples;
    ws->target = hk_alloc_array(n, sizeof(hk_Vec3), err);
    ws->trace = ws->target ? hk_alloc_array(n, sizeof(hk_Vec3), err) : NULL;
    ws->best = ws->trace ? hk_alloc_array(n, sizeof(hk_Vec3), err) : NULL;
    ws->chain = ws->best ? hk_alloc_array(n, sizeof(hk_Vec3), err) : NULL;
    ws->row = ws->chain ? hk_alloc_array(2 * n, sizeof(double), err) : NULL;
    ws->prefix = ws->row ? hk_alloc_array(n, sizeof(double), err) : NULL;
    ws->diff = ws->prefix ? hk_alloc_array(n, sizeof(double), err) : NULL;
    ws->lsq = ws->diff ? hk_alloc_array(HK_LEAST_SQUARES_WORK(POLISH_PARAMS, CHAIN_RESIDUALS(n)), sizeof(double), err)
                       : NULL;
    if (!ws->lsq) {
        hk_curve_fit_workspace_destroy(ws);
        return NULL;
    }
    return ws;
}

void hk_curve_fit_workspace_destroy(hk_CurveFitWorkspace *ws)
{
    if (!ws) return;
    hk_free(ws->target);
    hk_free(ws->trace);
    hk_free(ws->best);
    hk_free(ws->chain);
    hk_free(ws->row);
    hk_free(ws->prefix);
    hk_free(ws->diff);
    hk_free(ws->lsq);
    hk_free(ws);
}

/* ---- one fit ------------------------------------------------------------------------ */

#define M_PI_VALUE 3.14159265358979323846

typedef struct Piece {
    double params[MAXP];
    double rot[ROT];     /* rotation of the root frame (refined first piece), else 0 */
    hk_CurveStart start; /* the pose it starts from */
    hk_CurveStart base;  /* at the root: that pose before the model's root_frame rule */
    hk_CurveStart end;   /* and ends at */
    double error;        /* normalised coupling against its fragment (m) */
    double frechet;      /* Fréchet distance against its fragment (m) */
    double join_error;   /* least squares, a piece with a successor: how far its end
                            tangent's error turns the rest (m), see residuals() */
    int params_valid_for_cut; /* a cut heuristic's fit: 1 when it is the first part's own */
} Piece;

typedef struct Fit {
    hk_CurveFitWorkspace *ws;
    hk_CurveModelFn model;
    void *user;
    int np;
    const double *seed;
    double scale[MAXP + ROT];
    const hk_CurveFitOptions *opt;
    int n;          /* samples */
    double h;       /* their spacing */
    int min_points; /* samples of the shortest fragment a split may create */
    long evaluations;
    hk_CurveFit *out;
    hk_CurveStart starts[HK_CURVEFIT_MAX_PIECES]; /* start pose of each emitted piece */
    hk_CurveStart root_base;                      /* the root piece's pose before root_frame */
    hk_Error *err;
    /* what the objective compares: samples i0 .. i0 + m - 1, traced from `base`, turned
     * by the last ROT parameters when `rotating` */
    int i0, m, rotating;
    hk_CurveStart base;
} Fit;

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

/* The pose the model starts from for parameters x: the base pose, turned by the root
 * rotation when it is free, and at the root adjusted by the model's own rule
 * (options.root_frame) from the estimated frame to its own. */
static hk_CurveStart start_pose(const Fit *F, const hk_CurveStart *base, const double *x, int rotating, int at_root)
{
    hk_CurveStart s = rotating ? rotated(base, x + F->np) : *base;
    if (at_root && F->opt->root_frame) F->opt->root_frame(F->user, x, &s);
    return s;
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

/* Traces m samples from `start`; 0 when the model succeeded with finite output. */
static int trace(Fit *F, const double *params, const hk_CurveStart *start, int m, hk_Vec3 *out,
                 hk_CurveStart *end)
{
    F->evaluations++;
    if (F->model(F->user, params, start, F->h * (double)(m - 1), m, out, end) != 0) return 1;
    return !trace_finite(out, m, end);
}

/* The weight of parameter j in the regularisation (options.penalty_weight, 0 = 1). */
static double penalty_weight(const hk_CurveFitOptions *o, int j)
{
    return o->penalty_weight[j] > 0.0 ? o->penalty_weight[j] : 1.0;
}

/* |W x| over the model's parameters, W the penalty weights: eq. (5)'s |k|. */
static double param_norm(const Fit *F, const double *x)
{
    double s = 0.0;
    for (int j = 0; j < F->np; j++) {
        const double v = penalty_weight(F->opt, j) * x[j];
        s += v * v;
    }
    return sqrt(s);
}

/* Eq. (5): normalised coupling + lambda |k| (the root rotation is not penalised).
 * Model failure: +inf, which Nelder-Mead never accepts. */
static double objective(const double *x, void *user)
{
    Fit *F = user;
    hk_CurveStart end;
    const hk_CurveStart s = start_pose(F, &F->base, x, F->rotating, F->i0 == 0);
    if (trace(F, x, &s, F->m, F->ws->trace, &end) != 0) return INFINITY;
    const double c = hk_frechet_coupling_prefix(F->ws->target + F->i0, F->ws->trace, F->m, F->ws->row, NULL);
    return c / (double)F->m + F->opt->lambda * param_norm(F, x);
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
    const hk_Vec3 t = F->opt->arc_length ? hk_v3_normalize(hk_v3_add(
                                               hk_v3_sub(hk_v3_scale(q[b], 3.0), hk_v3_scale(q[b - 1], 4.0)), q[b - 2]))
                                         : hk_v3_normalize(hk_v3_sub(q[b + 1], q[b]));
    const double rest = F->h * (double)(F->n - 1 - b), own = F->h * (double)(F->m - 1);
    return hk_v3_scale(hk_v3_sub(hk_m3_col(&end->frame, 0), t), (rest < own ? rest : own) / sqrt(3.0));
}

/* The least-squares form of eq. (5): the distances between the fragment's samples and the
 * model's points at the same arc length, weighted 1/sqrt(m) so that the cost is half the
 * mean squared distance, and lambda k_j for the regularisation (the root rotation is not
 * penalised). The model is traced at the samples' spacing, so point i of both is at arc
 * length i h: on clean data the minimum is 0 at the true parameters, as the coupling's. */
static int residuals(const double *x, double *r, void *user)
{
    Fit *F = user;
    hk_CurveStart end;
    const hk_CurveStart s = start_pose(F, &F->base, x, F->rotating, F->i0 == 0);
    if (trace(F, x, &s, F->m, F->ws->trace, &end) != 0) return 1;
    const double w = 1.0 / sqrt((double)F->m);
    const hk_Vec3 *target = F->ws->target + F->i0, *model = F->ws->trace;
    for (int i = 0; i < F->m; i++) {
        r[3 * i] = w * (model[i].x - target[i].x);
        r[3 * i + 1] = w * (model[i].y - target[i].y);
        r[3 * i + 2] = w * (model[i].z - target[i].z);
    }
    for (int j = 0; j < F->np; j++) r[3 * F->m + j] = F->opt->lambda * penalty_weight(F->opt, j) * x[j];
    if (has_join(F)) {
        const hk_Vec3 d = join_residual(F, &end);
        r[3 * F->m + F->np] = d.x;
        r[3 * F->m + F->np + 1] = d.y;
        r[3 * F->m + F->np + 2] = d.z;
    }
    return 0;
}

static int residual_count(const Fit *F) { return 3 * F->m + F->np + (has_join(F) ? 3 : 0); }

/* The cost the method minimises, for choosing where it starts. */
static double start_cost(const double *x, void *user)
{
    Fit *F = user;
    if (F->opt->method == HK_CURVEFIT_NELDER_MEAD) return objective(x, F);
    return residuals(x, F->ws->lsq, F) != 0 ? INFINITY : 0.5 * hk_dot(F->ws->lsq, F->ws->lsq, residual_count(F));
}

/* The Levenberg-Marquardt settings of the fits for nx parameters: the fit's evaluation
 * budget (at least a Jacobian and a step), a step tolerance 1e-3 times the simplex's
 * (quadratic convergence gets there in a step or two), and a stop once the cost levels
 * off to 1e-6 of itself (on a target the model cannot follow exactly, sloppy directions
 * would otherwise be crawled along for hundreds of evaluations for no visible gain). */
static hk_LeastSquaresOptions least_squares_options(const Fit *F, int nx)
{
    hk_LeastSquaresOptions lo = hk_default_least_squares_options();
    lo.max_evaluations = F->opt->max_evaluations > nx + 2 ? F->opt->max_evaluations : nx + 2;
    lo.x_tolerance = 1e-3 * F->opt->param_tolerance;
    lo.f_tolerance = 1e-6;
    return lo;
}

/* Levenberg-Marquardt over the first nx entries of x. */
static hk_Status minimise_least_squares(Fit *F, int nx, double *x, const double *scale)
{
    const hk_LeastSquaresOptions lo = least_squares_options(F, nx);
    hk_LeastSquaresResult r;
    return hk_least_squares_minimize(nx, residual_count(F), x, scale, residuals, F, &lo, F->ws->lsq, &r, NULL);
}

/* Nelder-Mead over the first nx entries of x, restarted from a converged simplex that
 * still misses the tolerance: Nelder-Mead can stall on a non-stationary point (McKinnon
 * 1998); a fresh simplex around it either confirms it or moves on. */
static hk_Status minimise(Fit *F, int nx, double *x, const double *scale)
{
    if (nx == 0) return HK_OK; /* nothing to choose: the model has one shape */
    if (F->opt->method == HK_CURVEFIT_LEAST_SQUARES) return minimise_least_squares(F, nx, x, scale);
    hk_NelderMeadOptions nm;
    nm.max_evaluations = F->opt->max_evaluations;
    nm.x_tolerance = F->opt->param_tolerance;
    nm.f_tolerance = F->opt->cost_tolerance;
    hk_NelderMeadResult r;
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

/* Minimises over the first nx entries from the candidates into x. Nelder-Mead (which
 * explores by itself, and costs hundreds of traces a run) starts from the best of them.
 * Levenberg-Marquardt is local and cheap: it runs from the candidates in the order of
 * their cost until one ends within the tolerance (at most MAX_STARTS), keeping the best end. On a target far
 * from any single piece (a tight lift-off bend with waviness on top) the candidates lead
 * to different minima, and the best start is not always the best end; on an easy one the
 * first run is the only one. */
/* Levenberg-Marquardt runs per fit at most: the best starts in the order of their cost.
 * On 100 groomed strands one run left 8 above the tolerance (largest 0.76 mm), three 4
 * (0.31 mm); a planar lift-off fitted on 3 fixed pieces ends 3.9 mm off with two runs,
 * 0.29 mm with three (test_lift_off_layouts). Clean two-piece strands cost 2.5 times
 * more with three than with one (bisection probes that miss the tolerance run all). */
#define MAX_STARTS 3
static hk_Status descend(Fit *F, double (*cand)[MAXP + ROT], int count, int nx, double *x)
{
    if (F->opt->method != HK_CURVEFIT_LEAST_SQUARES || nx == 0) {
        pick(F, cand, count, x);
        return minimise(F, nx, x, F->scale);
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
    for (int r = 0, runs = 0; r < count && runs < MAX_STARTS; r++) {
        const int c = order[r];
        int seen = 0;
        for (int d = 0; d < r && !seen; d++) seen = !memcmp(cand[c], cand[order[d]], (size_t)nx * sizeof(double));
        if (seen || !isfinite(cost[c])) continue;
        double y[MAXP + ROT];
        memcpy(y, cand[c], sizeof y);
        runs++;
        if (minimise(F, nx, y, F->scale) != HK_OK) continue;
        const double f = start_cost(y, F);
        if (result != HK_OK || f < best) {
            memcpy(x, y, sizeof y);
            best = f;
            result = HK_OK;
        }
        if (objective(x, F) - F->opt->lambda * param_norm(F, x) <= F->opt->tolerance) break;
    }
    if (result != HK_OK) pick(F, cand, count, x); /* every start failed: hand back the least bad */
    return result == HK_OK ? HK_OK : minimise(F, nx, x, F->scale);
}

/* Fits samples i0..i1 from `start`. Nelder-Mead starts at the best of the user's seed
 * and the hints (earlier fits of overlapping ranges, NULL when absent). With
 * refine_start and may_refine, a range at the root is first fitted in the estimated
 * frame, and only when that misses the tolerance is the frame's rotation freed: a good
 * frame (clean data) is kept exactly and costs nothing more. */
static hk_Status fit_piece(Fit *F, int i0, int i1, const hk_CurveStart *start, int may_refine, const Piece *hint1,
                           const Piece *hint2, Piece *piece)
{
    const int refine = F->opt->refine_start && i0 == 0 && may_refine;
    const Piece *hints[2] = {hint1, hint2};
    F->i0 = i0;
    F->m = i1 - i0 + 1;
    F->base = *start;
    F->rotating = 0;
    double cand[6][MAXP + ROT];
    int count = 0;
    memset(cand, 0, sizeof cand);
    memcpy(cand[count++], F->seed, (size_t)F->np * sizeof(double));
    if (F->opt->fragment_seed && F->m >= 3) F->opt->fragment_seed(F->user, F->ws->target + i0, F->m, start, cand[count++]);
    for (int h = 0; h < 2; h++)
        if (hints[h]) memcpy(cand[count++], hints[h]->params, (size_t)F->np * sizeof(double));
    double x[MAXP + ROT];
    hk_Status st = descend(F, cand, count, F->np, x);
    /* Least squares refines the frame already at a tenth of the tolerance: it costs a few
     * dozen traces, and the root frame's error, small at the root, is what every later
     * piece inherits through the joins. */
    const double refine_above = F->opt->method == HK_CURVEFIT_LEAST_SQUARES ? 0.1 * F->opt->tolerance : F->opt->tolerance;
    if (st == HK_OK && refine && objective(x, F) - F->opt->lambda * param_norm(F, x) > refine_above) {
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
            cand[count++][F->np] = q * (M_PI_VALUE / 2.0);
        }
        st = descend(F, cand, count, F->np + ROT, x);
    }
    if (st != HK_OK)
        return hk_error_set(F->err, HK_ERR_NUMERIC,
                            "curve fit: the model failed (or gave non-finite points) for every parameter "
                            "vector tried on samples %d..%d",
                            i0, i1);
    memset(piece, 0, sizeof *piece);
    memcpy(piece->params, x, (size_t)F->np * sizeof(double));
    if (F->rotating) memcpy(piece->rot, x + F->np, sizeof piece->rot);
    piece->base = F->rotating ? rotated(start, piece->rot) : *start;
    piece->start = start_pose(F, start, x, F->rotating, i0 == 0);
    if (trace(F, piece->params, &piece->start, F->m, F->ws->best, &piece->end) != 0)
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
static int acceptable(const Fit *F, const Piece *p)
{
    return p->error <= F->opt->tolerance && p->join_error <= F->opt->tolerance;
}

static void emit(Fit *F, const Piece *p, int i0, int i1)
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
static int trace_chain(hk_CurveModelFn model, void *user, const hk_CurveFit *fit, int from, int to, int i_end,
                       double h, const hk_CurveStart *start, hk_Vec3 *out, long *evaluations)
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

/* ---- splitting (§5.3) --------------------------------------------------------------- */

/* Upper limit of the first fragment: the last sample k such that the fragment i0..k
 * couples with the same stretch of the fit (in ws->best) within `threshold` of the
 * whole range's coupling. */
static int frechet_upper_limit(Fit *F, int i0, int i1)
{
    const int m = i1 - i0 + 1;
    const double total = hk_frechet_coupling_prefix(F->ws->target + i0, F->ws->best, m, F->ws->row, F->ws->prefix);
    const double limit = F->opt->split_threshold * total;
    for (int k = 1; k < m; k++)
        if (F->ws->prefix[k] > limit) return i0 + k - 1;
    return i1;
}

/* Backtracking from the upper limit k_max: the cut k in [k_lo, k_max] where the target's
 * bend stops agreeing with the fit of fragment i0..k_max (see the top comment). Vertex j's
 * bend (its turning angle and the twist that follows) belongs to the piece that owns the
 * step from segment j-1 to segment j, so a cut at k keeps vertices up to k. The fit is
 * traced two samples past k_max (k_max <= i1 - 2) so that those bends exist. */
static hk_Status curvature_cut(Fit *F, int i0, int k_lo, int k_max, const Piece *frag, int *cut)
{
    const int m = k_max - i0 + 3;
    hk_CurveStart end;
    /* A model may refuse to go on past its fragment (a helicoid nearing its singular
     * axis): then the last two vertices' bends are not compared (they count as the mean
     * difference, neutral in the cumulative sum below). */
    int last = k_max;
    if (trace(F, frag->params, &frag->start, m, F->ws->best, &end) != 0) {
        last = k_max - 2;
        if (last <= i0 || trace(F, frag->params, &frag->start, m - 2, F->ws->best, &end) != 0)
            return hk_error_set(F->err, HK_ERR_NUMERIC,
                                "curve fit: the model failed at its own best fit (samples %d..%d)", i0, k_max);
    }
    double *d = F->ws->diff;
    double mean = 0.0;
    for (int j = i0 + 1; j <= last; j++) {
        double turn_t, twist_t, turn_f, twist_f;
        hk_polyline_bend(F->ws->target, j, &turn_t, &twist_t);
        hk_polyline_bend(F->ws->best, j - i0, &turn_f, &twist_f);
        d[j] = fabs(turn_t - turn_f) + fabs(twist_t - twist_f);
        mean += d[j];
    }
    mean /= (double)(last - i0);
    for (int j = last + 1; j <= k_max; j++) d[j] = mean;
    double s = 0.0, best_s = INFINITY;
    int best_k = k_max;
    for (int k = i0 + 1; k <= k_max; k++) {
        s += d[k] - mean;
        /* <=: among equal sums the longest fragment, the first met when backtracking
         * from the upper limit as the paper does. */
        if (k >= k_lo && s <= best_s) {
            best_s = s;
            best_k = k;
        }
    }
    *cut = best_k;
    return HK_OK;
}

/* The paper's cut (§5.3, see the top comment): an upper limit from the Fréchet threshold,
 * grown while the fragment still fits, then backtracking by bends. frag gets a fit
 * usable as the first part's hint, marked reusable when it fits exactly i0..cut. */
static hk_Status paper_cut(Fit *F, int i0, int i1, int k_lo, int k_hi, const hk_CurveStart *start, const Piece *whole,
                           Piece *frag, int *cut)
{
    hk_Status st;
    /* The whole fit's trace for the Fréchet threshold (a `known` fit left none behind). */
    hk_CurveStart tmp;
    if (trace(F, whole->params, &whole->start, i1 - i0 + 1, F->ws->best, &tmp) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed at its own best fit (samples %d..%d)",
                            i0, i1);
    int k_max = frechet_upper_limit(F, i0, i1);
    k_max = k_max < k_lo ? k_lo : (k_max > k_hi ? k_hi : k_max);
    *frag = *whole;
    frag->params_valid_for_cut = 0;
    *cut = k_lo;
    if (k_max <= k_lo) return HK_OK;
    /* Fits that only locate the cut stay in the estimated root frame: no refinement
     * for each, and on clean data that frame is the exact one. */
    if ((st = fit_piece(F, i0, k_max, start, 0, whole, NULL, frag)) != HK_OK) return st;
    /* The threshold is only a first guess: while the fragment still fits within the
     * tolerance, grow it by half, so that the backtracking starts past the change. */
    while (frag->error <= F->opt->tolerance && k_max < k_hi) {
        const int step = (k_max - i0) / 2 > F->min_points - 1 ? (k_max - i0) / 2 : F->min_points - 1;
        const int next = k_max + step < k_hi ? k_max + step : k_hi;
        Piece longer;
        if ((st = fit_piece(F, i0, next, start, 0, frag, NULL, &longer)) != HK_OK) return st;
        k_max = next;
        *frag = longer;
    }
    if ((st = curvature_cut(F, i0, k_lo, k_max, frag, cut)) != HK_OK) return st;
    /* The fragment's fit is the first part's when the cut is at its end (at the root
     * with refine_start, the first part gets its own chance to refine the frame). */
    frag->params_valid_for_cut = *cut == k_max && (i0 > 0 || !F->opt->refine_start);
    return HK_OK;
}

/* Samples the longest acceptable prefix may overshoot a join by (its last points lean
 * a little off the piece it belongs to, within the tolerance) and the cuts tried there. */
#define SETTLE_BACK 3

/* A prefix that runs a sample or two past a join still fits within the tolerance, but
 * it ends in a pose the next piece cannot start from. Try the cut at the longest
 * acceptable prefix and up to SETTLE_BACK samples before it: each with its first part
 * fitted and a look-ahead piece (as long as half that part, at least a minimal fragment)
 * fitted from its end pose; keep the cut whose two fits have the least mean error (the
 * later cut on ties). frag holds the first part's fit of *cut on entry and on return. */
static hk_Status settle_cut(Fit *F, int i0, int k_lo, int i1, Piece *frag, int *cut)
{
    const int good = *cut;
    double best = INFINITY;
    Piece first = *frag, ahead;
    for (int c = good; c >= k_lo && c >= good - SETTLE_BACK; c--) {
        hk_Status st;
        if (c != good && (st = fit_piece(F, i0, c, &frag->base, 0, frag, NULL, &first)) != HK_OK) return st;
        if (!acceptable(F, &first)) continue;
        const int half = (c - i0) / 2 > F->min_points - 1 ? (c - i0) / 2 : F->min_points - 1;
        const int end = c + half < i1 ? c + half : i1;
        if (end <= c + 1) return HK_OK; /* no room to look ahead: keep the longest */
        if ((st = fit_piece(F, c, end, &first.end, 0, NULL, NULL, &ahead)) != HK_OK) return st;
        const double mean = (first.error * (c - i0 + 1) + ahead.error * (end - c + 1)) / (double)(end - i0 + 2);
        if (mean < best) {
            best = mean;
            *cut = c;
            if (c != good) *frag = first;
        }
    }
    frag->params_valid_for_cut = 1;
    return HK_OK;
}

/* Our cut for the least-squares fitter: the longest first fragment i0..k (k_lo <= k <=
 * k_hi) whose own fit is within the tolerance, by bisection (a longer fragment can only
 * fit worse, give or take the normalisation), each fit started from the last one that
 * fitted. Cutting greedily at the longest acceptable prefix gives the fewest pieces when
 * acceptability is monotone, and on a target made of pieces it lands on a join (the
 * prefix stops fitting exactly where the next piece begins). When even the shortest
 * fragment misses the tolerance the cut is there. frag gets the fit of i0..cut. */
static hk_Status longest_prefix_cut(Fit *F, int i0, int i1, int k_lo, int k_hi, const hk_CurveStart *start,
                                    const Piece *whole, Piece *frag, int *cut)
{
    hk_Status st;
    Piece trial;
    /* The probes stay in the estimated root frame (a probe that misses the tolerance is
     * expected here, refining the frame for each would be costly and, on a range that
     * needs two pieces, would turn the frame to fit the wrong shape); the shortest one
     * may refine it, which noisy first points need. */
    if ((st = fit_piece(F, i0, k_lo, start, 1, whole, NULL, frag)) != HK_OK) return st;
    frag->params_valid_for_cut = 1;
    *cut = k_lo;
    if (!acceptable(F, frag)) return HK_OK;
    int good = k_lo, bad = k_hi + 1; /* fits within the tolerance / does not (k_hi + 1: assumed) */
    while (bad - good > 1) {
        const int mid = good + (bad - good) / 2;
        if ((st = fit_piece(F, i0, mid, &frag->base, 0, frag, whole, &trial)) != HK_OK) return st;
        if (acceptable(F, &trial)) {
            good = mid;
            *frag = trial;
            frag->params_valid_for_cut = 1;
        } else {
            bad = mid;
        }
    }
    *cut = good;
    if ((st = settle_cut(F, i0, k_lo, i1, frag, cut)) != HK_OK) return st;
    /* The first piece at the root, now that its extent is known, may refine the frame it
     * starts from (the probes kept the estimated one): every later piece inherits it. */
    if (i0 == 0 && F->opt->refine_start) {
        if ((st = fit_piece(F, i0, *cut, start, 1, frag, NULL, &trial)) != HK_OK) return st;
        if (acceptable(F, &trial) && trial.error + trial.join_error < frag->error + frag->join_error) {
            *frag = trial;
            frag->params_valid_for_cut = 1;
        }
    }
    return HK_OK;
}

/* Fits samples i0..i1 from `start` with at most `budget` pieces, appending them to
 * F->out; *end gets the end pose of the last one. `known` (may be NULL) is a fit of this
 * very range already computed; hint (may be NULL) an extra seed. */
static hk_Status fit_range(Fit *F, int i0, int i1, const hk_CurveStart *start, int budget, const Piece *known,
                           const Piece *hint, hk_CurveStart *end)
{
    Piece whole;
    hk_Status st;
    if (known) whole = *known;
    else if ((st = fit_piece(F, i0, i1, start, 1, hint, NULL, &whole)) != HK_OK) return st;
    /* A first fragment that also turns the root frame has ROT more unknowns to pin down. */
    const int first_points = F->min_points + (F->opt->refine_start && i0 == 0 ? ROT : 0);
    const int k_lo = i0 + first_points - 1, k_hi = i1 - (F->min_points - 1);
    if (acceptable(F, &whole) || budget < 2 || k_lo > k_hi) {
        emit(F, &whole, i0, i1);
        *end = whole.end;
        return HK_OK;
    }

    Piece frag;
    int cut = k_lo, reuse;
    st = F->opt->method == HK_CURVEFIT_LEAST_SQUARES ? longest_prefix_cut(F, i0, i1, k_lo, k_hi, start, &whole, &frag, &cut)
                                                     : paper_cut(F, i0, i1, k_lo, k_hi, start, &whole, &frag, &cut);
    if (st != HK_OK) return st;
    /* frag fits samples i0..cut when the heuristic says so (reuse); otherwise it is only a
     * hint for the first part's own fit. */
    reuse = frag.params_valid_for_cut;
    const int mark = F->out->piece_count;
    hk_CurveStart mid;
    st = fit_range(F, i0, cut, start, budget - 1, reuse ? &frag : NULL, &frag, &mid);
    if (st != HK_OK) return st;
    const int used = F->out->piece_count - mark;
    st = fit_range(F, cut, i1, &mid, budget - used, NULL, &whole, end);
    if (st != HK_OK) return st;

    /* Undo a split that made the range worse (the heuristics can misjudge a cut). */
    if (trace_chain(F->model, F->user, F->out, mark, F->out->piece_count, i1, F->h, &F->starts[mark],
                    F->ws->chain, &F->evaluations) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed re-tracing its own pieces");
    const int m = i1 - i0 + 1;
    const double split_error =
        hk_frechet_coupling_prefix(F->ws->target + i0, F->ws->chain + i0, m, F->ws->row, NULL) / (double)m;
    if (!(split_error < whole.error)) {
        F->out->piece_count = mark;
        emit(F, &whole, i0, i1);
        *end = whole.end;
    }
    return HK_OK;
}

/* ---- a fixed layout (§5.4) ------------------------------------------------------------ */

/* Exactly P pieces of equal length, fitted one after the other from the end pose of the
 * last (the root one may refine its frame), each seeded by its predecessor. */
static hk_Status fit_fixed(Fit *F, int pieces, const hk_CurveStart *start)
{
    hk_CurveStart pose = *start;
    Piece prev, piece;
    for (int k = 0; k < pieces; k++) {
        const int a = (int)(((long)k * (F->n - 1) + pieces / 2) / pieces);
        const int b = (int)(((long)(k + 1) * (F->n - 1) + pieces / 2) / pieces);
        hk_Status st = fit_piece(F, a, b, &pose, 1, k > 0 ? &prev : NULL, NULL, &piece);
        if (st != HK_OK) return st;
        emit(F, &piece, a, b);
        pose = piece.end;
        prev = piece;
    }
    return HK_OK;
}

/* ---- polishing a chain (least squares) ------------------------------------------------ */

/* The chain's residuals for all its parameters x (piece after piece): the distances of
 * every sample to the chained model, weighted 1/sqrt(n), and lambda x_j. */
static int chain_residuals(const double *x, double *r, void *user)
{
    Fit *F = user;
    const hk_CurveFit *o = F->out;
    hk_CurveStart pose = F->root_base, end;
    if (F->opt->root_frame) F->opt->root_frame(F->user, x, &pose);
    for (int k = 0; k < o->piece_count; k++) {
        const int a = o->first_sample[k], b = k + 1 < o->piece_count ? o->first_sample[k + 1] : F->n - 1;
        if (trace(F, x + k * F->np, &pose, b - a + 1, F->ws->chain + a, &end) != 0) return 1;
        pose = end;
    }
    const double w = 1.0 / sqrt((double)F->n);
    for (int i = 0; i < F->n; i++) {
        r[3 * i] = w * (F->ws->chain[i].x - F->ws->target[i].x);
        r[3 * i + 1] = w * (F->ws->chain[i].y - F->ws->target[i].y);
        r[3 * i + 2] = w * (F->ws->chain[i].z - F->ws->target[i].z);
    }
    const int np = o->piece_count * F->np;
    for (int j = 0; j < np; j++) r[3 * F->n + j] = F->opt->lambda * penalty_weight(F->opt, j % F->np) * x[j];
    return 0;
}

/* All pieces refitted together, their joins fixed: each piece was fitted alone from the
 * end pose of its predecessor, whose small errors in the frame there its successors
 * could only bend to follow; moving them together lets the first pieces end where the
 * later ones need them (the p-helicoid's frame continuity of §3.4 is kept, the joins
 * stay chained). Kept only when the chain's coupling improves. Chains of more than
 * POLISH_PARAMS parameters are left as they are. */
static hk_Status polish_chain(Fit *F)
{
    hk_CurveFit *o = F->out;
    const int n = o->piece_count * F->np;
    if (o->piece_count < 2 || n > POLISH_PARAMS || n < 1) return HK_OK;
    double x[POLISH_PARAMS], scale[POLISH_PARAMS];
    for (int k = 0; k < o->piece_count; k++)
        for (int j = 0; j < F->np; j++) {
            x[k * F->np + j] = o->params[k][j];
            scale[k * F->np + j] = F->scale[j];
        }
    const hk_LeastSquaresOptions lo = least_squares_options(F, n);
    const int m = (int)(3 * F->n) + n;
    hk_LeastSquaresResult r;
    if (hk_least_squares_minimize(n, m, x, scale, chain_residuals, F, &lo, F->ws->lsq, &r, NULL) != HK_OK) return HK_OK;
    /* The polished chain, traced once more into ws->chain with its poses. */
    double saved[HK_CURVEFIT_MAX_PIECES][MAXP];
    memcpy(saved, o->params, sizeof saved);
    for (int k = 0; k < o->piece_count; k++) memcpy(o->params[k], x + k * F->np, (size_t)F->np * sizeof(double));
    hk_CurveStart pose = F->root_base, starts[HK_CURVEFIT_MAX_PIECES], end;
    if (F->opt->root_frame) F->opt->root_frame(F->user, x, &pose);
    int ok = 1;
    for (int k = 0; k < o->piece_count && ok; k++) {
        const int a = o->first_sample[k], b = k + 1 < o->piece_count ? o->first_sample[k + 1] : F->n - 1;
        starts[k] = pose;
        ok = trace(F, o->params[k], &pose, b - a + 1, F->ws->chain + a, &end) == 0;
        pose = end;
    }
    const double polished = ok ? hk_frechet_coupling_prefix(F->ws->target, F->ws->chain, F->n, F->ws->row, NULL) : INFINITY;
    if (!(polished / (double)F->n < o->error)) {
        memcpy(o->params, saved, sizeof saved);
        return HK_OK;
    }
    for (int k = 0; k < o->piece_count; k++) {
        const int a = o->first_sample[k], b = k + 1 < o->piece_count ? o->first_sample[k + 1] : F->n - 1;
        double c, d;
        hk_frechet_both(F->ws->target + a, b - a + 1, F->ws->chain + a, b - a + 1, F->ws->row, &c, &d);
        o->piece_error[k] = c / (double)(b - a + 1);
        o->piece_frechet[k] = d;
        F->starts[k] = starts[k];
    }
    return HK_OK;
}

/* ---- entry points ----------------------------------------------------------------------- */

static int frame_ok(const hk_Mat3 *q)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            if (!isfinite(q->m[i][j])) return 0;
            const double dot = hk_v3_dot(hk_m3_col(q, i), hk_m3_col(q, j));
            if (fabs(dot - (i == j)) > 1e-6) return 0;
        }
    return hk_v3_dot(hk_v3_cross(hk_m3_col(q, 0), hk_m3_col(q, 1)), hk_m3_col(q, 2)) > 0.0;
}

static hk_Status check_options(const hk_CurveFitOptions *o, int np, hk_Error *err)
{
#define BAD(...) hk_error_set(err, HK_ERR_INVALID, "curve fit: " __VA_ARGS__)
    if (!(o->lambda >= 0.0) || !isfinite(o->lambda)) return BAD("lambda must be finite and >= 0, got %g", o->lambda);
    for (int j = 0; j < HK_CURVEFIT_MAX_PARAMS; j++)
        if (!(o->penalty_weight[j] >= 0.0) || !isfinite(o->penalty_weight[j]))
            return BAD("penalty_weight[%d] must be finite and >= 0, got %g", j, o->penalty_weight[j]);
    if (!(o->tolerance >= 0.0)) return BAD("tolerance must be >= 0, got %g", o->tolerance);
    if (!(o->split_threshold > 0.0 && o->split_threshold <= 1.0))
        return BAD("split_threshold must be in (0, 1], got %g", o->split_threshold);
    if (!(o->min_fragment_length >= 0.0) || !isfinite(o->min_fragment_length))
        return BAD("min_fragment_length must be finite and >= 0, got %g", o->min_fragment_length);
    if (o->max_pieces < 1 || o->max_pieces > HK_CURVEFIT_MAX_PIECES)
        return BAD("max_pieces must be in 1..%d, got %d", HK_CURVEFIT_MAX_PIECES, o->max_pieces);
    if (o->method != HK_CURVEFIT_LEAST_SQUARES && o->method != HK_CURVEFIT_NELDER_MEAD)
        return BAD("method must be HK_CURVEFIT_LEAST_SQUARES or HK_CURVEFIT_NELDER_MEAD, got %d", o->method);
    if (o->max_evaluations < np + 1)
        return BAD("max_evaluations must be >= param_count + 1 = %d, got %d", np + 1, o->max_evaluations);
    if (o->samples != 0 && (o->samples < 2 || o->samples > HK_CURVEFIT_MAX_SAMPLES))
        return BAD("samples must be 0 or in 2..%d, got %d", HK_CURVEFIT_MAX_SAMPLES, o->samples);
    if (o->fixed_pieces < 0 || o->fixed_pieces > HK_CURVEFIT_MAX_PIECES)
        return BAD("fixed_pieces must be in 0..%d, got %d", HK_CURVEFIT_MAX_PIECES, o->fixed_pieces);
    if (o->restarts < 0 || o->restarts > 100) return BAD("restarts must be in 0..100, got %d", o->restarts);
    if (!(o->param_tolerance >= 0.0) || !(o->cost_tolerance >= 0.0))
        return BAD("param_tolerance and cost_tolerance must be >= 0 (got %g and %g)", o->param_tolerance,
                   o->cost_tolerance);
    if (o->arc_length != 0 && o->arc_length != 1) return BAD("arc_length must be 0 or 1, got %d", o->arc_length);
    if (o->refine_start != 0 && o->refine_start != 1) return BAD("refine_start must be 0 or 1, got %d", o->refine_start);
    if (o->use_start && (!hk_v3_isfinite(o->start.pos) || !frame_ok(&o->start.frame)))
        return BAD("the given start pose needs a finite position and a right-handed orthonormal frame");
    return HK_OK;
#undef BAD
}

/* Initial simplex step of the root frame's rotation (rad): a noisy first segment tilts
 * the estimated frame by about noise / spacing, a few degrees for captured hair. */
#define ROOT_TURN_SCALE 0.2

static int samples_for(const hk_CurveFitOptions *o, int count) { return o->samples ? o->samples : count; }

hk_Status hk_curve_fit_piecewise_ws(hk_CurveFitWorkspace *ws, const hk_Vec3 *target, int count,
                                    hk_CurveModelFn model, void *user, int param_count,
                                    const double *seed, const double *scale,
                                    const hk_CurveFitOptions *opt, hk_CurveFit *out, hk_Error *err)
{
    if (!ws || !target || !model || !out) return hk_error_set(err, HK_ERR_INVALID, "curve fit: NULL argument");
    memset(out, 0, sizeof *out);
    const hk_CurveFitOptions defaults = hk_default_curve_fit_options();
    if (!opt) opt = &defaults;
    if (param_count < 0 || param_count > MAXP)
        return hk_error_set(err, HK_ERR_INVALID, "curve fit: %d parameters, expected 0..%d", param_count, MAXP);
    if (param_count > 0 && (!seed || !scale)) return hk_error_set(err, HK_ERR_INVALID, "curve fit: NULL seed or scale");
    for (int j = 0; j < param_count; j++) {
        if (!isfinite(seed[j])) return hk_error_set(err, HK_ERR_INVALID, "curve fit: seed[%d] is not finite", j);
        if (!isfinite(scale[j]) || scale[j] == 0.0)
            return hk_error_set(err, HK_ERR_INVALID, "curve fit: scale[%d] must be finite and non-zero, got %g", j,
                                scale[j]);
    }
    if (count < 2) return hk_error_set(err, HK_ERR_INVALID, "curve fit: the target needs at least 2 points, got %d", count);
    hk_Status st = check_options(opt, param_count, err);
    if (st != HK_OK) return st;
    const int n = samples_for(opt, count);
    if (n > ws->capacity)
        return hk_error_set(err, HK_ERR_INVALID, "curve fit: %d samples exceed the workspace's %d", n, ws->capacity);

    double length;
    st = opt->arc_length ? hk_curve_resample_arc(target, count, n, ws->target, &length, err)
                         : hk_curve_resample(target, count, n, ws->target, &length, err);
    if (st != HK_OK) return st;
    hk_CurveStart start = opt->start;
    if (!opt->use_start && (st = hk_curve_estimate_start(ws->target, n, &start, err)) != HK_OK) return st;

    double zero[MAXP] = {0};
    Fit F;
    memset(&F, 0, sizeof F);
    F.ws = ws;
    F.model = model;
    F.user = user;
    F.np = param_count;
    F.seed = param_count > 0 ? seed : zero;
    for (int j = 0; j < param_count; j++) F.scale[j] = scale[j];
    for (int j = 0; j < ROT; j++) F.scale[param_count + j] = ROOT_TURN_SCALE;
    F.opt = opt;
    F.n = n;
    F.h = length / (double)(n - 1);
    /* A fragment spans at least min_fragment_length and has at least param_count + 2
     * samples, and 4: fewer cannot pin the parameters down, and a parameter the points
     * do not see (the last twist of a 3-sample helix) still turns the end pose the next
     * piece starts from. */
    const double min_segments = ceil(opt->min_fragment_length / F.h - 1e-9);
    F.min_points = param_count + 2 > 4 ? param_count + 2 : 4;
    if (min_segments + 1.0 > (double)F.min_points)
        F.min_points = min_segments + 1.0 >= (double)n ? n : (int)min_segments + 1;
    F.out = out;
    F.err = err;

    out->param_count = param_count;
    out->sample_count = n;
    out->sample_spacing = F.h;
    out->start = start;
    hk_CurveStart end;
    if (opt->fixed_pieces > 0) {
        /* every piece needs the samples of the shortest fragment */
        if ((long)opt->fixed_pieces * (F.min_points - 1) > n - 1)
            st = hk_error_set(err, HK_ERR_INVALID,
                              "curve fit: %d pieces of at least %d samples each do not fit in %d samples (a "
                              "piece spans at least min_fragment_length = %g m and %d samples)",
                              opt->fixed_pieces, F.min_points, n, opt->min_fragment_length,
                              param_count + 2 > 4 ? param_count + 2 : 4);
        else st = fit_fixed(&F, opt->fixed_pieces, &start);
    } else {
        st = fit_range(&F, 0, n - 1, &start, opt->max_pieces, NULL, NULL, &end);
    }
    for (int pass = 0; pass < 2 && st == HK_OK; pass++) {
        out->start = F.starts[0];
        if (trace_chain(model, user, out, 0, out->piece_count, n - 1, F.h, &out->start, ws->chain, &F.evaluations) != 0) {
            st = hk_error_set(err, HK_ERR_NUMERIC, "curve fit: the model failed re-tracing its own pieces");
        } else {
            double c, d;
            hk_frechet_both(ws->target, n, ws->chain, n, ws->row, &c, &d);
            out->error = c / (double)n;
            out->frechet = d;
        }
        /* Polish only a chain that misses the tolerance: its pieces each met it. */
        if (st != HK_OK || pass == 1 || opt->method != HK_CURVEFIT_LEAST_SQUARES || out->piece_count < 2 ||
            out->error <= opt->tolerance)
            break;
        st = polish_chain(&F);
    }
    out->evaluations = F.evaluations;
    if (st != HK_OK) out->piece_count = 0;
    return st;
}

hk_Status hk_curve_fit_piecewise(const hk_Vec3 *target, int count, hk_CurveModelFn model, void *user,
                                 int param_count, const double *seed, const double *scale,
                                 const hk_CurveFitOptions *opt, hk_CurveFit *out, hk_Error *err)
{
    const hk_CurveFitOptions defaults = hk_default_curve_fit_options();
    const int n = samples_for(opt ? opt : &defaults, count);
    if (out) memset(out, 0, sizeof *out);
    if (count < 2) return hk_error_set(err, HK_ERR_INVALID, "curve fit: the target needs at least 2 points, got %d", count);
    if (n < 2 || n > HK_CURVEFIT_MAX_SAMPLES)
        return hk_error_set(err, HK_ERR_INVALID, "curve fit: %d samples, expected 2..%d (set options.samples to resample)",
                            n, HK_CURVEFIT_MAX_SAMPLES);
    hk_CurveFitWorkspace *ws = hk_curve_fit_workspace_create(n, err);
    if (!ws) return err ? err->code : HK_ERR_NOMEM;
    const hk_Status st = hk_curve_fit_piecewise_ws(ws, target, count, model, user, param_count, seed, scale, opt, out, err);
    hk_curve_fit_workspace_destroy(ws);
    return st;
}

hk_Status hk_curve_fit_trace(const hk_CurveFit *fit, hk_CurveModelFn model, void *user, hk_Vec3 *out, hk_Error *err)
{
    if (!fit || !model || !out) return hk_error_set(err, HK_ERR_INVALID, "curve fit trace: NULL argument");
    const int n = fit->sample_count, pc = fit->piece_count;
    if (pc < 1 || pc > HK_CURVEFIT_MAX_PIECES || n < 2 || n > HK_CURVEFIT_MAX_SAMPLES || fit->param_count < 0 ||
        fit->param_count > MAXP || !(fit->sample_spacing > 0.0) || !isfinite(fit->sample_spacing) ||
        fit->first_sample[0] != 0)
        return hk_error_set(err, HK_ERR_INVALID, "curve fit trace: malformed fit (%d pieces, %d samples)", pc, n);
    for (int k = 1; k < pc; k++)
        if (fit->first_sample[k] <= fit->first_sample[k - 1] || fit->first_sample[k] >= n - 1)
            return hk_error_set(err, HK_ERR_INVALID, "curve fit trace: piece %d starts at sample %d, out of order", k,
                                fit->first_sample[k]);
    long evaluations = 0;
    if (trace_chain(model, user, fit, 0, pc, n - 1, fit->sample_spacing, &fit->start, out, &evaluations) != 0)
        return hk_error_set(err, HK_ERR_NUMERIC, "curve fit trace: the model failed");
    return HK_OK;
}
