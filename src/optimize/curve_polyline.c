/* Polyline helpers of the fitting (Piuze et al. 2011 §5.2): uniform resampling by arc
 * length, the start pose ("target hair h with estimated Frenet frame Q" [Ros03]) and the
 * discrete curvature vectors the split heuristics of §5.3 compare. */
#include <math.h>

#include "optimize/curvefit_internal.h"

/* Turning angle (rad) at vertex i of a polyline, 0 at its ends and where a segment is
 * degenerate. */
static double turning_angle(const hk_Vec3 *points, int count, int i)
{
    if (i <= 0 || i >= count - 1) return 0.0;
    const hk_Vec3 a = hk_v3_sub(points[i], points[i - 1]), b = hk_v3_sub(points[i + 1], points[i]);
    return atan2(hk_v3_norm(hk_v3_cross(a, b)), hk_v3_dot(a, b));
}

/* Length given to segment i (points i, i + 1): the chord, or with `arc` the arc of the
 * circle that turns by the mean of the turning angles at its ends (the interior one at
 * the polyline's ends): for points spaced by arc length s on a circle of radius R each
 * vertex turns by phi = s / R and the chord is 2 R sin(phi / 2), so the arc is
 * chord * (phi / 2) / sin(phi / 2), exact on circles and helices' osculating circles
 * to O(s^2) where the curvature varies. */
static double segment_length(const hk_Vec3 *points, int count, int i, int arc)
{
    const double chord = hk_v3_dist(points[i], points[i + 1]);
    if (!arc || count < 3) return chord;
    const double t0 = turning_angle(points, count, i), t1 = turning_angle(points, count, i + 1);
    const double phi = i == 0 ? t1 : (i + 1 == count - 1 ? t0 : 0.5 * (t0 + t1));
    const double half = 0.5 * phi;
    /* x / sin x = 1 + x^2 / 6 + 7 x^4 / 360 + ...: the series below 1e-4 rad, where the
     * quotient loses digits; the turning angle is at most pi, half of it pi / 2. */
    return chord * (half < 1e-4 ? 1.0 + half * half / 6.0 : half / sin(half));
}

static hk_Status resample(const hk_Vec3 *points, int count, int samples, int arc, hk_Vec3 *out, double *length,
                          hk_Error *err)
{
    if (!points || !out) return hk_error_set(err, HK_ERR_INVALID, "resample: NULL argument");
    if (count < 2)
        return hk_error_set(err, HK_ERR_INVALID, "resample: a polyline needs at least 2 points, got %d", count);
    if (samples < 2) return hk_error_set(err, HK_ERR_INVALID, "resample: need at least 2 samples, got %d", samples);
    for (int i = 0; i < count; i++)
        if (!hk_v3_isfinite(points[i])) return hk_error_set(err, HK_ERR_INVALID, "resample: point %d is not finite", i);
    double total = 0.0;
    for (int i = 0; i + 1 < count; i++) total += segment_length(points, count, i, arc);
    if (!(total > 0.0) || !isfinite(total))
        return hk_error_set(err, HK_ERR_INVALID, "resample: the polyline has %s length",
                            total > 0.0 ? "infinite" : "zero");
    /* Walk the segments once; the running length is summed in the same order as the
     * total, so an evenly spaced polyline resampled to its own count comes back equal
     * to rounding. A sample within a segment is placed on its chord, in proportion. */
    int seg = 0;
    double seg_start = 0.0, seg_len = segment_length(points, count, 0, arc);
    out[0] = points[0];
    for (int k = 1; k < samples - 1; k++) {
        const double s = total * (double)k / (double)(samples - 1);
        while (seg < count - 2 && seg_start + seg_len < s) {
            seg_start += seg_len;
            seg++;
            seg_len = segment_length(points, count, seg, arc);
        }
        double t = seg_len > 0.0 ? (s - seg_start) / seg_len : 0.0;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        out[k] = hk_v3_madd(points[seg], hk_v3_sub(points[seg + 1], points[seg]), t);
    }
    out[samples - 1] = points[count - 1];
    if (length) *length = total;
    return HK_OK;
}

hk_Status hk_curve_resample(const hk_Vec3 *points, int count, int samples, hk_Vec3 *out, double *length, hk_Error *err)
{
    return resample(points, count, samples, 0, out, length, err);
}

