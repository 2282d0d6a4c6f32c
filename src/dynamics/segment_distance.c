/* Closest points of two segments, the distance every hair-hair pair is measured by
 * (paper 000 §4.1: "pairs of closest points"). The squared distance is a convex
 * quadratic over (u, v) in [0, 1]^2: its minimum is the interior critical point when
 * that lies in the square, otherwise on one of the four edges, each a point-segment
 * problem (as in Ericson, Real-Time Collision Detection §5.1.9, but trying all edges
 * so that parallel and zero-length segments need no special tolerance). */
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "hair_contacts_internal.h"

#ifndef __SSE2__
static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

/* Parameter on [q0, q0 + d] (|d|^2 = dd) of the point closest to p. */
static double point_segment(hk_Vec3 p, hk_Vec3 q0, hk_Vec3 d, double dd)
{
    return dd > 0.0 ? clamp01(hk_v3_dot(hk_v3_sub(p, q0), d) / dd) : 0.0;
}
#endif

static double dist2_at(hk_Vec3 p0, hk_Vec3 d1, hk_Vec3 q0, hk_Vec3 d2, double u, double v)
{
    return hk_v3_norm2(hk_v3_sub(hk_v3_madd(p0, d1, u), hk_v3_madd(q0, d2, v)));
}

/* The first strictly smallest of the four edges' squared distances (u = 0, u = 1,
 * v = 0, v = 1 in this order), so that equal candidates always resolve the same way. */
static double pick_edge(const double d[4], const double cu[4], const double cv[4], double *u, double *v)
{
    int best = 0;
    for (int k = 1; k < 4; k++)
        if (d[k] < d[best]) best = k;
    *u = cu[best];
    *v = cv[best];
    return d[best];
}

#ifdef __SSE2__
/* The measure two lanes at a time (SSE2, part of x86-64). Every lane does the
 * operations of the scalar expression it stands for (the code without SSE2, kept
 * below), in the same order (hk_v3_dot's x, y, then z; hk_v3_madd's a + s b): the same
 * bits. Lanes (segment p, segment q) hold (d1, d2), (a, e), (c, f), the edges'
 * point-to-segment parameters (u on v = 0, v on u = 0) and (u on v = 1, v on u = 1),
 * then the edges' squared distances (u = 0, v = 0) and (u = 1, v = 1). On
 * examples/guides200 shaking, where the edges are 94 % of the measures, 264 instead of
 * 323 instructions a measure (callgrind), and three divisions instead of six. */
static __m128d lo2(__m128d x) { return _mm_unpacklo_pd(x, x); }
static __m128d hi2(__m128d x) { return _mm_unpackhi_pd(x, x); }
static __m128d swap2(__m128d x) { return _mm_shuffle_pd(x, x, 1); }
static __m128d dot2(__m128d ax, __m128d ay, __m128d az, __m128d bx, __m128d by, __m128d bz)
{
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(ax, bx), _mm_mul_pd(ay, by)), _mm_mul_pd(az, bz));
}

/* Lane by lane, dd > 0 ? clamp01(n / dd) : 0 (point_segment's): a zero dd is
 * divided by 1 instead and the lane dropped, no division by zero; maxpd (0, x) is
 * 0 > x ? 0 : x and minpd (1, x) 1 < x ? 1 : x, clamp01's tests. */
static __m128d clamped_ratio(__m128d n, __m128d dd, __m128d pos)
{
    const __m128d one = _mm_set1_pd(1.0);
    const __m128d x = _mm_div_pd(n, _mm_or_pd(_mm_and_pd(pos, dd), _mm_andnot_pd(pos, one)));
    return _mm_and_pd(pos, _mm_min_pd(one, _mm_max_pd(_mm_setzero_pd(), x)));
}

/* Lane by lane, (p + u dp) - (q + v dq) along one axis, from the lanes (p, q) of a
 * coordinate of the starts and (dp, dq) of the directions'. */
static __m128d gap2(__m128d pq, __m128d d, __m128d u, __m128d v)
{
    return _mm_sub_pd(_mm_add_pd(lo2(pq), _mm_mul_pd(u, lo2(d))), _mm_add_pd(hi2(pq), _mm_mul_pd(v, hi2(d))));
}

/* Squared distances p0 + u d1 to q0 + v d2, lane by lane (dist2_at twice). Written
 * out axis by axis (GCC -O2 kept a loop over three axes, its arrays in memory: 367
 * instructions a measure), and inlined by force (GCC called it: 38.5 million
 * instructions of calls in 8 frames). */
static inline __attribute__((always_inline)) __m128d dist2_at2(__m128d sx, __m128d sy, __m128d sz, __m128d dx,
                                                               __m128d dy, __m128d dz, __m128d u, __m128d v)
{
    const __m128d x = gap2(sx, dx, u, v), y = gap2(sy, dy, u, v), z = gap2(sz, dz, u, v);
    return dot2(x, y, z, x, y, z);
}
#endif

/* hk_segment_closest's body, inlined into both its callers: the broad phase measures
 * through hk_hc_ends_distance2, and the call with four vectors by value cost ~20 % of
 * a measure (examples/guides200 shaking). */
