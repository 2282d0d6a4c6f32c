/* Fitting parametric curve models to polylines (Piuze et al. 2011 §5).
 *
 * The machinery of the paper's hair fitting, generic over the curve model: the model is
 * a callback that traces points from a start pose (position + frame) with a parameter
 * vector, so generalized helicoids, Frenet helices or anything else can be fitted.
 *  - discrete Fréchet measures (§5.1): the coupling (minimum total leash length, the
 *    paper's objective) and the distance (minimum longest leash, Eiter & Mannila 1994);
 *  - a Nelder-Mead minimiser (Nelder & Mead 1965, the paper's [NM65]) and a
 *    Levenberg-Marquardt one for least squares (ours, the default: 10-20 times fewer
 *    model traces);
 *  - single-piece fits, eq. (5): argmin_k C(h, H(k, Q, p0, L)) + lambda |k| (the paper's,
 *    Nelder-Mead), or the mean squared distance of samples and model points at the same
 *    arc length (least squares);
 *  - piecewise fits with recursive splitting (§5.3), pieces chained through the end pose
 *    of their predecessor so that the frame is continuous across joins; fixed layouts
 *    shared by every strand (§5.4).
 * See docs/helicoid-fitting.md for the choices made where the paper is vague. */
#ifndef HAIRKIT_CURVEFIT_H
#define HAIRKIT_CURVEFIT_H

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/optimize.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- discrete Fréchet measures (§5.1) ------------------------------------------- */

/* A coupling of polylines a (p points) and b (q points) is a sequence of pairs
 * (a_i, b_j) from (a_0, b_0) to (a_{p-1}, b_{q-1}) in which each step advances i, j or
 * both by one (the walkers never backtrack, the leashes never cross). All three
 * measures below are minima over couplings, computed by O(pq) dynamic programming in
 * O(min(p, q)) memory, and are exactly symmetric in (a, b).
 *
 * `work` must hold HK_FRECHET_WORK(p, q) doubles. These fast entry points do not
 * check their input: they return NaN when a pointer is NULL or a count < 1, and the
 * result is meaningless when a point is not finite (use hk_frechet_measures to check). */
#define HK_FRECHET_WORK(p, q) ((p) < (q) ? (p) : (q))

/* Minimum over couplings of the SUM of leash lengths (the paper's "Fréchet coupling",
 * C in eq. 5). Metres times pairs. */
HK_API double hk_frechet_coupling(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work);

/* The coupling divided by max(p, q), the fewest pairs any coupling has: a length in
 * metres, comparable across point counts (d for a curve against a copy of itself moved
 * by d perpendicular to its plane). Minimising it is minimising the coupling. */
HK_API double hk_frechet_coupling_normalized(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work);

/* Minimum over couplings of the LONGEST leash: the discrete Fréchet distance of Eiter &
 * Mannila (1994). Metres. */
HK_API double hk_frechet_distance(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work);

typedef struct hk_FrechetMeasures {
    double coupling;   /* sum of leashes of the best coupling (m) */
    double normalized; /* coupling / max(p, q) (m) */
    double distance;   /* discrete Fréchet distance (m) */
} hk_FrechetMeasures;

/* All three measures with checked input (counts >= 1, finite points) and its own work
 * memory: for occasional use; inner loops use the functions above with a workspace. */
HK_API hk_Status hk_frechet_measures(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, hk_FrechetMeasures *out,
                                     hk_Error *err);

/* ---- Nelder-Mead (Nelder & Mead 1965) -------------------------------------------- */

#define HK_NELDER_MEAD_MAX_PARAMS 16

typedef struct hk_NelderMeadDef {
    long max_evaluations; /* hard limit on calls of f (>= n + 1) */
    double x_tolerance;   /* stop when every vertex is within x_tolerance * |scale_j| of the
                             best one in every coordinate j ... */
    double f_tolerance;   /* ... and f(worst) - f(best) <= f_tolerance */
} hk_NelderMeadDef;

