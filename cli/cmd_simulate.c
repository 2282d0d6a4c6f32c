/* hairkit simulate: a full head of hair in motion (Bertails et al. 2006 §3-4). Parses the options
 * and prints progress; the work is hk_simulation_run and hk_simulation_rebuild
 * (src/simulate/sim_run.c, sim_rebuild.c). */
#include <getopt.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/core_internal.h"
#include "hairkit/simulate.h"

static const char *const CMD = "simulate";

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit simulate SETUP.txt --frames N --fps F -o DIR [options]\n"
                 "       hairkit simulate --rebuild DIR --frame K -o OUT.hair [--threads N]\n"
                 "\n"
                 "Dynamics of a full head of hair (Bertails et al. 2006): one Super-Helix per guide\n"
                 "follicle of the setup's wick, starting from its rest shape, moved by the head,\n"
                 "pushed by the collision shapes (with anisotropic friction) and by the other\n"
                 "guides. Frame k (k = 0 .. N-1, at t = k / F; frame 0 is the rest state) is\n"
                 "written as\n"
                 "DIR/guides_kkkk.hair (the guides) and DIR/frame_kkkk.png (the guides and the\n"
                 "interpolated hair grown from them), and DIR/hair.mp4 is made from the pictures\n"
                 "when ffmpeg is installed. DIR/simulation.txt records what grows the interpolated\n"
                 "hair again: --rebuild writes any frame's full hair, byte for byte what\n"
                 "--full-hair would have written (about 60 MB a frame on the default head, so\n"
                 "not written by default).\n"
                 "\n"
                 "Files of an earlier run in DIR (frame_*.png, frame_*.hair, guides_*.hair,\n"
                 "hair.mp4, simulation.txt) are removed first; nothing else in DIR is touched.\n"
                 "\n"
                 "options:\n"
                 "  --frames N         number of frames (1 to 100000)\n"
                 "  --fps F            frames per second; the time step is 1/F (the paper: 30)\n"
                 "  -o, --output DIR   folder for the frames (made if missing)\n"
                 "  --guides-only      simulate and write only the guides (DIR/guides_kkkk.hair),\n"
                 "                     no interpolation and no pictures: a quick preview\n"
                 "  --full-hair        also write every strand of every frame, DIR/frame_kkkk.hair\n"
                 "                     (guides first, then the interpolated strands)\n"
                 "  --no-contacts      no guide-guide interactions\n"
                 "  --preroll auto|S   let the hair settle on the still head before frame 0 (the\n"
                 "                     groomed shape ignores the guide-guide contacts): S seconds,\n"
                 "                     or (auto, the default) 1 s and then on until every guide's\n"
                 "                     tip is at rest (slower than 0.1 mm/s for 5 frames), 5 s at\n"
                 "                     most\n"
                 "  --damping on|off   internal friction and air drag (default on)\n"
                 "  --integrator auto|trbdf2|euler\n"
                 "                     time stepping of the guides: the linearly implicit Euler\n"
                 "                     step with the guide-guide contacts solved together, guides\n"
                 "                     over 25 cm in several steps a frame (auto, the default;\n"
                 "                     euler), or TR-BDF2 (second order, the contacts as penalty\n"
                 "                     forces per guide; long guides whip)\n");
    hk_cli_motion_options_help(out);
    fprintf(out, "pictures:\n");
    hk_cli_render_options_help(out);
    fprintf(out, "rebuilding a frame:\n"
                 "  --rebuild DIR      the folder of an earlier run (it needs DIR/simulation.txt,\n"
                 "                     DIR/guides_kkkk.hair and the setup's unchanged hairstyle,\n"
                 "                     wick, collision and motion files)\n"
                 "  --frame K          the frame to rebuild; -o names the .hair to write\n"
                 "\n"
                 "  --seed N           random seed of the interpolation (default 1)\n"
                 "  --threads N        threads to use (default: all cores); the results do not\n"
                 "                     depend on it\n"
                 "  --quiet            no progress or summary on stderr (otherwise a bar with the\n"
                 "                     time left on a terminal, else a line every few seconds)\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "# 3 s of a shaking head: frames of guides and pictures in out/",
                    "hairkit simulate examples/guides200/setup.txt --frames 90 --fps 30 --motion shake -o out",
                    "# every strand of frame 1 again, grown from its guides",
                    "hairkit simulate --rebuild out --frame 1 -o frame1.hair",
                    "# a quick preview: the guides only, moved by a motion file",
                    "hairkit simulate examples/guides200/setup.txt --frames 60 --fps 30 --guides-only --motion "
                    "examples/motions/nod-and-shake.txt -o preview");
}

