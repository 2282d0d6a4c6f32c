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

#include "helicoid/curvefit_internal.h"

#define MAXP HK_CURVEFIT_MAX_PARAMS

struct hk_CurveFitWorkspace {
    int capacity;
    hk_Vec3 *target; /* the resampled target */
    hk_Vec3 *trace;  /* the objective's model output */
    hk_Vec3 *best;   /* a fit's trace kept for the split heuristics */
    hk_Vec3 *chain;  /* chained pieces, for the error of a split and of the result */
    double *row;     /* 2 * capacity: dynamic programming rows */
    double *prefix;  /* coupling of growing fragments */
    double *diff;    /* bend differences */
};

hk_CurveFitOptions hk_default_curve_fit_options(void)
{
    hk_CurveFitOptions o;
    memset(&o, 0, sizeof o);
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
    if (!ws->diff) {
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
    hk_free(ws);
}

/* ---- one fit ------------------------------------------------------------------------ */

#define ROT 3 /* parameters of the root frame's rotation when it is refined */
#define M_PI_VALUE 3.14159265358979323846

typedef struct Piece {
    double params[MAXP];
    double rot[ROT];     /* rotation of the root frame (refined first piece), else 0 */
    hk_CurveStart start; /* the pose it starts from */
    hk_CurveStart end;   /* and ends at */
    double error;        /* normalised coupling against its fragment (m) */
    double frechet;      /* Fréchet distance against its fragment (m) */
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

static double param_norm(int np, const double *x)
{
    double s = 0.0;
    for (int j = 0; j < np; j++) s += x[j] * x[j];
    return sqrt(s);
}

/* Eq. (5): normalised coupling + lambda |k| (the root rotation is not penalised).
 * Model failure: +inf, which Nelder-Mead never accepts. */
static double objective(const double *x, void *user)
{
    Fit *F = user;
    hk_CurveStart end;
    const hk_CurveStart s = F->rotating ? rotated(&F->base, x + F->np) : F->base;
    if (trace(F, x, &s, F->m, F->ws->trace, &end) != 0) return INFINITY;
    const double c = hk_frechet_coupling_prefix(F->ws->target + F->i0, F->ws->trace, F->m, F->ws->row, NULL);
    return c / (double)F->m + F->opt->lambda * param_norm(F->np, x);
}

/* Nelder-Mead over the first nx entries of x, restarted from a converged simplex that
 * still misses the tolerance: Nelder-Mead can stall on a non-stationary point (McKinnon
 * 1998); a fresh simplex around it either confirms it or moves on. */
static hk_Status minimise(Fit *F, int nx, double *x, const double *scale)
{
    hk_NelderMeadOptions nm;
    nm.max_evaluations = F->opt->max_evaluations;
    nm.x_tolerance = F->opt->param_tolerance;
    nm.f_tolerance = F->opt->cost_tolerance;
    hk_NelderMeadResult r;
    hk_Status st = hk_nelder_mead_minimize(nx, x, scale, objective, F, &nm, &r, NULL);
    for (int k = 0; st == HK_OK && r.converged && k < F->opt->restarts &&
                    r.f - F->opt->lambda * param_norm(F->np, x) > F->opt->tolerance;
         k++) {
        const double before = r.f;
        st = hk_nelder_mead_minimize(nx, x, scale, objective, F, &nm, &r, NULL);
        if (st != HK_OK || !(before - r.f > F->opt->cost_tolerance)) break;
    }
    return st;
}

/* Copies into x the candidate (rows of cand, nx entries each) with the lowest objective. */
static void pick(Fit *F, double (*cand)[MAXP + ROT], int count, double *x)
{
    double fx = INFINITY;
    for (int c = 0; c < count; c++) {
        const double f = objective(cand[c], F);
        if (c == 0 || f < fx) {
            memcpy(x, cand[c], (MAXP + ROT) * sizeof(double));
            fx = f;
        }
    }
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
    for (int h = 0; h < 2; h++)
        if (hints[h]) memcpy(cand[count++], hints[h]->params, (size_t)F->np * sizeof(double));
    double x[MAXP + ROT];
    pick(F, cand, count, x);
    hk_Status st = minimise(F, F->np, x, F->scale);
    if (st == HK_OK && refine && objective(x, F) - F->opt->lambda * param_norm(F->np, x) > F->opt->tolerance) {
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
        pick(F, cand, count, x);
        st = minimise(F, F->np + ROT, x, F->scale);
    }
    if (st != HK_OK)
        return hk_error_set(F->err, HK_ERR_NUMERIC,
                            "curve fit: the model failed (or gave non-finite points) for every parameter "
                            "vector tried on samples %d..%d",
                            i0, i1);
    memset(piece, 0, sizeof *piece);
    memcpy(piece->params, x, (size_t)F->np * sizeof(double));
    if (F->rotating) memcpy(piece->rot, x + F->np, sizeof piece->rot);
    piece->start = F->rotating ? rotated(start, piece->rot) : *start;
    if (trace(F, piece->params, &piece->start, F->m, F->ws->best, &piece->end) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed at its own best fit (samples %d..%d)",
                            i0, i1);
    double c, d;
    hk_frechet_both(F->ws->target + i0, F->m, F->ws->best, F->m, F->ws->row, &c, &d);
    piece->error = c / (double)F->m;
    piece->frechet = d;
    return HK_OK;
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
    if (trace(F, frag->params, &frag->start, m, F->ws->best, &end) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed at its own best fit (samples %d..%d)",
                            i0, k_max);
    double *d = F->ws->diff;
    double mean = 0.0;
    for (int j = i0 + 1; j <= k_max; j++) {
        double turn_t, twist_t, turn_f, twist_f;
        hk_polyline_bend(F->ws->target, j, &turn_t, &twist_t);
        hk_polyline_bend(F->ws->best, j - i0, &turn_f, &twist_f);
        d[j] = fabs(turn_t - turn_f) + fabs(twist_t - twist_f);
        mean += d[j];
    }
    mean /= (double)(k_max - i0);
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
    if (whole.error <= F->opt->tolerance || budget < 2 || k_lo > k_hi) {
        emit(F, &whole, i0, i1);
        *end = whole.end;
        return HK_OK;
    }

    /* The whole fit's trace for the Fréchet threshold (a `known` fit left none behind). */
    hk_CurveStart tmp;
    if (trace(F, whole.params, &whole.start, i1 - i0 + 1, F->ws->best, &tmp) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed at its own best fit (samples %d..%d)",
                            i0, i1);
    int k_max = frechet_upper_limit(F, i0, i1);
    k_max = k_max < k_lo ? k_lo : (k_max > k_hi ? k_hi : k_max);
    Piece frag;
    int have_frag = 0, cut = k_lo;
    if (k_max > k_lo) {
        /* Fits that only locate the cut stay in the estimated root frame: no refinement
         * for each, and on clean data that frame is the exact one. */
        if ((st = fit_piece(F, i0, k_max, start, 0, &whole, NULL, &frag)) != HK_OK) return st;
        have_frag = 1;
        /* The threshold is only a first guess: while the fragment still fits within the
         * tolerance, grow it by half, so that the backtracking starts past the change. */
        while (frag.error <= F->opt->tolerance && k_max < k_hi) {
            const int step = (k_max - i0) / 2 > F->min_points - 1 ? (k_max - i0) / 2 : F->min_points - 1;
            const int next = k_max + step < k_hi ? k_max + step : k_hi;
            Piece longer;
            if ((st = fit_piece(F, i0, next, start, 0, &frag, NULL, &longer)) != HK_OK) return st;
            k_max = next;
            frag = longer;
        }
        if ((st = curvature_cut(F, i0, k_lo, k_max, &frag, &cut)) != HK_OK) return st;
    }

    const int mark = F->out->piece_count;
    hk_CurveStart mid;
    /* The fragment's fit is the first part's when the cut is at its end (at the root
     * with refine_start, the first part gets its own chance to refine the frame). */
    const int reuse = have_frag && cut == k_max && (i0 > 0 || !F->opt->refine_start);
    st = fit_range(F, i0, cut, start, budget - 1, reuse ? &frag : NULL, have_frag ? &frag : &whole, &mid);
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
    if (!(o->tolerance >= 0.0)) return BAD("tolerance must be >= 0, got %g", o->tolerance);
    if (!(o->split_threshold > 0.0 && o->split_threshold <= 1.0))
        return BAD("split_threshold must be in (0, 1], got %g", o->split_threshold);
    if (!(o->min_fragment_length >= 0.0) || !isfinite(o->min_fragment_length))
        return BAD("min_fragment_length must be finite and >= 0, got %g", o->min_fragment_length);
    if (o->max_pieces < 1 || o->max_pieces > HK_CURVEFIT_MAX_PIECES)
        return BAD("max_pieces must be in 1..%d, got %d", HK_CURVEFIT_MAX_PIECES, o->max_pieces);
    if (o->max_evaluations < np + 1)
        return BAD("max_evaluations must be >= param_count + 1 = %d, got %d", np + 1, o->max_evaluations);
    if (o->samples != 0 && (o->samples < 2 || o->samples > HK_CURVEFIT_MAX_SAMPLES))
        return BAD("samples must be 0 or in 2..%d, got %d", HK_CURVEFIT_MAX_SAMPLES, o->samples);
    if (o->restarts < 0 || o->restarts > 100) return BAD("restarts must be in 0..100, got %d", o->restarts);
    if (!(o->param_tolerance >= 0.0) || !(o->cost_tolerance >= 0.0))
        return BAD("param_tolerance and cost_tolerance must be >= 0 (got %g and %g)", o->param_tolerance,
                   o->cost_tolerance);
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
    if ((st = hk_curve_resample(target, count, n, ws->target, &length, err)) != HK_OK) return st;
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
    st = fit_range(&F, 0, n - 1, &start, opt->max_pieces, NULL, NULL, &end);
    if (st == HK_OK) {
        out->start = F.starts[0];
        if (trace_chain(model, user, out, 0, out->piece_count, n - 1, F.h, &out->start, ws->chain, &F.evaluations) != 0) {
            st = hk_error_set(err, HK_ERR_NUMERIC, "curve fit: the model failed re-tracing its own pieces");
        } else {
            double c, d;
            hk_frechet_both(ws->target, n, ws->chain, n, ws->row, &c, &d);
            out->error = c / (double)n;
            out->frechet = d;
        }
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
