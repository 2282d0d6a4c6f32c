/* Rosenbrock's rotating-coordinates direct search (Rosenbrock 1960) with Palmer's
 * orthonormalisation (Palmer 1969), as the thesis minimises the Super-Helix energy
 * (thesis 004 §4.1.3.2-4.1.3.3). Kept faithful for comparison with the Newton solver. */
#include <math.h>
#include <string.h>

#include "hairkit/statics.h"

hk_RosenbrockOptions hk_default_rosenbrock_options(void)
{
    hk_RosenbrockOptions o = {20, 1e-4, 0.1, 3.0, 0.5, 10000000};
    return o;
}

void hk_rosenbrock_palmer_directions(int n, const double *xi, const double *d, double *xi_new)
{
    const size_t sn = (size_t)n;
    /* |A_k|^2 = sum_{i >= k} d_i^2 because the old directions are orthonormal; A_k is
     * accumulated from the tail. The new xi_k for k >= 2 is
     *   (d_{k-1} A_k - |A_k|^2 xi_{k-1}) / (|A_k| |A_{k-1}|),
     * Palmer's formula with the common factor d_{k-1} cancelled: it is orthogonal to
     * A_1..A_{k-1}, has unit norm, and stays defined when d_{k-1} = 0. */
    double a2_next = 0.0; /* |A_{k+1}|^2 */
    for (int k = n - 1; k >= 0; k--) {
        const double a2 = a2_next + d[k] * d[k]; /* |A_k|^2 */
        double *out = xi_new + (size_t)k * sn;
        if (k == 0) {
            if (a2 > 0.0) {
                /* A_1 = sum d_i xi_i, normalised: the direction of greatest advance. */
                for (size_t j = 0; j < sn; j++) {
                    double s = 0.0;
                    for (int i = 0; i < n; i++) s += d[i] * xi[(size_t)i * sn + j];
                    out[j] = s / sqrt(a2);
                }
            } else {
                memcpy(out, xi, sn * sizeof(double));
            }
        } else if (a2 > 0.0) {
            /* k here is 0-based: new direction k uses A_k (tail from k) and xi_{k-1}. */
            const double a2_prev = a2 + d[k - 1] * d[k - 1];
            const double scale = 1.0 / (sqrt(a2) * sqrt(a2_prev));
            for (size_t j = 0; j < sn; j++) {
                double ak = 0.0;
                for (int i = k; i < n; i++) ak += d[i] * xi[(size_t)i * sn + j];
                out[j] = (d[k - 1] * ak - a2 * xi[(size_t)(k - 1) * sn + j]) * scale;
            }
        } else {
            /* No advance along xi_k..xi_n: they stay orthogonal to the new xi_1..xi_{k-1}. */
            memcpy(out, xi + (size_t)k * sn, sn * sizeof(double));
        }
        a2_next = a2;
    }
}

hk_Status hk_rosenbrock_minimize(int n, double *x, hk_ObjectiveFn f, void *user,
                                 const hk_RosenbrockOptions *o, hk_MinimizeResult *result,
                                 hk_Error *err)
{
    hk_MinimizeResult res = {0.0, 0, 0, 0};
    if (result) *result = res;
    if (n < 1 || !x || !f || !o || o->max_stages < 0 || !(o->epsilon >= 0.0) ||
        !(o->initial_step > 0.0) || !isfinite(o->initial_step) || !(o->alpha > 1.0) ||
        !(o->beta > 0.0 && o->beta < 1.0))
        return hk_error_set(err, HK_ERR_INVALID, "rosenbrock: invalid arguments (n = %d)", n);
    const size_t sn = (size_t)n;
    /* directions, new directions: n^2 each; trial point, steps, advances: n each; state. */
    double *block = hk_alloc_array(2 * sn * sn + 3 * sn, sizeof(double), err);
    unsigned char *state = hk_alloc_array(sn, 1, err);
    if (!block || !state) {
        hk_free(block);
        hk_free(state);
        return HK_ERR_NOMEM;
    }
    double *xi = block, *xi_new = xi + sn * sn, *xt = xi_new + sn * sn, *step = xt + sn, *adv = step + sn;
    memset(xi, 0, sn * sn * sizeof(double));
    for (int i = 0; i < n; i++) xi[(size_t)i * sn + (size_t)i] = 1.0;

    hk_Status status = HK_OK;
    double fx = f(x, user);
    res.evaluations = 1;
    if (!isfinite(fx)) {
        status = hk_error_set(err, HK_ERR_NUMERIC, "rosenbrock: objective is not finite at the start");
        goto done;
    }
    const long max_eval = o->max_evaluations > 0 ? o->max_evaluations : -1;
    while (res.iterations < o->max_stages) {
        const double f_stage = fx;
        for (int i = 0; i < n; i++) {
            step[i] = o->initial_step; /* the thesis resets the step lengths every stage */
            adv[i] = 0.0;
            state[i] = 0; /* 0: no success yet, 1: success seen, 2: failure after success */
        }
        int done_dirs = 0, out_of_budget = 0;
        while (done_dirs < n && !out_of_budget) {
            for (int i = 0; i < n && done_dirs < n; i++) {
                if (max_eval > 0 && res.evaluations >= max_eval) {
                    out_of_budget = 1;
                    break;
                }
                const double *dir = xi + (size_t)i * sn;
                for (size_t j = 0; j < sn; j++) xt[j] = x[j] + step[i] * dir[j];
                const double ft = f(xt, user);
                res.evaluations++;
                if (ft <= fx) { /* NaN compares false: a failure */
                    memcpy(x, xt, sn * sizeof(double));
                    fx = ft;
                    adv[i] += step[i];
                    step[i] *= o->alpha;
                    if (state[i] == 0) state[i] = 1;
                } else {
                    step[i] *= -o->beta;
                    if (state[i] == 1) {
                        state[i] = 2;
                        done_dirs++;
                    }
                }
            }
        }
        if (out_of_budget) break;
        res.iterations++;
        hk_rosenbrock_palmer_directions(n, xi, adv, xi_new);
        memcpy(xi, xi_new, sn * sn * sizeof(double));
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
