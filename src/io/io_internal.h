/* Internal to hairkit (not installed, not exported): helpers of the file readers and
 * writers. Included as "io/io_internal.h". */
#ifndef HK_IO_INTERNAL_H
#define HK_IO_INTERNAL_H

#include <stdint.h>

#include "hairkit/core.h"

/* FNV-1a 64 of a file's bytes ("path: cannot read" when it cannot be read). */
hk_Status hk_file_fingerprint(const char *path, uint64_t *out, hk_Error *err);

#endif /* HK_IO_INTERNAL_H */
