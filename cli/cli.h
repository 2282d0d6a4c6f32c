/* Shared pieces of the hairkit command-line tool: subcommand entry points and the
 * small helpers they all use (argument parsing, error printing). */
#ifndef HK_CLI_H
#define HK_CLI_H

#include <stdint.h>
#include <stdio.h>

#include "hairkit/core.h"
#include "hairkit/groom.h"
#include "hairkit/hair_formats.h"
#include "hairkit/hairfile.h"
#include "hairkit/io.h"
#include "hairkit/render.h"
#include "hairkit/scene.h"
#include "hairkit/vecmath.h"

/* Exit codes, one rule for every command (README, "Exit codes"): 0 success; 1 bad input
 * data or a failed computation (a file that cannot be read or parsed, numerics, I/O
 * during the work); 2 a bad command line (unknown options, bad values, output paths of
 * the wrong kind), always said before any long work starts. */
#define HK_EXIT_OK    0
#define HK_EXIT_FAIL  1
#define HK_EXIT_USAGE 2

/* Subcommands: argv[0] is the subcommand name. */
int hk_cmd_strand(int argc, char **argv);
int hk_cmd_bench(int argc, char **argv);
int hk_cmd_groom(int argc, char **argv);
int hk_cmd_info(int argc, char **argv);
int hk_cmd_render(int argc, char **argv);
int hk_cmd_run(int argc, char **argv);
int hk_cmd_simulate(int argc, char **argv);
int hk_cmd_helicoid(int argc, char **argv);
int hk_cmd_convert(int argc, char **argv);
int hk_cmd_import(int argc, char **argv);
int hk_cmd_view(int argc, char **argv);

/* "x,y,z" -> vector; returns 0 on malformed or non-finite input. */
int hk_cli_parse_vec3(const char *text, hk_Vec3 *out);
/* Whole-string finite number; returns 0 otherwise. */
int hk_cli_parse_double(const char *text, double *out);
/* "A,B": two finite numbers separated by a comma; 0 when malformed. */
int hk_cli_parse_pair(const char *text, double *a, double *b);
/* Whole-string integer in [lo, hi]; returns 0 otherwise. */
int hk_cli_parse_int(const char *text, long lo, long hi, long *out);

/* --threads N (1 to 1024) and --seed N (a non-negative integer): 0 when parsed into
 * *out, else the usage error's exit code (the message names cmd). */
int hk_cli_threads_option(const char *cmd, const char *value, int *out);
int hk_cli_seed_option(const char *cmd, const char *value, uint64_t *out);

/* Prints "hairkit <cmd>: <message>" to stderr and returns HK_EXIT_FAIL. */
int hk_cli_fail(const char *cmd, const hk_Error *err);
/* Prints "hairkit <cmd>: <formatted>" and "Try 'hairkit <cmd> --help'." and returns
 * HK_EXIT_USAGE. */
int hk_cli_usage_error(const char *cmd, const char *fmt, ...) HK_PRINTF_LIKE(2, 3);

/* The one operand of a command after its options (argv[optind]): 0 when there is exactly
 * one, else the usage error "<missing>" (e.g. "missing SETUP file") or "unexpected
 * argument '...'". */
int hk_cli_one_operand(const char *cmd, int argc, char *const argv[], const char *missing);

/* ---- did you mean (cli_suggest.c) ---- */
struct option;
/* Levenshtein distance of two names (SIZE_MAX beyond 64 characters). */
size_t hk_cli_edit_distance(const char *a, const char *b);
/* The name nearest to `word`, or NULL when none is within max(2, len/3) edits. */
const char *hk_cli_nearest(const char *word, const char *const *names, size_t count);
/* The usage error of an unknown option `arg` (argv's word), naming the nearest long
 * option of the getopt_long table: "unknown option '--frams' (did you mean --frames?)". */
int hk_cli_unknown_option(const char *cmd, const struct option *options, const char *arg);
/* The usage error of getopt_long's answer `c` outside a command's options (the option
 * string begins with ':'): "option '--x' needs a value" for ':', else the unknown
 * option's error above; argv's word is argv[optind - 1]. Returns HK_EXIT_USAGE. */
int hk_cli_bad_option(const char *cmd, int c, const struct option *options, char *const argv[]);
/* "unknown WHAT 'word' (did you mean NAME?)", or the list of names when none is near;
 * returns HK_EXIT_USAGE. */
int hk_cli_unknown_name(const char *cmd, const char *what, const char *word, const char *const *names, size_t count);

/* ---- output paths, checked before the work (cli_outputs.c) ---- */
/* -o FILE and the like: refused (usage error, exit 2) when it is a folder, when its
 * folder is missing or not writable, or when `extension` (e.g. ".png"; NULL: any) is
 * not its ending. A FIFO or a character device is accepted whatever its name.
 * 0 when it may be written, else HK_EXIT_USAGE. */
