/* Points uniform by area on a triangle mesh (include/hairkit/mesh.h): roots for strands
 * spread over a surface with no follicle sampling (Piuze, Kry and Siddiqi, "Generalized
 * helicoids for modeling hair geometry", 2011, §4.3 grows interpolated strands this way). */
#include <omp.h>

#include "hairkit/mesh.h"
#include "hairkit/rng.h"

/* RNG streams (hk_rng_uniform) of the triangle and of the two barycentric draws: those
 * `hairkit helicoid interpolate` has always used, so that its roots stay the same. */
enum { TRIANGLE_STREAM = 101, FIRST_STREAM = 102, SECOND_STREAM = 103 };

hk_Status hk_mesh_sample_uniform(const hk_Mesh *m, long count, uint64_t seed, int threads, hk_Vec3 *point,
                                 hk_Vec3 *normal, hk_Error *err)
{
    if (count < 0) return hk_error_set(err, HK_ERR_INVALID, "mesh sampling: %ld points", count);
    double *cumulative = hk_alloc_array((size_t)m->triangle_count + 1, sizeof(double), err);
    if (!cumulative) return HK_ERR_NOMEM;
    cumulative[0] = 0.0;
    for (int t = 0; t < m->triangle_count; t++) cumulative[t + 1] = cumulative[t] + hk_mesh_triangle_area(m, t);
    const double area = cumulative[m->triangle_count];
    if (!(area > 0.0) || !(area < 1e300)) {
        hk_free(cumulative);
        return hk_error_set(err, HK_ERR_INVALID, "mesh sampling: the mesh has no finite area (%g)", area);
    }
#pragma omp parallel for schedule(static) num_threads(threads > 0 ? threads : omp_get_max_threads())
    for (long i = 0; i < count; i++) {
        const double u = hk_rng_uniform(seed, TRIANGLE_STREAM, (uint64_t)i) * area;
        int lo = 0, hi = m->triangle_count - 1;
        while (lo < hi) { /* the triangle whose share of the area holds u */
            const int mid = (lo + hi) / 2;
            if (cumulative[mid + 1] <= u)
                lo = mid + 1;
            else
                hi = mid;
        }
        /* uniform in the triangle: a point of the unit square folded onto the half below
         * its diagonal */
        double r1 = hk_rng_uniform(seed, FIRST_STREAM, (uint64_t)i),
               r2 = hk_rng_uniform(seed, SECOND_STREAM, (uint64_t)i);
        if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
        const int *t = m->triangles + 3 * lo;
        const double b[3] = {1.0 - r1 - r2, r1, r2};
        hk_Vec3 p = hk_v3_zero(), n = hk_v3_zero();
        for (int k = 0; k < 3; k++) {
            p = hk_v3_madd(p, m->positions[t[k]], b[k]);
            n = hk_v3_madd(n, m->normals[t[k]], b[k]);
        }
        point[i] = p;
        if (normal) normal[i] = hk_v3_normalize(n);
    }
    hk_free(cumulative);
    return HK_OK;
}
