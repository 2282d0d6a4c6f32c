/* Stability matrix of the strand dynamics (docs/dynamics.md): single strands run as
 * `hairkit strand HAIRSTYLE --simulate T` runs them (root at the origin leaving along +x,
 * no body, O(N) solver with the Gauss-Newton stiffness, released from rest in the natural
 * shape), for the four hair types of Bertails et al. 2006 Appendix B (examples/strand/) cut into N
 * elements of L / N, on a still head and the scripted motions of the CLI's defaults (25
 * degrees or 3 cm at 1 Hz) and examples/motions/nod-and-shake.txt, at dt = 1/24 and 1/30 s,
 * TR-BDF2 and linear Euler side by side. Each cell: whether it ran to the end (or the time
 * of the frame that failed), an energy figure, Newton evaluations per frame and wall time
 * per simulated second. The cells run in parallel (OpenMP) in the order they are printed;
 * each row is printed as soon as it and every row before it are done (a full run takes
 * tens of minutes), with a progress line per cell on stderr, so the output is the same
 * whatever the thread count or the order the cells finish in.
 *
 * A cell that is not done within CELL_CPU_BUDGET seconds of its thread's CPU time gives
 * up at the end of the frame it is in and is reported as such, apart from the cells that
 * failed: an undamped wavy 1.5 m strand's Newton stages stop converging after 0.25 s,
 * are split again and again and solved again with the dense matrix (O(N^3), about 0.3 s
 * a stage at N = 80), and would take hours to reach 10 s. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/dynamics.h"
#include "hairkit/motion.h"
#include "hairkit/statics.h"

typedef struct Strand {
    const char *type; /* examples/strand/TYPE.txt */
    double length;    /* m */
    int n;            /* elements of length / n */
} Strand;

/* wavy at every length, the four types at 25 cm and 1 m */
static const Strand strands[] = {
    {"wavy", 0.05, 5},   {"straight", 0.25, 10}, {"wavy", 0.25, 10},    {"curly", 0.25, 10},
    {"fuzzy", 0.25, 10}, {"wavy", 0.5, 20},      {"straight", 1.0, 40}, {"wavy", 1.0, 40},
    {"curly", 1.0, 40},  {"fuzzy", 1.0, 40},     {"wavy", 1.5, 80},
};
enum { STRAND_COUNT = sizeof strands / sizeof strands[0] };

/* Rows per strand: "still" twice (damped, then undamped), the scripted motions, the file. */
static const char *const motions[] = {"still", "still", "shake", "nod", "tilt", "sway", "jump", "file"};
enum { MOTION_COUNT = sizeof motions / sizeof motions[0], UNDAMPED_ROW = 1 };
static const char *const MOTION_FILE = "examples/motions/nod-and-shake.txt";

/* Seconds of CPU a cell may take (checked between frames, so a cell can pass it by one
 * frame). At dt = 1/24 s every cell up to 1 m, undamped ones included, took less than
 * 70 s (2 December 2026); damped wavy 1.5 m strands under nod and tilt did not: they gave up
 * at t = 5.2 and 7.6 s at dt = 1/24 s (docs/dynamics.md, "Stability matrix"). CPU time,
 * not evaluations, because a dense stage at N = 80 costs a hundred O(N) evaluations; it
 * depends on the machine and its load, so where a cell gives up does too. */
static const double CELL_CPU_BUDGET = 240.0;

static const double dts[2] = {1.0 / 24.0, 1.0 / 30.0};
static const char *const dt_names[2] = {"1/24", "1/30"};

/* In --quick: 1 s, dt = 1/30 s, wavy 25 cm and 1 m, still (both), shake and the file. */
static const int quick_strands[] = {2, 7};
static const int quick_motions[] = {0, 1, 2, 7};

typedef struct StrandRef {
    hk_Hairstyle def; /* the type's file with its HairLengths replaced */
    double rest;      /* the statics minimum of the potential (no body) */
    int ok;
} StrandRef;

