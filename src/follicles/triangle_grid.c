/* Distance to a triangle mesh within a radius, for the "hair grows here" mask of the
 * follicle sampling on a wick (Piuze et al. 2011 §4.3: sampling confined to a region). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "follicle_internal.h"

hk_Vec3 hk_closest_point_triangle(hk_Vec3 p, hk_Vec3 a, hk_Vec3 b, hk_Vec3 c)
{
    /* Voronoi regions of the vertices, then edges, then the face. */
    const hk_Vec3 ab = hk_v3_sub(b, a), ac = hk_v3_sub(c, a), ap = hk_v3_sub(p, a);
    const double d1 = hk_v3_dot(ab, ap), d2 = hk_v3_dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const hk_Vec3 bp = hk_v3_sub(p, b);
    const double d3 = hk_v3_dot(ab, bp), d4 = hk_v3_dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return hk_v3_madd(a, ab, d1 / (d1 - d3));
    const hk_Vec3 cp = hk_v3_sub(p, c);
    const double d5 = hk_v3_dot(ab, cp), d6 = hk_v3_dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return hk_v3_madd(a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
        return hk_v3_madd(b, hk_v3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double sum = va + vb + vc;
    if (!(sum > 0.0)) return a; /* degenerate triangle: its vertex regions cover it */
    const double v = vb / sum, w = vc / sum;
    return hk_v3_add(a, hk_v3_add(hk_v3_scale(ab, v), hk_v3_scale(ac, w)));
}

void hk_triangle_grid_free(hk_TriangleGrid *g)
{
    hk_free(g->cell_start);
    hk_free(g->items);
    memset(g, 0, sizeof *g);
}

static int cell_index(const hk_TriangleGrid *g, int i, int j, int k) { return (k * g->dims[1] + j) * g->dims[0] + i; }

/* Cell range of a box, clamped to the grid. */
static void cell_range(const hk_TriangleGrid *g, hk_Vec3 lo, hk_Vec3 hi, int r0[3], int r1[3])
{
    for (int a = 0; a < 3; a++) {
        const double l = (hk_v3_get(lo, a) - hk_v3_get(g->origin, a)) / g->cell;
        const double h = (hk_v3_get(hi, a) - hk_v3_get(g->origin, a)) / g->cell;
        r0[a] = (int)fmax(0.0, fmin(g->dims[a] - 1, floor(l)));
        r1[a] = (int)fmax(0.0, fmin(g->dims[a] - 1, floor(h)));
    }
}

hk_Status hk_triangle_grid_build(hk_TriangleGrid *g, const hk_Vec3 *positions, const int *triangles, int triangle_count,
                                 double radius, hk_Error *err)
{
    memset(g, 0, sizeof *g);
    if (triangle_count < 1) return hk_error_set(err, HK_ERR_INVALID, "the mesh has no triangles");
    if (!(radius > 0.0) || !isfinite(radius)) return hk_error_set(err, HK_ERR_INVALID, "distance radius %g", radius);
    g->positions = positions;
    g->triangles = triangles;
    g->radius = radius;
    hk_Vec3 lo = hk_v3(DBL_MAX, DBL_MAX, DBL_MAX), hi = hk_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    double edges = 0.0;
    for (int t = 0; t < triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            const hk_Vec3 p = positions[triangles[3 * t + c]];
            if (!hk_v3_isfinite(p)) return hk_error_set(err, HK_ERR_INVALID, "triangle %d has a non-finite vertex", t);
            lo = hk_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
            hi = hk_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
            edges += hk_v3_dist(p, positions[triangles[3 * t + (c + 1) % 3]]);
        }
    lo = hk_v3_sub(lo, hk_v3(radius, radius, radius));
    hi = hk_v3_add(hi, hk_v3(radius, radius, radius));
    /* cells about a triangle wide and at least the radius, at most 2^21 of them */
    double cell = fmax(2.0 * radius, edges / (3.0 * triangle_count));
    const hk_Vec3 ext = hk_v3_sub(hi, lo);
    for (;;) {
        const double n = ceil(ext.x / cell) * ceil(ext.y / cell) * ceil(ext.z / cell);
        if (n <= (double)(1 << 21)) break;
        cell *= 1.25;
    }
    g->origin = lo;
    g->cell = cell;
    for (int a = 0; a < 3; a++) g->dims[a] = (int)fmax(1.0, ceil(hk_v3_get(ext, a) / cell));
    const int cells = g->dims[0] * g->dims[1] * g->dims[2];
    g->cell_start = hk_calloc_array((size_t)cells + 1, sizeof(int), err);
    if (!g->cell_start) return HK_ERR_NOMEM;
    /* two passes: count, then fill (a triangle goes in every cell its grown box meets) */
    long total = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (int t = 0; t < triangle_count; t++) {
            const hk_Vec3 a = positions[triangles[3 * t]], b = positions[triangles[3 * t + 1]],
                          c = positions[triangles[3 * t + 2]];
            const hk_Vec3 tl = hk_v3(fmin(a.x, fmin(b.x, c.x)) - radius, fmin(a.y, fmin(b.y, c.y)) - radius,
                                     fmin(a.z, fmin(b.z, c.z)) - radius);
            const hk_Vec3 th = hk_v3(fmax(a.x, fmax(b.x, c.x)) + radius, fmax(a.y, fmax(b.y, c.y)) + radius,
                                     fmax(a.z, fmax(b.z, c.z)) + radius);
            int r0[3], r1[3];
            cell_range(g, tl, th, r0, r1);
            for (int k = r0[2]; k <= r1[2]; k++)
                for (int j = r0[1]; j <= r1[1]; j++)
                    for (int i = r0[0]; i <= r1[0]; i++) {
                        const int ci = cell_index(g, i, j, k);
                        if (pass == 0) {
                            g->cell_start[ci + 1]++;
                            total++;
                        } else {
                            g->items[g->cell_start[ci]++] = t;
                        }
                    }
        }
        if (pass == 0) {
            if (total > 50000000L) {
                hk_triangle_grid_free(g);
                return hk_error_set(err, HK_ERR_NOMEM, "triangle grid would hold %ld entries", total);
            }
            for (int c = 0; c < cells; c++) g->cell_start[c + 1] += g->cell_start[c];
            g->items = hk_alloc_array((size_t)total, sizeof(int), err);
            if (!g->items) {
                hk_triangle_grid_free(g);
                return HK_ERR_NOMEM;
            }
        }
    }
    /* the fill pass moved each start to the next cell's: shift back */
    for (int c = cells; c > 0; c--) g->cell_start[c] = g->cell_start[c - 1];
    g->cell_start[0] = 0;
    return HK_OK;
}

