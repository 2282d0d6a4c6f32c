/* hairkit simulate: a full head of hair in motion (paper 000 §3-4). The guides of the
 * setup's wick are solved at rest, then moved by the head's motion frame after frame;
 * every frame writes the hair (.hair) and its picture (PNG), and an .mp4 of the
 * pictures is made at the end when ffmpeg is installed. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "hairkit/simulate.h"

static const char *const CMD = "simulate";

static void usage(FILE *out)
{
    fprintf(out,
            "usage: hairkit simulate SETUP.txt --frames N --fps F -o DIR [options]\n"
            "\n"
            "Dynamics of a full head of hair (paper 000): one Super-Helix per guide follicle\n"
            "of the setup's wick, starting from its rest shape, moved by the head, pushed by\n"
            "the collision shapes (with anisotropic friction) and by the other guides. Frame\n"
            "k (k = 0 .. N-1, at t = k / F; frame 0 is the rest state) is written as\n"
            "DIR/frame_kkkk.hair (guides and interpolated hair) and DIR/frame_kkkk.png, and\n"
            "DIR/hair.mp4 is made from the pictures when ffmpeg is installed. A frame's\n"
            ".hair holds every strand: about 60 MB for the 123,000 strands of the default\n"
            "head.\n"
            "\n"
            "options:\n"
            "  --frames N         number of frames (1 to 100000)\n"
            "  --fps F            frames per second; the time step is 1/F (the paper: 30)\n"
            "  -o, --output DIR   folder for the frames (made if missing)\n"
            "  --guides-only      simulate and write only the guides (DIR/guides_kkkk.hair),\n"
            "                     no interpolation and no pictures: a quick preview\n"
            "  --no-contacts      no guide-guide interactions\n"
            "  --preroll S        let the hair settle S seconds on the still head before\n"
            "                     frame 0 (default 1; the groomed shape ignores the\n"
            "                     guide-guide contacts)\n"
            "  --damping on|off   internal friction and air drag (default on)\n");
    hk_cli_motion_options_help(out);
    fprintf(out, "pictures:\n");
    hk_cli_render_options_help(out);
    fprintf(out,
            "  --seed N           random seed of the interpolation (default 1)\n"
            "  --threads N        threads to use (default: all cores); the results do not\n"
            "                     depend on it\n"
            "  --quiet            no progress or summary on stderr\n"
            "  -h, --help         this help\n");
}

typedef struct SimArgs {
    const char *setup, *dir;
    long frames;
    double fps;
    int guides_only, contacts, damping, quiet;
    double preroll;
    hk_CliMotion motion;
    hk_RenderOptions render;
    hk_GroomOptions groom;
} SimArgs;

static int parse_args(int argc, char **argv, SimArgs *a)
{
    enum { OPT_FRAMES = 2000, OPT_FPS, OPT_GUIDES_ONLY, OPT_NO_CONTACTS, OPT_DAMPING, OPT_PREROLL };
    static const struct option options[] = {
        {"frames", required_argument, NULL, OPT_FRAMES},
        {"fps", required_argument, NULL, OPT_FPS},
        {"output", required_argument, NULL, 'o'},
        {"guides-only", no_argument, NULL, OPT_GUIDES_ONLY},
        {"no-contacts", no_argument, NULL, OPT_NO_CONTACTS},
        {"damping", required_argument, NULL, OPT_DAMPING},
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
    a->contacts = 1;
    a->damping = 1;
    a->preroll = 1.0;
    a->motion = hk_cli_default_motion();
    a->render = hk_default_render_options();
    a->groom = hk_default_groom_options();
    optind = 1;
    opterr = 0;
    int c, rc;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        if (HK_CLI_IS_RENDER_OPTION(c)) {
            if ((rc = hk_cli_render_option(CMD, c, optarg, &a->render))) return rc;
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
        case 'o': a->dir = optarg; break;
        case OPT_GUIDES_ONLY: a->guides_only = 1; break;
        case OPT_NO_CONTACTS: a->contacts = 0; break;
        case OPT_PREROLL:
            if (!hk_cli_parse_double(optarg, &a->preroll) || !(a->preroll >= 0.0 && a->preroll <= 100.0))
                return hk_cli_usage_error(CMD, "--preroll expects seconds in [0, 100], got '%s'", optarg);
            break;
        case OPT_DAMPING:
            if (strcmp(optarg, "on") != 0 && strcmp(optarg, "off") != 0)
                return hk_cli_usage_error(CMD, "--damping must be on or off, got '%s'", optarg);
            a->damping = strcmp(optarg, "on") == 0;
            break;
        case 's':
            if ((rc = hk_cli_seed_option(CMD, optarg, &a->groom.seed))) return rc;
            break;
        case 't':
            if ((rc = hk_cli_threads_option(CMD, optarg, &a->render.threads))) return rc;
            a->groom.threads = a->render.threads;
            break;
        case 'q': a->quiet = 1; break;
        case 'h': usage(stdout); return -1;
        case ':': return hk_cli_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
        default: return hk_cli_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return hk_cli_usage_error(CMD, "missing SETUP file");
    if (optind + 1 < argc) return hk_cli_usage_error(CMD, "unexpected argument '%s'", argv[optind + 1]);
    if (!a->frames) return hk_cli_usage_error(CMD, "give the number of frames: --frames N");
    if (!(a->fps > 0.0)) return hk_cli_usage_error(CMD, "give the frame rate: --fps F");
    if (!a->dir) return hk_cli_usage_error(CMD, "no output folder: give -o DIR");
    a->setup = argv[optind];
    return 0;
}

/* The head mesh moved by the head's rigid state (positions and normals). */
static void move_head(const hk_Mesh *rest, const hk_RigidState *st, hk_Mesh *out)
{
    for (int i = 0; i < rest->vertex_count; i++) {
        hk_rigid_point(st, rest->positions[i], &out->positions[i], NULL, NULL);
        out->normals[i] = hk_m3_mul_v3(&st->rot, rest->normals[i]);
    }
}