typedef struct Cell {
    int strand, motion, dt, integrator;
    /* results */
    int ran;            /* 1: reached the end */
    int gave_up;        /* 1: stopped at gave_up_at, over CELL_CPU_BUDGET (no step failed) */
    double failed_at;   /* start of the frame whose step failed */
    double gave_up_at;  /* end of the last frame done before giving up */
    double energy;      /* still head: worst gain E(t) - E(0) in % of E(0) - rest; else max kinetic (J) */
    double evaluations; /* Newton evaluations per frame */
    double wall;        /* wall seconds per simulated second */
    double cpu;         /* the cell's thread CPU seconds in all */
    long projections;   /* energy guard */
    char error[160];
} Cell;

static double thread_cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void head_state(void *user, double t, hk_RigidState *out) { hk_head_motion_eval(user, t, out); }

/* The hairstyle of a strand and its potential at the statics minimum. */
static int strand_ref(const hk_BenchOptions *options, const Strand *st, StrandRef *ref)
{
    char path[4096];
    hk_Error err;
    hk_SuperHelix *sh = NULL;
    hk_StrandWorkspace *ws = NULL;
    memset(ref, 0, sizeof *ref);
    ref->def = hk_default_hairstyle();
    snprintf(path, sizeof path, "%s/examples/strand/%s.txt", options->root, st->type);
    if (hk_hairstyle_load(path, &ref->def, &err) != HK_OK) goto fail;
    double *lengths = hk_alloc_array((size_t)st->n, sizeof *lengths, &err);
    if (!lengths) goto fail;
    for (int i = 0; i < st->n; i++) lengths[i] = st->length / st->n;
    hk_free(ref->def.strand.element_lengths);
    ref->def.strand.element_lengths = lengths;
    ref->def.strand.element_count = st->n;
    const hk_StrandEnvDef env = hk_default_strand_env_def();
    const hk_StaticsDef opt = hk_default_statics_def();
    hk_MinimizeResult res;
    if (hk_superhelix_from_def(&ref->def.strand, hk_v3(0, 0, 0), hk_v3(1, 0, 0), &sh, &err) != HK_OK ||
        hk_statics_solve(sh, &env, &opt, &res, &err) != HK_OK ||
        hk_strand_workspace_create(sh, &env, &ws, &err) != HK_OK)
        goto fail;
    ref->rest = hk_strand_energy(sh, &env, sh->q, ws, NULL, NULL, NULL);
    ref->ok = 1;
    hk_strand_workspace_destroy(ws);
    hk_superhelix_destroy(sh);
    return 0;
fail:
    fprintf(stderr, "bench stability: %s %.2f m: %s\n", st->type, st->length, err.message);
    hk_strand_workspace_destroy(ws);
    hk_superhelix_destroy(sh);
    return 1;
}

