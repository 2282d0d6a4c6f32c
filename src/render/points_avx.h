/* Four hair points at a time in AVX, for the passes over every point of a picture (the
 * camera's fit, the projections onto the picture and the light's map): the points are
 * the file's floats, three a point, and those passes do their arithmetic in doubles.
 * Four lanes do each point's IEEE operations in the same order as the scalar code (no
 * FMA: target "avx" only), so the same bits; min and max are exact in any order. */
#ifndef HK_RENDER_POINTS_AVX_H
#define HK_RENDER_POINTS_AVX_H

#include <stddef.h>

#include <omp.h>

/* The calling thread's part [*lo, *hi) of n points, in an OpenMP parallel region:
 * contiguous parts in thread order (each part's vectors and its rest in it). */
static inline void hk_points_part(size_t n, size_t *lo, size_t *hi)
{
    const size_t parts = (size_t)omp_get_num_threads(), part = (size_t)omp_get_thread_num();
    *lo = n * part / parts, *hi = n * (part + 1) / parts;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define HK_POINTS_AVX 1
#include <immintrin.h>

#include "hairkit/vecmath.h"

/* Points i .. i + 3 of p (x, y, z floats each) as doubles, one lane a point. */
__attribute__((target("avx"))) static inline void hk_load4_points_avx(const float *p, size_t i, __m256d *x, __m256d *y,
                                                                      __m256d *z)
{
    const __m128 v0 = _mm_loadu_ps(p + 3 * i), v1 = _mm_loadu_ps(p + 3 * i + 4), v2 = _mm_loadu_ps(p + 3 * i + 8);
    /* v0 = x0 y0 z0 x1, v1 = y1 z1 x2 y2, v2 = z2 x3 y3 z3 */
    const __m128 t = _mm_shuffle_ps(v1, v2, _MM_SHUFFLE(2, 1, 3, 2)); /* x2 y2 x3 y3 */
    const __m128 u = _mm_shuffle_ps(v0, v1, _MM_SHUFFLE(1, 0, 2, 1)); /* y0 z0 y1 z1 */
    *x = _mm256_cvtps_pd(_mm_shuffle_ps(v0, t, _MM_SHUFFLE(2, 0, 3, 0)));
    *y = _mm256_cvtps_pd(_mm_shuffle_ps(u, t, _MM_SHUFFLE(3, 1, 2, 0)));
    *z = _mm256_cvtps_pd(_mm_shuffle_ps(u, v2, _MM_SHUFFLE(3, 0, 3, 1)));
}

/* (a.x b.x + a.y b.y) + a.z b.z, as hk_v3_dot, a in lanes and b one vector. */
__attribute__((target("avx"))) static inline __m256d hk_dot4_avx(__m256d x, __m256d y, __m256d z, hk_Vec3 b)
{
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, _mm256_set1_pd(b.x)), _mm256_mul_pd(y, _mm256_set1_pd(b.y))),
                         _mm256_mul_pd(z, _mm256_set1_pd(b.z)));
}

/* The largest and smallest of a vector's four lanes. */
__attribute__((target("avx"))) static inline double hk_max4_avx(__m256d v)
{
    double l[4];
    _mm256_storeu_pd(l, v);
    double m = l[0];
    for (int k = 1; k < 4; k++) m = l[k] > m ? l[k] : m;
    return m;
}
__attribute__((target("avx"))) static inline double hk_min4_avx(__m256d v)
{
    double l[4];
    _mm256_storeu_pd(l, v);
    double m = l[0];
    for (int k = 1; k < 4; k++) m = l[k] < m ? l[k] : m;
    return m;
}
#endif

#endif
