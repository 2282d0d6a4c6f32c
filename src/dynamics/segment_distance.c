/* Closest points of two segments, the distance every hair-hair pair is measured by
 * (paper 000 §4.1: "pairs of closest points"). The squared distance is a convex
 * quadratic over (u, v) in [0, 1]^2: its minimum is the interior critical point when
 * that lies in the square, otherwise on one of the four edges, each a point-segment
 * problem (as in Ericson, Real-Time Collision Detection §5.1.9, but trying all edges
 * so that parallel and zero-length segments need no special tolerance). */
#include "hair_contacts_internal.h"

static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

/* Parameter on [q0, q0 + d] (|d|^2 = dd) of the point closest to p. */
static double point_segment(hk_Vec3 p, hk_Vec3 q0, hk_Vec3 d, double dd)
{
    return dd > 0.0 ? clamp01(hk_v3_dot(hk_v3_sub(p, q0), d) / dd) : 0.0;
}

static double dist2_at(hk_Vec3 p0, hk_Vec3 d1, hk_Vec3 q0, hk_Vec3 d2, double u, double v)
{
    return hk_v3_norm2(hk_v3_sub(hk_v3_madd(p0, d1, u), hk_v3_madd(q0, d2, v)));
}

/* hk_segment_closest's body, inlined into both its callers: the broad phase measures
 * through hk_hc_ends_distance2, and the call with four vectors by value cost ~20 % of
 * a measure (~120 instructions; examples/guides200 shaking, 24,000 a step). */
static inline __attribute__((always_inline)) double closest(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, double *u,
                                                            double *v)
{
    const hk_Vec3 d1 = hk_v3_sub(p1, p0), d2 = hk_v3_sub(q1, q0), r = hk_v3_sub(p0, q0);
    const double a = hk_v3_dot(d1, d1), e = hk_v3_dot(d2, d2), b = hk_v3_dot(d1, d2);
    const double c = hk_v3_dot(d1, r), f = hk_v3_dot(d2, r);
    /* Interior critical point: a u - b v = -c, -b u + e v = f. Only trusted when the
     * segments are clearly not parallel (the determinant is a e sin^2 of their angle);
     * otherwise the minimum over the edges below is exact anyway. */
    const double det = a * e - b * b;
    if (det > 1e-12 * a * e && det > 0.0) {
        const double uu = (b * f - c * e) / det, vv = (a * f - b * c) / det;
        if (uu >= 0.0 && uu <= 1.0 && vv >= 0.0 && vv <= 1.0) {
            *u = uu;
            *v = vv;
            return dist2_at(p0, d1, q0, d2, uu, vv);
        }
    }
    /* The edges u = 0, u = 1, v = 0, v = 1, in this order; the first strictly
     * smallest wins, so equal candidates always resolve the same way. */
    double cu[4], cv[4];
    cu[0] = 0.0, cv[0] = point_segment(p0, q0, d2, e);
    cu[1] = 1.0, cv[1] = point_segment(p1, q0, d2, e);
    cv[2] = 0.0, cu[2] = point_segment(q0, p0, d1, a);
    cv[3] = 1.0, cu[3] = point_segment(q1, p0, d1, a);
    int best = 0;
    double best_d2 = dist2_at(p0, d1, q0, d2, cu[0], cv[0]);
    for (int k = 1; k < 4; k++) {
        double d = dist2_at(p0, d1, q0, d2, cu[k], cv[k]);
        if (d < best_d2) best_d2 = d, best = k;
    }
    *u = cu[best];
    *v = cv[best];
    return best_d2;
}

double hk_segment_closest(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, double *u, double *v)
{
    return closest(p0, p1, q0, q1, u, v);
}

double hk_hc_ends_distance2(const hk_HcEnds *x, const hk_HcEnds *y, double *u, double *v)
{
    double uc, vc;
    const double d2 = closest(x->p0, x->p1, y->p0, y->p1, &uc, &vc);
    *u = x->t0 + uc * (1.0 - x->t0);
    *v = y->t0 + vc * (1.0 - y->t0);
    return d2;
}
