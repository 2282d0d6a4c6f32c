/* Follicles on an arbitrary surface (Piuze et al. 2011 §4.3, Fig. 9): a variational implicit
 * surface fitted to points with normals (Turk & O'Brien 2002), then a particle system
 * of repulsion and the implicit constraint with fission and death (Witkin & Heckbert
 * 1994) that spreads near-regularly over the part of the surface where hair grows. */
#ifndef HAIRKIT_FOLLICLE_SAMPLING_H
#define HAIRKIT_FOLLICLE_SAMPLING_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/mesh.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- variational implicit surface ------------------------------------------------
 * f(x) = sum_j w_j |x - c_j|^3 + p0 + p . x: the 3D thin-plate (biharmonic) spline
 * through f = 0 at the surface points and f = +1 at the points moved by
 * normal_offset along their normals (f = -1 at the points moved inwards too when
 * both_sides is set). So f < 0 inside, f > 0 outside and grad f points out. */

/* Largest number of constraints (surface points + offset points) of one fit: the
 * dense system takes 8 n^2 bytes (200 MB at the limit) and n^3 / 6 multiply-adds. */
#define HK_IMPLICIT_MAX_CONSTRAINTS 5000

typedef struct hk_ImplicitFitDef {
    double normal_offset; /* distance of the off-surface constraints (m); <= 0: 1% of the
                             diagonal of the points' bounding box */
    int both_sides;       /* 1: also f = -1 at the points moved inwards (3 n constraints) */
    int threads;          /* OpenMP threads for the solve; <= 0: the OpenMP default */
} hk_ImplicitFitDef;

HK_API hk_ImplicitFitDef hk_default_implicit_fit_def(void);

typedef struct hk_ImplicitSurface hk_ImplicitSurface;

/* Fits the surface through `count` points with outward `normals` (unit or not, but
 * not zero). Errors: no or too many points, NaN/Inf, a zero normal, coincident
 * constraints, all constraints in one plane, a singular system. def may be NULL. */
HK_API hk_Status hk_implicit_surface_fit(const hk_Vec3 *points, const hk_Vec3 *normals, int count,
                                         const hk_ImplicitFitDef *def, hk_ImplicitSurface **out, hk_Error *err);
HK_API void hk_implicit_surface_destroy(hk_ImplicitSurface *s);

/* f(x); when grad is not NULL also the analytic gradient. Thread-safe. */
HK_API double hk_implicit_surface_eval(const hk_ImplicitSurface *s, hk_Vec3 x, hk_Vec3 *grad);

/* The offset actually used (normal_offset or its default), and the constraint count. */
HK_API double hk_implicit_surface_offset(const hk_ImplicitSurface *s);
HK_API int hk_implicit_surface_constraint_count(const hk_ImplicitSurface *s);

/* ---- sampling -------------------------------------------------------------------- */

/* Any implicit function the sampler can work on: returns f(x) and writes grad f(x).
 * Called from several threads at once. */
typedef double (*hk_ImplicitEvalFn)(const void *user, hk_Vec3 x, hk_Vec3 *grad);

typedef struct hk_ImplicitFunction {
    hk_ImplicitEvalFn eval;
    const void *user;
} hk_ImplicitFunction;

/* The fitted surface as an hk_ImplicitFunction (s must outlive its use). */
HK_API hk_ImplicitFunction hk_implicit_surface_function(const hk_ImplicitSurface *s);

/* Newton projection x <- x - f grad f / |grad f|^2 until |f| / |grad f| <= tol (at most
 * 50 steps, each shortened to `max_step` when that is > 0). Writes the point and the
 * unit normal grad f / |grad f| there. Returns 1 on success, 0 when grad f vanishes,
 * a value is not finite or the iteration does not converge. */
HK_API int hk_implicit_project(hk_ImplicitFunction fn, hk_Vec3 x, double tol, double max_step, hk_Vec3 *out_point,
                               hk_Vec3 *out_normal);