/* One cell, as hk_cli_strand_simulate runs it. */
static void run_cell(const hk_BenchOptions *options, const StrandRef *ref, double duration, Cell *c)
{
    hk_Error err;
    hk_SuperHelix *sh = NULL;
    hk_HeadMotion *motion = NULL;
    hk_StrandDynamics *dyn = NULL;
    const int still = !strcmp(motions[c->motion], "still");
    c->ran = c->gave_up = 0;
    c->failed_at = c->gave_up_at = 0.0;
    c->energy = c->evaluations = c->wall = NAN;
    c->error[0] = '\0';
    hk_DynamicsDef params = ref->def.dynamics;
    if (c->motion == UNDAMPED_ROW) params.internal_friction = params.air_drag = 0.0;
    params.solver = HK_DYNAMICS_LINEAR;
    params.stiffness = HK_STIFFNESS_GAUSS_NEWTON;
    params.integrator = c->integrator ? HK_INTEGRATOR_LINEAR_EULER : HK_INTEGRATOR_TRBDF2;
    hk_Status st;
    if (!strcmp(motions[c->motion], "file")) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", options->root, MOTION_FILE);
        st = hk_head_motion_load(path, &motion, &err);
    } else {
        const int translation = !strcmp(motions[c->motion], "sway") || !strcmp(motions[c->motion], "jump");
        st = hk_head_motion_scripted(motions[c->motion], translation ? 0.03 : 25.0, 1.0, hk_default_head_pivot(),
                                     &motion, &err);
    }
    if (st != HK_OK || hk_superhelix_from_def(&ref->def.strand, hk_v3(0, 0, 0), hk_v3(1, 0, 0), &sh, &err) != HK_OK ||
        hk_strand_dynamics_create(sh, &params, NULL, &dyn, &err) != HK_OK) {
        snprintf(c->error, sizeof c->error, "%.150s", err.message);
        goto done;
    }
    hk_RigidState head;
    hk_head_motion_eval(motion, 0.0, &head);
    hk_strand_dynamics_place(dyn, &head);
    double kinetic, potential;
    hk_strand_dynamics_energy(dyn, &head, &kinetic, &potential);
    const double start = kinetic + potential, available = start - ref->rest;
    double worst = 0.0; /* still: largest E(t) - E(0), t >= 0; moving: largest kinetic */
    const double dt = dts[c->dt];
    const long frames = (long)ceil(duration / dt - 1e-9);
    const double t0 = hk_seconds_now(), cpu0 = thread_cpu();
    double t = 0.0;
    long done_frames = 0;
    for (long i = 0; i < frames; i++) {
        const double next = i == frames - 1 ? duration : (double)(i + 1) * dt;
        if (hk_strand_dynamics_advance(dyn, head_state, motion, t, next - t, NULL, 0, NULL, &err) != HK_OK) {
            c->failed_at = t;
            snprintf(c->error, sizeof c->error, "%.150s", err.message);
            break;
        }
        t = next;
        done_frames++;
        hk_head_motion_eval(motion, t, &head);
        hk_strand_dynamics_energy(dyn, &head, &kinetic, &potential);
        const double e = still ? kinetic + potential - start : kinetic;
        worst = isfinite(e) && isfinite(worst) ? fmax(worst, e) : INFINITY;
        if (i < frames - 1 && thread_cpu() - cpu0 > CELL_CPU_BUDGET) {
            c->gave_up = 1;
            c->gave_up_at = t;
            break;
        }
    }
    const double seconds = hk_seconds_now() - t0;
    c->cpu = thread_cpu() - cpu0;
    const hk_DynamicsStats stats = hk_strand_dynamics_stats(dyn);
    c->ran = done_frames == frames;
    c->energy = still ? 100.0 * worst / available : worst;
    c->evaluations = (double)stats.iterations / (double)(done_frames + (!c->ran && !c->gave_up));
    c->wall = t > 0.0 ? seconds / t : NAN;
    c->projections = stats.projections;
done:
    hk_strand_dynamics_destroy(dyn);
    hk_superhelix_destroy(sh);
    hk_head_motion_destroy(motion);
}

static void print_cell(FILE *out, const Cell *c)
{
    char result[32], energy[32];
    if (c->ran)
        snprintf(result, sizeof result, "ran");
    else if (c->gave_up)
        snprintf(result, sizeof result, "GAVE@%.2fs", c->gave_up_at);
    else if (c->error[0] && isnan(c->evaluations))
        snprintf(result, sizeof result, "error");
    else
        snprintf(result, sizeof result, "FAIL@%.2fs", c->failed_at);
    const int still = !strcmp(motions[c->motion], "still");
    if (isnan(c->energy))
        snprintf(energy, sizeof energy, "-");
    else if (still)
        snprintf(energy, sizeof energy, fabs(c->energy) < 1e5 ? "%+.2f%%" : "%+.2e%%", c->energy);
    else
        snprintf(energy, sizeof energy, "%.3g uJ", 1e6 * c->energy);
    char guard[16] = "-";
    if (still && !isnan(c->evaluations)) snprintf(guard, sizeof guard, "%ld", c->projections);
    fprintf(out, "   %-10s %11s %6.1f %8.1f %5s", result, energy, c->evaluations, 1e3 * c->wall, guard);
}

/* Which cells a run holds: all, or the few of --quick. */
typedef struct Layout {
    int quick, strand_count, motion_count, dt_count, dt_first, count;
    double duration;
} Layout;

static const Strand *layout_strand(const Layout *l, int k) { return &strands[l->quick ? quick_strands[k] : k]; }
static int layout_motion(const Layout *l, int m) { return l->quick ? quick_motions[m] : m; }

