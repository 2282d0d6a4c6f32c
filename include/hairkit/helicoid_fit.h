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
 * their singular axis (they describe no definite curve). */
HK_API hk_Status hk_helicoid_fit(hk_HelicoidFitter *f, const hk_Vec3 *points, int count, const hk_CurveFitDef *options,
                                 hk_PHelicoid *out, hk_CurveFit *fit, hk_Error *err);

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