double hk_triangle_grid_distance(const hk_TriangleGrid *g, hk_Vec3 x, double *tangential)
{
    if (tangential) *tangential = g->radius;
    int c[3];
    for (int a = 0; a < 3; a++) {
        const double f = floor((hk_v3_get(x, a) - hk_v3_get(g->origin, a)) / g->cell);
        if (!(f >= 0.0 && f < g->dims[a])) return g->radius; /* outside the grown box, or NaN */
        c[a] = (int)f;
    }
    const int ci = cell_index(g, c[0], c[1], c[2]);
    double best = g->radius;
    for (int s = g->cell_start[ci]; s < g->cell_start[ci + 1]; s++) {
        const int *t = g->triangles + 3 * g->items[s];
        const hk_Vec3 a = g->positions[t[0]], b = g->positions[t[1]], cc = g->positions[t[2]];
        const hk_Vec3 q = hk_closest_point_triangle(x, a, b, cc);
        const double dist = hk_v3_dist(x, q);
        if (dist >= best) continue;
        best = dist;
        if (tangential) {
            /* the part of x - q in the triangle's plane: 0 above the triangle, the
             * overshoot beyond an edge otherwise */
            const hk_Vec3 n = hk_v3_normalize(hk_v3_cross(hk_v3_sub(b, a), hk_v3_sub(cc, a)));
            const hk_Vec3 d = hk_v3_sub(x, q);
            *tangential = hk_v3_norm(hk_v3_madd(d, n, -hk_v3_dot(d, n)));
        }
    }
    return best;
}
