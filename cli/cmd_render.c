/* hairkit render: a .hair file (hairkit's or another tool's) rendered over a head. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

static const char *const CMD = "render";

static void usage(FILE *out)
{
    fprintf(out,
            "usage: hairkit render HAIR.hair -o OUT.png [--head HEAD.obj] [--visuality V.txt]\n"
            "                      [--no-shadows] [--width W --height H] [options]\n"
            "\n"
            "Renders the strands of a cyHair .hair file on the CPU: Kajiya-Kay (or Marschner)\n"
            "shading, self-shadowing with deep opacity maps, exact transparency of the\n"
            "sub-pixel strands. The camera frames hair and head from a three-quarter front\n"
            "view. Strand width is the file's thickness (hairkit writes the hair diameter).\n"
            "\n"
            "options:\n"
            "  -o, --output FILE  the PNG to write\n"
            "  --head FILE        OBJ of the head (optional)\n"
            "  --visuality FILE   hair colours (thesis visuality file; default brown)\n");
    hk_cli_render_options_help(out);
    fprintf(out,
            "  --threads N        threads to use (default: all cores); the picture does not\n"
            "                     depend on it\n"
            "  --quiet            no summary on stderr\n"
            "  -h, --help         this help\n");
}

int hk_cmd_render(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'}, {"head", required_argument, NULL, 'H'},
        {"visuality", required_argument, NULL, 'v'}, {"threads", required_argument, NULL, 't'},
        {"quiet", no_argument, NULL, 'q'}, {"help", no_argument, NULL, 'h'},
        HK_CLI_RENDER_LONG_OPTIONS, {NULL, 0, NULL, 0},
    };
    const char *output = NULL, *head_path = NULL, *vis_path = NULL;
    hk_RenderDef ro = hk_default_render_def();
    int quiet = 0, c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        if (HK_CLI_IS_RENDER_OPTION(c)) {
            int rc = hk_cli_render_option(CMD, c, optarg, &ro);
            if (rc) return rc;
            continue;
        }
        switch (c) {
        case 'o': output = optarg; break;
        case 'H': head_path = optarg; break;
        case 'v': vis_path = optarg; break;
        case 'q': quiet = 1; break;
        case 't': {
            int rc = hk_cli_threads_option(CMD, optarg, &ro.threads);
            if (rc) return rc;
            break;
        }
        case 'h': usage(stdout); return HK_EXIT_OK;
        case ':': return hk_cli_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
        default: return hk_cli_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return hk_cli_usage_error(CMD, "missing HAIR.hair file");
    if (optind + 1 < argc) return hk_cli_usage_error(CMD, "unexpected argument '%s'", argv[optind + 1]);
    if (!output) return hk_cli_usage_error(CMD, "no output: give -o OUT.png");
    hk_Error err;
    hk_HairFile hair;
    hk_Mesh head = {0, 0, NULL, NULL, NULL};
    hk_Visuality vis = hk_default_visuality();
    hk_Canvas image = {0, 0, NULL};
    hk_RenderStats stats;
    int status = HK_EXIT_FAIL;
    hk_Status st = hk_hair_load(argv[optind], &hair, &err);
    if (st != HK_OK) return hk_cli_fail(CMD, &err);
    if (head_path) st = hk_obj_load(head_path, &head, &err);
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
