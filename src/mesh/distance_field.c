/* Signed distance field of a triangle mesh on a regular grid (hairkit/mesh.h; the head as
 * a collider, docs/capture.md).
 *
 * The construction of C. Batty's SDFGen (makelevelset3, public domain), after Bridson,
 * "Fluid Simulation for Computer Graphics" (2008), §4.3, and Zhao, "A fast sweeping
 * method for eikonal equations" (Math. Comp. 74, 2005):
 * 1. every node within `exact_band` cells of a triangle's bounding box gets its exact
 *    distance to that triangle, the smallest kept with the triangle that gave it;
 * 2. sweeps in the 8 diagonal orders carry each node's closest triangle to its
 *    neighbours, which take it when it is closer than theirs (one pass), so that every
 *    node up to `exact_reach` from the mesh ends with the distance to its closest
 *    triangle (nearly always the true one); beyond, where that costs most (neighbours
 *    there rarely share their closest triangle) and a collider needs least, the sweeps
 *    carry the chamfer distance (the neighbour's plus the step: a few per cent long);
 * 3. the sign from the parity of the mesh's crossings along +x: a column of nodes
 *    (j, k) is cut by the triangles whose yz-projection holds it, each crossing flips
 *    inside and outside for the nodes beyond it. The point-in-triangle test breaks ties
 *    on edges and vertices consistently (the orientation's sign from the coordinates
 *    when the area is zero), so that a column through a shared edge counts one crossing.
 * A closed (watertight) mesh gives the right sign everywhere; an open one (a head cut at
 * the neck) leaks along the columns through its hole. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "hairkit/mesh.h"
#include "mesh/mesh_internal.h"

/* Passes of the 8 sweeps. SDFGen makes two; the second changed no node within
 * exact_reach on the tests' sphere and cube, and costs as much as the first. */
#define SWEEP_PASSES 1

hk_DistanceFieldDef hk_default_distance_field_def(void)
{
    hk_DistanceFieldDef d;
    d.spacing = 0.002;
    d.margin = 0.03;
    d.exact_band = 2;
    d.exact_reach = 0.01;
    return d;
}

void hk_distance_field_free(hk_DistanceField *field)
{
    if (!field) return;
    hk_free(field->distance);
    memset(field, 0, sizeof *field);
}

typedef struct Grid {
    int n[3];
    hk_Vec3 origin;
    double h;
    double reach; /* exact distances up to this far from the mesh */
    float *phi;
    int *closest;
    unsigned char *parity; /* crossings before each node along x, mod 2 */
} Grid;

static size_t at(const Grid *g, int i, int j, int k)
{
    return ((size_t)k * (size_t)g->n[1] + (size_t)j) * (size_t)g->n[0] + (size_t)i;
}

static hk_Vec3 node(const Grid *g, int i, int j, int k)
{
    return hk_v3(g->origin.x + i * g->h, g->origin.y + j * g->h, g->origin.z + k * g->h);
}

static double triangle_distance(const hk_Mesh *m, int t, hk_Vec3 p)
{
    const int *v = m->triangles + 3 * t;
    return hk_triangle_distance(p, m->positions[v[0]], m->positions[v[1]], m->positions[v[2]]);
}

