/* Rosenbrock's rotating-coordinates direct search with Palmer's orthonormalisation. */
/*
 * The thesis's minimiser of the Super-Helix energy (Lansink 2010 §4.1.3.2 "Rosenbrock
 * Method" and §4.1.3.3 "Palmer Improvement"), after
 *   H. H. Rosenbrock, "An automatic method for finding the greatest or least value of
 *   a function", Computer J. 3 (1960) 175-184, and
 *   J. R. Palmer, Computer J. 12 (1969) 69-71 (orthogonalising Rosenbrock's search
 *   directions without Gram-Schmidt).
 * It is kept faithful so that the Newton solver can be compared with it; the only
 * departures are the guards that make termination certain (see "Termination" below).
 *
 * Stage: n orthonormal directions xi_i, steps e_i = initial_step, advances d_i = 0.
 * The trials cycle through the directions: x + e_i xi_i succeeds when f does not
 * increase (accept it, d_i += e_i, e_i *= alpha), else fails (e_i *= -beta). A stage
 * ends as soon as every direction has had a success and, after it, a failure. The
 * directions are then rotated (Palmer) so that xi_1 points along the stage's total
 * advance A_1 = sum d_i xi_i, and the next stage starts with fresh steps.
 *
 * Termination. The thesis argues that a failing direction eventually succeeds because
 * e_i shrinks until x + e_i xi_i == x, where f cannot differ. That holds for an
 * objective that is a function of x, and takes about a thousand trials when x is near
 * zero; it fails when f is NaN, or differs from itself at the same x, or has a kink
 * exactly at a zero coordinate (f = |x| at x = 0 never succeeds with a non-zero step).
 * Symmetrically a direction along which f keeps decreasing would grow its step for
 * ever. So, in addition to the thesis's rules:
 *  - a trial whose point is not finite, or whose f is NaN or infinite, is a failure
 *    (NaN compares false; +-inf would make the stage's decrease undefined). A point
 *    that is not finite is not passed to f at all;
 *  - a direction is retired for the rest of the stage (it counts as finished) when its
 *    step can no longer do anything: when a failed trial did not move x at all (f is
 *    not a function of x there), or the step has shrunk below DBL_MIN (no normal
 *    number is left to try), or it has overflowed;
 *  - alpha and beta must change the step by at least STEP_CHANGE_MIN per trial, so that
 *    a direction's run of failures before its first success, and its run of successes
 *    before the failure that follows, are each bounded: the step crosses at most the
 *    ~1420 e-folds between DBL_MIN and DBL_MAX, i.e. 1420 / ln(1/beta) or 1420 / ln(alpha)
 *    trials.
 * With these every stage ends after finitely many trials, even with no evaluation
 * limit; the stage limit then ends the search.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "hairkit/statics.h"
#include "optimize/optimize_internal.h"

/* alpha >= 1 + STEP_CHANGE_MIN and beta <= 1 - STEP_CHANGE_MIN. Rosenbrock's values (3 and
 * 0.5) are far from it; nearer to 1 a direction could need millions of trials. */
#define STEP_CHANGE_MIN 1e-3

hk_RosenbrockDef hk_default_rosenbrock_def(void)
{
    hk_RosenbrockDef o;
    o.max_stages = 20; /* the thesis's MaxIter */
    o.epsilon = 1e-4;  /* the thesis's Epsilon */
    o.initial_step = 0.1;
    o.alpha = 3.0; /* Rosenbrock 1960 */
    o.beta = 0.5;  /* Rosenbrock 1960 */
    o.max_evaluations = 10000000L;
    return o;
}

/*
 * Palmer's new directions, 0-based here: A_k = sum_{i >= k} d_i xi_i, and because the
 * old directions are orthonormal |A_k|^2 = sum_{i >= k} d_i^2 and A_{k-1} = d_{k-1}
 * xi_{k-1} + A_k with A_k orthogonal to xi_{k-1}. Palmer's formula
 *     xi'_k = (A_k |A_{k-1}|^2 - A_{k-1} |A_k|^2) / (|A_{k-1}| |A_k| sqrt(|A_{k-1}|^2 - |A_k|^2))
 * has numerator d_{k-1} (d_{k-1} A_k - |A_k|^2 xi_{k-1}) and sqrt(...) = |d_{k-1}|, so
 *     xi'_k = sgn(d_{k-1}) (d_{k-1} A_k - |A_k|^2 xi_{k-1}) / (|A_{k-1}| |A_k|)
 *           = cos_k A_k / |A_k| - sgn(d_{k-1}) sin_k xi_{k-1},
 * with cos_k = |d_{k-1}| / |A_{k-1}| and sin_k = |A_k| / |A_{k-1}|. This is exactly the
 * Gram-Schmidt vector B_k / |B_k| of Rosenbrock's procedure (unit, orthogonal to
 * A_0..A_{k-1}, positive along A_k), but it stays defined when d_{k-1} = 0, where
 * Gram-Schmidt divides 0 by 0: there cos_k = 0 and we take the limit d_{k-1} -> 0-, i.e.
 * xi'_k = +xi_{k-1}, so a direction that did not advance is carried on unchanged, one
 * place further down. When |A_k| = 0 (no advance from k on) xi_k..xi_{n-1} are already
 * orthogonal to the span of A_0..A_{k-1} and are kept.
 *
 * The formula is homogeneous of degree 0 in d, so A_k is accumulated scaled by c =
 * max_{i >= k} |d_i|: then |A_k| / c lies in [1, sqrt(n)] and neither tiny nor huge
 * advances lose precision to underflow or overflow. Cost O(n^2) (Gram-Schmidt: O(n^3)).
 * Row 0 of xi_new holds A_k / c while the rows below are computed; it is written last.
 */