/* 2000 evaluations, x_tolerance 1e-8, f_tolerance 1e-12. */
HK_API hk_NelderMeadDef hk_default_nelder_mead_def(void);

/* Minimises f over n (0..16) parameters with the standard Nelder-Mead simplex moves:
 * reflection 1, expansion 2, contraction 0.5 (outside and inside), shrink 0.5, in the
 * ordering and acceptance rules of Lagarias et al. (1998). The initial simplex is x and
 * x + scale_j e_j (scale_j finite and non-zero). A NaN objective counts as +infinity (a
 * region where it is undefined is simply never accepted). result->converged: both
 * tolerances met (0: the evaluation limit stopped it). x is updated in place with the best
 * vertex. Deterministic (ties keep the older vertex first). Returns HK_ERR_INVALID for
 * bad arguments and HK_ERR_NUMERIC when f was NaN or +inf everywhere it was tried (x
 * is then left at the start). Never allocates. */
HK_API hk_Status hk_nelder_mead_minimize(int n, double *x, const double *scale, hk_ObjectiveFn f, void *user,
                                         const hk_NelderMeadDef *options, hk_MinimizeResult *result, hk_Error *err);

/* ---- Levenberg-Marquardt (src/helicoid/least_squares.c) ------------------------------ */

#define HK_LEAST_SQUARES_MAX_PARAMS    32
#define HK_LEAST_SQUARES_MAX_RESIDUALS 1000000

/* Residuals: writes the m values r(x); returns 0, or non-zero where r is undefined (the
 * step is then rejected, like one that does not lower the cost). */
typedef int (*hk_ResidualFn)(void *user, const double *x, double *residuals);

/* The Jacobian of the residuals at x: jac (m x n, column-major: column j at jac + j m)
 * gets d r_i / d x_j; returns 0, or non-zero where it is not available (forward
 * differences are then taken). */
typedef int (*hk_JacobianFn)(void *user, const double *x, double *jac);

typedef struct hk_LeastSquaresDef {
    long max_evaluations;  /* hard limit on calls of r (>= n + 2) */
    double x_tolerance;    /* stop when every |step_j| <= x_tolerance * |scale_j| ... */
    double f_tolerance;    /* ... or two accepted steps in a row each lowered the cost by
                              <= f_tolerance * cost ... */
    double g_tolerance;    /* ... or max_j |g_j scale_j| <= g_tolerance * cost (g = J^T r) ... */
    double gain_tolerance; /* ... or the next step's predicted gain (the damped linear
                              model's) is <= gain_tolerance * cost (0: never) */
} hk_LeastSquaresDef;

/* 400 evaluations, x_tolerance 1e-10, f_tolerance 1e-12, g_tolerance 1e-14,
 * gain_tolerance 0. */
HK_API hk_LeastSquaresDef hk_default_least_squares_def(void);

/* Doubles of work memory for n parameters and m residuals. */
#define HK_LEAST_SQUARES_WORK(n, m) ((size_t)(m) * ((size_t)(n) + 3))

/* Minimises sum r_i(x)^2 / 2 over n (1..32) parameters, m >= n residuals, by
 * Levenberg-Marquardt with a forward-difference Jacobian (step sqrt(eps) times
 * max(|x_j|, |scale_j|)), Marquardt's diagonal scaling and Nielsen's damping update.
 * x is updated in place with the best point found (never worse than the start).
 * result->f is the cost sum r_i^2 / 2 and result->converged says a tolerance was met (0:
 * the evaluation limit stopped it).
 * `work` holds HK_LEAST_SQUARES_WORK(n, m) doubles. Deterministic; never allocates.
 * HK_ERR_INVALID for bad arguments, HK_ERR_NUMERIC when r is undefined at the start. */
