/* hairkit bench: runs the benchmarks of bench/ and prints their figures. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "cli.h"

typedef struct Bench {
    const char *name;
    int (*run)(FILE *out, const hk_BenchOptions *options);
    const char *summary;
} Bench;

static const Bench benches[] = {
    {"statics", hk_bench_statics, "Super-Helix statics: Newton vs the thesis's Rosenbrock, N = 5..40"},
    {"groom", hk_bench_groom, "grooming examples/default with 1 and 2 threads"},
    {"render", hk_bench_render,
     "rendering examples/default at 64x48, 640x480, 1920x1080 with shadows, 1 and 2 threads"},
    {"dynamics", hk_bench_dynamics,
     "one strand's steps/s (dense and O(N)); 201 guides' frames/s, 1 and 2 threads, N = 10, 20, 40"},
    {"stability", hk_bench_stability,
     "single strands 5 cm..1.5 m, 7 head motions, dt 1/24 and 1/30 s: ran or failed, energy"},
    {"long-heads", hk_bench_long_heads,
     "201 guides of 1 m, 7 head motions, 10 s at 24 and 30 frames/s: ran, recovered, tip moves"},
    {"curvefit", hk_bench_curvefit, "helicoid fitting machinery: fits/s of 30-sample strands, 1 and 2 threads"},
    {"helicoid", hk_bench_helicoid,
     "helicoids: 90,000 hairs interpolated, fits/s of 30-vertex strands, reconstruction"},
    {"follicles", hk_bench_follicles,
     "thin-plate fit of 500..2000 points; follicles sampled on the wick, 1 and 2 threads"},
    {"view", hk_bench_view, "hairkit view headless: default head with/without shadows, guides200 live (frames/s)"},
    {"io", hk_bench_io, "Sintel .tfx -> .hair; 1M strands x 32 points .hair read and written against stdio"},
    {"import", hk_bench_import,
     "Sintel groom imported with 300 guides: time of each stage; the still-head drift after 2 s"},
};

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit bench [NAME...] [--quick] [--min-time SECONDS] [--root DIR]\n"
                 "\n"
                 "Runs benchmarks and prints their figures side by side (all of them when no\n"
                 "NAME is given). Timings are wall-clock on this machine.\n"
                 "\n"
                 "benchmarks:\n");
    for (size_t i = 0; i < sizeof benches / sizeof *benches; i++)
        fprintf(out, "  %-10s %s\n", benches[i].name, benches[i].summary);
    fprintf(out, "\n"
                 "options:\n"
                 "  --quick            smoke run: few repetitions, figures not meaningful\n"
                 "  --min-time S       measure each figure for at least S seconds (default 0.5)\n"
                 "  --root DIR         the hairkit source folder, for its examples (default .;\n"
                 "                     'io' and 'import' read DIR/../shared/hair-data when it\n"
                 "                     is there)\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "# Newton against the thesis's Rosenbrock on one strand", "hairkit bench statics",
                    "# the helicoid fitter, each figure measured for at least 2 s",
                    "hairkit bench curvefit --min-time 2", "# a smoke run of two benchmarks (figures not meaningful)",
                    "hairkit bench groom io --quick");
}

int hk_cmd_bench(int argc, char **argv)
{
    static const struct option options[] = {
        {"quick", no_argument, NULL, 'q'},
        {"min-time", required_argument, NULL, 't'},
        {"root", required_argument, NULL, 'r'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    hk_BenchOptions bo = {0, 0.5, "."};
    optind = 1;
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":h", options, NULL)) != -1) {
        switch (c) {
        case 'q':
            bo.quick = 1;
            break;
        case 't':
            if (!hk_cli_parse_double(optarg, &bo.min_seconds) || bo.min_seconds < 0 || bo.min_seconds > 3600)
                return hk_cli_usage_error("bench", "--min-time expects seconds in [0, 3600], got '%s'", optarg);
            break;
        case 'r':
            bo.root = optarg;
            break;
        case 'h':
            usage(stdout);
            return HK_EXIT_OK;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option("bench", c, options, argv);
        }
    }
    if (bo.quick) bo.min_seconds = 0.0;
    const char *names[sizeof benches / sizeof *benches];
    for (size_t b = 0; b < sizeof benches / sizeof *benches; b++) names[b] = benches[b].name;
    for (int i = optind; i < argc; i++) {
        int found = 0;
        for (size_t b = 0; b < sizeof benches / sizeof *benches; b++) found |= !strcmp(argv[i], benches[b].name);
        if (!found) return hk_cli_unknown_name("bench", "benchmark", argv[i], names, sizeof names / sizeof *names);
    }
    int rc = HK_EXIT_OK;
    for (size_t b = 0; b < sizeof benches / sizeof *benches; b++) {
        int selected = optind >= argc;
        for (int i = optind; i < argc; i++) selected |= !strcmp(argv[i], benches[b].name);
        if (selected && benches[b].run(stdout, &bo) != 0) rc = HK_EXIT_FAIL;
    }
    return rc;
}
