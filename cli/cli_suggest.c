/* "Did you mean ...?" for misspelt options, subcommands and option values: the valid
 * name nearest to what was typed by edit distance (Levenshtein), offered only when it
 * is close enough to be the likely intent (issue 18, item 2). */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

#define HK_SUGGEST_MAX_LEN 64

size_t hk_cli_edit_distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > HK_SUGGEST_MAX_LEN || lb > HK_SUGGEST_MAX_LEN) return (size_t)-1;
    size_t row[HK_SUGGEST_MAX_LEN + 1];
    for (size_t j = 0; j <= lb; j++) row[j] = j;
    for (size_t i = 1; i <= la; i++) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            const size_t above = row[j];
            const size_t substitute = diagonal + (a[i - 1] != b[j - 1]);
            size_t best = above + 1 < row[j - 1] + 1 ? above + 1 : row[j - 1] + 1;
            if (substitute < best) best = substitute;
            row[j] = best;
            diagonal = above;
        }
    }
    return row[lb];
}

const char *hk_cli_nearest(const char *word, const char *const *names, size_t count)
{
    /* Close enough: two edits, or a third of the word for long names ("--shadowmap"). */
    const size_t len = strlen(word);
    const size_t limit = len / 3 > 2 ? len / 3 : 2;
    const char *best = NULL;
    size_t best_distance = limit + 1;
    for (size_t i = 0; i < count; i++) {
        const size_t d = hk_cli_edit_distance(word, names[i]);
        if (d < best_distance) best = names[i], best_distance = d;
    }
    /* A one-letter word is within two edits of every short name: no guess. */
    return len >= 2 ? best : NULL;
}

int hk_cli_unknown_option(const char *cmd, const struct option *options, const char *arg)
{
    const char *names[128];
    size_t count = 0;
    for (; options->name && count < sizeof names / sizeof *names; options++) names[count++] = options->name;
    /* "--frams=3": the name only. */
    char word[HK_SUGGEST_MAX_LEN + 1];
    const char *name = arg;
    while (*name == '-') name++;
    snprintf(word, sizeof word, "%.*s", (int)strcspn(name, "="), name);
    const char *nearest = name != arg && word[0] ? hk_cli_nearest(word, names, count) : NULL;
    if (nearest) return hk_cli_usage_error(cmd, "unknown option '%s' (did you mean --%s?)", arg, nearest);
    return hk_cli_usage_error(cmd, "unknown option '%s'", arg);
}

int hk_cli_bad_option(const char *cmd, int c, const struct option *options, char *const argv[])
{
    const char *word = argv[optind - 1];
    if (c == ':') return hk_cli_usage_error(cmd, "option '%s' needs a value", word);
    return hk_cli_unknown_option(cmd, options, word);
}

int hk_cli_unknown_name(const char *cmd, const char *what, const char *word, const char *const *names, size_t count)
{
    char list[512] = "";
    for (size_t i = 0; i < count; i++) {
        const size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? (i + 1 < count ? ", " : " or ") : "", names[i]);
    }
    const char *nearest = hk_cli_nearest(word, names, count);
    if (nearest) return hk_cli_usage_error(cmd, "unknown %s '%s' (did you mean %s?)", what, word, nearest);
    return hk_cli_usage_error(cmd, "unknown %s '%s' (%s)", what, word, list);
}
