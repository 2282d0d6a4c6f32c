/* Helpers shared by the hairkit subcommands: argument parsing and error reporting. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"

int hk_cli_parse_double(const char *text, double *out)
{
    if (!text || !*text) return 0;
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

int hk_cli_parse_int(const char *text, long lo, long hi, long *out)
{
    if (!text || !*text) return 0;
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (*end != '\0' || errno == ERANGE || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

int hk_cli_parse_vec3(const char *text, hk_Vec3 *out)
{
    double v[3];
    const char *p = text;
    for (int i = 0; i < 3; i++) {
        char *end;
        errno = 0;
        v[i] = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v[i])) return 0;
        p = end;
        if (i < 2) {
            if (*p != ',') return 0;
            p++;
        }
    }
    if (*p != '\0') return 0;
    *out = hk_v3(v[0], v[1], v[2]);
    return 1;
}

int hk_cli_fail(const char *cmd, const hk_Error *err)
{
    fprintf(stderr, "hairkit %s: %s\n", cmd, err->message[0] ? err->message : hk_status_name(err->code));
    return HK_EXIT_FAIL;
}

int hk_cli_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "hairkit %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\nTry 'hairkit %s --help'.\n", cmd);
    return HK_EXIT_USAGE;
}

int hk_cli_one_operand(const char *cmd, int argc, char *const argv[], const char *missing)
{
    if (optind >= argc) return hk_cli_usage_error(cmd, "%s", missing);
    if (optind + 1 < argc) return hk_cli_usage_error(cmd, "unexpected argument '%s'", argv[optind + 1]);
    return 0;
}

int hk_cli_stderr_is_tty(void) { return isatty(STDERR_FILENO); }

void hk_cli_progress(void *user, const char *stage, double fraction)
{
    hk_cli_progress_note(user, stage, fraction, NULL);
}

void hk_cli_progress_note(hk_CliProgress *p, const char *stage, double fraction, const char *note)
{
    if (!p->enabled) return;
    const int percent = (int)(100.0 * fraction + 0.5);
    const int new_stage = strncmp(p->stage, stage, sizeof p->stage - 1) != 0;
    /* A note (the time left) changes more often than the percentage: redraw for it. */
    if (!new_stage && percent == p->last_percent && !note) return;
    if (new_stage && p->stage[0]) fputc('\n', stderr);
    snprintf(p->stage, sizeof p->stage, "%s", stage);
    p->last_percent = percent;
    char bar[31];
    const int filled = percent * 30 / 100;
    for (int i = 0; i < 30; i++) bar[i] = i < filled ? '#' : '.';
    bar[30] = '\0';
    /* \033[K clears what a longer note left at the end of the line. */
    fprintf(stderr, "\r%-8s [%s] %3d%%%s%s\033[K", stage, bar, percent, note ? "  " : "", note ? note : "");
    fflush(stderr);
}

void hk_cli_format_duration(double seconds, char *buf, size_t size)
{
    if (!(seconds >= 0.0)) seconds = 0.0;
    if (seconds < 60.0)
        snprintf(buf, size, "%.0f s", seconds);
    else if (seconds < 3600.0)
        snprintf(buf, size, "%.0f min %.0f s", floor(seconds / 60.0), fmod(seconds, 60.0));
    else
        snprintf(buf, size, "%.0f h %.0f min", floor(seconds / 3600.0), floor(fmod(seconds, 3600.0) / 60.0));
}

void hk_cli_progress_done(hk_CliProgress *p)
{
    if (p->enabled && p->stage[0]) fputc('\n', stderr);
    p->stage[0] = '\0';
}

int hk_cli_threads_option(const char *cmd, const char *value, int *out)
{
    long n;
    if (!hk_cli_parse_int(value, 1, 1024, &n))
        return hk_cli_usage_error(cmd, "--threads expects 1 to 1024, got '%s'", value);
    *out = (int)n;
    return 0;
}

int hk_cli_seed_option(const char *cmd, const char *value, uint64_t *out)
{
    char *end;
    errno = 0;
    const unsigned long long v = strtoull(value, &end, 10);
    if (!*value || *end || errno || value[0] == '-')
        return hk_cli_usage_error(cmd, "--seed expects a non-negative integer, got '%s'", value);
    *out = v;
    return 0;
}

void hk_cli_examples(FILE *out, const char *const *lines, size_t count)
{
    fprintf(out, "\nexamples (from the hairkit folder, on its bundled examples):\n");
    for (size_t i = 0; i < count; i++) fprintf(out, "  %s\n", lines[i]);
}
