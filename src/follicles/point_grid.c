/* Hashed uniform grid for the neighbour sums of the particle system (Witkin &
 * Heckbert 1994 use a similar bin structure): O(1) neighbours per particle instead of
 * all pairs. Buckets are filled by a counting sort over increasing point index, so
 * every query visits its points in one order whatever the threads. */
#include <math.h>
#include <string.h>

#include "follicle_internal.h"

static uint32_t cell_hash(int32_t kx, int32_t ky, int32_t kz, int buckets)
{
    const uint32_t h = ((uint32_t)kx * 73856093u) ^ ((uint32_t)ky * 19349663u) ^ ((uint32_t)kz * 83492791u);
    return h & (uint32_t)(buckets - 1);
}

void hk_point_grid_free(hk_PointGrid *g)
{
    hk_free(g->bucket_start);
    hk_free(g->items);
    hk_free(g->key);
    memset(g, 0, sizeof *g);
}

hk_Status hk_point_grid_build(hk_PointGrid *g, const hk_Vec3 *p, int count, double cell, hk_Error *err)
{
    if (!(cell > 0.0) || !isfinite(cell)) return hk_error_set(err, HK_ERR_INVALID, "grid cell size %g", cell);
    int buckets = 64;
    while (buckets < 2 * count && buckets < (1 << 28)) buckets *= 2;
    if (count > g->count || buckets > g->bucket_count) {
        hk_free(g->items), hk_free(g->key), hk_free(g->bucket_start);
        g->items = hk_alloc_array((size_t)count, sizeof(int), err);
        g->key = hk_alloc_array(3 * (size_t)count, sizeof(int32_t), err);
        g->bucket_start = hk_alloc_array((size_t)buckets + 1, sizeof(int), err);
        if (!g->items || !g->key || !g->bucket_start) {
            hk_point_grid_free(g);
            return HK_ERR_NOMEM;
        }
    }
    g->count = count;
    g->bucket_count = buckets;
    g->cell = cell;
    memset(g->bucket_start, 0, sizeof(int) * ((size_t)buckets + 1));
    const double inv = 1.0 / cell;
    for (int i = 0; i < count; i++) {
        const double c[3] = {floor(p[i].x * inv), floor(p[i].y * inv), floor(p[i].z * inv)};
        for (int k = 0; k < 3; k++) {
            /* cells are 32-bit: refuse coordinates a billion cells from the origin */
            if (!(fabs(c[k]) < 1e9))
                return hk_error_set(err, HK_ERR_INVALID,
                                    "point %d at (%g, %g, %g) is too far from the origin for a grid of %g", i, p[i].x,
                                    p[i].y, p[i].z, cell);
            g->key[3 * i + k] = (int32_t)c[k];
        }
        g->bucket_start[cell_hash(g->key[3 * i], g->key[3 * i + 1], g->key[3 * i + 2], buckets) + 1]++;
    }
    for (int b = 0; b < buckets; b++) g->bucket_start[b + 1] += g->bucket_start[b];
    /* counting sort: bucket_start[b] walks forward while filling, then is restored */
    for (int i = 0; i < count; i++) {
        const uint32_t b = cell_hash(g->key[3 * i], g->key[3 * i + 1], g->key[3 * i + 2], buckets);
        g->items[g->bucket_start[b]++] = i;
    }
    for (int b = buckets; b > 0; b--) g->bucket_start[b] = g->bucket_start[b - 1];
    g->bucket_start[0] = 0;
    return HK_OK;
}

void hk_point_grid_query(const hk_PointGrid *g, hk_Vec3 x, void (*visit)(void *user, int j), void *user)
{
    const double inv = 1.0 / g->cell;
    const double fx = floor(x.x * inv), fy = floor(x.y * inv), fz = floor(x.z * inv);
    if (!(fabs(fx) < 1e9 && fabs(fy) < 1e9 && fabs(fz) < 1e9)) return;
    const int32_t cx = (int32_t)fx, cy = (int32_t)fy, cz = (int32_t)fz;
    /* Two of the 27 cells can share a bucket: skip a bucket already visited so no
     * point is seen twice, and check each point's own cell. */
    uint32_t seen[27];
    int nseen = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                const uint32_t b = cell_hash(cx + dx, cy + dy, cz + dz, g->bucket_count);
                int dup = 0;
                for (int k = 0; k < nseen; k++) dup |= seen[k] == b;
                if (dup) continue;
                seen[nseen++] = b;
                for (int t = g->bucket_start[b]; t < g->bucket_start[b + 1]; t++) {
                    const int j = g->items[t];
                    const int32_t *k = g->key + 3 * j;
                    if (k[0] - cx >= -1 && k[0] - cx <= 1 && k[1] - cy >= -1 && k[1] - cy <= 1 && k[2] - cz >= -1 &&
                        k[2] - cz <= 1)
                        visit(user, j);
                }
            }
}
