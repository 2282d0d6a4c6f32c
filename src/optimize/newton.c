/* Newton's method with Levenberg-Marquardt regularisation and a backtracking line
 * search: the fast default minimiser of the statics (it uses the exact gradient and Hessian of
 * the strand energy, where the thesis's Rosenbrock search uses energies alone). */
#include "core/linalg.h"
#include "hairkit/statics.h"

#include <float.h>
#include <math.h>
#include <string.h>

hk_NewtonDef hk_default_newton_def(void)
{
    hk_NewtonDef o = {500, 1e-16, 0.0, 0.0, NULL};
    return o;
}

/* Damping is relative to the metric: mu = 1e-3 is a gentle nudge, mu >> 1 a short
 * gradient-like step. */
#define MU_START 1e-3
#define MU_LIMIT 1e30

hk_Status hk_newton_minimize(int n, double *x, hk_DerivFn f, void *user, const double *metric,
                             const hk_NewtonDef *options, hk_MinimizeResult *result, hk_Error *err)
{
    hk_MinimizeResult res = {0.0, 0, 0, 0};
    if (result) *result = res;
    const hk_NewtonDef defaults = hk_default_newton_def();
    if (!options) options = &defaults;
    if (n < 1 || !x || !f || options->max_iterations < 0 || !(options->tolerance >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "newton: invalid arguments (n = %d)", n);
    const size_t sn = (size_t)n;
    /* g, trial g, p, trial x: 4n; H, trial H, L: 3 n^2. One block per solve. */
    double *block = hk_alloc_array(4 * sn + 3 * sn * sn, sizeof(double), err);
    if (!block) return HK_ERR_NOMEM;
    double *g = block, *gt = g + sn, *p = gt + sn, *xt = p + sn;
    double *h = xt + sn, *ht = h + sn * sn, *l = ht + sn * sn;

    double fx = f(user, x, g, h);
    res.evaluations = 1;
    hk_Status status = HK_OK;
    if (!isfinite(fx)) {
        status = hk_error_set(err, HK_ERR_NUMERIC, "newton: objective is not finite at the start");
        goto done;
    }
    const double scale = options->energy_scale > 0.0 ? options->energy_scale : fmax(fabs(fx), DBL_MIN);
    double mu = 0.0;
    int last_full = 0; /* was the previous step a full Newton step? */
    for (int it = 0; it < options->max_iterations; it++) {
        /* Regularise only as much as needed to make H + mu D positive definite, so
         * that p is a descent direction. */
        while (!hk_cholesky_factor(n, h, mu, metric, l)) {
            mu = mu > 0.0 ? 10.0 * mu : MU_START;
            if (mu > MU_LIMIT) {
                status = hk_error_set(err, HK_ERR_NUMERIC, "newton: Hessian cannot be regularised");
                goto done;
            }
        }
        for (int i = 0; i < n; i++) p[i] = -g[i];
        hk_cholesky_solve(n, l, p);
        /* Step control: a Newton step far from the minimum can leap into another basin
         * (a strand flipping through wild twists); cap the largest move. */
        if (options->max_step > 0.0) {
            double worst = 0.0;
            for (int i = 0; i < n; i++) {
                double u = options->step_unit ? options->step_unit[i] : 1.0;
                worst = fmax(worst, fabs(p[i]) / u);
            }
            if (worst > options->max_step)
                for (int i = 0; i < n; i++) p[i] *= options->max_step / worst;
        }
        double gp = 0.0;
        for (int i = 0; i < n; i++) gp += g[i] * p[i];
        /* Newton decrement -g.p / 2: the predicted decrease of a full undamped step. */
        if (mu == 0.0 && -0.5 * gp <= options->tolerance * scale) {
            res.converged = 1;
            break;
        }
        /* Backtracking line search (Armijo, quadratic interpolation of f along p). */
        const double noise = 8.0 * DBL_EPSILON * fmax(fabs(fx), scale);
        double alpha = 1.0, ft = fx;
        int accepted = 0;
        for (int ls = 0; ls < 60; ls++) {
            for (int i = 0; i < n; i++) xt[i] = x[i] + alpha * p[i];
            /* Once full steps are being accepted they usually go on being accepted:
             * then evaluate their derivatives right away. */
            const int eager = ls == 0 && last_full;
            ft = f(user, xt, eager ? gt : NULL, eager ? ht : NULL);
            res.evaluations++;
            if (isfinite(ft) && ft <= fx + 1e-4 * alpha * gp) {
                accepted = 1;
                break;
            }
            if (-alpha * gp <= noise) break; /* the step's effect is below rounding */
            double next = isfinite(ft) ? -gp * alpha * alpha / (2.0 * (ft - fx - gp * alpha)) : 0.1 * alpha;
            alpha = fmin(fmax(next, 0.1 * alpha), 0.5 * alpha);
        }
        if (!accepted) {
            if (-0.5 * gp <= noise) { /* at machine precision: nothing left to gain */
                res.converged = 1;
                break;
            }
            mu = fmax(10.0 * mu, MU_START); /* the quadratic model is poor here: damp more */
            continue;
        }
        memcpy(x, xt, sn * sizeof(double));
        const int had_derivs = alpha == 1.0 && last_full;
        last_full = alpha == 1.0;
        if (had_derivs) {
            fx = ft;
            double *swap = g;
            g = gt, gt = swap;
            swap = h;
            h = ht, ht = swap;
        } else {
            fx = f(user, x, g, h);
            res.evaluations++;
        }
        res.iterations++;
        if (!isfinite(fx)) {
            status = hk_error_set(err, HK_ERR_NUMERIC, "newton: objective became non-finite");
            goto done;
        }
        /* A full step means the model was trusted rightly: relax the damping. */
        if (alpha == 1.0) mu = mu > 10.0 * MU_START ? 0.1 * mu : 0.0;
    }
done:
    res.f = fx;
    if (result) *result = res;
    hk_free(block);
    return status;
}