static void print_legend(FILE *out, const Layout *l)
{
    fprintf(out,
            "dynamics stability: one strand as `hairkit strand TYPE.txt --simulate %g` runs it (root at the origin\n"
            "along +x, no body, O(N) solver, from rest in its natural shape), examples/strand/TYPE.txt cut into N\n"
            "elements of L/N; damping on (the hairstyle's) except the row `still, undamped`; motions at the CLI's\n"
            "defaults (25 degrees or 3 cm at 1 Hz) and `file` = %s.\n"
            "  result   ran to %g s, or FAIL@t: the step of the frame from t failed even split (error: no start),\n"
            "           or GAVE@t: gave up at t, no step failed but the cell took more than %.0f s of CPU\n"
            "  energy   still head: worst gain max_t E(t) - E(0) (kinetic + elastic + gravity, at frame ends) in %%\n"
            "           of E(0) - E_rest, E_rest the statics minimum (hk_statics_solve, no body); 0 = never above\n"
            "           the start. moving head: the energy is not conserved; max kinetic energy (absolute, uJ)\n"
            "  eval/f   Newton evaluations (force evaluations and solves) per frame, splits included\n"
            "  ms/s     wall milliseconds per simulated second (cells run %d at a time)\n"
            "  guard    still head: steps whose energy excess the TR-BDF2 energy guard took back (Euler: none)\n",
            l->duration, MOTION_FILE, l->duration, CELL_CPU_BUDGET, omp_get_max_threads());
}

/* Row r of the table (both integrators of one dt, strand and motion: cells 2r, 2r + 1),
 * with the dt's heading before its first row. */
static void print_row(FILE *out, const Layout *l, const Cell *cells, int row)
{
    const int per_dt = l->strand_count * l->motion_count;
    const int d = row / per_dt, k = row / l->motion_count % l->strand_count, m = row % l->motion_count;
    if (row % per_dt == 0)
        fprintf(out,
                "\n  dt = %s s                        TR-BDF2 (default)                          linear Euler\n"
                "  type      L       N   motion             result          energy eval/f     ms/s guard"
                "   result          energy eval/f     ms/s guard\n",
                dt_names[l->dt_first + d]);
    const Strand *st = layout_strand(l, k);
    const int motion = layout_motion(l, m);
    char len[16], n[8] = "";
    snprintf(len, sizeof len, st->length < 1.0 ? "%.0f cm" : "%.1f m",
             st->length < 1.0 ? 100 * st->length : st->length);
    if (m == 0) snprintf(n, sizeof n, "%d", st->n);
    fprintf(out, "  %-9s %-7s %3s   %-17s", m == 0 ? st->type : "", m == 0 ? len : "", n,
            motion == UNDAMPED_ROW             ? "still, undamped"
            : !strcmp(motions[motion], "file") ? "nod-and-shake.txt"
                                               : motions[motion]);
    for (int g = 0; g < 2; g++) {
        Cell shown = cells[2 * row + g];
        shown.motion = motion;
        print_cell(out, &shown);
    }
    fputc('\n', out);
    fflush(out);
}

/* Progress on stderr: the cell just done, how many are, and the time so far. */
static void print_progress(const Layout *l, const Cell *c, int done, double elapsed)
{
    const Strand *st = layout_strand(l, c->strand);
    const int motion = layout_motion(l, c->motion);
    char result[48];
    if (c->ran)
        snprintf(result, sizeof result, "ran");
    else if (c->gave_up)
        snprintf(result, sizeof result, "gave up at t = %.2f s", c->gave_up_at);
    else if (isnan(c->evaluations))
        snprintf(result, sizeof result, "error");
    else
        snprintf(result, sizeof result, "failed at t = %.2f s", c->failed_at);
    fprintf(stderr, "bench stability: %3d/%d done, %4.0f s: %s %.2f m %s dt %s %s: %s (%.1f s CPU)\n", done, l->count,
            elapsed, st->type, st->length, motion == UNDAMPED_ROW ? "still undamped" : motions[motion], dt_names[c->dt],
            c->integrator ? "Euler" : "TR-BDF2", result, c->cpu);
}

/* The hairstyles of the layout's strands; 0 on success. */
static int load_refs(const hk_BenchOptions *options, const Layout *l, StrandRef *refs)
{
    int failed = 0;
    for (int k = 0; k < l->strand_count; k++) memset(&refs[k], 0, sizeof refs[k]);
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : failed)
    for (int k = 0; k < l->strand_count; k++) failed += strand_ref(options, layout_strand(l, k), &refs[k]);
    return failed;
}