typedef struct SimArgs {
    const char *setup, *dir, *rebuild;
    long frames, frame;
    double fps;
    int quiet;
    hk_SimRunDef run;
    hk_CliMotion motion;
} SimArgs;

static int parse_args(int argc, char **argv, SimArgs *a)
{
    enum {
        OPT_FRAMES = 2000,
        OPT_FPS,
        OPT_GUIDES_ONLY,
        OPT_NO_CONTACTS,
        OPT_DAMPING,
        OPT_INTEGRATOR,
        OPT_PREROLL,
        OPT_FULL_HAIR,
        OPT_REBUILD,
        OPT_FRAME
    };
    static const struct option options[] = {
        {"frames", required_argument, NULL, OPT_FRAMES},
        {"fps", required_argument, NULL, OPT_FPS},
        {"output", required_argument, NULL, 'o'},
        {"guides-only", no_argument, NULL, OPT_GUIDES_ONLY},
        {"full-hair", no_argument, NULL, OPT_FULL_HAIR},
        {"rebuild", required_argument, NULL, OPT_REBUILD},
        {"frame", required_argument, NULL, OPT_FRAME},
        {"no-contacts", no_argument, NULL, OPT_NO_CONTACTS},
        {"damping", required_argument, NULL, OPT_DAMPING},
        {"integrator", required_argument, NULL, OPT_INTEGRATOR},
        {"preroll", required_argument, NULL, OPT_PREROLL},
        {"seed", required_argument, NULL, 's'},
        {"threads", required_argument, NULL, 't'},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        HK_CLI_MOTION_LONG_OPTIONS,
        HK_CLI_RENDER_LONG_OPTIONS,
        {NULL, 0, NULL, 0},
    };
    memset(a, 0, sizeof *a);
    a->frame = -1;
    a->run = hk_default_sim_run_def();
    a->motion = hk_cli_default_motion();
    optind = 1;
    opterr = 0;
    int c, rc;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        if (HK_CLI_IS_RENDER_OPTION(c)) {
            if ((rc = hk_cli_render_option(CMD, c, optarg, &a->run.render))) return rc;
            continue;
        }
        if (HK_CLI_IS_MOTION_OPTION(c)) {
            if ((rc = hk_cli_motion_option(CMD, c, optarg, &a->motion))) return rc;
            continue;
        }
        switch (c) {
        case OPT_FRAMES:
            if (!hk_cli_parse_int(optarg, 1, 100000, &a->frames))
                return hk_cli_usage_error(CMD, "--frames expects a whole number from 1 to 100000, got '%s'", optarg);
            break;
        case OPT_FPS:
            if (!hk_cli_parse_double(optarg, &a->fps) || !(a->fps >= 1.0 && a->fps <= 100000.0))
                return hk_cli_usage_error(CMD, "--fps expects a number from 1 to 100000, got '%s'", optarg);
            break;
        case 'o':
            a->dir = optarg;
            break;
        case OPT_GUIDES_ONLY:
            a->run.guides_only = 1;
            break;
        case OPT_FULL_HAIR:
            a->run.full_hair = 1;
            break;
        case OPT_REBUILD:
            a->rebuild = optarg;
            break;
        case OPT_FRAME:
            if (!hk_cli_parse_int(optarg, 0, 99999, &a->frame))
                return hk_cli_usage_error(CMD, "--frame expects a frame number from 0 to 99999, got '%s'", optarg);
            break;
        case OPT_NO_CONTACTS:
            a->run.hair_contacts = 0;
            break;
        case OPT_PREROLL:
            if (strcmp(optarg, "auto") == 0) {
                const hk_SimRunDef def = hk_default_sim_run_def();
                a->run.preroll = def.preroll, a->run.preroll_max = def.preroll_max;
                break;
            }
            if (!hk_cli_parse_double(optarg, &a->run.preroll) || !(a->run.preroll >= 0.0 && a->run.preroll <= 100.0))
                return hk_cli_usage_error(CMD, "--preroll expects auto or seconds in [0, 100], got '%s'", optarg);
            a->run.preroll_max = a->run.preroll; /* exactly */
            break;
        case OPT_DAMPING:
            if (strcmp(optarg, "on") != 0 && strcmp(optarg, "off") != 0)
                return hk_cli_usage_error(CMD, "--damping must be on or off, got '%s'", optarg);
            a->run.damping = strcmp(optarg, "on") == 0;
            break;
        case OPT_INTEGRATOR:
            if (strcmp(optarg, "auto") == 0)
                a->run.integrator = HK_INTEGRATOR_AUTO;
            else if (strcmp(optarg, "trbdf2") == 0)
                a->run.integrator = HK_INTEGRATOR_TRBDF2;
            else if (strcmp(optarg, "euler") == 0)
                a->run.integrator = HK_INTEGRATOR_LINEAR_EULER;
            else
                return hk_cli_usage_error(CMD, "--integrator must be auto, trbdf2 or euler, got '%s'", optarg);
            break;
        case 's':
            if ((rc = hk_cli_seed_option(CMD, optarg, &a->run.seed))) return rc;
            break;
        case 't':
            if ((rc = hk_cli_threads_option(CMD, optarg, &a->run.threads))) return rc;
            break;
        case 'q':
            a->quiet = 1;
            break;
        case 'h':
            usage(stdout);
            return -1;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    if (a->rebuild) {
        if (optind < argc) return hk_cli_usage_error(CMD, "--rebuild takes no SETUP file, got '%s'", argv[optind]);
        if (a->frame < 0) return hk_cli_usage_error(CMD, "give the frame to rebuild: --frame K");
        if (!a->dir) return hk_cli_usage_error(CMD, "no output file: give -o OUT.hair");
        return hk_cli_output_file(CMD, "-o", a->dir, NULL);
    }
    if (a->frame >= 0) return hk_cli_usage_error(CMD, "--frame goes with --rebuild DIR");
    if (a->run.guides_only && a->run.full_hair)
        return hk_cli_usage_error(CMD, "--full-hair and --guides-only exclude each other");
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, "missing SETUP file");
    if (operand_rc) return operand_rc;
    if (!a->frames) return hk_cli_usage_error(CMD, "give the number of frames: --frames N");
    if (!(a->fps > 0.0)) return hk_cli_usage_error(CMD, "give the frame rate: --fps F");
    if (!a->dir) return hk_cli_usage_error(CMD, "no output folder: give -o DIR");
    /* A setup that cannot be read fails before the output folder is made (it left an
     * empty one behind); the same message and exit code as when loading it. */
    FILE *setup = fopen(argv[optind], "r");
    if (!setup) {
        fprintf(stderr, "hairkit %s: %s: cannot open: %s\n", CMD, argv[optind], strerror(errno));
        return HK_EXIT_FAIL;
    }
    fclose(setup);
    if ((rc = hk_cli_output_folder(CMD, "-o", a->dir))) return rc;
    a->setup = argv[optind];
    a->run.frames = a->frames;
    a->run.fps = a->fps;
    return 0;
}