/* Hard limit on the particles of one sampling (free + fixed). */
#define HK_SAMPLING_MAX_PARTICLES 1000000

/* Says whether hair grows at x (1) or not (0). Called from several threads at once. */
typedef int (*hk_InsideFn)(void *user, hk_Vec3 x);

typedef struct hk_FollicleSamplingDef {
    double spacing;       /* target distance between neighbouring follicles (m), > 0 */
    int max_particles;    /* cap on the free particles (fission stops there) */
    int max_iterations;   /* all iterations, population control then relaxation */
    int relax_iterations; /* last iterations with the population frozen */
    uint64_t seed;        /* same seed -> same follicles, byte for byte, any thread count */
    const hk_Vec3 *fixed; /* fixed particles (e.g. the scalp contour): they repel the others and
                             never move; they are not returned. May be NULL when fixed_count = 0 */
    int fixed_count;
    hk_InsideFn inside; /* NULL: hair grows everywhere on the surface */
    void *inside_user;
    int threads;            /* OpenMP threads; <= 0: the OpenMP default */
    hk_ProgressFn progress; /* may be NULL: stage "follicles", fraction of the iterations */
    void *progress_user;
} hk_FollicleSamplingDef;

/* spacing 0 (must be set), max_particles 100000, max_iterations 600, relax_iterations
 * 80, seed 1, no fixed particles, no mask, default threads. */
HK_API hk_FollicleSamplingDef hk_default_follicle_sampling_def(void);

typedef struct hk_FollicleSamples {
    int count;
    hk_Vec3 *points;    /* count, on f = 0 within 1e-6 spacing (1e-9 where rounding allows) */
    hk_Vec3 *normals;   /* count, grad f / |grad f| */
    int iterations;     /* iterations run */
    int births, deaths; /* fissions and deaths over the run */
} hk_FollicleSamples;

/* Spreads particles over the zero set of fn from the `seeds` (projected onto it; those
 * outside the mask are dropped, at least one must remain). Errors: no seeds, NaN,
 * spacing <= 0, counts out of range, a seed that cannot be projected. */
HK_API hk_Status hk_sample_follicles(hk_ImplicitFunction fn, const hk_Vec3 *seeds, int seed_count,
                                     const hk_FollicleSamplingDef *def, hk_FollicleSamples *out, hk_Error *err);
HK_API void hk_follicle_samples_free(hk_FollicleSamples *s);

/* ---- on a head: the wick region ---------------------------------------------------
 * Fits the implicit surface to the wick's vertices and the head's vertices within
 * `margin` of the wick (thinned to one per cell of `fit_spacing`), puts fixed particles
 * every `spacing` along the wick's boundary edges projected on the surface (the scalp
 * contour of Fig. 9), seeds at the wick's vertices and samples over the wick (within
 * spacing / 4 of its triangles, at most spacing / 10 beyond its edges, both widened by
 * how far the flat triangles stray from the smooth surface). The result holds the
 * free follicles followed by the contour ones (both on the surface, with its
 * normals): roots for interpolated hair. */
typedef struct hk_WickSamplingDef {
    double spacing;      /* follicle spacing (m), > 0 */
    double fit_spacing;  /* thinning of the fitted points (m); <= 0: 1 cm */
    double margin;       /* head vertices closer than this to the wick are fitted too (m); < 0: 2 cm */
    int include_contour; /* 1: append the contour particles to the follicles */
    int max_particles, max_iterations, relax_iterations;
    uint64_t seed;
    int threads;
    hk_ProgressFn progress; /* may be NULL: stages "surface" (the fit) and "follicles" */
    void *progress_user;
} hk_WickSamplingDef;

HK_API hk_WickSamplingDef hk_default_wick_sampling_def(void);

/* head may be NULL (then only the wick's vertices are fitted). */
HK_API hk_Status hk_wick_follicles(const hk_Mesh *head, const hk_Mesh *wick, const hk_WickSamplingDef *def,
                                   hk_FollicleSamples *out, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
