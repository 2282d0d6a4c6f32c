/* Whole chains of pieces: fixed layouts (§5.4 blends fits piece by piece) and the joint
 * polish of all a chain's parameters (least squares). */
#include <math.h>
#include <string.h>

#include "optimize/piecewise_internal.h"

/* ---- a fixed layout (§5.4) ------------------------------------------------------------ */

/* The pieces of a given layout, fitted one after the other from the end pose of the last
 * (the root one may refine its frame), each seeded by its predecessor. */
hk_Status hk_cf_fit_fixed(Fit *F, const int *bounds, int pieces, const hk_CurveStart *start)
{
    hk_CurveStart pose = *start;
    Piece prev, piece;
    for (int k = 0; k < pieces; k++) {
        const int a = bounds[k], b = bounds[k + 1];
        hk_Status st = hk_cf_fit_piece(F, a, b, &pose, 1, k > 0 ? &prev : NULL, NULL, &piece);
        if (st != HK_OK) return st;
        hk_cf_emit(F, &piece, a, b);
        pose = piece.end;
        prev = piece;
    }
    return HK_OK;
}

/* ---- finishing and polishing a chain (least squares) ---------------------------------- */

/* The sample where the output's piece k ends. */
static int piece_end(const Fit *F, int k)
{
    return k + 1 < F->out->piece_count ? F->out->first_sample[k + 1] : F->n - 1;
}

/* The normalised coupling of the output's chain traced by F->model, or +inf. */
static double chain_error(Fit *F)
{
    if (hk_cf_trace_chain(F->model, F->user, F->out, 0, F->out->piece_count, F->n - 1, F->h, &F->starts[0],
                          F->ws->chain, &F->evaluations) != 0)
        return INFINITY;
    return hk_frechet_coupling_prefix(F->ws->target, F->ws->chain, F->n, F->ws->row, NULL) / (double)F->n;
}

/* Each piece fitted again with the final model, in order, from its predecessor's new end
 * pose (the root one from the root pose the search settled, before the model's
 * root_frame rule), by one Levenberg-Marquardt run from its parameters: they are a few
 * microns from the final model's minimum, which a run reaches in a few steps. Kept when
 * the chain traced by the final model comes out closer than the search's pieces do. */
hk_Status hk_cf_finish_pieces(Fit *F)
{
    if (!F->opt->final_model) return HK_OK;
    hk_CurveFit *o = F->out;
    const hk_CurveModelFn search = F->model;
    const hk_CurveModelDerivFn search_derivative = F->derivative;
    F->model = F->opt->final_model;
    F->derivative = F->opt->final_derivative;
    const double before = chain_error(F);
    hk_CurveFit kept = *o;
    hk_CurveStart starts[HK_CURVEFIT_MAX_PIECES];
    memcpy(starts, F->starts, sizeof starts);
    hk_CurveStart pose = F->root_base;
    hk_Status st = HK_OK;
    F->finishing = 1;
    for (int k = 0; k < o->piece_count && st == HK_OK; k++) {
        const int a = o->first_sample[k], b = piece_end(F, k);
        Piece found, piece;
        memset(&found, 0, sizeof found);
        memcpy(found.params, o->params[k], sizeof found.params);
        if ((st = hk_cf_fit_piece(F, a, b, &pose, 1, &found, NULL, &piece)) != HK_OK) break;
        memcpy(o->params[k], piece.params, sizeof o->params[k]);
        o->piece_error[k] = piece.error;
        o->piece_frechet[k] = piece.frechet;
        F->starts[k] = piece.start;
        pose = piece.end;
    }
    F->finishing = 0;
    const double after = st == HK_OK ? chain_error(F) : INFINITY;
    F->chain_traced = st == HK_OK && after <= before && isfinite(after); /* measure() reuses it */
    if (st != HK_OK || !(after <= before)) {
        *o = kept;
        memcpy(F->starts, starts, sizeof starts);
        if (!isfinite(before)) {
            /* the final model refuses the search's pieces and found none of its own:
             * the result stays the search's, measured by its model */
            F->model = search;
            F->derivative = search_derivative;
        }
    }
    return HK_OK;
}

/* The number of parameters in which x differs from the reference chain's (n in all). */
static int differing(const ChainRef *ref, const double *x, int n)
{
    int d = 0;
    for (int j = 0; j < n; j++) d += memcmp(&x[j], &ref->x[j], sizeof(double)) != 0;
    return d;
}

