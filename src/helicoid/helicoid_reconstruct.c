/* The strands of a hair file fitted with p-helicoids, and a full head rebuilt from the
 * fits of a few of them (include/hairkit/helicoid_hair.h; Piuze, Kry and Siddiqi 2011,
 * §5 and §5.4; the rebuild itself in reconstruct_blend.c). */
#include <math.h>
#include <omp.h>
#include <string.h>

#include "core/core_internal.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/helicoid_hair.h"
#include "helicoid_internal.h"

/* hk_helicoid_fit_strands, and with wavy (not NULL) hk_helicoid_fit_wavy for strands of 8
 * points or more, their waves into waves[0..count) (amplitude 0: none). */
static hk_Status fit_strands(const hk_HairFile *hair, const long *index, long count, const hk_CurveFitDef *options,
                             const hk_WavyFitDef *wavy, int threads, hk_ProgressFn progress, void *progress_user,
                             hk_PHelicoid *out, hk_Waviness *waves, hk_HelicoidFitReport *reports, hk_Error *err)
{
    const hk_CurveFitDef defaults = hk_default_helicoid_fit_def();
    if (!options) options = wavy ? &wavy->base : &defaults;
    uint32_t longest = 2;
    for (long i = 0; i < count; i++) {
        if (index[i] < 0 || index[i] >= (long)hair->strand_count)
            return hk_error_set(err, HK_ERR_INVALID, "strand %ld: the hair has %u strands", index[i] + 1,
                                hair->strand_count);
        const uint32_t c = hair->first_point[index[i] + 1] - hair->first_point[index[i]];
        if (c < 2 || c > HK_CURVEFIT_MAX_SAMPLES)
            return hk_error_set(err, HK_ERR_INVALID, "strand %ld has %u points (2 to %d can be fitted)", index[i] + 1,
                                c, HK_CURVEFIT_MAX_SAMPLES);
        if (c > longest) longest = c;
    }
    hk_FirstError first;
    hk_first_error_init(&first);
    long done = 0;
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads())
    {
        hk_Error e;
        /* room for the resampled retry of coarse strands (hk_helicoid_fit) */
        const int capacity = longest < 64 ? 4 * ((int)longest - 1) + 1 : (int)longest;
        hk_HelicoidFitter *f = hk_helicoid_fitter_create(capacity, &e);
        hk_Vec3 *pts = hk_alloc_array(2 * (size_t)longest, sizeof(hk_Vec3), f ? &e : NULL);
#pragma omp for schedule(dynamic, 4)
        for (long i = 0; i < count; i++) {
            if (hk_first_error_skip(&first, i)) continue;
            const uint32_t a = hair->first_point[index[i]], b = hair->first_point[index[i] + 1];
            const int n = (int)(b - a);
            hk_Status st = (f && pts) ? HK_OK : HK_ERR_NOMEM;
            hk_CurveFit fit;
            hk_HelicoidFitReport rep = {0.0, 0.0, 0, 0};
            if (st == HK_OK)
                for (uint32_t p = a; p < b; p++) {
                    const float *q = hair->points + 3 * (size_t)p;
                    pts[p - a] = hk_v3(q[0], q[1], q[2]);
                }
            if (st == HK_OK && wavy && n >= 8) {
                hk_FrechetMeasures m;
                double error;
                st = hk_helicoid_fit_wavy(f, pts, n, wavy, &out[i], &waves[i], &error, &e);
                if (st == HK_OK) st = hk_helicoid_traced_measures(&out[i], &waves[i], pts, n, pts + longest, &m, &e);
                if (st == HK_OK) rep = (hk_HelicoidFitReport){m.normalized, m.distance, out[i].piece_count, 0};
            } else if (st == HK_OK) {
                st = hk_helicoid_fit(f, pts, n, options, &out[i], &fit, &e);
                if (waves) waves[i] = (hk_Waviness){0.0, 0.0, 0.0};
                if (st == HK_OK) rep = (hk_HelicoidFitReport){fit.error, fit.frechet, fit.piece_count, fit.evaluations};
            }
            if (st == HK_OK && reports)
                reports[i] = rep;
            else if (st != HK_OK)
                hk_first_error_record(&first, i, &e);
            long now;
#pragma omp atomic capture
            now = ++done;
            if (progress && omp_get_thread_num() == 0) progress(progress_user, "fitting", (double)now / (double)count);
        }
        hk_helicoid_fitter_destroy(f);
        hk_free(pts);
    }
    if (first.index >= 0)
        return hk_error_set(err, first.error.code, "strand %ld: %s", index[first.index] + 1, first.error.message);
    return HK_OK;
}

hk_Status hk_helicoid_fit_strands(const hk_HairFile *hair, const long *index, long count, const hk_CurveFitDef *options,
                                  int threads, hk_ProgressFn progress, void *progress_user, hk_PHelicoid *out,
                                  hk_HelicoidFitReport *reports, hk_Error *err)
{
    return fit_strands(hair, index, count, options, NULL, threads, progress, progress_user, out, NULL, reports, err);
}

