/* AMD TressFX .tfx files (docs/file-formats.md, "TressFX"): little-endian, every strand
 * the same number of vertices.
 *
 * v3.0 (296-byte header): f32 version, u32 numStrands, u32 vertsPerStrand,
 *   u32 numFollowHairsPerGuide, u32 bothEndsImmovable, u32 reserved1[31], u32 offsets
 *   [vertices, perStrandThickness, perStrandTexCoord, perVertexColor, guideHairStrand,
 *   perVertexTexCoord], u32 reserved2[32]; vertices float3, strand-major.
 * v4.0 (160-byte header): f32 version, u32 numStrands, u32 vertsPerStrand,
 *   u32 offsetVertexPosition, u32 offsetStrandUV, u32 offsetVertexUV,
 *   u32 offsetStrandThickness, u32 offsetVertexColor, u32 reserved[32]; vertices float4
 *   (x, y, z, w: w is 0 for a vertex that does not move, 1 otherwise).
 * Only the guide vertices are read; UVs, thickness, colours and follow-hair counts are
 * ignored. */
#include <string.h>

#include "hair_io.h"
#include "hairkit/hair_formats.h"

#define V3_HEADER 296
#define V4_HEADER 160

hk_Status hk_tfx_load(const char *path, hk_HairFile *h, hk_Error *err)
{
    memset(h, 0, sizeof *h);
    hk_BinIn in;
    hk_Status st = hk_binin_open(&in, path, err);
    if (st != HK_OK) return st;
    unsigned char head[V3_HEADER];
    st = hk_binin_read(&in, head, 4, "the TressFX header", err);
    if (st != HK_OK) goto done;
    const float version = hk_le_f32(head);
    int v3 = version == 3.0f, v4 = version == 4.0f;
    if (!v3 && !v4) {
        st = hk_binin_error(&in, 0, err, "not a TressFX file: version %g (3.0 and 4.0 are read)", (double)version);
        goto done;
    }
    const size_t header = v3 ? V3_HEADER : V4_HEADER;
    st = hk_binin_read(&in, head + 4, header - 4, v3 ? "the TressFX 3 header" : "the TressFX 4 header", err);
    if (st != HK_OK) goto done;
    const uint32_t ns = hk_le_u32(head + 4), nv = hk_le_u32(head + 8);
    const size_t offset_at = v3 ? 144 : 12; /* where the vertex offset is stored */
    const uint32_t offset = hk_le_u32(head + offset_at);
    const uint64_t stride = v3 ? 3 : 4;
    if (nv < 1 || nv > 65536) {
        st = hk_binin_error(&in, 8, err, "%u vertices per strand (1 to 65536 are read)", nv);
        goto done;
    }
    if ((uint64_t)ns * nv > UINT32_MAX) {
        st = hk_binin_error(&in, 4, err, "%u strands of %u vertices are more than 2^32 points", ns, nv);
        goto done;
    }
    if (offset < header) {
        st = hk_binin_error(&in, offset_at, err, "the vertices' offset %u lies inside the %zu-byte header", offset,
                            header);
        goto done;
    }
    const uint64_t need = (uint64_t)offset + (uint64_t)ns * nv * stride * 4;
    if (need > in.size) {
        st = hk_binin_error(&in, 4, err,
                            "truncated: the header announces %u strands of %u vertices at offset %u (%llu bytes), "
                            "the file has %llu",
                            ns, nv, offset, (unsigned long long)need, (unsigned long long)in.size);
        goto done;
    }
    uint32_t *counts = hk_alloc_array(ns, sizeof *counts, err);
    if (!counts) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    for (uint32_t s = 0; s < ns; s++) counts[s] = nv;
    st = hk_hair_alloc(h, ns, counts, err);
    hk_free(counts);
    if (st != HK_OK) goto done;
    st = hk_binin_seek(&in, offset, err);
    if (st == HK_OK) st = hk_binin_read_xyz(&in, h->points, (size_t)ns * nv, (size_t)stride, "the vertices", err);
    if (st == HK_OK) st = hk_hair_check_finite(path, h, err);
done:
    hk_binin_close(&in);
    if (st != HK_OK) hk_hair_free(h);
    return st;
}

hk_Status hk_tfx_save(const char *path, const hk_HairFile *hair, uint32_t points, hk_Error *err)
{
    hk_HairFile resampled;
    memset(&resampled, 0, sizeof resampled);
    const hk_HairFile *h = hair;
    const uint32_t first = h->strand_count ? hk_hair_strand_points(h, 0) : 0;
    const int uniform = hk_hair_uniform_strands(h);
    if (!uniform || (points && points != first)) {
        if (!points) {
            uint32_t lo = UINT32_MAX, hi = 0;
            for (uint32_t s = 0; s < h->strand_count; s++) {
                const uint32_t n = hk_hair_strand_points(h, s);
                lo = n < lo ? n : lo, hi = n > hi ? n : hi;
            }
            return hk_error_set(err, HK_ERR_INVALID,
                                "%s: TressFX needs the same number of points in every strand, these have %u to %u: "
                                "give the number to resample them to (--points N)",
                                path, lo, hi);
        }
        hk_Status st = hk_hair_resample(hair, points, &resampled, err);
        if (st != HK_OK) return st;
        h = &resampled;
    }
    const uint32_t nv = h->strand_count ? hk_hair_strand_points(h, 0) : 0;
    if (h->strand_count && nv < 2) {
        hk_hair_free(&resampled);
        return hk_error_set(err, HK_ERR_INVALID,
                            "%s: TressFX strands need at least 2 points, these have 1 (--points N resamples them)",
                            path);
    }
    hk_Writer w;
    hk_Status st = hk_writer_open(&w, path, err);
    if (st != HK_OK) {
        hk_hair_free(&resampled);
        return st;
    }
    unsigned char head[V4_HEADER];
    memset(head, 0, sizeof head);
    hk_put_f32(head, 4.0f);
    hk_put_u32(head + 4, h->strand_count);
    hk_put_u32(head + 8, nv);
    hk_put_u32(head + 12, V4_HEADER); /* offsetVertexPosition; no UVs, thickness or colours */
    hk_writer_bytes(&w, head, sizeof head);
    for (uint32_t s = 0; s < h->strand_count; s++)
        for (uint32_t i = 0; i < nv; i++) {
            const float *p = h->points + 3 * ((size_t)h->first_point[s] + i);
            hk_writer_f32(&w, p[0]);
            hk_writer_f32(&w, p[1]);
            hk_writer_f32(&w, p[2]);
            hk_writer_f32(&w, i == 0 ? 0.0f : 1.0f); /* the root does not move */
        }
    hk_hair_free(&resampled);
    return hk_writer_commit(&w, err);
}
