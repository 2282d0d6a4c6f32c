/* hairkit run: the main job. A setup file in, a picture out: the hair is loaded or
 * grown (as `groom` does), then rendered over the setup's head with its colours. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/core_internal.h"

static const char *const CMD = "run";

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit run SETUP.txt -o OUT.png [--hair OUT.hair] [--width W --height H] [options]\n"
                 "\n"
                 "The main job: reads a setup file (thesis Appendix B), grows the hair (guides\n"
                 "solved as Super-Helices under gravity and the collision shapes, then the\n"
                 "interpolated strands) or loads it ('Load true'), saves it when the setup says\n"
                 "'Save true', and renders it over HeadModel with the VisualityInfo colours.\n"
                 "LoadFile may be any hair format hairkit reads (.hair .tfx .data .ply .obj\n"
                 ".usda, by the extension); HeadModel and WickModel OBJ or PLY. Loaded hair whose\n"
                 "strand width is not a hair's (see 'hairkit render --help') is drawn at the\n"
                 "hairstyle's diameter (HairRadius1 + HairRadius2; 70 um without HairstyleInfo).\n"
                 "\n"
                 "options:\n"
                 "  -o, --output FILE  the PNG to write\n"
                 "  --hair FILE        also write the hair as a .hair file\n"
                 "  --scale S, --up AXIS  units and up axis of the LoadFile hair (Load true):\n"
                 "                     multiply by S (0.001: millimetres to metres), rotate AXIS\n"
                 "                     (+x -x +y -y +z -z) onto +y as 'hairkit convert' does\n"
                 "  --head-scale S, --head-up AXIS  the same for the head and wick meshes\n"
                 "                     (HeadModel, WickModel; not the collision shapes)\n");
    hk_cli_render_options_help(out);
    fprintf(out, "  --seed N           random seed of the interpolation (default 1)\n"
                 "  --threads N        threads to use (default: all cores); the results do not\n"
                 "                     depend on it\n"
                 "  --quiet            no progress or summary on stderr\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "hairkit run examples/default/setup.txt -o head.png",
                    "# a thesis coupe, smaller, with Marschner's shading",
                    "hairkit run examples/coupe2/setup.txt -o coupe2.png --width 640 --height 480 --shading marschner",
                    "# from behind, the hair also kept for 'hairkit render'",
                    "hairkit run examples/default/setup.txt -o back.png --view 180,10 --hair head.hair");
}

int hk_cmd_run(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"hair", required_argument, NULL, 'a'},
        {"seed", required_argument, NULL, 's'},
        {"threads", required_argument, NULL, 't'},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        HK_CLI_RENDER_LONG_OPTIONS,
        HK_CLI_HAIR_TRANSFORM_LONG_OPTIONS,
        HK_CLI_HEAD_TRANSFORM_LONG_OPTIONS,
        {NULL, 0, NULL, 0},
    };
    const char *output = NULL, *hair_out = NULL;
    hk_RenderDef ro = hk_default_render_def();
    hk_GroomDef go = hk_default_groom_def();
    hk_CliTransform hair_tf = hk_cli_default_transform(), head_tf = hk_cli_default_transform();
    int quiet = 0, c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        if (HK_CLI_IS_RENDER_OPTION(c)) {
            int rc = hk_cli_render_option(CMD, c, optarg, &ro);
            if (rc) return rc;
            continue;
        }
        if (HK_CLI_IS_TRANSFORM_OPTION(c)) {
            const int rc = hk_cli_transforms_option(CMD, c, optarg, &hair_tf, &head_tf);
            if (rc) return rc;
            continue;
        }
        switch (c) {
        case 'o':
            output = optarg;
            break;
        case 'a':
            hair_out = optarg;
            break;
        case 'q':
            quiet = 1;
            break;
        case 's': {
            int rc = hk_cli_seed_option(CMD, optarg, &go.seed);
            if (rc) return rc;
            break;
        }
        case 't': {
            int rc = hk_cli_threads_option(CMD, optarg, &ro.threads);
            if (rc) return rc;
            go.threads = ro.threads;
            break;
        }
        case 'h':
            usage(stdout);
            return HK_EXIT_OK;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, "missing SETUP file");
    if (operand_rc) return operand_rc;
    if (!output) return hk_cli_usage_error(CMD, "no output: give -o OUT.png");
    int out_rc = hk_cli_output_file(CMD, "-o", output, ".png");
    if (!out_rc && hair_out) out_rc = hk_cli_output_file(CMD, "--hair", hair_out, NULL);
    if (out_rc) return out_rc;

    hk_Error err;
    hk_Scene scene;
    hk_CliProgress progress = {!quiet && hk_cli_stderr_is_tty(), "", -1};
    go.progress = hk_cli_progress;
    go.progress_user = &progress;
    const double t0 = hk_seconds_now();
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_SceneHairReport report;
    hk_Canvas image = {0, 0, NULL};
    hk_RenderStats stats;
    int status = HK_EXIT_FAIL;
    /* hk_scene_load reads the small files first, so that their errors come before the
     * long work. */
    hk_Status st = hk_scene_load(argv[optind], HK_SCENE_RENDERING | HK_SCENE_HAIR, &scene, &err);
    if (st != HK_OK) return hk_cli_fail(CMD, &err);
    /* SaveFile is written after the growing: a path that cannot be written is said now. */
    const int save_rc = hk_cli_setup_save_file(CMD, &scene);
    if (save_rc) {
        hk_scene_free(&scene);
        return save_rc;
    }
    if (hair_tf.given && !scene.setup.load) {
        hk_scene_free(&scene);
        return hk_cli_usage_error(
            CMD, "--scale and --up are for hair read from LoadFile; %s grows its hair (Load false)", argv[optind]);
    }
    /* Loaded hair is drawn at the hairstyle's diameter when its file's width is not a
     * hair's: the hairstyle is read for it when the setup names one. */
    if (scene.setup.load && scene.setup.hairstyle) st = hk_scene_load_parts(&scene, HK_SCENE_HAIRSTYLE, &err);
    if (st == HK_OK && scene.head.vertex_count)
        st = hk_cli_transform_mesh(&head_tf, scene.setup.head_model, &scene.head, &err);
    if (st == HK_OK && scene.wick.vertex_count)
        st = hk_cli_transform_mesh(&head_tf, scene.setup.wick_model, &scene.wick, &err);
    if (st == HK_OK) st = hk_scene_hair(&scene, &go, &hair, &report, &err);
    hk_cli_progress_done(&progress);
    if (st == HK_OK && !report.grown) st = hk_cli_transform_hair(&hair_tf, &hair, &err);
    if (st == HK_OK && hair_out) st = hk_hair_save(hair_out, &hair, &err);
    if (st == HK_OK && !quiet) hk_cli_report_scene_hair(CMD, &scene.setup, &hair, &report);
    if (st == HK_OK && !report.grown) {
        const hk_StrandDef *strand = &scene.style.strand;
        const double diameter = scene.setup.hairstyle ? strand->radius1 + strand->radius2 : HK_HUMAN_HAIR_DIAMETER;
        hk_cli_fine_hair(CMD, &hair, diameter, hair_tf.scale != 1.0, &ro);
    }
    if (st == HK_OK) st = hk_scene_render(&scene, &hair, &ro, &image, &stats, &err);
    if (st == HK_OK) st = hk_render_write_png(&image, output, &err);
    if (st == HK_OK) {
        if (!quiet) {
            hk_cli_report_render(CMD, output, &ro, &stats);
            fprintf(stderr, "hairkit %s: %.2f s in all\n", CMD, hk_seconds_now() - t0);
        }
        status = HK_EXIT_OK;
    } else {
        hk_cli_fail(CMD, &err);
    }
    hk_canvas_free(&image);
    hk_hair_free(&hair);
    hk_scene_free(&scene);
    return status;
}