hk_Status hk_helicoid_fit_strands_wavy(const hk_HairFile *hair, const long *index, long count,
                                       const hk_WavyFitDef *options, int threads, hk_ProgressFn progress,
                                       void *progress_user, hk_PHelicoid *out, hk_Waviness *waves,
                                       hk_HelicoidFitReport *reports, hk_Error *err)
{
    const hk_WavyFitDef defaults = hk_default_wavy_fit_def();
    if (!waves) return hk_error_set(err, HK_ERR_INVALID, "wavy fits: no room for the waves");
    return fit_strands(hair, index, count, NULL, options ? options : &defaults, threads, progress, progress_user, out,
                       waves, reports, err);
}

/* Each rebuilt strand against its original: the mean leash of their Fréchet coupling. */
static hk_Status compare(const hk_HairFile *a, const hk_HairFile *b, double *mean, double *worst, hk_Error *err)
{
    double sum = 0.0;
    *worst = 0.0;
    for (uint32_t s = 0; s < a->strand_count; s++) {
        const uint32_t a0 = a->first_point[s], a1 = a->first_point[s + 1];
        const uint32_t b0 = b->first_point[s], b1 = b->first_point[s + 1];
        hk_Vec3 *pa = hk_alloc_array(a1 - a0 + (b1 - b0), sizeof(hk_Vec3), err);
        if (!pa) return HK_ERR_NOMEM;
        hk_Vec3 *pb = pa + (a1 - a0);
        for (uint32_t p = a0; p < a1; p++)
            pa[p - a0] = hk_v3(a->points[3 * p], a->points[3 * p + 1], a->points[3 * p + 2]);
        for (uint32_t p = b0; p < b1; p++)
            pb[p - b0] = hk_v3(b->points[3 * p], b->points[3 * p + 1], b->points[3 * p + 2]);
        hk_FrechetMeasures m;
        hk_Error ignored; /* a strand the measure refuses (a point not finite) is left out */
        if (hk_frechet_measures(pa, (int)(a1 - a0), pb, (int)(b1 - b0), &m, &ignored) == HK_OK) {
            sum += m.normalized;
            *worst = fmax(*worst, m.normalized);
        }
        hk_free(pa);
    }
    *mean = a->strand_count ? sum / a->strand_count : 0.0;
    return HK_OK;
}

hk_Status hk_helicoid_reconstruct(const hk_HairFile *hair, long every, const hk_CurveFitDef *options, double power,
                                  double step, uint64_t seed, int threads, hk_ProgressFn progress, void *progress_user,
                                  hk_HairFile *out, hk_HelicoidReconstruction *report, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    hk_HelicoidReconstruction local;
    if (!report) report = &local;
    memset(report, 0, sizeof *report);
    if (every < 1) return hk_error_set(err, HK_ERR_INVALID, "reconstruct: one strand in %ld", every);
    if (!(step > 0.0) || !isfinite(step)) return hk_error_set(err, HK_ERR_INVALID, "reconstruct: step %g", step);
    hk_CurveFitDef opt = hk_default_helicoid_fit_def();
    if (options) {
        opt = *options;
    } else {
        opt.piece_length = HK_RECONSTRUCT_PIECE_LENGTH;
        opt.root_piece_length = HK_RECONSTRUCT_ROOT_PIECE;
    }
    const long n = hair->strand_count, k = (n + every - 1) / every;
    if (n < 1) return hk_error_set(err, HK_ERR_INVALID, "reconstruct: the hair has no strands");
    hk_HelicoidSet guides;
    memset(&guides, 0, sizeof guides);
    long *idx = NULL;
    hk_Status st = hk_helicoid_set_alloc(&guides, (int)k, err);
    if (st == HK_OK) {
        idx = hk_alloc_array((size_t)k, sizeof(long), err);
        if (!idx) st = HK_ERR_NOMEM;
    }
    const double t0 = hk_seconds_now();
    if (st == HK_OK) {
        for (long i = 0; i < k; i++) idx[i] = i * every;
        st = hk_helicoid_fit_strands(hair, idx, k, &opt, threads, progress, progress_user, guides.strands, NULL, err);
    }
    const double t1 = hk_seconds_now();
    (void)seed; /* the rebuild draws nothing: no waves are added to the capture's strands */
    if (st == HK_OK) st = hk_helicoid_rebuild(hair, guides.strands, (int)k, power, step, threads, out, err);
    const double t2 = hk_seconds_now();
    if (st == HK_OK) st = compare(hair, out, &report->mean_error, &report->max_error, err);
    if (st == HK_OK) {
        report->strands = n, report->fitted = k;
        report->seconds_fit = t1 - t0, report->seconds_rebuild = t2 - t1;
    } else {
        hk_hair_free(out);
    }
    hk_free(idx);
    hk_helicoid_set_free(&guides);
    return st;
}