/* Progress: the bar (with the time left) on a terminal, else a line every few seconds,
 * so that a log shows the run is alive. */
typedef struct Printer {
    hk_CliProgress bar;
    int lines;
    double last_line;
    const char *dir;
    long recovered; /* guides recovered, as last reported */
} Printer;

#define LINE_INTERVAL 5.0 /* seconds between two progress lines in a log */

static void on_progress(void *user, const hk_SimProgress *p)
{
    Printer *pr = user;
    if (p->frame == 0) {
        hk_cli_progress_done(&pr->bar);
        if (!pr->lines && !pr->bar.enabled) return;
        if (p->removed)
            fprintf(stderr, "hairkit %s: removed %d files of an earlier run from %s\n", CMD, p->removed, pr->dir);
        char elements[48];
        if (p->elements_min < p->elements)
            snprintf(elements, sizeof elements, "%d to %d elements", p->elements_min, p->elements);
        else
            snprintf(elements, sizeof elements, "%d element%s", p->elements, p->elements == 1 ? "" : "s");
        fprintf(stderr, "hairkit %s: %d guides of %s %s after %.2f s of settling (set up in %.2f s); %ld frames\n", CMD,
                p->guides, elements, p->preroll_at_rest || p->preroll == 0.0 ? "at rest" : "still moving", p->preroll,
                p->seconds_setup, p->frames);
        pr->last_line = hk_seconds_now();
        return;
    }
    if (p->recovered > pr->recovered) { /* always said, even without progress lines */
        hk_cli_progress_done(&pr->bar);
        fprintf(stderr,
                "hairkit %s: by frame %ld, %ld guide(s) could not be advanced through a frame and were held "
                "at rest relative to the head for it (%ld so far)\n",
                CMD, p->frame, p->recovered - pr->recovered, p->recovered);
        pr->recovered = p->recovered;
    }
    const double per_frame = p->seconds / (double)p->frame;
    char left[32], note[96];
    hk_cli_format_duration(per_frame * (double)(p->frames - p->frame), left, sizeof left);
    snprintf(note, sizeof note, "%.2f s/frame, about %s left", per_frame, left);
    if (pr->bar.enabled) {
        hk_cli_progress_note(&pr->bar, "frames", (double)p->frame / (double)p->frames, note);
    } else if (pr->lines &&
               (p->frame == 1 || p->frame == p->frames || hk_seconds_now() - pr->last_line >= LINE_INTERVAL)) {
        fprintf(stderr, "hairkit %s: frame %ld/%ld, %s\n", CMD, p->frame, p->frames, note);
        pr->last_line = hk_seconds_now();
    }
}

