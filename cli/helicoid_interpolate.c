/* hairkit helicoid interpolate: new strands on a surface, each the inverse-distance blend of
 * a helicoid file's guides (Piuze et al. 2011 §4.1-4.3), rooted at random area-uniform points or at
 * follicles spread by the particle sampler (docs/helicoids.md). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/core_internal.h"
#include "helicoid_cli.h"
#include "hairkit/follicle_sampling.h"

static const char *const CMD = HK_HELICOID_CMD;

/* Roots drawn area-uniformly on the mesh: --count N, or --density per cm^2 of its area. */
static hk_Status random_roots(const hk_HelicoidArgs *a, const hk_Mesh *mesh, long *count, hk_Vec3 **roots,
                              hk_Vec3 **normals, hk_Error *err)
{
    const double area = hk_mesh_area(mesh);
    long n = a->count ? a->count : (long)llround(area * 1e4 * a->density);
    if (n < 1 || !(area > 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "%s: no area to grow %ld strands on", a->surface, n);
    if (n > 10000000) return hk_error_set(err, HK_ERR_INVALID, "%ld strands: at most 10,000,000", n);
    *roots = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
    *normals = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
    if (!*roots || !*normals) return HK_ERR_NOMEM;
    const hk_Status st = hk_mesh_sample_uniform(mesh, n, a->seed, a->threads, *roots, *normals, err);
    if (st == HK_OK) *count = n;
    return st;
}

/* Roots at follicles (§4.3): the particle sampler on the implicit surface of the wick (the
 * --surface mesh) and the head around it, normals from that surface. Prints a summary. */
static hk_Status follicle_roots(const hk_HelicoidArgs *a, const hk_Mesh *wick, long *count, hk_Vec3 **roots,
                                hk_Vec3 **normals, hk_Error *err)
{
    hk_Mesh head;
    memset(&head, 0, sizeof head);
    if (a->head && hk_mesh_load(a->head, &head, err) != HK_OK) return err->code;
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
                    CMD, i + 1, a->input, asin(fmin(1.0, -lean)) * (180.0 / HK_PI), a->surface);
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
    hk_Status st = HK_OK;
    /* Interpolation blends the guides' pieces (§4); waves of their own (fit --waves) have
     * phases that do not blend. */
    for (int g = 0; g < guides.count && st == HK_OK; g++)
        if (guides.has_waves[g])
            st = hk_error_set(&err, HK_ERR_INVALID,
                              "%s: strand %d has waves of its own (Waves): interpolation blends the guides' "
                              "pieces only; fit them without --waves, or give the file one Waviness",
                              a->input, g + 1);
    if (st == HK_OK) st = hk_mesh_load(a->surface, &mesh, &err);
    hk_Vec3 *roots = NULL, *normals = NULL, *gnormals = NULL;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
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
        st = hk_helicoid_interpolate_at(guides.strands, gnormals, guides.count, roots, normals, count, a->power,
                                        a->threads, made.strands, &err);
    const double t1 = hk_seconds_now();
    made.step = a->step > 0.0 ? a->step : guides.step;
    made.waviness = guides.waviness;
    made.wave_jitter = guides.wave_jitter;
    if (st == HK_OK) st = hk_helicoid_set_trace(&made, made.step, a->seed, a->threads, &hair, &err);
    const double t2 = hk_seconds_now();
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
