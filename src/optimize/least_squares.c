/* Levenberg-Marquardt for small nonlinear least-squares problems: the fast fitter of
 * helicoids (docs/helicoid-fitting.md). the paper (Piuze et al. 2011 §5.2) minimises the Fréchet
 * coupling with Nelder-Mead, about 5 fits per second; a curve traced at the target's own
 * arc-length spacing can instead be matched point for point, and the sum of squared
 * distances is smooth in the parameters, so a Gauss-Newton method converges in a few
 * iterations of (n + 1) traces where the simplex needs hundreds of traces.
 *
 * K. Levenberg (1944), D. Marquardt (1963), with Marquardt's diagonal scaling and the
 * damping update of H. B. Nielsen, "Damping parameter in Marquardt's method", IMM-REP
 * 1999-05 (also K. Madsen, H. B. Nielsen, O. Tingleff, "Methods for non-linear least
 * squares problems", 2004, Algorithm 3.16):
 *   (A + mu D) h = -g,  A = J^T J, g = J^T r, D = diag(A) (floored)
 *   gain ratio rho = (F(x) - F(x + h)) / (L(0) - L(h)),  L(0) - L(h) = h^T (mu D h - g) / 2
 *   rho > 0: accept, mu *= max(1/3, 1 - (2 rho - 1)^3), nu = 2
 *   else:    mu *= nu, nu *= 2.
 * The Jacobian is the caller's when it has one (a curve model differentiated along its
 * trace, helicoid_fit.c), else taken by forward differences.
 * Deterministic; allocates nothing (the caller passes the work memory). */
#include <math.h>
#include <string.h>

#include "hairkit/curvefit.h"
#include "core/linalg.h"

#define NMAX HK_LEAST_SQUARES_MAX_PARAMS

hk_LeastSquaresDef hk_default_least_squares_def(void)
{
    hk_LeastSquaresDef o;
    o.max_evaluations = 400;
    o.x_tolerance = 1e-10;
    o.f_tolerance = 1e-12;
    o.g_tolerance = 1e-14;
    o.gain_tolerance = 0.0;
    return o;
}

typedef struct Run {
    int n, m;
    hk_ResidualFn f;
    hk_JacobianFn jac;
    void *user;
    long evaluations, max_evaluations;
} Run;

/* r = f(x); 0 when the residuals exist and are all finite. Counts the evaluation. */
static int residuals(Run *run, const double *x, double *r)
{
    run->evaluations++;
    for (int j = 0; j < run->n; j++)
        if (!isfinite(x[j])) return 1;
    if (run->f(run->user, x, r) != 0) return 1;
    for (int i = 0; i < run->m; i++)
        if (!isfinite(r[i])) return 1;
    return 0;
}

static double half_norm2(const double *r, int m) { return 0.5 * hk_dot(r, r, m); }

/* Forward-difference Jacobian, column-major (column j at jac + j m). The step is
 * sqrt(eps) relative to the parameter's size (or its scale near zero); a step that makes
 * the model fail is tried backwards. 0 on success. */
static int jacobian(Run *run, const double *x, const double *r, const double *scale, double *jac, double *trial)
{
    if (run->jac) {
        run->evaluations++;
        int ok = run->jac(run->user, x, jac) == 0;
        for (size_t i = 0; ok && i < (size_t)run->n * (size_t)run->m; i++) ok = isfinite(jac[i]);
        if (ok) return 0;
    }
    double xt[NMAX];
    memcpy(xt, x, (size_t)run->n * sizeof(double));
    for (int j = 0; j < run->n; j++) {
        const double size = fabs(x[j]) > fabs(scale[j]) ? fabs(x[j]) : fabs(scale[j]);
        double step = 1.4901161193847656e-08 * size; /* sqrt(2^-52) */
        int ok = 0;
        for (int side = 0; side < 2 && !ok; side++, step = -step) {
            xt[j] = x[j] + step;
            const double h = xt[j] - x[j]; /* the step actually taken, after rounding */
            if (h != 0.0 && residuals(run, xt, trial) == 0) {
                double *col = jac + (size_t)j * (size_t)run->m;
                for (int i = 0; i < run->m; i++) col[i] = (trial[i] - r[i]) / h;
                ok = 1;
            }
        }
        xt[j] = x[j];
        if (!ok) return 1;
    }
    return 0;
}

