/* Items in order of increasing depth, stable (equal depths keep item order), so that
 * the result is the same on every run: a radix sort on the bits of positive floats
 * (which order like unsigned integers). A tile of a full head stops drawing, opaque,
 * after about a third of its segments, so the order is made as it is read: one pass
 * buckets the items by the highest 8 bits in which their keys differ, and each bucket
 * is sorted on the bits below when the reading reaches it. Stable throughout, this
 * gives the order of a full stable sort. */
#include <string.h>

#include "render_internal.h"

void hk_depth_order_begin(hk_DepthOrder *d, uint32_t n, const float *depth, const uint32_t *value, uint32_t *order,
                          uint32_t *work)
{
    /* An empty tile may have no work array yet (NULL): no offset is applied to it. */
    d->n = n, d->order = order, d->keys = work;
    d->key_tmp = n ? work + n : work, d->order_tmp = n ? work + 2 * (size_t)n : work;
    d->sorted = 0, d->bucket = 0;
    uint32_t *keys = d->order_tmp; /* unsorted keys; the buckets go to d->keys */
    uint32_t differ = 0;
    for (uint32_t i = 0; i < n; i++) {
        float v = depth[i] > 0.0f ? depth[i] : 0.0f; /* NaN and negatives first */
        uint32_t k;
        memcpy(&k, &v, sizeof v);
        keys[i] = k;
        differ |= k ^ keys[0];
    }
    /* Buckets by the 8 bits from the highest one in which the keys differ down: a
     * tile's depths span a few per cent, so whole bytes would put them in a handful
     * of buckets. */
    int high = 31;
    while (high > 0 && !(differ >> high)) high--;
    d->shift = high >= 7 ? high - 7 : 0;
    uint32_t count[256] = {0};
    for (uint32_t i = 0; i < n; i++) count[(keys[i] >> d->shift) & 0xffu]++;
    uint32_t at = 0;
    for (int v = 0; v < 256; v++) d->start[v] = at, at += count[v];
    d->start[256] = at;
    uint32_t fill[256];
    memcpy(fill, d->start, sizeof fill);
    for (uint32_t i = 0; i < n; i++) {
        const uint32_t slot = fill[(keys[i] >> d->shift) & 0xffu]++;
        d->keys[slot] = keys[i];
        order[slot] = value ? value[i] : i;
    }
}

/* Sorts order[lo, hi) by keys[lo, hi) on the bits below `shift` (those above are
 * equal within a bucket), stably: bytes from the lowest up (the last may reach into
 * the equal bits, which leaves the order as it is). */
static void sort_bucket(hk_DepthOrder *d, uint32_t lo, uint32_t hi)
{
    uint32_t *keys = d->keys + lo, *ord = d->order + lo;
    const uint32_t n = hi - lo;
    if (n <= 32) { /* insertion sort: stable, and cheapest for the many small buckets */
        for (uint32_t i = 1; i < n; i++) {
            const uint32_t k = keys[i], o = ord[i];
            uint32_t j = i;
            for (; j > 0 && keys[j - 1] > k; j--) keys[j] = keys[j - 1], ord[j] = ord[j - 1];
            keys[j] = k, ord[j] = o;
        }
        return;
    }
    uint32_t *key_tmp = d->key_tmp + lo, *tmp = d->order_tmp + lo;
    for (int shift = 0; shift < d->shift; shift += 8) {
        uint32_t count[257] = {0};
        for (uint32_t i = 0; i < n; i++) count[((keys[i] >> shift) & 0xffu) + 1]++;
        if (count[((keys[0] >> shift) & 0xffu) + 1] == n) continue; /* one value: in place already */
        for (int b = 0; b < 256; b++) count[b + 1] += count[b];
        for (uint32_t i = 0; i < n; i++) {
            const uint32_t to = count[(keys[i] >> shift) & 0xffu]++;
            key_tmp[to] = keys[i];
            tmp[to] = ord[i];
        }
        uint32_t *swap = keys;
        keys = key_tmp, key_tmp = swap;
        swap = ord, ord = tmp, tmp = swap;
    }
    if (ord != d->order + lo) {
        memcpy(d->order + lo, ord, (size_t)n * sizeof *ord);
        memcpy(d->keys + lo, keys, (size_t)n * sizeof *keys);
    }
}

void hk_depth_order_ready(hk_DepthOrder *d, uint32_t upto)
{
    if (upto > d->n) upto = d->n;
    while (d->sorted < upto) {
        while (d->start[d->bucket + 1] <= d->sorted) d->bucket++;
        sort_bucket(d, d->start[d->bucket], d->start[d->bucket + 1]);
        d->sorted = d->start[d->bucket + 1];
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
