/* The scene of a benchmark: an example's setup, hairstyle, collision shapes and wick. */
#include <stdio.h>
#include <string.h>

#include "bench.h"

int hk_bench_scene_load(const hk_BenchOptions *options, const char *example, const char *bench, hk_BenchScene *s)
{
    char path[4096];
    memset(s, 0, sizeof *s);
    s->style = hk_default_hairstyle();
    snprintf(path, sizeof path, "%s/examples/%s/setup.txt", options->root, example);
    hk_Error err;
    if (hk_setup_load(path, &s->setup, &err) != HK_OK || hk_hairstyle_load(s->setup.hairstyle, &s->style, &err) != HK_OK ||
        (s->setup.collision && hk_collision_load(s->setup.collision, &s->shapes, &s->shape_count, &err) != HK_OK) ||
        hk_obj_load(s->setup.wick_model, &s->wick, &err) != HK_OK) {
        fprintf(stderr, "bench %s: %s (run from the source folder or give --root)\n", bench, err.message);
        hk_bench_scene_free(s);
        return 1;
    }
    return 0;
}

void hk_bench_scene_free(hk_BenchScene *s)
{
    hk_mesh_free(&s->wick);
    hk_free(s->shapes);
    hk_hairstyle_free(&s->style);
    hk_setup_free(&s->setup);
    memset(s, 0, sizeof *s);
}