/* a = J^T J (n x n, row-major), g = J^T r, with fixed-order dot products (two at a time
 * where they share a column: hk_dot2, the same bits as hk_dot). */
static void normal_equations(const Run *run, const double *jac, const double *r, double *a, double *g)
{
    const int n = run->n, m = run->m;
    for (int j = 0; j < n; j++) {
        const double *cj = jac + (size_t)j * (size_t)m;
        int k = 0;
        for (; k + 1 <= j; k += 2) {
            hk_dot2(cj, jac + (size_t)k * (size_t)m, jac + (size_t)(k + 1) * (size_t)m, m, &a[j * n + k],
                    &a[j * n + k + 1]);
            a[k * n + j] = a[j * n + k];
            a[(k + 1) * n + j] = a[j * n + k + 1];
        }
        if (k == j) {
            hk_dot2(cj, cj, r, m, &a[j * n + j], &g[j]);
        } else {
            g[j] = hk_dot(cj, r, m);
        }
    }
}

/* A rejected step (or an unsolvable system): damp more, mu *= nu, nu *= 2 (Nielsen).
 * 0 when the damping has grown past any use (no step would ever be taken). */
static int more_damping(double *mu, double *nu)
{
    *mu *= *nu;
    *nu *= 2.0;
    return *mu < 1e300;
}

static hk_Status check_args(int n, int m, const double *x, const double *scale, hk_ResidualFn f, double *work,
                            const hk_LeastSquaresDef *o, hk_Error *err)
{
    if (n < 1 || n > NMAX)
        return hk_error_set(err, HK_ERR_INVALID, "least squares: %d parameters, expected 1..%d", n, NMAX);
    if (m < n || m > HK_LEAST_SQUARES_MAX_RESIDUALS)
        return hk_error_set(err, HK_ERR_INVALID, "least squares: %d residuals for %d parameters, expected %d..%d", m, n,
                            n, HK_LEAST_SQUARES_MAX_RESIDUALS);
    if (!x || !scale || !f || !work) return hk_error_set(err, HK_ERR_INVALID, "least squares: NULL argument");
    for (int j = 0; j < n; j++) {
        if (!isfinite(x[j])) return hk_error_set(err, HK_ERR_INVALID, "least squares: x[%d] is not finite", j);
        if (!isfinite(scale[j]) || scale[j] == 0.0)
            return hk_error_set(err, HK_ERR_INVALID, "least squares: scale[%d] must be finite and non-zero", j);
    }
    if (o && (o->max_evaluations < n + 2 || !(o->x_tolerance >= 0.0) || !(o->f_tolerance >= 0.0) ||
              !(o->g_tolerance >= 0.0) || !(o->gain_tolerance >= 0.0)))
        return hk_error_set(err, HK_ERR_INVALID,
                            "least squares: options need max_evaluations >= n + 2 and tolerances >= 0");
    return HK_OK;
}

hk_Status hk_least_squares_minimize(int n, int m, double *x, const double *scale, hk_ResidualFn f, void *user,
                                    const hk_LeastSquaresDef *options, double *work, hk_MinimizeResult *result,
                                    hk_Error *err)
{
    return hk_least_squares_minimize_jac(n, m, x, scale, f, NULL, user, options, work, result, err);
}