void hk_rosenbrock_palmer_directions(int n, const double *xi, const double *d, double *xi_new)
{
    if (n < 1 || !xi || !d || !xi_new) return;
    const size_t sn = (size_t)n;
    for (int i = 0; i < n; i++)
        if (!isfinite(d[i])) {
            /* Only an objective unbounded below can overflow an advance; no direction
             * can be derived from it, so the old ones are kept. */
            memcpy(xi_new, xi, sn * sn * sizeof(double));
            return;
        }
    double *u = xi_new; /* A_k / c */
    memset(u, 0, sn * sizeof(double));
    double c = 0.0, ssq = 0.0; /* scale and |A_k / c|^2 */
    for (int k = n - 1; k >= 0; k--) {
        const double *xk = xi + (size_t)k * sn;
        const double ad = fabs(d[k]);
        if (ad > 0.0) {
            if (ad > c) {
                if (c > 0.0) {
                    const double r = c / ad;
                    ssq *= r * r;
                    for (size_t j = 0; j < sn; j++) u[j] *= r;
                }
                c = ad;
            }
            const double t = d[k] / c;
            ssq += t * t;
            for (size_t j = 0; j < sn; j++) u[j] += t * xk[j];
        }
        if (k == 0) break;
        double *out = xi_new + (size_t)k * sn;
        if (c == 0.0) {
            memcpy(out, xk, sn * sizeof(double));
            continue;
        }
        const double q = sqrt(ssq);           /* |A_k| / c >= 1 */
        const double tp = fabs(d[k - 1]) / c; /* may overflow to inf: harmless */
        double cosk, sink;                    /* see above, without overflow */
        if (tp >= q) {
            const double rho = q / tp;
            cosk = 1.0 / sqrt(1.0 + rho * rho);
            sink = rho * cosk;
        } else {
            const double rho = tp / q;
            sink = 1.0 / sqrt(1.0 + rho * rho);
            cosk = rho * sink;
        }
        const double a = cosk / q;                      /* times A_k / c: cos_k A_k / |A_k| */
        const double b = d[k - 1] > 0.0 ? -sink : sink; /* times xi_{k-1} */
        const double *xp = xi + (size_t)(k - 1) * sn;
        for (size_t j = 0; j < sn; j++) out[j] = a * u[j] + b * xp[j];
    }
    if (c > 0.0) {
        /* xi'_0 = A_0 / |A_0|: the direction of the stage's total advance. */
        const double inv = 1.0 / sqrt(ssq);
        for (size_t j = 0; j < sn; j++) u[j] *= inv;
    } else {
        memcpy(u, xi, sn * sizeof(double)); /* no advance at all: keep every direction */
    }
}

/* Per-direction progress within a stage. */
enum {
    DIR_FRESH = 0, /* no success yet */
    DIR_SUCCEEDED, /* a success, no failure since */
    DIR_FINISHED,  /* a failure after a success: the thesis's condition */
    DIR_RETIRED    /* the step can do nothing more this stage (see Termination) */
};

