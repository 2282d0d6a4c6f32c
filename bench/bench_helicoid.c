/* Benchmark of generalized helicoids (Piuze et al. 2011): interpolating 90,000 hairs from 9
 * p-helicoid guides of 4 pieces (the paper: 1,000 in 0.67 s, a head of 90,000 in about a
 * minute), fitting 30-vertex strands (the paper: about 5 per second), and the error of a
 * tuft reconstructed from one strand in ten (§5.4); 1 and 2 threads. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/rng.h"

static double uniform(uint64_t stream, uint64_t i, double lo, double hi)
{
    return lo + (hi - lo) * hk_rng_uniform(7, stream, i);
}

/* 9 guides of 4 pieces on a 4 x 4 cm patch of the plane y = 0, hanging down. */
static void make_guides(hk_PHelicoid *g)
{
    for (int i = 0; i < 9; i++) {
        memset(&g[i], 0, sizeof g[i]);
        g[i].root = hk_v3(0.02 * (i % 3) - 0.02, 0.0, 0.02 * (i / 3) - 0.02);
        g[i].frame = hk_m3_from_cols(hk_v3(0, -1, 0), hk_v3(1, 0, 0), hk_v3(0, 0, 1));
        g[i].piece_count = 4;
        for (int p = 0; p < 4; p++) {
            const uint64_t k = (uint64_t)(4 * i + p);
            g[i].k[p] = (hk_Helicoid){uniform(1, k, 2, 30), uniform(2, k, -3, 3), uniform(3, k, -8, 8),
                                      uniform(4, k, -0.3, 0.3)};
            g[i].length[p] = 0.05;
        }
    }
}

static hk_Vec3 patch_root(long i)
{
    return hk_v3(uniform(5, (uint64_t)i, -0.025, 0.025), 0.0, uniform(6, (uint64_t)i, -0.025, 0.025));
}

/* Seconds to interpolate n strands (and trace them at 41 points when `trace`). */
static double interpolate_run(const hk_PHelicoid *guides, long n, int threads, int trace)
{
    const double t0 = hk_seconds_now();
    int failures = 0;
#pragma omp parallel reduction(+ : failures) num_threads(threads)
    {
        hk_Vec3 pts[64];
#pragma omp for schedule(static)
        for (long i = 0; i < n; i++) {
            hk_PHelicoid h;
            if (hk_phelicoid_interpolate(guides, 9, patch_root(i), NULL, 3.0, &h, NULL) != HK_OK)
                failures++;
            else if (trace &&
                     hk_phelicoid_trace(&h, hk_phelicoid_length(&h) / 40.0, NULL, NULL, pts, NULL, NULL) != HK_OK)
                failures++;
        }
    }
    const double t = hk_seconds_now() - t0;
    return failures ? -1.0 : t;
}

/* Fits n 30-vertex strands (single helicoids with random parameters, 10 cm); returns
 * seconds and the mean error. */
static double fit_run(long n, int threads, int method, double *mean_error, double *pieces)
{
    double err_sum = 0.0, piece_sum = 0.0;
    const double t0 = hk_seconds_now();
#pragma omp parallel reduction(+ : err_sum, piece_sum) num_threads(threads)
    {
        hk_HelicoidFitter *f = hk_helicoid_fitter_create(64, NULL);
#pragma omp for schedule(dynamic, 4)
        for (long i = 0; i < n; i++) {
            hk_PHelicoid h, fit;
            memset(&h, 0, sizeof h);
            h.frame = hk_helicoid_frame(uniform(10, (uint64_t)i, -3, 3), uniform(11, (uint64_t)i, -1, 1));
            h.piece_count = 1;
            h.k[0] = (hk_Helicoid){uniform(12, (uint64_t)i, 2, 30), uniform(13, (uint64_t)i, -3, 3),
                                   uniform(14, (uint64_t)i, -8, 8), uniform(15, (uint64_t)i, -0.3, 0.3)};
            h.length[0] = 0.1;
            hk_Vec3 pts[30];
            hk_CurveFit report;
            hk_CurveFitDef opt = hk_default_helicoid_fit_def();
            opt.method = (hk_CurveFitMethod)method;
            if (f && hk_phelicoid_trace(&h, 0.1 / 29.0, NULL, NULL, pts, NULL, NULL) == HK_OK &&
                hk_helicoid_fit(f, pts, 30, &opt, &fit, &report, NULL) == HK_OK) {
                err_sum += report.error;
                piece_sum += report.piece_count;
            }
        }
        hk_helicoid_fitter_destroy(f);
    }
    const double t = hk_seconds_now() - t0;
    *mean_error = err_sum / n;
    *pieces = piece_sum / n;
    return t;
}

/* A tuft of n strands interpolated from the guides (41 points), one in ten fitted, all
 * reconstructed at their roots from the fits: the mean and largest normalised Fréchet
 * coupling against the originals. */
