/* Fitting a chain of curve-model pieces to a polyline (Piuze et al. 2011 §5.2-5.3): the
 * options, the workspace and the entry points. The parts: fit_piece.c (one piece),
 * fit_cuts.c (where to cut, the recursion), fit_chain.c (fixed layouts, the polish).
 *
 * One piece, eq. (5): k0 = argmin_k C(h, H(k, Q, p0, L)) + lambda |k|. The paper's way
 * (method HK_CURVEFIT_NELDER_MEAD): C the discrete Fréchet coupling, normalised by the
 * sample count so that it and lambda are in metres, minimised by Nelder-Mead. Ours (the
 * default, HK_CURVEFIT_LEAST_SQUARES): the mean squared distance of sample i of the
 * target to point i of the model, both at the same arc length, plus (lambda |k|)^2 and a
 * term for the end tangent where another piece joins, by Levenberg-Marquardt. The target
 * is first resampled uniformly by arc length (estimated arc length for smooth models),
 * so every millimetre of hair weighs the same whatever the capture's vertex spacing, and
 * the model is traced with the same spacing.
 *
 * Root frame: Q is estimated from the first points (curve_polyline.c), turned by the
 * model's root_frame rule; with refine_start, a fit at the root that misses the tolerance
 * is redone with three more parameters, a rotation of Q (on noisy captures the first bend
 * is buried in the noise and the estimated normal can be off by any angle).
 *
 * Pieces, §5.3 (recursive): fit the whole range; accept it if it is within the
 * tolerance; otherwise cut (the paper's Fréchet threshold and bend backtracking, or our
 * longest acceptable prefix), fit the first part, start the second at its end pose
 * (frames continuous across the join, §3.4), recurse, and undo a split that made the
 * range worse. See docs/helicoid-fitting.md for why these choices. */
#include <math.h>
#include <string.h>

#include "optimize/piecewise_internal.h"

