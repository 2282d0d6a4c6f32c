/* A whole groom imported as Super-Helix guides at rest and strands that follow them
 * (hairkit/capture.h; docs/capture.md, "Importing a groom"):
 * 1. points that start inside the body are moved out (hk_groom_keep_outside, segment
 *    lengths kept);
 * 2. K guides by farthest-point sampling of the roots (deterministic: the first from the
 *    seed, ties to the lower index);
 * 3. each guide fitted (hk_superhelix_fit) and inverted with the body (hk_statics_invert),
 *    in parallel, each guide's work independent of the threads;
 * 4. every strand attached to its HK_IMPORT_ATTACH nearest guide roots with inverse
 *    distance weights; a strand that is a guide follows itself alone.
 * The strands are rebuilt from the guides' stations (every station_step along each
 * guide) as displacements from the rest, so that at rest they are their captured floats
 * exactly (hk_imported_groom_strands). */
#include <math.h>
#include <omp.h>
#include <string.h>

#include "core/core_internal.h"
#include "groom/groom_internal.h"
#include "hairkit/capture.h"
#include "hairkit/rng.h"

hk_GroomImportDef hk_default_groom_import_def(void)
{
    hk_GroomImportDef d;
    memset(&d, 0, sizeof d);
    d.guides = 0;
    d.seed = 1;
    d.threads = 0;
    d.station_step = 0.001;
    d.collision_step = hk_default_strand_def().collision_step;
    d.material = hk_rod_material(4e-5, 4e-5, 3e9, 0.48, 1300.0, hk_v3(0.0, -9.81, 0.0));
    d.fit = hk_default_superhelix_fit_def();
    d.inverse = hk_default_inverse_statics_def();
    return d;
}

void hk_imported_groom_free(hk_ImportedGroom *g)
{
    if (!g) return;
    for (int i = 0; g->guide && i < g->guide_count; i++) hk_superhelix_destroy(g->guide[i]);
    hk_free(g->guide);
    hk_free(g->guide_strand);
    hk_free(g->first_point);
    hk_free(g->points);
    hk_free(g->attach_guide);
    hk_free(g->attach_weight);
    memset(g, 0, sizeof *g);
}

static hk_Vec3 point_of(const float *p, uint32_t k)
{
    return hk_v3(p[3 * (size_t)k], p[3 * (size_t)k + 1], p[3 * (size_t)k + 2]);
}

/* Farthest-point sampling of the roots: chosen[0..k). */
static hk_Status choose_guides(const hk_ImportedGroom *g, int k, uint64_t seed, int *chosen, hk_Error *err)
{
    const int n = g->strand_count;
    if (k >= n) {
        for (int i = 0; i < n; i++) chosen[i] = i;
        return HK_OK;
    }
    double *d2 = hk_alloc_array((size_t)n, sizeof(double), err);
    if (!d2) return HK_ERR_NOMEM;
    for (int i = 0; i < n; i++) d2[i] = HUGE_VAL;
    int next = (int)(hk_rng_bits(seed, 0, 0) % (uint64_t)n);
    for (int c = 0; c < k; c++) {
        chosen[c] = next;
        const hk_Vec3 r = point_of(g->points, g->first_point[next]);
        int far = 0;
        double best = -1.0;
        for (int i = 0; i < n; i++) {
            const double d = hk_v3_norm2(hk_v3_sub(point_of(g->points, g->first_point[i]), r));
            if (d < d2[i]) d2[i] = d;
            if (d2[i] > best) best = d2[i], far = i;
        }
        next = far;
    }
    hk_free(d2);
    return HK_OK;
}

/* The HK_IMPORT_ATTACH nearest guide roots of strand i among the usable guides,
 * inverse distance weights. */
