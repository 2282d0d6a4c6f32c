/* Every hair point projected onto a view (the picture, the light's map): 5 million a
 * frame of a full head, twice, each hk_view_project's doubles. Four points at a time
 * where the CPU has AVX (points_avx.h: the same operations per point, the same bits). */
#include <omp.h>

#include "core/linalg.h"
#include "points_avx.h"
#include "render_internal.h"

#ifdef HK_POINTS_AVX
/* Points i .. while four remain before hi; returns where it stopped. */
__attribute__((target("avx"))) static size_t project_avx(const hk_View *v, const float *p, size_t i, size_t hi,
                                                         hk_RasterPoint *out)
{
    const __m256d ox = _mm256_set1_pd(v->origin.x), oy = _mm256_set1_pd(v->origin.y), oz = _mm256_set1_pd(v->origin.z);
    const __m256d half_w = _mm256_set1_pd(0.5 * v->width), half_h = _mm256_set1_pd(0.5 * v->height);
    const __m256d focal = _mm256_set1_pd(v->focal), offset = _mm256_set1_pd(v->depth_offset);
    const __m256d nearest = _mm256_set1_pd(1e-9);
    for (; i + 4 <= hi; i += 4) {
        __m256d x, y, z;
        hk_load4_points_avx(p, i, &x, &y, &z);
        x = _mm256_sub_pd(x, ox), y = _mm256_sub_pd(y, oy), z = _mm256_sub_pd(z, oz);
        const __m256d depth = hk_dot4_avx(x, y, z, v->forward);
        /* z > 1e-9 ? focal / z : 0 (+0, as the scalar's) */
        const __m256d s = v->perspective
                              ? _mm256_and_pd(_mm256_cmp_pd(depth, nearest, _CMP_GT_OQ), _mm256_div_pd(focal, depth))
                              : focal;
        __m128 rx = _mm256_cvtpd_ps(_mm256_add_pd(half_w, _mm256_mul_pd(s, hk_dot4_avx(x, y, z, v->right))));
        __m128 ry = _mm256_cvtpd_ps(_mm256_sub_pd(half_h, _mm256_mul_pd(s, hk_dot4_avx(x, y, z, v->up))));
        __m128 rz = _mm256_cvtpd_ps(v->perspective ? depth : _mm256_add_pd(depth, offset));
        __m128 rs = _mm256_cvtpd_ps(s);
        _MM_TRANSPOSE4_PS(rx, ry, rz, rs); /* one point a row: x, y, z, px_per_unit */
        float *o = &out[i].x;
        _mm_storeu_ps(o, rx), _mm_storeu_ps(o + 4, ry), _mm_storeu_ps(o + 8, rz), _mm_storeu_ps(o + 12, rs);
    }
    return i;
}
#endif

void hk_view_project_points(const hk_View *v, const hk_HairFile *h, hk_RasterPoint *out, int threads)
{
    const size_t n = h->point_count;
#ifdef HK_POINTS_AVX
    const int avx = hk_avx_path();
#endif
#pragma omp parallel num_threads(threads)
    {
        size_t i, hi;
        hk_points_part(n, &i, &hi);
#ifdef HK_POINTS_AVX
        if (avx) i = project_avx(v, h->points, i, hi, out);
#endif
        for (; i < hi; i++) out[i] = hk_view_project(v, hk_hair_point(h, (uint32_t)i));
    }
}