hk_Status hk_curve_resample_arc(const hk_Vec3 *points, int count, int samples, hk_Vec3 *out, double *length,
                                hk_Error *err)
{
    return resample(points, count, samples, 1, out, length, err);
}

/* Squared sine of the angle below which a chord counts as collinear with the tangent:
 * 1e-8 rad, far above rounding, far below any bend a fit could care about. */
#define COLLINEAR_SIN2 1e-16

hk_Status hk_curve_estimate_start(const hk_Vec3 *points, int count, hk_CurveStart *out, hk_Error *err)
{
    if (!points || !out) return hk_error_set(err, HK_ERR_INVALID, "start pose: NULL argument");
    if (count < 2) return hk_error_set(err, HK_ERR_INVALID, "start pose: need at least 2 points, got %d", count);
    for (int i = 0; i < count; i++)
        if (!hk_v3_isfinite(points[i]))
            return hk_error_set(err, HK_ERR_INVALID, "start pose: point %d is not finite", i);
    int i1 = 1;
    while (i1 < count && hk_v3_norm2(hk_v3_sub(points[i1], points[0])) == 0.0) i1++;
    if (i1 == count) return hk_error_set(err, HK_ERR_INVALID, "start pose: all %d points are the same", count);
    /* The paper traces with forward Euler (eq. 3): p1 - p0 = h E_T(p0), so the first
     * segment is the tangent itself, not an approximation of it. */
    const hk_Vec3 t = hk_v3_normalize(hk_v3_sub(points[i1], points[0]));
    hk_Vec3 n = hk_v3_zero();
    for (int k = i1 + 1; k < count; k++) {
        const hk_Vec3 d = hk_v3_sub(points[k], points[i1]);
        const hk_Vec3 perp = hk_v3_madd(d, t, -hk_v3_dot(d, t));
        if (hk_v3_norm2(perp) > COLLINEAR_SIN2 * hk_v3_norm2(d)) {
            n = hk_v3_normalize(perp);
            break;
        }
    }
    if (hk_v3_norm2(n) == 0.0) {
        /* Straight: any normal will do, the model's parameters rotate the bend into
         * place; take the world axis least aligned with t, deterministic and well
         * conditioned (|t_i| <= 1/sqrt(3) for that axis). */
        int axis = 0;
        for (int i = 1; i < 3; i++)
            if (fabs(hk_v3_get(t, i)) < fabs(hk_v3_get(t, axis))) axis = i;
        const hk_Vec3 e = hk_v3_unit(axis);
        n = hk_v3_normalize(hk_v3_madd(e, t, -hk_v3_dot(e, t)));
    }
    out->pos = points[0];
    out->frame = hk_m3_from_cols(t, n, hk_v3_cross(t, n));
    return HK_OK;
}

/* Below this turning angle (rad) a corner has no usable binormal, so no twist. */
#define TWIST_MIN_TURN 1e-3

void hk_polyline_bend(const hk_Vec3 *points, int i, double *turn, double *twist)
{
    const hk_Vec3 t0 = hk_v3_sub(points[i], points[i - 1]);
    const hk_Vec3 t1 = hk_v3_sub(points[i + 1], points[i]);
    const hk_Vec3 t2 = hk_v3_sub(points[i + 2], points[i + 1]);
    const hk_Vec3 b1 = hk_v3_cross(t0, t1), b2 = hk_v3_cross(t1, t2);
    /* atan2 keeps the angles accurate from 0 to pi, where asin or acos lose them. */
    const double a1 = atan2(hk_v3_norm(b1), hk_v3_dot(t0, t1));
    const double a2 = atan2(hk_v3_norm(b2), hk_v3_dot(t1, t2));
    *turn = a1;
    *twist = 0.0;
    if (a1 > TWIST_MIN_TURN && a2 > TWIST_MIN_TURN) {
        /* Signed angle from b1 to b2 about t1: the dihedral angle of the two osculating
         * planes, the discrete torsion times the spacing. */
        const double s = hk_v3_dot(hk_v3_cross(b1, b2), t1) / hk_v3_norm(t1);
        *twist = atan2(s, hk_v3_dot(b1, b2));
    }
}
