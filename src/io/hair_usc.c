/* USC-HairSalon .data files (docs/file-formats.md, "USC-HairSalon"): little-endian
 * i32 number of strands, then for each strand i32 number of vertices and that many
 * float32 x, y, z. There is no header to check the total against: a first pass walks the
 * strands' counts through the file (seeking over the points), so that the points are
 * allocated only once the counts are known to fit the file. */
#include <string.h>

#include "hair_io.h"
#include "hairkit/hair_formats.h"

hk_Status hk_usc_load(const char *path, hk_HairFile *h, hk_Error *err)
{
    memset(h, 0, sizeof *h);
    hk_BinIn in;
    hk_Status st = hk_binin_open(&in, path, err);
    if (st != HK_OK) return st;
    unsigned char b[4];
    uint32_t *counts = NULL;
    st = hk_binin_read(&in, b, 4, "the strand count", err);
    if (st != HK_OK) goto done;
    const int32_t ns = (int32_t)hk_le_u32(b);
    /* Every strand takes at least 4 + 12 bytes. */
    if (ns < 0 || 4 + 16 * (uint64_t)ns > in.size) {
        st = hk_binin_error(&in, 0, err, "%d strands cannot fit in a file of %llu bytes", ns,
                            (unsigned long long)in.size);
        goto done;
    }
    counts = hk_alloc_array((size_t)ns, sizeof *counts, err);
    if (!counts) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    for (int32_t s = 0; s < ns; s++) {
        const uint64_t at = in.offset;
        st = hk_binin_read(&in, b, 4, "a strand's vertex count", err);
        if (st != HK_OK) goto done;
        const int32_t n = (int32_t)hk_le_u32(b);
        if (n < 1 || n > 65536) {
            st = hk_binin_error(&in, at, err, "strand %d has %d vertices (1 to 65536 are read)", s, n);
            goto done;
        }
        if (in.offset + 12 * (uint64_t)n > in.size) {
            st = hk_binin_error(&in, at, err,
                                "truncated: strand %d announces %d vertices (%llu bytes), the file ends at %llu", s, n,
                                12 * (unsigned long long)n, (unsigned long long)in.size);
            goto done;
        }
        counts[s] = (uint32_t)n;
        st = hk_binin_seek(&in, in.offset + 12 * (uint64_t)n, err);
        if (st != HK_OK) goto done;
    }
    if (in.offset != in.size) {
        st = hk_binin_error(&in, in.offset, err, "%llu bytes after the last strand",
                            (unsigned long long)(in.size - in.offset));
        goto done;
    }
    st = hk_hair_alloc(h, (uint32_t)ns, counts, err);
    if (st != HK_OK) goto done;
    st = hk_binin_seek(&in, 4, err);
    for (int32_t s = 0; s < ns && st == HK_OK; s++) {
        st = hk_binin_seek(&in, in.offset + 4, err);
        if (st == HK_OK)
            st = hk_binin_read_xyz(&in, h->points + 3 * (size_t)h->first_point[s], counts[s], 3, "the vertices", err);
    }
    if (st == HK_OK) st = hk_hair_check_finite(path, h, err);
done:
    hk_free(counts);
    hk_binin_close(&in);
    if (st != HK_OK) hk_hair_free(h);
    return st;
}

hk_Status hk_usc_save(const char *path, const hk_HairFile *h, hk_Error *err)
{
    if (h->strand_count > INT32_MAX)
        return hk_error_set(err, HK_ERR_INVALID, "%s: %u strands are more than a .data file holds", path,
                            h->strand_count);
    hk_Writer w;
    hk_Status st = hk_writer_open(&w, path, err);
    if (st != HK_OK) return st;
    hk_writer_u32(&w, h->strand_count);
    for (uint32_t s = 0; s < h->strand_count; s++) {
        const uint32_t n = hk_hair_strand_points(h, s);
        hk_writer_u32(&w, n);
        const float *p = h->points + 3 * (size_t)h->first_point[s];
        for (size_t i = 0; i < 3 * (size_t)n; i++) hk_writer_f32(&w, p[i]);
    }
    return hk_writer_commit(&w, err);
}
