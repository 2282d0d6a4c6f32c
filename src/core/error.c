/* Error reporting: one formatted message per failure, carried up to the caller. */
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
    case HK_OK: return "ok";
    case HK_ERR_IO: return "io";
    case HK_ERR_PARSE: return "parse";
    case HK_ERR_INVALID: return "invalid";
    case HK_ERR_NOMEM: return "nomem";
    case HK_ERR_NUMERIC: return "numeric";
    }
    return "unknown";
}