int hk_cli_output_file(const char *cmd, const char *option, const char *path, const char *extension);
/* -o DIR of commands that write a folder of files: made with its parents (mkdir -p);
 * refused when it is a file, when it is named like a file hairkit writes (head.hair)
 * and does not exist, or when it cannot be made or written. 0 or HK_EXIT_USAGE. */
int hk_cli_output_folder(const char *cmd, const char *option, const char *dir);
/* The setup's SaveFile ('Save true'), checked as -o FILE is, once the setup is read and
 * before the hair is grown: 0 when the setup does not save or the file may be written,
 * else HK_EXIT_USAGE. */
int hk_cli_setup_save_file(const char *cmd, const hk_Scene *scene);

/* The section that ends every --help: "examples (...):" and one command a line, run
 * from the repository root on the bundled examples; lines starting with '#' explain
 * the next. tests/cli/help.sh runs every one of them, so that they cannot drift. */
void hk_cli_examples(FILE *out, const char *const *lines, size_t count);
#define HK_CLI_EXAMPLES(out, ...)                                                                                      \
    do {                                                                                                               \
        static const char *const hk_examples_[] = {__VA_ARGS__};                                                       \
        hk_cli_examples(out, hk_examples_, sizeof hk_examples_ / sizeof *hk_examples_);                                \
    } while (0)

/* Whether progress and summaries may go to stderr (a terminal and not --quiet). */
int hk_cli_stderr_is_tty(void);

/* Progress bar on stderr for long work (hk_ProgressFn-compatible): redraws one line
 * "stage [#####.....]  45%"; `user` is an hk_CliProgress. */
typedef struct hk_CliProgress {
    int enabled; /* stderr is a terminal and --quiet was not given */
    char stage[32];
    int last_percent;
} hk_CliProgress;
void hk_cli_progress(void *user, const char *stage, double fraction);
/* The bar followed by a note, e.g. the time left; redrawn at every call. */
void hk_cli_progress_note(hk_CliProgress *p, const char *stage, double fraction, const char *note);
/* "12 s", "4 min 3 s", "1 h 5 min". */
void hk_cli_format_duration(double seconds, char *buf, size_t size);
/* Ends the bar's line (if one was drawn). */
void hk_cli_progress_done(hk_CliProgress *p);

/* ---- the hair of a setup file (report_hair.c) ---- */
/* One line on stderr: what hk_scene_hair loaded or grew. */
void hk_cli_report_scene_hair(const char *cmd, const hk_Setup *setup, const hk_HairFile *hair,
                              const hk_SceneHairReport *report);

/* ---- render options (render_options.c) ---- */
/* getopt_long codes of the render options; add HK_CLI_RENDER_LONG_OPTIONS to the
 * option table and pass these codes to hk_cli_render_option. */
enum {
    HK_OPT_WIDTH = 1000,
    HK_OPT_HEIGHT,
    HK_OPT_NO_SHADOWS,
    HK_OPT_SHADING,
    HK_OPT_SCATTERING,
    HK_OPT_VIEW,
    HK_OPT_LIGHT,
    HK_OPT_SHADOW_MAP,
    HK_OPT_ALL_STRANDS,
    HK_OPT_THICKNESS
};
#define HK_CLI_RENDER_LONG_OPTIONS                                                                                     \
    {"width", required_argument, NULL, HK_OPT_WIDTH}, {"height", required_argument, NULL, HK_OPT_HEIGHT},              \
        {"no-shadows", no_argument, NULL, HK_OPT_NO_SHADOWS}, {"shading", required_argument, NULL, HK_OPT_SHADING},    \
        {"view", required_argument, NULL, HK_OPT_VIEW}, {"light", required_argument, NULL, HK_OPT_LIGHT},              \
        {"scattering", required_argument, NULL, HK_OPT_SCATTERING},                                                    \
        {"shadow-map", required_argument, NULL, HK_OPT_SHADOW_MAP},                                                    \
        {"all-strands", no_argument, NULL, HK_OPT_ALL_STRANDS},                                                        \
    {                                                                                                                  \
        "thickness", required_argument, NULL, HK_OPT_THICKNESS                                                         \
    }
#define HK_CLI_IS_RENDER_OPTION(c) ((c) >= HK_OPT_WIDTH && (c) <= HK_OPT_THICKNESS)
/* Applies one render option; 0 on success, else the usage error's exit code. */
int hk_cli_render_option(const char *cmd, int option, const char *value, hk_RenderDef *o);
void hk_cli_render_options_help(FILE *out);
void hk_cli_report_render(const char *cmd, const char *path, const hk_RenderDef *o, const hk_RenderStats *s);

/* ---- units and up axis of foreign files (transform_options.c) ---- */
/* --scale / --up (hair) and --head-scale / --head-up (head meshes): add the codes to
 * the option table and pass the option's name to hk_cli_transform_option. */
