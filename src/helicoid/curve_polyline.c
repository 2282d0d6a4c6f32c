/* Polyline helpers of the fitting (helicoid paper 003 §5.2): uniform resampling by arc
 * length, the start pose ("target hair h with estimated Frenet frame Q" [Ros03]) and the
 * discrete curvature vectors the split heuristics of §5.3 compare. */
#include <math.h>

#include "helicoid/curvefit_internal.h"

hk_Status hk_curve_resample(const hk_Vec3 *points, int count, int samples, hk_Vec3 *out,
                            double *length, hk_Error *err)
{
    if (!points || !out) return hk_error_set(err, HK_ERR_INVALID, "resample: NULL argument");
    if (count < 2) return hk_error_set(err, HK_ERR_INVALID, "resample: a polyline needs at least 2 points, got %d", count);
    if (samples < 2) return hk_error_set(err, HK_ERR_INVALID, "resample: need at least 2 samples, got %d", samples);
    double total = 0.0;
    for (int i = 0; i < count; i++) {
        if (!hk_v3_isfinite(points[i]))
            return hk_error_set(err, HK_ERR_INVALID, "resample: point %d is not finite", i);
        if (i > 0) total += hk_v3_dist(points[i - 1], points[i]);
    }
    if (!(total > 0.0) || !isfinite(total))
        return hk_error_set(err, HK_ERR_INVALID, "resample: the polyline has %s length",
                            total > 0.0 ? "infinite" : "zero");
    /* Walk the segments once; the running length is summed in the same order as the
     * total, so an evenly spaced polyline resampled to its own count comes back equal
     * to rounding. */
    int seg = 0;
    double seg_start = 0.0, seg_len = hk_v3_dist(points[0], points[1]);
    out[0] = points[0];
    for (int k = 1; k < samples - 1; k++) {
        const double s = total * (double)k / (double)(samples - 1);
        while (seg < count - 2 && seg_start + seg_len < s) {
            seg_start += seg_len;
            seg++;
            seg_len = hk_v3_dist(points[seg], points[seg + 1]);
        }
        double t = seg_len > 0.0 ? (s - seg_start) / seg_len : 0.0;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        out[k] = hk_v3_madd(points[seg], hk_v3_sub(points[seg + 1], points[seg]), t);
    }
    out[samples - 1] = points[count - 1];
    if (length) *length = total;
    return HK_OK;
}

/* Squared sine of the angle below which a chord counts as collinear with the tangent:
 * 1e-8 rad, far above rounding, far below any bend a fit could care about. */
#define COLLINEAR_SIN2 1e-16

hk_Status hk_curve_estimate_start(const hk_Vec3 *points, int count, hk_CurveStart *out, hk_Error *err)
{
    if (!points || !out) return hk_error_set(err, HK_ERR_INVALID, "start pose: NULL argument");
    if (count < 2) return hk_error_set(err, HK_ERR_INVALID, "start pose: need at least 2 points, got %d", count);
    for (int i = 0; i < count; i++)
        if (!hk_v3_isfinite(points[i])) return hk_error_set(err, HK_ERR_INVALID, "start pose: point %d is not finite", i);
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
