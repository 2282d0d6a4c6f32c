/* hairkit helicoid fit / reconstruct: p-helicoids fitted to the strands of a .hair file
 * (paper 003 §5, docs/helicoid-fitting.md), and a full head rebuilt from the fits of one
 * strand in K (§5.4). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "helicoid_cli.h"
#include "hairkit/helicoid_fit.h"

static const char *const CMD = HK_HELICOID_CMD;

/* The common layout of reconstruct's fits (§5.4: fits are blended piece by piece, so
 * piece j must cover the same stretch of hair on every fit): by length from the root, a
 * 1 cm piece for the lift off the scalp, then 3 cm pieces. On the head example (1,000
 * strands without waves, one in ten fitted) it rebuilds to 14 mm, against 12.5 mm for
 * blending the strands' true parameters and 91 mm with 4 equal pieces; on the
 * benchmark's tuft as well as 4 equal pieces (2.8 mm, the blend's floor). */
#define RECONSTRUCT_PIECE_LENGTH 0.03
#define RECONSTRUCT_ROOT_PIECE 0.01

typedef struct FitReport {
    double error, frechet; /* normalised coupling and Fréchet distance (m) */
    int pieces;
    long evaluations;
} FitReport;

/* Fits strands idx[0..n) of the hair file into out[0..n), in parallel, one fitter per
 * thread (sized for the longest of them), with a progress bar on a terminal. */
static hk_Status fit_strands(const hk_HairFile *hair, const long *idx, long n, const hk_CurveFitOptions *opt,
                             const hk_HelicoidArgs *args, hk_PHelicoid *out, FitReport *report, hk_Error *err)
{
    uint32_t longest = 2;
    for (long i = 0; i < n; i++) {
        const uint32_t c = hair->first_point[idx[i] + 1] - hair->first_point[idx[i]];
        if (c < 2 || c > HK_CURVEFIT_MAX_SAMPLES)
            return hk_error_set(err, HK_ERR_INVALID, "%s: strand %ld has %u points (2 to %d can be fitted)",
                                args->input, idx[i] + 1, c, HK_CURVEFIT_MAX_SAMPLES);
        if (c > longest) longest = c;
    }
    hk_FirstError first;
    hk_first_error_init(&first);
    hk_CliProgress bar = {hk_cli_stderr_is_tty() && !args->quiet, "", -1};
    long done = 0;
    const int saved = omp_get_max_threads();
    if (args->threads > 0) omp_set_num_threads(args->threads);
#pragma omp parallel
    {
        hk_Error e;
        hk_HelicoidFitter *f = hk_helicoid_fitter_create((int)longest, &e);
        hk_Vec3 *pts = hk_alloc_array(longest, sizeof(hk_Vec3), f ? &e : NULL);
#pragma omp for schedule(dynamic, 4)
        for (long i = 0; i < n; i++) {
            if (hk_first_error_skip(&first, i)) continue;
            const uint32_t a = hair->first_point[idx[i]], b = hair->first_point[idx[i] + 1];
            hk_Status st = (f && pts) ? HK_OK : HK_ERR_NOMEM;
            hk_CurveFit fit;
            if (st == HK_OK) {
                for (uint32_t p = a; p < b; p++) {
                    const float *q = hair->points + 3 * (size_t)p;
                    pts[p - a] = hk_v3(q[0], q[1], q[2]);
                }
                st = hk_helicoid_fit(f, pts, (int)(b - a), opt, &out[i], &fit, &e);
            }
            if (st == HK_OK) report[i] = (FitReport){fit.error, fit.frechet, fit.piece_count, fit.evaluations};
            else hk_first_error_record(&first, i, &e);
            long now;
#pragma omp atomic capture
            now = ++done;
            if (omp_get_thread_num() == 0) hk_cli_progress(&bar, "fitting", (double)now / (double)n);
        }
        hk_helicoid_fitter_destroy(f);
        hk_free(pts);
    }
    hk_cli_progress_done(&bar);
    if (args->threads > 0) omp_set_num_threads(saved);
    if (first.index >= 0)
        return hk_error_set(err, first.error.code, "%s: strand %ld: %s", args->input, idx[first.index] + 1,
                            first.error.message);
    return HK_OK;
}