HK_API hk_Status hk_least_squares_minimize(int n, int m, double *x, const double *scale, hk_ResidualFn f, void *user,
                                           const hk_LeastSquaresDef *options, double *work, hk_MinimizeResult *result,
                                           hk_Error *err);

/* The same with the Jacobian given by jac (NULL: forward differences), called once per
 * accepted point instead of the n traces of the differences; result->evaluations counts
 * a call of jac as one evaluation. */
HK_API hk_Status hk_least_squares_minimize_jac(int n, int m, double *x, const double *scale, hk_ResidualFn f,
                                               hk_JacobianFn jac, void *user, const hk_LeastSquaresDef *options,
                                               double *work, hk_MinimizeResult *result, hk_Error *err);

/* ---- curve models ------------------------------------------------------------------- */

/* A pose on a curve: position and frame. The frame's columns are the unit tangent, the
 * normal and the binormal (T, N, B) of the paper's eq. (2), right-handed, world = frame *
 * local (as in vecmath.h). */
typedef struct hk_CurveStart {
    hk_Vec3 pos;
    hk_Mat3 frame;
} hk_CurveStart;

/* A curve model: traces `count` (>= 2) points of a curve of arc length `length` that
 * starts at `start`, out_points[0] = start->pos and out_points[i] at arc length
 * i * length / (count - 1) (a model traced with forward Euler steps, like the paper's
 * eq. 3, places them at that polyline length). Writes the pose at the last point to
 * `end` (never NULL), the pose the next piece of a p-helicoid starts from (§3.4, §5.3).
 * Tracing more points at the same spacing must reproduce the same leading points.
 * Returns 0 on success, non-zero when the parameters are unusable (the fit treats that
 * as an infinitely bad fit). Must be deterministic (a function of its arguments and
 * `user` alone: the fitter copies a recent trace of the same arguments instead of calling
 * it again) and thread-safe for distinct out_points. */
typedef int (*hk_CurveModelFn)(void *user, const double *params, const hk_CurveStart *start, double length, int count,
                               hk_Vec3 *out_points, hk_CurveStart *end);

/* A model's derivatives: traces as the model does (the same points and end pose, up to
 * rounding) and also d_points[j * count + i] = d out_points[i] / d params[j] and
 * d_end_tangent[j] = d (column 0 of end->frame) / d params[j], the start pose held
 * fixed (the fitter adds the start pose's own dependence on the parameters, for
 * models that are equivariant: a start pose turned about its position turns the whole
 * trace with it, as curves defined in their start frame are). 0 on success, non-zero
 * where the model fails. */
typedef int (*hk_CurveModelDerivFn)(void *user, const double *params, const hk_CurveStart *start, double length,
                                    int count, hk_Vec3 *out_points, hk_CurveStart *end, hk_Vec3 *d_points,
                                    hk_Vec3 *d_end_tangent);

/* A model: the discrete Frenet helix, params (kappa, tau) in 1/m, traced like the paper
 * traces helicoids (forward Euler, eq. 3): each step moves length / (count - 1) along T,
 * then turns the frame by kappa h about B and twists it by tau h about the new T. Its
 * vertices lie on a helix of curvature ~ kappa and torsion ~ tau; its first segment is
 * the start tangent and its first bend lies in the (T, N) plane, so
 * hk_curve_estimate_start recovers the start frame exactly (kappa > 0). user is unused;
 * non-zero only for count < 2. */
HK_API int hk_curve_model_frenet_helix(void *user, const double *params, const hk_CurveStart *start, double length,
                                       int count, hk_Vec3 *out_points, hk_CurveStart *end);

