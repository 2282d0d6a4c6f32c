/* Benchmark of the dynamics (paper 000 §3.4, §4.4): steps per second of one strand for
 * N = 5, 10, 20 with the dense solver (full stiffness) and the O(N) recursion
 * (Gauss-Newton stiffness) side by side, and frames per second of the 201 guides of
 * examples/guides200 (N = 10) on a shaking head with body and guide-guide contacts at
 * dt = 1/30 s, with 1 and 2 threads, and of the same guides cut into N = 20 and 40
 * elements (issue 12). The paper: up to 10 strands in real time, and 0.3
 * to 3 s per frame for 100 to 200 guides, on a 3 GHz Pentium 4. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/simulate.h"

/* Runs of N = 10 on 1 and 2 threads whose median the bench prints. */
#define HK_BENCH_HEAD_REPEATS      5
#define HK_BENCH_HEAD_REPEATS_TEXT "five"

/* Steps per second of a 20 cm wavy strand released sideways, restarted from rest
 * every 3 s of simulated time so that it keeps moving. */
static double strand_steps_per_second(int n, hk_DynamicsIntegrator integrator, hk_DynamicsSolver solver,
                                      hk_DynamicsStiffness stiffness, double min_seconds, int quick)
{
    double len[64];
    for (int i = 0; i < n; i++) len[i] = 0.2 / n;
    hk_SuperHelix *sh = NULL;
    hk_StrandDynamics *d = NULL;
    hk_Error err;
    if (hk_superhelix_create(n, len, &sh, &err) != HK_OK) return 0.0;
    sh->material = hk_rod_material(42e-6, 38e-6, 2e9, 0.48, 1300.0, hk_v3(0, -9.81, 0));
    double tau, kappa;
    hk_helix_natural_curvature(0.012, 0.12, &tau, &kappa);
    hk_superhelix_set_uniform_rest(sh, tau, kappa, 0.0);
    sh->root_frame = hk_root_frame(hk_v3(1, 0.2, 0.1));
    hk_DynamicsDef p = hk_default_dynamics_def();
    p.integrator = integrator;
    p.solver = solver;
    p.stiffness = stiffness;
    if (hk_strand_dynamics_create(sh, &p, NULL, &d, &err) != HK_OK) {
        hk_superhelix_destroy(sh);
        return 0.0;
    }
    long steps = 0;
    const double t0 = hk_seconds_now();
    double elapsed = 0.0;
    do {
        memcpy(sh->q, sh->q_rest, sizeof(double) * 3 * (size_t)n);
        memset(hk_strand_dynamics_velocity(d), 0, sizeof(double) * 3 * (size_t)n);
        for (int i = 0; i < (quick ? 5 : 90); i++, steps++)
            if (hk_strand_dynamics_advance(d, NULL, NULL, i / 30.0, 1.0 / 30.0, NULL, 0, NULL, &err) != HK_OK) {
                fprintf(stderr, "bench dynamics: N = %d: %s\n", n, err.message);
                break;
            }
        elapsed = hk_seconds_now() - t0;
    } while (!quick && elapsed < min_seconds);
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
    return steps / elapsed;
}

typedef struct HeadRun {
    double seconds_per_frame, substeps, iterations, contacts, body;
} HeadRun;

/* The hairstyle with its guides cut into n equal elements of the same total length
 * (lengths: room for n); the style itself when n is its own count. */
static hk_Hairstyle with_elements(const hk_Hairstyle *style, int n, double *lengths)
{
    hk_Hairstyle s = *style;
    if (n == style->strand.element_count) return s;
    double total = 0.0;
    for (int i = 0; i < style->strand.element_count; i++) total += style->strand.element_lengths[i];
    for (int i = 0; i < n; i++) lengths[i] = total / n;
    s.strand.element_count = n;
    s.strand.element_lengths = lengths;
    return s;
}

