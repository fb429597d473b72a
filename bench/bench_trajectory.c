/* bench_trajectory.c - trajectories per second per core on the 30-segment
 * profile of examples/trajectory/slope.yaml with the `constant` law (issue 11
 * goal: >= 200 000 per second per core), for a point block with fixed
 * coefficients and for the example as written (sphere rolling, random
 * restitution, roughness, Latin hypercube).  Reports wall time and CPU time:
 * on a shared machine the CPU rate is the figure to compare.
 * Usage: bench_trajectory [samples] [threads] [file] */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "rockfuzz/trajectory.h"

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int run(const char *label, rf_traj_spec *s, size_t samples, int threads)
{
    rf_traj_ensemble e;
    rf_traj_stats st;
    rf_error err;
    s->samples = samples;
    s->record = 0;
    double c0 = cpu_seconds();
    if (rf_traj_run(s, threads, &e, &err) != RF_OK || rf_traj_stats_compute(&e, &st, &err) != RF_OK) {
        fprintf(stderr, "bench_trajectory: %s\n", err.msg);
        return 1;
    }
    double cpu = cpu_seconds() - c0;
    size_t impacts = 0;
    printf("%-34s %d thread%s: %zu trajectories, wall %.3f s (%.0f /s), CPU %.3f s -> %.0f per second per core "
           "(runout p50 %.1f m, stopped %zu, exited %zu, step_limit %zu)\n",
           label, threads, threads == 1 ? " " : "s", samples, e.wall_seconds, (double)samples / e.wall_seconds, cpu,
           (double)samples / cpu, st.runout_x.p50, st.stopped, st.exited, st.step_limit);
    (void)impacts;
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&e);
    return 0;
}

int main(int argc, char **argv)
{
    size_t samples = argc > 1 ? (size_t)atol(argv[1]) : 200000;
    int threads = argc > 2 ? atoi(argv[2]) : 1;
    const char *file = argc > 3 ? argv[3] : "examples/trajectory/slope.yaml";
    rf_traj_spec s;
    rf_error err;
    if (rf_traj_load(file, &s, &err) != RF_OK) {
        fprintf(stderr, "bench_trajectory: %s\n", err.msg);
        return 1;
    }
    int rc = run("slope.yaml as written (sphere)", &s, samples, threads);
    /* point block, fixed coefficients, no roughness: the lumped-mass core */
    rf_traj_spec p;
    if (rf_traj_spec_copy(&s, &p, &err) != RF_OK)
        return 1;
    p.sphere = 0, p.mass = 1360;
    for (size_t i = 0; i < p.n_random; i++)
        if (p.random[i].path[0] == 'm')
            p.random[i].dist = RF_DIST_FIXED; /* keeps the nominal (a = mean) */
    for (size_t m = 0; m < p.n_materials; m++)
        p.materials[m].roughness = 0;
    for (size_t i = 0; i < p.n_random; i++)
        if (p.random[i].dist == RF_DIST_FIXED)
            rf_traj_spec_set(&p, p.random[i].path, p.random[i].a);
    rc |= run("point block, fixed R_n/R_t", &p, samples, threads);
    rf_traj_spec_free(&p);
    rf_traj_spec_free(&s);
    return rc;
}
