/* Shared pieces of the hairkit command-line tool: subcommand entry points and the
 * small helpers they all use (argument parsing, error printing). */
#ifndef HK_CLI_H
#define HK_CLI_H

#include <stdio.h>

#include "hairkit/core.h"
#include "hairkit/vecmath.h"

/* Exit codes: 0 success, 1 failure (bad input file, I/O, numerics), 2 usage error. */
#define HK_EXIT_OK 0
#define HK_EXIT_FAIL 1
#define HK_EXIT_USAGE 2

/* Subcommands: argv[0] is the subcommand name. */
int hk_cmd_strand(int argc, char **argv);
int hk_cmd_bench(int argc, char **argv);
int hk_cmd_groom(int argc, char **argv);
int hk_cmd_info(int argc, char **argv);

/* "x,y,z" -> vector; returns 0 on malformed or non-finite input. */
int hk_cli_parse_vec3(const char *text, hk_Vec3 *out);
/* Whole-string finite number; returns 0 otherwise. */
int hk_cli_parse_double(const char *text, double *out);
/* Whole-string integer in [lo, hi]; returns 0 otherwise. */
int hk_cli_parse_int(const char *text, long lo, long hi, long *out);

/* Prints "hairkit <cmd>: <message>" to stderr and returns HK_EXIT_FAIL. */
int hk_cli_fail(const char *cmd, const hk_Error *err);
/* Prints "hairkit <cmd>: <formatted>" and "Try 'hairkit <cmd> --help'." and returns
 * HK_EXIT_USAGE. */
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
int hk_cli_usage_error(const char *cmd, const char *fmt, ...);

/* Whether progress and summaries may go to stderr (a terminal and not --quiet). */
int hk_cli_stderr_is_tty(void);

/* Progress bar on stderr for long work (hk_ProgressFn-compatible): redraws one line
 * "stage [#####.....]  45%"; `user` is an hk_CliProgress. */
typedef struct hk_CliProgress {
    int enabled;          /* stderr is a terminal and --quiet was not given */
    char stage[32];
    int last_percent;
} hk_CliProgress;
void hk_cli_progress(void *user, const char *stage, double fraction);
/* Ends the bar's line (if one was drawn). */
void hk_cli_progress_done(hk_CliProgress *p);

/* Monotonic wall clock in seconds. */
double hk_cli_now(void);

#endif