enum { HK_OPT_HAIR_SCALE = 1200, HK_OPT_HAIR_UP, HK_OPT_HEAD_SCALE, HK_OPT_HEAD_UP };
#define HK_CLI_HAIR_TRANSFORM_LONG_OPTIONS                                                                             \
    {"scale", required_argument, NULL, HK_OPT_HAIR_SCALE}, { "up", required_argument, NULL, HK_OPT_HAIR_UP }
#define HK_CLI_HEAD_TRANSFORM_LONG_OPTIONS                                                                             \
    {"head-scale", required_argument, NULL, HK_OPT_HEAD_SCALE}, { "head-up", required_argument, NULL, HK_OPT_HEAD_UP }
#define HK_CLI_IS_TRANSFORM_OPTION(c) ((c) >= HK_OPT_HAIR_SCALE && (c) <= HK_OPT_HEAD_UP)
typedef struct hk_CliTransform {
    double scale; /* 1: none */
    hk_Axis up;   /* HK_AXIS_POS_Y: none */
    int given;    /* an option set it */
} hk_CliTransform;
hk_CliTransform hk_cli_default_transform(void);
/* Parses the value of --OPTION (a name containing "scale", or an up axis); 0 when set,
 * else the usage error's exit code. */
int hk_cli_transform_option(const char *cmd, const char *option, const char *value, hk_CliTransform *t);
/* The same by option code (HK_OPT_HAIR_* into *hair, HK_OPT_HEAD_* into *head), for the
 * commands that take both. */
int hk_cli_transforms_option(const char *cmd, int code, const char *value, hk_CliTransform *hair,
                             hk_CliTransform *head);
hk_Status hk_cli_transform_hair(const hk_CliTransform *t, hk_HairFile *hair, hk_Error *err);
hk_Status hk_cli_transform_mesh(const hk_CliTransform *t, const char *path, hk_Mesh *mesh, hk_Error *err);
void hk_cli_transform_help(FILE *out, int hair, int head);
/* Plausible strand width for a foreign groom: when --thickness was not given
 * (ro->hair_thickness <= 0) and the file's width is not hair's
 * (hk_hair_thickness_implausible), sets ro->hair_thickness to `diameter` (metres) in the
 * file's units (metres when `metres`, else guessed from the extent), says so on stderr
 * and returns 1; 0 otherwise. */
int hk_cli_fine_hair(const char *cmd, const hk_HairFile *hair, double diameter, int metres, hk_RenderDef *ro);
/* For commands that take hair in metres: when the groom's extent suggests millimetres or
 * centimetres (hk_hair_guess_meters_per_unit), says so on stderr with the `hairkit
 * convert` that fixes it, and returns 1; 0 otherwise. Only a warning: a groom may be
 * that large or small on purpose. */
int hk_cli_warn_units(const char *cmd, const char *path, const hk_HairFile *hair);

/* ---- head motion options (motion_options.c) ---- */
enum { HK_OPT_MOTION = 1100, HK_OPT_AMPLITUDE, HK_OPT_FREQUENCY };
#define HK_CLI_MOTION_LONG_OPTIONS                                                                                     \
    {"motion", required_argument, NULL, HK_OPT_MOTION}, {"amplitude", required_argument, NULL, HK_OPT_AMPLITUDE},      \
    {                                                                                                                  \
        "frequency", required_argument, NULL, HK_OPT_FREQUENCY                                                         \
    }
#define HK_CLI_IS_MOTION_OPTION(c) ((c) >= HK_OPT_MOTION && (c) <= HK_OPT_FREQUENCY)
typedef struct hk_CliMotion {
    const char *spec; /* a scripted motion's name or a motion file */
    double amplitude; /* given with has_amplitude */
    double frequency; /* Hz */
    int has_amplitude;
} hk_CliMotion;
struct hk_HeadMotion;
hk_CliMotion hk_cli_default_motion(void);
/* Applies one motion option; 0 on success, else the usage error's exit code. */
int hk_cli_motion_option(const char *cmd, int option, const char *value, hk_CliMotion *m);
void hk_cli_motion_options_help(FILE *out);
hk_Status hk_cli_motion_create(const hk_CliMotion *m, struct hk_HeadMotion **out, hk_Error *err);

/* ---- hairkit strand --simulate (strand_simulate.c) ---- */
typedef struct hk_CliStrandSim {
    int enabled;
    double duration, dt;
    int damping, dense, euler, quiet;
    const char *tip_csv;
    hk_CliMotion motion;
} hk_CliStrandSim;
hk_CliStrandSim hk_cli_default_strand_sim(void);
struct hk_SuperHelix;
struct hk_StrandEnvDef;
/* Simulates the strand from rest and prints its shape at the end (the strand command's
 * contract); returns the exit code. */
int hk_cli_strand_simulate(const char *cmd, const hk_CliStrandSim *sim, const hk_Hairstyle *def,
                           struct hk_SuperHelix *sh, const struct hk_StrandEnvDef *env, const char *plot,
                           const hk_Shape *shapes, int shape_count);

#endif