/* The pose a fit starts from, estimated from a polyline's first points (the paper's
 * "target hair h with estimated Frenet frame Q" [Ros03]): position = points[0]; tangent
 * = the first segment of non-zero length (exact for curves traced by forward Euler, as
 * the paper traces helicoids); normal = the part of the next chord orthogonal to the
 * tangent, from the first later point not collinear with the first segment (the
 * discrete Frenet frame of the first three non-collinear points); binormal = T x N.
 * When every point lies on the first segment's line (straight hair) the normal is the
 * world axis least aligned with the tangent, made orthogonal to it. HK_ERR_INVALID when
 * count < 2, a point is not finite or every point is the same. */
HK_API hk_Status hk_curve_estimate_start(const hk_Vec3 *points, int count, hk_CurveStart *out, hk_Error *err);

/* Resamples a polyline to `samples` (>= 2) points spaced uniformly by arc length along
 * it (first and last points kept exactly); *length (may be NULL) gets its length.
 * HK_ERR_INVALID for count < 2, non-finite points or zero length. */
HK_API hk_Status hk_curve_resample(const hk_Vec3 *points, int count, int samples, hk_Vec3 *out, double *length,
                                   hk_Error *err);

/* The same, uniformly by the arc length of the smooth curve the points sample: each
 * chord lengthened to the arc of the circle turning by the polyline's turning angles
 * there (chord * (phi/2) / sin(phi/2); exact for points on a circle). A curve sampled
 * at arc spacing s has chords shorter than s by s (kappa s)^2 / 24: fitting a model
 * traced at spacing s to chord-length samples leaves that much error per segment
 * (30 microns over a 10 cm curl of 3 cm radius at 3.4 mm spacing). *length gets the
 * estimated arc length. */
HK_API hk_Status hk_curve_resample_arc(const hk_Vec3 *points, int count, int samples, hk_Vec3 *out, double *length,
                                       hk_Error *err);

/* ---- fitting (§5.2, §5.3) ------------------------------------------------------------ */

#define HK_CURVEFIT_MAX_PIECES 64
#define HK_CURVEFIT_MAX_PARAMS 8
/* The coupling is O(samples^2) per evaluation: longer polylines are resampled (see
 * hk_CurveFitDef.samples) rather than fitted at full resolution. */
#define HK_CURVEFIT_MAX_SAMPLES 4096

/* How a piece's parameters are found. */
typedef enum hk_CurveFitMethod {
    /* Levenberg-Marquardt on the squared distances between the target's samples and the
     * model's points at the same arc length (the default: a few dozen traces per piece) */
    HK_CURVEFIT_LEAST_SQUARES = 0,
    /* the paper's: Nelder-Mead on the Fréchet coupling, eq. (5) (hundreds of traces) */
    HK_CURVEFIT_NELDER_MEAD = 1
} hk_CurveFitMethod;

