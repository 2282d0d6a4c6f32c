/* hairkit view: the command line of the interactive viewer (viewer/, docs/viewer.md).
 * Parses the options, reads the hair and the head as `render` and `run` do, and hands
 * them to hk_viewer_run; built without HK_VIEWER it says so. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "hairkit/live_sim.h"
#include "hairkit/motion.h"
#include "hairkit/scene.h"
#ifdef HK_HAVE_VIEWER
#include "viewer/viewer.h"
#endif

static const char *const CMD = "view";

enum {
    OPT_FRAMES = 1300,
    OPT_SCREENSHOT,
    OPT_HEAD_VERT,
    OPT_HEAD_FRAG,
    OPT_HAIR_VERT,
    OPT_HAIR_FRAG,
    OPT_SIMULATE,
    OPT_FPS,
    OPT_PREROLL,
    OPT_NO_CONTACTS,
    OPT_GUIDES_ONLY,
    OPT_SHOW_WICK,
    OPT_SHOW_SHAPES,
    OPT_OVERLAY,
    OPT_NO_OVERLAY,
    OPT_DRAG
};

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit view SETUP.txt | HAIR [--head MESH] [--visuality V.txt]\n"
                 "                    [--width W --height H] [--view AZ,EL] [--light AZ,EL]\n"
                 "                    [--frames N --screenshot OUT.png] [options]\n"
                 "\n"
                 "The interactive OpenGL viewer (thesis 4.1.5-4.1.6): the head with a Lambert\n"
                 "shader, the hair as line strips with Kajiya-Kay (or Marschner) shading and\n"
                 "opacity shadow maps. A setup file's hair is grown (or loaded) as 'hairkit run'\n"
                 "does; any other file is hair in a format hairkit reads, as 'hairkit render'.\n"
                 "--view, --light, --width and --height frame the picture as 'render' does.\n"
                 "Mouse: left drag turns, right drag moves, wheel zooms, L + left drag moves the\n"
                 "light, Shift + left drag moves the head (live dynamics). Keys: arrows turn,\n"
                 "+ - zoom, S shadows, M shading, H head, G guides only, W wick, C collision\n"
                 "shapes, O overlay, Space play/pause the dynamics, N one step, Backspace back to time 0,\n"
                 "R camera reset, P screenshot, F5 reload shaders, Esc quits (docs/viewer.md).\n"
                 "Shader files and the hairstyle file are read again when they change.\n"
                 "\n"
                 "options:\n"
                 "  --head FILE        the head mesh, OBJ or PLY (with a hair file; optional)\n"
                 "  --visuality FILE   hair colours (with a hair file; default brown)\n"
                 "  --frames N         headless: draw N frames in a hidden window, then stop\n"
                 "  --screenshot FILE  the last frame as a PNG (with --frames; alone: one frame)\n"
                 "  --head-vert F, --head-frag F, --hair-vert F, --hair-frag F\n"
                 "                     GLSL files replacing the built-in shaders (as the setup\n"
                 "                     keys HeadVert, HeadFrag, HairVert, HairFrag)\n"
                 "  --guides-only, --show-wick, --show-shapes\n"
                 "                     start with the guides alone, the wick, the collision shapes\n"
                 "                     shown (keys G, W, C; a setup file's)\n"
                 "  --overlay, --no-overlay\n"
                 "                     frames per second and counts drawn in the picture's top left\n"
                 "                     corner, or not (key O; default: on in a window, off headless)\n"
                 "live dynamics (a setup file that grows its hair):\n"
                 "  --simulate         simulate the guides from the start and regrow the head every\n"
                 "                     step, as 'hairkit simulate' (headless: one step a frame)\n"
                 "  --fps F            steps per simulated second; the step is 1/F (default 30)\n"
                 "  --preroll auto|S   settle the hair before time 0: auto (default) at least 1 s,\n"
                 "                     then until at rest, at most 5 s; S: exactly S seconds\n"
                 "  --no-contacts      no guide-guide interactions\n"
                 "  --drag DX,DY       as a Shift + left drag of DX, DY pixels before the first step\n"
                 "                     (the head moved across the view; with --simulate)\n");
    hk_cli_motion_options_help(out);
    hk_cli_transform_help(out, 1, 1);
    hk_cli_render_options_help(out);
    fprintf(out, "  --quiet            no summary on stderr\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(
        out, "hairkit view examples/coupe4/setup.txt",
        "hairkit view examples/coupe3/setup.txt --view 180,10 --light 90,30",
        "# headless: ten frames drawn, the last one saved",
        "hairkit view examples/coupe4/setup.txt --frames 10 --screenshot shot.png --width 640 --height 480");
}

typedef struct ViewArgs {
    const char *input, *head_path, *vis_path, *screenshot;
    const char *shader[4];
    long frames;
    int quiet, simulate;
    int show[3]; /* guides only, the wick, the collision shapes (keys G, W, C) */
    int overlay; /* -1: on in a window, off headless */
    double drag[2];
    int dragged;
    hk_LiveSimDef live;
    hk_CliMotion motion;
    hk_RenderDef ro;
    hk_CliTransform hair_tf, head_tf;
    int usage_rc; /* an exit code already reported (a setup's SaveFile that cannot be written) */
} ViewArgs;

