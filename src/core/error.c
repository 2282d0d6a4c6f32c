/* Error reporting: one formatted message per failure, carried up to the caller; the
 * first (lowest index) error of a parallel loop. */
#include "core/core_internal.h"
#include "hairkit/core.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

hk_Status hk_error_set(hk_Error *err, hk_Status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}

void hk_error_clear(hk_Error *err)
{
    if (err) {
        err->code = HK_OK;
        err->message[0] = '\0';
    }
}

const char *hk_status_name(hk_Status status)
{
    switch (status) {
    case HK_OK:
        return "ok";
    case HK_ERR_IO:
        return "io";
    case HK_ERR_PARSE:
        return "parse";
    case HK_ERR_INVALID:
        return "invalid";
    case HK_ERR_NOMEM:
        return "nomem";
    case HK_ERR_NUMERIC:
        return "numeric";
    }
    return "unknown";
}

void hk_first_error_init(hk_FirstError *fe)
{
    fe->index = -1;
    hk_error_clear(&fe->error);
}

/* Writes of fe->index happen inside the critical section and are atomic, so that
 * hk_first_error_skip may read it at any time without a lock; the error is only read
 * after the loop (its end is a barrier). */
void hk_first_error_record(hk_FirstError *fe, long index, const hk_Error *err)
{
#pragma omp critical(hk_first_error)
    {
        if (fe->index < 0 || index < fe->index) {
            fe->error = *err;
#pragma omp atomic write
            fe->index = index;
        }
    }
}

int hk_first_error_skip(const hk_FirstError *fe, long index)
{
    long failed;
#pragma omp atomic read
    failed = fe->index;
    return failed >= 0 && failed < index;
}

hk_Status hk_first_error_status(const hk_FirstError *fe, hk_Error *err)
{
    if (fe->index < 0) return HK_OK;
    if (err) *err = fe->error;
    return fe->error.code;
}