hk_Status hk_least_squares_minimize_jac(int n, int m, double *x, const double *scale, hk_ResidualFn f,
                                        hk_JacobianFn jac_fn, void *user, const hk_LeastSquaresDef *options,
                                        double *work, hk_MinimizeResult *result, hk_Error *err)
{
    const hk_LeastSquaresDef o = options ? *options : hk_default_least_squares_def();
    hk_Status st = check_args(n, m, x, scale, f, work, options, err);
    if (st != HK_OK) return st;
    Run run = {n, m, f, jac_fn, user, 0, o.max_evaluations};
    double *r = work, *r_new = r + m, *trial = r_new + m, *jac = trial + m;
    double a[NMAX * NMAX], l[NMAX * NMAX], g[NMAX], d[NMAX], h[NMAX], x_new[NMAX];
    hk_MinimizeResult res = {0.0, 0, 0, 0};

    if (residuals(&run, x, r) != 0) {
        if (result) res.evaluations = run.evaluations, res.f = INFINITY, *result = res;
        return hk_error_set(err, HK_ERR_NUMERIC, "least squares: the residuals are not defined at the start");
    }
    double cost = half_norm2(r, m), mu = 1e-3, nu = 2.0;
    int fresh = 0;  /* 1 when a, g hold the normal equations at x */
    int stalls = 0; /* accepted steps in a row that gained nearly nothing */
    /* Room for a Jacobian and a trial step. */
    const long per_step = jac_fn ? 2 : n + 1;
    while (run.evaluations + per_step <= run.max_evaluations) {
        if (!fresh) {
            if (jacobian(&run, x, r, scale, jac, trial) != 0) break;
            normal_equations(&run, jac, r, a, g);
            fresh = 1;
        }
        double gmax = 0.0, amax = 0.0;
        for (int j = 0; j < n; j++) {
            gmax = fmax(gmax, fabs(g[j]) * fabs(scale[j]));
            amax = fmax(amax, a[j * n + j]);
        }
        /* Stationary: the gradient is at rounding level relative to the cost. */
        if (gmax <= o.g_tolerance * fmax(cost, 1e-300) || cost == 0.0 || !(amax > 0.0)) {
            res.converged = 1;
            break;
        }
        /* Marquardt's scaling, floored so that a parameter the residuals do not see
         * (a zero column) still gets a damped, finite step. */
        for (int j = 0; j < n; j++) d[j] = fmax(a[j * n + j], 1e-12 * amax);
        if (!hk_cholesky_factor(n, a, mu, d, l)) {
            if (!more_damping(&mu, &nu)) break;
            continue;
        }
        for (int j = 0; j < n; j++) h[j] = -g[j];
        hk_cholesky_solve(n, l, h);
        int small = 1;
        double predicted = 0.0;
        for (int j = 0; j < n; j++) {
            if (fabs(h[j]) > o.x_tolerance * fabs(scale[j])) small = 0;
            x_new[j] = x[j] + h[j];
            predicted += 0.5 * h[j] * (mu * d[j] * h[j] - g[j]);
        }
        /* A step predicted to gain next to nothing: from a start already at the minimum
         * (a refit from a nearby model's fit) its trial is as often rejected at rounding
         * level, and each rejection costs an evaluation and a stronger damping. */
        if (small || predicted <= o.gain_tolerance * cost) {
            res.converged = 1;
            break;
        }
        const int failed = residuals(&run, x_new, r_new) != 0;
        const double cost_new = failed ? INFINITY : half_norm2(r_new, m);
        const double rho = predicted > 0.0 ? (cost - cost_new) / predicted : -1.0;
        res.iterations++;
        if (!(rho > 0.0)) {
            if (!more_damping(&mu, &nu)) break;
            continue;
        }
        const double gained = cost - cost_new;
        memcpy(x, x_new, (size_t)n * sizeof(double));
        memcpy(r, r_new, (size_t)m * sizeof(double));
        cost = cost_new;
        fresh = 0;
        const double t = 2.0 * rho - 1.0;
        mu *= fmax(1.0 / 3.0, 1.0 - t * t * t);
        nu = 2.0;
        /* Two accepted steps in a row that each gained a negligible fraction: the cost
         * has levelled off (one such step can be a heavily damped one far from it). */
        stalls = gained <= o.f_tolerance * cost ? stalls + 1 : 0;
        if (stalls >= 2) {
            res.converged = 1;
            break;
        }
    }
    res.f = cost;
    res.evaluations = run.evaluations;
    if (result) *result = res;
    return HK_OK;
}