static inline __attribute__((always_inline)) double closest(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, double *u,
                                                            double *v)
{
#ifdef __SSE2__
    /* starts (p0, q0) and ends (p1, q1), directions (d1, d2), (q0 - p0, p0 - q0 = r) */
    const __m128d sx = _mm_set_pd(q0.x, p0.x), sy = _mm_set_pd(q0.y, p0.y), sz = _mm_set_pd(q0.z, p0.z);
    const __m128d ex = _mm_set_pd(q1.x, p1.x), ey = _mm_set_pd(q1.y, p1.y), ez = _mm_set_pd(q1.z, p1.z);
    const __m128d dx = _mm_sub_pd(ex, sx), dy = _mm_sub_pd(ey, sy), dz = _mm_sub_pd(ez, sz);
    const __m128d rx = _mm_sub_pd(swap2(sx), sx), ry = _mm_sub_pd(swap2(sy), sy), rz = _mm_sub_pd(swap2(sz), sz);
    const __m128d ae = dot2(dx, dy, dz, dx, dy, dz);
    const __m128d cf = dot2(dx, dy, dz, hi2(rx), hi2(ry), hi2(rz));
    const __m128d bb = dot2(dx, dy, dz, swap2(dx), swap2(dy), swap2(dz));
    const double a = _mm_cvtsd_f64(ae), e = _mm_cvtsd_f64(hi2(ae)), b = _mm_cvtsd_f64(bb);
    const double c = _mm_cvtsd_f64(cf), f = _mm_cvtsd_f64(hi2(cf));
#else
    const hk_Vec3 d1 = hk_v3_sub(p1, p0), d2 = hk_v3_sub(q1, q0), r = hk_v3_sub(p0, q0);
    const double a = hk_v3_dot(d1, d1), e = hk_v3_dot(d2, d2), b = hk_v3_dot(d1, d2);
    const double c = hk_v3_dot(d1, r), f = hk_v3_dot(d2, r);
#endif
    /* Interior critical point: a u - b v = -c, -b u + e v = f. Only trusted when the
     * segments are clearly not parallel (the determinant is a e sin^2 of their angle);
     * otherwise the minimum over the edges below is exact anyway. */
    const double det = a * e - b * b;
    if (det > 1e-12 * a * e && det > 0.0) {
#ifdef __SSE2__
        /* (uu, vv) as two lanes, one division, and whether both are in [0, 1] by one
         * test: the four comparisons as branches mispredicted 343,000 times in
         * 462,000 measures (cachegrind, examples/guides200 shaking, 23 rescans), the
         * critical point being in the square for 6 % of them. The lanes do the
         * scalar expressions' operations (the same bits). */
        const __m128d uv = _mm_div_pd(
            _mm_sub_pd(_mm_mul_pd(_mm_set_pd(a, b), _mm_set1_pd(f)), _mm_mul_pd(_mm_set_pd(b, c), _mm_set_pd(c, e))),
            _mm_set1_pd(det));
        const double uu = _mm_cvtsd_f64(uv), vv = _mm_cvtsd_f64(hi2(uv));
        if (_mm_movemask_pd(_mm_and_pd(_mm_cmpge_pd(uv, _mm_setzero_pd()), _mm_cmple_pd(uv, _mm_set1_pd(1.0)))) == 3) {
#else
        const double uu = (b * f - c * e) / det, vv = (a * f - b * c) / det;
        if (uu >= 0.0 && uu <= 1.0 && vv >= 0.0 && vv <= 1.0) {
#endif
            *u = uu;
            *v = vv;
            return dist2_at(p0, hk_v3_sub(p1, p0), q0, hk_v3_sub(q1, q0), uu, vv);
        }
    }
    /* The edges u = 0, u = 1, v = 0, v = 1: each a point-segment problem. */
    double cu[4], cv[4], dd[4];
#ifdef __SSE2__
    const __m128d pos = _mm_cmpgt_pd(ae, _mm_setzero_pd());
    const __m128d t0 = clamped_ratio(dot2(rx, ry, rz, dx, dy, dz), ae, pos);
    /* (q1 - p0, p1 - q0) */
    const __m128d wx = _mm_sub_pd(swap2(ex), sx), wy = _mm_sub_pd(swap2(ey), sy), wz = _mm_sub_pd(swap2(ez), sz);
    const __m128d t1 = clamped_ratio(dot2(wx, wy, wz, dx, dy, dz), ae, pos);
    const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0);
    /* lanes (u = 0, v = 0): u (0, t0's u), v (t0's v, 0); (u = 1, v = 1) alike */
    const __m128d e0 = dist2_at2(sx, sy, sz, dx, dy, dz, _mm_unpacklo_pd(zero, t0), _mm_unpackhi_pd(t0, zero));
    const __m128d e1 = dist2_at2(sx, sy, sz, dx, dy, dz, _mm_unpacklo_pd(one, t1), _mm_unpackhi_pd(t1, one));
    _mm_storel_pd(&dd[0], e0), _mm_storeh_pd(&dd[2], e0), _mm_storel_pd(&dd[1], e1), _mm_storeh_pd(&dd[3], e1);
    cu[0] = 0.0, cu[1] = 1.0, cv[2] = 0.0, cv[3] = 1.0;
    _mm_storel_pd(&cu[2], t0), _mm_storeh_pd(&cv[0], t0), _mm_storel_pd(&cu[3], t1), _mm_storeh_pd(&cv[1], t1);
#else
    cu[0] = 0.0, cv[0] = point_segment(p0, q0, d2, e);
    cu[1] = 1.0, cv[1] = point_segment(p1, q0, d2, e);
    cv[2] = 0.0, cu[2] = point_segment(q0, p0, d1, a);
    cv[3] = 1.0, cu[3] = point_segment(q1, p0, d1, a);
    for (int k = 0; k < 4; k++) dd[k] = dist2_at(p0, d1, q0, d2, cu[k], cv[k]);
#endif
    return pick_edge(dd, cu, cv, u, v);
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
