/* Checked allocation: sizes are validated before any allocation is attempted, so
 * absurd counts from bad input become an error message, never a crash or a
 * machine brought to its knees. And the memory budget of a whole job (core.h). */
#include "hairkit/core.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* "16G", "16GiB", "500M", "8000000000": decimal digits, an optional fraction, then
 * k/M/G/T, an optional i (powers of 1024 instead of 1000) and an optional B. */
static int parse_size(const char *s, double *out)
{
    const char *p = s;
    double v = 0.0;
    int digits = 0;
    for (; *p >= '0' && *p <= '9'; p++, digits++) v = 10.0 * v + (*p - '0');
    if (*p == '.') {
        double place = 0.1;
        for (p++; *p >= '0' && *p <= '9'; p++, digits++, place *= 0.1) v += place * (*p - '0');
    }
    if (digits == 0) return 0;
    int power = 0;
    switch (*p) {
    case 'k':
    case 'K':
        power = 1;
        break;
    case 'm':
    case 'M':
        power = 2;
        break;
    case 'g':
    case 'G':
        power = 3;
        break;
    case 't':
    case 'T':
        power = 4;
        break;
    default:
        break;
    }
    double base = 1000.0;
    if (power) {
        p++;
        if (*p == 'i') base = 1024.0, p++;
    }
    if (*p == 'B' || *p == 'b') p++;
    if (*p != '\0') return 0;
    for (int i = 0; i < power; i++) v *= base;
    if (!(v >= 1.0 && v <= 1e18)) return 0;
    *out = v;
    return 1;
}

static double default_limit(void)
{
    double limit = HK_DEFAULT_MEMORY_LIMIT;
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0 && (double)pages * (double)page < limit) limit = (double)pages * (double)page;
    return limit;
}

hk_Status hk_memory_limit(double *bytes, hk_Error *err)
{
    const char *env = getenv(HK_MEMORY_LIMIT_ENV);
    if (env && *env) {
        if (parse_size(env, bytes)) return HK_OK;
        *bytes = default_limit();
        return hk_error_set(err, HK_ERR_INVALID, "%s='%s' is not a size (bytes, or e.g. 16G, 500M, 16GiB)",
                            HK_MEMORY_LIMIT_ENV, env);
    }
    *bytes = default_limit();
    return HK_OK;
}

hk_Status hk_memory_check(double bytes, const char *what, hk_Error *err)
{
    double limit;
    hk_Status st = hk_memory_limit(&limit, err);
    if (st != HK_OK) return st;
    if (bytes <= limit) return HK_OK;
    /* A suggestion that fits: the next power of two in GB above the need. */
    double suggest = 1.0;
    while (suggest < bytes / 1e9 && suggest < 1e9) suggest *= 2.0;
    return hk_error_set(
        err, HK_ERR_NOMEM,
        "%s would take about %.3g GB of memory, over the limit of %.3g GB (%s raises it, e.g. %s=%.0fG)", what,
        bytes / 1e9, limit / 1e9, HK_MEMORY_LIMIT_ENV, HK_MEMORY_LIMIT_ENV, suggest);
}

static int size_ok(size_t count, size_t size, size_t *bytes, hk_Error *err)
{
    if (size != 0 && count > SIZE_MAX / size) {
        hk_error_set(err, HK_ERR_NOMEM, "allocation of %zu x %zu bytes overflows", count, size);
        return 0;
    }
    *bytes = count * size;
    if (*bytes > HK_MAX_ALLOCATION) {
        /* Only here is the budget read (from the environment): a larger one, set on
         * purpose, lets a single array grow past HK_MAX_ALLOCATION too. */
        double limit = 0.0;
        hk_memory_limit(&limit, NULL);
        if ((double)*bytes > limit) {
            const size_t shown = limit > (double)HK_MAX_ALLOCATION ? (size_t)limit : (size_t)HK_MAX_ALLOCATION;
            hk_error_set(err, HK_ERR_NOMEM, "refusing to allocate %zu bytes (limit %zu)", *bytes, shown);
            return 0;
        }
    }
    if (*bytes == 0) *bytes = 1;
    return 1;
}

void *hk_alloc_array(size_t count, size_t size, hk_Error *err)
{
    size_t bytes;
    if (!size_ok(count, size, &bytes, err)) return NULL;
    void *p = malloc(bytes);
    if (!p) hk_error_set(err, HK_ERR_NOMEM, "out of memory allocating %zu bytes", bytes);
    return p;
}

void *hk_calloc_array(size_t count, size_t size, hk_Error *err)
{
    size_t bytes;
    if (!size_ok(count, size, &bytes, err)) return NULL;
    void *p = calloc(1, bytes);
    if (!p) hk_error_set(err, HK_ERR_NOMEM, "out of memory allocating %zu bytes", bytes);
    return p;
}

void hk_free(void *ptr) { free(ptr); }

char *hk_strdup(const char *s, hk_Error *err)
{
    const size_t n = strlen(s) + 1;
    char *d = hk_alloc_array(n, 1, err);
    if (d) memcpy(d, s, n);
    return d;
}