static int is_setup(const char *path)
{
    const size_t n = strlen(path);
    return n > 4 && !strcmp(path + n - 4, ".txt");
}

/* Returns -1 to go on, else the exit status. */
static int parse(int argc, char **argv, ViewArgs *a)
{
    static const struct option options[] = {
        {"head", required_argument, NULL, 'H'},
        {"visuality", required_argument, NULL, 'v'},
        {"frames", required_argument, NULL, OPT_FRAMES},
        {"screenshot", required_argument, NULL, OPT_SCREENSHOT},
        {"head-vert", required_argument, NULL, OPT_HEAD_VERT},
        {"head-frag", required_argument, NULL, OPT_HEAD_FRAG},
        {"hair-vert", required_argument, NULL, OPT_HAIR_VERT},
        {"hair-frag", required_argument, NULL, OPT_HAIR_FRAG},
        {"simulate", no_argument, NULL, OPT_SIMULATE},
        {"fps", required_argument, NULL, OPT_FPS},
        {"preroll", required_argument, NULL, OPT_PREROLL},
        {"no-contacts", no_argument, NULL, OPT_NO_CONTACTS},
        {"guides-only", no_argument, NULL, OPT_GUIDES_ONLY},
        {"show-wick", no_argument, NULL, OPT_SHOW_WICK},
        {"show-shapes", no_argument, NULL, OPT_SHOW_SHAPES},
        {"overlay", no_argument, NULL, OPT_OVERLAY},
        {"no-overlay", no_argument, NULL, OPT_NO_OVERLAY},
        {"drag", required_argument, NULL, OPT_DRAG},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        HK_CLI_MOTION_LONG_OPTIONS,
        HK_CLI_RENDER_LONG_OPTIONS,
        HK_CLI_HAIR_TRANSFORM_LONG_OPTIONS,
        HK_CLI_HEAD_TRANSFORM_LONG_OPTIONS,
        {NULL, 0, NULL, 0},
    };
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":h", options, NULL)) != -1) {
        if (HK_CLI_IS_MOTION_OPTION(c)) {
            const int rc = hk_cli_motion_option(CMD, c, optarg, &a->motion);
            if (rc) return rc;
            continue;
        }
        if (HK_CLI_IS_RENDER_OPTION(c)) {
            const int rc = hk_cli_render_option(CMD, c, optarg, &a->ro);
            if (rc) return rc;
            continue;
        }
        if (HK_CLI_IS_TRANSFORM_OPTION(c)) {
            const int rc = hk_cli_transforms_option(CMD, c, optarg, &a->hair_tf, &a->head_tf);
            if (rc) return rc;
            continue;
        }
        switch (c) {
        case 'H':
            a->head_path = optarg;
            break;
        case 'v':
            a->vis_path = optarg;
            break;
        case 'q':
            a->quiet = 1;
            break;
        case OPT_FRAMES:
            if (!hk_cli_parse_int(optarg, 1, 1000000, &a->frames))
                return hk_cli_usage_error(CMD, "--frames expects 1 to 1000000, got '%s'", optarg);
            break;
        case OPT_SCREENSHOT:
            a->screenshot = optarg;
            break;
        case OPT_SIMULATE:
            a->simulate = 1;
            break;
        case OPT_FPS:
            if (!hk_cli_parse_double(optarg, &a->live.fps) || !(a->live.fps >= 1.0 && a->live.fps <= 100000.0))
                return hk_cli_usage_error(CMD, "--fps expects a number from 1 to 100000, got '%s'", optarg);
            break;
        case OPT_PREROLL:
            if (!strcmp(optarg, "auto")) {
                const hk_LiveSimDef def = hk_default_live_sim_def();
                a->live.preroll = def.preroll, a->live.preroll_max = def.preroll_max;
                break;
            }
            if (!hk_cli_parse_double(optarg, &a->live.preroll) || !(a->live.preroll >= 0.0 && a->live.preroll <= 100.0))
                return hk_cli_usage_error(CMD, "--preroll expects auto or seconds in [0, 100], got '%s'", optarg);
            a->live.preroll_max = a->live.preroll; /* exactly, as hairkit simulate */
            break;
        case OPT_NO_CONTACTS:
            a->live.hair_contacts = 0;
            break;
        case OPT_DRAG:
            if (!hk_cli_parse_pair(optarg, &a->drag[0], &a->drag[1]) || fabs(a->drag[0]) > 1e4 ||
                fabs(a->drag[1]) > 1e4)
                return hk_cli_usage_error(CMD, "--drag expects DX,DY in pixels, got '%s'", optarg);
            a->dragged = 1;
            break;
        case OPT_GUIDES_ONLY:
        case OPT_SHOW_WICK:
        case OPT_SHOW_SHAPES:
            a->show[c - OPT_GUIDES_ONLY] = 1;
            break;
        case OPT_OVERLAY:
        case OPT_NO_OVERLAY:
            a->overlay = c == OPT_OVERLAY;
            break;
        case OPT_HEAD_VERT:
        case OPT_HEAD_FRAG:
        case OPT_HAIR_VERT:
        case OPT_HAIR_FRAG:
            a->shader[c - OPT_HEAD_VERT] = optarg;
            break;
        case 'h':
            usage(stdout);
            return HK_EXIT_OK;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, "missing SETUP.txt or HAIR file");
    if (operand_rc) return operand_rc;
    a->input = argv[optind];
    if (a->screenshot) {
        const int rc = hk_cli_output_file(CMD, "--screenshot", a->screenshot, ".png");
        if (rc) return rc;
    }
    if (a->screenshot && !a->frames) a->frames = 1;
    if (a->simulate && !is_setup(a->input))
        return hk_cli_usage_error(CMD, "--simulate needs a setup file (SETUP.txt), got '%s'", a->input);
    if (a->dragged && !a->simulate) return hk_cli_usage_error(CMD, "--drag needs --simulate");
    if (a->simulate && (a->head_tf.given || a->hair_tf.given))
        return hk_cli_usage_error(CMD, "--simulate moves the setup's own head and shapes: no --scale, --up, "
                                       "--head-scale or --head-up");
    return -1;
}