static hk_Status check_options(int n, const double *x, hk_ObjectiveFn f, const hk_RosenbrockDef *o, hk_Error *err)
{
    if (n < 1) return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: dimension must be >= 1, got %d", n);
    if (!x || !f) return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: %s is NULL", !x ? "x" : "the objective");
    if (o->max_stages < 1)
        return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: max_stages must be >= 1, got %d", o->max_stages);
    if (!(o->epsilon >= 0.0) || !isfinite(o->epsilon))
        return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: epsilon must be finite and >= 0, got %g", o->epsilon);
    if (!(o->initial_step > 0.0) || !isfinite(o->initial_step))
        return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: initial_step must be finite and > 0, got %g",
                            o->initial_step);
    if (!(o->alpha >= 1.0 + STEP_CHANGE_MIN) || !isfinite(o->alpha))
        return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: alpha must be finite and >= %g, got %g",
                            1.0 + STEP_CHANGE_MIN, o->alpha);
    if (!(o->beta > 0.0 && o->beta <= 1.0 - STEP_CHANGE_MIN))
        return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: beta must be in (0, %g], got %g", 1.0 - STEP_CHANGE_MIN,
                            o->beta);
    return HK_OK;
}

hk_Status hk_rosenbrock_minimize(int n, double *x, hk_ObjectiveFn f, void *user, const hk_RosenbrockDef *options,
                                 hk_MinimizeResult *result, hk_Error *err)
{
    hk_MinimizeResult res = {0.0, 0, 0, 0};
    if (result) *result = res;
    const hk_RosenbrockDef defaults = hk_default_rosenbrock_def();
    if (!options) options = &defaults;
    hk_Status status = check_options(n, x, f, options, err);
    if (status != HK_OK) return status;
    const hk_RosenbrockDef *o = options;
    const size_t sn = (size_t)n;

    /* Directions and their successors (n x n each), trial point, steps, advances. */
    double *block = hk_alloc_array(2 * sn * sn + 3 * sn, sizeof(double), err);
    if (!block) return HK_ERR_NOMEM;
    unsigned char *state = hk_alloc_array(sn, 1, err);
    if (!state) {
        hk_free(block);
        return HK_ERR_NOMEM;
    }
    double *xi = block, *xi_next = block + sn * sn;
    double *xt = xi_next + sn * sn, *step = xt + sn, *adv = step + sn;
    memset(xi, 0, sn * sn * sizeof(double));
    for (size_t i = 0; i < sn; i++) xi[i * sn + i] = 1.0; /* first stage: the coordinate axes */

    double fx = f(user, x);
    res.evaluations = 1;
    if (!isfinite(fx)) {
        status = hk_error_set(err, HK_ERR_NUMERIC,
                              "rosenbrock: the objective is not finite at the starting point "
                              "(f = %g)",
                              fx);
        goto done;
    }
    const long budget = o->max_evaluations; /* <= 0: no limit */

    while (res.iterations < o->max_stages) {
        const double f_stage = fx;
        for (size_t i = 0; i < sn; i++) {
            step[i] = o->initial_step; /* the thesis resets the steps at every stage */
            adv[i] = 0.0;
            state[i] = DIR_FRESH;
        }
        int finished = 0, out_of_budget = 0;
        for (size_t i = 0; finished < n; i = (i + 1 == sn) ? 0 : i + 1) {
            if (state[i] == DIR_RETIRED) continue;
            const double *dir = xi + i * sn;
            const double e = step[i];
            int moved = 0, finite = 1;
            for (size_t j = 0; j < sn; j++) {
                xt[j] = x[j] + e * dir[j];
                moved |= xt[j] != x[j];
                finite &= isfinite(xt[j]) != 0;
            }
            double ft = NAN;
            if (finite) {
                if (budget > 0 && res.evaluations >= budget) {
                    out_of_budget = 1;
                    break;
                }
                ft = f(user, xt);
                res.evaluations++;
            }
            if (isfinite(ft) && ft <= fx) {
                /* Success (ties included, so a step too small to change f succeeds and
                 * grows again, as Rosenbrock intends). */
                memcpy(x, xt, sn * sizeof(double));
                fx = ft;
                adv[i] += e;
                step[i] = e * o->alpha;
                if (state[i] == DIR_FRESH) state[i] = DIR_SUCCEEDED;
            } else {
                step[i] = -o->beta * e;
                int next = state[i] == DIR_SUCCEEDED ? DIR_FINISHED : state[i];
                const double s = fabs(step[i]);
                if ((finite && !moved) || s < DBL_MIN || !isfinite(s)) next = DIR_RETIRED;
                if (next != state[i]) {
                    if (state[i] != DIR_FINISHED) finished++;
                    state[i] = (unsigned char)next;
                }
            }
        }
        if (out_of_budget) break; /* the interrupted stage is not counted */
        res.iterations++;
        hk_rosenbrock_palmer_directions(n, xi, adv, xi_next);
        double *tmp = xi;
        xi = xi_next;
        xi_next = tmp;
        if (f_stage - fx <= o->epsilon * fabs(f_stage)) {
            res.converged = 1;
            break;
        }
    }
done:
    res.f = fx;
    if (result) *result = res;
    hk_free(block);
    hk_free(state);
    return status;
}