static void attach_strand(hk_ImportedGroom *g, int i, const int *guide_of_strand, const unsigned char *usable)
{
    int *ag = g->attach_guide + (size_t)i * HK_IMPORT_ATTACH;
    double *aw = g->attach_weight + (size_t)i * HK_IMPORT_ATTACH;
    for (int a = 0; a < HK_IMPORT_ATTACH; a++) ag[a] = -1, aw[a] = 0.0;
    if (guide_of_strand[i] >= 0 && usable[guide_of_strand[i]]) {
        ag[0] = guide_of_strand[i];
        aw[0] = 1.0;
        return;
    }
    const hk_Vec3 r = point_of(g->points, g->first_point[i]);
    double best[HK_IMPORT_ATTACH];
    int count = 0;
    for (int q = 0; q < g->guide_count; q++) {
        if (!usable[q]) continue;
        const double d = hk_v3_norm(hk_v3_sub(g->guide[q]->root, r));
        int at = count;
        while (at > 0 && d < best[at - 1]) at--; /* ties: the lower guide index first */
        if (at >= HK_IMPORT_ATTACH) continue;
        const int last = count < HK_IMPORT_ATTACH ? count : HK_IMPORT_ATTACH - 1;
        for (int m = last; m > at; m--) best[m] = best[m - 1], ag[m] = ag[m - 1];
        best[at] = d, ag[at] = q;
        if (count < HK_IMPORT_ATTACH) count++;
    }
    double sum = 0.0;
    for (int a = 0; a < count; a++) sum += aw[a] = 1.0 / (best[a] + 1e-6);
    for (int a = 0; a < count; a++) aw[a] /= sum;
}

typedef struct GuideResult {
    hk_SuperHelixFitReport fit;
    hk_InverseStaticsReport inv;
    double seconds_fit, seconds_inverse; /* CPU time of this guide's task */
} GuideResult;

static hk_Status make_guide(const hk_ImportedGroom *g, int strand, const hk_Shape *body, int body_count,
                            const hk_GroomImportDef *d, hk_SuperHelix **out, GuideResult *res, hk_Error *err)
{
    const uint32_t first = g->first_point[strand], np = g->first_point[strand + 1] - first;
    hk_Vec3 *p = hk_alloc_array(np, sizeof *p, err);
    if (!p) return HK_ERR_NOMEM;
    for (uint32_t j = 0; j < np; j++) p[j] = point_of(g->points, first + j);
    const double t0 = hk_thread_cpu_seconds();
    hk_Status st = hk_superhelix_fit(p, (int)np, &d->material, &d->fit, out, &res->fit, err);
    const double t1 = hk_thread_cpu_seconds();
    res->seconds_fit = t1 - t0;
    hk_free(p);
    if (st != HK_OK) return hk_error_set(err, st, "strand %d: %s", strand, err->message);
    hk_StrandEnvDef env = hk_default_strand_env_def();
    env.shapes = body;
    env.shape_count = body_count;
    /* The samples the simulation's body contacts use (hk_hair_sim_create_imported: the
     * hairstyle's CollisionStep, envelope level 0): with no step the inverse saw no
     * head at all, and a guide whose samples lie in the head's penalty started out of
     * equilibrium by that force (Sintel's guides 5 and 17, docs/capture.md). */
    env.collision_step = d->collision_step;
    st = hk_statics_invert(*out, body_count > 0 ? &env : NULL, &d->inverse, &res->inv, err);
    res->seconds_inverse = hk_thread_cpu_seconds() - t1;
    return st;
}

static int threads_of(int t) { return t > 0 ? t : omp_get_max_threads(); }

