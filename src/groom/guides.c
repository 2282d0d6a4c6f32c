/* Guide strands (Lansink 2010 §4.1.4.2): one Super-Helix per follicle, its rest shape
 * under gravity and the layered collision envelopes found by the Newton statics, all
 * guides in parallel. */
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "core/core_internal.h"
#include "groom_internal.h"
#include "hairkit/statics.h"

/* Solves guide i and writes its samples; returns the status. */
static hk_Status solve_one(const hk_StrandDef *strand, const hk_Shape *shapes, int shape_count, const hk_Follicles *f,
                           int i, int points, double *out, long *iterations, int *converged, double *penetration,
                           hk_Error *err)
{
    hk_SuperHelix *sh;
    hk_Status st = hk_superhelix_from_def(strand, f->position[i], f->normal[i], &sh, err);
    if (st != HK_OK) return st;
    hk_StrandEnvDef env = hk_default_strand_env_def();
    env.shapes = shapes;
    env.shape_count = shape_count;
    env.envelope_alpha = f->alpha[i];
    env.collision_step = strand->collision_step;
    hk_StaticsDef opt = hk_default_statics_def();
    hk_MinimizeResult res;
    st = hk_statics_solve(sh, &env, &opt, &res, err);
    if (st == HK_OK) {
        hk_Vec3 buf[256], *p = points <= 256 ? buf : hk_alloc_array((size_t)points, sizeof(hk_Vec3), err);
        if (!p) {
            st = HK_ERR_NOMEM;
        } else {
            hk_superhelix_sample(sh, NULL, strand->visuality_step, NULL, p, NULL);
            for (int j = 0; j < points; j++) {
                out[3 * j] = p[j].x;
                out[3 * j + 1] = p[j].y;
                out[3 * j + 2] = p[j].z;
            }
            if (p != buf) hk_free(p);
        }
        *iterations = res.iterations;
        *converged = res.converged;
        *penetration = 0.0;
        if (st == HK_OK && shape_count > 0) {
            hk_StrandWorkspace *ws;
            if (hk_strand_workspace_create(sh, &env, &ws, err) == HK_OK) {
                *penetration = hk_strand_max_penetration(sh, &env, sh->q, ws);
                hk_strand_workspace_destroy(ws);
            }
        }
    }
    hk_superhelix_destroy(sh);
    return st;
}

hk_Status hk_groom_solve_guides(const hk_StrandDef *strand, const hk_Shape *shapes, int shape_count,
                                const hk_Follicles *f, const hk_GroomDef *o, hk_Groom *g, hk_Error *err)
{
    /* Every guide has the same sample count: it depends on the length and step only. */
    hk_SuperHelix *probe;
    hk_Status st = hk_superhelix_create(strand->element_count, strand->element_lengths, &probe, err);
    if (st != HK_OK) return st;
    const int points = hk_superhelix_sample_count(probe, strand->visuality_step);
    hk_superhelix_destroy(probe);
    g->points_per_strand = points;
    g->guide_count = f->count;
    g->guides = hk_alloc_array((size_t)f->count * (size_t)points, 3 * sizeof(double), err);
    if (!g->guides) return HK_ERR_NOMEM;

    long iterations = 0, done = 0;
    int not_converged = 0;
    double deepest = 0.0;
    hk_FirstError first;
    hk_first_error_init(&first);
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : iterations, not_converged) reduction(max : deepest) \
        num_threads(hk_groom_threads(o))
    for (int i = 0; i < f->count; i++) {
        if (hk_first_error_skip(&first, i)) continue;
        long it = 0;
        int conv = 1;
        double pen = 0.0;
        hk_Error e;
        hk_Status s = solve_one(strand, shapes, shape_count, f, i, points, g->guides + (size_t)i * (size_t)points * 3,
                                &it, &conv, &pen, &e);
        if (s != HK_OK) hk_first_error_record(&first, i, &e);
        iterations += it;
        not_converged += !conv;
        deepest = pen > deepest ? pen : deepest;
        long d;
#pragma omp atomic capture
        d = ++done;
        if (omp_get_thread_num() == 0) hk_groom_report(o, "guides", d, f->count);
    }
    if (first.index >= 0) {
        const hk_Vec3 p = f->position[first.index];
        return hk_error_set(err, first.error.code, "guide %ld (follicle at %.4g, %.4g, %.4g): %s", first.index + 1, p.x,
                            p.y, p.z, first.error.message);
    }
    hk_groom_report(o, "guides", f->count, f->count);
    g->stats.guide_iterations = iterations;
    g->stats.guides_not_converged = not_converged;
    g->stats.max_guide_penetration = deepest;
    return HK_OK;
}
