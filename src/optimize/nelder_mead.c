/* Nelder-Mead simplex minimiser: the paper's [NM65] choice for fitting helicoids (paper
 * Piuze et al. 2011 §5.2), "a gradient-free method ... that performs well with arbitrary seed points".
 *
 * J. A. Nelder and R. Mead, "A simplex method for function minimization", Computer J. 7
 * (1965) 308-313, with the standard coefficients (reflection 1, expansion 2, contraction
 * 0.5, shrink 0.5) and the precise acceptance rules of J. C. Lagarias, J. A. Reeds,
 * M. H. Wright and P. E. Wright, "Convergence properties of the Nelder-Mead simplex
 * method in low dimensions", SIAM J. Optim. 9 (1998) 112-147:
 *   reflect xr = c + (c - x_worst)            (c: centroid of all but the worst)
 *   f(best) <= fr < f(second worst)           accept xr
 *   fr < f(best)                              expand xe = c + 2 (c - x_worst); keep the
 *                                             better of xe and xr ("greedy minimisation")
 *   f(second worst) <= fr < f(worst)          outside contraction c + 0.5 (xr - c),
 *                                             accepted if no worse than xr
 *   fr >= f(worst)                            inside contraction c + 0.5 (x_worst - c),
 *                                             accepted if better than x_worst
 *   otherwise                                 shrink every vertex halfway to the best.
 * Ties: a new vertex ranks after the vertices of equal value (stable insertion sort),
 * so the run is deterministic.
 *
 * Robustness: NaN counts as +inf, and a trial point with a non-finite coordinate
 * (after expansions overflowed) is not evaluated and counts as +inf; every trial counts
 * towards the evaluation limit, which is therefore a hard bound on the work. No memory
 * is allocated: the simplex of at most 17 x 16 doubles lives on the stack. */
#include <math.h>
#include <string.h>

#include "hairkit/curvefit.h"

#define NMAX HK_NELDER_MEAD_MAX_PARAMS

hk_NelderMeadDef hk_default_nelder_mead_def(void)
{
    hk_NelderMeadDef o;
    o.max_evaluations = 2000;
    o.x_tolerance = 1e-8;
    o.f_tolerance = 1e-12;
    return o;
}

typedef struct Run {
    int n;
    hk_ObjectiveFn f;
    void *user;
    long evaluations;
    long max_evaluations;
} Run;

static int budget_left(const Run *r) { return r->evaluations < r->max_evaluations; }

static double evaluate(Run *r, const double *x)
{
    r->evaluations++;
    for (int j = 0; j < r->n; j++)
        if (!isfinite(x[j])) return INFINITY;
    const double v = r->f(r->user, x);
    return isnan(v) ? INFINITY : v;
}

/* x = c + t (y - c) */
static void along(int n, const double *c, const double *y, double t, double *x)
{
    for (int j = 0; j < n; j++) x[j] = c[j] + t * (y[j] - c[j]);
}

/* Stable insertion sort of the vertex indices by value. */
static void sort_order(int m, const double *fv, int *order)
{
    for (int i = 1; i < m; i++) {
        const int k = order[i];
        int j = i - 1;
        while (j >= 0 && fv[k] < fv[order[j]]) {
            order[j + 1] = order[j];
            j--;
        }
        order[j + 1] = k;
    }
}

