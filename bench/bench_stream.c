/* bench_stream.c - STREAM-style triad a[i] = b[i] + s c[i] on 1 and 2
 * threads, for working sets from cache-sized to well beyond the last-level
 * cache: the bandwidth ceiling that a memory-bound FE kernel can reach here
 * (docs/fem-speed.md compares the element loops' bytes per element-step with
 * it).  Bytes counted as STREAM does: 24 per index (the write-allocate read
 * of a, 8 more, is not counted).  Best of the repetitions (the machine is
 * shared: the best is the least disturbed).
 *   bench_stream [MB per working set ...]   default 3 24 192 1536 */
#include <stdio.h>
#include <stdlib.h>

#include "core/util.h"

static double triad(double *a, const double *b, const double *c, long n, int threads, int reps)
{
    double best = 1e30;
    for (int r = 0; r < reps; r++) {
        const double t0 = rf_monotonic_seconds();
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
        for (long i = 0; i < n; i++)
            a[i] = b[i] + 3.0 * c[i];
        const double t = rf_monotonic_seconds() - t0;
        if (t < best)
            best = t;
    }
    (void)threads;
    return 24.0 * (double)n / best / 1e9;
}

int main(int argc, char **argv)
{
    double sizes[8] = {3, 24, 192, 1536};
    int ns = 4;
    if (argc > 1) {
        ns = argc - 1 < 8 ? argc - 1 : 8;
        for (int k = 0; k < ns; k++)
            sizes[k] = atof(argv[k + 1]);
    }
    for (int k = 0; k < ns; k++) {
        const long n = (long)(sizes[k] * 1e6 / 24);
        double *a = malloc((size_t)n * sizeof *a), *b = malloc((size_t)n * sizeof *b), *c = malloc((size_t)n * sizeof *c);
        if (!a || !b || !c) {
            fprintf(stderr, "bench_stream: out of memory for %g MB\n", sizes[k]);
            return 1;
        }
        /* first touch by the same static split as the triad */
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(2)
#endif
        for (long i = 0; i < n; i++)
            a[i] = 0, b[i] = 1, c[i] = 2;
        const int reps = (int)(2e9 / (24.0 * (double)n)) + 5;
        const double g1 = triad(a, b, c, n, 1, reps), g2 = triad(a, b, c, n, 2, reps);
        printf("working set %7.1f MB: triad %6.1f GB/s on 1 thread, %6.1f GB/s on 2 (best of %d)\n", sizes[k], g1, g2,
               reps);
        free(a), free(b), free(c);
    }
    return 0;
}