#ifdef HK_HAVE_VIEWER
/* The scene of a setup file: its hair grown or loaded, head, colours, shaders. */
static hk_Status load_setup(ViewArgs *a, hk_Scene *scene, hk_HairFile *hair, int *guides, hk_Error *err)
{
    if (a->head_path || a->vis_path)
        return hk_error_set(err, HK_ERR_INVALID, "--head and --visuality are for a hair file; %s names its own",
                            a->input);
    hk_Status st = hk_scene_load(a->input, HK_SCENE_RENDERING | HK_SCENE_HAIR, scene, err);
    if (st != HK_OK) return st;
    /* SaveFile is written after the growing (and again when the viewer re-solves): a
     * path that cannot be written is said now, as groom and run do. */
    if ((a->usage_rc = hk_cli_setup_save_file(CMD, scene)) != 0) return HK_ERR_INVALID;
    if (scene->head.vertex_count) st = hk_cli_transform_mesh(&a->head_tf, scene->setup.head_model, &scene->head, err);
    if (st == HK_OK && scene->wick.vertex_count)
        st = hk_cli_transform_mesh(&a->head_tf, scene->setup.wick_model, &scene->wick, err);
    if (st == HK_OK && a->simulate && scene->setup.load)
        return hk_error_set(err, HK_ERR_INVALID,
                            "%s: Load true: --simulate grows its guides from HairstyleInfo and WickModel and cannot "
                            "simulate the hair of LoadFile (%s); set Load false",
                            a->input, scene->setup.load_file);
    hk_SceneHairReport report;
    memset(&report, 0, sizeof report);
    hk_GroomDef go = hk_default_groom_def();
    /* simulated: the live simulation grows the hair */
    if (st == HK_OK && !a->simulate) st = hk_scene_hair(scene, &go, hair, &report, err);
    *guides = report.grown ? report.guides : 0;
    if (st == HK_OK && !report.grown && !a->simulate) st = hk_cli_transform_hair(&a->hair_tf, hair, err);
    if (st == HK_OK && !a->quiet && !a->simulate) hk_cli_report_scene_hair(CMD, &scene->setup, hair, &report);
    if (st == HK_OK && !report.grown && !a->simulate)
        hk_cli_fine_hair(CMD, hair, HK_HUMAN_HAIR_DIAMETER, a->hair_tf.scale != 1.0, &a->ro);
    const char *setup_shader[4] = {scene->setup.head_vert, scene->setup.head_frag, scene->setup.hair_vert,
                                   scene->setup.hair_frag};
    for (int k = 0; k < 4; k++)
        if (!a->shader[k]) a->shader[k] = setup_shader[k];
    return st;
}

