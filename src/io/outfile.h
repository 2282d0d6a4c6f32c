/* Atomic output files: written under a temporary name in the destination folder and
 * renamed over the destination only when complete, so that a crash or an error never
 * leaves a half-written or truncated output (and never destroys an older good one).
 *
 * A destination that is a symbolic link is followed: the file it names (made if the
 * link dangles) is replaced, the link stays. An existing destination that is not a
 * regular file is never replaced: a FIFO or a character device (/dev/null,
 * /dev/stdout) is written in place, without a temporary (so without the atomicity);
 * a folder, a block device or a socket is refused with a message.
 *
 * Internal to hairkit (not installed, not exported): included as "io/outfile.h". */
#ifndef HK_IO_OUTFILE_H
#define HK_IO_OUTFILE_H

#include <stdio.h>

#include "hairkit/core.h"

typedef struct hk_OutFile {
    FILE *fp;       /* write here */
    char *path;     /* final destination (the links followed) */
    char *tmp_path; /* temporary file next to it; NULL when written in place */
} hk_OutFile;

/* Creates the temporary file for `path` (binary mode). */
hk_Status hk_outfile_open(hk_OutFile *out, const char *path, hk_Error *err);

/* Flushes, closes and renames the temporary file onto the destination. On failure
 * the temporary file is removed and the destination left as it was. */
hk_Status hk_outfile_commit(hk_OutFile *out, hk_Error *err);

/* Closes and removes the temporary file (after an error). Safe to call twice. */
void hk_outfile_abort(hk_OutFile *out);

/* Installs handlers of SIGINT, SIGTERM, SIGHUP and SIGPIPE that remove the temporary
 * files open at that moment (up to 16 at once), then end the process by the same
 * signal, as it would have ended without them. Signals the program ignores or handles
 * already are left alone. For programs (the hairkit command calls it first); a
 * library never installs it by itself. */
void hk_outfile_cleanup_on_signals(void);

#endif /* HK_IO_OUTFILE_H */
