/* Long guides on a full head (issue 12: "full heads with 1 m guides ... run 10 s at dt
 * 1/24 and 1/30 under still, shake, nod, tilt, sway, jump and the motion file, with no
 * failure"; docs/dynamics.md, "Long guides on a head"). The 201 guides of
 * examples/guides200 grown 1 m in 20 elements of 5 cm, stepped as `hairkit simulate`
 * steps them (hk_hair_sim_def_for), with body and guide-guide contacts, settle
 * 1 s on the still head and then follow each motion for 10 s in frames of dt. Each row:
 * whether every frame advanced, the guide steps that had to be recovered (held at rest
 * relative to the head for a step because they could not be advanced), the farthest a
 * tip moved in one frame (a whipping guide moves metres), steps and force evaluations
 * per guide and frame, and CPU seconds per frame. The rows run one after the other, each
 * with every thread, and are printed as they are done (the full table takes about
 * two hours on 2 cores). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/motion.h"
#include "hairkit/simulate.h"

#define ELEMENTS       20
#define ELEMENT_LENGTH 0.05

static const char *const motions[] = {"still", "shake", "nod", "tilt", "sway", "jump", "file"};
enum { MOTION_COUNT = sizeof motions / sizeof motions[0] };
static const char *const MOTION_FILE = "examples/motions/nod-and-shake.txt";
static const double fps[2] = {24.0, 30.0};

typedef struct Row {
    int ran;
    double failed_at;          /* start of the frame that failed */
    int recovered;             /* guide steps recovered */
    double tip_move;           /* m, the farthest a tip moved in a frame */
    double steps, evaluations; /* per guide and frame */
    double cpu;                /* s per frame */
    char error[160];
} Row;

static double process_cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static hk_Status make_motion(const hk_BenchOptions *options, const char *name, hk_HeadMotion **out, hk_Error *err)
{
    *out = NULL;
    if (!strcmp(name, "still")) return HK_OK;
    if (!strcmp(name, "file")) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", options->root, MOTION_FILE);
        return hk_head_motion_load(path, out, err);
    }
    const int translation = !strcmp(name, "sway") || !strcmp(name, "jump");
    return hk_head_motion_scripted(name, translation ? 0.03 : 25.0, 1.0, hk_default_head_pivot(), out, err);
}

