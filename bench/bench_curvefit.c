/* Benchmark of the curve fitting machinery (Piuze et al. 2011 §5): fits per second of
 * 30-sample strands, the paper's "approximately 5 hairs per second" data size, with 1
 * and 2 threads (one workspace per thread). The model is a discrete Frenet helix
 * (kappa, tau) traced like the paper traces helicoids (forward Euler), standing in for
 * the helicoid model; the same machinery serves any model. Three sets: clean single
 * helices, clean two-piece strands (a split to find), and single helices with 0.1 mm
 * noise (the root frame has to be refined). Then real grooms with the helicoid model,
 * forward-difference Jacobians against the model's derivatives (bench_helicoid_real.c). */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <string.h>

#include "bench.h"
#include "hairkit/curvefit.h"

#define SAMPLES 30
#define LENGTH  0.1

/* Counter-based uniform numbers, so that the strands do not depend on the thread count. */
static double uniform(uint64_t key, double lo, double hi)
{
    uint64_t z = key * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static double gaussian(uint64_t key)
{
    const double u = 1.0 - uniform(2 * key, 0, 1), v = uniform(2 * key + 1, 0, 1);
    return sqrt(-2.0 * log(u)) * cos(2.0 * HK_PI * v);
}

/* Strand s of a set: kind 0 single helix, 1 two pieces joined at sample 14, 2 single
 * helix plus 0.1 mm noise. */
static void make_strand(int kind, int s, hk_Vec3 *pts)
{
    const uint64_t key = (uint64_t)s * 64;
    const hk_Vec3 t = hk_v3_normalize(hk_v3(uniform(key, -1, 1), uniform(key + 1, -1, 1), 1.0));
    const hk_Vec3 n = hk_v3_normalize(hk_v3_cross(t, hk_v3(1, 0, 0)));
    hk_CurveStart start = {hk_v3(uniform(key + 2, -0.1, 0.1), 0.1, 0.0), hk_m3_from_cols(t, n, hk_v3_cross(t, n))};
    hk_CurveStart end;
    const double h = LENGTH / (SAMPLES - 1);
    const double k1[2] = {uniform(key + 3, 20, 100), uniform(key + 4, -40, 40)};
    const double k2[2] = {uniform(key + 5, 20, 100), uniform(key + 6, -40, 40)};
    if (kind == 1) {
        hk_curve_model_frenet_helix(NULL, k1, &start, 14 * h, 15, pts, &end);
        hk_curve_model_frenet_helix(NULL, k2, &end, (SAMPLES - 15) * h, SAMPLES - 14, pts + 14, &end);
    } else {
        hk_curve_model_frenet_helix(NULL, k1, &start, LENGTH, SAMPLES, pts, &end);
    }
    if (kind == 2)
        for (int i = 1; i < SAMPLES; i++)
            pts[i] = hk_v3_add(pts[i], hk_v3_scale(hk_v3(gaussian(key + 8 + 3 * i), gaussian(key + 9 + 3 * i),
                                                         gaussian(key + 10 + 3 * i)),
                                                   1e-4));
}

typedef struct Stats {
    double seconds, evaluations, pieces, error, worst;
    int failures;
} Stats;

static Stats run_set(const hk_Vec3 (*strands)[SAMPLES], int count, int threads, const hk_CurveFitDef *o)
{
    Stats st = {0, 0, 0, 0, 0, 0};
    double evals = 0.0, pieces = 0.0, error = 0.0, worst = 0.0;
    int failures = 0;
    const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
    const double t0 = omp_get_wtime();
#pragma omp parallel num_threads(threads) reduction(+ : evals, pieces, error, failures) reduction(max : worst)
    {
        hk_CurveFitWorkspace *ws = hk_curve_fit_workspace_create(SAMPLES, NULL);
#pragma omp for schedule(dynamic, 4)
        for (int s = 0; s < count; s++) {
            hk_CurveFit fit;
            if (!ws || hk_curve_fit_piecewise_ws(ws, strands[s], SAMPLES, hk_curve_model_frenet_helix, NULL, 2, seed,
                                                 scale, o, &fit, NULL) != HK_OK) {
                failures++;
                continue;
            }
            evals += (double)fit.evaluations;
            pieces += fit.piece_count;
            error += fit.error;
            worst = fit.error > worst ? fit.error : worst;
            if (fit.error > o->tolerance) failures++;
        }
        hk_curve_fit_workspace_destroy(ws);
    }
    st.seconds = omp_get_wtime() - t0;
    st.evaluations = evals / count;
    st.pieces = pieces / count;
    st.error = error / count;
    st.worst = worst;
    st.failures = failures;
    return st;
}

int hk_bench_curvefit(FILE *out, const hk_BenchOptions *options)
{
    const int count = options->quick ? 8 : 400;
    hk_Vec3(*strands)[SAMPLES] = hk_alloc_array((size_t)count, sizeof *strands, NULL);
    if (!strands) return 1;
    static const char *const names[3] = {"clean single helices", "clean two-piece strands", "0.1 mm noise, single"};
    fprintf(out,
            "curvefit: piecewise fits of %d-sample strands, L = %.2f m (helix model, 2 parameters),\n"
            "default options (tolerance %.1f mm, root frame refined when needed); %d strands per set\n"
            "  set                   method  threads   fits/s   evals/fit  us/eval  pieces  mean err (mm)  worst (mm)  "
            "over tol\n",
            SAMPLES, LENGTH, 1e3 * hk_default_curve_fit_def().tolerance, count);
    int rc = 0;
    for (int kind = 0; kind < 3; kind++) {
        for (int s = 0; s < count; s++) make_strand(kind, s, strands[s]);
        for (int run = 0; run < 4; run++) {
            /* the paper's Nelder-Mead, then our Levenberg-Marquardt, 1 and 2 threads each */
            const hk_CurveFitMethod method = run < 2 ? HK_CURVEFIT_NELDER_MEAD : HK_CURVEFIT_LEAST_SQUARES;
            const int threads = 1 + run % 2;
            hk_CurveFitDef o = hk_default_curve_fit_def();
            o.method = method;
            Stats st = {0, 0, 0, 0, 0, 0};
            double total = 0.0;
            int reps = 0;
            do {
                st = run_set((const hk_Vec3(*)[SAMPLES])strands, count, threads, &o);
                total += st.seconds;
                reps++;
            } while (total < options->min_seconds && !options->quick);
            const double per_fit = total / reps / count;
            fprintf(out, "  %-22s %6s %7d %8.0f %11.0f %8.2f %7.2f %14.3f %11.3f %9d\n", names[kind],
                    method == HK_CURVEFIT_NELDER_MEAD ? "NM" : "LM", threads, 1.0 / per_fit, st.evaluations,
                    1e6 * per_fit * threads / st.evaluations, st.pieces, 1e3 * st.error, 1e3 * st.worst, st.failures);
        }
    }
    fprintf(out, "NM: the paper's Nelder-Mead on the Frechet coupling; LM: Levenberg-Marquardt on point distances\n"
                 "target: >= 1000 fits/s on 2 cores for 30-vertex strands (the paper: about 5 per second)\n\n");
    hk_free(strands);
    return rc ? rc : hk_bench_curvefit_real(out, options);
}
