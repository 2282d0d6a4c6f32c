/* hairkit helicoid interpolate: new strands on a surface, each the inverse-distance blend of
 * a helicoid file's guides (paper 003 §4.1-4.3), rooted at random area-uniform points or at
 * follicles spread by the particle sampler (docs/helicoids.md). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "helicoid_cli.h"
#include "hairkit/follicle_sampling.h"
#include "hairkit/rng.h"

static const char *const CMD = HK_HELICOID_CMD;

/* Interpolated strands leave the surface at least this steeply (radians; §4.3, see
 * hk_phelicoid_interpolate_on_surface): a floor for averages of guides that lean different
 * ways, not a style (the guides set the angle). */
static const double MIN_ELEVATION = 0.17453292519943295; /* 10 degrees */

/* count roots uniform by area on the mesh (a triangle by its area, then uniform in it),
 * each from the counter-based RNG keyed by its index: the same roots whatever the threads. */
static void mesh_roots(const hk_Mesh *m, long count, uint64_t seed, const double *cumulative, hk_Vec3 *pos,
                       hk_Vec3 *normal)
{
#pragma omp parallel for schedule(static)
    for (long i = 0; i < count; i++) {
        const double u = hk_rng_uniform(seed, 101, (uint64_t)i) * cumulative[m->triangle_count];
        int lo = 0, hi = m->triangle_count - 1;
        while (lo < hi) {
            const int mid = (lo + hi) / 2;
            if (cumulative[mid + 1] <= u) lo = mid + 1;
            else hi = mid;
        }
        double r1 = hk_rng_uniform(seed, 102, (uint64_t)i), r2 = hk_rng_uniform(seed, 103, (uint64_t)i);
        if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
        const int *t = m->triangles + 3 * lo;
        const double b[3] = {1.0 - r1 - r2, r1, r2};
        hk_Vec3 p = hk_v3_zero(), n = hk_v3_zero();
        for (int k = 0; k < 3; k++) {
            p = hk_v3_madd(p, m->positions[t[k]], b[k]);
            n = hk_v3_madd(n, m->normals[t[k]], b[k]);
        }
        pos[i] = p;
        normal[i] = hk_v3_normalize(n);
    }
}

hk_Status hk_helicoid_cli_interpolate_at(const hk_PHelicoid *guides, const hk_Vec3 *guide_normals, int guide_count,
                                         const hk_Vec3 *roots, const hk_Vec3 *normals, long count, double power,
                                         hk_PHelicoid *out, hk_Error *err)
{
    hk_FirstError failed;
    hk_first_error_init(&failed);
#pragma omp parallel for schedule(static)
    for (long i = 0; i < count; i++) {
        hk_Error e;
        const hk_Vec3 x = roots[i];
        const hk_Status st =
            guide_normals
                ? hk_phelicoid_interpolate_on_surface(guides, guide_normals, guide_count, x, normals[i], power,
                                                      MIN_ELEVATION, &out[i], &e)
                : hk_phelicoid_interpolate(guides, guide_count, x, normals ? &normals[i] : NULL, power, &out[i], &e);
        if (st != HK_OK) hk_first_error_record(&failed, i, &e);
    }
    if (failed.index >= 0)
        return hk_error_set(err, failed.error.code, "interpolated strand %ld: %s", failed.index + 1,
                            failed.error.message);
    return HK_OK;
}

/* Roots drawn area-uniformly on the mesh: --count N, or --density per cm^2 of its area. */
static hk_Status random_roots(const hk_HelicoidArgs *a, const hk_Mesh *mesh, long *count, hk_Vec3 **roots,
                              hk_Vec3 **normals, hk_Error *err)
{
    double *cumulative = hk_alloc_array((size_t)mesh->triangle_count + 1, sizeof(double), err);
    if (!cumulative) return HK_ERR_NOMEM;
    cumulative[0] = 0.0;
    for (int t = 0; t < mesh->triangle_count; t++) cumulative[t + 1] = cumulative[t] + hk_mesh_triangle_area(mesh, t);
    const double area = cumulative[mesh->triangle_count];
    long n = a->count ? a->count : (long)llround(area * 1e4 * a->density);
    hk_Status st = HK_OK;
    if (n < 1 || !(area > 0.0))
        st = hk_error_set(err, HK_ERR_INVALID, "%s: no area to grow %ld strands on", a->surface, n);
    else if (n > 10000000) st = hk_error_set(err, HK_ERR_INVALID, "%ld strands: at most 10,000,000", n);
    if (st == HK_OK) {
        *roots = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
        *normals = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
        if (!*roots || !*normals) st = HK_ERR_NOMEM;
    }
    if (st == HK_OK) {
        mesh_roots(mesh, n, a->seed, cumulative, *roots, *normals);
        *count = n;
    }
    hk_free(cumulative);
    return st;
}

/* Roots at follicles (§4.3): the particle sampler on the implicit surface of the wick (the
 * --surface mesh) and the head around it, normals from that surface. Prints a summary. */