static int clampi(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

/* Sign of twice the signed area of (0, 0), (x1, y1), (x2, y2), ties broken by the
 * coordinates so that no two triangles sharing an edge both claim a point on it. */
static int orientation(double x1, double y1, double x2, double y2, double *twice_area)
{
    *twice_area = y1 * x2 - x1 * y2;
    if (*twice_area > 0.0) return 1;
    if (*twice_area < 0.0) return -1;
    if (y2 > y1) return 1;
    if (y2 < y1) return -1;
    if (x1 > x2) return 1;
    if (x1 < x2) return -1;
    return 0;
}

/* (x0, y0) inside the 2D triangle: its barycentric weights in w. */
static int inside_2d(double x0, double y0, const double x[3], const double y[3], double w[3])
{
    const double x1 = x[0] - x0, x2 = x[1] - x0, x3 = x[2] - x0;
    const double y1 = y[0] - y0, y2 = y[1] - y0, y3 = y[2] - y0;
    const int sa = orientation(x2, y2, x3, y3, &w[0]);
    if (sa == 0) return 0;
    if (orientation(x3, y3, x1, y1, &w[1]) != sa) return 0;
    if (orientation(x1, y1, x2, y2, &w[2]) != sa) return 0;
    const double sum = w[0] + w[1] + w[2];
    if (sum == 0.0) return 0;
    w[0] /= sum, w[1] /= sum, w[2] /= sum;
    return 1;
}

/* Step 1 and the crossings of step 3 for triangle t. */
static void rasterise(Grid *g, const hk_Mesh *m, int t, int band)
{
    const int *v = m->triangles + 3 * t;
    double f[3][3]; /* the corners in grid units */
    for (int c = 0; c < 3; c++) {
        const hk_Vec3 p = m->positions[v[c]];
        f[c][0] = (p.x - g->origin.x) / g->h;
        f[c][1] = (p.y - g->origin.y) / g->h;
        f[c][2] = (p.z - g->origin.z) / g->h;
    }
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        const double mn = fmin(f[0][a], fmin(f[1][a], f[2][a])), mx = fmax(f[0][a], fmax(f[1][a], f[2][a]));
        lo[a] = clampi((int)floor(mn) - band, 0, g->n[a] - 1);
        hi[a] = clampi((int)ceil(mx) + band, 0, g->n[a] - 1);
    }
    for (int k = lo[2]; k <= hi[2]; k++)
        for (int j = lo[1]; j <= hi[1]; j++)
            for (int i = lo[0]; i <= hi[0]; i++) {
                const double d = triangle_distance(m, t, node(g, i, j, k));
                const size_t x = at(g, i, j, k);
                if (d < g->phi[x]) g->phi[x] = (float)d, g->closest[x] = t;
            }
    /* crossings of the columns (j, k) along +x */
    const double ys[3] = {f[0][1], f[1][1], f[2][1]}, zs[3] = {f[0][2], f[1][2], f[2][2]};
    const int j0 = clampi((int)ceil(fmin(ys[0], fmin(ys[1], ys[2]))), 0, g->n[1] - 1);
    const int j1 = clampi((int)floor(fmax(ys[0], fmax(ys[1], ys[2]))), 0, g->n[1] - 1);
    const int k0 = clampi((int)ceil(fmin(zs[0], fmin(zs[1], zs[2]))), 0, g->n[2] - 1);
    const int k1 = clampi((int)floor(fmax(zs[0], fmax(zs[1], zs[2]))), 0, g->n[2] - 1);
    for (int k = k0; k <= k1; k++)
        for (int j = j0; j <= j1; j++) {
            double w[3];
            if (!inside_2d(j, k, ys, zs, w)) continue;
            const double fi = w[0] * f[0][0] + w[1] * f[1][0] + w[2] * f[2][0];
            int first = (int)ceil(fi); /* the first node beyond the crossing */
            if (first < 0) first = 0;
            if (first < g->n[0]) g->parity[at(g, first, j, k)] ^= 1;
        }
}

/* closest[x]: the triangle whose exact distance phi[x] is (>= 0), or -2 - t when phi[x]
 * is a chamfer distance carried from t, or -1 before any. */
static int triangle_of(int closest) { return closest >= 0 ? closest : -2 - closest; }

/* Offers node x the closest triangle of its neighbour y, `apart` away. The triangle is
 * at phi[y] from y, so at least phi[y] - apart from x: no closer than x's own when that
 * is already larger (which spares most of the distance computations). */
static void offer(Grid *g, const hk_Mesh *m, hk_Vec3 p, size_t x, size_t y, double apart)
{
    const int t = triangle_of(g->closest[y]);
    if (t < 0 || g->phi[y] - apart >= g->phi[x]) return;
    if (g->phi[y] >= g->reach) { /* far from the mesh: the chamfer distance will do */
        const double d = g->phi[y] + apart;
        if (d < g->phi[x]) g->phi[x] = (float)d, g->closest[x] = -2 - t;
        return;
    }
    if (t == g->closest[x]) return; /* its exact distance is x's already */
    const double d = triangle_distance(m, t, p);
    if (d < g->phi[x]) g->phi[x] = (float)d, g->closest[x] = t;
}

