/* util.h - the few small helpers every module needs, defined once.
 *
 * Internal (not part of the public API): pi, a monotonic clock for progress
 * and timing, a strdup that C17 lacks, and a name-table lookup. */
#ifndef ROCKFUZZ_CORE_UTIL_H
#define ROCKFUZZ_CORE_UTIL_H

#include <stddef.h>

#define RF_PI 3.14159265358979323846

/* Seconds on a monotonic clock (arbitrary origin). */
double rf_monotonic_seconds(void);

/* A malloc'ed copy of s, or NULL when s is NULL or memory runs out. */
char *rf_strdup(const char *s);

/* The index of name in names[0..n), or -1 (also for a NULL name): the parse side of every
   enum <-> name table. */
int rf_name_index(const char *name, const char *const *names, int n);

/* Levenshtein distance of two names (each capped at 256 characters): how a
   "did you mean" message finds the nearest known name. */
size_t rf_name_distance(const char *a, const char *b);

#endif