/* ffmpeg -framerate F -i DIR/frame_%04d.png ... DIR/hair.mp4, when ffmpeg is on the
 * PATH; returns 1 if the video was made. Run without a shell: DIR may hold anything. */
static int make_video(const char *dir, double fps, int quiet)
{
    char rate[32], pattern[4096], video[4096];
    snprintf(rate, sizeof rate, "%g", fps);
    if (snprintf(pattern, sizeof pattern, "%s/frame_%%04d.png", dir) >= (int)sizeof pattern ||
        snprintf(video, sizeof video, "%s/hair.mp4", dir) >= (int)sizeof video)
        return 0;
    const pid_t pid = fork();
    if (pid < 0) return 0;
    if (pid == 0) {
        char *const args[] = {"ffmpeg", "-y", "-loglevel", "error", "-framerate", rate, "-i", pattern,
                              "-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", video, NULL};
        execvp("ffmpeg", args);
        _exit(127); /* not installed */
    }
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return 0;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return 1;
    if (!quiet && !(WIFEXITED(status) && WEXITSTATUS(status) == 127))
        fprintf(stderr, "hairkit %s: ffmpeg failed, no video\n", CMD);
    return 0;
}

typedef struct Scene {
    hk_SetupDef setup;
    hk_HairstyleDef style;
    hk_Shape *shapes;
    int shape_count;
    hk_Mesh head, moved, wick;
    hk_VisualityDef vis;
    hk_HeadMotion *motion;
    hk_HairSim *sim;
} Scene;

static void scene_free(Scene *s)
{
    hk_hair_sim_destroy(s->sim);
    hk_head_motion_destroy(s->motion);
    hk_mesh_free(&s->head);
    hk_free(s->moved.positions);
    hk_free(s->moved.normals);
    hk_mesh_free(&s->wick);
    hk_free(s->shapes);
    hk_hairstyle_free(&s->style);
    hk_setup_free(&s->setup);
}

