/* hairkit helicoid: generalized helicoids (Piuze, Kry and Siddiqi 2011): trace helicoid
 * files into hair, interpolate guides over a surface (helicoid_interpolate.c), fit
 * helicoids to .hair strands and reconstruct a full head from sparse fitted strands
 * (helicoid_fit.c); the work itself is the library's (hairkit/helicoid_hair.h). This
 * file: the options, tracing, and the dispatch. */
#include <getopt.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core_internal.h"
#include "helicoid_cli.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/rng.h"

static const char *const CMD = HK_HELICOID_CMD;

/* The actions, each with its synopsis and what it does: `hairkit helicoid ACTION --help`
 * prints its own, `hairkit helicoid --help` all of them. */
enum { TRACE = 1, INTERPOLATE = 2, FIT = 4, RECONSTRUCT = 8, ALL = 15 };
typedef struct Action {
    const char *name;
    int bit;
    const char *synopsis, *summary;
} Action;
static const Action actions[] = {
    {"trace", TRACE, "trace FILE.txt -o OUT.hair [--step S] [--seed N] [options]\n",
     "  trace        p-helicoid strands of a helicoid file (docs/file-formats.md), with\n"
     "               their waviness and wisps, as a .hair file\n"},
    {"interpolate", INTERPOLATE,
     "interpolate GUIDES.txt --surface MESH.obj -o OUT.hair\n"
     "               [--density D | --count N | --follicles SPACING [--head HEAD.obj]]\n"
     "               [--power P] [--seed N] [--params OUT.txt] [options]\n",
     "  interpolate  new strands rooted on a surface mesh (area-uniform random roots,\n"
     "               or follicles with --follicles), each the inverse-distance blend of\n"
     "               the file's guides (paper 4.1-4.3), their root frames averaged\n"
     "               relative to the surface normal so that every strand leaves it\n"},
    {"fit", FIT,
     "fit HAIR -o OUT.txt [--tolerance M] [--lambda L]\n"
     "               [--max-pieces N | --pieces N | --piece-length L [--root-piece R]]\n"
     "               [--method lm|nelder-mead | --waves] [options]\n",
     "  fit          a p-helicoid for every strand of HAIR, in metres and any hair\n"
     "               format hairkit reads (paper 5; docs/helicoid-fitting.md); prints\n"
     "               the error of every strand and in all (mean leash of the Frechet\n"
     "               coupling); writes a helicoid file\n"},
    {"reconstruct", RECONSTRUCT,
     "reconstruct HAIR -o OUT.hair [--every K] [--power P]\n"
     "               [--pieces N | --piece-length L [--root-piece R]] [options]\n",
     "  reconstruct  fits every K-th strand of HAIR (any format, metres) and\n"
     "               rebuilds every strand from its own root, root direction and\n"
     "               length by blending the traced fits of its nearest fitted strands\n"
     "               (paper 5.4); prints the error\n"},
};
#define ACTION_COUNT (sizeof actions / sizeof *actions)

