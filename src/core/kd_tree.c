/* k-d tree for k-nearest-neighbour queries (core/kd_tree.h): a balanced tree kept implicit
 * in one array (Bentley 1975), each node's median at the middle of its range, split along
 * the range's widest axis; queries descend to the nearer side first and visit the other
 * only when the splitting plane is not farther than the k-th candidate (Friedman, Bentley
 * and Finkel 1977). Used by the reconstruction (helicoid/reconstruct_blend.c) to find each
 * strand's nearest fitted strands: O(log n) per query where a scan is O(n). */
#include "kd_tree.h"

#include <math.h>
#include <string.h>

enum { LEAF = 8 }; /* ranges this small are scanned */

static double coord(hk_Vec3 p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

/* (coordinate, index) order: a total order, so the tree is the same whatever the sort. */
static int before(const hk_Vec3 *p, const int *index, int axis, int a, int b)
{
    const double ca = coord(p[a], axis), cb = coord(p[b], axis);
    return ca < cb || (ca == cb && index[a] < index[b]);
}

static void swap(hk_Vec3 *p, int *index, int a, int b)
{
    const hk_Vec3 tp = p[a];
    const int ti = index[a];
    p[a] = p[b], index[a] = index[b];
    p[b] = tp, index[b] = ti;
}

/* Hoare's selection: the element of rank `nth` of [lo, hi) to place nth, smaller ones
 * before it and larger ones after. The pivot is the middle element (deterministic). */
static void select_nth(hk_Vec3 *p, int *index, int axis, int lo, int hi, int nth)
{
    while (hi - lo > 1) {
        swap(p, index, (lo + hi) / 2, hi - 1); /* pivot to the end */
        int store = lo;
        for (int i = lo; i < hi - 1; i++)
            if (before(p, index, axis, i, hi - 1)) swap(p, index, i, store++);
        swap(p, index, store, hi - 1);
        if (store == nth) return;
        if (nth < store)
            hi = store;
        else
            lo = store + 1;
    }
}

static void build(hk_KdTree *t, int lo, int hi)
{
    if (hi - lo <= LEAF) return;
    hk_Vec3 a = t->points[lo], b = a; /* the range's bounding box */
    for (int i = lo + 1; i < hi; i++) {
        a = hk_v3(fmin(a.x, t->points[i].x), fmin(a.y, t->points[i].y), fmin(a.z, t->points[i].z));
        b = hk_v3(fmax(b.x, t->points[i].x), fmax(b.y, t->points[i].y), fmax(b.z, t->points[i].z));
    }
    const hk_Vec3 e = hk_v3_sub(b, a);
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
    const int mid = (lo + hi) / 2;
    select_nth(t->points, t->index, axis, lo, hi, mid);
    t->axis[mid] = (unsigned char)axis;
    build(t, lo, mid);
    build(t, mid + 1, hi);
}

void hk_kd_tree_free(hk_KdTree *t)
{
    hk_free(t->points);
    hk_free(t->index);
    hk_free(t->axis);
    memset(t, 0, sizeof *t);
}

hk_Status hk_kd_tree_build(hk_KdTree *t, const hk_Vec3 *points, int count, hk_Error *err)
{
    memset(t, 0, sizeof *t);
    if (count < 1) return hk_error_set(err, HK_ERR_INVALID, "k-d tree of %d points", count);
    for (int i = 0; i < count; i++)
        if (!(isfinite(points[i].x) && isfinite(points[i].y) && isfinite(points[i].z)))
            return hk_error_set(err, HK_ERR_INVALID, "point %d at (%g, %g, %g) is not finite", i, points[i].x,
                                points[i].y, points[i].z);
    t->points = hk_alloc_array((size_t)count, sizeof *t->points, err);
    t->index = t->points ? hk_alloc_array((size_t)count, sizeof *t->index, err) : NULL;
    t->axis = t->index ? hk_calloc_array((size_t)count, sizeof *t->axis, err) : NULL;
    if (!t->axis) {
        hk_kd_tree_free(t);
        return HK_ERR_NOMEM;
    }
    t->count = count;
    memcpy(t->points, points, (size_t)count * sizeof *points);
    for (int i = 0; i < count; i++) t->index[i] = i;
    build(t, 0, count);
    return HK_OK;
}

/* The candidates so far, sorted by (dist, index). */
typedef struct Best {
    int *index;
    double *dist;
    int m, k;
} Best;

static int less(double d, int i, double e, int j) { return d < e || (d == e && i < j); }

/* The brute force's rule: a point joins when the list is not full or when it comes before
 * the last one, and is placed after every candidate it does not come before. */
static void offer(Best *b, double d, int i)
{
    if (b->m == b->k && !less(d, i, b->dist[b->m - 1], b->index[b->m - 1])) return;
    int at = b->m < b->k ? b->m++ : b->m - 1;
    for (; at > 0 && less(d, i, b->dist[at - 1], b->index[at - 1]); at--) {
        b->dist[at] = b->dist[at - 1];
        b->index[at] = b->index[at - 1];
    }
    b->dist[at] = d, b->index[at] = i;
}

static void search(const hk_KdTree *t, hk_Vec3 x, int lo, int hi, Best *b)
{
    if (hi - lo <= LEAF) {
        for (int i = lo; i < hi; i++) offer(b, hk_v3_dist(x, t->points[i]), t->index[i]);
        return;
    }
    const int mid = (lo + hi) / 2, axis = t->axis[mid];
    const double split = coord(t->points[mid], axis), diff = coord(x, axis) - split;
    /* Points before mid are not above the split, points after it not below it. */
    const int near_lo = diff < 0.0 ? lo : mid + 1, near_hi = diff < 0.0 ? mid : hi;
    const int far_lo = diff < 0.0 ? mid + 1 : lo, far_hi = diff < 0.0 ? hi : mid;
    search(t, x, near_lo, near_hi, b);
    offer(b, hk_v3_dist(x, t->points[mid]), t->index[mid]);
    /* Every point beyond the plane is at least |diff| away. A point exactly as far as the
     * k-th candidate may still come before it by its index, so the far side is skipped
     * only when the plane is farther; the margin (far above the rounding of diff and of
     * the distances) keeps rounding from skipping a point the brute force would take. */
    const double worst = b->m == b->k ? b->dist[b->m - 1] : INFINITY;
    const double margin = 1e-12 * (fabs(coord(x, axis)) + fabs(split) + worst);
    if (fabs(diff) <= worst + margin) search(t, x, far_lo, far_hi, b);
}

int hk_kd_tree_nearest(const hk_KdTree *t, hk_Vec3 x, int k, int *index, double *dist)
{
    const int m = k < t->count ? k : t->count;
    if (m < 1) return 0;
    if (!(isfinite(x.x) && isfinite(x.y) && isfinite(x.z))) {
        /* Every distance is +inf or NaN: a scan keeps the first m points, in order. */
        for (int i = 0; i < t->count; i++)
            if (t->index[i] < m) {
                index[t->index[i]] = t->index[i];
                dist[t->index[i]] = hk_v3_dist(x, t->points[i]);
            }
        return m;
    }
    Best b = {index, dist, 0, m};
    search(t, x, 0, t->count, &b);
    return b.m;
}

int hk_nearest_by_scan(const hk_Vec3 *points, int count, hk_Vec3 x, int k, int *index, double *dist)
{
    int m = 0;
    for (int g = 0; g < count && k > 0; g++) {
        const double d = hk_v3_dist(x, points[g]);
        if (m == k && !(d < dist[m - 1])) continue;
        int i = m < k ? m++ : m - 1;
        for (; i > 0 && d < dist[i - 1]; i--) {
            dist[i] = dist[i - 1];
            index[i] = index[i - 1];
        }
        dist[i] = d, index[i] = g;
    }
    return m;
}
