/* hairkit import: a groom (any hair format) and a head made Super-Helix guides at rest,
 * written as a setup that `hairkit simulate` runs (hk_import_run; docs/capture.md). The
 * command parses and prints; the pipeline is the library's. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "hairkit/capture.h"

static const char *const CMD = "import";

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit import HAIR --head MESH -o DIR [--scale S] [--up AXIS]\n"
                 "                      [--head-scale S] [--head-up AXIS] [--guides K] [--elements N]\n"
                 "                      [--hairstyle STYLE.txt] [--threads N] [--seed N] [--quiet]\n"
                 "\n"
                 "Makes a groom in any hair format (.hair .tfx .data .ply .obj .usda) Super-Helices\n"
                 "at rest on a head (docs/capture.md, \"Importing a groom\"): strand points inside\n"
                 "the head are moved out; K guides are chosen by farthest-point sampling of the\n"
                 "roots, each fitted with a Super-Helix and given the natural shape that makes the\n"
                 "captured shape its rest under gravity and the head (inverse statics); every\n"
                 "strand follows its 3 nearest guides. Writes DIR/setup.txt (run by\n"
                 "'hairkit simulate DIR/setup.txt'), DIR/hairstyle.txt, DIR/head.obj (the head as\n"
                 "scaled and turned), DIR/guides.txt and DIR/strands.hair.\n"
                 "\n"
                 "options:\n"
                 "  --head MESH        the head, OBJ or PLY: the collider (a signed distance field)\n"
                 "  -o, --output DIR   the folder to write (made if missing)\n");
    hk_cli_transform_help(out, 1, 1);
    fprintf(out, "  --guides K         guides (default: one per 75 strands; K >= the strands: every\n"
                 "                     strand is a guide)\n"
                 "  --elements N       Super-Helix elements of every guide (default: chosen per\n"
                 "                     strand from its length and the fit's error)\n"
                 "  --hairstyle FILE   the material (radii, Young, Poisson, Density, Gravity) and the\n"
                 "                     dynamics' friction; copied to DIR (default: 40 um, 3 GPa)\n"
                 "  --threads N        threads (default: all cores); the files do not depend on it\n"
                 "  --seed N           the first guide of the sampling (default 1)\n"
                 "  --quiet            no progress and summary on stderr\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "# 500 long strands on the default head's scalp, made by helicoids",
                    "hairkit helicoid interpolate examples/helicoid/guides.txt --surface assets/wick.obj --count 500 "
                    "-o long.hair",
                    "hairkit import long.hair --head assets/head.obj -o imported",
                    "hairkit simulate imported/setup.txt --frames 30 --fps 30 --motion nod --guides-only -o "
                    "imported/frames");
}

enum { OPT_HEAD = 1, OPT_GUIDES, OPT_ELEMENTS, OPT_HAIRSTYLE, OPT_THREADS, OPT_SEED, OPT_QUIET };

int hk_cmd_import(int argc, char **argv)
{
    static const struct option options[] = {
        {"head", required_argument, NULL, OPT_HEAD},
        {"output", required_argument, NULL, 'o'},
        HK_CLI_HAIR_TRANSFORM_LONG_OPTIONS,
        HK_CLI_HEAD_TRANSFORM_LONG_OPTIONS,
        {"guides", required_argument, NULL, OPT_GUIDES},
        {"elements", required_argument, NULL, OPT_ELEMENTS},
        {"hairstyle", required_argument, NULL, OPT_HAIRSTYLE},
        {"threads", required_argument, NULL, OPT_THREADS},
        {"seed", required_argument, NULL, OPT_SEED},
        {"quiet", no_argument, NULL, OPT_QUIET},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    hk_ImportRunDef d = hk_default_import_run_def();
    hk_CliTransform hair_tf = hk_cli_default_transform(), head_tf = hk_cli_default_transform();
    int quiet = 0, c, rc;
    long n;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        if (HK_CLI_IS_TRANSFORM_OPTION(c)) {
            if ((rc = hk_cli_transforms_option(CMD, c, optarg, &hair_tf, &head_tf))) return rc;
            continue;
        }
        switch (c) {
        case OPT_HEAD:
            d.head = optarg;
            break;
        case 'o':
            d.dir = optarg;
            break;
        case OPT_GUIDES:
            if (!hk_cli_parse_int(optarg, 1, HK_MAX_IMPORT_STRANDS, &n))
                return hk_cli_usage_error(CMD, "--guides expects 1 to %d, got '%s'", HK_MAX_IMPORT_STRANDS, optarg);
            d.groom.guides = (int)n;
            break;
        case OPT_ELEMENTS:
            if (!hk_cli_parse_int(optarg, 1, 64, &n))
                return hk_cli_usage_error(CMD, "--elements expects 1 to 64, got '%s'", optarg);
            d.groom.fit.elements = (int)n;
            break;
        case OPT_HAIRSTYLE:
            d.hairstyle = optarg;
            break;
        case OPT_THREADS:
            if ((rc = hk_cli_threads_option(CMD, optarg, &d.groom.threads))) return rc;
            break;
        case OPT_SEED:
            if ((rc = hk_cli_seed_option(CMD, optarg, &d.groom.seed))) return rc;
            break;
        case OPT_QUIET:
            quiet = 1;
            break;
        case 'h':
            usage(stdout);
            return HK_EXIT_OK;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, "missing the HAIR file");
    if (operand_rc) return operand_rc;
    if (!d.head) return hk_cli_usage_error(CMD, "missing --head MESH (the collider)");
    if (!d.dir) return hk_cli_usage_error(CMD, "missing -o DIR");
    d.hair = argv[optind];
    const int out_rc = hk_cli_output_folder(CMD, "-o", d.dir);
    if (out_rc) return out_rc;
    d.scale = hair_tf.scale, d.up = hair_tf.up;
    d.head_scale = head_tf.scale, d.head_up = head_tf.up;
    hk_CliProgress progress = {!quiet && hk_cli_stderr_is_tty(), "", -1};
    d.groom.progress = hk_cli_progress;
    d.groom.progress_user = &progress;
    hk_ImportRunReport r;
    hk_Error err;
    const hk_Status st = hk_import_run(&d, &r, &err);
    hk_cli_progress_done(&progress);
    if (st != HK_OK) return hk_cli_fail(CMD, &err);
    if (!quiet) {
        const hk_GroomImportReport *g = &r.groom;
        fprintf(stderr, "hairkit %s: %d strands (%ld points), %d guides; wrote %s/setup.txt\n", CMD, g->strands,
                r.points, g->guides, d.dir);
        fprintf(stderr, "  head: %d triangles, field %d x %d x %d nodes\n", r.head_triangles, r.field_size[0],
                r.field_size[1], r.field_size[2]);
        fprintf(stderr, "  moved out of the head: %d strands, %ld points, by %.3f mm at most, %.3f mm on average\n",
                g->moved_strands, g->moved_points, 1e3 * g->moved_max, 1e3 * g->moved_mean);
        fprintf(stderr, "  fit: mean error %.3f mm (worst guide %.3f mm, largest point error %.3f mm), %.1f elements\n",
                1e3 * g->fit_mean, 1e3 * g->fit_worst, 1e3 * g->fit_max, g->elements_mean);
        fprintf(stderr, "  inverse statics: %d guides unstable", g->unstable);
        if (g->unstable)
            fprintf(stderr,
                    ", %d settled to the stable rest nearby (moved %.2f mm at most); %d of them, moved more than "
                    "%g mm, are followed by no strand",
                    g->settled, 1e3 * g->drift_max, g->unfollowed, 1e3 * HK_IMPORT_MAX_DRIFT);
        fprintf(stderr,
                "\n  time: %.2f s (read %.2f, head field %.2f, push out %.2f, guides %.2f, fit and inverse "
                "%.2f [CPU: fits %.2f, inversions %.2f], attach %.2f, write %.2f)\n",
                r.seconds, r.seconds_read, r.seconds_field, g->seconds_push, g->seconds_choose, g->seconds_fit,
                g->task_seconds_fit, g->task_seconds_inverse, g->seconds_attach, r.seconds_write);
    }
    return HK_EXIT_OK;
}
