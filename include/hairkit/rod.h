/* Super-Helix kinematics and energies (Bertails et al. 2006 §3.1-3.2 and Appendix A; Lansink 2010
 * §4.1.1-4.1.2).
 *
 * A strand of length L is cut into N elements of lengths l_Q. Over element Q the twist
 * tau and the material curvatures kappa1, kappa2 are constant: the generalized
 * coordinates are q = (tau_Q, kappa1_Q, kappa2_Q) for Q = 0..N-1, in that order. Over
 * an element the Darboux vector is constant, so the material frame rotates uniformly
 * and the centreline is a helix; elements join with C1 continuity. With the frame
 * stored as the rotation R = [n0 n1 n2] (n0 the tangent) and k = (tau, kappa1,
 * kappa2), an element maps its start pose (R, r) to
 *     R(u) = R exp(u [k]x),      r(u) = r + R Lambda(u; k) e0,
 *     Lambda(u; k) = int_0^u exp(v [k]x) dv,
 * evaluated in closed form with series near k = 0 (docs/physics.md). */
#ifndef HAIRKIT_ROD_H
#define HAIRKIT_ROD_H

#include "hairkit/collide.h"
#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Limits that keep absurd input from turning into absurd allocations or run times. */
#define HK_MAX_ELEMENTS           1000    /* Super-Helix elements per strand */
#define HK_MAX_SAMPLES_PER_STRAND 1000000 /* L / VisualityStep, L / CollisionStep */

/* A strand as a hairstyle file describes it (thesis Appendix B; the key of each field
 * after its colon): its elements, the section and the material of the hair, its natural
 * helix, gravity, how it is sampled and the thesis's statics solver. */
typedef struct hk_StrandDef {
    int element_count;       /* N, the number of values of HairLengths */
    double *element_lengths; /* HairLengths: l_Q for Q = 1..N (m); a hairstyle's own them
                                (hk_hairstyle_free), a def made by hand points at the
                                caller's */
    double radius1;          /* HairRadius1: semi-axis a of the section along n1 (m) */
    double radius2;          /* HairRadius2: semi-axis b of the section along n2 (m) */
    double helix_radius;     /* HelixRadius r_h (m); 0 means straight hair */
    double helix_step;       /* HelixStep Delta_h (m); negative gives a left-handed helix */
    double poisson;          /* Poisson: sigma in (-1, 0.5) */
    double young;            /* Young: E (Pa) */
    double density;          /* Density: rho (kg/m^3) */
    double gravity;          /* Gravity: |g| (m/s^2) */
    hk_Vec3 gravity_dir;     /* GravityDirection: unit vector, default (0, -1, 0) */
    double visuality_step;   /* VisualityStep: spacing of output vertices along s (m) */
    double collision_step;   /* CollisionStep: spacing of collision samples along s (m) */
    int max_iter;            /* MaxIter: Rosenbrock stages */
    double epsilon;          /* Epsilon: Rosenbrock relative energy decrease per stage */
} hk_StrandDef;

/* The defaults of the hairstyle file's optional keys: VisualityStep 2.5 mm,
 * CollisionStep 5 mm, MaxIter 20, Epsilon 1e-4, Poisson 0.48, Density 1300, Gravity 9.81
 * along (0, -1, 0); no elements, and the required keys (radii, helix, Young) zero. */
HK_API hk_StrandDef hk_default_strand_def(void);

/* Sum of the element lengths. */
HK_API double hk_strand_def_length(const hk_StrandDef *def);

/* Mechanical constants of a strand (Bertails et al. 2006 eq. 5; DESIGN.md physics notes). */
typedef struct hk_RodMaterial {
    double stiffness[3];      /* (mu J, E I1, E I2): twist and bending stiffnesses (N m^2) */
    double mass_per_length;   /* rho * pi a b (kg/m) */
    double rotary_inertia[3]; /* rho (I1 + I2, I1, I2): moments of inertia per length of the
                                 section about n0, n1, n2 (kg m), for the dynamics */
    hk_Vec3 gravity;          /* acceleration of gravity (m/s^2), e.g. (0, -9.81, 0) */
} hk_RodMaterial;

/* Stiffnesses of an elliptic section with semi-axes a (along n1) and b (along n2):
 * I1 = pi a b^3 / 4, I2 = pi b a^3 / 4, J = pi a b (a^2 + b^2) / 4, mu = E / (2 (1 + sigma)).
 * The section's polar moment I1 + I2 equals J for the ellipse. */
HK_API hk_RodMaterial hk_rod_material(double radius1, double radius2, double young, double poisson, double density,
                                      hk_Vec3 gravity);

/* Natural twist and curvature of the exact helix of radius r_h and step Delta_h:
 * with c = Delta_h / (2 pi), kappa1 = r_h / (r_h^2 + c^2), tau = c / (r_h^2 + c^2),
 * kappa2 = 0. r_h == 0 gives a straight strand (tau = kappa1 = 0). */
HK_API void hk_helix_natural_curvature(double helix_radius, double helix_step, double *tau, double *kappa1);

/* Root material frame for a follicle direction (thesis §4.1.4.1): n0 = dir / |dir|,
 * n1 = n0 x y / |n0 x y| with y = (0, 1, 0), or (0, 0, 1) when n0 is vertical,
 * n2 = n0 x n1. Returned as the columns of a rotation matrix. */
HK_API hk_Mat3 hk_root_frame(hk_Vec3 dir);