hk_Status hk_groom_import(const hk_HairFile *hair, const hk_Shape *body, int body_count, const hk_GroomImportDef *def,
                          hk_ImportedGroom *out, hk_GroomImportReport *report, hk_Error *err)
{
    const hk_GroomImportDef defaults = hk_default_groom_import_def();
    const hk_GroomImportDef *d = def ? def : &defaults;
    hk_GroomImportReport local;
    if (!report) report = &local;
    memset(report, 0, sizeof *report);
    memset(out, 0, sizeof *out);
    if (hair->strand_count < 1 || hair->strand_count > (uint32_t)HK_MAX_IMPORT_STRANDS)
        return hk_error_set(err, HK_ERR_INVALID, "%u strands: an import takes 1 to %d", hair->strand_count,
                            HK_MAX_IMPORT_STRANDS);
    if (!(d->station_step > 0.0) || d->guides < 0)
        return hk_error_set(err, HK_ERR_INVALID, "station step %g, %d guides", d->station_step, d->guides);
    for (uint32_t i = 0; i < hair->strand_count; i++)
        if (hk_hair_strand_points(hair, i) < 2)
            return hk_error_set(err, HK_ERR_INVALID, "strand %u has %u point(s): a strand needs two", i,
                                hk_hair_strand_points(hair, i));
    const int n = (int)hair->strand_count;
    const int threads = threads_of(d->threads);
    hk_ImportedGroom *g = out;
    g->strand_count = n;
    g->station_step = d->station_step;
    g->material = d->material;
    g->first_point = hk_alloc_array((size_t)n + 1, sizeof(uint32_t), err);
    g->points = hk_alloc_array((size_t)hair->point_count, 3 * sizeof(float), err);
    if (!g->first_point || !g->points) {
        hk_imported_groom_free(g);
        return HK_ERR_NOMEM;
    }
    memcpy(g->first_point, hair->first_point, ((size_t)n + 1) * sizeof(uint32_t));
    memcpy(g->points, hair->points, (size_t)hair->point_count * 3 * sizeof(float));

    /* 1. out of the body */
    double t0 = hk_seconds_now();
    int moved_strands = 0;
    long moved_points = 0;
    double moved_sum = 0.0, moved_max = 0.0;
    if (body_count > 0) {
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads) \
            reduction(+ : moved_strands, moved_points, moved_sum) reduction(max : moved_max)
        for (int i = 0; i < n; i++) {
            const uint32_t first = g->first_point[i], np = g->first_point[i + 1] - first;
            float *p = g->points + 3 * (size_t)first;
            float before[3 * 256];
            float *b = np <= 256 ? before : hk_alloc_array(np, 3 * sizeof(float), NULL);
            if (!b) continue;
            memcpy(b, p, (size_t)np * 3 * sizeof(float));
            hk_groom_keep_outside(body, body_count, p, (int)np);
            int moved = 0;
            for (uint32_t j = 0; j < 3 * np; j += 3) {
                const double m =
                    hk_v3_norm(hk_v3((double)p[j] - b[j], (double)p[j + 1] - b[j + 1], (double)p[j + 2] - b[j + 2]));
                if (m > 0.0) {
                    moved = 1;
                    moved_points++;
                    moved_sum += m;
                    if (m > moved_max) moved_max = m;
                }
            }
            moved_strands += moved;
            if (b != before) hk_free(b);
        }
    }
    report->strands = n;
    report->moved_strands = moved_strands;
    report->moved_points = moved_points;
    report->moved_max = moved_max;
    report->moved_mean = moved_points > 0 ? moved_sum / (double)moved_points : 0.0;
    double t1 = hk_seconds_now();
    report->seconds_push = t1 - t0;
    if (d->progress) d->progress(d->progress_user, "push out", 1.0);

    /* 2. the guides */
    int k = d->guides > 0 ? d->guides : (n + 74) / 75;
    if (k > n) k = n;
    g->guide_count = k;
    g->guide_strand = hk_alloc_array((size_t)k, sizeof(int), err);
    g->guide = hk_calloc_array((size_t)k, sizeof(hk_SuperHelix *), err);
    int *guide_of_strand = hk_alloc_array((size_t)n, sizeof(int), err);
    GuideResult *res = hk_calloc_array((size_t)k, sizeof(GuideResult), err);
    g->attach_guide = hk_alloc_array((size_t)n * HK_IMPORT_ATTACH, sizeof(int), err);
    g->attach_weight = hk_alloc_array((size_t)n * HK_IMPORT_ATTACH, sizeof(double), err);
    hk_Status st = HK_OK;
    if (!g->guide_strand || !g->guide || !guide_of_strand || !res || !g->attach_guide || !g->attach_weight)
        st = HK_ERR_NOMEM;
    if (st == HK_OK) st = choose_guides(g, k, d->seed, g->guide_strand, err);
    if (st == HK_OK) {
        for (int i = 0; i < n; i++) guide_of_strand[i] = -1;
        for (int c = 0; c < k; c++) guide_of_strand[g->guide_strand[c]] = c;
    }
    double t2 = hk_seconds_now();
    report->seconds_choose = t2 - t1;

    /* 3. fitted and inverted */
    if (st == HK_OK) {
        hk_FirstError first;
        hk_first_error_init(&first);
        long done = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
        for (int c = 0; c < k; c++) {
            if (hk_first_error_skip(&first, c)) continue;
            hk_Error e;
            if (make_guide(g, g->guide_strand[c], body, body_count, d, &g->guide[c], &res[c], &e) != HK_OK)
                hk_first_error_record(&first, c, &e);
            long dn;
#pragma omp atomic capture
            dn = ++done;
            if (d->progress && omp_get_thread_num() == 0) d->progress(d->progress_user, "fit", (double)dn / k);
        }
        st = hk_first_error_status(&first, err);
    }
    double t3 = hk_seconds_now();
    report->seconds_fit = t3 - t2;
    if (st == HK_OK) {
        double sum = 0.0, elements = 0.0;
        for (int c = 0; c < k; c++) {
            sum += res[c].fit.mean_error;
            elements += res[c].fit.elements;
            report->task_seconds_fit += res[c].seconds_fit;
            report->task_seconds_inverse += res[c].seconds_inverse;
            report->fit_worst = fmax(report->fit_worst, res[c].fit.mean_error);
            report->fit_max = fmax(report->fit_max, res[c].fit.max_error);
            if (!res[c].inv.stable) report->unstable++;
            if (res[c].inv.settled) report->settled++;
            report->drift_max = fmax(report->drift_max, res[c].inv.drift);
        }
        report->guides = k;
        report->fit_mean = sum / k;
        report->elements_mean = elements / k;
        /* 4. attached. A guide that was settled away from its capture is simulated
         * but followed by no strand, its own included: a strand held at a distance
         * from its guide's frames is swung by the lever (on Sintel, 8 guides settled
         * up to 19 cm away threw their strands 28 cm in two frames). */
        unsigned char *usable = hk_alloc_array((size_t)k, 1, err);
        int any = 0;
        if (!usable) st = HK_ERR_NOMEM;
        for (int c = 0; st == HK_OK && c < k; c++) {
            usable[c] = !res[c].inv.settled || res[c].inv.drift <= HK_IMPORT_MAX_DRIFT;
            any |= usable[c];
            report->unfollowed += !usable[c];
        }
        for (int c = 0; st == HK_OK && !any && c < k; c++) usable[c] = 1;
        if (st == HK_OK) {
#pragma omp parallel for schedule(static) num_threads(threads)
            for (int i = 0; i < n; i++) attach_strand(g, i, guide_of_strand, usable);
        }
        hk_free(usable);
    }
    report->seconds_attach = hk_seconds_now() - t3;
    hk_free(guide_of_strand);
    hk_free(res);
    if (st != HK_OK) hk_imported_groom_free(g);
    return st;
}

