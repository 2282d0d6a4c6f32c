/* Benchmark of strands with eq. 4's waves (Piuze et al. 2011 §3.2): examples/helicoid/wisp.txt
 * traced at its step, every 32nd strand (one with --quick) fitted by the plain fitter
 * (hk_helicoid_fit: about 9 pieces a wave) and by the fit with waves (hk_helicoid_fit_wavy):
 * pieces, mean error (normalised coupling against the strand, each fitter's report) and CPU
 * seconds per strand on one thread. */
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/helicoid_hair.h"

int hk_bench_helicoid_waves(FILE *out, const hk_BenchOptions *options)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/examples/helicoid/wisp.txt", options->root);
    hk_HelicoidSet set;
    hk_HairFile hair;
    memset(&set, 0, sizeof set);
    memset(&hair, 0, sizeof hair);
    hk_Error err;
    if (hk_helicoid_file_load(path, &set, &err) != HK_OK ||
        hk_helicoid_set_trace(&set, set.step, 1, 1, &hair, &err) != HK_OK) {
        fprintf(stderr, "bench helicoid: %s\n", err.message);
        hk_helicoid_set_free(&set);
        return 1;
    }
    const uint32_t every = options->quick ? hair.strand_count : 32;
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(4096, &err);
    double seconds[2] = {0.0, 0.0}, error[2] = {0.0, 0.0}, pieces[2] = {0.0, 0.0};
    int n = 0, status = f ? 0 : 1;
    for (uint32_t s = 0; !status && s < hair.strand_count; s += every, n++) {
        const uint32_t a = hair.first_point[s], count = hair.first_point[s + 1] - a;
        hk_Vec3 *p = malloc((size_t)count * sizeof *p);
        status = !p;
        for (uint32_t i = 0; !status && i < count; i++)
            p[i] = hk_v3(hair.points[3 * (a + i)], hair.points[3 * (a + i) + 1], hair.points[3 * (a + i) + 2]);
        hk_PHelicoid fit;
        hk_CurveFit report;
        hk_Waviness wave;
        double e, c0 = hk_thread_cpu_seconds();
        status = status || hk_helicoid_fit(f, p, (int)count, NULL, &fit, &report, &err) != HK_OK;
        if (!status) seconds[0] += hk_thread_cpu_seconds() - c0, error[0] += report.error, pieces[0] += fit.piece_count;
        c0 = hk_thread_cpu_seconds();
        status = status || hk_helicoid_fit_wavy(f, p, (int)count, NULL, &fit, &wave, &e, &err) != HK_OK;
        if (!status) seconds[1] += hk_thread_cpu_seconds() - c0, error[1] += e, pieces[1] += fit.piece_count;
        free(p);
    }
    if (!status) {
        fprintf(out,
                "helicoid fits of wavy strands: examples/helicoid/wisp.txt (27 cm, 2 pieces, waves of 2 mm\n"
                "  at 120 rad/m), %d strands of %u, one thread\n"
                "  fitter                          pieces   mean error (mm)   CPU s per strand\n",
                n, hair.strand_count);
        static const char *const name[2] = {"plain (hk_helicoid_fit)", "with waves (hk_helicoid_fit_wavy)"};
        for (int k = 0; k < 2; k++)
            fprintf(out, "  %-33s %6.1f %17.4f %18.2f\n", name[k], pieces[k] / n, 1e3 * error[k] / n, seconds[k] / n);
        fprintf(out, "\n");
    } else {
        fprintf(stderr, "bench helicoid: wisp.txt: %s\n", err.message);
    }
    hk_helicoid_fitter_destroy(f);
    hk_hair_free(&hair);
    hk_helicoid_set_free(&set);
    return status;
}
