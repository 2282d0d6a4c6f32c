/* Benchmark of the follicle sampling (Piuze et al. 2011 §4.3): the thin-plate fit for growing
 * point counts, and the particle sampling of the default wick at two spacings, with
 * 1 and 2 threads. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/follicle_sampling.h"

/* n points with normals on an ellipsoid the size of a head (Fibonacci spiral). */
static void head_like(int n, hk_Vec3 *p, hk_Vec3 *nrm)
{
    const double a = 0.08, b = 0.1, c = 0.11;
    for (int i = 0; i < n; i++) {
        const double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z), phi = 2.399963229728653 * i;
        const hk_Vec3 u = hk_v3(r * cos(phi), r * sin(phi), z);
        p[i] = hk_v3(a * u.x, b * u.y, c * u.z);
        nrm[i] = hk_v3(u.x / a, u.y / b, u.z / c);
    }
}

int hk_bench_follicles(FILE *out, const hk_BenchOptions *options)
{
    hk_Error err;
    int rc = 0;
    const int reps = options->quick ? 1 : 3;
    fprintf(out, "follicles: thin-plate fit (n points -> 2n constraints, dense Cholesky of the reduced system)\n");
    fprintf(out, "  points  constraints   1 thread (s)  2 threads (s)\n");
    const int sizes[3] = {500, 1000, 2000};
    for (int k = 0; k < (options->quick ? 1 : 3) && !rc; k++) {
        const int n = sizes[k];
        hk_Vec3 *p = malloc(sizeof *p * (size_t)n), *nrm = malloc(sizeof *nrm * (size_t)n);
        if (!p || !nrm) {
            free(p), free(nrm);
            return 1;
        }
        head_like(n, p, nrm);
        double best[3] = {0, 1e30, 1e30};
        for (int threads = 1; threads <= 2 && !rc; threads++)
            for (int r = 0; r < reps; r++) {
                hk_ImplicitFitDef def = hk_default_implicit_fit_def();
                def.threads = threads;
                hk_ImplicitSurface *s;
                const double t0 = hk_seconds_now();
                if (hk_implicit_surface_fit(p, nrm, n, &def, &s, &err) != HK_OK) {
                    fprintf(stderr, "bench follicles: %s\n", err.message);
                    rc = 1;
                    break;
                }
                best[threads] = fmin(best[threads], hk_seconds_now() - t0);
                hk_implicit_surface_destroy(s);
            }
        if (!rc) fprintf(out, "  %6d %12d %14.3f %14.3f\n", n, 2 * n, best[1], best[2]);
        free(p), free(nrm);
    }
    if (rc) return rc;

    char head_path[4096], wick_path[4096];
    snprintf(head_path, sizeof head_path, "%s/assets/head.obj", options->root);
    snprintf(wick_path, sizeof wick_path, "%s/assets/wick.obj", options->root);
    hk_Mesh head, wick;
    if (hk_obj_load(head_path, &head, &err) != HK_OK) {
        fprintf(stderr, "bench follicles: %s\n", err.message);
        return 1;
    }
    if (hk_obj_load(wick_path, &wick, &err) != HK_OK) {
        fprintf(stderr, "bench follicles: %s\n", err.message);
        hk_mesh_free(&head);
        return 1;
    }
    fprintf(out, "follicles: the default wick (%.0f cm^2), fit + contour + particle sampling\n",
            1e4 * hk_mesh_area(&wick));
    fprintf(out, "  spacing (mm)  follicles  iterations   1 thread (s)  2 threads (s)\n");
    const double spacings[2] = {0.01, 0.005};
    for (int k = 0; k < (options->quick ? 1 : 2) && !rc; k++) {
        double best[3] = {0, 1e30, 1e30};
        int count = 0, iterations = 0;
        for (int threads = 1; threads <= 2 && !rc; threads++)
            for (int r = 0; r < reps; r++) {
                hk_WickSamplingDef def = hk_default_wick_sampling_def();
                def.spacing = spacings[k];
                def.threads = threads;
                hk_FollicleSamples f;
                const double t0 = hk_seconds_now();
                if (hk_wick_follicles(&head, &wick, &def, &f, &err) != HK_OK) {
                    fprintf(stderr, "bench follicles: %s\n", err.message);
                    rc = 1;
                    break;
                }
                best[threads] = fmin(best[threads], hk_seconds_now() - t0);
                count = f.count, iterations = f.iterations;
                hk_follicle_samples_free(&f);
            }
        if (!rc)
            fprintf(out, "  %12.1f %10d %11d %14.3f %14.3f\n", 1e3 * spacings[k], count, iterations, best[1], best[2]);
    }
    fprintf(out, "\n");
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
    return rc;
}
