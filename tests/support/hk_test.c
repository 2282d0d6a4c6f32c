/* Shared helpers for the cmocka tests (see hk_test.h). */
#define _XOPEN_SOURCE 700 /* nftw */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ftw.h>
#include <unistd.h>

static char tmpdir[256];

/* Removes one entry of the private folder, deepest first (nftw). */
static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    remove(path);
    return 0;
}

/* Removes the private folder and everything the test put in it, folders too (a
 * simulation's frame folder was left behind in /tmp by every run). */
static void remove_tmpdir(void) { nftw(tmpdir, remove_entry, 16, FTW_DEPTH | FTW_PHYS); }

const char *hk_test_tmpdir(void)
{
    if (!tmpdir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(tmpdir, sizeof tmpdir, "%s/hairkit-test-XXXXXX", base && *base ? base : "/tmp");
        if (!mkdtemp(tmpdir)) {
            fprintf(stderr, "cannot create temporary folder %s\n", tmpdir);
            abort();
        }
        atexit(remove_tmpdir);
    }
    return tmpdir;
}

#define SLOTS 64
static char paths[SLOTS][512];
static int next_slot;

const char *hk_test_write_file(const char *name, const void *data, size_t size)
{
    char *path = paths[next_slot++ % SLOTS];
    snprintf(path, 512, "%s/%s", hk_test_tmpdir(), name);
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        fprintf(stderr, "cannot write %s\n", path);
        abort();
    }
    return path;
}

const char *hk_test_write_text(const char *name, const char *text)
{
    return hk_test_write_file(name, text, strlen(text));
}

void hk_assert_near_impl(double a, double b, double tol, const char *as, const char *bs, const char *file, int line)
{
    if (!(fabs(a - b) <= tol)) {
        print_error("%s = %.17g and %s = %.17g differ by %.3g > %.3g\n", as, a, bs, b, fabs(a - b), tol);
        _fail(file, line);
    }
}

void hk_assert_rel_impl(double a, double b, double rtol, double floor, const char *as, const char *bs, const char *file,
                        int line)
{
    double scale = fmax(fmax(fabs(a), fabs(b)), floor);
    if (!(fabs(a - b) <= rtol * scale)) {
        print_error("%s = %.17g and %s = %.17g: relative difference %.3g > %.3g\n", as, a, bs, b, fabs(a - b) / scale,
                    rtol);
        _fail(file, line);
    }
}

void hk_assert_contains_impl(const char *haystack, const char *needle, const char *file, int line)
{
    if (!haystack || !strstr(haystack, needle)) {
        print_error("expected \"%s\" to contain \"%s\"\n", haystack ? haystack : "(null)", needle);
        _fail(file, line);
    }
}

double hk_test_uniform(void)
{
    static unsigned long long state = 88172645463325252ULL;
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return (double)(state >> 11) / 9007199254740992.0;
}

size_t hk_test_mutate(char *buf, size_t len, size_t cap, const char *plausible, const char *const *junk, int junk_count,
                      unsigned long long *state)
{
    unsigned long long x = *state;
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    *state = x;
    if (len == 0) return 0;
    size_t at = (size_t)(x % len);
    switch ((x >> 20) % 5) {
    case 0:
        buf[at] = (char)(x >> 32);
        return len; /* any byte */
    case 1:
        return at; /* truncate */
    case 2:
        buf[at] = plausible[(x >> 40) % strlen(plausible)];
        return len; /* plausible byte */
    case 3: {       /* insert junk */
        const char *j = junk[(x >> 44) % (unsigned)junk_count];
        size_t jl = strlen(j);
        if (len + jl > cap) return len;
        memmove(buf + at + jl, buf + at, len - at);
        memcpy(buf + at, j, jl);
        return len + jl;
    }
    default: { /* delete a span */
        size_t span = (size_t)((x >> 50) % 24);
        if (at + span > len) span = len - at;
        memmove(buf + at, buf + at + span, len - at - span);
        return len - span;
    }
    }
}

#ifndef HK_SHARED_DATA_DIR
#define HK_SHARED_DATA_DIR "../shared/hair-data"
#endif

int hk_test_have_shared_data(void)
{
    if (access(HK_SHARED_DATA_DIR "/SOURCES.md", R_OK) == 0) return 1;
    print_message("skipped: %s is absent (the real grooms and heads of ../shared/hair-data)\n", HK_SHARED_DATA_DIR);
    return 0;
}

const char *hk_test_shared_path(const char *name)
{
    static char buf[4][1024];
    static int slot;
    char *p = buf[slot++ % 4];
    snprintf(p, sizeof buf[0], "%s/%s", HK_SHARED_DATA_DIR, name);
    return p;
}