hk_CurveFitDef hk_default_curve_fit_def(void)
{
    hk_CurveFitDef o;
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
    ws->lsq =
        ws->diff ? hk_alloc_array(HK_LEAST_SQUARES_WORK(POLISH_PARAMS, CHAIN_RESIDUALS(n)), sizeof(double), err) : NULL;
    ws->dtrace = ws->lsq ? hk_alloc_array((size_t)MAXP * n, sizeof(hk_Vec3), err) : NULL;
    ws->cache_points = ws->dtrace ? hk_alloc_array((size_t)TRACE_CACHE * n, sizeof(hk_Vec3), err) : NULL;
    ws->ref_points = ws->cache_points ? hk_alloc_array(n, sizeof(hk_Vec3), err) : NULL;
    if (!ws->ref_points) {
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
    hk_free(ws->dtrace);
    hk_free(ws->cache_points);
    hk_free(ws->ref_points);
    hk_free(ws);
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

static hk_Status check_options(const hk_CurveFitDef *o, int np, hk_Error *err)
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
        return BAD("method must be HK_CURVEFIT_LEAST_SQUARES or HK_CURVEFIT_NELDER_MEAD, got %d", (int)o->method);
    if (o->max_evaluations < np + 1)
        return BAD("max_evaluations must be >= param_count + 1 = %d, got %d", np + 1, o->max_evaluations);
    if (o->samples != 0 && (o->samples < 2 || o->samples > HK_CURVEFIT_MAX_SAMPLES))
        return BAD("samples must be 0 or in 2..%d, got %d", HK_CURVEFIT_MAX_SAMPLES, o->samples);
    if (o->fixed_pieces < 0 || o->fixed_pieces > HK_CURVEFIT_MAX_PIECES)
        return BAD("fixed_pieces must be in 0..%d, got %d", HK_CURVEFIT_MAX_PIECES, o->fixed_pieces);
    if (!(o->piece_length >= 0.0) || !isfinite(o->piece_length) || !(o->root_piece_length >= 0.0) ||
        !isfinite(o->root_piece_length))
        return BAD("piece_length and root_piece_length must be finite and >= 0, got %g and %g", o->piece_length,
                   o->root_piece_length);
    if (o->piece_length > 0.0 && o->fixed_pieces > 0)
        return BAD("fixed_pieces (%d) and piece_length (%g m) are two layouts: set one", o->fixed_pieces,
                   o->piece_length);
    if (o->restarts < 0 || o->restarts > 100) return BAD("restarts must be in 0..100, got %d", o->restarts);
    if (!(o->param_tolerance >= 0.0) || !(o->cost_tolerance >= 0.0))
        return BAD("param_tolerance and cost_tolerance must be >= 0 (got %g and %g)", o->param_tolerance,
                   o->cost_tolerance);
    if (o->arc_length != 0 && o->arc_length != 1) return BAD("arc_length must be 0 or 1, got %d", o->arc_length);
    if (o->refine_start != 0 && o->refine_start != 1)
        return BAD("refine_start must be 0 or 1, got %d", o->refine_start);
    if (o->known_to_split != 0 && o->known_to_split != 1)
        return BAD("known_to_split must be 0 or 1, got %d", o->known_to_split);
    if (o->use_start && (!hk_v3_isfinite(o->start.pos) || !frame_ok(&o->start.frame)))
        return BAD("the given start pose needs a finite position and a right-handed orthonormal frame");
    return HK_OK;
#undef BAD
}

/* Initial simplex step of the root frame's rotation (rad): a noisy first segment tilts
 * the estimated frame by about noise / spacing, a few degrees for captured hair. */
#define ROOT_TURN_SCALE 0.2

/* The samples where the pieces of a fixed layout start, bounds[0] = 0 and bounds[count] =
 * n - 1; returns the count. Every piece needs the samples of the shortest fragment: a
 * target too short for the layout gets as many pieces as it holds, at least one (a strand
 * of a head may be short, and failing the whole head for it would help nobody); with
 * piece_length, a rest shorter than that goes to the last piece. */
static int fixed_layout(const Fit *F, const hk_CurveFitDef *o, int *bounds)
{
    const int least = F->min_points > 1 ? F->min_points - 1 : 1; /* segments of a piece */
    int count = 0;
    bounds[0] = 0;
    if (o->piece_length > 0.0) {
        double at = o->root_piece_length > 0.0 ? o->root_piece_length : o->piece_length;
        while (count < HK_CURVEFIT_MAX_PIECES - 1) {
            const double q = at / F->h;
            int b = q < (double)F->n ? (int)lround(q) : F->n;
            if (b < bounds[count] + least) b = bounds[count] + least;
            if (b > F->n - 1 - least) break;
            bounds[++count] = b;
            at += o->piece_length;
        }
        bounds[++count] = F->n - 1;
        return count;
    }
    const long fit = (F->n - 1) / least;
    const int pieces = fit < 1 ? 1 : (fit < o->fixed_pieces ? (int)fit : o->fixed_pieces);
    for (int k = 1; k <= pieces; k++) bounds[k] = (int)(((long)k * (F->n - 1) + pieces / 2) / pieces);
    return pieces;
}

/* The output's start, error and Fréchet distance: its chain traced by F->model. */
static hk_Status measure(Fit *F)
{
    hk_CurveFit *out = F->out;
    out->start = F->starts[0];
    /* the finished chain was traced by the finishing's last check, from the same start */
    const int traced = F->chain_traced;
    F->chain_traced = 0;
    if (!traced && hk_cf_trace_chain(F->model, F->user, out, 0, out->piece_count, F->n - 1, F->h, &out->start,
                                     F->ws->chain, &F->evaluations) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed re-tracing its own pieces");
    double c, d;
    hk_frechet_both(F->ws->target, F->n, F->ws->chain, F->n, F->ws->row, &c, &d);
    out->error = c / (double)F->n;
    out->frechet = d;
    return HK_OK;
}

static int samples_for(const hk_CurveFitDef *o, int count) { return o->samples ? o->samples : count; }

hk_Status hk_curve_fit_piecewise_ws(hk_CurveFitWorkspace *ws, const hk_Vec3 *target, int count, hk_CurveModelFn model,
                                    void *user, int param_count, const double *seed, const double *scale,
                                    const hk_CurveFitDef *opt, hk_CurveFit *out, hk_Error *err)
{
    if (!ws || !target || !model || !out) return hk_error_set(err, HK_ERR_INVALID, "curve fit: NULL argument");
    memset(out, 0, sizeof *out);
    const hk_CurveFitDef defaults = hk_default_curve_fit_def();
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
    if (count < 2)
        return hk_error_set(err, HK_ERR_INVALID, "curve fit: the target needs at least 2 points, got %d", count);
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

    /* the remembered traces are of another target's spacing and model */
    for (int k = 0; k < TRACE_CACHE; k++) ws->cache[k].model = NULL;
    double zero[MAXP] = {0};
    Fit F;
    memset(&F, 0, sizeof F);
    F.ws = ws;
    F.model = model;
    F.derivative = opt->model_derivative;
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
    if (opt->fixed_pieces > 0 || opt->piece_length > 0.0) {
        int bounds[HK_CURVEFIT_MAX_PIECES + 1];
        const int pieces = fixed_layout(&F, opt, bounds);
        st = hk_cf_fit_fixed(&F, bounds, pieces, &start);
    } else {
        st = hk_cf_fit_range(&F, 0, n - 1, &start, opt->max_pieces, NULL, NULL, &end);
    }
    if (st == HK_OK) st = measure(&F);
    /* Polish only a chain that misses the tolerance: its pieces each met it. */
    if (st == HK_OK && opt->method == HK_CURVEFIT_LEAST_SQUARES && out->piece_count >= 2 && out->error > opt->tolerance)
        st = hk_cf_polish_chain(&F);
    /* The pieces finished with the final model, and measured by it (after the polish,
     * which its traces are cheaper for; a finished chain is kept only when closer). */
    if (st == HK_OK && opt->final_model && (st = hk_cf_finish_pieces(&F)) == HK_OK) st = measure(&F);
    out->evaluations = F.evaluations;
    if (st != HK_OK) out->piece_count = 0;
    return st;
}

hk_Status hk_curve_fit_piecewise(const hk_Vec3 *target, int count, hk_CurveModelFn model, void *user, int param_count,
                                 const double *seed, const double *scale, const hk_CurveFitDef *opt, hk_CurveFit *out,
                                 hk_Error *err)
{
    const hk_CurveFitDef defaults = hk_default_curve_fit_def();
    const int n = samples_for(opt ? opt : &defaults, count);
    if (out) memset(out, 0, sizeof *out);
    if (count < 2)
        return hk_error_set(err, HK_ERR_INVALID, "curve fit: the target needs at least 2 points, got %d", count);
    if (n < 2 || n > HK_CURVEFIT_MAX_SAMPLES)
        return hk_error_set(err, HK_ERR_INVALID,
                            "curve fit: %d samples, expected 2..%d (set options.samples to resample)", n,
                            HK_CURVEFIT_MAX_SAMPLES);
    hk_CurveFitWorkspace *ws = hk_curve_fit_workspace_create(n, err);
    if (!ws) return err ? err->code : HK_ERR_NOMEM;
    const hk_Status st =
        hk_curve_fit_piecewise_ws(ws, target, count, model, user, param_count, seed, scale, opt, out, err);
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
    if (hk_cf_trace_chain(model, user, fit, 0, pc, n - 1, fit->sample_spacing, &fit->start, out, &evaluations) != 0)
        return hk_error_set(err, HK_ERR_NUMERIC, "curve fit trace: the model failed");
    return HK_OK;
}
