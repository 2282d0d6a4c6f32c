/* hairkit core: status codes, error reports and checked allocation.
 *
 * Every library function that can fail returns an hk_Status (HK_OK == 0) and, when
 * given a non-NULL hk_Error, fills it with a one-line message. Messages about input
 * files start with "path:line: " so that editors can jump to the spot.
 *
 * Every function that takes a pointer to a parameter struct (a configuration with a
 * default function) accepts NULL for it and then uses the defaults; docs/library.md
 * lists the conventions of the API. */
#ifndef HAIRKIT_CORE_H
#define HAIRKIT_CORE_H

#include <stddef.h>

#include "hairkit/export.h"
#include "hairkit/version.h"

#ifdef __cplusplus
extern "C" {
#endif


typedef enum hk_Status {
    HK_OK = 0,
    HK_ERR_IO = 1,      /* a file could not be opened, read or written */
    HK_ERR_PARSE = 2,   /* an input file is malformed */
    HK_ERR_INVALID = 3, /* a value is out of its physical or sane range */
    HK_ERR_NOMEM = 4,   /* an allocation failed or would be absurdly large */
    HK_ERR_NUMERIC = 5  /* a computation produced NaN/Inf or did not converge */
} hk_Status;

#define HK_ERROR_MESSAGE_SIZE 512

typedef struct hk_Error {
    hk_Status code;
    char message[HK_ERROR_MESSAGE_SIZE];
} hk_Error;

/* Fills err (when not NULL) with code and a printf-style message; returns code so
 * that callers can write `return hk_error_set(err, HK_ERR_PARSE, "...")`. */
HK_API hk_Status hk_error_set(hk_Error *err, hk_Status code, const char *fmt, ...) HK_PRINTF_LIKE(3, 4);

/* Clears err to HK_OK with an empty message. */
HK_API void hk_error_clear(hk_Error *err);

/* Short name of a status code ("io", "parse", ...). */
HK_API const char *hk_status_name(hk_Status status);

/* The version of the library linked, "MAJOR.MINOR.PATCH" (what `hairkit --version`
 * prints); HK_VERSION_STRING is the version of the headers compiled against. */
HK_API const char *hk_version(void);

/* Progress report of long work: stage name and fraction done in [0, 1]. Called from one
 * thread at a time. */
typedef void (*hk_ProgressFn)(void *user, const char *stage, double fraction);

/* Largest single allocation the library will attempt (bytes). Bigger requests come
 * from absurd input sizes and are refused with HK_ERR_NOMEM instead of trying. */
#define HK_MAX_ALLOCATION ((size_t)8 << 30)

/* The memory budget of one job: what growing a groom (with the .hair made from it) or
 * loading a .hair file may take in all, estimated from the counts before anything is
 * allocated (docs/file-formats.md, "Limits"). By default HK_DEFAULT_MEMORY_LIMIT
 * (8 GB), or the machine's physical memory when it has less; the environment variable
 * HAIRKIT_MEMORY_LIMIT sets another: a number of bytes with an optional suffix k, M, G,
 * T (powers of 1000) or Ki, Mi, Gi, Ti (powers of 1024) and an optional B, e.g.
 * HAIRKIT_MEMORY_LIMIT=16G. A budget over HK_MAX_ALLOCATION also raises the limit of
 * a single allocation to it. */
#define HK_DEFAULT_MEMORY_LIMIT 8e9
#define HK_MEMORY_LIMIT_ENV     "HAIRKIT_MEMORY_LIMIT"

/* The budget in bytes into *bytes; HK_ERR_INVALID (and *bytes the default) when
 * HAIRKIT_MEMORY_LIMIT is set to something that is not a size. */
HK_API hk_Status hk_memory_limit(double *bytes, hk_Error *err);

/* HK_OK when `bytes` fit the budget; else HK_ERR_NOMEM and a message "WHAT would take
 * about N GB of memory, over the limit of M GB (HAIRKIT_MEMORY_LIMIT raises it, e.g.
 * ...)"; `what` is a phrase such as "8385000 strands of 41 points". */
HK_API hk_Status hk_memory_check(double bytes, const char *what, hk_Error *err);

/* malloc/calloc of count*size bytes with overflow and HK_MAX_ALLOCATION checks (or the
 * memory budget when it is larger).
 * On failure returns NULL and fills err. A zero count returns a valid minimal block. */
HK_API void *hk_alloc_array(size_t count, size_t size, hk_Error *err);
HK_API void *hk_calloc_array(size_t count, size_t size, hk_Error *err);
HK_API void hk_free(void *ptr);
/* A copy of the string s (free with hk_free); NULL and err filled when out of memory. */
HK_API char *hk_strdup(const char *s, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_CORE_H */
