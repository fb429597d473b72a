/* bench_terrain.c - 3D trajectories on terrain end to end (issue 28 goal:
 * >= 50 000 trajectories per second per core, rasters included): a synthetic
 * 1 km^2 DEM at 2 m (501 x 501 nodes, ESRI ASCII grids written to a
 * temporary folder and read as a terrain file is read) falling to the south
 * in four stretches (35 deg rock, then talus at 20, 8 and 2 deg) with
 * gullies and bumps across; sphere blocks (r 0.5 m) released at three points
 * 1 m above the ground at y = RELEASE_Y, `constant` law, a barrier across
 * the slope, all five raster statistics at 2 m cells.  Prints trajectories
 * per second per core (CPU time: the figure to compare on a shared machine)
 * at 1 and 2 threads, the peak RSS after 10^4 and after 10^5 blocks (its
 * growth must stay within the per-sample arrays), and the mean runout,
 * impacts and contact steps per trajectory (the latter over 1000 recorded
 * trajectories).
 * Usage: bench_terrain [samples (default 100000)] [release y (default 850 m)] [once]
 * "once": one run of `samples` blocks (>= 100) at 1 thread and nothing else,
 * for instruction counts (valgrind --tool=callgrind --toggle-collect=tmc_worker). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <math.h>

#include "trajectory/terrain_internal.h"

#define NODES 501
#define CELL 2.0

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double peak_rss_mb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0; /* Linux: KiB */
}

/* The ground [m]: continuous slopes of 35, 20, 8 and 2 deg going south (breaks at y = 700, 550, 400 m),
 * gullies (120 m apart, 4 m deep) and bumps. */
static double ground(double x, double y)
{
    const double z400 = 12.5, z550 = z400 + 0.14 * 150, z700 = z550 + 0.364 * 150;
    double z = y > 700 ? z700 + 0.7 * (y - 700)
             : y > 550 ? z550 + 0.364 * (y - 550)
             : y > 400 ? z400 + 0.14 * (y - 400)
                       : z400 - 0.035 * (400 - y);
    return z + 2.0 * cos(2 * 3.14159265358979 * x / 120) + 0.4 * sin(x / 9.0) * cos(y / 11.0);
}

static int write_grid(const char *path, int classes)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f, "ncols %d\nnrows %d\nxllcenter 0\nyllcenter 0\ncellsize %g\nNODATA_value -9999\n", NODES, NODES, CELL);
    for (int j = NODES - 1; j >= 0; j--) { /* north first */
        for (int i = 0; i < NODES; i++) {
            if (classes)
                fprintf(f, "%s%d", i ? " " : "", j * CELL > 700 ? 1 : 2);
            else
                fprintf(f, "%s%.4f", i ? " " : "", ground(i * CELL, j * CELL));
        }
        fputc('\n', f);
    }
    return fclose(f) != 0;
}

static int write_spec(const char *dir, double release_y)
{
    char path[512];
    snprintf(path, sizeof path, "%s/bench.yaml", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f,
            "name: bench_terrain\n"
            "terrain: {dem: %s/dem.asc, materials: {raster: %s/classes.asc, classes: {1: rock, 2: talus}}}\n"
            "materials:\n"
            "  rock:  {R_n: 0.5, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1, roughness: 5}\n"
            "  talus: {R_n: 0.35, R_t: 0.75, friction_angle: 35, rolling_resistance: 0.3, roughness: 10}\n"
            "block: {shape: sphere, radius: 0.5, density: 2600}\n"
            "release: {points: [[450, %g], [500, %g], [550, %g]], height: 1.0, velocity: [0, 0, 0]}\n"
            "bounce: {law: constant}\n"
            "barriers: [{name: fence, line: [[100, 500], [900, 500]], height: 4, capacity: 2.0e6}]\n"
            "rasters: {cell: 2, statistics: [passages, reach_probability, deposits, energy_p95, height_p95]}\n"
            "samples: 10000\nseed: 1\n",
            dir, dir, release_y, release_y, release_y);
    return fclose(f) != 0;
}

