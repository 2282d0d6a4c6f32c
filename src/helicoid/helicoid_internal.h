/* Pieces of the helicoid module shared between src/helicoid/ files: the field evaluation of
 * eq. 1-2 (inline: it is the inner loop of tracing), the two piece integrators and the
 * strand-level tracer with its piece placements. */
#ifndef HK_HELICOID_INTERNAL_H
#define HK_HELICOID_INTERNAL_H

#include <math.h>

#include "hairkit/curvefit.h"
#include "hairkit/hairfile.h"
#include "hairkit/helicoid.h"


/* The angles of the field at one point, with their sines and cosines (the frame of eq. 2 and
 * the tangent need only these, so tracing takes each sine once). */
typedef struct hk_HelicoidAngles {
    double theta;  /* continued: the 2 pi cycles are counted along the path */
    double ct, st; /* cos, sin theta */
    double cp, sp; /* cos, sin phi, phi = alpha theta */
} hk_HelicoidAngles;

/* Eq. 1 at the local point (x, y, z): the arctangent is the argument of the complex number
 * w = 1 + (k_N + i k_T)(x + i y) (its real and imaginary parts are eq. 1's denominator and
 * numerator), taken on the branch nearest to theta_ref. atan2 alone jumps by 2 pi where w
 * crosses the negative real axis, and phi = alpha theta would jump with it. */
static inline void hk_helicoid_eval(const hk_Helicoid *k, double x, double y, double z, double theta_ref,
                                    hk_HelicoidAngles *a)
{
    const double wr = 1.0 + k->kn * x - k->kt * y, wi = k->kt * x + k->kn * y;
    double t = atan2(wi, wr) + k->kb * z;
    if (fabs(theta_ref - t) > HK_PI) /* rare: only after a 2 pi cycle */
        t += (2.0 * HK_PI) * round((theta_ref - t) * (1.0 / (2.0 * HK_PI)));
    a->theta = t;
    a->ct = cos(t);
    a->st = sin(t);
    if (k->alpha != 0.0) {
        const double phi = k->alpha * t;
        a->cp = cos(phi);
        a->sp = sin(phi);
    } else {
        a->cp = 1.0;
        a->sp = 0.0;
    }
}

/* The bound on how fast the field's direction turns along a strand (rad per unit length)
 * where |w| = W: per_w / W + constant, with per_w = |k_N + i k_T| (1 + |alpha|) and
 * constant = |k_B| (1 + |alpha|) (the gradient of theta = arg w + k_B z, and phi = alpha
 * theta). The tracer's substeps and the fitter's resolution rule both use it. */
static inline void hk_helicoid_turn_bound(const hk_Helicoid *k, double *per_w, double *constant)
{
    const double a = 1.0 + fabs(k->alpha);
    *per_w = hypot(k->kt, k->kn) * a;
    *constant = fabs(k->kb) * a;
}

/* Eq. 2 from the sines and cosines: columns E_T, E_N, E_B. */
static inline hk_Mat3 hk_helicoid_frame_of(const hk_HelicoidAngles *a)
{
    return hk_m3_from_cols(hk_v3(a->cp * a->ct, a->cp * a->st, a->sp), hk_v3(-a->st, a->ct, 0.0),
                           hk_v3(-a->sp * a->ct, -a->sp * a->st, a->cp));
}

/* One piece as placed in the world: its field's origin and frame, its length and steps. */
typedef struct hk_HelicoidPiece {
    const hk_Helicoid *k;
    hk_Vec3 origin;
    hk_Mat3 frame;
    double length;
    int steps; /* >= 1; the step is length / steps */
} hk_HelicoidPiece;

/* Where a piece's points go: entry j (1..steps) is the point after j steps. Either pointer may
 * be NULL; wave (NULL or amplitude 0: none) offsets the points, s_start being the strand's arc
 * length at the piece's start (the phase of eq. 4). */
typedef struct hk_HelicoidSink {
    hk_Vec3 *points;
    hk_Mat3 *frames;
    const hk_Waviness *wave;
    double s_start;
} hk_HelicoidSink;

/* Writes point j of a piece from its local position and angles: world = origin + Q x, frame
 * Q F(theta, phi) (eq. 2 carried to the world), waviness of eq. 4 at arc length s. */
static inline void hk_helicoid_emit(const hk_HelicoidPiece *pc, const hk_HelicoidSink *out, int j, double x, double y,
                                    double z, const hk_HelicoidAngles *a, double s)
{
    if (!out->points && !out->frames) return;
    const hk_Mat3 *q = &pc->frame;
    /* The same arithmetic as the tracer's piece ends, so a join is bitwise the next origin. */
    hk_Vec3 p = hk_v3_add(pc->origin, hk_m3_mul_v3(q, hk_v3(x, y, z)));
    const int waved = out->wave && out->wave->amplitude != 0.0;
    if (out->frames || waved) {
        const hk_Mat3 f = hk_helicoid_frame_of(a);
        const hk_Mat3 w = hk_m3_mul(q, &f);
        if (out->frames) out->frames[j] = w;
        if (waved) {
            const double b = out->wave->frequency * s + out->wave->phase, amp = out->wave->amplitude;
            p = hk_v3_madd(p, hk_m3_col(&w, 2), amp * cos(b));
            p = hk_v3_madd(p, hk_m3_col(&w, 1), amp * sin(b));
        }
    }
    if (out->points) out->points[j] = p;
}

/* Piece integrators. On entry *p is the local start point and *a the angles there (continued
 * branch); on exit the end point and its angles. Points 1..steps go to out. */