/* Every option's help and the actions it is for. */
static const struct {
    int actions;
    const char *text;
} option_help[] = {
    {ALL, "  -o, --output FILE  the file to write\n"},
    {ALL, "  --step S           tracing step in metres (default: the file's Step, or 2 mm)\n"},
    {INTERPOLATE, "  --surface MESH     OBJ or PLY mesh the interpolated roots lie on\n"
                  "                     (e.g. assets/wick.obj)\n"},
    {INTERPOLATE, "  --density D        interpolated strands per cm^2 of the surface (default 100)\n"},
    {INTERPOLATE, "  --count N          or exactly N interpolated strands\n"},
    {INTERPOLATE, "  --follicles D      or one strand per follicle, follicles D metres apart spread\n"
                  "                     by repelling particles over an implicit surface fitted to the\n"
                  "                     --surface mesh (the wick) and the head around it (paper 4.3,\n"
                  "                     docs/follicle-sampling.md); 0.005 gives about 2,300 on\n"
                  "                     assets/wick.obj in a second or two, 0.003 about 6,400\n"
                  "                     in ten; the time grows as 1 / D^2 or faster\n"},
    {INTERPOLATE, "  --head MESH        with --follicles: the head mesh, whose vertices near the\n"
                  "                     wick are fitted too (e.g. assets/head.obj; optional)\n"},
    {INTERPOLATE | RECONSTRUCT, "  --power P          inverse-distance power (default 3, the paper's)\n"},
    {INTERPOLATE, "  --params FILE      also write the interpolated strands as a helicoid file\n"},
    {FIT | RECONSTRUCT, "  --tolerance M      accept a fit when its mean leash (normalised Frechet\n"
                        "                     coupling) is below M metres (default 0.0002)\n"},
    {FIT | RECONSTRUCT, "  --lambda L         regularisation of eq. 5 (default 1e-7)\n"},
    {FIT | RECONSTRUCT, "  --max-pieces N     most pieces per fitted strand (default 64; a piece is at\n"
                        "                     least 5 mm long, so a strand gets at most one per 5 mm)\n"},
    {FIT | RECONSTRUCT, "  --pieces N         exactly N pieces of equal length on every strand, the same\n"
                        "                     layout for all (default: split where each strand needs it;\n"
                        "                     reconstruct: --piece-length 0.03 --root-piece 0.01, a\n"
                        "                     piece of its own for the lift off the scalp)\n"},
    {FIT | RECONSTRUCT, "  --piece-length L   or pieces L metres long from the root (the same stretch of\n"
                        "                     hair for piece j on strands of any length; the last piece\n"
                        "                     takes what is left)\n"},
    {FIT | RECONSTRUCT, "  --root-piece R     with --piece-length: the first piece R metres long (a lift\n"
                        "                     off the scalp); default L\n"},
    {FIT | RECONSTRUCT, "  --method M         lm: Levenberg-Marquardt on point distances (default, fast);\n"
                        "                     nelder-mead: the paper's, on the Frechet coupling (slow)\n"},
    {FIT, "  --waves            fit each strand as a p-helicoid with waves of its own on top\n"
          "                     (eq. 4: amplitude, frequency, phase; a Waves line in the\n"
          "                     file): wavy strands in a few pieces instead of about 9 a\n"
          "                     wave (docs/helicoid-fitting.md 5e); kept only where it beats\n"
          "                     the plain fit; slower\n"},
    {RECONSTRUCT, "  --every K          reconstruct: fit one strand in K (default 10)\n"},
    {ALL, "  --seed N           random seed (default 1)\n"},
    {ALL, "  --threads N        threads (default: all cores); results do not depend on it\n"},
    {ALL, "  --quiet            no summary on stderr\n"},
    {ALL, "  -h, --help         this help\n"},
};

/* The help of one action (`which`), or of all of them (ALL). */
static void usage(FILE *out, int which)
{
    int first = 1;
    for (size_t i = 0; i < ACTION_COUNT; i++) {
        if (!(actions[i].bit & which)) continue;
        fprintf(out, "%s hairkit helicoid %s", first ? "usage:" : "      ", actions[i].synopsis);
        first = 0;
    }
    fprintf(out, "\nGeneralized helicoids (Piuze, Kry, Siddiqi; docs/helicoids.md):\n");
    for (size_t i = 0; i < ACTION_COUNT; i++)
        if (actions[i].bit & which) fputs(actions[i].summary, out);
    if (which == ALL) fprintf(out, "'hairkit helicoid ACTION --help' shows one action's options.\n");
    fprintf(out, "\noptions:\n");
    for (size_t i = 0; i < sizeof option_help / sizeof *option_help; i++)
        if (option_help[i].actions & which) fputs(option_help[i].text, out);
    switch (which) {
    case TRACE:
        HK_CLI_EXAMPLES(out, "hairkit helicoid trace examples/helicoid/curly.txt -o curly.hair",
                        "# a finer step along the strands",
                        "hairkit helicoid trace examples/helicoid/wisp.txt -o wisp.hair --step 0.001",
                        "hairkit render curly.hair -o curly.png");
        break;
    case INTERPOLATE:
        HK_CLI_EXAMPLES(out,
                        "hairkit helicoid interpolate examples/helicoid/guides.txt --surface assets/wick.obj -o "
                        "long.hair",
                        "# one strand per follicle, follicles 8 mm apart over the scalp",
                        "hairkit helicoid interpolate examples/helicoid/guides.txt --surface assets/wick.obj "
                        "--follicles 0.008 --head assets/head.obj -o follicles.hair",
                        "hairkit render long.hair --head assets/head.obj -o long.png");
        break;
    case FIT:
        HK_CLI_EXAMPLES(out, "hairkit helicoid trace examples/helicoid/wavy.txt -o wavy.hair",
                        "hairkit helicoid fit wavy.hair -o wavy-fit.txt",
                        "# the fitted helicoids traced back into strands",
                        "hairkit helicoid trace wavy-fit.txt -o wavy-again.hair");
        break;
    case RECONSTRUCT:
        HK_CLI_EXAMPLES(out,
                        "hairkit helicoid interpolate examples/helicoid/guides.txt --surface assets/wick.obj "
                        "--count 500 -o long.hair",
                        "# fit one strand in ten, interpolate the others from them",
                        "hairkit helicoid reconstruct long.hair -o rebuilt.hair --every 10");
        break;
    default:
        HK_CLI_EXAMPLES(out, "hairkit helicoid trace examples/helicoid/curly.txt -o curly.hair",
                        "hairkit helicoid fit curly.hair -o curly-fit.txt", "hairkit helicoid fit --help");
        break;
    }
}

