/* bench_fem3d.c - wall time of one 3D impact (10 m/s, 45 degree slope,
 * f = 0.6, half model) on 1 to tmax threads, and ns per element-step.
 *   bench_fem3d [refinement (a/h), default 6] [max threads, default 2] [domain factor, default 0 = automatic]
 *               [repeats, default 1]
 * With repeats > 1 the thread counts alternate (1, 2, 1, 2, ...) so that a burst
 * of load from other processes hits them alike, and the median wall time and
 * the median of the per-round speed-ups are printed.  Each run prints its
 * process CPU time and the load average before it (the machine is shared: a
 * wall-time speed-up means little when the load average exceeds the free cores).
 * The results must not depend on the thread count: the state hashes are
 * printed and compared. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/util.h"
#include "rockfuzz/fem3d.h"

enum { MAX_T = 8, MAX_REP = 64 };

static double load_average(void)
{
    double l = -1;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf", &l) != 1)
            l = -1;
        fclose(f);
    }
    return l;
}

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* One run on t threads: its wall time (the solver's, set-up included) and state hash. */
static int run(const rf_impact_input *in, double ref, int t, double domain, double *wall, unsigned long long *hash)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = ref;
    o.threads = t;
    o.domain_factor = domain;
    rf_impact_output out;
    rf_fem3d_report rep;
    rf_error err;
    const double load = load_average(), c0 = cpu_seconds();
    if (rf_fem3d_impact_ex(in, &o, NULL, &out, NULL, &rep, &err) != RF_OK) {
        fprintf(stderr, "bench_fem3d: %s\n", err.msg);
        return 1;
    }
    const double cpu = cpu_seconds() - c0, ns = 1e9 * out.wall_seconds / (out.elements * out.steps);
    printf("threads=%d ref=%g domain=%g elements=%.0f steps=%.0f wall=%.3f s cpu=%.3f s load=%.2f "
           "ns_per_element_step=%.1f R_t=%.6f omega=%.5f hash=%016llx\n",
           t, ref, rf_fem_domain_factor(&o, in), out.elements, out.steps, out.wall_seconds, cpu, load, ns, out.R_t,
           out.omega_after, (unsigned long long)rep.state_hash);
    fflush(stdout);
    *wall = out.wall_seconds;
    *hash = rep.state_hash;
    rf_fem3d_report_free(&rep);
    return 0;
}

int main(int argc, char **argv)
{
    double ref = argc > 1 ? atof(argv[1]) : 6;
    int tmax = argc > 2 ? atoi(argv[2]) : 2;
    double domain = argc > 3 ? atof(argv[3]) : 0;
    int reps = argc > 4 ? atoi(argv[4]) : 1;
    if (tmax < 1 || tmax > MAX_T || reps < 1 || reps > MAX_REP) {
        fprintf(stderr, "bench_fem3d: max threads must be in [1, %d] (got %d), repeats in [1, %d] (got %d)\n", MAX_T,
                tmax, MAX_REP, reps);
        return 2;
    }
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10,
                          .slope_angle = 45 * RF_PI / 180, .friction = 0.6};
    static double wall[MAX_T][MAX_REP], speedup[MAX_T][MAX_REP];
    unsigned long long h1 = 0;
    int same = 1;
    for (int r = 0; r < reps; r++)
        for (int t = 1; t <= tmax; t++) {
            unsigned long long h;
            if (run(&in, ref, t, domain, &wall[t - 1][r], &h))
                return 1;
            if (r == 0 && t == 1)
                h1 = h;
            else if (h != h1)
                same = 0;
            speedup[t - 1][r] = wall[0][r] / wall[t - 1][r];
        }
    if (reps > 1)
        for (int t = 1; t <= tmax; t++)
            printf("median of %d: threads=%d wall=%.3f s speed-up=%.3f (median of the rounds' ratios)\n", reps, t,
                   median(wall[t - 1], reps), median(speedup[t - 1], reps));
    printf("identical results across thread counts: %s\n", same ? "yes" : "NO");
    return same ? 0 : 1;
}
