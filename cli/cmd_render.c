/* hairkit render: hair in any format hairkit reads (hairkit's or another tool's) rendered
 * over a head (OBJ or PLY), with the units and up axis of both. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

static const char *const CMD = "render";

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit render HAIR -o OUT.png [--head HEAD.obj] [--visuality V.txt]\n"
                 "                      [--width W --height H] [options]\n"
                 "\n"
                 "Renders hair strands on the CPU: Kajiya-Kay (or Marschner) shading,\n"
                 "self-shadowing with deep opacity maps, exact transparency of the sub-pixel\n"
                 "strands. The camera frames hair and head from a three-quarter front view.\n"
                 "HAIR is any format hairkit reads, by its extension (.hair .tfx .data .ply .obj\n"
                 ".usda, as 'hairkit convert'). Strand width is the file's thickness (hairkit\n"
                 "writes the hair diameter). When the file gives none per strand and its default\n"
                 "is not a hair's (over 1%% of the groom's extent or over 0.5 mm: other tools\n"
                 "write 1.0), hair 70 um across is drawn in the file's units (--scale says them,\n"
                 "otherwise they are guessed from the extent) and stderr says so.\n"
                 "\n"
                 "options:\n"
                 "  -o, --output FILE  the PNG to write\n"
                 "  --head FILE        the head mesh, OBJ or PLY (by the extension; optional)\n"
                 "  --visuality FILE   hair colours (thesis visuality file; default brown)\n");
    hk_cli_transform_help(out, 1, 1);
    hk_cli_render_options_help(out);
    fprintf(out, "  --threads N        threads to use (default: all cores); the picture does not\n"
                 "                     depend on it\n"
                 "  --quiet            no summary on stderr\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "hairkit groom examples/default/setup.txt -o head.hair",
                    "hairkit render head.hair --head assets/head.obj --visuality examples/default/visuality.txt -o "
                    "head.png",
                    "# the hair alone, from the left, with Marschner's shading",
                    "hairkit render head.hair -o side.png --view -90,10 --shading marschner --width 640 --height 480");
}

int hk_cmd_render(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"head", required_argument, NULL, 'H'},
        {"visuality", required_argument, NULL, 'v'},
        {"threads", required_argument, NULL, 't'},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        HK_CLI_RENDER_LONG_OPTIONS,
        HK_CLI_HAIR_TRANSFORM_LONG_OPTIONS,
        HK_CLI_HEAD_TRANSFORM_LONG_OPTIONS,
        {NULL, 0, NULL, 0},
    };
    const char *output = NULL, *head_path = NULL, *vis_path = NULL;
    hk_RenderDef ro = hk_default_render_def();
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
        case 'H':
            head_path = optarg;
            break;
        case 'v':
            vis_path = optarg;
            break;
        case 'q':
            quiet = 1;
            break;
        case 't': {
            int rc = hk_cli_threads_option(CMD, optarg, &ro.threads);
            if (rc) return rc;
            break;
        }
        case 'h':
            usage(stdout);
            return HK_EXIT_OK;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, "missing HAIR file");
    if (operand_rc) return operand_rc;
    if (head_tf.given && !head_path) return hk_cli_usage_error(CMD, "--head-scale and --head-up need --head");
    if (!output) return hk_cli_usage_error(CMD, "no output: give -o OUT.png");
    const int out_rc = hk_cli_output_file(CMD, "-o", output, ".png");
    if (out_rc) return out_rc;
    hk_Error err;
    hk_HairFile hair;
    hk_Mesh head = {0, 0, NULL, NULL, NULL};
    hk_Visuality vis = hk_default_visuality();
    hk_Canvas image = {0, 0, NULL};
    hk_RenderStats stats;
    int status = HK_EXIT_FAIL;
    hk_Status st = hk_hair_read(argv[optind], HK_HAIR_FORMAT_AUTO, &hair, &err);
    if (st != HK_OK) return hk_cli_fail(CMD, &err);
    st = hk_cli_transform_hair(&hair_tf, &hair, &err);
    if (st == HK_OK) hk_cli_fine_hair(CMD, &hair, HK_HUMAN_HAIR_DIAMETER, hair_tf.scale != 1.0, &ro);
    if (st == HK_OK && head_path) st = hk_mesh_load(head_path, &head, &err);
    if (st == HK_OK && head_path) st = hk_cli_transform_mesh(&head_tf, head_path, &head, &err);
    if (st == HK_OK && vis_path) st = hk_visuality_load(vis_path, &vis, &err);
    if (st == HK_OK) st = hk_render(&hair, head_path ? &head : NULL, &vis, &ro, &image, &stats, &err);
    if (st == HK_OK) st = hk_render_write_png(&image, output, &err);
    if (st == HK_OK) {
        if (!quiet) hk_cli_report_render(CMD, output, &ro, &stats);
        status = HK_EXIT_OK;
    } else {
        hk_cli_fail(CMD, &err);
    }
    hk_canvas_free(&image);
    hk_mesh_free(&head);
    hk_hair_free(&hair);
    return status;
}
