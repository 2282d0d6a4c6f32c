/* Super-Helix dynamics (paper 000 §3.3-3.4 and §4.1-4.2; docs/dynamics.md).
 *
 * The generalized coordinates q (twist and curvatures per element, hairkit/rod.h) obey
 * Lagrange's equations (paper 000 eq. 4-6)
 *     M(q) q'' + K (q - q_rest) = A(q, q', t) + int J^T F ds,
 * with the kinetic energy of the centreline and the rotary inertia of the section, the
 * elastic energy K, the internal friction gamma (eq. 5d), the air drag nu (eq. 5a),
 * gravity, the inertial forces of a moving head and point forces (body contacts with
 * anisotropic friction, hair-hair contacts).
 *
 * Time stepping is TR-BDF2 (Bank et al. 1985; Hosea and Shampine 1996): each step is a
 * trapezoidal stage to t + g dt, g = 2 - sqrt 2, then a second-order backward
 * difference stage to t + dt, both implicit in every force of the equations (the
 * velocity products, the mass matrix's change, the geometric stiffness), solved by
 * Newton's iteration with the matrix
 *     M + ch D + ch^2 K,   ch = (1 - 1/sqrt 2) dt  (the same for both stages),
 * where D is the damping (internal friction, air drag, contact friction) and K the
 * stiffness: either the exact Hessian of the potential with its geometric part made
 * positive semi-definite (dense Cholesky of the 3N x 3N matrix), or its
 * elastic and Gauss-Newton contact parts only, which a recursive O(N) elimination along
 * the strand solves (an articulated chain where each element's own mass moves with its
 * coordinates); with the same stiffness the dense and O(N) solvers agree to rounding.
 * The matrix only steers Newton's iteration: the converged step is the same for both.
 * Second order, L-stable: the stiff modes (the twist of a thin section, contacts) are
 * damped in a step, the motion of the hair (a few Hz) loses about 1 % of its amplitude
 * per period at dt = 1/30 s (docs/dynamics.md). */
#ifndef HAIRKIT_DYNAMICS_H
#define HAIRKIT_DYNAMICS_H

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/motion.h"
#include "hairkit/rod.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hk_DynamicsSolver {
    HK_DYNAMICS_LINEAR = 0, /* O(N) recursive elimination (default) */
    HK_DYNAMICS_DENSE = 1   /* assembled M and Cholesky, O(N^2) + O(N^3): the reference */
} hk_DynamicsSolver;

typedef enum hk_DynamicsStiffness {
    /* Implicit in the exact Hessian of the potential (elastic, gravity and the body's
     * penalty, thesis §4.1.2), of which the geometric part (all but the elastic
     * diagonal) is projected on its positive semi-definite part; dense solver only.
     * Stable on hair pressed into the collision envelopes. (default) */
    HK_STIFFNESS_FULL = 0,
    /* Implicit in the elastic stiffness and the Gauss-Newton part of the contacts (the
     * terms the O(N) recursion can carry); gravity's and the contacts' geometric
     * stiffness explicit, as in paper 000 §3.4. */
    HK_STIFFNESS_GAUSS_NEWTON = 1
} hk_DynamicsStiffness;

typedef enum hk_DynamicsIntegrator {
    /* In hk_SimRunDef only: the integrator the hair simulation chooses
     * (hk_hair_sim_def_for'); hk_DynamicsDef refuses it */
    HK_INTEGRATOR_AUTO = -1,
    /* TR-BDF2 with Newton's iteration on every stage: second order, L-stable, every
     * force implicit, the energy guard on a still head; stable for long hair at the
     * paper's step (default) */
    HK_INTEGRATOR_TRBDF2 = 0,
    /* Linearly implicit Euler (paper 000 §3.4): one linear solve per step, the
     * velocity products and the negative geometric stiffness explicit. About 7 times
     * cheaper on a full head, first order, numerically damped, and not stable for long
     * strands at dt = 1/30 s (docs/dynamics.md) */
    HK_INTEGRATOR_LINEAR_EULER = 1
} hk_DynamicsIntegrator;

typedef struct hk_DynamicsDef {
    double internal_friction; /* gamma (kg m^3/s), paper 000 eq. 5d: visco-elastic
                                 dissipation of the curvatures, paper: 5e-11 .. 5e-10 */
    double air_drag;          /* nu (kg/(m s)), paper 000 eq. 5a: viscous drag of the air
                                 at rest, paper: 5e-6 (disciplined) .. 5e-5 (fuzzy hair) */
    double friction_with;     /* body friction coefficient for the hair sliding with its
                                 scales (root first relative to the body) */
    double friction_against;  /* ... against them (tip first); paper 000 §4.2 blends the
                                 two with the cosine of the sliding angle */
    double friction_velocity; /* sliding speed (m/s) below which friction is viscous,
                                 proportional to the speed (paper 000 §4.2); Coulomb above */
    int quadrature;           /* Gauss points per element; 0 chooses from the curvature */
    double max_turn;          /* hk_strand_dynamics_advance: largest turn of an element's
                                 frame in one step (rad) before the step is split */
    double max_travel;        /* ... or moves a node by more than this (m) relative to
                                 the head: contacts are found at the start of a step */
    double max_entry;         /* ... or, with the linearly implicit Euler step (whose
                                 contacts are those of the step's start), lets a
                                 collision sample that felt no body shape at the start
                                 end more than this (m) inside one */
    int max_depth;            /* ... splits at most this deep (dt / 2^max_depth) */
    hk_DynamicsSolver solver;
    hk_DynamicsStiffness stiffness; /* HK_STIFFNESS_FULL needs HK_DYNAMICS_DENSE */
    int hessian_interval;           /* HK_STIFFNESS_FULL: the Hessian and its positive part are
                                       refreshed every this many evaluations (default 4), the
                                       gradient every time */
    double newton_tolerance;        /* a stage has converged when Newton's last correction
                                       turns no element's frame by more than this (rad) */
    int newton_iterations;          /* most Newton iterations of a stage before the step
                                       counts as failed (and is split by advance) */
    hk_DynamicsIntegrator integrator;
} hk_DynamicsDef;