static int parse_args(int argc, char **argv, hk_HelicoidArgs *a)
{
    enum {
        OPT_STEP = 3000,
        OPT_SURFACE,
        OPT_DENSITY,
        OPT_COUNT,
        OPT_POWER,
        OPT_PARAMS,
        OPT_TOLERANCE,
        OPT_LAMBDA,
        OPT_MAX_PIECES,
        OPT_EVERY,
        OPT_FOLLICLES,
        OPT_HEAD,
        OPT_PIECES,
        OPT_METHOD,
        OPT_PIECE_LENGTH,
        OPT_ROOT_PIECE,
        OPT_WAVES
    };
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"step", required_argument, NULL, OPT_STEP},
        {"surface", required_argument, NULL, OPT_SURFACE},
        {"density", required_argument, NULL, OPT_DENSITY},
        {"count", required_argument, NULL, OPT_COUNT},
        {"power", required_argument, NULL, OPT_POWER},
        {"params", required_argument, NULL, OPT_PARAMS},
        {"tolerance", required_argument, NULL, OPT_TOLERANCE},
        {"lambda", required_argument, NULL, OPT_LAMBDA},
        {"max-pieces", required_argument, NULL, OPT_MAX_PIECES},
        {"every", required_argument, NULL, OPT_EVERY},
        {"seed", required_argument, NULL, 's'},
        {"follicles", required_argument, NULL, OPT_FOLLICLES},
        {"head", required_argument, NULL, OPT_HEAD},
        {"pieces", required_argument, NULL, OPT_PIECES},
        {"piece-length", required_argument, NULL, OPT_PIECE_LENGTH},
        {"root-piece", required_argument, NULL, OPT_ROOT_PIECE},
        {"method", required_argument, NULL, OPT_METHOD},
        {"waves", no_argument, NULL, OPT_WAVES},
        {"threads", required_argument, NULL, 't'},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    memset(a, 0, sizeof *a);
    a->density = 100.0;
    a->power = 3.0;
    a->tolerance = hk_default_helicoid_fit_def().tolerance;
    a->lambda = hk_default_helicoid_fit_def().lambda;
    a->max_pieces = hk_default_helicoid_fit_def().max_pieces;
    a->every = 10;
    a->seed = 1;
    a->method = HK_CURVEFIT_LEAST_SQUARES;
    if (argc < 2) return hk_cli_usage_error(CMD, "missing action: trace, interpolate, fit or reconstruct");
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(stdout, ALL);
        return -1;
    }
    a->action = argv[1];
    int which = 0;
    const char *names[ACTION_COUNT];
    for (size_t i = 0; i < ACTION_COUNT; i++) {
        names[i] = actions[i].name;
        if (!strcmp(a->action, actions[i].name)) which = actions[i].bit;
    }
    if (!which) return hk_cli_unknown_name(CMD, "action", a->action, names, ACTION_COUNT);
    optind = 2;
    opterr = 0;
    int c, rc;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        switch (c) {
        case 'o':
            a->output = optarg;
            break;
        case OPT_SURFACE:
            a->surface = optarg;
            break;
        case OPT_PARAMS:
            a->params = optarg;
            break;
        case OPT_HEAD:
            a->head = optarg;
            break;
        case OPT_FOLLICLES:
            if (!hk_cli_parse_double(optarg, &a->follicles) || !(a->follicles > 0.0 && a->follicles <= 1.0))
                return hk_cli_usage_error(CMD, "--follicles expects a spacing in metres in (0, 1], got '%s'", optarg);
            break;
        case OPT_STEP:
            if (!hk_cli_parse_double(optarg, &a->step) || !(a->step > 0.0 && a->step <= 1.0))
                return hk_cli_usage_error(CMD, "--step expects metres in (0, 1], got '%s'", optarg);
            break;
        case OPT_DENSITY:
            if (!hk_cli_parse_double(optarg, &a->density) || !(a->density > 0.0 && a->density <= 100000.0))
                return hk_cli_usage_error(CMD, "--density expects strands per cm^2 in (0, 100000], got '%s'", optarg);
            a->density_given = 1;
            break;
        case OPT_COUNT:
            if (!hk_cli_parse_int(optarg, 1, 10000000, &a->count))
                return hk_cli_usage_error(CMD, "--count expects 1 to 10000000, got '%s'", optarg);
            break;
        case OPT_POWER:
            if (!hk_cli_parse_double(optarg, &a->power) || !(a->power > 0.0 && a->power <= 20.0))
                return hk_cli_usage_error(CMD, "--power expects a number in (0, 20], got '%s'", optarg);
            break;
        case OPT_TOLERANCE:
            if (!hk_cli_parse_double(optarg, &a->tolerance) || !(a->tolerance > 0.0))
                return hk_cli_usage_error(CMD, "--tolerance expects metres > 0, got '%s'", optarg);
            break;
        case OPT_LAMBDA:
            if (!hk_cli_parse_double(optarg, &a->lambda) || !(a->lambda >= 0.0))
                return hk_cli_usage_error(CMD, "--lambda expects a number >= 0, got '%s'", optarg);
            break;
        case OPT_MAX_PIECES:
            if (!hk_cli_parse_int(optarg, 1, HK_HELICOID_MAX_PIECES, &a->max_pieces))
                return hk_cli_usage_error(CMD, "--max-pieces expects 1 to %d, got '%s'", HK_HELICOID_MAX_PIECES,
                                          optarg);
            a->max_pieces_given = 1;
            break;
        case OPT_PIECES:
            if (!hk_cli_parse_int(optarg, 0, HK_HELICOID_MAX_PIECES, &a->pieces))
                return hk_cli_usage_error(CMD, "--pieces expects 0 (split as needed) to %d, got '%s'",
                                          HK_HELICOID_MAX_PIECES, optarg);
            a->pieces_given = 1;
            break;
        case OPT_PIECE_LENGTH:
        case OPT_ROOT_PIECE: {
            double *v = c == OPT_PIECE_LENGTH ? &a->piece_length : &a->root_piece;
            if (!hk_cli_parse_double(optarg, v) || !(*v > 0.0 && *v <= 10.0))
                return hk_cli_usage_error(CMD, "--%s expects metres in (0, 10], got '%s'",
                                          c == OPT_PIECE_LENGTH ? "piece-length" : "root-piece", optarg);
            break;
        }
        case OPT_METHOD:
            if (!strcmp(optarg, "lm"))
                a->method = HK_CURVEFIT_LEAST_SQUARES;
            else if (!strcmp(optarg, "nelder-mead"))
                a->method = HK_CURVEFIT_NELDER_MEAD;
            else
                return hk_cli_usage_error(CMD, "--method expects lm or nelder-mead, got '%s'", optarg);
            break;
        case OPT_WAVES:
            a->waves = 1;
            break;
        case OPT_EVERY:
            if (!hk_cli_parse_int(optarg, 1, 1000000, &a->every))
                return hk_cli_usage_error(CMD, "--every expects 1 to 1000000, got '%s'", optarg);
            break;
        case 's':
            if ((rc = hk_cli_seed_option(CMD, optarg, &a->seed))) return rc;
            break;
        case 't':
            if ((rc = hk_cli_threads_option(CMD, optarg, &a->threads))) return rc;
            break;
        case 'q':
            a->quiet = 1;
            break;
        case 'h':
            usage(stdout, which);
            return -1;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    char missing[64];
    snprintf(missing, sizeof missing, "%s: missing input file", a->action);
    const int operand_rc = hk_cli_one_operand(CMD, argc, argv, missing);
    if (operand_rc) return operand_rc;
    a->input = argv[optind];
    if (!a->output) return hk_cli_usage_error(CMD, "no output: give -o FILE");
    if (!strcmp(a->action, "interpolate") && !a->surface)
        return hk_cli_usage_error(CMD, "interpolate needs --surface MESH.obj for the roots");
    if (a->follicles > 0.0 && (a->count || a->density_given))
        return hk_cli_usage_error(CMD, "--follicles places one strand per follicle: drop --%s",
                                  a->count ? "count" : "density");
    if ((a->pieces > 0 || a->piece_length > 0.0) && a->max_pieces_given)
        return hk_cli_usage_error(CMD, "--%s fixes the layout: drop --max-pieces",
                                  a->pieces > 0 ? "pieces" : "piece-length");
    if (a->pieces_given && a->piece_length > 0.0)
        return hk_cli_usage_error(CMD, "--pieces and --piece-length are two layouts: give one");
    if (a->root_piece > 0.0 && !(a->piece_length > 0.0))
        return hk_cli_usage_error(CMD,
                                  "--root-piece is the first piece of a --piece-length layout: give --piece-length");
    if (a->waves && strcmp(a->action, "fit"))
        return hk_cli_usage_error(CMD, "--waves is for fit (a p-helicoid with waves of its own for every strand)");
    if (a->waves &&
        (a->pieces_given || a->piece_length > 0.0 || a->max_pieces_given || a->method != HK_CURVEFIT_LEAST_SQUARES))
        return hk_cli_usage_error(CMD, "--waves chooses its own layout (the base in pieces of about 7 cm) and "
                                       "Levenberg-Marquardt: drop --pieces, --piece-length, --max-pieces, --method");
    if (a->head && !(a->follicles > 0.0))
        return hk_cli_usage_error(CMD, "--head is fitted with the wick by --follicles: give --follicles SPACING");
    if ((rc = hk_cli_output_file(CMD, "-o", a->output, NULL))) return rc;
    if (a->params && (rc = hk_cli_output_file(CMD, "--params", a->params, NULL))) return rc;
    return 0;
}

