/* Items in order of increasing depth: a stable LSD radix sort on the bits of positive
 * floats (which order like unsigned integers), so that equal depths keep item order
 * and the result is the same on every run. */
#include <string.h>

#include "render_internal.h"

void hk_depth_order(uint32_t n, const float *depth, uint32_t *order, uint32_t *work)
{
    uint32_t *keys = work, *key_tmp = work + n, *tmp = work + 2 * (size_t)n, *ord = order;
    /* The four bytes' histograms in one read of the keys. */
    uint32_t count[4][257];
    memset(count, 0, sizeof count);
    for (uint32_t i = 0; i < n; i++) {
        float d = depth[i] > 0.0f ? depth[i] : 0.0f; /* NaN and negatives first */
        uint32_t k;
        memcpy(&k, &d, sizeof d);
        keys[i] = k;
        ord[i] = i;
        for (int b = 0; b < 4; b++) count[b][((k >> (8 * b)) & 0xffu) + 1]++;
    }
    /* A pass of 8 bits per byte, ping-ponging between the buffers. A byte that is the
     * same in every key (the exponent's, within a tile: its depths span less than a
     * factor of two) would copy the keys in place: its pass is skipped. */
    for (int b = 0; b < 4; b++) {
        const int shift = 8 * b;
        uint32_t *c = count[b];
        if (n == 0 || c[((keys[0] >> shift) & 0xffu) + 1] == n) continue;
        for (int v = 0; v < 256; v++) c[v + 1] += c[v];
        for (uint32_t i = 0; i < n; i++) {
            const uint32_t at = c[(keys[i] >> shift) & 0xffu]++;
            key_tmp[at] = keys[i];
            tmp[at] = ord[i];
        }
        uint32_t *swap = keys;
        keys = key_tmp, key_tmp = swap;
        swap = ord, ord = tmp, tmp = swap;
    }
    if (ord != order) memcpy(order, ord, (size_t)n * sizeof *order);
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

int hk_sort_nearly_sorted(uint64_t *keys, size_t n, size_t budget)
{
    size_t moves = 0;
    for (size_t i = 1; i < n; i++) {
        const uint64_t v = keys[i];
        size_t j = i;
        for (; j > 0 && keys[j - 1] > v; j--) keys[j] = keys[j - 1];
        keys[j] = v;
        moves += i - j;
        if (moves > budget) return 0;
    }
    return 1;
}