/* Traces the output's pieces with the parameters x (piece after piece) into ws->chain,
 * from the root pose of the fit (the model's root_frame rule applied with x); starts (may
 * be NULL) gets each piece's start pose. 0 on success.
 * A forward-difference Jacobian column changes one piece's parameters: the pieces before
 * it start from the same poses with the same parameters as in the chain the column is
 * taken at, and a model is deterministic (hk_CurveModelFn), so their points are copied
 * from that chain (ws->ref, the last chain traced whose parameters differ from the one
 * before in more than one entry: the Jacobian's base point or a trial step) instead of
 * traced again: the same bytes. On Curly's strands of 16-32 points the polish traced
 * 14,794 pieces instead of 22,971, 24 % fewer instructions in its traces. */
static int trace_params(Fit *F, const double *x, hk_CurveStart *starts)
{
    hk_CurveFitWorkspace *ws = F->ws;
    ChainRef *ref = &ws->ref;
    const int pieces = F->out->piece_count, n = pieces * F->np;
    int same = ref->pieces == pieces; /* so far the pieces are the reference's */
    const int renew = !same || differing(ref, x, n) > 1;
    hk_CurveStart pose = F->root_base, end;
    if (F->opt->root_frame) F->opt->root_frame(F->user, x, &pose);
    for (int k = 0; k < pieces; k++) {
        const int a = F->out->first_sample[k], m = piece_end(F, k) - a + 1;
        const double *p = x + k * F->np;
        if (starts) starts[k] = pose;
        same = same && !memcmp(p, ref->x + k * F->np, (size_t)F->np * sizeof(double)) &&
               !memcmp(&pose, &ref->start[k], sizeof pose);
        if (same) {
            memcpy(ws->chain + a, ws->ref_points + a, (size_t)m * sizeof(hk_Vec3));
            end = ref->end[k];
        } else if (hk_cf_trace(F, p, &pose, m, ws->chain + a, &end) != 0) {
            if (renew) ref->pieces = 0;
            return 1;
        }
        if (renew) {
            ref->start[k] = pose;
            ref->end[k] = end;
        }
        pose = end;
    }
    if (renew) {
        ref->pieces = pieces;
        memcpy(ref->x, x, (size_t)n * sizeof(double));
        memcpy(ws->ref_points, ws->chain, (size_t)F->n * sizeof(hk_Vec3));
    }
    return 0;
}

/* The chain's residuals for all its parameters x: the distances of every sample to the
 * chained model and the regularisation. */
static int chain_residuals(void *user, const double *x, double *r)
{
    Fit *F = user;
    if (trace_params(F, x, NULL) != 0) return 1;
    hk_cf_distance_residuals(F->ws->chain, F->ws->target, F->n, r);
    hk_cf_penalty_residuals(F, x, F->out->piece_count * F->np, r + 3 * F->n);
    return 0;
}

/* All pieces refitted together, their joins fixed: each piece was fitted alone from the
 * end pose of its predecessor, whose small errors in the frame there its successors
 * could only bend to follow; moving them together lets the first pieces end where the
 * later ones need them (the p-helicoid's frame continuity of §3.4 is kept, the joins
 * stay chained). Kept only when the chain's coupling improves; then the output's
 * parameters, start, errors (whole and per piece) are the polished chain's. Chains of
 * more than POLISH_PARAMS parameters are left as they are. */
hk_Status hk_cf_polish_chain(Fit *F)
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
    const hk_LeastSquaresDef lo = hk_cf_least_squares_options(F, n);
    const int m = (int)(3 * F->n) + n;
    F->ws->ref.pieces = 0;
    hk_MinimizeResult r;
    if (hk_least_squares_minimize(n, m, x, scale, chain_residuals, F, &lo, F->ws->lsq, &r, NULL) != HK_OK) return HK_OK;
    /* The polished chain, traced once more (the minimiser's last trace may have been a
     * rejected step) with its poses. */
    hk_CurveStart starts[HK_CURVEFIT_MAX_PIECES];
    if (trace_params(F, x, starts) != 0) return HK_OK;
    double c, d;
    hk_frechet_both(F->ws->target, F->n, F->ws->chain, F->n, F->ws->row, &c, &d);
    if (!(c / (double)F->n < o->error)) return HK_OK;
    o->error = c / (double)F->n;
    o->frechet = d;
    o->start = starts[0];
    for (int k = 0; k < o->piece_count; k++) {
        const int a = o->first_sample[k], b = piece_end(F, k);
        memcpy(o->params[k], x + k * F->np, (size_t)F->np * sizeof(double));
        hk_frechet_both(F->ws->target + a, b - a + 1, F->ws->chain + a, b - a + 1, F->ws->row, &c, &d);
        o->piece_error[k] = c / (double)(b - a + 1);
        o->piece_frechet[k] = d;
        F->starts[k] = starts[k];
    }
    return HK_OK;
}
