/* Benchmark of the renderer (thesis 004 §4.1.5-4.1.6 on the CPU): the default head of
 * examples/default groomed once, then rendered at 64 x 48, 640 x 480 and 1920 x 1080
 * with deep opacity shadows, with 1 and 2 threads, the passes side by side, and the
 * texels a side of the light's maps each size gets (hk_render_shadow_map_texels). */
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
    /* Three sizes (issue 18, item 4): the work that scales with pixels should shrink
     * with the picture; what does not (growing aside: the light's maps, the camera
     * pass over every segment) shows as the floor of the small picture. */
    static const int full_sizes[][2] = {{64, 48}, {640, 480}, {1920, 1080}};
    static const int quick_sizes[][2] = {{64, 48}, {320, 180}};
    const int(*sizes)[2] = options->quick ? quick_sizes : full_sizes;
    const int size_count = options->quick ? 2 : 3;
    fprintf(out, "render: examples/default, %u strands, %u points, Kajiya-Kay, deep opacity shadows\n",
            hair.strand_count, hair.point_count);
    fprintf(out, "  picture    threads  map  strands  light maps (s)  camera (s)  head+hair (s)   total (s)  hair "
                 "fragments\n");
    /* Each size as drawn by default, then the smallest with every strand (the level of
     * detail off: what a thumbnail cost before it). */
    for (int z = 0; z <= size_count; z++) {
        const int every = z == size_count;
        const int width = sizes[every ? 0 : z][0], height = sizes[every ? 0 : z][1];
        double total[3] = {0, 0, 0};
        for (int threads = 1; threads <= 2; threads++) {
            hk_RenderDef ro = hk_default_render_def();
            ro.width = width, ro.height = height, ro.threads = threads;
            ro.strand_lod = !every;
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
            char picture[24];
            snprintf(picture, sizeof picture, "%dx%d", width, height);
            char drawn[24];
            snprintf(drawn, sizeof drawn, best.strand_stride > 1 ? "1 in %d" : "all", best.strand_stride);
            fprintf(out, "  %-10s %7d %4d %8s %15.3f %11.3f %14.3f %11.3f %15lld\n", picture, threads,
                    hk_render_shadow_map_texels(&ro), drawn, best.seconds_light, best.seconds_camera, best.seconds_hair,
                    best_total, best.hair_fragments);
        }
        fprintf(out, "  %dx%d%s: speed-up with 2 threads %.2fx\n", width, height,
                every ? " with every strand (--all-strands)" : "", total[1] / total[2]);
    }
    fprintf(out, "  target: 1920x1080 with shadows in under 2 s on 2 cores\n\n");
    rc = 0;
done:
    hk_hair_free(&hair);
    hk_scene_free(&sc);
    return rc;
}