static void reconstruct_run(const hk_PHelicoid *guides, long n, int fixed_pieces, double piece_length,
                            double root_piece, double *mean, double *worst, double *seconds)
{
    enum { P = 41 };
    static hk_Vec3 original[1000][P];
    static hk_PHelicoid fitted[100];
    const double t0 = hk_seconds_now();
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(64, NULL);
    long k = 0;
    for (long i = 0; i < n; i++) {
        hk_PHelicoid h;
        hk_phelicoid_interpolate(guides, 9, patch_root(i), NULL, 3.0, &h, NULL);
        hk_phelicoid_trace(&h, hk_phelicoid_length(&h) / (P - 1), NULL, NULL, original[i], NULL, NULL);
        hk_CurveFitDef opt = hk_default_helicoid_fit_def();
        opt.fixed_pieces = fixed_pieces;
        opt.piece_length = piece_length;
        opt.root_piece_length = root_piece;
        if (i % 10 == 0 && f && hk_helicoid_fit(f, original[i], P, &opt, &fitted[k], NULL, NULL) == HK_OK) k++;
    }
    hk_helicoid_fitter_destroy(f);
    double sum = 0.0, big = 0.0;
    for (long i = 0; i < n; i++) {
        hk_PHelicoid h;
        hk_Vec3 again[4 * P];
        hk_phelicoid_interpolate(fitted, (int)k, original[i][0], NULL, 3.0, &h, NULL);
        const double step = hk_phelicoid_length(&h) / (P - 1);
        int m = hk_phelicoid_point_count(&h, step);
        if (m < 2 || m > 4 * P || hk_phelicoid_trace(&h, step, NULL, NULL, again, NULL, NULL) != HK_OK) continue;
        hk_FrechetMeasures fm;
        if (hk_frechet_measures(original[i], P, again, m, &fm, NULL) == HK_OK) {
            sum += fm.normalized;
            big = fmax(big, fm.normalized);
        }
    }
    *mean = sum / n;
    *worst = big;
    *seconds = hk_seconds_now() - t0;
}

int hk_bench_helicoid(FILE *out, const hk_BenchOptions *options)
{
    hk_PHelicoid guides[9];
    make_guides(guides);
    const long hairs = options->quick ? 2000 : 90000;
    fprintf(out,
            "helicoid interpolation: %ld hairs from 9 guides of 4 pieces (20 cm), inverse distance power 3\n"
            "  (the paper: 1,000 in 0.67 s on one 2.4 GHz core, a head of 90,000 in about a minute)\n"
            "  threads   parameters (s)   parameters + 41-point trace (s)   hairs/s\n",
            hairs);
    double t2 = 0.0, t1 = 0.0;
    for (int threads = 1; threads <= 2; threads++) {
        const double a = interpolate_run(guides, hairs, threads, 0), b = interpolate_run(guides, hairs, threads, 1);
        if (a < 0.0 || b < 0.0) {
            fprintf(stderr, "bench helicoid: interpolation failed\n");
            return 1;
        }
        fprintf(out, "  %7d %16.3f %33.3f %9.0f\n", threads, a, b, hairs / b);
        if (threads == 1)
            t1 = b;
        else
            t2 = b;
    }
    fprintf(out, "  speed-up with 2 threads: %.2fx; target: 90,000 hairs in under 1 s on 2 cores\n", t1 / t2);

    const long fits = options->quick ? 20 : 2000;
    fprintf(out,
            "\nhelicoid fitting: %ld strands of 30 vertices (10 cm single helicoids, random parameters)\n"
            "  (the paper: Nelder-Mead on the Frechet coupling, about 5 fits per second on one 2.4 GHz core)\n"
            "  method                  threads   fits/s   mean error (m)   pieces per fit\n",
            fits);
    for (int method = HK_CURVEFIT_NELDER_MEAD; method >= HK_CURVEFIT_LEAST_SQUARES; method--)
        for (int threads = 1; threads <= 2; threads++) {
            double e, p;
            /* the paper's method is ten times slower: a tenth of the strands */
            const long count = method == HK_CURVEFIT_NELDER_MEAD ? (fits + 9) / 10 : fits;
            const double t = fit_run(count, threads, method, &e, &p);
            fprintf(out, "  %-22s %8d %8.0f %16.3g %16.2f\n",
                    method == HK_CURVEFIT_NELDER_MEAD ? "Nelder-Mead (paper)" : "Levenberg-Marquardt", threads,
                    count / t, e, p);
        }
    fprintf(out, "  target: at least 1,000 fits per second on 2 cores\n");

    const long tuft = options->quick ? 100 : 1000;
    fprintf(out,
            "\nhelicoid reconstruction (paper 5.4): a tuft of %ld strands, one in ten fitted, all\n"
            "  interpolated back from the fits at their roots; error: normalised Frechet coupling\n"
            "  against the originals (m)\n"
            "  fitted pieces                    mean error   largest error   seconds (1 thread)\n",
            tuft);
    static const struct {
        const char *name;
        int fixed;
        double length, root;
    } layouts[3] = {{"as each strand needs", 0, 0.0, 0.0},
                    {"4, the same layout on every fit", 4, 0.0, 0.0},
                    {"1 cm, then 3 cm (reconstruct's)", 0, 0.03, 0.01}};
    for (int l = 0; l < 3; l++) {
        double mean, worst, seconds;
        reconstruct_run(guides, tuft, layouts[l].fixed, layouts[l].length, layouts[l].root, &mean, &worst, &seconds);
        fprintf(out, "  %-32s %10.3g %15.3g %20.2f\n", layouts[l].name, mean, worst, seconds);
    }
    fprintf(out, "\n");
    if (hk_bench_helicoid_rebuild(out, options) != 0 || hk_bench_helicoid_waves(out, options) != 0) return 1;
    return hk_bench_helicoid_real(out, options);
}