static int view(ViewArgs *a)
{
    hk_Error err;
    hk_Scene scene;
    memset(&scene, 0, sizeof scene);
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_Mesh head = {0, 0, NULL, NULL, NULL};
    hk_ViewerInput in;
    memset(&in, 0, sizeof in);
    in.visuality = hk_default_visuality();
    hk_HeadMotion *motion = NULL;
    hk_Status st = HK_OK;
    if (a->simulate || strcmp(a->motion.spec, "still") != 0) st = hk_cli_motion_create(&a->motion, &motion, &err);
    if (st == HK_OK && is_setup(a->input)) {
        st = load_setup(a, &scene, &hair, &in.guide_count, &err);
        in.visuality = scene.visuality;
        in.head = &scene.head;
        in.scene = &scene;
    } else if (st == HK_OK) {
        if (a->head_tf.given && !a->head_path) return hk_cli_usage_error(CMD, "--head-scale and --head-up need --head");
        st = hk_hair_read(a->input, HK_HAIR_FORMAT_AUTO, &hair, &err);
        if (st == HK_OK) st = hk_cli_transform_hair(&a->hair_tf, &hair, &err);
        if (st == HK_OK) hk_cli_fine_hair(CMD, &hair, HK_HUMAN_HAIR_DIAMETER, a->hair_tf.scale != 1.0, &a->ro);
        if (st == HK_OK && a->head_path) st = hk_mesh_load(a->head_path, &head, &err);
        if (st == HK_OK && a->head_path) st = hk_cli_transform_mesh(&a->head_tf, a->head_path, &head, &err);
        if (st == HK_OK && a->vis_path) st = hk_visuality_load(a->vis_path, &in.visuality, &err);
        in.head = &head;
    }
    int status = HK_EXIT_FAIL;
    if (st == HK_OK) {
        in.hair = &hair;
        in.render = a->ro;
        for (int k = 0; k < 4; k++) in.shader[k] = a->shader[k];
        in.frames = (int)a->frames;
        in.screenshot = a->screenshot;
        in.quiet = a->quiet;
        in.simulate = a->simulate;
        in.drag[0] = a->drag[0], in.drag[1] = a->drag[1];
        in.guides_only = a->show[0], in.show_wick = a->show[1], in.show_shapes = a->show[2];
        /* off headless: the screenshots of the tests stay the picture alone */
        in.overlay = a->overlay >= 0 ? a->overlay : a->frames == 0;
        in.live = a->live;
        in.motion = motion;
        status = hk_viewer_run(&in);
    } else if (a->usage_rc) {
        status = a->usage_rc;
    } else {
        hk_cli_fail(CMD, &err);
    }
    hk_head_motion_destroy(motion);
    hk_mesh_free(&head);
    hk_hair_free(&hair);
    hk_scene_free(&scene);
    return status;
}
#endif

int hk_cmd_view(int argc, char **argv)
{
    ViewArgs a;
    memset(&a, 0, sizeof a);
    a.ro = hk_default_render_def();
    a.hair_tf = hk_cli_default_transform();
    a.head_tf = hk_cli_default_transform();
    a.motion = hk_cli_default_motion();
    a.live = hk_default_live_sim_def();
    a.overlay = -1;
    const int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
#ifdef HK_HAVE_VIEWER
    return view(&a);
#else
    fprintf(stderr, "hairkit view: this hairkit was built without the viewer (HK_VIEWER off: GLFW or libepoxy "
                    "were not found); install them (scripts/install-deps.sh) and build again\n");
    return HK_EXIT_FAIL;
#endif
}
