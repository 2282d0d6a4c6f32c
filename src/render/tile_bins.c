/* The tile bins that let the renderer work on 32 x 32 pixel tiles in parallel: every
 * item (segment, triangle) listed in each tile its pixel box touches, in item order. */
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "render_internal.h"

/* One pass over the items, one contiguous range per thread: (fill 0) find every
 * item's box with box_of, keep it in bins->boxes and count each range's entries per
 * tile into at[range][tile], or (fill 1) write the entries from the offsets in
 * at[range][tile], reading the kept boxes. A box is computed once: that is most of
 * the binning's work, and the tiles read the boxes again to find which of their blocks
 * a segment covers. */
static void bin_ranges(uint32_t item_count, hk_BoxFn box_of, void *user, const float *key, const float *cull,
                       hk_TileBins *bins, int ranges, uint64_t *at, int fill)
{
    const size_t tiles = (size_t)bins->tiles_x * (size_t)bins->tiles_y;
    const int tiles_x = bins->tiles_x;
#pragma omp parallel for schedule(static, 1) num_threads(ranges)
    for (int g = 0; g < ranges; g++) {
        const uint32_t lo = (uint32_t)((uint64_t)item_count * g / ranges);
        const uint32_t hi = (uint32_t)((uint64_t)item_count * (g + 1) / ranges);
        uint64_t *c = at + (size_t)g * tiles;
        for (uint32_t i = lo; i < hi; i++) {
            hk_TileBox *b = &bins->boxes[i];
            if (!fill) {
                hk_Rect box;
                if (box_of(user, i, &box))
                    b->x0 = (uint16_t)box.x0, b->y0 = (uint16_t)box.y0, b->x1 = (uint16_t)box.x1,
                    b->y1 = (uint16_t)box.y1;
                else
                    b->x0 = b->y0 = b->x1 = b->y1 = 0; /* empty: x1 <= x0 */
            }
            const hk_TileBox r = *b;
            if (r.x1 <= r.x0) continue;
            const float k = key ? key[i] : 0.0f;
            for (int ty = r.y0 / HK_TILE; ty <= (r.y1 - 1) / HK_TILE; ty++)
                for (int tx = r.x0 / HK_TILE; tx <= (r.x1 - 1) / HK_TILE; tx++) {
                    const size_t t = (size_t)ty * tiles_x + tx;
                    if (cull && k >= cull[t]) continue;
                    uint64_t *slot = &c[t];
                    if (fill) {
                        if (key) bins->keys[*slot] = k;
                        bins->items[(*slot)++] = i;
                    } else {
                        (*slot)++;
                    }
                }
        }
    }
}

static int increasing(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : (x > y);
}

/* The tiles by decreasing number of items (ties by index), sorted through keys (in
 * `work`, tiles of them): handed out in this order, the busiest tiles start first and
 * the threads finish together; in image order the busy middle of the picture came last
 * and one thread often finished it alone. */
static void order_heavy_first(hk_TileBins *bins, size_t tiles, uint64_t *work)
{
    for (size_t t = 0; t < tiles; t++)
        work[t] = ((uint64_t)(UINT32_MAX - (bins->start[t + 1] - bins->start[t])) << 32) | t;
    qsort(work, tiles, sizeof *work, increasing);
    for (size_t t = 0; t < tiles; t++) bins->heavy[t] = (uint32_t)(work[t] & UINT32_MAX);
}

hk_Status hk_tile_bins_build(uint32_t item_count, hk_BoxFn box_of, void *user, const float *key, const float *cull,
                             int width, int height, hk_TileBins *bins, hk_Error *err)
{
    bins->tiles_x = (width + HK_TILE - 1) / HK_TILE;
    bins->tiles_y = (height + HK_TILE - 1) / HK_TILE;
    const size_t tiles = (size_t)bins->tiles_x * (size_t)bins->tiles_y;
    /* The items are cut into one contiguous range per thread. Each range is counted
     * per tile, the counts are laid out tile by tile and range by range, and each
     * range fills its own places: the bins hold the items in item order whatever the
     * number of threads. */
    const int ranges = omp_get_max_threads();
    if (!HK_RESERVE(bins->start, bins->start_cap, tiles + 1, err) ||
        !HK_RESERVE(bins->boxes, bins->boxes_cap, item_count, err) ||
        !HK_RESERVE(bins->heavy, bins->heavy_cap, tiles, err) ||
        !HK_RESERVE(bins->count, bins->count_cap, (size_t)ranges * tiles, err)) {
        hk_tile_bins_free(bins);
        return HK_ERR_NOMEM;
    }
    memset(bins->count, 0, (size_t)ranges * tiles * sizeof *bins->count);
    uint64_t *count = bins->count;
    bin_ranges(item_count, box_of, user, key, cull, bins, ranges, count, 0);
    /* Offsets: count[g][t] becomes where range g starts writing in tile t. */
    uint64_t total = 0;
    for (size_t t = 0; t < tiles; t++) {
        bins->start[t] = (uint32_t)(total < UINT32_MAX ? total : UINT32_MAX);
        for (int g = 0; g < ranges; g++) {
            const uint64_t n = count[(size_t)g * tiles + t];
            count[(size_t)g * tiles + t] = total;
            total += n;
        }
    }
    if (total > UINT32_MAX - 1) {
        hk_tile_bins_free(bins);
        return hk_error_set(err, HK_ERR_NOMEM, "too many segments for one picture (%llu tile entries)",
                            (unsigned long long)total);
    }
    bins->start[tiles] = (uint32_t)total;
    if (!HK_RESERVE(bins->items, bins->items_cap, (size_t)total, err) ||
        (key && !HK_RESERVE(bins->keys, bins->keys_cap, (size_t)total, err))) {
        hk_tile_bins_free(bins);
        return HK_ERR_NOMEM;
    }
    bin_ranges(item_count, box_of, user, key, cull, bins, ranges, count, 1);
    order_heavy_first(bins, tiles, count); /* the counts are spent */
    return HK_OK;
}

void hk_tile_bins_free(hk_TileBins *bins)
{
    hk_free(bins->start);
    hk_free(bins->items);
    hk_free(bins->boxes);
    hk_free(bins->count);
    hk_free(bins->heavy);
    hk_free(bins->keys);
    memset(bins, 0, sizeof *bins);
}
