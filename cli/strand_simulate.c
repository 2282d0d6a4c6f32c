/* hairkit strand --simulate: the motion of one strand from rest in its natural shape
 * (Bertails et al. 2006 §3.3-3.4), printed in the strand command's format at the final time. */
#include <math.h>
#include <stdio.h>

#include "cli.h"
#include "core/core_internal.h"
#include "hairkit/canvas.h"
#include "hairkit/dynamics.h"
#include "hairkit/motion.h"
#include "io/outfile.h"

hk_CliStrandSim hk_cli_default_strand_sim(void)
{
    hk_CliStrandSim s = {0, 0.0, 1.0 / 30.0, 1, 0, 0, 0, NULL, hk_cli_default_motion()};
    return s;
}

static void head_state(void *user, double t, hk_RigidState *out) { hk_head_motion_eval(user, t, out); }

static int write_tip(FILE *fp, double t, const hk_SuperHelix *sh)
{
    hk_Vec3 tip;
    hk_superhelix_eval(sh, NULL, sh->total_length, &tip, NULL);
    return fprintf(fp, "%.10g,%.10g,%.10g,%.10g\n", t, tip.x, tip.y, tip.z) > 0;
}

int hk_cli_strand_simulate(const char *cmd, const hk_CliStrandSim *sim, const hk_Hairstyle *def, hk_SuperHelix *sh,
                           const hk_StrandEnvDef *env, const char *plot, const hk_Shape *shapes, int shape_count)
{
    hk_Error err;
    hk_HeadMotion *motion = NULL;
    hk_StrandDynamics *dyn = NULL;
    hk_OutFile tip = {NULL, NULL, NULL};
    double *s = NULL;
    hk_Vec3 *p = NULL;
    int status = HK_EXIT_FAIL;

    hk_DynamicsDef params = def->dynamics;
    if (!sim->damping) params.internal_friction = params.air_drag = 0.0;
    params.solver = sim->dense ? HK_DYNAMICS_DENSE : HK_DYNAMICS_LINEAR;
    params.stiffness = sim->dense ? HK_STIFFNESS_FULL : HK_STIFFNESS_GAUSS_NEWTON;
    params.integrator = sim->euler ? HK_INTEGRATOR_LINEAR_EULER : HK_INTEGRATOR_TRBDF2;
    if (hk_cli_motion_create(&sim->motion, &motion, &err) != HK_OK ||
        hk_strand_dynamics_create(sh, &params, env, &dyn, &err) != HK_OK ||
        (sim->tip_csv && hk_outfile_open(&tip, sim->tip_csv, &err) != HK_OK)) {
        hk_cli_fail(cmd, &err);
        goto done;
    }
    if (!sim->quiet && env->shape_count > 0) {
        /* The natural shape inside an envelope starts far from equilibrium: the penalty
         * then throws the strand out violently (a groomed head starts from its statics). */
        const double depth = /* sh->root is still in head space, where the shapes are */
            hk_collision_depth(env->shapes, env->shape_count, env->envelope_alpha, sh->root);
        if (depth > 1e-3)
            fprintf(stderr,
                    "hairkit %s: warning: the root lies %.3g m inside the collision envelopes; the strand "
                    "starts far from equilibrium\n",
                    cmd, depth);
    }
    hk_RigidState head;
    hk_head_motion_eval(motion, 0.0, &head);
    hk_strand_dynamics_place(dyn, &head);
    if (tip.fp && (fprintf(tip.fp, "t,x,y,z\n") < 0 || !write_tip(tip.fp, 0.0, sh))) goto write_error;

    /* Fixed steps of dt; the last one is shortened so that the run ends at T. */
    const long steps = (long)ceil(sim->duration / sim->dt - 1e-9);
    hk_CliProgress progress = {!sim->quiet && hk_cli_stderr_is_tty(), "simulate", -1};
    const double t0 = hk_seconds_now();
    double t = 0.0;
    long substeps = 0;
    for (long i = 0; i < steps; i++) {
        const double next = i == steps - 1 ? sim->duration : (double)(i + 1) * sim->dt;
        int taken = 0;
        if (hk_strand_dynamics_advance(dyn, head_state, motion, t, next - t, NULL, 0, &taken, &err) != HK_OK) {
            fprintf(stderr, "hairkit %s: at t = %.6g s: %s\n", cmd, t, err.message);
            goto done;
        }
        substeps += taken;
        t = next;
        hk_head_motion_eval(motion, t, &head);
        if (tip.fp && !write_tip(tip.fp, t, sh)) goto write_error;
        if (progress.enabled && (i & 63) == 0) hk_cli_progress(&progress, "simulate", (double)i / steps);
    }
    hk_cli_progress_done(&progress);
    const double seconds = hk_seconds_now() - t0;
    if (tip.fp && hk_outfile_commit(&tip, &err) != HK_OK) {
        hk_cli_fail(cmd, &err);
        goto done;
    }

    double kinetic, potential;
    hk_strand_dynamics_energy(dyn, &head, &kinetic, &potential);
    const int count = hk_superhelix_sample_count(sh, def->strand.visuality_step);
    s = hk_alloc_array((size_t)count, sizeof *s, &err);
    p = hk_alloc_array((size_t)count, sizeof *p, &err);
    if (!s || !p) {
        hk_cli_fail(cmd, &err);
        goto done;
    }
    hk_superhelix_sample(sh, NULL, def->strand.visuality_step, s, p, NULL);
    if (plot) {
        hk_PlotStrand ps = {p, count, {0.45, 0.22, 0.05}};
        if (hk_plot_strands_png(plot, 1200, 600, &ps, 1, shapes, shape_count, env->envelope_alpha, &err) != HK_OK) {
            hk_cli_fail(cmd, &err);
            goto done;
        }
    }
    const hk_DynamicsStats stats = hk_strand_dynamics_stats(dyn);
    printf("# energy=%.10e iterations=%ld evaluations=%ld solver=%s\n", kinetic + potential, steps, stats.iterations,
           sim->dense ? "dynamics-dense" : "dynamics-linear");
    printf("s,x,y,z\n");
    for (int j = 0; j < count; j++) printf("%.10g,%.10g,%.10g,%.10g\n", s[j], p[j].x, p[j].y, p[j].z);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "hairkit %s: cannot write to standard output\n", cmd);
        goto done;
    }
    if (!sim->quiet && hk_cli_stderr_is_tty())
        fprintf(stderr,
                "hairkit %s: %d elements, %ld steps of %.4g s (%ld with the splits of fast motion) in "
                "%.3g s (%.0f steps/s); kinetic %.3g J, potential %.3g J\n",
                cmd, sh->n, steps, sim->dt, substeps, seconds, substeps / fmax(seconds, 1e-9), kinetic, potential);
    status = HK_EXIT_OK;
    goto done;
write_error:
    fprintf(stderr, "hairkit %s: cannot write %s\n", cmd, sim->tip_csv);
done:
    hk_outfile_abort(&tip);
    hk_free(s);
    hk_free(p);
    hk_strand_dynamics_destroy(dyn);
    hk_head_motion_destroy(motion);
    return status;
}