static int do_trace(const hk_HelicoidArgs *a)
{
    hk_Error err;
    hk_HelicoidSet set;
    if (hk_helicoid_file_load(a->input, &set, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    const double step = a->step > 0.0 ? a->step : set.step;
    const double t0 = hk_seconds_now();
    hk_Status st = hk_helicoid_set_trace(&set, step, a->seed, a->threads, &hair, &err);
    if (st == HK_OK) st = hk_hair_save(a->output, &hair, &err);
    if (st == HK_OK && !a->quiet)
        fprintf(stderr, "hairkit %s trace: %d helicoid strands, %u hair strands (with wisps), %u points in %.3f s\n",
                CMD, set.count, hair.strand_count, hair.point_count, hk_seconds_now() - t0);
    hk_hair_free(&hair);
    hk_helicoid_set_free(&set);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

int hk_cmd_helicoid(int argc, char **argv)
{
    hk_HelicoidArgs a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc < 0 ? HK_EXIT_OK : rc;
    if (!strcmp(a.action, "trace")) return do_trace(&a);
    if (!strcmp(a.action, "interpolate")) return hk_helicoid_cli_interpolate(&a);
    if (!strcmp(a.action, "fit")) return hk_helicoid_cli_fit(&a);
    return hk_helicoid_cli_reconstruct(&a);
}
