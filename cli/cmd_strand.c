/* hairkit strand: the rest shape of one Super-Helix strand (statics, Bertails et al. 2006 §3 and
 * Lansink 2010 §4.1.1-4.1.3) printed as CSV samples along its arc length. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/core_internal.h"
#include "hairkit/canvas.h"
#include "hairkit/io.h"
#include "hairkit/statics.h"

static const char *const CMD = "strand";

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit strand HAIRSTYLE.txt [--collision FILE] [--root X,Y,Z] [--dir X,Y,Z]\n"
                 "                      [--plot FILE.png] [--simulate T [--dt DT]] [options]\n"
                 "\n"
                 "Finds the rest shape of one hair strand (a Super-Helix) under gravity and\n"
                 "collision penalties by minimising its energy, and prints it.\n"
                 "\n"
                 "options:\n"
                 "  --collision FILE   collision shapes (thesis Collision Info file)\n"
                 "  --root X,Y,Z       root position in metres (default 0,0,0)\n"
                 "  --dir X,Y,Z        direction in which the strand leaves the root (default 1,0,0)\n"
                 "  --solver NAME      newton (default: analytic gradient and Hessian) or\n"
                 "                     rosenbrock (the thesis's direct search, MaxIter/Epsilon)\n"
                 "  --envelope A       envelope level of this strand in [0,1] (thesis 4.1.2.2:\n"
                 "                     0 lowest follicle, 1 highest; default 0)\n"
                 "  --plot FILE.png    also draw side and front views of the strand and shapes\n"
                 "  --quiet            no summary on stderr\n"
                 "  -h, --help         this help\n"
                 "\n"
                 "dynamics (Bertails et al. 2006, 3.3-3.4): instead of the rest shape, the\n"
                 "strand's motion from rest in its natural shape, under gravity, friction and\n"
                 "the head's motion\n"
                 "  --simulate T       simulated time in seconds\n"
                 "  --dt DT            time step in seconds (default 1/30, the paper's)\n"
                 "  --damping on|off   internal friction and air drag (InternalFriction, AirDrag\n"
                 "                     of the hairstyle file; default on)\n"
                 "  --dynamics-solver linear|dense\n"
                 "                     matrix of Newton's iteration: the O(N) recursion with the\n"
                 "                     elastic and Gauss-Newton contact stiffness (default), or\n"
                 "                     dense Cholesky with the full stiffness\n"
                 "  --integrator trbdf2|euler\n"
                 "                     TR-BDF2, second order with every force implicit (default),\n"
                 "                     or the linearly implicit Euler step of Bertails et al.\n"
                 "                     2006, 3.4 (cheaper, first order, unstable for long hair at 1/30 s)\n"
                 "  --tip-csv FILE     write t,x,y,z of the tip at every step\n");
    hk_cli_motion_options_help(out);
    fprintf(out, "\n"
                 "output (stdout):\n"
                 "  # energy=<J> iterations=<n> evaluations=<n> solver=<name>\n"
                 "  s,x,y,z            one row every VisualityStep from the root, the tip last\n"
                 "with --simulate, energy is the total (kinetic + elastic + gravity) at time T,\n"
                 "iterations counts the steps of DT, evaluations the evaluations of the forces\n"
                 "(Newton iterations, with the splits of fast motion), and the solver is\n"
                 "dynamics-linear or dynamics-dense.\n");
    HK_CLI_EXAMPLES(out, "# a curly strand over the head's ellipsoid, drawn from the side and the front",
                    "hairkit strand examples/strand/curly.txt --collision examples/strand/head.txt --root "
                    "0.04,0.137,0.03 --dir 1,0.6,0.3 --plot strand.png",
                    "hairkit strand examples/strand/straight.txt --solver rosenbrock",
                    "# 2 s of motion from rest on a nodding head, the tip's path in a CSV",
                    "hairkit strand examples/strand/wavy.txt --simulate 2 --motion nod --tip-csv tip.csv");
}

typedef struct StrandArgs {
    const char *hairstyle, *collision, *plot;
    hk_Vec3 root, dir;
    hk_SolverKind solver;
    double envelope;
    int quiet;
    hk_CliStrandSim sim;
} StrandArgs;

static int parse_args(int argc, char **argv, StrandArgs *a)
{
    enum {
        OPT_COLLISION = 1000,
        OPT_ROOT,
        OPT_DIR,
        OPT_SOLVER,
        OPT_ENVELOPE,
        OPT_PLOT,
        OPT_QUIET,
        OPT_SIMULATE,
        OPT_DT,
        OPT_DAMPING,
        OPT_DYN_SOLVER,
        OPT_TIP_CSV,
        OPT_INTEGRATOR
    };
    static const struct option options[] = {
        {"simulate", required_argument, NULL, OPT_SIMULATE},
        {"dt", required_argument, NULL, OPT_DT},
        {"damping", required_argument, NULL, OPT_DAMPING},
        {"dynamics-solver", required_argument, NULL, OPT_DYN_SOLVER},
        {"integrator", required_argument, NULL, OPT_INTEGRATOR},
        {"tip-csv", required_argument, NULL, OPT_TIP_CSV},
        HK_CLI_MOTION_LONG_OPTIONS,
        {"collision", required_argument, NULL, OPT_COLLISION},
        {"root", required_argument, NULL, OPT_ROOT},
        {"dir", required_argument, NULL, OPT_DIR},
        {"solver", required_argument, NULL, OPT_SOLVER},
        {"envelope", required_argument, NULL, OPT_ENVELOPE},
        {"plot", required_argument, NULL, OPT_PLOT},
        {"quiet", no_argument, NULL, OPT_QUIET},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    *a = (StrandArgs){NULL, NULL, NULL, {0, 0, 0}, {1, 0, 0}, HK_SOLVER_NEWTON, 0.0, 0, hk_cli_default_strand_sim()};
    optind = 1;
    opterr = 0;
    int c, dynamics_option = 0;
    while ((c = getopt_long(argc, argv, ":h", options, NULL)) != -1) {
        if (HK_CLI_IS_MOTION_OPTION(c)) {
            int rc = hk_cli_motion_option(CMD, c, optarg, &a->sim.motion);
            if (rc) return rc;
            dynamics_option = 1;
            continue;
        }
        switch (c) {
        case OPT_SIMULATE:
            if (!hk_cli_parse_double(optarg, &a->sim.duration) || !(a->sim.duration > 0.0) || a->sim.duration > 1e5)
                return hk_cli_usage_error(CMD, "--simulate expects a time in (0, 1e5] s, got '%s'", optarg);
            a->sim.enabled = 1;
            break;
        case OPT_DT:
            if (!hk_cli_parse_double(optarg, &a->sim.dt) || !(a->sim.dt > 0.0) || a->sim.dt > 1.0)
                return hk_cli_usage_error(CMD, "--dt expects a time step in (0, 1] s, got '%s'", optarg);
            dynamics_option = 1;
            break;
        case OPT_DAMPING:
            if (strcmp(optarg, "on") != 0 && strcmp(optarg, "off") != 0)
                return hk_cli_usage_error(CMD, "--damping must be on or off, got '%s'", optarg);
            a->sim.damping = strcmp(optarg, "on") == 0;
            dynamics_option = 1;
            break;
        case OPT_DYN_SOLVER:
            if (strcmp(optarg, "linear") != 0 && strcmp(optarg, "dense") != 0)
                return hk_cli_usage_error(CMD, "--dynamics-solver must be linear or dense, got '%s'", optarg);
            a->sim.dense = strcmp(optarg, "dense") == 0;
            break;
        case OPT_INTEGRATOR:
            if (strcmp(optarg, "trbdf2") != 0 && strcmp(optarg, "euler") != 0)
                return hk_cli_usage_error(CMD, "--integrator must be trbdf2 or euler, got '%s'", optarg);
            a->sim.euler = strcmp(optarg, "euler") == 0;
            dynamics_option = 1;
            break;
        case OPT_TIP_CSV:
            a->sim.tip_csv = optarg;
            dynamics_option = 1;
            break;
        case OPT_COLLISION:
            a->collision = optarg;
            break;
        case OPT_PLOT:
            a->plot = optarg;
            break;
        case OPT_QUIET:
            a->quiet = 1;
            break;
        case OPT_ROOT:
            if (!hk_cli_parse_vec3(optarg, &a->root))
                return hk_cli_usage_error(CMD, "--root expects X,Y,Z (three numbers), got '%s'", optarg);
            break;
        case OPT_DIR:
            if (!hk_cli_parse_vec3(optarg, &a->dir) || hk_v3_norm(a->dir) == 0.0)
                return hk_cli_usage_error(CMD, "--dir expects a non-zero X,Y,Z, got '%s'", optarg);
            break;
        case OPT_SOLVER: {
            int s = hk_solver_from_name(optarg);
            if (s < 0) return hk_cli_usage_error(CMD, "--solver must be newton or rosenbrock, got '%s'", optarg);
            a->solver = (hk_SolverKind)s;
            break;
        }
        case OPT_ENVELOPE:
            if (!hk_cli_parse_double(optarg, &a->envelope) || a->envelope < 0.0 || a->envelope > 1.0)
                return hk_cli_usage_error(CMD, "--envelope expects a number in [0, 1], got '%s'", optarg);
            break;
        case 'h':
            usage(stdout);
            return -1;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    if (dynamics_option && !a->sim.enabled)
        return hk_cli_usage_error(CMD, "--dt, --damping, --tip-csv and the motion options need --simulate T");
    if (a->sim.enabled && a->sim.duration / a->sim.dt > 1e8)
        return hk_cli_usage_error(CMD, "--simulate %g with --dt %g is more than 1e8 steps", a->sim.duration, a->sim.dt);
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, "missing HAIRSTYLE file");
    if (operand_rc) return operand_rc;
    a->hairstyle = argv[optind];
    int rc;
    if (a->plot && (rc = hk_cli_output_file(CMD, "--plot", a->plot, ".png"))) return rc;
    if (a->sim.tip_csv && (rc = hk_cli_output_file(CMD, "--tip-csv", a->sim.tip_csv, NULL))) return rc;
    return 0;
}

/* Writes the sampled strand to stdout in the format of the command-line contract. */
static void print_strand(const hk_MinimizeResult *res, hk_SolverKind solver, double energy, int count, const double *s,
                         const hk_Vec3 *p)
{
    printf("# energy=%.10e iterations=%d evaluations=%ld solver=%s\n", energy, res->iterations, res->evaluations,
           hk_solver_name(solver));
    printf("s,x,y,z\n");
    for (int j = 0; j < count; j++) printf("%.10g,%.10g,%.10g,%.10g\n", s[j], p[j].x, p[j].y, p[j].z);
}