static hk_Status load_scene(const SimArgs *a, Scene *s, hk_Error *err)
{
    hk_Status st = hk_setup_load(a->setup, &s->setup, err);
    if (st != HK_OK) return st;
    if (!s->setup.hairstyle || !s->setup.wick_model)
        return hk_error_set(err, HK_ERR_PARSE, "%s: simulating needs HairstyleInfo and WickModel", a->setup);
    if ((st = hk_hairstyle_load(s->setup.hairstyle, &s->style, err)) != HK_OK) return st;
    if (s->setup.collision &&
        (st = hk_collision_load(s->setup.collision, &s->shapes, &s->shape_count, err)) != HK_OK)
        return st;
    if ((st = hk_obj_load(s->setup.wick_model, &s->wick, err)) != HK_OK) return st;
    if (s->setup.head_model) {
        if ((st = hk_obj_load(s->setup.head_model, &s->head, err)) != HK_OK) return st;
        s->moved = s->head;
        s->moved.positions = hk_alloc_array((size_t)s->head.vertex_count, sizeof(hk_Vec3), err);
        s->moved.normals = hk_alloc_array((size_t)s->head.vertex_count, sizeof(hk_Vec3), err);
        if (!s->moved.positions || !s->moved.normals) return HK_ERR_NOMEM;
    }
    if (s->setup.visuality && (st = hk_visuality_load(s->setup.visuality, &s->vis, err)) != HK_OK) return st;
    return hk_cli_motion_create(&a->motion, &s->motion, err);
}

static hk_Status frame_path(char *buf, size_t size, const char *dir, const char *stem, long k, const char *ext,
                            hk_Error *err)
{
    if (snprintf(buf, size, "%s/%s_%04ld.%s", dir, stem, k, ext) >= (int)size)
        return hk_error_set(err, HK_ERR_INVALID, "output folder name too long");
    return HK_OK;
}

/* Writes frame k: the guides alone, or the interpolated hair and its picture. The
 * camera is fixed at the first frame's fit, backed off by 15 % to leave room. */
static hk_Status write_frame(const SimArgs *a, Scene *s, long k, double t, hk_RenderOptions *ro, hk_Error *err)
{
    char path[4096];
    hk_Groom g;
    memset(&g, 0, sizeof g);
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_Status st;
    if (a->guides_only) {
        g.points_per_strand = hk_hair_sim_points_per_strand(s->sim);
        g.guide_count = hk_hair_sim_guide_count(s->sim);
        g.guides = hk_alloc_array((size_t)g.guide_count * (size_t)g.points_per_strand, 3 * sizeof(double), err);
        if (!g.guides) return HK_ERR_NOMEM;
        hk_hair_sim_guides(s->sim, g.guides);
        st = hk_groom_to_hair(&g, &s->style, &hair, err);
        if (st == HK_OK) st = frame_path(path, sizeof path, a->dir, "guides", k, "hair", err);
        if (st == HK_OK) st = hk_hair_save(path, &hair, err);
        hk_hair_free(&hair);
        hk_groom_free(&g);
        return st;
    }
    st = hk_hair_sim_groom(s->sim, &s->wick, &a->groom, &g, err);
    if (st == HK_OK) st = hk_groom_to_hair(&g, &s->style, &hair, err);
    hk_groom_free(&g);
    if (st == HK_OK) st = frame_path(path, sizeof path, a->dir, "frame", k, "hair", err);
    if (st == HK_OK) st = hk_hair_save(path, &hair, err);
    const hk_Mesh *head = NULL;
    if (st == HK_OK && s->head.vertex_count > 0) {
        hk_RigidState state;
        hk_head_motion_eval(s->motion, t, &state);
        move_head(&s->head, &state, &s->moved);
        head = &s->moved;
    }
    if (st == HK_OK && k == 0 && !(ro->camera_distance > 0.0)) {
        st = hk_render_fit_camera(&hair, head, ro, &ro->camera_target, &ro->camera_distance, err);
        ro->camera_distance *= 1.15;
    }
    hk_Canvas image = {0, 0, NULL};
    if (st == HK_OK) st = hk_render(&hair, head, &s->vis, ro, &image, NULL, err);
    if (st == HK_OK) st = frame_path(path, sizeof path, a->dir, "frame", k, "png", err);
    if (st == HK_OK) st = hk_render_write_png(&image, path, err);
    hk_canvas_destroy(&image);
    hk_hair_free(&hair);
    return st;
}