static hk_Status follicle_roots(const hk_HelicoidArgs *a, const hk_Mesh *wick, long *count, hk_Vec3 **roots,
                                hk_Vec3 **normals, hk_Error *err)
{
    hk_Mesh head;
    memset(&head, 0, sizeof head);
    if (a->head && hk_obj_load(a->head, &head, err) != HK_OK) return err->code;
    if (hk_cli_stderr_is_tty() && !a->quiet)
        fprintf(stderr, "hairkit %s interpolate: sampling follicles %g mm apart on %s...\n", CMD, 1e3 * a->follicles,
                a->surface);
    hk_WickSamplingDef def = hk_default_wick_sampling_def();
    def.spacing = a->follicles;
    def.seed = a->seed;
    def.threads = a->threads;
    hk_CliProgress bar = {hk_cli_stderr_is_tty() && !a->quiet, "", -1};
    def.progress = hk_cli_progress;
    def.progress_user = &bar;
    hk_FollicleSamples f;
    hk_Error e;
    const double t0 = hk_seconds_now();
    hk_Status st = hk_wick_follicles(a->head ? &head : NULL, wick, &def, &f, &e);
    hk_cli_progress_done(&bar);
    hk_mesh_free(&head);
    if (st != HK_OK) {
        if (a->head) return hk_error_set(err, st, "follicles on %s (head %s): %s", a->surface, a->head, e.message);
        return hk_error_set(err, st, "follicles on %s: %s", a->surface, e.message);
    }
    if (!a->quiet)
        fprintf(stderr, "hairkit %s interpolate: %d follicles %g mm apart on %s (%.4g cm^2), %d iterations, %.3f s\n",
                CMD, f.count, 1e3 * a->follicles, a->surface, 1e4 * hk_mesh_area(wick), f.iterations,
                hk_seconds_now() - t0);
    *count = f.count, *roots = f.points, *normals = f.normals;
    f.points = f.normals = NULL; /* handed over */
    hk_follicle_samples_free(&f);
    return HK_OK;
}

/* The surface normal at each guide's root: at the closest point of the surface mesh (§4.3's W_i).
 * Warns about guides that leave into the surface (their neighbours are lifted off it, they are
 * not: a guide is reproduced as it is). */
static hk_Status guide_normals(const hk_HelicoidArgs *a, const hk_Mesh *mesh, const hk_HelicoidSet *guides,
                               hk_Vec3 *normals, hk_Error *err)
{
    for (int i = 0; i < guides->count; i++) {
        const hk_PHelicoid *g = &guides->strands[i];
        const double d = hk_mesh_closest_point(mesh, g->root, NULL, &normals[i]);
        if (d < 0.0 || !(hk_v3_norm(normals[i]) > 0.5))
            return hk_error_set(err, HK_ERR_INVALID, "%s: no surface normal for guide %d of %s", a->surface, i + 1,
                                a->input);
        const double lean = hk_v3_dot(hk_m3_col(&g->frame, 0), normals[i]);
        if (lean < 0.0 && !a->quiet)
            fprintf(stderr, "hairkit %s interpolate: warning: guide %d of %s points %.0f degrees into %s at its root\n",
                    CMD, i + 1, a->input, asin(fmin(1.0, -lean)) * 57.29577951308232, a->surface);
    }
    return HK_OK;
}

int hk_helicoid_cli_interpolate(const hk_HelicoidArgs *a)
{
    hk_Error err;
    hk_HelicoidSet guides, made;
    memset(&made, 0, sizeof made);
    hk_Mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    if (hk_helicoid_file_load(a->input, &guides, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_Status st = hk_obj_load(a->surface, &mesh, &err);
    hk_Vec3 *roots = NULL, *normals = NULL, *gnormals = NULL;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    const int saved = omp_get_max_threads();
    if (a->threads > 0) omp_set_num_threads(a->threads);
    long count = 0;
    if (st == HK_OK) {
        gnormals = hk_alloc_array((size_t)guides.count, sizeof(hk_Vec3), &err);
        st = gnormals ? guide_normals(a, &mesh, &guides, gnormals, &err) : HK_ERR_NOMEM;
    }
    if (st == HK_OK)
        st = a->follicles > 0.0 ? follicle_roots(a, &mesh, &count, &roots, &normals, &err)
                                : random_roots(a, &mesh, &count, &roots, &normals, &err);
    const double t0 = hk_seconds_now();
    if (st == HK_OK) st = hk_helicoid_set_alloc(&made, (int)count, &err);
    if (st == HK_OK)
        st = hk_helicoid_cli_interpolate_at(guides.strands, gnormals, guides.count, roots, normals, count, a->power,
                                            made.strands, &err);
    const double t1 = hk_seconds_now();
    made.step = a->step > 0.0 ? a->step : guides.step;
    made.waviness = guides.waviness;
    made.wave_jitter = guides.wave_jitter;
    if (st == HK_OK) st = hk_helicoid_cli_trace_set(&made, made.step, a->seed, a->threads, &hair, &err);
    const double t2 = hk_seconds_now();
    if (a->threads > 0) omp_set_num_threads(saved);
    if (st == HK_OK) st = hk_hair_save(a->output, &hair, &err);
    if (st == HK_OK && a->params) st = hk_helicoid_file_save(a->params, &made, "interpolated by hairkit", &err);
    if (st == HK_OK && !a->quiet)
        fprintf(stderr,
                "hairkit %s interpolate: %ld strands from %d guides: parameters %.3f s, traced %.3f s (%u points)\n",
                CMD, count, guides.count, t1 - t0, t2 - t1, hair.point_count);
    hk_hair_free(&hair);
    hk_free(roots), hk_free(normals), hk_free(gnormals);
    hk_mesh_free(&mesh);
    hk_helicoid_set_free(&made);
    hk_helicoid_set_free(&guides);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}
