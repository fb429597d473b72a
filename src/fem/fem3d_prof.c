/* fem3d_prof.c - the per-phase timers of fem3d_prof.h (only with -DRF_FEM3D_PROFILE). */
#include "fem3d_prof.h"

#ifdef RF_FEM3D_PROFILE
#include <stdio.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

enum { F3P_THREADS = 4 };
static double acc_wall[F3P_N][F3P_THREADS], acc_cpu[F3P_N][F3P_THREADS];
static const char *const names[F3P_N] = {"boulder frame", "fork",     "ub transform", "element kernel",
                                         "kernel barrier", "gather",  "join",         "torque",
                                         "commit",         "dashpots", "contact locate", "predictor",
                                         "contact predict", "contact solve", "contact account", "energy",
                                         "step account",
                                         "set-up (once)"};

static double seconds(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

f3p_mark f3p_now(void)
{
    return (f3p_mark){seconds(CLOCK_MONOTONIC), seconds(CLOCK_THREAD_CPUTIME_ID)};
}

void f3p_lap(int p, f3p_mark *m)
{
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    f3p_mark n = f3p_now();
    if (t < F3P_THREADS)
        acc_wall[p][t] += n.wall - m->wall, acc_cpu[p][t] += n.cpu - m->cpu;
    *m = n;
}

void f3p_report(long steps, long elements, long nodes, long boulder_nodes)
{
    double tw = 0, tc[F3P_THREADS] = {0};
    fprintf(stderr,
            "fem3d profile: %ld steps, %ld elements, %ld nodes (%ld boulder); seconds per phase (ns per element-step)\n",
            steps, elements, nodes, boulder_nodes);
    fprintf(stderr, "%-16s %9s %9s %9s %9s\n", "phase", "wall t0", "cpu t0", "wall t1", "cpu t1");
    const double k = 1e9 / ((double)steps * (double)elements);
    for (int p = 0; p < F3P_N; p++) {
        fprintf(stderr, "%-16s %9.3f %9.3f %9.3f %9.3f   (%.1f ns)\n", names[p], acc_wall[p][0], acc_cpu[p][0],
                acc_wall[p][1], acc_cpu[p][1], acc_wall[p][0] * k);
        if (p == F3P_SETUP)
            continue;
        tw += acc_wall[p][0];
        for (int t = 0; t < F3P_THREADS; t++)
            tc[t] += acc_cpu[p][t];
    }
    fprintf(stderr, "%-16s %9.3f %9.3f %9s %9.3f   (%.1f ns)\n", "total (loop)", tw, tc[0], "", tc[1], tw * k);
    memset(acc_wall, 0, sizeof acc_wall), memset(acc_cpu, 0, sizeof acc_cpu);
}
#else
typedef int f3p_unused; /* ISO C wants a declaration in every translation unit */
#endif
