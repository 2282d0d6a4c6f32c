/* Items in order of increasing depth: a stable LSD radix sort on the bits of positive
 * floats (which order like unsigned integers), so that equal depths keep item order
 * and the result is the same on every run. */
#include <string.h>

#include "render_internal.h"

void hk_depth_order(uint32_t n, const float *depth, uint32_t *order, uint32_t *work)
{
    uint32_t *keys = work, *key_tmp = work + n, *tmp = work + 2 * (size_t)n, *ord = order;
    for (uint32_t i = 0; i < n; i++) {
        float d = depth[i] > 0.0f ? depth[i] : 0.0f; /* NaN and negatives first */
        memcpy(&keys[i], &d, sizeof d);
        ord[i] = i;
    }
    /* Four passes of 8 bits, ping-ponging between the buffers: after an even number
     * of passes the result is back in `order`. */
    for (int shift = 0; shift < 32; shift += 8) {
        uint32_t count[257] = {0};
        for (uint32_t i = 0; i < n; i++) count[((keys[i] >> shift) & 0xffu) + 1]++;
        for (int b = 0; b < 256; b++) count[b + 1] += count[b];
        for (uint32_t i = 0; i < n; i++) {
            const uint32_t at = count[(keys[i] >> shift) & 0xffu]++;
            key_tmp[at] = keys[i];
            tmp[at] = ord[i];
        }
        uint32_t *swap = keys;
        keys = key_tmp, key_tmp = swap;
        swap = ord, ord = tmp, tmp = swap;
    }
}

void hk_sort_by_high_bits(uint64_t *keys, uint32_t n, uint64_t *tmp)
{
    if (n < 2) return;
    uint64_t *src = keys, *dst = tmp;
    for (int shift = 32; shift < 64; shift += 8) {
        uint32_t count[257] = {0};
        for (uint32_t i = 0; i < n; i++) count[((src[i] >> shift) & 0xffu) + 1]++;
        /* Every key in one bucket: this pass would copy them in place, skip it. */
        if (count[((src[0] >> shift) & 0xffu) + 1] == n) continue;
        for (int b = 0; b < 256; b++) count[b + 1] += count[b];
        for (uint32_t i = 0; i < n; i++) dst[count[(src[i] >> shift) & 0xffu]++] = src[i];
        uint64_t *swap = src;
        src = dst, dst = swap;
    }
    if (src != keys) memcpy(keys, src, (size_t)n * sizeof *keys);
}