/* One run of `samples` blocks; prints its rate; the ensemble in e (free it). */
static int run(rf_traj_spec *s, size_t samples, size_t record, int threads, rf_traj_ensemble *e, double *rate)
{
    rf_error err;
    s->samples = samples, s->record = record;
    double c0 = cpu_seconds();
    if (rf_terrain_run(s, threads, NULL, NULL, e, &err) != RF_OK) {
        fprintf(stderr, "bench_terrain: %s\n", err.msg);
        return 1;
    }
    double cpu = cpu_seconds() - c0;
    *rate = (double)samples / cpu;
    printf("%zu blocks, %d thread%s: wall %.3f s (%.0f /s), CPU %.3f s -> %.0f trajectories per second per core; "
           "peak RSS %.1f MB\n", samples, threads, threads == 1 ? " " : "s", e->wall_seconds,
           (double)samples / e->wall_seconds, cpu, *rate, peak_rss_mb());
    return 0;
}

static double mean_of(const double *v, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++)
        s += v[i];
    return n ? s / (double)n : NAN;
}

static int measure(rf_traj_spec *s, size_t big)
{
    rf_traj_ensemble e;
    double rate, rss0;
    if (run(s, 10000, 0, 1, &e, &rate))
        return 1;
    rf_traj_ensemble_free(&e);
    rss0 = peak_rss_mb();
    if (run(s, big, 0, 1, &e, &rate))
        return 1;
    size_t stopped = 0;
    for (size_t i = 0; i < e.samples; i++)
        stopped += e.state[i] == RF_TRAJ_STOPPED;
    printf("mean runout %.1f m over %zu blocks; %.1f %% stopped\n", mean_of(e.runout_x, e.samples), e.samples,
           100.0 * (double)stopped / (double)e.samples);
    rf_traj_ensemble_free(&e);
    double per = terrain_bytes_per_sample(s->n_collectors);
    printf("peak RSS growth 10^4 -> %zu blocks: %.1f MB; the per-sample arrays account for %.1f MB (%.0f B per "
           "block)\n", big, peak_rss_mb() - rss0, (double)(big - 10000) * per / 1048576.0, per);
    if (run(s, 10000, 0, 2, &e, &rate))
        return 1;
    rf_traj_ensemble_free(&e);
    if (run(s, 1000, 1000, 1, &e, &rate))
        return 1;
    double impacts = 0, steps = 0;
    for (size_t i = 0; i < e.terrain->n_recorded; i++)
        impacts += (double)e.terrain->recorded[i].n_impacts, steps += (double)e.terrain->recorded[i].n_steps;
    printf("per trajectory (1000 recorded): %.2f impacts, %.1f contact steps\n", impacts / 1000, steps / 1000);
    rf_traj_ensemble_free(&e);
    return 0;
}

/* One run of n blocks at one thread: its rate, mean runout and steps. */
static int measure_once(rf_traj_spec *s, size_t n)
{
    rf_traj_ensemble e;
    double rate;
    if (run(s, n, 0, 1, &e, &rate))
        return 1;
    printf("mean runout %.6f m over %zu blocks\n", mean_of(e.runout_x, e.samples), e.samples);
    rf_traj_ensemble_free(&e);
    return 0;
}

int main(int argc, char **argv)
{
    size_t big = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 100000;
    double release_y = argc > 2 ? strtod(argv[2], NULL) : 850;
    int once = argc > 3 && !strcmp(argv[3], "once");
    char dir[] = "/tmp/bench_terrain_XXXXXX", path[512];
    if (big < (once ? 100 : 10000) || !mkdtemp(dir)) {
        fprintf(stderr, "usage: bench_terrain [samples >= 10000] [release y m] [once (samples >= 100)]\n");
        return 2;
    }
    snprintf(path, sizeof path, "%s/dem.asc", dir);
    int bad = write_grid(path, 0);
    snprintf(path, sizeof path, "%s/classes.asc", dir);
    bad |= write_grid(path, 1) | write_spec(dir, release_y);
    rf_traj_spec s;
    rf_error err;
    snprintf(path, sizeof path, "%s/bench.yaml", dir);
    int rc = 1;
    if (bad || rf_traj_load(path, &s, &err) != RF_OK) {
        fprintf(stderr, "bench_terrain: %s\n", bad ? "cannot write the grids" : err.msg);
    } else {
        printf("terrain: 501 x 501 nodes at 2 m, sphere r 0.5 m, constant law, rasters at 2 m (5 statistics)\n");
        rc = once ? measure_once(&s, big) : measure(&s, big);
        rf_traj_spec_free(&s);
    }
    const char *names[3] = {"dem.asc", "classes.asc", "bench.yaml"};
    for (int k = 0; k < 3; k++)
        snprintf(path, sizeof path, "%s/%s", dir, names[k]), unlink(path);
    rmdir(dir);
    return rc;
}