/* ---- strands from the guides ----------------------------------------------------- */

static int station_count(const hk_SuperHelix *sh, double step)
{
    const double m = floor(sh->total_length / step + 0.5);
    return (m > 1e6 ? 1000000 : (int)m) + 1;
}

/* Guide sh's stations: s_k = min(k step, L), position and frame. */
static void stations(const hk_SuperHelix *sh, double step, int count, hk_Vec3 *pos, hk_Mat3 *frame)
{
    for (int k = 0; k < count; k++) {
        const double s = fmin(k * step, sh->total_length);
        hk_superhelix_eval(sh, NULL, s, &pos[k], &frame[k]);
    }
}

hk_Status hk_imported_groom_strands(const hk_ImportedGroom *g, const hk_SuperHelix *const *guides_now, int threads,
                                    float *out, hk_Error *err)
{
    const int k = g->guide_count;
    size_t *first = hk_alloc_array((size_t)k + 1, sizeof(size_t), err);
    if (!first) return HK_ERR_NOMEM;
    first[0] = 0;
    for (int c = 0; c < k; c++) first[c + 1] = first[c] + (size_t)station_count(g->guide[c], g->station_step);
    hk_Vec3 *r0 = hk_alloc_array(first[k], sizeof(hk_Vec3), err), *r1 = hk_alloc_array(first[k], sizeof(hk_Vec3), err);
    hk_Mat3 *f0 = hk_alloc_array(first[k], sizeof(hk_Mat3), err), *f1 = hk_alloc_array(first[k], sizeof(hk_Mat3), err);
    hk_Status st = r0 && r1 && f0 && f1 ? HK_OK : HK_ERR_NOMEM;
    const int nt = threads_of(threads);
    if (st == HK_OK) {
#pragma omp parallel for schedule(dynamic, 4) num_threads(nt)
        for (int c = 0; c < k; c++) {
            const int m = (int)(first[c + 1] - first[c]);
            stations(g->guide[c], g->station_step, m, r0 + first[c], f0 + first[c]);
            /* the rest shape is q (the captured one); the guide now is guides_now[c] */
            if (guides_now && guides_now[c] != g->guide[c])
                stations(guides_now[c], g->station_step, m, r1 + first[c], f1 + first[c]);
            else {
                memcpy(r1 + first[c], r0 + first[c], (size_t)m * sizeof(hk_Vec3));
                memcpy(f1 + first[c], f0 + first[c], (size_t)m * sizeof(hk_Mat3));
            }
        }
#pragma omp parallel for schedule(dynamic, 16) num_threads(nt)
        for (int i = 0; i < g->strand_count; i++) {
            const uint32_t a = g->first_point[i], b = g->first_point[i + 1];
            double s = 0.0;
            hk_Vec3 prev = point_of(g->points, a);
            for (uint32_t j = a; j < b; j++) {
                const hk_Vec3 p = point_of(g->points, j);
                s += hk_v3_norm(hk_v3_sub(p, prev));
                prev = p;
                hk_Vec3 disp = hk_v3_zero();
                for (int t = 0; t < HK_IMPORT_ATTACH; t++) {
                    const int c = g->attach_guide[(size_t)i * HK_IMPORT_ATTACH + (size_t)t];
                    if (c < 0) continue;
                    const double w = g->attach_weight[(size_t)i * HK_IMPORT_ATTACH + (size_t)t];
                    const int m = (int)(first[c + 1] - first[c]);
                    double kk = floor(s / g->station_step + 0.5);
                    const size_t at = first[c] + (size_t)(kk >= m - 1 ? m - 1 : kk);
                    /* o = R0^T (p - r0); displacement (r1 - r0) + (R1 - R0) o */
                    const hk_Vec3 o = hk_m3_tmul_v3(&f0[at], hk_v3_sub(p, r0[at]));
                    const hk_Vec3 moved = hk_v3_add(r1[at], hk_m3_mul_v3(&f1[at], o));
                    const hk_Vec3 rest = hk_v3_add(r0[at], hk_m3_mul_v3(&f0[at], o));
                    disp = hk_v3_add(disp, hk_v3_scale(hk_v3_sub(moved, rest), w));
                }
                float *q = out + 3 * (size_t)j;
                const float *c0 = g->points + 3 * (size_t)j;
                q[0] = (float)((double)c0[0] + disp.x);
                q[1] = (float)((double)c0[1] + disp.y);
                q[2] = (float)((double)c0[2] + disp.z);
            }
        }
    }
    hk_free(first);
    hk_free(r0);
    hk_free(r1);
    hk_free(f0);
    hk_free(f1);
    return st;
}
