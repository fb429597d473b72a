/* util.h - the few small helpers every module needs, defined once.
 *
 * Internal (not part of the public API): pi, a monotonic clock for progress
 * and timing, a strdup that C17 lacks, a name-table lookup and the one
 * duration formatter of progress lines and status reports. */
#ifndef ROCKFUZZ_CORE_UTIL_H
#define ROCKFUZZ_CORE_UTIL_H

#include <stddef.h>

#include "rockfuzz/status.h"

#define RF_PI 3.14159265358979323846

/* Seconds on a monotonic clock (arbitrary origin). */
double rf_monotonic_seconds(void);

/* A malloc'ed copy of s, or NULL when s is NULL or memory runs out. */
char *rf_strdup(const char *s);

/* Grow *p (n elements used, *cap allocated, elem bytes each) to hold one more,
   doubling from 16; 0 if out of memory (*p and *cap then unchanged). */
int rf_grow(void **p, size_t n, size_t *cap, size_t elem);

/* The index of name in names[0..n), or -1 (also for a NULL name): the parse side of every
   enum <-> name table. */
int rf_name_index(const char *name, const char *const *names, int n);

/* Levenshtein distance of two names (each capped at 256 characters): how a
   "did you mean" message finds the nearest known name. */
size_t rf_name_distance(const char *a, const char *b);

/* The same over a registry whose k-th name names(k) gives (k in [0, n)):
   *index = k, or RF_EINVAL with "WHAT 'name' is not one of a, b, c". */
rf_status rf_name_parse(const char *what, const char *name, const char *(*names)(size_t k), size_t n,
                        int *index, rf_error *err);

/* Styles of rf_format_duration (flags). */
enum {
    RF_DURATION_COMPACT = 1, /* "12.3s", "4m05s", "1h02m" instead of "12.3 s", "4 min 05 s", "1 h 02 min" */
    RF_DURATION_WHOLE = 2    /* whole seconds below a minute: "12 s" */
};

/* A duration for people: below a minute in seconds (one decimal unless
   RF_DURATION_WHOLE), below an hour in minutes and seconds, then hours and
   minutes (both truncated).  Returns 1, or 0 with "?" in buf when s is not
   known (negative, NaN) or beyond 1e8 s (three years). */
int rf_format_duration(double s, int style, char *buf, size_t size);

#endif