typedef struct hk_CurveFitDef {
    hk_CurveFitMethod method;
    double lambda;                                 /* eq. (5) regularisation (m per unit of |params|), >= 0;
                                                      least squares adds (lambda |params|)^2 to the mean
                                                      squared distance */
    double penalty_weight[HK_CURVEFIT_MAX_PARAMS]; /* the regularisation's |k| is |W k|, W =
                                                      diag(penalty_weight), 0 meaning 1: parameters of other
                                                      units or meaning can be weighed (helicoid_fit.c) */
    double tolerance;                              /* accept a fit when its normalised coupling <= this (m) */
    double split_threshold;                        /* §5.3 Fréchet threshold in (0, 1]: 0.6 in the paper */
    double min_fragment_length;                    /* shortest piece the splitting creates (m), >= 0 */
    int max_pieces;                                /* 1..HK_CURVEFIT_MAX_PIECES; 1 = single fit (§5.2) */
    int fixed_pieces;                              /* 0: split where the target needs it (§5.3); P >= 1: P pieces
                                                      of equal length (sample counts differing by at most one),
                                                      the same layout for every strand, so that fits of
                                                      neighbouring strands can be blended piece by piece (§5.4);
                                                      a target too short for P minimal fragments gets as many as
                                                      it holds (at least one): see fit.piece_count */
    double piece_length;                           /* > 0 (instead of fixed_pieces): a layout by arc length from
                                                      the root, the same stretch of hair for piece j on strands
                                                      of any length: the first piece root_piece_length long (0:
                                                      piece_length), the next ones piece_length, the last one
                                                      what is left (m) */
    double root_piece_length;
    int max_evaluations;    /* per minimiser run (>= param_count + 1; a fit makes
                               a few runs, see fit.evaluations for the total) */
    int samples;            /* points the target is resampled to; 0 = its own count */
    int arc_length;         /* 0: the model places its points at polyline spacing (forward
                               Euler traces, like the paper's eq. 3): resample the target
                               by polyline length; 1: at arc-length spacing on a smooth
                               curve (RK4, closed forms): resample by estimated arc length
                               (hk_curve_resample_arc) */
    int restarts;           /* Nelder-Mead restarts from a converged simplex that
                               still misses the tolerance (0..100) */
    double param_tolerance; /* NM stop: simplex size relative to `scale` (least
                               squares: a step of 1e-3 times this) */
    double cost_tolerance;  /* NM stop: spread of the objective (m) */
    int use_start;          /* non-zero: start from `start` instead of estimating it */
    hk_CurveStart start;    /* the root pose when use_start is set */
    /* NULL, or the model's rule for its frame at the root: given the start pose (the
     * estimated Frenet frame, or `start`) and the first piece's parameters, turn it
     * into the frame the model is traced from (a helicoid's Frenet normal is rolled
     * from its field's E_N by atan(alpha), helicoid_fit.c). Pieces after the first
     * start from their predecessor's end pose, unchanged. */
    void (*root_frame)(void *user, const double *params, hk_CurveStart *start);
    /* NULL, or the model's guess of a piece's parameters from its fragment (points,
     * count >= 3, at the fit's spacing) and the pose it starts from (for a root piece
     * the estimated pose, before root_frame): tried as a starting point beside `seed`
     * and the fits of overlapping ranges. */
    void (*fragment_seed)(void *user, const hk_Vec3 *points, int count, const hk_CurveStart *start, double *params);
    /* NULL, or the model's derivatives (hk_CurveModelDerivFn): Levenberg-Marquardt then
     * takes its Jacobian from one differentiated trace instead of param_count + 1 traces
     * of forward differences. The model must be equivariant (see there). */
    hk_CurveModelDerivFn model_derivative;
    /* NULL, or the model the result is finished with, when `model` is a cheaper
     * discretisation of the same curves that the search for the pieces traces: each
     * piece found is then fitted again from its parameters with this one (one
     * Levenberg-Marquardt run, from its predecessor's new end pose; kept when the chain
     * comes out closer), and the output's errors and polish are this model's.
     * final_derivative: its derivatives, or those of a close approximation such as
     * `model`'s (they only steer the runs' steps; the residuals are final_model's;
     * NULL: differences). */
    hk_CurveModelFn final_model;
    hk_CurveModelDerivFn final_derivative;
    int refine_start;   /* 1: a first piece that misses the tolerance in the root
                           frame is refitted with a rotation of that frame (3 more
                           Nelder-Mead parameters), for noisy captures whose first
                           points give a poor frame; 0: keep the frame as it is */
    int known_to_split; /* least squares: 0 (default) fits the whole target in one piece
                           before looking for cuts; 1: the caller knows one piece
                           misses (a second try of a strand that did), and the cuts
                           are searched for at once */
} hk_CurveFitDef;

/* lambda 1e-7 m, tolerance 0.2 mm, split_threshold 0.6, min_fragment_length 5 mm,
 * max_pieces 16, max_evaluations 1000, samples 0, restarts 1, param_tolerance 1e-5,
 * cost_tolerance 1e-8 m, use_start 0, refine_start 1, known_to_split 0. */
HK_API hk_CurveFitDef hk_default_curve_fit_def(void);