/* What the steps of a strand have cost since its creation. */
typedef struct hk_DynamicsStats {
    long steps;        /* steps taken (TR-BDF2, two stages each) */
    long iterations;   /* Newton iterations (force evaluations and solves) */
    long splits;       /* steps split in two by hk_strand_dynamics_advance */
    long failures;     /* steps that did not converge (then split) */
    long dense_stages; /* stages the O(N) solver's matrix did not converge, solved again
                          with the dense matrix and the potential's Hessian */
    long projections;  /* steps on a still head whose energy excess was taken from the
                          kinetic energy (the energy guard, docs/dynamics.md) */
} hk_DynamicsStats;

/* Paper-range defaults: gamma 1e-10, nu 1e-5, friction 0.2 / 0.4, 5 cm/s, auto
 * quadrature, O(N) solver with the Gauss-Newton stiffness. A hairstyle file's are these
 * with its InternalFriction, AirDrag and BodyFriction (hk_Hairstyle.dynamics). */
HK_API hk_DynamicsDef hk_default_dynamics_def(void);

/* A point force on a strand at arc length s, with its linearisation for the implicit
 * step (both matrices symmetric positive semi-definite). */
typedef struct hk_PointForce {
    double s;          /* arc length on the strand where the force acts */
    hk_Vec3 force;     /* N */
    hk_Mat3 stiffness; /* -dF/dx of this point */
    hk_Mat3 damping;   /* -dF/dv of this point */
} hk_PointForce;

typedef struct hk_StrandDynamics hk_StrandDynamics;

/* Dynamics of the strand sh (borrowed: it must outlive the object; its q is the
 * position state and is updated by every step). The strand's root and root frame at
 * creation are taken as head-space: every step places them with the head's motion.
 * body (may be NULL) holds the collision shapes, also in head space; it is copied. The
 * velocity starts at zero. */
HK_API hk_Status hk_strand_dynamics_create(hk_SuperHelix *sh, const hk_DynamicsDef *params, const hk_StrandEnvDef *body,
                                           hk_StrandDynamics **out, hk_Error *err);
HK_API void hk_strand_dynamics_destroy(hk_StrandDynamics *d);

/* Generalized velocities q' (3N values), readable and writable. */
HK_API double *hk_strand_dynamics_velocity(hk_StrandDynamics *d);

/* Places the root with the head state (NULL: at rest) without stepping: sh->root and
 * sh->root_frame become R x + T and R F of their head-space values. */
HK_API void hk_strand_dynamics_place(hk_StrandDynamics *d, const hk_RigidState *head);

/* One step of dt seconds. head (NULL: at rest) is the head's state at the end of the
 * step (the inner stage's state is extrapolated from it, second order; advance
 * evaluates the motion itself); forces (may be NULL) are extra point forces sorted by
 * s, e.g. hair-hair contacts, following their linearisation through the step. Fails
 * (HK_ERR_NUMERIC, state unchanged) if Newton's iteration does not converge or the new
 * state is not finite. */
HK_API hk_Status hk_strand_dynamics_step(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces,
                                         int force_count, double dt, hk_Error *err);

/* The head's state at time t, for hk_strand_dynamics_advance (user: caller data). */
typedef void (*hk_HeadStateFn)(void *user, double t, hk_RigidState *out);

/* Advances from time t to t + dt with error control: a step that turns some element's
 * frame by more than max_turn radians (the linearisation of the step no longer holds:
 * a whipping tip, a fast shake), moves a node by more than max_travel relative to the
 * head, lets a collision sample enter the body by more than max_entry unfelt (linearly
 * implicit Euler), or fails is undone and done again as two half steps,
 * recursively, down to dt / 2^max_depth. head (NULL: at rest) gives the head's state at
 * any time; the point forces are held over the whole interval. *substeps (may be NULL)
 * receives the number of steps taken. */
HK_API hk_Status hk_strand_dynamics_advance(hk_StrandDynamics *d, hk_HeadStateFn head, void *user, double t, double dt,
                                            const hk_PointForce *forces, int force_count, int *substeps, hk_Error *err);

/* Energies at the current state with the head state head (NULL: at rest): kinetic
 * (centreline and rotary, absolute velocities) and potential (elastic + gravity, the
 * statics energy without contacts). Either pointer may be NULL. */
HK_API void hk_strand_dynamics_energy(hk_StrandDynamics *d, const hk_RigidState *head, double *kinetic,
                                      double *potential);

/* Positions and world velocities at the arc lengths s[0..count) (sorted), for contact
 * detection and output. vel may be NULL. head as above. */
HK_API void hk_strand_dynamics_points(hk_StrandDynamics *d, const hk_RigidState *head, const double *s, int count,
                                      hk_Vec3 *pos, hk_Vec3 *vel);

/* Number of body contact samples that touched a shape during the last step. */
HK_API int hk_strand_dynamics_contact_count(const hk_StrandDynamics *d);

/* Work done so far (steps, Newton iterations, splits, failures). */
HK_API hk_DynamicsStats hk_strand_dynamics_stats(const hk_StrandDynamics *d);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_DYNAMICS_H */