/* The fit's options from the command line (layout: --pieces, --piece-length, or split
 * as each strand needs). */
static hk_CurveFitOptions fit_options(const hk_HelicoidArgs *a)
{
    hk_CurveFitOptions o = hk_helicoid_fit_options();
    o.method = a->method;
    o.tolerance = a->tolerance;
    o.lambda = a->lambda;
    o.max_pieces = (int)a->max_pieces;
    o.fixed_pieces = a->piece_length > 0.0 ? 0 : (int)a->pieces;
    o.piece_length = a->piece_length;
    o.root_piece_length = a->root_piece;
    return o;
}

int hk_helicoid_cli_fit(const hk_HelicoidArgs *a)
{
    hk_Error err;
    hk_HairFile hair;
    if (hk_hair_load(a->input, &hair, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_HelicoidSet set;
    long *idx = NULL;
    FitReport *rep = NULL;
    hk_Status st = hk_helicoid_set_alloc(&set, (int)hair.strand_count, &err);
    if (st == HK_OK) {
        idx = hk_alloc_array(hair.strand_count ? hair.strand_count : 1, sizeof(long), &err);
        rep = hk_alloc_array(hair.strand_count ? hair.strand_count : 1, sizeof(FitReport), &err);
        if (!idx || !rep) st = HK_ERR_NOMEM;
    }
    const hk_CurveFitOptions opt = fit_options(a);
    const double t0 = hk_seconds_now();
    if (st == HK_OK) {
        for (uint32_t s = 0; s < hair.strand_count; s++) idx[s] = s;
        st = fit_strands(&hair, idx, hair.strand_count, &opt, a, set.strands, rep, &err);
    }
    const double seconds = hk_seconds_now() - t0;
    if (st == HK_OK) st = hk_helicoid_file_save(a->output, &set, "fitted by hairkit helicoid fit", &err);
    if (st == HK_OK) {
        double sum = 0.0, worst = 0.0, fr = 0.0;
        long pieces = 0;
        printf("strand,points,pieces,error_m,frechet_m\n");
        for (uint32_t s = 0; s < hair.strand_count; s++) {
            printf("%u,%u,%d,%.6g,%.6g\n", s + 1, hair.first_point[s + 1] - hair.first_point[s], rep[s].pieces,
                   rep[s].error, rep[s].frechet);
            sum += rep[s].error, worst = fmax(worst, rep[s].error), fr = fmax(fr, rep[s].frechet);
            pieces += rep[s].pieces;
        }
        const double n = hair.strand_count ? (double)hair.strand_count : 1.0;
        printf("# strands=%u mean_error_m=%.6g max_error_m=%.6g max_frechet_m=%.6g mean_pieces=%.3g "
               "fits_per_second=%.1f\n",
               hair.strand_count, sum / n, worst, fr, pieces / n, hair.strand_count / fmax(seconds, 1e-9));
    }
    hk_free(idx), hk_free(rep);
    hk_helicoid_set_free(&set);
    hk_hair_free(&hair);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

int hk_helicoid_cli_reconstruct(const hk_HelicoidArgs *a)
{
    hk_Error err;
    hk_HairFile hair, out;
    memset(&out, 0, sizeof out);
    if (hk_hair_load(a->input, &hair, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    const long n = hair.strand_count, k = (n + a->every - 1) / a->every;
    hk_HelicoidSet guides, all;
    memset(&all, 0, sizeof all);
    long *idx = NULL;
    FitReport *rep = NULL;
    hk_Vec3 *roots = NULL;
    hk_Status st = n > 0 ? hk_helicoid_set_alloc(&guides, (int)k, &err)
                         : hk_error_set(&err, HK_ERR_INVALID, "%s has no strands", a->input);
    if (st == HK_OK) st = hk_helicoid_set_alloc(&all, (int)n, &err);
    if (st == HK_OK) {
        idx = hk_alloc_array((size_t)k, sizeof(long), &err);
        rep = hk_alloc_array((size_t)k, sizeof(FitReport), &err);
        roots = hk_alloc_array((size_t)n, sizeof(hk_Vec3), &err);
        if (!idx || !rep || !roots) st = HK_ERR_NOMEM;
    }
    hk_CurveFitOptions opt = fit_options(a);
    if (!a->pieces_given && !(a->piece_length > 0.0)) {
        opt.piece_length = RECONSTRUCT_PIECE_LENGTH;
        opt.root_piece_length = RECONSTRUCT_ROOT_PIECE;
    }
    const double t0 = hk_seconds_now();
    if (st == HK_OK) {
        for (long i = 0; i < k; i++) idx[i] = i * a->every;
        st = fit_strands(&hair, idx, k, &opt, a, guides.strands, rep, &err);
    }
    const double t1 = hk_seconds_now();
    if (st == HK_OK) {
        for (long s = 0; s < n; s++) {
            const float *q = hair.points + 3 * (size_t)hair.first_point[s];
            roots[s] = hk_v3(q[0], q[1], q[2]);
        }
        const int saved = omp_get_max_threads();
        if (a->threads > 0) omp_set_num_threads(a->threads);
        st = hk_helicoid_cli_interpolate_at(guides.strands, NULL, guides.count, roots, NULL, n, a->power, all.strands,
                                            &err);
        if (a->threads > 0) omp_set_num_threads(saved);
    }
    const double step = a->step > 0.0 ? a->step : 0.002;
    all.step = step;
    if (st == HK_OK) st = hk_helicoid_cli_trace_set(&all, step, a->seed, a->threads, &out, &err);
    const double t2 = hk_seconds_now();
    if (st == HK_OK) st = hk_hair_save(a->output, &out, &err);
    if (st == HK_OK) {
        /* Error of the reconstruction: each strand against the original, by the mean
         * leash of their Fréchet coupling. */
        double sum = 0.0, worst = 0.0;
        for (long s = 0; s < n && st == HK_OK; s++) {
            const uint32_t a0 = hair.first_point[s], a1 = hair.first_point[s + 1];
            const uint32_t b0 = out.first_point[s], b1 = out.first_point[s + 1];
            hk_Vec3 *pa = hk_alloc_array(a1 - a0 + (b1 - b0), sizeof(hk_Vec3), &err);
            if (!pa) {
                st = HK_ERR_NOMEM;
                break;
            }
            hk_Vec3 *pb = pa + (a1 - a0);
            for (uint32_t p = a0; p < a1; p++)
                pa[p - a0] = hk_v3(hair.points[3 * p], hair.points[3 * p + 1], hair.points[3 * p + 2]);
            for (uint32_t p = b0; p < b1; p++)
                pb[p - b0] = hk_v3(out.points[3 * p], out.points[3 * p + 1], out.points[3 * p + 2]);
            hk_FrechetMeasures m;
            if (hk_frechet_measures(pa, (int)(a1 - a0), pb, (int)(b1 - b0), &m, &err) == HK_OK) {
                sum += m.normalized;
                worst = fmax(worst, m.normalized);
            }
            hk_free(pa);
        }
        if (st == HK_OK)
            printf("# strands=%ld fitted=%ld fit_s=%.3f interpolated_and_traced_s=%.3f mean_error_m=%.6g "
                   "max_error_m=%.6g\n",
                   n, k, t1 - t0, t2 - t1, sum / n, worst);
    }
    hk_free(idx), hk_free(rep), hk_free(roots);
    hk_helicoid_set_free(&guides);
    hk_helicoid_set_free(&all);
    hk_hair_free(&out);
    hk_hair_free(&hair);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}
