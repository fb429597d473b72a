/* bench_util.h - small helpers shared by the benchmark programs: the
 * process's CPU time and a comma list of numbers from a key=value argument. */
#ifndef ROCKFUZZ_BENCH_UTIL_H
#define ROCKFUZZ_BENCH_UTIL_H

#include <stdlib.h>
#include <sys/resource.h>

/* CPU seconds (user + system) of this process so far. */
static inline double cpu_now(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

/* Comma list -> x[] (at most cap), returns the count. */
static inline int parse_list(const char *s, double *x, int cap)
{
    int n = 0;
    while (s && *s && n < cap) {
        char *end;
        x[n++] = strtod(s, &end);
        s = *end == ',' ? end + 1 : NULL;
    }
    return n;
}

#endif
