/* Energy minimisers for Super-Helix statics (Bertails et al. 2006 §3, Lansink 2010 §4.1.3).
 *
 * Two methods find the rest shape of a strand under gravity and contacts:
 *  - the thesis's Rosenbrock direct search with Palmer's orthogonalisation, kept
 *    faithful for comparison (MaxIter stages, Epsilon relative decrease per stage);
 *  - the default Newton method with the analytic gradient and Hessian of the strand
 *    energy, Levenberg-Marquardt damping and a backtracking line search. */
#ifndef HAIRKIT_STATICS_H
#define HAIRKIT_STATICS_H

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/optimize.h"
#include "hairkit/rod.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- generic minimisers ------------------------------------------------------- */

/* hk_ObjectiveFn and hk_MinimizeResult: hairkit/optimize.h. */

typedef struct hk_RosenbrockDef {
    int max_stages;       /* MaxIter of the hairstyle file */
    double epsilon;       /* stop when a stage lowers f by <= epsilon * |f| */
    double initial_step;  /* trial step length at the start of every stage */
    double alpha;         /* step growth after a success (Rosenbrock 1960: 3) */
    double beta;          /* step shrink after a failure (Rosenbrock 1960: 0.5) */
    long max_evaluations; /* safety limit on objective evaluations (<= 0: none) */
} hk_RosenbrockDef;

HK_API hk_RosenbrockDef hk_default_rosenbrock_def(void);

/* Rosenbrock's rotating-coordinates direct search (Rosenbrock 1960) with Palmer's
 * (1969) orthonormalisation of the new directions, as described in thesis §4.1.3.2-3.
 * A trial succeeds when f(x + step * xi_i) <= f(x); a stage ends once every direction
 * has had a success followed by a failure; then the directions are rotated so that
 * xi_1 points along the stage's total advance. x (size n) is updated in place. */
HK_API hk_Status hk_rosenbrock_minimize(int n, double *x, hk_ObjectiveFn f, void *user, const hk_RosenbrockDef *options,
                                        hk_MinimizeResult *result, hk_Error *err);

/* Objective with derivatives: returns f(x); fills grad (n) and hess (n x n, row-major)
 * when they are not NULL. */
typedef double (*hk_DerivFn)(void *user, const double *x, double *grad, double *hess);

typedef struct hk_NewtonDef {
    int max_iterations;      /* Newton steps (accepted or not) */
    double tolerance;        /* stop when the Newton decrement g.H^-1.g / 2 <= tolerance * scale */
    double energy_scale;     /* `scale` above; <= 0 uses max(|f|, tiny) */
    double max_step;         /* > 0: no step moves a variable by more than max_step units */
    const double *step_unit; /* the unit of each variable for max_step (NULL: 1) */
} hk_NewtonDef;

HK_API hk_NewtonDef hk_default_newton_def(void);

/* Newton's method: steps (H + mu D) p = -g with D a positive diagonal metric (NULL:
 * the identity) and mu the smallest damping that makes H + mu D positive definite,
 * then a backtracking (Armijo) line search on f: robust on the indefinite Hessians of
 * strands far from rest, quadratically convergent near the minimum. x (size n) is
 * updated in place. */
HK_API hk_Status hk_newton_minimize(int n, double *x, hk_DerivFn f, void *user, const double *metric,
                                    const hk_NewtonDef *options, hk_MinimizeResult *result, hk_Error *err);

/* ---- strand statics --------------------------------------------------------------- */

typedef enum hk_SolverKind { HK_SOLVER_NEWTON = 0, HK_SOLVER_ROSENBROCK = 1 } hk_SolverKind;

typedef struct hk_StaticsDef {
    hk_SolverKind solver;
    hk_RosenbrockDef rosenbrock; /* for HK_SOLVER_ROSENBROCK */
    hk_NewtonDef newton;         /* for HK_SOLVER_NEWTON */
} hk_StaticsDef;

/* Newton by default; Rosenbrock settings from the thesis defaults (MaxIter 20,
 * Epsilon 1e-4). */
HK_API hk_StaticsDef hk_default_statics_def(void);

/* Rosenbrock settings of a strand (MaxIter, Epsilon) and its initial step. */
HK_API hk_RosenbrockDef hk_rosenbrock_def_for(const hk_StrandDef *def);

/* Name of a solver for messages ("newton", "rosenbrock"); parse back with
 * hk_solver_from_name (returns -1 for an unknown name). */
HK_API const char *hk_solver_name(hk_SolverKind kind);
HK_API int hk_solver_from_name(const char *name);

/* Finds the rest shape of the strand: minimises hk_strand_energy over sh->q starting
 * from the current sh->q. On success sh->q holds the minimiser. */
HK_API hk_Status hk_statics_solve(hk_SuperHelix *sh, const hk_StrandEnvDef *env, const hk_StaticsDef *options,
                                  hk_MinimizeResult *result, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_STATICS_H */
