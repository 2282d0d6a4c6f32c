/* Internal to hairkit (not installed, not exported): helpers of the file readers and
 * writers. Included as "io/io_internal.h". */
#ifndef HK_IO_INTERNAL_H
#define HK_IO_INTERNAL_H

#include <stdint.h>

#include "hairkit/core.h"

/* FNV-1a 64 of a file's bytes ("path: cannot read" when it cannot be read). */
hk_Status hk_file_fingerprint(const char *path, uint64_t *out, hk_Error *err);

/* The same, continued over the file's bytes from *hash (what hk_file_fingerprint gave
 * for the files before): the fingerprint of several files read one after the other. */
hk_Status hk_file_fingerprint_more(const char *path, uint64_t *hash, hk_Error *err);

/* A collision file's fingerprint: its bytes, then those of the meshes its Mesh lines
 * name, in order (hk_file_fingerprint's value for a file without Mesh lines), so that a
 * simulation's rebuild notices a changed mesh as it notices a changed file. */
hk_Status hk_collision_fingerprint(const char *path, uint64_t *out, hk_Error *err);

#endif /* HK_IO_INTERNAL_H */
