/* Generalized helicoids and hair files (Piuze, Kry and Siddiqi, "Generalized helicoids
 * for modeling hair geometry", Eurographics 2011): a set of p-helicoids traced into
 * strands with their wisps (§3), strands interpolated at roots from guides (§4.1-4.3),
 * the strands of a hair file fitted with p-helicoids (§5) and a full head rebuilt from
 * the fits of a few of its strands (§5.4). The jobs of `hairkit helicoid`, in the
 * library. */
#ifndef HAIRKIT_HELICOID_HAIR_H
#define HAIRKIT_HELICOID_HAIR_H

#include <stdint.h>

#include "hairkit/curvefit.h"
#include "hairkit/hairfile.h"
#include "hairkit/helicoid.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_fit.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Interpolated strands leave the surface at least this steeply (radians; §4.3,
 * hk_phelicoid_interpolate_on_surface): a floor for averages of guides that lean
 * different ways, not a style (the guides set the angle). 10 degrees. */
#define HK_HELICOID_MIN_ELEVATION 0.17453292519943295

/* Traces the set's strands at `step` (m), each followed by its wisp strands, into `hair`
 * (filled here; free with hk_hair_free). `seed` draws the strands' wave phases when the
 * set's waviness has a jitter, from the strand's index: the same bytes whatever the
 * threads (<= 0: OpenMP's default). */
HK_API hk_Status hk_helicoid_set_trace(const hk_HelicoidSet *set, double step, uint64_t seed, int threads,
                                       hk_HairFile *hair, hk_Error *err);

/* Strands out[0..count) interpolated from the guides at the roots. With guide_normals
 * (then normals too): on the surface whose outward normals they are (§4.3: frames
 * relative to the normals, HK_HELICOID_MIN_ELEVATION); else plain inverse-distance
 * weighting of power `power` (§4.1), normals (may be NULL) only keeping each strand's
 * E_T out of the surface. In parallel (threads <= 0: OpenMP's default); the first strand
 * that fails (by index) gives the error. */
HK_API hk_Status hk_helicoid_interpolate_at(const hk_PHelicoid *guides, const hk_Vec3 *guide_normals, int guide_count,
                                            const hk_Vec3 *roots, const hk_Vec3 *normals, long count, double power,
                                            int threads, hk_PHelicoid *out, hk_Error *err);

/* A fit's figures (hk_CurveFit's, without its per-piece arrays). */
typedef struct hk_HelicoidFitReport {
    double error;   /* normalised coupling of the fit vs the strand (m) */
    double frechet; /* discrete Fréchet distance, same pair (m) */
    int pieces;
    long evaluations;
} hk_HelicoidFitReport;

/* Fits p-helicoids to strands index[0..count) of `hair` (hk_helicoid_fit with `options`;
 * NULL: hk_default_helicoid_fit_def()) into out[0..count), their figures into
 * reports[0..count) (may be NULL), in parallel with one fitter per thread (threads <= 0:
 * OpenMP's default). progress (may be NULL) is told the fraction done ("fitting"), from
 * one thread. A strand of fewer than 2 or more than HK_CURVEFIT_MAX_SAMPLES points is
 * refused before any fitting; the first strand that fails (by position) gives the
 * error. */
HK_API hk_Status hk_helicoid_fit_strands(const hk_HairFile *hair, const long *index, long count,
                                         const hk_CurveFitDef *options, int threads, hk_ProgressFn progress,
                                         void *progress_user, hk_PHelicoid *out, hk_HelicoidFitReport *reports,
                                         hk_Error *err);

/* The same with hk_helicoid_fit_wavy (options NULL: hk_default_wavy_fit_def()): each
 * strand's p-helicoid and its own waves of eq. 4 into waves[0..count) (amplitude 0 where
 * the plain fit was as good; strands under 8 points get the plain fit of options->base).
 * The reports' error and Fréchet distance are of the fit traced with its waves at the
 * strand's count of points; their evaluations 0. */
HK_API hk_Status hk_helicoid_fit_strands_wavy(const hk_HairFile *hair, const long *index, long count,
                                              const hk_WavyFitDef *options, int threads, hk_ProgressFn progress,
                                              void *progress_user, hk_PHelicoid *out, hk_Waviness *waves,
                                              hk_HelicoidFitReport *reports, hk_Error *err);

/* The layout of a reconstruction's fits: by length from the root, a 1 cm piece for the
 * lift off the scalp, then 3 cm pieces. On the head example (3,629 strands without waves,
 * one in ten fitted) it rebuilds to 5.4 mm, against 9.9 mm with fits split where each
 * strand needs it; on TressFX Sintel 3.8 mm against 3.6 mm. (It was chosen when the fits'
 * parameters were blended piece by piece, which needs piece j on the same stretch of hair
 * on every fit; the blend below traces each fit whole.) */
#define HK_RECONSTRUCT_PIECE_LENGTH 0.03
#define HK_RECONSTRUCT_ROOT_PIECE   0.01

/* How a reconstruction blends the fits (§5.4; docs/helicoid-fitting.md, "Reconstruction of
 * captured grooms", has what each choice gave on TressFX Sintel, CT2Hair Bangs and Curly).
 * Each strand is rebuilt from the shapes of its NEIGHBOURS nearest fitted guides (by root),
 * each traced from the strand's root to the strand's own length, weighted by §4.1's
 * inverse-distance weight times exp(-(1 - cos a) / DIRECTION_WIDTH), a the angle between
 * the guide's and the strand's own root directions (the capture gives it: the chord to the
 * strand's first point), and turned by TURN times a towards the strand's direction. Sintel
 * from one strand in ten: 3.8 mm mean error; 5.2 mm with neither the direction weight nor
 * the turn, 3.9 mm without the turn, 4.5 mm with the whole turn (hanging tips then swing
 * with the root); 8 or 32 neighbours change it by 0.03 mm. */
#define HK_RECONSTRUCT_NEIGHBOURS      16
#define HK_RECONSTRUCT_DIRECTION_WIDTH 0.05
#define HK_RECONSTRUCT_TURN            0.6

typedef struct hk_HelicoidReconstruction {
    long strands, fitted;         /* of the hair; fitted: one in `every` */
    double seconds_fit;           /* fitting */
    double seconds_rebuild;       /* interpolating and tracing */
    double mean_error, max_error; /* each rebuilt strand against its original: the mean
                                     leash of their Fréchet coupling (m) */
} hk_HelicoidReconstruction;

/* A full head rebuilt from sparse fits (§5.4): strands 0, every, 2 every, ... of `hair`
 * fitted (options; NULL: hk_default_helicoid_fit_def() with the layout above), every strand
 * of the hair then rebuilt from its own root, root direction and length by blending the
 * fits as above (inverse-distance power `power`), its points at most `step` apart, into
 * `out`, and each compared with its original. A fitted strand is rebuilt from its own fit
 * alone. seed: unused (the rebuild draws nothing; kept for the callers). report may be
 * NULL. The same bytes whatever the threads. */
HK_API hk_Status hk_helicoid_reconstruct(const hk_HairFile *hair, long every, const hk_CurveFitDef *options,
                                         double power, double step, uint64_t seed, int threads, hk_ProgressFn progress,
                                         void *progress_user, hk_HairFile *out, hk_HelicoidReconstruction *report,
                                         hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
