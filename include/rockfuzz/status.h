/* status.h - the one error-reporting path of rockfuzz.
 *
 * Every fallible function returns an rf_status and, on failure, fills an
 * rf_error with a human-readable message that names the file, field and
 * value involved where there is one.  Messages are plain sentences without a
 * trailing newline; callers print them.  No global state. */
#ifndef ROCKFUZZ_STATUS_H
#define ROCKFUZZ_STATUS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RF_OK = 0,
    RF_EINVAL,   /* invalid input (user data or arguments) */
    RF_ENOMEM,   /* out of memory */
    RF_EIO,      /* file or process I/O failed */
    RF_EMODEL,   /* a model evaluation failed */
    RF_ECAP,     /* a user limit (e.g. evaluation cap) would be exceeded */
    RF_EPARSE,   /* a study file or expression could not be parsed */
    RF_EINTERNAL, /* a bug: an invariant did not hold */
    RF_EINTERRUPTED /* stopped on request (e.g. the program got SIGINT/SIGTERM) */
} rf_status;

#define RF_ERROR_MAX 1024

typedef struct {
    rf_status code;
    char msg[RF_ERROR_MAX];
} rf_error;

/* printf-style; returns code so that `return rf_fail(err, RF_EINVAL, ...)`
 * reads naturally.  err may be NULL. */
rf_status rf_fail(rf_error *err, rf_status code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Prefix an existing message: "context: old message". */
rf_status rf_error_prefix(rf_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

const char *rf_status_name(rf_status s);

#ifdef __cplusplus
}
#endif
#endif
