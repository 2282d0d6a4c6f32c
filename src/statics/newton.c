/* Newton's method with Levenberg-Marquardt damping and a trust-region ratio test: the
 * fast default minimiser of the statics (it uses the exact gradient and Hessian of
 * the strand energy, where the thesis's Rosenbrock search uses energies alone). */
#include "hairkit/linalg.h"
#include "hairkit/statics.h"

#include <float.h>
#include <math.h>
#include <string.h>

hk_NewtonOptions hk_default_newton_options(void)
{
    hk_NewtonOptions o = {500, 1e-14, 0.0};
    return o;
}

/* Damping is relative to the metric: mu = 1e-3 is a gentle nudge, mu >> 1 a short
 * gradient-like step. */
#define MU_START 1e-3
#define MU_LIMIT 1e30

hk_Status hk_newton_minimize(int n, double *x, hk_DerivFn f, void *user, const double *metric,
                             const hk_NewtonOptions *options, hk_MinimizeResult *result,
                             hk_Error *err)
{
    hk_MinimizeResult res = {0.0, 0, 0, 0};
    if (result) *result = res;
    if (n < 1 || !x || !f || !options || options->max_iterations < 0 || !(options->tolerance >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "newton: invalid arguments (n = %d)", n);
    const size_t sn = (size_t)n;
    /* g, p, trial x: 3n; H, L: 2 n^2. One block, allocated once per solve. */
    double *block = hk_alloc_array(3 * sn + 2 * sn * sn, sizeof(double), err);
    if (!block) return HK_ERR_NOMEM;
    double *g = block, *p = g + sn, *xt = p + sn, *h = xt + sn, *l = h + sn * sn;

    double fx = f(x, g, h, user);
    res.evaluations = 1;
    hk_Status status = HK_OK;
    if (!isfinite(fx)) {
        status = hk_error_set(err, HK_ERR_NUMERIC, "newton: objective is not finite at the start");
        goto done;
    }
    const double scale = options->energy_scale > 0.0 ? options->energy_scale : fmax(fabs(fx), DBL_MIN);
    double mu = 0.0;
    for (int trial = 0; trial < options->max_iterations; trial++) {
        while (!hk_cholesky_factor(n, h, mu, metric, l)) {
            mu = mu > 0.0 ? 10.0 * mu : MU_START;
            if (mu > MU_LIMIT) {
                status = hk_error_set(err, HK_ERR_NUMERIC, "newton: Hessian cannot be regularised");
                goto done;
            }
        }
        for (int i = 0; i < n; i++) p[i] = -g[i];
        hk_cholesky_solve(n, l, p);
        double gp = 0.0, php = 0.0;
        for (int i = 0; i < n; i++) {
            gp += g[i] * p[i];
            double hp = 0.0;
            for (int j = 0; j < n; j++) hp += h[(size_t)i * sn + (size_t)j] * p[j];
            php += p[i] * hp;
        }
        /* Newton decrement: the model's predicted decrease with the undamped Hessian. */
        if (mu == 0.0 && -0.5 * gp <= options->tolerance * scale) {
            res.converged = 1;
            break;
        }
        const double predicted = -(gp + 0.5 * php); /* > 0 whenever H + mu D is SPD */
        for (int i = 0; i < n; i++) xt[i] = x[i] + p[i];
        const double ft = f(xt, NULL, NULL, user);
        res.evaluations++;
        /* Below the rounding level of f the ratio test is noise: accept a step that
         * does not measurably raise f and stop, we are at machine precision. */
        const double noise = 8.0 * DBL_EPSILON * fmax(fabs(fx), scale);
        if (predicted <= noise) {
            if (isfinite(ft) && ft <= fx + noise) {
                memcpy(x, xt, sn * sizeof(double));
                fx = ft;
            }
            res.converged = 1;
            break;
        }
        const double rho = isfinite(ft) ? (fx - ft) / predicted : -1.0;
        if (rho > 1e-4) {
            memcpy(x, xt, sn * sizeof(double));
            fx = f(x, g, h, user);
            res.evaluations++;
            res.iterations++;
            if (!isfinite(fx)) {
                status = hk_error_set(err, HK_ERR_NUMERIC, "newton: objective became non-finite");
                goto done;
            }
            if (rho > 0.75) mu = mu > MU_START ? 0.25 * mu : 0.0;
            else if (rho < 0.25) mu = fmax(2.0 * mu, MU_START);
        } else {
            mu = fmax(4.0 * mu, MU_START);
        }
    }
done:
    res.f = fx;
    if (result) *result = res;
    hk_free(block);
    return status;
}
