/* Benchmark of the reconstruction's rebuild (Piuze et al. 2011, §5.4;
 * helicoid/reconstruct_blend.c) on a large synthetic head: 100,000 strands rebuilt from
 * 10,000 fitted guides, each from its 16 nearest guides by root. The neighbour search alone
 * is timed both ways, the scan of every guide that the rebuild used until 6 December 2026
 * and the k-d tree it uses now (core/kd_tree.c), on one thread in CPU seconds; then the whole
 * rebuild on 1 and 2 threads (wall clock). */
#include <math.h>
#include <string.h>

#include "bench.h"
#include "core/core_internal.h"
#include "core/kd_tree.h"
#include "hairkit/helicoid_hair.h"
#include "hairkit/rng.h"
#include "helicoid/helicoid_internal.h"

static double uniform(uint64_t stream, uint64_t i, double lo, double hi)
{
    return lo + (hi - lo) * hk_rng_uniform(23, stream, i);
}

/* A direction off a 10 cm head's upper half: the tangent of hk_helicoid_frame(theta, phi). */
static hk_Mat3 scalp_frame(uint64_t stream, uint64_t i)
{
    return hk_helicoid_frame(uniform(stream, i, -acos(-1.0), acos(-1.0)), asin(uniform(stream + 1, i, 0.0, 1.0)));
}

/* Guides of 2 pieces of 5 cm leaving the head along its normal, curling moderately. */
static void make_guides(hk_PHelicoid *g, int count)
{
    for (int i = 0; i < count; i++) {
        const uint64_t u = (uint64_t)i;
        memset(&g[i], 0, sizeof g[i]);
        g[i].frame = scalp_frame(1, u);
        g[i].root = hk_v3_scale(hk_m3_col(&g[i].frame, 0), 0.1);
        g[i].piece_count = 2;
        for (int p = 0; p < 2; p++) {
            const uint64_t k = 2 * u + (uint64_t)p;
            g[i].k[p] = (hk_Helicoid){uniform(3, k, 2, 30), uniform(4, k, -3, 3), uniform(5, k, -8, 8),
                                      uniform(6, k, -0.3, 0.3)};
            g[i].length[p] = 0.05;
        }
    }
}

/* Strands of two points: all the rebuild reads of a capture is root, length and direction. */
static hk_Status make_hair(hk_HairFile *hair, long count)
{
    uint32_t *two = hk_alloc_array((size_t)count, sizeof *two, NULL);
    if (!two) return HK_ERR_NOMEM;
    for (long s = 0; s < count; s++) two[s] = 2;
    const hk_Status st = hk_hair_alloc(hair, (uint32_t)count, two, NULL);
    hk_free(two);
    for (long s = 0; st == HK_OK && s < count; s++) {
        const hk_Mat3 f = scalp_frame(7, (uint64_t)s);
        const hk_Vec3 t = hk_m3_col(&f, 0), root = hk_v3_scale(t, 0.1), tip = hk_v3_madd(root, t, 0.1);
        float *q = hair->points + 6 * (size_t)s;
        q[0] = (float)root.x, q[1] = (float)root.y, q[2] = (float)root.z;
        q[3] = (float)tip.x, q[4] = (float)tip.y, q[5] = (float)tip.z;
    }
    return st;
}

int hk_bench_helicoid_rebuild(FILE *out, const hk_BenchOptions *options)
{
    const int guide_count = options->quick ? 200 : 10000;
    const long strands = options->quick ? 2000 : 100000;
    hk_PHelicoid *guides = hk_alloc_array((size_t)guide_count, sizeof *guides, NULL);
    hk_Vec3 *roots = hk_alloc_array((size_t)guide_count, sizeof *roots, NULL);
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    if (!guides || !roots || make_hair(&hair, strands) != HK_OK) {
        fprintf(stderr, "bench helicoid: out of memory\n");
        hk_free(guides), hk_free(roots), hk_hair_free(&hair);
        return 1;
    }
    make_guides(guides, guide_count);
    for (int g = 0; g < guide_count; g++) roots[g] = guides[g].root;
    fprintf(out,
            "helicoid reconstruction's rebuild (5.4): %ld strands of 10 cm from %d guides of 2 pieces,\n"
            "  roots on a 10 cm half sphere, traced every 2 mm, each from its %d nearest guides\n",
            strands, guide_count, HK_RECONSTRUCT_NEIGHBOURS);
    /* The search alone, one thread, CPU time: the scan, then the tree (its build included). */
    int ia[HK_RECONSTRUCT_NEIGHBOURS], ib[HK_RECONSTRUCT_NEIGHBOURS];
    double da[HK_RECONSTRUCT_NEIGHBOURS], db[HK_RECONSTRUCT_NEIGHBOURS];
    long checksum_scan = 0, checksum_tree = 0;
    double c0 = hk_thread_cpu_seconds();
    for (long s = 0; s < strands; s++) {
        const float *q = hair.points + 6 * (size_t)s;
        const int m =
            hk_nearest_by_scan(roots, guide_count, hk_v3(q[0], q[1], q[2]), HK_RECONSTRUCT_NEIGHBOURS, ia, da);
        for (int i = 0; i < m; i++) checksum_scan += (long)ia[i] * (i + 1);
    }
    const double scan_seconds = hk_thread_cpu_seconds() - c0;
    c0 = hk_thread_cpu_seconds();
    hk_KdTree tree;
    int status = hk_kd_tree_build(&tree, roots, guide_count, NULL) != HK_OK;
    for (long s = 0; !status && s < strands; s++) {
        const float *q = hair.points + 6 * (size_t)s;
        const int m = hk_kd_tree_nearest(&tree, hk_v3(q[0], q[1], q[2]), HK_RECONSTRUCT_NEIGHBOURS, ib, db);
        for (int i = 0; i < m; i++) checksum_tree += (long)ib[i] * (i + 1);
    }
    const double tree_seconds = hk_thread_cpu_seconds() - c0;
    hk_kd_tree_free(&tree);
    fprintf(out,
            "  neighbour search, 1 thread (CPU s): scan of every guide %.3f, k-d tree %.3f (%.0fx);"
            " the same neighbours: %s\n",
            scan_seconds, tree_seconds, scan_seconds / fmax(tree_seconds, 1e-9),
            checksum_scan == checksum_tree ? "yes" : "NO");
    fprintf(out, "  threads   whole rebuild (s)   strands/s\n");
    for (int threads = 1; !status && threads <= 2; threads++) {
        hk_HairFile rebuilt;
        const double t0 = hk_seconds_now();
        status = hk_helicoid_rebuild(&hair, guides, guide_count, 3.0, 0.002, threads, &rebuilt, NULL) != HK_OK;
        const double t = hk_seconds_now() - t0;
        if (!status) fprintf(out, "  %7d %19.3f %11.0f\n", threads, t, strands / t);
        hk_hair_free(&rebuilt);
    }
    fprintf(out, "\n");
    if (status) fprintf(stderr, "bench helicoid: the rebuild failed\n");
    hk_free(guides), hk_free(roots), hk_hair_free(&hair);
    return status;
}
