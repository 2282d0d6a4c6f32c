/* HK_TILE_BINS_BUILD: the passes of the tile bins over the items, made in the file that
 * gives the box function, so that the compiler folds the box (a few comparisons per
 * segment, for 5 million segments in each view of a full head) into the loop instead
 * of calling it through a pointer. The steps around the passes are in tile_bins.c. */
#ifndef HK_TILE_BINS_INLINE_H
#define HK_TILE_BINS_INLINE_H

#include <omp.h>

#include "raster_inline.h"
#include "render_internal.h"

/* Item i's entry in tile t (fill 1: written at the tile's next place, with its key k
 * when there are keys; fill 0: counted), unless the tile culls it. */
static inline __attribute__((always_inline)) void hk_tile_bin_entry(size_t t, uint32_t i, float k, const float *key,
                                                                    const float *cull, uint32_t *items, float *keys,
                                                                    uint64_t *c, int fill)
{
    if (cull && k >= cull[t]) return;
    if (fill) {
        const uint64_t at = c[t]++;
        if (key) keys[at] = k;
        items[at] = i;
    } else {
        c[t]++;
    }
}

/* HK_TILE_BINS_BUILD(name, box_of) defines
 *   static hk_Status name(uint32_t item_count, void *user, const float *key,
 *                         const float *cull, int width, int height, hk_TileBins *bins,
 *                         hk_Error *err)
 * which puts items 0 .. item_count - 1 into the tiles of a width x height picture that
 * their boxes touch (box_of(user, item, &rect): 0 when the item is not drawn). bins:
 * zeroed before its first build; a build reuses the arrays of the one before. key
 * (NULL: none): a number per item, copied next to its entries (bins->keys), so that a
 * tile reads its items' keys in order instead of scattered. cull (NULL: none; only with
 * keys): a number per tile; an item whose key is at or beyond it is left out of that
 * tile.
 *
 * The items are cut into one contiguous range per thread; each range is counted per
 * tile, the counts are laid out tile by tile and range by range, and each range fills
 * its own places: the bins hold the items in item order whatever the number of
 * threads. One pass over the items per step, one range per thread: (fill 0) find every
 * item's box, keep it in bins->boxes and count each range's entries per tile into
 * at[range][tile], or (fill 1) write the entries from the offsets in at[range][tile],
 * reading the kept boxes. A box is computed once: that is most of the binning's work,
 * and the tiles read the boxes again to find which of their blocks a segment covers.
 * (A macro rather than a function taking box_of: OpenMP outlines the parallel loop
 * before anything is inlined, so a pointer passed in stayed a call per item.) */
#define HK_TILE_BINS_BUILD(name, box_of)                                                                               \
    /* Items lo .. hi - 1 (their tiles' counts or places in c). Everything in locals,    \
     * which the stores cannot change: read through the shared data of OpenMP's loop,     \
     * they were loaded again for every item. */                             \
    static inline __attribute__((always_inline)) void name##_range(                                                    \
        uint32_t lo, uint32_t hi, void *user, const float *key, const float *cull, hk_TileBox *boxes, uint32_t *items, \
        float *keys, int tiles_x, uint64_t *c, int fill)                                                               \
    {                                                                                                                  \
        for (uint32_t i = lo; i < hi; i++) {                                                                           \
            hk_TileBox *b = &boxes[i];                                                                                 \
            if (!fill) {                                                                                               \
                hk_Rect box;                                                                                           \
                if (box_of(user, i, &box))                                                                             \
                    b->x0 = (uint16_t)box.x0, b->y0 = (uint16_t)box.y0, b->x1 = (uint16_t)box.x1,                      \
                    b->y1 = (uint16_t)box.y1;                                                                          \
                else                                                                                                   \
                    b->x0 = b->y0 = b->x1 = b->y1 = 0; /* empty: x1 <= x0 */                                           \
            }                                                                                                          \
            const hk_TileBox r = *b;                                                                                   \
            if (r.x1 <= r.x0) continue;                                                                                \
            const float k = key ? key[i] : 0.0f;                                                                       \
            const unsigned tx0 = r.x0 / HK_TILE, tx1 = (r.x1 - 1u) / HK_TILE;                                          \
            const unsigned ty0 = r.y0 / HK_TILE, ty1 = (r.y1 - 1u) / HK_TILE;                                          \
            if (tx0 == tx1 && ty0 == ty1) { /* one tile, most items: without the loops' setup */                       \
                hk_tile_bin_entry((size_t)ty0 *(size_t)tiles_x + tx0, i, k, key, cull, items, keys, c, fill);          \
                continue;                                                                                              \
            }                                                                                                          \
            for (unsigned ty = ty0; ty <= ty1; ty++)                                                                   \
                for (unsigned tx = tx0; tx <= tx1; tx++)                                                               \
                    hk_tile_bin_entry((size_t)ty *(size_t)tiles_x + tx, i, k, key, cull, items, keys, c, fill);        \
        }                                                                                                              \
    }                                                                                                                  \
    static void name##_ranges(uint32_t item_count, void *user, const float *key, const float *cull, hk_TileBins *bins, \
                              int ranges, uint64_t *at, int fill)                                                      \
    {                                                                                                                  \
        const size_t tiles = (size_t)bins->tiles_x * (size_t)bins->tiles_y;                                            \
        const int tiles_x = bins->tiles_x;                                                                             \
        hk_TileBox *boxes = bins->boxes;                                                                               \
        uint32_t *items = bins->items;                                                                                 \
        float *keys = bins->keys;                                                                                      \
        _Pragma("omp parallel for schedule(static, 1) num_threads(ranges)") for (int g = 0; g < ranges; g++)           \
        {                                                                                                              \
            const uint32_t lo = (uint32_t)((uint64_t)item_count * (uint64_t)g / (uint64_t)ranges);                     \
            const uint32_t hi = (uint32_t)((uint64_t)item_count * (uint64_t)(g + 1) / (uint64_t)ranges);               \
            uint64_t *c = at + (size_t)g * tiles;                                                                      \
            if (fill)                                                                                                  \
                name##_range(lo, hi, user, key, cull, boxes, items, keys, tiles_x, c, 1);                              \
            else                                                                                                       \
                name##_range(lo, hi, user, key, cull, boxes, items, keys, tiles_x, c, 0);                              \
        }                                                                                                              \
    }                                                                                                                  \
    static hk_Status name(uint32_t item_count, void *user, const float *key, const float *cull, int width, int height, \
                          int ranges, hk_TileBins *bins, hk_Error *err)                                                \
    {                                                                                                                  \
        hk_Status st = hk_tile_bins_begin(item_count, width, height, bins, ranges, err);                               \
        if (st != HK_OK) return st;                                                                                    \
        name##_ranges(item_count, user, key, cull, bins, ranges, bins->count, 0);                                      \
        if ((st = hk_tile_bins_offsets(bins, ranges, key != NULL, err)) != HK_OK) return st;                           \
        name##_ranges(item_count, user, key, cull, bins, ranges, bins->count, 1);                                      \
        hk_tile_bins_end(bins);                                                                                        \
        return HK_OK;                                                                                                  \
    }

#endif
