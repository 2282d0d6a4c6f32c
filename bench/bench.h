/* Benchmarks of hairkit: each prints its figures side by side on `out`. They measure
 * speed and never assert it (tests check correctness, benchmarks report speed). */
#ifndef HK_BENCH_H
#define HK_BENCH_H

#include <stdio.h>

#include "hairkit/io.h"
#include "hairkit/mesh.h"
#include "hairkit/scene.h"

typedef struct hk_BenchOptions {
    int quick;          /* a smoke run with tiny repetition counts (used by the tests) */
    double min_seconds; /* minimum measuring time per figure */
    const char *root;   /* the repository (for examples/ and assets/), default "." */
} hk_BenchOptions;

/* An example's scene (bench_scene.c). */
/* Loads examples/EXAMPLE/setup.txt with the parts asked for (hk_scene_load): 0 on
 * success; else prints "bench BENCH: ..." and returns 1. Free with hk_scene_free. */
int hk_bench_scene_load(const hk_BenchOptions *options, const char *example, const char *bench, unsigned parts,
                        hk_Scene *s);

/* Super-Helix statics: Newton against the thesis's Rosenbrock on the same strands. */
int hk_bench_statics(FILE *out, const hk_BenchOptions *options);

/* Grooming the default head: guides and strands per second, 1 and 2 threads. */
int hk_bench_groom(FILE *out, const hk_BenchOptions *options);

/* Rendering the default head at 1920 x 1080 with shadows, 1 and 2 threads. */
int hk_bench_render(FILE *out, const hk_BenchOptions *options);

/* Dynamics: steps per second of one strand (dense and O(N) solvers, N = 5 to 40)
 * and frames per second of 201 guides on a shaking head, 1 and 2 threads for N = 10,
 * 2 threads for N = 20 and 40. */
int hk_bench_dynamics(FILE *out, const hk_BenchOptions *options);

/* The viewer headless (bench_view.c): frames per second of the default head with and
 * without shadows and of examples/guides200 simulated live; the GL renderer named. */
int hk_bench_view(FILE *out, const hk_BenchOptions *options);

/* Stability matrix of single strands (bench_stability.c): hair types and lengths 5 cm to
 * 1.5 m, still and moving heads, dt = 1/24 and 1/30 s, TR-BDF2 and linear Euler. */
int hk_bench_stability(FILE *out, const hk_BenchOptions *options);

/* Long guides on a full head (bench_long_heads.c): 201 guides of 1 m under every motion,
 * 10 s at 24 and 30 frames/s: ran or failed, recovered guides, the farthest tip move. */
int hk_bench_long_heads(FILE *out, const hk_BenchOptions *options);

/* Curve fitting (helicoid paper §5): fits per second of 30-sample strands, 1 and 2
 * threads, clean single and two-piece strands and noisy ones. */
int hk_bench_curvefit(FILE *out, const hk_BenchOptions *options);

/* Follicle sampling: the thin-plate fit for 500..2000 points and the default wick
 * sampled at 1 cm and 5 mm, 1 and 2 threads. */
int hk_bench_follicles(FILE *out, const hk_BenchOptions *options);

/* Generalized helicoids: interpolating 90,000 hairs, fits per second of 30-vertex
 * strands, reconstruction error of a tuft from one strand in ten; 1 and 2 threads. */
int hk_bench_helicoid(FILE *out, const hk_BenchOptions *options);
/* The same on real grooms (bench_helicoid_real.c): fits of Sintel, Bangs and Curly
 * (../shared/hair-data; skipped when absent) and Sintel rebuilt from one strand in ten. */
int hk_bench_helicoid_real(FILE *out, const hk_BenchOptions *options);
/* The reconstruction's rebuild (bench_helicoid_rebuild.c): 100,000 synthetic strands from
 * 10,000 guides, the neighbour search by a scan and by the k-d tree, 1 and 2 threads. */
int hk_bench_helicoid_rebuild(FILE *out, const hk_BenchOptions *options);
/* Fits of examples/helicoid/wisp.txt's wavy strands (bench_helicoid_waves.c): the plain fitter
 * against the fit with eq. 4's waves, one thread. */
int hk_bench_helicoid_waves(FILE *out, const hk_BenchOptions *options);
/* bench curvefit's rows on the same real grooms: the fitter with forward-difference
 * Jacobians and with the helicoid's derivatives, one thread. */
int hk_bench_curvefit_real(FILE *out, const hk_BenchOptions *options);

/* Hair file input and output: the Sintel TressFX groom to .hair (../shared/hair-data;
 * skipped when absent), and 1 million strands of 32 points written and read as .hair
 * against stdio writing and reading the same bytes. */
int hk_bench_io(FILE *out, const hk_BenchOptions *options);

/* Importing a groom (bench_import.c): the Sintel groom of ../shared/hair-data (skipped
 * when absent) imported with 300 guides, the time of each stage, then its still-head
 * drift from the capture after 2 s. */
int hk_bench_import(FILE *out, const hk_BenchOptions *options);

#endif
