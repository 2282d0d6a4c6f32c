/* What the generic minimisers share: the objective function and the result of a run.
 * The solvers are Rosenbrock's direct search and Newton's method (hairkit/statics.h),
 * Nelder-Mead and Levenberg-Marquardt (hairkit/curvefit.h). */
#ifndef HAIRKIT_OPTIMIZE_H
#define HAIRKIT_OPTIMIZE_H

#ifdef __cplusplus
extern "C" {
#endif

/* Objective without derivatives: returns f(x) for x of the size given to the minimiser
 * (user: the pointer given to it, first as in every callback of hairkit). */
typedef double (*hk_ObjectiveFn)(void *user, const double *x);

/* The result of a minimiser's run. */
typedef struct hk_MinimizeResult {
    double f;         /* objective at the returned x (least squares: sum r_i^2 / 2) */
    int iterations;   /* Rosenbrock: stages; Newton: Newton steps; Nelder-Mead: simplex
                         moves; Levenberg-Marquardt: trial steps */
    long evaluations; /* objective evaluations (with derivatives or not; the residuals of
                         the Jacobian's differences included) */
    int converged;    /* 1 if the stopping test was met, 0 if a limit stopped it */
} hk_MinimizeResult;

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_OPTIMIZE_H */
