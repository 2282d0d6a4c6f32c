/* hairkit: command-line front end. Each subcommand lives in its own file (cmd_*.c)
 * and is a thin layer over the library. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "io/outfile.h"

typedef struct Command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} Command;

static const Command commands[] = {
    {"run", hk_cmd_run, "the main job: a setup file in, a picture of the groomed head out"},
    {"strand", hk_cmd_strand, "rest shape (or motion, --simulate) of one Super-Helix strand"},
    {"groom", hk_cmd_groom, "grow a full head of hair from a setup file into a .hair file"},
    {"info", hk_cmd_info, "strands, points, lengths, bounding box and units of a hair file"},
    {"convert", hk_cmd_convert, "hair files between formats: .hair .tfx .data .ply .obj .usda"},
    {"render", hk_cmd_render, "render a .hair file over a head into a PNG"},
    {"import", hk_cmd_import, "a groom and a head made guides at rest: a setup simulate runs"},
    {"view", hk_cmd_view, "the interactive OpenGL viewer: turn the head, move the light"},
    {"simulate", hk_cmd_simulate, "a full head of hair in motion: frames of .hair and PNG"},
    {"helicoid", hk_cmd_helicoid, "generalized helicoids: trace, interpolate, fit, reconstruct"},
    {"bench", hk_cmd_bench, "benchmarks with side-by-side figures"},
};

static void print_help(FILE *out)
{
    fprintf(out,
            "hairkit %s - natural hair: Super-Helix statics and dynamics, grooming, rendering, helicoids\n"
            "\n"
            "usage: hairkit COMMAND [ARGS...]\n"
            "       hairkit COMMAND --help | hairkit help COMMAND [SUBCOMMAND]\n"
            "       hairkit --version\n"
            "\n"
            "commands:\n",
            hk_version());
    for (size_t i = 0; i < sizeof commands / sizeof *commands; i++)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n"
                 "Units are SI (metres, pascals, kg/m^3); y is up and gravity points along -y.\n"
                 "Input files are the thesis's text files; hair is read and written as cyHair .hair,\n"
                 "TressFX .tfx, USC-HairSalon .data, PLY, OBJ polylines and USD ascii\n"
                 "(docs/file-formats.md).\n"
                 "\n"
                 "Exit codes: 0 success, 1 bad input data or a failed computation, 2 a bad\n"
                 "command line (options, values, output paths), said before any long work.\n");
    HK_CLI_EXAMPLES(out, "# grow the default head (about 124,000 strands) and draw it",
                    "hairkit run examples/default/setup.txt -o head.png",
                    "# the rest shape of one strand, drawn from the side and the front",
                    "hairkit strand examples/strand/curly.txt --plot strand.png", "hairkit help simulate");
}

int main(int argc, char **argv)
{
    /* Ctrl-C or a kill while an output is written leaves no OUT.tmp-XXXXXX behind. */
    hk_outfile_cleanup_on_signals();
    if (argc < 2) {
        print_help(stderr);
        return HK_EXIT_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        if (argc > 2 && strcmp(argv[1], "help") == 0) {
            const char *names[sizeof commands / sizeof *commands];
            for (size_t i = 0; i < sizeof commands / sizeof *commands; i++) {
                names[i] = commands[i].name;
                if (!strcmp(argv[2], commands[i].name)) {
                    /* "hairkit help helicoid fit": the subcommand's own help. */
                    char *sub[] = {argv[2], argc > 3 ? argv[3] : "--help", "--help", NULL};
                    return commands[i].run(argc > 3 ? 3 : 2, sub);
                }
            }
            const char *nearest = hk_cli_nearest(argv[2], names, sizeof names / sizeof *names);
            fprintf(stderr, "hairkit: no command '%s'%s%s%s\nTry 'hairkit --help'.\n", argv[2],
                    nearest ? " (did you mean " : "", nearest ? nearest : "", nearest ? "?)" : "");
            return HK_EXIT_USAGE;
        }
        print_help(stdout);
        return HK_EXIT_OK;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("hairkit %s\n", hk_version());
        return HK_EXIT_OK;
    }
    const char *names[sizeof commands / sizeof *commands];
    for (size_t i = 0; i < sizeof commands / sizeof *commands; i++) {
        if (!strcmp(argv[1], commands[i].name)) return commands[i].run(argc - 1, argv + 1);
        names[i] = commands[i].name;
    }
    const char *nearest = hk_cli_nearest(argv[1], names, sizeof names / sizeof *names);
    if (nearest)
        fprintf(stderr, "hairkit: unknown command '%s' (did you mean %s?)\nTry 'hairkit --help'.\n", argv[1], nearest);
    else
        fprintf(stderr, "hairkit: unknown command '%s'\nTry 'hairkit --help'.\n", argv[1]);
    return HK_EXIT_USAGE;
}
