/* Checked allocation: sizes are validated before any allocation is attempted, so
 * absurd counts from bad input become an error message, never a crash or a
 * machine brought to its knees. */
#include "hairkit/core.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static int size_ok(size_t count, size_t size, size_t *bytes, hk_Error *err)
{
    if (size != 0 && count > SIZE_MAX / size) {
        hk_error_set(err, HK_ERR_NOMEM, "allocation of %zu x %zu bytes overflows", count, size);
        return 0;
    }
    *bytes = count * size;
    if (*bytes > HK_MAX_ALLOCATION) {
        hk_error_set(err, HK_ERR_NOMEM, "refusing to allocate %zu bytes (limit %zu)", *bytes,
                     (size_t)HK_MAX_ALLOCATION);
        return 0;
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
