/* Helicoid sets traced into hair files and strands interpolated at roots
 * (include/hairkit/helicoid_hair.h; Piuze, Kry and Siddiqi 2011, §3-4). */
#include <omp.h>

#include "core/core_internal.h"
#include "hairkit/helicoid_hair.h"
#include "hairkit/rng.h"

/* RNG stream of the strands' wave phases (hk_rng_uniform). */
enum { WAVE_PHASE_STREAM = 104 };

hk_Status hk_helicoid_set_trace(const hk_HelicoidSet *set, double step, uint64_t seed, int threads, hk_HairFile *hair,
                                hk_Error *err)
{
    /* Point counts first, so that the file is allocated once. */
    long total = 0;
    for (int s = 0; s < set->count; s++) {
        total += 1 + set->wisp_count[s];
        if (total > 100000000L) return hk_error_set(err, HK_ERR_INVALID, "more than 1e8 strands with the wisps");
    }
    uint32_t *counts = hk_alloc_array((size_t)total, sizeof(uint32_t), err);
    long *first = hk_alloc_array((size_t)set->count + 1, sizeof(long), err);
    if (!counts || !first) {
        hk_free(counts), hk_free(first);
        return HK_ERR_NOMEM;
    }
    hk_Status st = HK_OK;
    long k = 0;
    for (int s = 0; s < set->count && st == HK_OK; s++) {
        first[s] = k;
        const int n = hk_phelicoid_point_count(&set->strands[s], step);
        if (n < 2 || n > 65536)
            st = hk_error_set(err, HK_ERR_INVALID, "strand %d: %d points at step %g (2 to 65536 allowed)", s + 1, n,
                              step);
        for (int w = 0; w <= set->wisp_count[s]; w++) counts[k++] = (uint32_t)(n > 0 ? n : 0);
    }
    first[set->count] = k;
    if (st == HK_OK) st = hk_hair_alloc(hair, (uint32_t)total, counts, err);
    hk_free(counts);
    if (st != HK_OK) {
        hk_free(first);
        return st;
    }
    hk_FirstError failed;
    hk_first_error_init(&failed);
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads > 0 ? threads : omp_get_max_threads())
    for (int s = 0; s < set->count; s++) {
        if (hk_first_error_skip(&failed, s)) continue;
        const hk_PHelicoid *h = &set->strands[s];
        const int n = (int)(hair->first_point[first[s] + 1] - hair->first_point[first[s]]);
        const int m = 1 + set->wisp_count[s];
        hk_Error e;
        /* the strand's wave phase: from the seed and its index, whatever the threads */
        hk_Waviness wave = set->waviness;
        wave.phase = 2.0 * HK_PI * set->wave_jitter * hk_rng_uniform(seed, WAVE_PHASE_STREAM, (uint64_t)s);
        if (set->has_waves && set->has_waves[s]) wave = set->waves[s]; /* its own (Waves) */
        hk_Vec3 *pts = hk_alloc_array((size_t)n * (size_t)m, sizeof(hk_Vec3), &e);
        hk_Status rs = pts ? hk_phelicoid_trace(h, step, &wave, NULL, pts, NULL, &e) : HK_ERR_NOMEM;
        if (rs == HK_OK && m > 1)
            rs = hk_phelicoid_wisp(h, m - 1, set->wisp_radius[s], set->wisp_spread[s], (uint64_t)s, step, &wave,
                                   pts + n, &e);
        if (rs == HK_OK) {
            float *out = hair->points + 3 * (size_t)hair->first_point[first[s]];
            for (long i = 0; i < (long)n * m; i++) {
                out[3 * i] = (float)pts[i].x, out[3 * i + 1] = (float)pts[i].y, out[3 * i + 2] = (float)pts[i].z;
            }
        } else {
            hk_first_error_record(&failed, s, &e);
        }
        hk_free(pts);
    }
    hk_free(first);
    if (failed.index >= 0) {
        hk_hair_free(hair);
        return hk_error_set(err, failed.error.code, "strand %ld: %s", failed.index + 1, failed.error.message);
    }
    hair->default_thickness = 1e-4f;
    hk_hair_set_info(hair, "hairkit generalized helicoids");
    return HK_OK;
}

hk_Status hk_helicoid_interpolate_at(const hk_PHelicoid *guides, const hk_Vec3 *guide_normals, int guide_count,
                                     const hk_Vec3 *roots, const hk_Vec3 *normals, long count, double power,
                                     int threads, hk_PHelicoid *out, hk_Error *err)
{
    hk_FirstError failed;
    hk_first_error_init(&failed);
#pragma omp parallel for schedule(static) num_threads(threads > 0 ? threads : omp_get_max_threads())
    for (long i = 0; i < count; i++) {
        hk_Error e;
        const hk_Vec3 x = roots[i];
        const hk_Status st =
            guide_normals
                ? hk_phelicoid_interpolate_on_surface(guides, guide_normals, guide_count, x, normals[i], power,
                                                      HK_HELICOID_MIN_ELEVATION, &out[i], &e)
                : hk_phelicoid_interpolate(guides, guide_count, x, normals ? &normals[i] : NULL, power, &out[i], &e);
        if (st != HK_OK) hk_first_error_record(&failed, i, &e);
    }
    if (failed.index >= 0)
        return hk_error_set(err, failed.error.code, "interpolated strand %ld: %s", failed.index + 1,
                            failed.error.message);
    return HK_OK;
}
