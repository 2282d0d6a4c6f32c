/* hairkit groom: a setup file in, a full head of hair out (.hair), Lansink 2010 §4.1.4
 * and §4.2.2 (load or grow, optionally save). */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/core_internal.h"
#include "hairkit/groom.h"
#include "hairkit/io.h"

static const char *const CMD = "groom";

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit groom SETUP.txt -o OUT.hair [--seed N] [--threads N] [--quiet]\n"
                 "\n"
                 "Grows a full head of hair from a setup file: one guide strand per vertex of the\n"
                 "wick (WickModel), each a Super-Helix at rest under gravity and the collision\n"
                 "shapes' envelopes, then area x HairDensity interpolated strands per wick\n"
                 "triangle. With 'Load true' in the setup the hair is read from LoadFile instead;\n"
                 "with 'Save true' it is also written to SaveFile.\n"
                 "\n"
                 "options:\n"
                 "  -o, --output FILE  the .hair file to write (optional when the setup saves)\n"
                 "  --seed N           random seed of the interpolation (default 1); the same\n"
                 "                     seed gives the same bytes whatever the thread count\n"
                 "  --threads N        threads to use (default: all cores)\n"
                 "  --quiet            no progress bar (shown on a terminal) or summary on stderr\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "hairkit groom examples/default/setup.txt -o head.hair",
                    "# the same bytes with one thread as with all of them",
                    "hairkit groom examples/coupe4/setup.txt -o coupe4.hair --seed 7 --threads 1",
                    "hairkit info coupe4.hair");
}

int hk_cmd_groom(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},  {"seed", required_argument, NULL, 's'},
        {"threads", required_argument, NULL, 't'}, {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},          {NULL, 0, NULL, 0},
    };
    const char *output = NULL;
    hk_GroomDef go = hk_default_groom_def();
    int quiet = 0;
    optind = 1;
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        switch (c) {
        case 'o':
            output = optarg;
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
            int rc = hk_cli_threads_option(CMD, optarg, &go.threads);
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
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, "missing SETUP file");
    if (operand_rc) return operand_rc;
    const char *setup_path = argv[optind];
    if (output) {
        const int rc = hk_cli_output_file(CMD, "-o", output, NULL);
        if (rc) return rc;
    }

    hk_Error err;
    hk_Scene scene;
    if (hk_scene_load(setup_path, 0, &scene, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    if (!output && !scene.setup.save) {
        hk_scene_free(&scene);
        return hk_cli_usage_error(CMD, "no output: give -o OUT.hair (or 'Save true' in the setup)");
    }
    /* SaveFile is written after the growing: a path that cannot be written is said now. */
    const int save_rc = hk_cli_setup_save_file(CMD, &scene);
    if (save_rc) {
        hk_scene_free(&scene);
        return save_rc;
    }
    hk_CliProgress progress = {!quiet && hk_cli_stderr_is_tty(), "", -1};
    go.progress = hk_cli_progress;
    go.progress_user = &progress;

    int status = HK_EXIT_FAIL;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_SceneHairReport report;
    const double t0 = hk_seconds_now();
    hk_Status st = hk_scene_load_parts(&scene, HK_SCENE_HAIR, &err);
    if (st == HK_OK) st = hk_scene_hair(&scene, &go, &hair, &report, &err);
    hk_cli_progress_done(&progress);
    if (st == HK_OK && output) st = hk_hair_save(output, &hair, &err);
    if (st == HK_OK) {
        if (!quiet) {
            hk_cli_report_scene_hair(CMD, &scene.setup, &hair, &report);
            fprintf(stderr, "hairkit %s: %.2f s in all\n", CMD, hk_seconds_now() - t0);
        }
        status = HK_EXIT_OK;
    } else {
        hk_cli_fail(CMD, &err);
    }
    hk_hair_free(&hair);
    hk_scene_free(&scene);
    return status;
}
