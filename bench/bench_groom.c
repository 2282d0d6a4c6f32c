/* Benchmark of grooming (Lansink 2010 §4.1.4): the default head of examples/default,
 * guides solved and strands interpolated per second, with 1 and 2 threads. */
#include <omp.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <stdlib.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/groom.h"

int hk_bench_groom(FILE *out, const hk_BenchOptions *options)
{
    hk_Scene sc;
    if (hk_bench_scene_load(options, "default", "groom", HK_SCENE_GROOMING, &sc)) return 1;
    const hk_Hairstyle style = sc.style;
    const hk_Shape *shapes = sc.collision.shapes;
    const int shape_count = sc.collision.count;
    const hk_Mesh wick = sc.wick;
    hk_Error err;
    fprintf(out, "groom: examples/default (%d guides, %.0f hairs/cm^2 on %.0f cm^2 of scalp)\n", wick.vertex_count,
            style.interpolation.hair_density, 1e4 * hk_mesh_area(&wick));
    fprintf(out, "  threads   guides (s)  guides/s   strands (s)  strands/s   total (s)  strands   to .hair (s)\n");
    int rc = 0;
    double total[3] = {0, 0, 0};
    for (int threads = 1; threads <= 2; threads++) {
        hk_GroomDef o = hk_default_groom_def();
        o.threads = threads;
        const int reps = options->quick ? 1 : 3;
        double best = 1e30, best_g = 0, best_s = 0, best_save = 0;
        int strands = 0;
        for (int r = 0; r < reps; r++) {
            hk_Groom g;
            const double t0 = hk_seconds_now();
            if (hk_groom_grow(&style.strand, &style.interpolation, shapes, shape_count, &wick, &o, &g, &err) != HK_OK) {
                fprintf(stderr, "bench groom: %s\n", err.message);
                rc = 1;
                break;
            }
            const double t1 = hk_seconds_now();
            hk_HairFile hair;
            double t2 = t1;
            if (hk_groom_to_hair(&g, &style.strand, &hair, &err) == HK_OK) {
                char path[] = "/tmp/hairkit-bench-XXXXXX";
                int fd = mkstemp(path);
                if (fd >= 0) {
                    close(fd);
                    hk_hair_save(path, &hair, &err);
                    t2 = hk_seconds_now();
                    remove(path);
                }
                hk_hair_free(&hair);
            }
            if (t1 - t0 < best) {
                best = t1 - t0;
                best_g = g.stats.seconds_guides;
                best_s = g.stats.seconds_strands;
                best_save = t2 - t1;
            }
            strands = g.strand_count;
            hk_groom_free(&g);
        }
        if (rc) break;
        total[threads] = best;
        fprintf(out, "  %7d %12.3f %9.0f %13.3f %10.0f %11.3f %8d %12.3f\n", threads, best_g,
                wick.vertex_count / best_g, best_s, strands / best_s, best, strands, best_save);
    }
    if (!rc)
        fprintf(out, "  speed-up with 2 threads: %.2fx; target: the default head groomed in under 1 s on 2 cores\n\n",
                total[1] / total[2]);
    hk_scene_free(&sc);
    return rc;
}
