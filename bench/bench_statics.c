/* Benchmark of Super-Helix statics: the Newton solver (analytic gradient and Hessian)
 * against the thesis's Rosenbrock + Palmer search (Lansink 2010 §4.1.3), on the same
 * curly strand resting on an ellipsoidal head, for N = 5, 10, 20, 40 elements. */
#include <math.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/statics.h"

typedef struct Run {
    double seconds; /* per solve */
    double energy;
    hk_MinimizeResult result;
    int ok;
} Run;

/* Solves repeatedly from the natural shape until min_seconds have passed. */
static Run measure(hk_SuperHelix *sh, const hk_StrandEnvDef *env, const hk_StaticsDef *opt, double min_seconds,
                   int max_reps)
{
    Run run = {0, 0, {0, 0, 0, 0}, 0};
    const int dim = 3 * sh->n;
    int reps = 0;
    const double t0 = hk_seconds_now();
    double elapsed = 0.0;
    do {
        memcpy(sh->q, sh->q_rest, (size_t)dim * sizeof(double));
        hk_Error err;
        if (hk_statics_solve(sh, env, opt, &run.result, &err) != HK_OK) {
            fprintf(stderr, "bench statics: %s\n", err.message);
            return run;
        }
        reps++;
        elapsed = hk_seconds_now() - t0;
    } while (elapsed < min_seconds && reps < max_reps);
    run.seconds = elapsed / reps;
    hk_StrandWorkspace *ws;
    hk_Error err;
    if (hk_strand_workspace_create(sh, env, &ws, &err) != HK_OK) return run;
    run.energy = hk_strand_energy(sh, env, sh->q, ws, NULL, NULL, NULL);
    hk_strand_workspace_destroy(ws);
    run.ok = 1;
    return run;
}

static void print_run(FILE *out, int n, const char *name, const Run *r)
{
    fprintf(out, "  %3d  %-26s %12.4f %18.10e %8d %11ld  %s\n", n, name, 1e3 * r->seconds, r->energy,
            r->result.iterations, r->result.evaluations, r->result.converged ? "yes" : "no (limit)");
}

int hk_bench_statics(FILE *out, const hk_BenchOptions *options)
{
    /* Caucasian curly hair of Bertails et al. 2006 Appendix B: mean radius 50 um, ellipticity 1.1,
     * helix radius 0.6 cm and step 0.5 cm, E = 1.5 GPa; 20 cm long, rooted on the crown
     * of a head-sized ellipsoid with a 5 mm envelope, thesis penalty k = 10. */
    const double length = 0.2, a = 50e-6 * 2.0 * 1.1 / 2.1, b = 50e-6 * 2.0 / 2.1;
    const hk_Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const hk_Shape head = hk_shape_ellipsoid(hk_v3(0, 0, 0), hk_v3(0.08, 0.11, 0.09), axes, 0.005, 10.0);
    hk_StrandEnvDef env = hk_default_strand_env_def();
    env.shapes = &head;
    env.shape_count = 1;
    env.envelope_alpha = 1.0;
    env.collision_step = 0.005;
    double tau, kappa;
    hk_helix_natural_curvature(0.006, 0.005, &tau, &kappa);

    fprintf(out,
            "statics: curly strand (r_h 6 mm, step 5 mm), L = %.2f m, resting on an ellipsoid head,\n"
            "collision step 5 mm; one core; time per solve from the natural shape\n"
            "    N  solver                     time (ms)        energy (J)    iters evaluations  converged\n",
            length);
    const int sizes[] = {5, 10, 20, 40};
    int rc = 0;
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        const int n = sizes[k];
        double len[40];
        for (int i = 0; i < n; i++) len[i] = length / n;
        hk_SuperHelix *sh;
        hk_Error err;
        if (hk_superhelix_create(n, len, &sh, &err) != HK_OK) return 1;
        sh->material = hk_rod_material(a, b, 1.5e9, 0.48, 1300.0, hk_v3(0, -9.81, 0));
        sh->root = hk_v3(0.0, 0.116, 0.0);
        sh->root_frame = hk_root_frame(hk_v3(0.0, 0.2, 1.0));
        hk_superhelix_set_uniform_rest(sh, tau, kappa, 0.0);

        hk_StaticsDef newton = hk_default_statics_def();
        hk_StaticsDef thesis = hk_default_statics_def();
        thesis.solver = HK_SOLVER_ROSENBROCK;
        thesis.rosenbrock.max_stages = 20; /* the thesis's MaxIter and Epsilon (Appendix C) */
        thesis.rosenbrock.epsilon = 1e-4;
        thesis.rosenbrock.initial_step = 1.0 / length;
        hk_StaticsDef converged = thesis;
        converged.rosenbrock.max_stages = 1000000;
        converged.rosenbrock.epsilon = 1e-12;
        converged.rosenbrock.max_evaluations = options->quick ? 20000 : 4000000;

        const double mt = options->min_seconds;
        Run rn = measure(sh, &env, &newton, mt, options->quick ? 1 : 100000);
        Run rt = measure(sh, &env, &thesis, mt, options->quick ? 1 : 1000);
        Run rc_ = measure(sh, &env, &converged, 0.0, 1);
        if (!rn.ok || !rt.ok || !rc_.ok) rc = 1;
        print_run(out, n, "rosenbrock (MaxIter 20)", &rt);
        print_run(out, n, "rosenbrock (to 1e-12)", &rc_);
        print_run(out, n, "newton", &rn);
        fprintf(out, "       newton is %.0fx faster than rosenbrock (MaxIter 20), energy %s by %.3g J;\n",
                rt.seconds / rn.seconds, rn.energy <= rt.energy ? "lower" : "HIGHER", fabs(rt.energy - rn.energy));
        fprintf(out, "       %.0fx faster than rosenbrock run to 1e-12, energy %s by %.3g J\n",
                rc_.seconds / rn.seconds, rn.energy <= rc_.energy ? "lower" : "HIGHER", fabs(rc_.energy - rn.energy));
        hk_superhelix_destroy(sh);
    }
    fprintf(out, "targets: newton >= 20x faster than rosenbrock at equal or lower energy; N = 10 under 0.2 ms\n\n");
    return rc;
}