static int head_run(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count, const hk_Mesh *wick,
                    int threads, int frames, int trbdf2, HeadRun *out)
{
    hk_HairSimDef o = hk_hair_sim_def_for(style);
    o.threads = threads;
    if (trbdf2) { /* the single strands' default: O(N) solver, every force implicit */
        const hk_DynamicsDef strand = style->dynamics;
        o.dynamics.integrator = strand.integrator;
        o.dynamics.solver = strand.solver;
        o.dynamics.stiffness = strand.stiffness;
    }
    hk_HairSim *sim = NULL;
    hk_HeadMotion *shake = NULL;
    hk_Error err;
    int rc = 1;
    if (hk_hair_sim_create(style, shapes, shape_count, wick, &o, &sim, &err) != HK_OK ||
        hk_head_motion_scripted("shake", 25.0, 1.0, hk_default_head_pivot(), &shake, &err) != HK_OK ||
        hk_hair_sim_settle(sim, NULL, 0.5, 1.0 / 30.0, &err) != HK_OK) {
        fprintf(stderr, "bench dynamics: %s\n", err.message);
        goto done;
    }
    memset(out, 0, sizeof *out);
    double seconds = 0.0;
    for (int f = 0; f < frames; f++) {
        hk_HairSimStats stats;
        if (hk_hair_sim_advance(sim, shake, f / 30.0, 1.0 / 30.0, &stats, &err) != HK_OK) {
            fprintf(stderr, "bench dynamics: %s\n", err.message);
            goto done;
        }
        seconds += stats.seconds;
        out->substeps += stats.substeps;
        out->iterations += (double)stats.iterations;
        out->contacts += stats.contacts;
        out->body += stats.body_contacts;
    }
    const int guides = hk_hair_sim_guide_count(sim);
    out->seconds_per_frame = seconds / frames;
    out->substeps /= (double)frames * guides;
    out->iterations /= (double)frames * guides;
    out->contacts /= frames;
    out->body /= frames;
    rc = 0;
done:
    hk_head_motion_destroy(shake);
    hk_hair_sim_destroy(sim);
    return rc;
}

/* The median of count values (count <= HK_BENCH_HEAD_REPEATS), leaving them in place. */
static double median_of(const double *values, int count)
{
    double v[HK_BENCH_HEAD_REPEATS];
    for (int i = 0; i < count; i++) { /* insertion sort: a handful of values */
        int k = i;
        for (; k > 0 && v[k - 1] > values[i]; k--) v[k] = v[k - 1];
        v[k] = values[i];
    }
    return count % 2 ? v[count / 2] : 0.5 * (v[count / 2 - 1] + v[count / 2]);
}

/* The same simulation counted: steps, evaluations, contacts and body samples equal. */
static int same_counts(const HeadRun *a, const HeadRun *b)
{
    return a->substeps == b->substeps && a->iterations == b->iterations && a->contacts == b->contacts &&
           a->body == b->body;
}

