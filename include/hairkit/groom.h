/* Growing a full head of hair (Lansink 2010 §4.1.4, Bertails et al. 2006 §4.1): follicles on a
 * wick mesh, guide strands solved as Super-Helices, and interpolated strands filling
 * every wick triangle, with clumping, stray hairs and semi-interpolation. */
#ifndef HAIRKIT_GROOM_H
#define HAIRKIT_GROOM_H

#include <stdint.h>

#include "hairkit/collide.h"
#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/hairfile.h"
#include "hairkit/mesh.h"
#include "hairkit/rod.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hk_GroomDef {
    uint64_t seed;          /* the same seed gives the same hair, byte for byte */
    int threads;            /* OpenMP threads; <= 0: the OpenMP default */
    hk_ProgressFn progress; /* may be NULL */
    void *progress_user;
    int keep_outside; /* 1 (default): interpolated strands that enter a body shape
                         are moved out of it, keeping their length (docs/grooming.md);
                         0: the plain blend of the guides */
} hk_GroomDef;

HK_API hk_GroomDef hk_default_groom_def(void);

/* The interpolation of the full head as a hairstyle file describes it (thesis
 * §4.1.4.3-4, Bertails et al. 2006 §4.1; the key of each field after its colon). */
typedef struct hk_InterpolationDef {
    double hair_density;     /* HairDensity: hairs per cm^2 of wick surface */
    double clump;            /* ClumpFactor in [0, 1): spread of the tips around their nearest
                                guide (thesis: 0.25; 0 = tips on the guide) */
    double clump_profile;    /* ClumpProfile > 0: weights go from root to tip as t^profile
                                (1 = the thesis's linear blend; > 1 interpolates further
                                down before clumping, for straight hair) */
    int stray_hairs;         /* StrayHairs: the thesis's stray-hair behaviour (§4.1.4.4) */
    double max_tip_distance; /* MaxTipDistance (m): an interpolated strand does not blend
                                guides whose tips are this far or farther from its nearest
                                guide's tip, and fades them out from half of it (Bertails et al. 2006
                                Fig. 4d; docs/grooming.md); default 0.08, 0 = off */
} hk_InterpolationDef;

/* HairDensity 250, ClumpFactor 0.25, ClumpProfile 1, StrayHairs 0, MaxTipDistance 8 cm. */
HK_API hk_InterpolationDef hk_default_interpolation_def(void);

/* Follicles of a wick (thesis §4.1.4.1): one per vertex, growing along the vertex
 * normal, with the envelope level alpha = (y - y_min) / (y_max - y_min) of
 * §4.1.2.2 (0 when all follicles are at the same height). */
typedef struct hk_Follicles {
    int count;
    hk_Vec3 *position;
    hk_Vec3 *normal;
    double *alpha;
} hk_Follicles;

HK_API hk_Status hk_follicles_from_wick(const hk_Mesh *wick, hk_Follicles *out, hk_Error *err);
HK_API void hk_follicles_free(hk_Follicles *f);

typedef struct hk_GroomStats {
    long guide_iterations;        /* Newton steps over all guides */
    int guides_not_converged;     /* guides stopped by the iteration limit */
    double max_guide_penetration; /* deepest collision sample of any guide (m) */
    double seconds_guides, seconds_strands;
} hk_GroomStats;

typedef struct hk_Groom {
    int points_per_strand;      /* every strand has this many points (VisualityStep samples) */
    int guide_count;            /* = follicles = wick vertices */
    double *guides;             /* guide_count x points x 3, the solved guide strands */
    int strand_count;           /* interpolated strands */
    float *strands;             /* strand_count x points x 3 */
    int *strand_triangle;       /* wick triangle each interpolated strand grows from */
    float *strand_root_weights; /* 3 per strand: barycentric root in its triangle */
    hk_GroomStats stats;
} hk_Groom;

/* Grows the hair: solves one guide per follicle (in parallel) with the hairstyle's
 * statics and the collision shapes' layered envelopes, then fills every wick triangle
 * with round(area x HairDensity) interpolated strands (stochastic rounding, so the
 * expected count is exact) at uniformly random roots. */
HK_API hk_Status hk_groom_grow(const hk_StrandDef *strand, const hk_InterpolationDef *interpolation,
                               const hk_Shape *shapes, int shape_count, const hk_Mesh *wick, const hk_GroomDef *options,
                               hk_Groom *out, hk_Error *err);

HK_API void hk_groom_free(hk_Groom *g);

/* Most interpolated strands a groom may have. */
#define HK_MAX_GROOM_STRANDS 100000000L

/* Checks, before anything is grown, what hk_groom_grow would make of this hairstyle
 * and wick: the interpolated strand count (exact: the same stochastic rounding) must be
 * finite and at most HK_MAX_GROOM_STRANDS (HK_ERR_INVALID), and the groom with the
 * .hair made from it must fit the memory budget (hk_memory_check, HK_ERR_NOMEM: about
 * 1 kB a strand of 41 points). The count goes to *strands (may be NULL). hk_groom_grow
 * and hk_groom_interpolate_guides check the same; a caller that knows the files may call
 * it first to name them in the message. */
HK_API hk_Status hk_groom_check_size(const hk_StrandDef *strand, const hk_InterpolationDef *interpolation,
                                     const hk_Mesh *wick, const hk_GroomDef *options, long *strands, hk_Error *err);

/* Grows the interpolated strands of g again from its guides (g->guides,
 * g->guide_count, g->points_per_strand set, e.g. moved by the dynamics; follicles =
 * wick vertices): the same seed gives the same roots and clumps, so that strands
 * follow their guides from frame to frame. The strands are kept out of the body
 * shapes among shapes[0..shape_count) (may be NULL, 0), in the guides' space.
 * Replaces any strands g had (their arrays are reused when they hold as many). */
HK_API hk_Status hk_groom_interpolate_guides(const hk_InterpolationDef *interpolation, const hk_Shape *shapes,
                                             int shape_count, const hk_Mesh *wick, const hk_GroomDef *options,
                                             hk_Groom *g, hk_Error *err);

/* The groom as cyHair data: the guides first, then the interpolated strands; default
 * thickness is the hair's mean diameter. */
HK_API hk_Status hk_groom_to_hair(const hk_Groom *g, const hk_StrandDef *strand, hk_HairFile *out, hk_Error *err);

/* hk_groom_to_hair into out, the hair of an earlier hk_groom_to_hair (or zeroed): its
 * arrays are reused when it has as many strands of as many points (a simulation's
 * frames: 60 MB of fresh pages a frame otherwise), else it is freed and made anew. */
HK_API hk_Status hk_groom_to_hair_again(const hk_Groom *g, const hk_StrandDef *strand, hk_HairFile *out, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