typedef struct hk_SuperHelix {
    int n;               /* number of elements N >= 1 */
    double *length;      /* l_Q, Q = 0..N-1 */
    double *s_start;     /* s at the start of each element, N + 1 values, s_start[N] = L */
    double total_length; /* L */
    double *q;           /* 3N generalized coordinates, per element (tau, kappa1, kappa2) */
    double *q_rest;      /* 3N natural twist and curvatures */
    hk_Vec3 root;        /* r(0), clamped */
    hk_Mat3 root_frame;  /* material frame at s = 0, clamped (columns n0, n1, n2) */
    hk_RodMaterial material;
} hk_SuperHelix;

/* A strand of n elements with the given lengths (all > 0), straight at rest, root at
 * the origin along +x. */
HK_API hk_Status hk_superhelix_create(int n, const double *lengths, hk_SuperHelix **out, hk_Error *err);

/* A strand as def describes it: element lengths, material, natural helix (uniform
 * along the strand), root at `root` leaving along `dir`; q starts at q_rest. */
HK_API hk_Status hk_superhelix_from_def(const hk_StrandDef *def, hk_Vec3 root, hk_Vec3 dir, hk_SuperHelix **out,
                                        hk_Error *err);

HK_API void hk_superhelix_destroy(hk_SuperHelix *sh);

/* Sets the same natural twist and curvatures on every element and q = q_rest. */
HK_API void hk_superhelix_set_uniform_rest(hk_SuperHelix *sh, double tau, double kappa1, double kappa2);

/* Reconstruction (Bertails et al. 2006 Appendix A) for coordinates q (sh->q when q is NULL):
 * node poses at s_start[0..N]: pos[N+1] and frame[N+1] (either may be NULL). */
HK_API void hk_superhelix_nodes(const hk_SuperHelix *sh, const double *q, hk_Vec3 *pos, hk_Mat3 *frame);

/* Position and frame at arc length s in [0, L] (clamped to it). */
HK_API void hk_superhelix_eval(const hk_SuperHelix *sh, const double *q, double s, hk_Vec3 *pos, hk_Mat3 *frame);

/* Number of samples of hk_superhelix_sample: s = 0, step, 2 step, ... and always the
 * tip s = L last (a sample closer than 1e-9 L to the tip is replaced by the tip). */
HK_API int hk_superhelix_sample_count(const hk_SuperHelix *sh, double step);

/* Samples the centreline: s (may be NULL), positions, tangents n0 (may be NULL). */
HK_API void hk_superhelix_sample(const hk_SuperHelix *sh, const double *q, double step, double *s, hk_Vec3 *pos,
                                 hk_Vec3 *tangent);

/* Positions at the arc lengths s[0..count), ascending (clamped to [0, L]), in one sweep
 * from the root: O(N + count). */
HK_API void hk_superhelix_points(const hk_SuperHelix *sh, const double *q, const double *s, int count, hk_Vec3 *pos);

/* ---- energy ---------------------------------------------------------------------- */

/* Environment of a strand for the statics energy. */
typedef struct hk_StrandEnvDef {
    const hk_Shape *shapes; /* collision shapes (may be NULL when shape_count == 0) */
    int shape_count;
    double envelope_alpha; /* envelope level in [0, 1] of this strand (thesis §4.1.2.2) */
    double collision_step; /* CollisionStep; the strand is cut into ceil(L / step) equal
                              pieces sampled at their midpoints (<= 0: no collisions) */
} hk_StrandEnvDef;

HK_API hk_StrandEnvDef hk_default_strand_env_def(void);

/* Collision samples of the strand in env: ceil(L / collision_step) pieces (at least 1,
 * at most HK_MAX_SAMPLES_PER_STRAND) whose midpoints are sampled; 0 without shapes or
 * step. The statics energy and the dynamics' body contacts use the same samples. */
HK_API int hk_strand_collision_sample_count(const hk_SuperHelix *sh, const hk_StrandEnvDef *env);

typedef struct hk_StrandEnergy {
    double total, elastic, gravity, collision;
} hk_StrandEnergy;

/* Scratch memory for hk_strand_energy, sized for one strand and one environment. */
typedef struct hk_StrandWorkspace hk_StrandWorkspace;

HK_API hk_Status hk_strand_workspace_create(const hk_SuperHelix *sh, const hk_StrandEnvDef *env,
                                            hk_StrandWorkspace **out, hk_Error *err);
HK_API void hk_strand_workspace_destroy(hk_StrandWorkspace *ws);

/* Potential energy of the strand at coordinates q (thesis §4.1.1.3 and §4.1.2):
 *   elastic   sum_Q l_Q sum_i K_i / 2 (q_iQ - q_rest_iQ)^2
 *   gravity   -rho S g . int_0^L r(s) ds, closed form per element
 *   collision sum_samples w * sum_shapes 1/2 k max(dent + extra, 0)^2
 * grad (3N values) and hess (3N x 3N, row-major) are filled when not NULL. The
 * gradient is exact; the Hessian is exact as well (second derivatives of the
 * kinematics through every element, plus the shapes' own Hessians). O(N + samples)
 * for the gradient, O(N^2 + samples) for the Hessian. parts may be NULL. */
HK_API double hk_strand_energy(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q,
                               hk_StrandWorkspace *ws, double *grad, double *hess, hk_StrandEnergy *parts);

/* Greatest depth of a collision sample inside the envelopes at coordinates q (0 when
 * no sample touches a shape), evaluated at the same samples as the energy. */
HK_API double hk_strand_max_penetration(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q,
                                        hk_StrandWorkspace *ws);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_ROD_H */