/* Classical RK4 on dx/ds = E_T(theta(x), phi(x)) (any k). */
void hk_helicoid_piece_rk4(const hk_HelicoidPiece *pc, hk_Vec3 *p, hk_HelicoidAngles *a, const hk_HelicoidSink *out);
/* The closed-form streamline for alpha = 0 (a logarithmic spiral, circle or line in the plane
 * z = const); exact. */
void hk_helicoid_piece_planar(const hk_HelicoidPiece *pc, hk_Vec3 *p, hk_HelicoidAngles *a, const hk_HelicoidSink *out);

/* RK4 from the local origin (theta = 0) over `length` in `steps` output steps, with the
 * derivatives of the trace with respect to k = (k_T, k_N, k_B, alpha) (piece_rk4_tangent.c):
 * points[0..steps] local positions (the same steps and substeps as hk_helicoid_piece_rk4),
 * d_points[j * (steps + 1) + i] = d points[i] / d k_j, end the angles at the last point
 * and d_end_tangent[j] the derivative of its tangent E_T (local). */
void hk_helicoid_piece_rk4_tangent(const hk_Helicoid *k, double length, int steps, hk_Vec3 *points, hk_Vec3 *d_points,
                                   hk_HelicoidAngles *end, hk_Vec3 *d_end_tangent);

/* The fitter's search trace (piece_rk4.c), from the local origin over `length` in `steps`
 * output steps: points[0..steps] local, end the angles at the last point (theta not
 * carried: 0). RK4 steps that turn the field by at most `turn` (hk_helicoid_piece_rk4:
 * MAX_TURN_PER_STEP), one spanning up to `span` output steps where the bound allows it
 * over the whole step, the points inside it by cubic Hermite interpolation; the phases
 * e^{i k_B z} and e^{i phi} integrated with the position instead of taken by sincos
 * (rk4_field.h): the same curve to RK4's error. */
void hk_helicoid_piece_rk4_local(const hk_Helicoid *k, double length, int steps, double turn, int span, hk_Vec3 *points,
                                 hk_HelicoidAngles *end);
/* And with the derivatives, as hk_helicoid_piece_rk4_tangent's (piece_rk4_tangent.c): the
 * same bytes as hk_helicoid_piece_rk4_local for the points and end. */
void hk_helicoid_piece_rk4_tangent_local(const hk_Helicoid *k, double length, int steps, double turn, int span,
                                         hk_Vec3 *points, hk_Vec3 *d_points, hk_HelicoidAngles *end,
                                         hk_Vec3 *d_end_tangent);

/* Steps of a piece of length `length` with the largest step `step`: ceil(length / step) with a
 * 1e-12 relative tolerance; -1 when not finite or above HK_HELICOID_MAX_POINTS. */
int hk_helicoid_piece_steps(double length, double step);

typedef enum hk_HelicoidMethod {
    HK_HELICOID_AUTO = 0, /* closed form where alpha = 0, RK4 elsewhere */
    HK_HELICOID_RK4 = 1   /* RK4 everywhere (the tests compare it with the closed forms) */
} hk_HelicoidMethod;

/* Where each piece's field sits in the world (origin and frame of eq. 2 carried along). */
typedef struct hk_HelicoidPlacement {
    hk_Vec3 origin[HK_HELICOID_MAX_PIECES];
    hk_Mat3 frame[HK_HELICOID_MAX_PIECES];
} hk_HelicoidPlacement;

/* The tracer behind hk_phelicoid_trace, for a valid h and step (checked by the caller) and
 * outputs sized by hk_phelicoid_point_count. placement: NULL = the strand places its own
 * pieces (then offset must be NULL); else the pieces' fields sit there (see
 * hk_phelicoid_place). placed (may be NULL) receives the placement this trace produced.
 * HK_ERR_NUMERIC when the trace is not finite. */
hk_Status hk_phelicoid_trace_with(const hk_PHelicoid *h, double step, hk_HelicoidMethod method, const hk_Waviness *wave,
                                  const hk_Vec3 *offset, const hk_HelicoidPlacement *placement, hk_Vec3 *points,
                                  hk_Mat3 *frames, hk_HelicoidPlacement *placed, hk_Error *err);

/* Unit quaternions (w, x, y, z) of rotations: for the frame averages of interpolation. */
void hk_helicoid_quat_from_rotation(const hk_Mat3 *r, double q[4]);
hk_Mat3 hk_helicoid_rotation_from_quat(const double q[4]);
/* Rotation by `angle` (radians) about the unit axis a (Rodrigues). */
hk_Mat3 hk_helicoid_axis_angle(hk_Vec3 a, double angle);

/* Normalised coupling and Fréchet distance (hk_frechet_measures) of h traced with `wave`
 * (may be NULL) at the strand's own count of points against points[0..n), n >= 2; work
 * holds n points. HK_ERR_NUMERIC when h does not trace to n points at that spacing. */
hk_Status hk_helicoid_traced_measures(const hk_PHelicoid *h, const hk_Waviness *wave, const hk_Vec3 *points, int n,
                                      hk_Vec3 *work, hk_FrechetMeasures *m, hk_Error *err);

/* Every strand of `hair` rebuilt from the fitted guides (reconstruct_blend.c, §5.4) into
 * `out` (filled here): points `step` apart or closer, each strand at its own length, from
 * its own root and root direction. In parallel; the same bytes whatever the threads. */
hk_Status hk_helicoid_rebuild(const hk_HairFile *hair, const hk_PHelicoid *guides, int guide_count, double power,
                              double step, int threads, hk_HairFile *out, hk_Error *err);

#endif