/* The largest distance between the tips of two frames' guides (points per strand p). */
static double largest_tip_move(const double *a, const double *b, int guides, int p)
{
    double largest = 0.0;
    for (int g = 0; g < guides; g++) {
        const size_t tip = 3 * ((size_t)g * (size_t)p + (size_t)p - 1);
        const double dx = a[tip] - b[tip], dy = a[tip + 1] - b[tip + 1], dz = a[tip + 2] - b[tip + 2];
        largest = fmax(largest, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return largest;
}

static void run_row(const hk_BenchOptions *options, const hk_Scene *sc, const hk_Hairstyle *style,
                    const char *motion_name, double frame_rate, double settle, double seconds, Row *r)
{
    hk_Error err;
    hk_HairSim *sim = NULL;
    hk_HeadMotion *motion = NULL;
    double *before = NULL, *after = NULL;
    memset(r, 0, sizeof *r);
    const double dt = 1.0 / frame_rate;
    const hk_HairSimDef o = hk_hair_sim_def_for(style);
    if (make_motion(options, motion_name, &motion, &err) != HK_OK ||
        hk_hair_sim_create(style, sc->collision.shapes, sc->collision.count, &sc->wick, &o, &sim, &err) != HK_OK ||
        hk_hair_sim_settle(sim, NULL, settle, dt, &err) != HK_OK) {
        snprintf(r->error, sizeof r->error, "%.150s", err.message);
        goto done;
    }
    const int guides = hk_hair_sim_guide_count(sim), p = hk_hair_sim_points_per_strand(sim);
    before = malloc(sizeof(double) * 3 * (size_t)guides * (size_t)p);
    after = malloc(sizeof(double) * 3 * (size_t)guides * (size_t)p);
    if (!before || !after) {
        snprintf(r->error, sizeof r->error, "out of memory");
        goto done;
    }
    hk_hair_sim_guides(sim, before);
    const long frames = (long)ceil(seconds * frame_rate - 1e-9);
    const double cpu0 = process_cpu();
    long done_frames = 0;
    for (long f = 0; f < frames; f++) {
        hk_HairSimStats stats;
        if (hk_hair_sim_advance(sim, motion, (double)f * dt, dt, &stats, &err) != HK_OK) {
            r->failed_at = (double)f * dt;
            snprintf(r->error, sizeof r->error, "%.150s", err.message);
            break;
        }
        done_frames++;
        r->recovered += stats.recovered;
        r->steps += stats.substeps;
        r->evaluations += (double)stats.iterations;
        hk_hair_sim_guides(sim, after);
        r->tip_move = fmax(r->tip_move, largest_tip_move(before, after, guides, p));
        double *swap = before;
        before = after, after = swap;
    }
    r->ran = done_frames == frames;
    if (done_frames > 0) {
        r->cpu = (process_cpu() - cpu0) / (double)done_frames;
        r->steps /= (double)done_frames * guides;
        r->evaluations /= (double)done_frames * guides;
    }
done:
    free(before);
    free(after);
    hk_head_motion_destroy(motion);
    hk_hair_sim_destroy(sim);
}

int hk_bench_long_heads(FILE *out, const hk_BenchOptions *options)
{
    hk_Scene sc;
    if (hk_bench_scene_load(options, "guides200", "long-heads", HK_SCENE_GROOMING, &sc)) return 1;
    hk_Error err;
    double *lengths = hk_alloc_array(ELEMENTS, sizeof(double), &err);
    if (!lengths) {
        fprintf(stderr, "bench long-heads: %s\n", err.message);
        hk_scene_free(&sc);
        return 1;
    }
    for (int k = 0; k < ELEMENTS; k++) lengths[k] = ELEMENT_LENGTH;
    hk_free(sc.style.strand.element_lengths);
    sc.style.strand.element_lengths = lengths;
    sc.style.strand.element_count = ELEMENTS;
    /* --quick: 0.2 s of shaking at 1/30 s after 0.1 s of settling */
    const double settle = options->quick ? 0.1 : 1.0, seconds = options->quick ? 0.2 : 10.0;
    const int rates = options->quick ? 1 : 2, motion_count = options->quick ? 1 : MOTION_COUNT;
    fprintf(out,
            "long guides on a head: examples/guides200's %s grown %.0f m in %d elements, as `hairkit simulate`\n"
            "steps them; %.1f s of settling, then %.1f s of each motion (CLI defaults: 25 degrees or 3 cm at 1 Hz;\n"
            "file = %s)\n"
            "  result      ran, or FAIL@t (the frame from t failed)\n"
            "  recovered   guide steps held at rest relative to the head (could not be advanced)\n"
            "  tip mm      the farthest any guide's tip moved in one frame\n"
            "  steps, eval per guide and frame; CPU s per frame (all threads)\n\n"
            "  fps  motion     result      recovered   tip mm   steps    eval   CPU s\n",
            "201 guides", ELEMENTS * ELEMENT_LENGTH, ELEMENTS, settle, seconds, MOTION_FILE);
    fflush(out);
    int failed = 0, errors = 0;
    const double t0 = hk_seconds_now();
    for (int d = 0; d < rates; d++)
        for (int m = 0; m < motion_count; m++) {
            const double rate = options->quick ? 30.0 : fps[d];
            const char *name = options->quick ? "shake" : motions[m];
            Row r;
            run_row(options, &sc, &sc.style, name, rate, settle, seconds, &r);
            char result[32];
            if (r.ran)
                snprintf(result, sizeof result, "ran");
            else
                snprintf(result, sizeof result, "FAIL@%.2fs", r.failed_at);
            failed += !r.ran;
            fprintf(out, "  %3.0f  %-9s  %-10s  %9d  %7.1f  %6.2f  %6.2f  %6.2f\n", rate, name, result, r.recovered,
                    1e3 * r.tip_move, r.steps, r.evaluations, r.cpu);
            fflush(out);
            if (r.error[0]) {
                fprintf(stderr, "bench long-heads: %s at %.0f fps: %s\n", name, rate, r.error);
                errors += r.steps == 0.0;
            }
            fprintf(stderr, "bench long-heads: %s at %.0f fps done, %.0f s so far\n", name, rate,
                    hk_seconds_now() - t0);
        }
    fprintf(out, "\n  %d row(s) did not run to the end; %.0f s in all\n", failed, hk_seconds_now() - t0);
    hk_scene_free(&sc);
    return errors ? 1 : 0;
}
