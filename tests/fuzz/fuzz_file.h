/* Shared by the libFuzzer harnesses (tests/fuzz/README.md). hairkit's parsers read
 * paths, so each input is written to a file in a private folder (made at the first
 * input, removed at exit) and loaded from there. The memory budget is set to 1 GB so
 * that an input the parsers accept never trips libFuzzer's 2 GB malloc limit. */
#ifndef HK_FUZZ_FILE_H
#define HK_FUZZ_FILE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hairkit/core.h"

static char hk_fuzz_dir[256];
static char hk_fuzz_paths[8][512];
static int hk_fuzz_path_count;

static void hk_fuzz_cleanup(void)
{
    for (int i = 0; i < hk_fuzz_path_count; i++) unlink(hk_fuzz_paths[i]);
    rmdir(hk_fuzz_dir);
}

/* Writes size bytes to DIR/name and returns that path (NULL when it cannot). */
static const char *hk_fuzz_write(const char *name, const uint8_t *data, size_t size)
{
    if (!hk_fuzz_dir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(hk_fuzz_dir, sizeof hk_fuzz_dir, "%s/hairkit-fuzz-XXXXXX", base && *base ? base : "/tmp");
        if (!mkdtemp(hk_fuzz_dir)) abort();
        atexit(hk_fuzz_cleanup);
        setenv(HK_MEMORY_LIMIT_ENV, "1G", 1);
    }
    int slot = -1;
    char path[512];
    snprintf(path, sizeof path, "%s/%s", hk_fuzz_dir, name);
    for (int i = 0; i < hk_fuzz_path_count; i++)
        if (strcmp(hk_fuzz_paths[i], path) == 0) slot = i;
    if (slot < 0) {
        if (hk_fuzz_path_count == 8) abort();
        slot = hk_fuzz_path_count++;
        memcpy(hk_fuzz_paths[slot], path, sizeof path);
    }
    FILE *f = fopen(hk_fuzz_paths[slot], "wb");
    if (!f) return NULL;
    if (size) fwrite(data, 1, size, f);
    fclose(f);
    return hk_fuzz_paths[slot];
}

#endif