static void print_summary(const SimArgs *a, const hk_SimProgress *p)
{
    const double n = (double)(p->frames > 0 ? p->frames : 1);
    char total[32];
    hk_cli_format_duration(p->seconds_setup + p->seconds, total, sizeof total);
    fprintf(stderr,
            "hairkit %s: %ld frames in %s%s, %s in all; per frame %.2f s: dynamics %.3f s, interpolated hair %.3f s, "
            "picture %.3f s, writing %.3f s%s; %.1f MB written (%.2f MB per frame)\n",
            CMD, p->frame, a->dir, p->video > 0 ? " (and hair.mp4)" : "", total, p->seconds / n,
            p->seconds_dynamics / n, p->seconds_regrow / n, p->seconds_render / n, p->seconds_write / n,
            p->frames_at_once > 1 ? " (two frames drawn at once: the stages overlap)" : "", (double)p->bytes / 1e6,
            (double)p->bytes / 1e6 / n);
    if (p->video < 0) fprintf(stderr, "hairkit %s: ffmpeg failed, no video\n", CMD);
    if (p->recovered > 0)
        fprintf(stderr,
                "hairkit %s: %ld time(s) a guide could not be advanced through a frame and was held at rest "
                "relative to the head for it\n",
                CMD, p->recovered);
}

static int rebuild(const SimArgs *a)
{
    hk_Error err;
    hk_HairFile hair;
    hk_Status st = hk_simulation_rebuild(a->rebuild, a->frame, a->run.threads, &hair, &err);
    if (st == HK_OK) st = hk_hair_save(a->dir, &hair, &err);
    if (st == HK_OK && !a->quiet)
        fprintf(stderr, "hairkit %s: frame %ld of %s rebuilt: %u strands in %s\n", CMD, a->frame, a->rebuild,
                hair.strand_count, a->dir);
    hk_hair_free(&hair);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

int hk_cmd_simulate(int argc, char **argv)
{
    SimArgs a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc < 0 ? HK_EXIT_OK : rc;
    if (a.rebuild) return rebuild(&a);
    hk_Error err;
    hk_HeadMotion *motion = NULL;
    hk_Status st = hk_cli_motion_create(&a.motion, &motion, &err);
    Printer pr = {{!a.quiet && hk_cli_stderr_is_tty(), "", -1}, !a.quiet, 0.0, a.dir, 0};
    a.run.motion = motion;
    a.run.statics_progress = hk_cli_progress;
    a.run.statics_user = &pr.bar;
    a.run.progress = on_progress;
    a.run.progress_user = &pr;
    hk_SimProgress p;
    memset(&p, 0, sizeof p);
    if (st == HK_OK) st = hk_simulation_run(a.setup, a.dir, &a.run, &p, &err);
    hk_cli_progress_done(&pr.bar);
    hk_head_motion_destroy(motion);
    if (st != HK_OK) return hk_cli_fail(CMD, &err);
    if (!a.quiet) print_summary(&a, &p);
    return HK_EXIT_OK;
}
