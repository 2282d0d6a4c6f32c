/* Benchmark of the renderer (thesis 004 §4.1.5-4.1.6 on the CPU): the default head of
 * examples/default groomed once, then rendered at 1920 x 1080 with deep opacity
 * shadows, with 1 and 2 threads, the passes side by side. */
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "bench.h"

int hk_bench_render(FILE *out, const hk_BenchOptions *options)
{
    hk_Error err;
    hk_Scene sc;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    int rc = 1;
    if (hk_bench_scene_load(options, "default", "render", HK_SCENE_ALL, &sc)) return 1;
    if (hk_scene_hair(&sc, NULL, &hair, NULL, &err) != HK_OK) {
        fprintf(stderr, "bench render: %s\n", err.message);
        goto done;
    }
    const int width = options->quick ? 320 : 1920, height = options->quick ? 180 : 1080;
    fprintf(out, "render: examples/default, %u strands, %u points, %dx%d, Kajiya-Kay, deep opacity shadows\n",
            hair.strand_count, hair.point_count, width, height);
    fprintf(out, "  threads  light maps (s)  camera (s)  head+hair (s)   total (s)  hair fragments\n");
    double total[3] = {0, 0, 0};
    for (int threads = 1; threads <= 2; threads++) {
        hk_RenderDef ro = hk_default_render_def();
        ro.width = width, ro.height = height, ro.threads = threads;
        const int reps = options->quick ? 1 : 3;
        hk_RenderStats best;
        memset(&best, 0, sizeof best);
        double best_total = 1e30;
        for (int r = 0; r < reps; r++) {
            hk_Canvas img;
            hk_RenderStats st;
            const double t0 = omp_get_wtime();
            if (hk_scene_render(&sc, &hair, &ro, &img, &st, &err) != HK_OK) {
                fprintf(stderr, "bench render: %s\n", err.message);
                goto done;
            }
            const double t = omp_get_wtime() - t0;
            hk_canvas_free(&img);
            if (t < best_total) best_total = t, best = st;
        }
        total[threads] = best_total;
        fprintf(out, "  %7d %15.3f %11.3f %14.3f %11.3f %15lld\n", threads, best.seconds_light, best.seconds_camera,
                best.seconds_hair, best_total, best.hair_fragments);
    }
    fprintf(out, "  speed-up with 2 threads: %.2fx; target: 1920x1080 with shadows in under 2 s on 2 cores\n\n",
            total[1] / total[2]);
    rc = 0;
done:
    hk_hair_free(&hair);
    hk_scene_free(&sc);
    return rc;
}
