/* Atomic output files: written under a temporary name in the destination folder and
 * renamed over the destination only when complete, so that a crash or an error never
 * leaves a half-written or truncated output (and never destroys an older good one).
 * Internal to hairkit: these functions are not exported from the shared library (no HK_API). */
#ifndef HAIRKIT_OUTFILE_H
#define HAIRKIT_OUTFILE_H

#include <stdio.h>

#include "hairkit/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hk_OutFile {
    FILE *fp;          /* write here */
    char *path;        /* final destination */
    char *tmp_path;    /* temporary file next to it */
} hk_OutFile;

/* Creates the temporary file for `path` (binary mode). */
hk_Status hk_outfile_open(hk_OutFile *out, const char *path, hk_Error *err);

/* Flushes, closes and renames the temporary file onto the destination. On failure
 * the temporary file is removed and the destination left as it was. */
hk_Status hk_outfile_commit(hk_OutFile *out, hk_Error *err);

/* Closes and removes the temporary file (after an error). Safe to call twice. */
void hk_outfile_abort(hk_OutFile *out);

#ifdef __cplusplus
}
#endif

#endif