typedef struct hk_CurveFit {
    int piece_count;
    int param_count;
    int sample_count;      /* points of the resampled target */
    double sample_spacing; /* their spacing (m) */
    hk_CurveStart start;   /* the pose the first piece starts from: the
                              estimated (or given) root pose, turned when
                              refine_start refined it */
    double params[HK_CURVEFIT_MAX_PIECES][HK_CURVEFIT_MAX_PARAMS];
    double length[HK_CURVEFIT_MAX_PIECES];        /* arc length of each piece (m) */
    int first_sample[HK_CURVEFIT_MAX_PIECES];     /* index of a piece's first sample; the
                                                     piece ends at the next one's first */
    double piece_error[HK_CURVEFIT_MAX_PIECES];   /* normalised coupling vs its fragment (m) */
    double piece_frechet[HK_CURVEFIT_MAX_PIECES]; /* Fréchet distance vs its fragment (m) */
    double error;     /* normalised coupling of the chained pieces vs the resampled target (m) */
    double frechet;   /* discrete Fréchet distance, same pair (m) */
    long evaluations; /* model evaluations in all */
} hk_CurveFit;

/* Work memory of the fits for targets of up to `max_samples` resampled points: create one
 * per thread and reuse it, so that fitting never allocates. */
typedef struct hk_CurveFitWorkspace hk_CurveFitWorkspace;
HK_API hk_CurveFitWorkspace *hk_curve_fit_workspace_create(int max_samples, hk_Error *err);
HK_API void hk_curve_fit_workspace_destroy(hk_CurveFitWorkspace *ws);

/* Fits a chain of model pieces to the target polyline (count points):
 *  1. the target is resampled uniformly by arc length (opt->samples points, default
 *     its own count) and the root pose estimated (hk_curve_estimate_start) unless given;
 *  2. the whole target is fitted, eq. (5), Nelder-Mead from the best of the seeds; with
 *     refine_start, a fit at the root that misses the tolerance is redone with the root
 *     frame's rotation free;
 *  3. if its normalised coupling exceeds opt->tolerance the target is split (§5.3: the
 *     Fréchet threshold gives an upper limit, a comparison of bends backtracks from
 *     it) and both parts are fitted recursively, the second starting at the end pose of
 *     the first; a split that ends up worse than the unsplit fit is undone.
 * Pieces span at least min_fragment_length and max(param_count + 2, 4) samples.
 * Deterministic; thread-safe with one workspace per thread (and a thread-safe model).
 * `seed` and `scale` have param_count (0..HK_CURVEFIT_MAX_PARAMS) entries; scale gives
 * the initial simplex steps (finite, non-zero); opt NULL means the defaults. Errors: HK_ERR_INVALID for bad input,
 * HK_ERR_NUMERIC when the model fails for every parameter vector tried. */
HK_API hk_Status hk_curve_fit_piecewise_ws(hk_CurveFitWorkspace *ws, const hk_Vec3 *target, int count,
                                           hk_CurveModelFn model, void *user, int param_count, const double *seed,
                                           const double *scale, const hk_CurveFitDef *opt, hk_CurveFit *out,
                                           hk_Error *err);

/* The same with a workspace of its own (one allocation per call). */
HK_API hk_Status hk_curve_fit_piecewise(const hk_Vec3 *target, int count, hk_CurveModelFn model, void *user,
                                        int param_count, const double *seed, const double *scale,
                                        const hk_CurveFitDef *opt, hk_CurveFit *out, hk_Error *err);

/* Traces a fit's chained pieces at its sample spacing into out (fit->sample_count
 * points). HK_ERR_INVALID for a malformed fit, HK_ERR_NUMERIC when the model fails. */
HK_API hk_Status hk_curve_fit_trace(const hk_CurveFit *fit, hk_CurveModelFn model, void *user, hk_Vec3 *out,
                                    hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_CURVEFIT_H */