/* Runs every cell, printing each row once it and the rows before it are done. */
static void run_cells(FILE *out, const hk_BenchOptions *options, const Layout *l, const StrandRef *refs, Cell *cells,
                      unsigned char *done, double t_start)
{
    int finished = 0, printed = 0; /* cells done; rows printed */
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < l->count; i++) {
        Cell run = cells[i];
        run.motion = layout_motion(l, cells[i].motion);
        run_cell(options, &refs[run.strand], l->duration, &run);
        run.motion = cells[i].motion;
#pragma omp critical(hk_bench_stability_print)
        {
            cells[i] = run;
            done[i] = 1;
            print_progress(l, &cells[i], ++finished, hk_seconds_now() - t_start);
            while (2 * printed + 1 < l->count && done[2 * printed] && done[2 * printed + 1])
                print_row(out, l, cells, printed++);
        }
    }
}

int hk_bench_stability(FILE *out, const hk_BenchOptions *options)
{
    Layout l = {.quick = options->quick, .duration = options->quick ? 1.0 : 10.0};
    l.strand_count = l.quick ? (int)(sizeof quick_strands / sizeof *quick_strands) : STRAND_COUNT;
    l.motion_count = l.quick ? (int)(sizeof quick_motions / sizeof *quick_motions) : MOTION_COUNT;
    l.dt_count = l.quick ? 1 : 2;
    l.dt_first = l.quick ? 1 : 0;
    l.count = l.dt_count * l.strand_count * l.motion_count * 2;
    const double t_start = hk_seconds_now();

    StrandRef refs[STRAND_COUNT];
    if (load_refs(options, &l, refs)) {
        for (int k = 0; k < l.strand_count; k++) hk_hairstyle_free(&refs[k].def);
        fprintf(stderr, "bench stability: run from the source folder or give --root\n");
        return 1;
    }
    hk_Error err;
    Cell *cells = hk_calloc_array((size_t)l.count, sizeof *cells, &err);
    unsigned char *done = cells ? hk_calloc_array((size_t)l.count, 1, &err) : NULL;
    if (!done) {
        hk_free(cells);
        for (int k = 0; k < l.strand_count; k++) hk_hairstyle_free(&refs[k].def);
        fprintf(stderr, "bench stability: %s\n", err.message);
        return 1;
    }
    /* cells in print order: dt, strand, motion, integrator (indices into the layout) */
    for (int i = 0; i < l.count; i++) {
        Cell *c = &cells[i];
        c->integrator = i % 2;
        c->motion = i / 2 % l.motion_count;
        c->strand = i / (2 * l.motion_count) % l.strand_count;
        c->dt = l.dt_first + i / (2 * l.motion_count * l.strand_count);
    }
    print_legend(out, &l);
    fflush(out);
    run_cells(out, options, &l, refs, cells, done, t_start);

    int failures = 0, gave_up = 0, errors = 0;
    double cpu = 0.0;
    for (int i = 0; i < l.count; i++) {
        cpu += cells[i].cpu;
        failures += !cells[i].ran && !cells[i].gave_up;
        gave_up += cells[i].gave_up;
        errors += !cells[i].ran && isnan(cells[i].evaluations);
    }
    fprintf(out,
            "\n  %d of %d cells did not run to the end (%d failed, %d gave up over the budget of %.0f s CPU); %.0f s\n"
            "  wall in all with %d threads, the cells' stepping %.0f s of CPU (ms/s is wall: on a loaded machine it\n"
            "  exceeds the CPU time)\n",
            failures + gave_up, l.count, failures, gave_up, CELL_CPU_BUDGET, hk_seconds_now() - t_start,
            omp_get_max_threads(), cpu);
    for (int i = 0; i < l.count; i++)
        if (!cells[i].ran && isnan(cells[i].evaluations)) fprintf(stderr, "bench stability: %s\n", cells[i].error);
    for (int k = 0; k < l.strand_count; k++) hk_hairstyle_free(&refs[k].def);
    hk_free(done);
    hk_free(cells);
    return errors ? 1 : 0;
}