int hk_cmd_strand(int argc, char **argv)
{
    StrandArgs a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc < 0 ? HK_EXIT_OK : rc;

    hk_Error err;
    hk_Hairstyle def;
    hk_CollisionSet collision = {0};
    hk_SuperHelix *sh = NULL;
    hk_StrandWorkspace *ws = NULL;
    double *s = NULL;
    hk_Vec3 *p = NULL;
    int status = HK_EXIT_FAIL;

    if (hk_hairstyle_load(a.hairstyle, &def, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    if (a.collision && hk_collision_load(a.collision, &collision, &err) != HK_OK) {
        hk_cli_fail(CMD, &err);
        goto done;
    }
    if (hk_superhelix_from_def(&def.strand, a.root, a.dir, &sh, &err) != HK_OK) {
        hk_cli_fail(CMD, &err);
        goto done;
    }
    hk_StrandEnvDef env = hk_default_strand_env_def();
    env.shapes = collision.shapes;
    env.shape_count = collision.count;
    env.envelope_alpha = a.envelope;
    env.collision_step = def.strand.collision_step;

    if (a.sim.enabled) {
        a.sim.quiet = a.quiet;
        status = hk_cli_strand_simulate(CMD, &a.sim, &def, sh, &env, a.plot, collision.shapes, collision.count);
        goto done;
    }

    hk_StaticsDef opt = hk_default_statics_def();
    opt.solver = a.solver;
    opt.rosenbrock = hk_rosenbrock_def_for(&def.strand);
    hk_MinimizeResult res;
    const double t0 = hk_seconds_now();
    if (hk_statics_solve(sh, &env, &opt, &res, &err) != HK_OK) {
        hk_cli_fail(CMD, &err);
        goto done;
    }
    const double seconds = hk_seconds_now() - t0;
    if (hk_strand_workspace_create(sh, &env, &ws, &err) != HK_OK) {
        hk_cli_fail(CMD, &err);
        goto done;
    }
    const double energy = hk_strand_energy(sh, &env, sh->q, ws, NULL, NULL, NULL);

    const int count = hk_superhelix_sample_count(sh, def.strand.visuality_step);
    s = hk_alloc_array((size_t)count, sizeof *s, &err);
    p = hk_alloc_array((size_t)count, sizeof *p, &err);
    if (!s || !p) {
        hk_cli_fail(CMD, &err);
        goto done;
    }
    hk_superhelix_sample(sh, NULL, def.strand.visuality_step, s, p, NULL);
    if (a.plot) {
        hk_PlotStrand ps = {p, count, {0.45, 0.22, 0.05}};
        if (hk_plot_strands_png(a.plot, 1200, 600, &ps, 1, collision.shapes, collision.count, a.envelope, &err) !=
            HK_OK) {
            hk_cli_fail(CMD, &err);
            goto done;
        }
    }
    print_strand(&res, a.solver, energy, count, s, p);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "hairkit strand: cannot write to standard output\n");
        goto done;
    }
    if (!a.quiet && hk_cli_stderr_is_tty()) {
        fprintf(stderr, "hairkit strand: %d elements, L = %.4g m, %s: %d iterations, %ld evaluations, %.3g ms%s\n",
                sh->n, sh->total_length, hk_solver_name(a.solver), res.iterations, res.evaluations, 1e3 * seconds,
                res.converged ? "" : " (stopped by its limit before converging)");
        if (collision.count > 0)
            fprintf(stderr, "hairkit strand: deepest collision sample %.3g m inside the envelopes\n",
                    hk_strand_max_penetration(sh, &env, sh->q, ws));
    }
    status = HK_EXIT_OK;
done:
    hk_free(s);
    hk_free(p);
    hk_strand_workspace_destroy(ws);
    hk_superhelix_destroy(sh);
    hk_collision_free(&collision);
    hk_hairstyle_free(&def);
    return status;
}