int hk_bench_dynamics(FILE *out, const hk_BenchOptions *options)
{
    fprintf(out, "dynamics, one strand: 20 cm wavy hair released sideways, frames of dt = 1/30 s per second\n"
                 "  (the paper: up to 10 strands in real time, about 300 steps/s, on a 3 GHz Pentium 4)\n"
                 "         TR-BDF2 (default)             linear Euler (issue 6)\n"
                 "      N   O(N), Gauss-Newton   dense, full   dense, full   O(N), Gauss-Newton\n");
    const int ns[4] = {5, 10, 20, 40};
    for (int k = 0; k < 4; k++) {
        const double q = options->min_seconds;
        const int quick = options->quick;
        const double tr_linear = strand_steps_per_second(ns[k], HK_INTEGRATOR_TRBDF2, HK_DYNAMICS_LINEAR,
                                                         HK_STIFFNESS_GAUSS_NEWTON, q, quick);
        const double tr_dense =
            strand_steps_per_second(ns[k], HK_INTEGRATOR_TRBDF2, HK_DYNAMICS_DENSE, HK_STIFFNESS_FULL, q, quick);
        const double eu_dense =
            strand_steps_per_second(ns[k], HK_INTEGRATOR_LINEAR_EULER, HK_DYNAMICS_DENSE, HK_STIFFNESS_FULL, q, quick);
        const double eu_linear = strand_steps_per_second(ns[k], HK_INTEGRATOR_LINEAR_EULER, HK_DYNAMICS_LINEAR,
                                                         HK_STIFFNESS_GAUSS_NEWTON, q, quick);
        fprintf(out, "  %5d %20.0f %13.0f %13.0f %20.0f\n", ns[k], tr_linear, tr_dense, eu_dense, eu_linear);
    }

    hk_Scene sc;
    if (hk_bench_scene_load(options, "guides200", "dynamics", HK_SCENE_GROOMING, &sc)) return 1;
    const hk_Hairstyle style = sc.style;
    const hk_Mesh wick = sc.wick;
    int rc = 0;
    const int frames = options->quick ? 3 : 90, long_frames = options->quick ? 3 : 30;
    fprintf(out,
            "\ndynamics, full head: examples/guides200, %d guides, head shaking 25 degrees at 1 Hz,\n"
            "body and guide-guide contacts, dt = 1/30 s, %d frames (N = %d: %s; %d for N = 20 and 40) after 0.5 s "
            "of settling\n"
            "  (the paper: 0.3 to 3 s per frame for 100 to 200 guides)\n"
            "  integrator      N  threads   ms/frame   frames/s   steps/guide/frame   evaluations/guide/frame   guide "
            "contacts   body samples\n",
            wick.vertex_count, frames, style.strand.element_count,
            options->quick ? "the median of two runs" : "the median of " HK_BENCH_HEAD_REPEATS_TEXT " runs",
            long_frames);
    /* The simulate default (linear Euler) for N = 10 on 1 and 2 threads, TR-BDF2 on 2,
     * then linear Euler on 2 threads with the guides cut into 20 and 40 elements. */
    const struct {
        int n, threads, trbdf2;
    } runs[5] = {{style.strand.element_count, 1, 0},
                 {style.strand.element_count, 2, 0},
                 {style.strand.element_count, 2, 1},
                 {20, 2, 0},
                 {40, 2, 0}};
    /* The first two (N = 10 on 1 and 2 threads) are run `repeats` times, alternated, and
     * their rows give the median: the VM's speed drifts by a quarter within minutes, so
     * that one run says little (docs/dynamics.md, "Speed"). Their counts (steps,
     * contacts) are the same every time, the simulation being deterministic: checked. */
    const int repeats = options->quick ? 2 : HK_BENCH_HEAD_REPEATS;
    double ms[2][HK_BENCH_HEAD_REPEATS], lengths[40];
    HeadRun counted[2];
    for (int rep = 0; rep < repeats && !rc; rep++)
        for (int run = 0; run < 2 && !rc; run++) {
            HeadRun r;
            rc = head_run(&style, sc.collision.shapes, sc.collision.count, &wick, runs[run].threads, frames, 0, &r);
            if (rc) break;
            if (rep == 0)
                counted[run] = r;
            else if (!same_counts(&r, &counted[run])) {
                fprintf(stderr, "bench dynamics: run %d on %d threads counted other steps or contacts than run 1\n",
                        rep + 1, runs[run].threads);
                rc = 1;
            }
            ms[run][rep] = 1e3 * r.seconds_per_frame;
        }
    /* The quick (smoke) run leaves out N = 40, the slowest by far (its settling alone). */
    const int run_count = options->quick ? 4 : 5;
    for (int run = 0; run < run_count && !rc; run++) {
        HeadRun r;
        if (run < 2) {
            r = counted[run];
            r.seconds_per_frame = 1e-3 * median_of(ms[run], repeats);
        } else {
            const hk_Hairstyle cut = with_elements(&style, runs[run].n, lengths);
            rc = head_run(&cut, sc.collision.shapes, sc.collision.count, &wick, runs[run].threads,
                          run < 3 ? frames : long_frames, runs[run].trbdf2, &r);
            if (rc) break;
        }
        fprintf(out, "  %-12s %4d %8d %10.2f %10.1f %19.2f %25.2f %16.0f %14.0f\n",
                runs[run].trbdf2 ? "TR-BDF2" : "linear Euler", runs[run].n, runs[run].threads,
                1e3 * r.seconds_per_frame, 1.0 / r.seconds_per_frame, r.substeps, r.iterations, r.contacts, r.body);
    }
    if (!rc) {
        for (int run = 0; run < 2; run++) {
            fprintf(out, "  N = %d on %d thread%s, ms a frame in each of %d runs (alternated, the median above):",
                    style.strand.element_count, runs[run].threads, runs[run].threads > 1 ? "s" : "", repeats);
            for (int rep = 0; rep < repeats; rep++) fprintf(out, " %.2f", ms[run][rep]);
            fprintf(out, "\n");
        }
        fprintf(out, "  speed-up with 2 threads (N = %d): %.2fx; target: 60 frames/s or more on 2 cores\n\n",
                style.strand.element_count, median_of(ms[0], repeats) / median_of(ms[1], repeats));
    }
    hk_scene_free(&sc);
    return rc;
}