/* One sweep in the order given by the signs (di, dj, dk). */
static void sweep(Grid *g, const hk_Mesh *m, int di, int dj, int dk)
{
    const int i0 = di > 0 ? 1 : g->n[0] - 2, i1 = di > 0 ? g->n[0] : -1;
    const int j0 = dj > 0 ? 1 : g->n[1] - 2, j1 = dj > 0 ? g->n[1] : -1;
    const int k0 = dk > 0 ? 1 : g->n[2] - 2, k1 = dk > 0 ? g->n[2] : -1;
    /* the neighbours' distances, a little short (float phi) so that no offer is skipped
     * wrongly */
    const double h1 = g->h * (1.0 - 1e-6), h2 = h1 * sqrt(2.0), h3 = h1 * sqrt(3.0);
    for (int k = k0; k != k1; k += dk)
        for (int j = j0; j != j1; j += dj)
            for (int i = i0; i != i1; i += di) {
                const size_t x = at(g, i, j, k);
                const hk_Vec3 p = node(g, i, j, k);
                offer(g, m, p, x, at(g, i - di, j, k), h1);
                offer(g, m, p, x, at(g, i, j - dj, k), h1);
                offer(g, m, p, x, at(g, i - di, j - dj, k), h2);
                offer(g, m, p, x, at(g, i, j, k - dk), h1);
                offer(g, m, p, x, at(g, i - di, j, k - dk), h2);
                offer(g, m, p, x, at(g, i, j - dj, k - dk), h2);
                offer(g, m, p, x, at(g, i - di, j - dj, k - dk), h3);
            }
}

