/* Fitting p-helicoids to polylines (Piuze et al. 2011 §5) with the generic piecewise fitter of
 * curvefit.h, the helicoid piece as the model; and reconstruction of a full head from
 * sparse fitted strands (§5.4). */
#ifndef HAIRKIT_HELICOID_FIT_H
#define HAIRKIT_HELICOID_FIT_H

#include "hairkit/curvefit.h"
#include "hairkit/export.h"
#include "hairkit/helicoid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The fitter's defaults for hair: curvefit's (Levenberg-Marquardt, tolerance 0.2 mm) with
 * arc_length = 1 (pieces are traced at arc-length spacing), the model's derivatives
 * (hk_helicoid_piece_derivative) and max_pieces = HK_HELICOID_MAX_PIECES, so that the cap
 * is the minimal fragment's (5 mm: a strand of length L gets at most L / 5 mm pieces); and
 * the seed and initial steps
 * of the helicoid parameters (k_T, k_N, k_B, alpha) for a strand of the given length:
 * straight to start, steps of a quarter turn over the strand's length. */
HK_API hk_CurveFitDef hk_default_helicoid_fit_def(void);
HK_API void hk_helicoid_fit_seed(double length, double seed[4], double scale[4]);

/* A p-helicoid with the waviness of eq. 4 on top (§3.2), for strands made that way (the wisp and
 * head examples): the plain fitter follows such waves with about 9 pieces a turn, this fit
 * with the base's pieces and 3 wave parameters (src/helicoid/wavy_fit.c, docs/helicoid-
 * fitting.md "Waves"). The base gets pieces of equal length, about base_piece_length each (at
 * most 5, so that the final polish of every parameter at once stays within 32). */
typedef struct hk_WavyFitDef {
    hk_CurveFitDef base;      /* the base's fits (its layout is set here) */
    double base_piece_length; /* about this long each (m), > 0 */
    int rounds;               /* base and waves estimated in turn this many times, >= 1 */
    int polish_evaluations;   /* Levenberg-Marquardt of everything at once (0: none) */
} hk_WavyFitDef;

/* hk_default_helicoid_fit_def() for the base, pieces of 7 cm, 4 rounds, 3000 evaluations. */
HK_API hk_WavyFitDef hk_default_wavy_fit_def(void);

/* Work memory of one fitting thread (no allocation per fit). */
typedef struct hk_HelicoidFitter hk_HelicoidFitter;
HK_API hk_HelicoidFitter *hk_helicoid_fitter_create(int max_samples, hk_Error *err);
HK_API void hk_helicoid_fitter_destroy(hk_HelicoidFitter *f);

/* Fits a p-helicoid to the polyline points[0..count): out gets root, frame and pieces;
 * fit (may be NULL) the fitter's report (errors in metres, evaluations). On top of the
 * options it sets the helicoid's own rules (docs/helicoid-fitting.md, 4b): a second-order
 * root tangent, the root frame rolled by atan(alpha) (root_frame), a seed from each
 * fragment's curvature (fragment_seed) and alpha weighed in the regularisation as a
 * curvature of a radian per sample (penalty_weight[3], unless the caller set it). The
 * model refuses pieces that turn more than a radian per sample or come within a tenth of
 * their singular axis (they describe no definite curve). With the default derivatives
 * the search for the pieces traces more coarsely (RK4 steps of up to 0.5 rad, phases
 * carried instead of sincos) and the pieces found are finished with the model below
 * (options.final_model), which also gives the report's errors (docs/helicoid-fitting.md
 * §7, "The search's tracer"). */
HK_API hk_Status hk_helicoid_fit(hk_HelicoidFitter *f, const hk_Vec3 *points, int count, const hk_CurveFitDef *options,
                                 hk_PHelicoid *out, hk_CurveFit *fit, hk_Error *err);

/* Fits points[0..count) (8 to HK_CURVEFIT_MAX_SAMPLES, f made for at least count) with a
 * p-helicoid `out` traced with the waves `wave` (hk_phelicoid_trace(out, step, wave, ...)):
 * error gets their normalised coupling with the points, traced at the points' spacing. The
 * plain fit (hk_helicoid_fit with options->base) is made too and kept, with a wave amplitude
 * of 0, when it is as good: never worse than it. options NULL: hk_default_wavy_fit_def().
 * Allocates its work memory. */
HK_API hk_Status hk_helicoid_fit_wavy(hk_HelicoidFitter *f, const hk_Vec3 *points, int count,
                                      const hk_WavyFitDef *options, hk_PHelicoid *out, hk_Waviness *wave, double *error,
                                      hk_Error *err);

/* The curve model of one helicoid piece (params k_T, k_N, k_B, alpha), for curvefit.h;
 * user is the fitter. Non-zero for the refused parameters above. */
HK_API int hk_helicoid_piece_model(void *user, const double *params, const hk_CurveStart *start, double length,
                                   int count, hk_Vec3 *out_points, hk_CurveStart *end);

/* Its derivatives with respect to the params (curvefit.h, hk_CurveModelDerivFn): the
 * piece traced by RK4 with one tangent per parameter (the model itself uses a closed form
 * where alpha = 0: the two traces then agree to RK4's error). hk_default_helicoid_fit_def
 * sets it as options.model_derivative (NULL: forward differences). */
HK_API int hk_helicoid_piece_derivative(void *user, const double *params, const hk_CurveStart *start, double length,
                                        int count, hk_Vec3 *out_points, hk_CurveStart *end, hk_Vec3 *d_points,
                                        hk_Vec3 *d_end_tangent);

#ifdef __cplusplus
}
#endif

#endif