static hk_Status check_args(int n, const double *x, const double *scale, hk_ObjectiveFn f, const hk_NelderMeadDef *o,
                            hk_Error *err)
{
    if (n < 0 || n > NMAX)
        return hk_error_set(err, HK_ERR_INVALID, "nelder-mead: %d parameters, expected 0..%d", n, NMAX);
    if (!x || !f || !o || (n > 0 && !scale)) return hk_error_set(err, HK_ERR_INVALID, "nelder-mead: NULL argument");
    for (int j = 0; j < n; j++) {
        if (!isfinite(x[j])) return hk_error_set(err, HK_ERR_INVALID, "nelder-mead: start x[%d] is not finite", j);
        if (!isfinite(scale[j]) || scale[j] == 0.0)
            return hk_error_set(err, HK_ERR_INVALID, "nelder-mead: scale[%d] must be finite and non-zero, got %g", j,
                                scale[j]);
    }
    if (o->max_evaluations < (long)n + 1)
        return hk_error_set(err, HK_ERR_INVALID, "nelder-mead: max_evaluations must be >= n + 1 = %d, got %ld", n + 1,
                            o->max_evaluations);
    if (!(o->x_tolerance >= 0.0) || !(o->f_tolerance >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "nelder-mead: tolerances must be >= 0 (got %g and %g)", o->x_tolerance,
                            o->f_tolerance);
    return HK_OK;
}

hk_Status hk_nelder_mead_minimize(int n, double *x, const double *scale, hk_ObjectiveFn f, void *user,
                                  const hk_NelderMeadDef *options, hk_MinimizeResult *result, hk_Error *err)
{
    const hk_NelderMeadDef defaults = hk_default_nelder_mead_def();
    if (!options) options = &defaults;
    const hk_Status st = check_args(n, x, scale, f, options, err);
    if (st != HK_OK) return st;
    Run run = {n, f, user, 0, options->max_evaluations};
    double v[NMAX + 1][NMAX];
    double fv[NMAX + 1];
    int order[NMAX + 1];
    double c[NMAX], xr[NMAX], xt[NMAX];
    const int m = n + 1;

    for (int i = 0; i < m; i++) {
        memcpy(v[i], x, (size_t)n * sizeof(double));
        if (i > 0) v[i][i - 1] += scale[i - 1];
        fv[i] = evaluate(&run, v[i]);
        order[i] = i;
    }
    int iterations = 0, converged = 0;
    for (;;) {
        sort_order(m, fv, order);
        const int best = order[0], worst = order[n];
        double size = 0.0;
        for (int i = 1; i < m; i++)
            for (int j = 0; j < n; j++) {
                const double d = fabs(v[order[i]][j] - v[best][j]) / fabs(scale[j]);
                size = d > size ? d : size;
            }
        /* NaN spread (inf - inf, all vertices undefined) fails the test on purpose. */
        if (size <= options->x_tolerance && fv[worst] - fv[best] <= options->f_tolerance) {
            converged = 1;
            break;
        }
        if (n == 0 || !budget_left(&run)) break;
        iterations++;

        memset(c, 0, sizeof c);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) c[j] += v[order[i]][j];
        for (int j = 0; j < n; j++) c[j] /= (double)n;

        along(n, c, v[worst], -1.0, xr);
        const double fr = evaluate(&run, xr);
        const double f_second = fv[order[n - 1]];
        if (fr < fv[best]) {
            if (budget_left(&run)) {
                along(n, c, v[worst], -2.0, xt);
                const double fe = evaluate(&run, xt);
                if (fe < fr) {
                    memcpy(v[worst], xt, (size_t)n * sizeof(double));
                    fv[worst] = fe;
                    continue;
                }
            }
            memcpy(v[worst], xr, (size_t)n * sizeof(double));
            fv[worst] = fr;
            continue;
        }
        if (fr < f_second) {
            memcpy(v[worst], xr, (size_t)n * sizeof(double));
            fv[worst] = fr;
            continue;
        }
        if (!budget_left(&run)) break;
        if (fr < fv[worst]) {
            along(n, c, xr, 0.5, xt);
            const double fc = evaluate(&run, xt);
            if (fc <= fr) {
                memcpy(v[worst], xt, (size_t)n * sizeof(double));
                fv[worst] = fc;
                continue;
            }
        } else {
            along(n, c, v[worst], 0.5, xt);
            const double fc = evaluate(&run, xt);
            if (fc < fv[worst]) {
                memcpy(v[worst], xt, (size_t)n * sizeof(double));
                fv[worst] = fc;
                continue;
            }
        }
        /* Shrink towards the best vertex, one vertex at a time so that a simplex cut
         * short by the evaluation limit still has the right value at every vertex. */
        for (int i = 1; i < m && budget_left(&run); i++) {
            const int k = order[i];
            along(n, v[best], v[k], 0.5, v[k]);
            fv[k] = evaluate(&run, v[k]);
        }
    }
    const int best = order[0];
    if (result) {
        result->f = fv[best];
        result->iterations = iterations;
        result->evaluations = run.evaluations;
        result->converged = converged;
    }
    if (!(fv[best] < INFINITY))
        return hk_error_set(err, HK_ERR_NUMERIC, "nelder-mead: the objective was NaN or +inf at all %ld points tried",
                            run.evaluations);
    memcpy(x, v[best], (size_t)n * sizeof(double));
    return HK_OK;
}
