/* The scene of a benchmark: an example's setup file and the parts of it the benchmark uses. */
#include <stdio.h>

#include "bench.h"

int hk_bench_scene_load(const hk_BenchOptions *options, const char *example, const char *bench, unsigned parts,
                        hk_Scene *s)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/examples/%s/setup.txt", options->root, example);
    hk_Error err;
    if (hk_scene_load(path, parts, s, &err) != HK_OK) {
        fprintf(stderr, "bench %s: %s (run from the source folder or give --root)\n", bench, err.message);
        return 1;
    }
    return 0;
}
