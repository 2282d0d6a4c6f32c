/* Captured and foreign hair made into Super-Helices at rest (docs/capture.md).
 *
 * A groom made in another tool or captured from real hair is a set of polylines. To move
 * it with Super-Helices (Bertails et al. 2006) each strand becomes a Super-Helix that
 * follows its polyline (hk_superhelix_fit), and then gets the natural curvatures and
 * twist that make that shape an equilibrium under gravity and the body
 * (hk_statics_invert), so that the hair does not sag when the simulation starts: the
 * inverse problem of Derouet-Jourdan, Bertails-Descoubes, Daviet and Thollot, "Inverse
 * Dynamic Hair Modeling with Frictional Contact", ACM TOG 32(6) (SIGGRAPH Asia 2013).
 * Lengths are metres: scale a groom in other units first (hk_hair_read's options). */
#ifndef HAIRKIT_CAPTURE_H
#define HAIRKIT_CAPTURE_H

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/rod.h"
#include "hairkit/statics.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- fitting a Super-Helix to a polyline ------------------------------------------ */

typedef struct hk_SuperHelixFitDef {
    int elements;          /* N, elements of equal length; 0: chosen, starting from
                              ceil(L / element_length) and doubled (each element split in
                              two, which keeps the shape) while the mean error is above
                              `tolerance`, up to max_elements and one element per segment
                              of the polyline */
    double element_length; /* the first N when chosen (m; default 0.01) */
    int max_elements;      /* largest N chosen (default 64) */
    double tolerance;      /* mean error at which the choice of N stops (m; default 5e-5) */
    int max_iterations;    /* Levenberg-Marquardt iterations per N (default 200) */
} hk_SuperHelixFitDef;

HK_API hk_SuperHelixFitDef hk_default_superhelix_fit_def(void);

/* How well a Super-Helix follows its polyline: the distance between each point of the
 * polyline (after the root) and the Super-Helix at the same arc length. */
typedef struct hk_SuperHelixFitReport {
    double mean_error; /* m */
    double max_error;  /* m */
    double length;     /* L: the polyline's length, the Super-Helix's too (m) */
    int elements;      /* N */
    int iterations;    /* Levenberg-Marquardt iterations, over every N tried */
} hk_SuperHelixFitReport;

/* The Super-Helix of N elements of equal length that follows the polyline points[0..count)
 * (count >= 2; consecutive equal points are skipped) in the least-squares sense: its
 * root is points[0], its root tangent the polyline's there (from the parabola through
 * the first three points), its root frame hk_root_frame of that tangent, its length the
 * polyline's, and its curvatures and twist q minimise the sum of squared distances
 * between each point and the Super-Helix at the point's arc length (Levenberg-Marquardt
 * with the exact Jacobian dr/dq of the kinematics; G1 by construction). q_rest is set to
 * q (the fitted shape is the rest shape without gravity: see hk_statics_invert). The
 * material is *material, or hk_superhelix_create's when NULL. def NULL: the defaults.
 * report may be NULL. */
HK_API hk_Status hk_superhelix_fit(const hk_Vec3 *points, int count, const hk_RodMaterial *material,
                                   const hk_SuperHelixFitDef *def, hk_SuperHelix **out,
                                   hk_SuperHelixFitReport *report, hk_Error *err);

/* ---- inverse statics ---------------------------------------------------------------- */

typedef struct hk_InverseStaticsDef {
    int settle_unstable;   /* 1 (default): a strand whose shape is an unstable equilibrium
                              is settled by the statics from that shape (it moves to the
                              stable rest nearby, and the report says how far); 0: left
                              as it is */
    hk_StaticsDef statics; /* the statics of that settling (hk_default_statics_def) */
} hk_InverseStaticsDef;

HK_API hk_InverseStaticsDef hk_default_inverse_statics_def(void);

typedef struct hk_InverseStaticsReport {
    int stable;           /* 1 when the Hessian of the total energy at the shape is
                             positive definite (a stable equilibrium) */
    int settled;          /* 1 when it was not and the statics settled the strand */
    double drift;         /* settled: the largest distance between a node of the shape
                             and the same node after settling (m); else 0 */
    double rest_change;   /* max |q_rest - q| over the coordinates (1/m): how far the
                             natural shape is from the given one */
    double residual;      /* |grad E| at sh->q after the inversion, relative to the
                             largest external generalized force (0 when there is none) */
} hk_InverseStaticsReport;

/* Natural curvatures and twist that make the strand's current shape sh->q an equilibrium
 * under gravity and the shapes of env (NULL: gravity alone): the elastic force per
 * element is diagonal, l_Q K_i (q_iQ - q_rest_iQ), so with f = dE_ext/dq the gradient of
 * gravity and the shapes' penalties at sh->q,
 *     q_rest = q + f_iQ / (l_Q K_i),
 * in closed form (Derouet-Jourdan et al. 2013, §4, with the contact forces the
 * penalties give at the shape; choosing other forces inside the friction cone is not
 * done). Then the stability of that equilibrium: the Hessian of the total energy at q
 * (exact, hk_strand_energy) is factored; when it is not positive definite the strand is
 * unstable (a column of hair standing up higher than Greenhill's critical height, e.g.)
 * and, with def->settle_unstable, sh->q becomes the rest the statics find from it.
 * def NULL: the defaults. report may be NULL. */
HK_API hk_Status hk_statics_invert(hk_SuperHelix *sh, const hk_StrandEnvDef *env,
                                   const hk_InverseStaticsDef *def, hk_InverseStaticsReport *report,
                                   hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_CAPTURE_H */
