/* status.c - formatting of rf_error messages (see status.h). */
#include "rockfuzz/status.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

rf_status rf_fail(rf_error *err, rf_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}

rf_status rf_error_prefix(rf_error *err, const char *fmt, ...)
{
    if (!err)
        return RF_EINTERNAL;
    char head[RF_ERROR_MAX], old[RF_ERROR_MAX];
    memcpy(old, err->msg, sizeof old);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(head, sizeof head, fmt, ap);
    va_end(ap);
    /* head + ": " + old, truncated to the buffer (no format: -Wformat-truncation) */
    size_t hl = strnlen(head, RF_ERROR_MAX - 3), ol = strnlen(old, RF_ERROR_MAX - 3 - hl);
    memcpy(err->msg, head, hl);
    memcpy(err->msg + hl, ": ", 2);
    memcpy(err->msg + hl + 2, old, ol);
    err->msg[hl + 2 + ol] = '\0';
    return err->code;
}

const char *rf_status_name(rf_status s)
{
    switch (s) {
    case RF_OK: return "ok";
    case RF_EINVAL: return "invalid input";
    case RF_ENOMEM: return "out of memory";
    case RF_EIO: return "I/O error";
    case RF_EMODEL: return "model evaluation failed";
    case RF_ECAP: return "limit exceeded";
    case RF_EPARSE: return "parse error";
    case RF_EINTERNAL: return "internal error";
    case RF_EINTERRUPTED: return "interrupted";
    }
    return "unknown status";
}