hk_Status hk_distance_field_build(const hk_Mesh *mesh, const hk_DistanceFieldDef *def, hk_DistanceField *out,
                                  hk_Error *err)
{
    memset(out, 0, sizeof *out);
    const hk_DistanceFieldDef d = def ? *def : hk_default_distance_field_def();
    if (!(d.spacing > 0.0) || !(d.margin >= 0.0) || d.exact_band < 1 || d.exact_band > 100 || !(d.exact_reach >= 0.0))
        return hk_error_set(
            err, HK_ERR_INVALID,
            "distance field: spacing > 0, margin >= 0, exact_band 1..100 and exact_reach >= 0 expected");
    if (!mesh || mesh->triangle_count < 1)
        return hk_error_set(err, HK_ERR_INVALID, "distance field: the mesh has no triangles");
    hk_Vec3 lo = hk_v3(DBL_MAX, DBL_MAX, DBL_MAX), hi = hk_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    for (int i = 0; i < mesh->vertex_count; i++) {
        const hk_Vec3 p = mesh->positions[i];
        lo = hk_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
        hi = hk_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    Grid g = {0};
    g.h = d.spacing;
    g.reach = d.exact_reach;
    g.origin = hk_v3_sub(lo, hk_v3(d.margin, d.margin, d.margin));
    double nodes = 1.0;
    for (int a = 0; a < 3; a++) {
        const double extent = hk_v3_get(hi, a) - hk_v3_get(lo, a) + 2.0 * d.margin;
        const double count = ceil(extent / d.spacing) + 1.0;
        if (!(count <= 100000.0))
            return hk_error_set(err, HK_ERR_INVALID,
                                "distance field: %.3g nodes along an axis (mesh extent %.3g, spacing %.3g)", count,
                                extent, d.spacing);
        g.n[a] = (int)count < 2 ? 2 : (int)count;
        nodes *= g.n[a];
    }
    hk_Status st = hk_memory_check(nodes * (sizeof(float) + sizeof(int) + 1.0), "the distance field", err);
    if (st != HK_OK) return st;
    const size_t count = (size_t)nodes;
    g.phi = hk_alloc_array(count, sizeof(float), err);
    g.closest = hk_alloc_array(count, sizeof(int), err);
    g.parity = hk_calloc_array(count, 1, err);
    if (!g.phi || !g.closest || !g.parity) {
        hk_free(g.phi);
        hk_free(g.closest);
        hk_free(g.parity);
        return err ? err->code : HK_ERR_NOMEM;
    }
    const float far = (float)((g.n[0] + g.n[1] + g.n[2]) * g.h);
    for (size_t x = 0; x < count; x++) g.phi[x] = far, g.closest[x] = -1;
    for (int t = 0; t < mesh->triangle_count; t++) rasterise(&g, mesh, t, d.exact_band);
    for (int pass = 0; pass < SWEEP_PASSES; pass++) {
        sweep(&g, mesh, +1, +1, +1);
        sweep(&g, mesh, -1, -1, -1);
        sweep(&g, mesh, +1, +1, -1);
        sweep(&g, mesh, -1, -1, +1);
        sweep(&g, mesh, +1, -1, +1);
        sweep(&g, mesh, -1, +1, -1);
        sweep(&g, mesh, +1, -1, -1);
        sweep(&g, mesh, -1, +1, +1);
    }
    for (int k = 0; k < g.n[2]; k++)
        for (int j = 0; j < g.n[1]; j++) {
            int inside = 0;
            for (int i = 0; i < g.n[0]; i++) {
                const size_t x = at(&g, i, j, k);
                inside ^= g.parity[x];
                if (inside) g.phi[x] = -g.phi[x];
            }
        }
    hk_free(g.closest);
    hk_free(g.parity);
    out->origin = g.origin;
    out->spacing = g.h;
    for (int a = 0; a < 3; a++) out->size[a] = g.n[a];
    out->distance = g.phi;
    return HK_OK;
}

double hk_distance_field_eval(const hk_DistanceField *f, hk_Vec3 p, hk_Vec3 *grad)
{
    /* p clamped into the grid; beyond it the distance grows by the way out */
    double u[3], outside2 = 0.0;
    hk_Vec3 away = hk_v3_zero();
    int c[3];
    for (int a = 0; a < 3; a++) {
        const double top = (f->size[a] - 1) * f->spacing;
        double x = hk_v3_get(p, a) - hk_v3_get(f->origin, a);
        if (!(x >= 0.0)) {
            hk_v3_set(&away, a, x);
            x = 0.0;
        } else if (x > top) {
            hk_v3_set(&away, a, x - top);
            x = top;
        }
        const double s = x / f->spacing;
        c[a] = (int)s;
        if (c[a] > f->size[a] - 2) c[a] = f->size[a] - 2;
        u[a] = s - c[a];
    }
    outside2 = hk_v3_dot(away, away);
    const size_t nx = (size_t)f->size[0], nxy = nx * (size_t)f->size[1];
    const float *v = f->distance + (size_t)c[2] * nxy + (size_t)c[1] * nx + (size_t)c[0];
    const double v000 = v[0], v100 = v[1], v010 = v[nx], v110 = v[nx + 1];
    const double v001 = v[nxy], v101 = v[nxy + 1], v011 = v[nxy + nx], v111 = v[nxy + nx + 1];
    /* trilinear interpolation and its gradient */
    const double x0 = v000 + u[0] * (v100 - v000), x1 = v010 + u[0] * (v110 - v010);
    const double x2 = v001 + u[0] * (v101 - v001), x3 = v011 + u[0] * (v111 - v011);
    const double y0 = x0 + u[1] * (x1 - x0), y1 = x2 + u[1] * (x3 - x2);
    double value = y0 + u[2] * (y1 - y0);
    if (grad) {
        const double dx0 = v100 - v000, dx1 = v110 - v010, dx2 = v101 - v001, dx3 = v111 - v011;
        const double gx = (1.0 - u[2]) * (dx0 + u[1] * (dx1 - dx0)) + u[2] * (dx2 + u[1] * (dx3 - dx2));
        const double gy = (1.0 - u[2]) * (x1 - x0) + u[2] * (x3 - x2);
        const double gz = y1 - y0;
        *grad = hk_v3_scale(hk_v3(gx, gy, gz), 1.0 / f->spacing);
    }
    if (outside2 > 0.0) {
        const double o = sqrt(outside2);
        value += o;
        if (grad) *grad = hk_v3_scale(away, 1.0 / o);
    }
    return value;
}