int hk_cmd_simulate(int argc, char **argv)
{
    SimArgs a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc < 0 ? HK_EXIT_OK : rc;
    hk_Error err;
    Scene s;
    memset(&s, 0, sizeof s);
    s.vis = hk_default_visuality();
    int status = HK_EXIT_FAIL;
    const double t0 = hk_cli_now();
    hk_Status st = load_scene(&a, &s, &err);
    if (st == HK_OK && mkdir(a.dir, 0777) != 0 && errno != EEXIST)
        st = hk_error_set(&err, HK_ERR_IO, "%s: cannot make the folder: %s", a.dir, strerror(errno));
    hk_CliProgress progress = {!a.quiet && hk_cli_stderr_is_tty(), "", -1};
    if (st == HK_OK) {
        hk_HairSimOptions so = hk_default_hair_sim_options(&s.style);
        so.threads = a.groom.threads;
        so.hair_contacts = a.contacts;
        if (!a.damping) so.dynamics.internal_friction = so.dynamics.air_drag = 0.0;
        so.progress = hk_cli_progress;
        so.progress_user = &progress;
        st = hk_hair_sim_create(&s.style, s.shapes, s.shape_count, &s.wick, &so, &s.sim, &err);
        hk_cli_progress_done(&progress);
    }
    if (st == HK_OK && a.preroll > 0.0) {
        hk_RigidState pose;
        hk_head_motion_eval(s.motion, 0.0, &pose);
        st = hk_hair_sim_settle(s.sim, &pose, a.preroll, 1.0 / a.fps, &err);
    }
    if (st == HK_OK && !a.quiet)
        fprintf(stderr, "hairkit %s: %d guides of %d elements at rest (and settled %g s) after %.2f s; %ld frames at %g "
                "fps\n",
                CMD, hk_hair_sim_guide_count(s.sim), s.style.element_count, a.preroll, hk_cli_now() - t0, a.frames,
                a.fps);
    hk_RenderOptions ro = a.render;
    const double dt = 1.0 / a.fps;
    double sim_seconds = 0.0;
    long substeps = 0;
    for (long k = 0; st == HK_OK && k < a.frames; k++) {
        const double t = k * dt;
        if (k > 0) {
            hk_HairSimStats stats;
            st = hk_hair_sim_advance(s.sim, s.motion, t - dt, dt, &stats, &err);
            sim_seconds += stats.seconds;
            substeps += stats.substeps;
        }
        if (st == HK_OK) st = write_frame(&a, &s, k, t, &ro, &err);
        if (progress.enabled) hk_cli_progress(&progress, "frames", (double)(k + 1) / a.frames);
    }
    hk_cli_progress_done(&progress);
    if (st != HK_OK) {
        hk_cli_fail(CMD, &err);
    } else {
        const int video = !a.guides_only && make_video(a.dir, a.fps, a.quiet);
        if (!a.quiet)
            fprintf(stderr,
                    "hairkit %s: %ld frames in %s%s; dynamics %.3f s (%.1f ms per frame, %.2f guide steps per "
                    "guide and frame); %.2f s in all\n",
                    CMD, a.frames, a.dir, video ? " (and hair.mp4)" : "", sim_seconds,
                    a.frames > 1 ? 1e3 * sim_seconds / (a.frames - 1) : 0.0,
                    a.frames > 1 ? (double)substeps / (a.frames - 1) / hk_hair_sim_guide_count(s.sim) : 0.0,
                    hk_cli_now() - t0);
        status = HK_EXIT_OK;
    }
    scene_free(&s);
    return status;
}
