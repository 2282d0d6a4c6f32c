/* The tile bins that let the renderer work on 32 x 32 pixel tiles in parallel: every
 * item (segment, triangle) listed in each tile its pixel box touches, in item order.
 * The passes over the items are HK_TILE_BINS_BUILD's (tile_bins_inline.h); here what
 * comes before, between and after them. */
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

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

hk_Status hk_tile_bins_begin(uint32_t item_count, int width, int height, hk_TileBins *bins, int ranges, hk_Error *err)
{
    bins->tiles_x = (width + HK_TILE - 1) / HK_TILE;
    bins->tiles_y = (height + HK_TILE - 1) / HK_TILE;
    const size_t tiles = (size_t)bins->tiles_x * (size_t)bins->tiles_y;
    if (!HK_RESERVE(bins->start, bins->start_cap, tiles + 1, err) ||
        !HK_RESERVE(bins->boxes, bins->boxes_cap, item_count, err) ||
        !HK_RESERVE(bins->heavy, bins->heavy_cap, tiles, err) ||
        !HK_RESERVE(bins->count, bins->count_cap, (size_t)ranges * tiles, err)) {
        hk_tile_bins_free(bins);
        return HK_ERR_NOMEM;
    }
    memset(bins->count, 0, (size_t)ranges * tiles * sizeof *bins->count);
    return HK_OK;
}

hk_Status hk_tile_bins_offsets(hk_TileBins *bins, int ranges, int keys, hk_Error *err)
{
    const size_t tiles = (size_t)bins->tiles_x * (size_t)bins->tiles_y;
    uint64_t *count = bins->count;
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
        (keys && !HK_RESERVE(bins->keys, bins->keys_cap, (size_t)total, err))) {
        hk_tile_bins_free(bins);
        return HK_ERR_NOMEM;
    }
    return HK_OK;
}

void hk_tile_bins_end(hk_TileBins *bins)
{
    order_heavy_first(bins, (size_t)bins->tiles_x * (size_t)bins->tiles_y, bins->count); /* the counts are spent */
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
