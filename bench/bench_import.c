/* hairkit bench import: the Sintel groom of ../shared/hair-data imported as `hairkit
 * import` does it (hk_import_run, 300 guides, sintel-collider.obj), its time split by
 * stage, then the still-head drift: the folder's setup simulated for 2 s at 30 frames/s
 * without preroll, every strand compared with the capture (docs/capture.md, "Measured").
 * Skipped, saying so, when the shared data are absent. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/capture.h"
#include "hairkit/simulate.h"

#define GUIDES 300
#define FPS    30

static double cpu_now(void) { return (double)clock() / CLOCKS_PER_SEC; }

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The strands of the import now against the capture: mean, 95th percentile, largest (m). */
static int drift(const hk_ImportedGroom *g, const hk_HairSim *sim, double out[3], hk_Error *err)
{
    const size_t count = g->first_point[g->strand_count];
    float *p = hk_alloc_array(count, 3 * sizeof(float), err);
    double *d = hk_alloc_array(count, sizeof(double), err);
    int ok = p && d && hk_imported_groom_strands(g, hk_hair_sim_strands(sim), 0, p, err) == HK_OK;
    if (ok) {
        double sum = 0.0;
        for (size_t k = 0; k < count; k++) {
            const float *a = p + 3 * k, *b = g->points + 3 * k;
            d[k] = hk_v3_norm(hk_v3((double)a[0] - b[0], (double)a[1] - b[1], (double)a[2] - b[2]));
            sum += d[k];
        }
        qsort(d, count, sizeof *d, by_value);
        out[0] = sum / (double)count;
        out[1] = d[(size_t)(0.95 * (double)count)];
        out[2] = d[count - 1];
    }
    hk_free(p);
    hk_free(d);
    return ok;
}

/* The folder's setup on a still head for `frames` frames. */
static int still_drift(FILE *out, const char *setup, int frames, hk_Error *err)
{
    hk_Scene scene;
    hk_ImportedGroom g;
    memset(&g, 0, sizeof g);
    hk_HairSim *sim = NULL;
    const double t0 = hk_seconds_now();
    int ok = hk_scene_load(setup, HK_SCENE_HAIRSTYLE | HK_SCENE_COLLISION | HK_SCENE_HEAD, &scene, err) == HK_OK;
    ok = ok && scene.setup.import_file && hk_imported_groom_load(scene.setup.import_file, &g, err) == HK_OK;
    ok = ok && hk_hair_sim_create_imported(&scene.style, scene.collision.shapes, scene.collision.count, &g, NULL, &sim,
                                           err) == HK_OK;
    const double t1 = hk_seconds_now();
    long recovered = 0;
    for (int k = 0; ok && k < frames; k++) {
        hk_HairSimStats stats;
        ok = hk_hair_sim_advance(sim, NULL, (double)k / FPS, 1.0 / FPS, &stats, err) == HK_OK;
        recovered += stats.recovered;
    }
    const double t2 = hk_seconds_now();
    double d[3];
    ok = ok && drift(&g, sim, d, err);
    if (ok) {
        fprintf(out, "  still head, %d frames at %d/s (%.2f s), no preroll: set up %.2f s, dynamics %.3f s a frame\n",
                frames, FPS, (double)frames / FPS, t1 - t0, (t2 - t1) / frames);
        fprintf(out,
                "  drift from the capture: %.4f mm mean, %.4f mm at the 95th percentile, %.3f mm at most; "
                "%ld guide steps held (recovered)\n",
                1e3 * d[0], 1e3 * d[1], 1e3 * d[2], recovered);
    }
    hk_hair_sim_destroy(sim);
    hk_imported_groom_free(&g);
    hk_scene_free(&scene);
    return ok;
}

static void remove_folder(const char *dir)
{
    static const char *const files[] = {"setup.txt", "hairstyle.txt", "head.obj", "guides.txt", "strands.hair"};
    char path[4096 + 32];
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        unlink(path);
    }
    rmdir(dir);
}

int hk_bench_import(FILE *out, const hk_BenchOptions *options)
{
    char hair[4096], head[4096], dir[4096], setup[4096 + 16];
    snprintf(hair, sizeof hair, "%s/../shared/hair-data/SintelHairOriginal-sintel_hair.16points.tfx", options->root);
    snprintf(head, sizeof head, "%s/../shared/hair-data/sintel-collider.obj", options->root);
    struct stat sb;
    fprintf(out, "import: the Sintel groom (TressFX, 11,400 strands x 16 points) on sintel-collider.obj, %d guides\n",
            options->quick ? 30 : GUIDES);
    if (stat(hair, &sb) != 0 || stat(head, &sb) != 0) {
        fprintf(out, "  skipped: %s or %s is absent (../shared/hair-data)\n", hair, head);
        return 0;
    }
    const char *tmp = getenv("TMPDIR");
    snprintf(dir, sizeof dir, "%s/hairkit-bench-import-%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    snprintf(setup, sizeof setup, "%s/setup.txt", dir);
    hk_ImportRunDef d = hk_default_import_run_def();
    d.hair = hair;
    d.head = head;
    d.dir = dir;
    d.groom.guides = options->quick ? 30 : GUIDES;
    hk_ImportRunReport r;
    hk_Error err;
    const double c0 = cpu_now();
    int ok = hk_import_run(&d, &r, &err) == HK_OK;
    const double cpu = cpu_now() - c0;
    if (ok) {
        const hk_GroomImportReport *g = &r.groom;
        fprintf(out, "  import: %.2f s wall, %.2f s of CPU (all threads)\n", r.seconds, cpu);
        fprintf(out,
                "    read %.3f s, head's field %.3f s (%d x %d x %d nodes, %d triangles), push out %.3f s, "
                "guides chosen %.3f s\n",
                r.seconds_read, r.seconds_field, r.field_size[0], r.field_size[1], r.field_size[2], r.head_triangles,
                g->seconds_push, g->seconds_choose);
        fprintf(out,
                "    fit and inverse %.3f s wall: CPU of the fits %.3f s, of the "
                "inversions %.3f s (%.1f elements a guide)\n",
                g->seconds_fit, g->task_seconds_fit, g->task_seconds_inverse, g->elements_mean);
        fprintf(out, "    attachments %.3f s, writing %.3f s\n", g->seconds_attach, r.seconds_write);
        fprintf(out, "    fit %.3f mm mean (worst guide %.3f mm); %d guides unstable, %d followed by none\n",
                1e3 * g->fit_mean, 1e3 * g->fit_worst, g->unstable, g->unfollowed);
        ok = still_drift(out, setup, options->quick ? 3 : 2 * FPS, &err);
    }
    remove_folder(dir);
    if (!ok) {
        fprintf(stderr, "bench import: %s\n", err.message);
        return 1;
    }
    return 0;
}
