/* bench_terrain_hazard.c - the cost of the hazard rasters (terrain_hazard.c)
 * per piece and per cell crossed, on the issue 28 bench terrain: a 1 km^2
 * DEM at 2 m (a 35 deg slope with waves), output cells of 2 m, all
 * statistics.  Trajectories of synthetic pieces (not the simulator) run 300 m
 * down the slope: (a) flights only, 2-20 m long; (b) contact steps only,
 * 0.2-1 m long, on the ground; each trajectory ends with
 * terrain_hazard_end.  Prints CPU time per piece, per cell visit (a cell
 * crossed by a piece) and per trajectory; the accumulator's bytes.
 * Release along a line 800 m wide (wide) or within 10 m of one point
 * (point: the trajectories share cells, whose histograms stay in the cache).
 * Usage: bench_terrain_hazard [trajectories] [wide|point] [counts]   (counts:
 * passages and deposits only, no energy and height histograms) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "trajectory/terrain_internal.h"

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t rng = 12345;
static double release_width = 800; /* [m] */
static double urand(void)
{
    uint64_t z = (rng += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

#define N_NODES 501
#define CELL 2.0

static double ground(double x, double y) { return 0.7 * (1000 - y) + 3 * sin(x / 17) * cos(y / 23); }

/* The pieces of one trajectory from (x, 950) down to y = 650. */
static size_t make_trajectory(terrain_piece *pc, size_t cap, int flights)
{
    double x = 500 + release_width * (urand() - 0.5), y = 950;
    size_t n = 0;
    while (y > 650 && n < cap) {
        double len = flights ? 2 + 18 * urand() : 0.2 + 0.8 * urand(), az = -0.3 + 0.6 * urand();
        double dx = len * sin(az), dy = -len * cos(az), T = flights ? len / 10 : len / 5;
        terrain_piece *p = &pc[n++];
        memset(p, 0, sizeof *p);
        p->T = T, p->p[0] = x, p->p[1] = y, p->p[2] = ground(x, y) + (flights ? 0.5 : 0);
        p->v[0] = dx / T, p->v[1] = dy / T, p->v[2] = flights ? 3 : -0.7 * len / T;
        p->a[2] = flights ? -9.81 : 0;
        p->on_ground = !flights;
        p->e_rot = 1e4 * urand();
        x += dx, y += dy;
    }
    return n;
}

/* Cells a piece crosses (grid lines crossed + 1; corners are rare). */
static double cells_of(const terrain_piece *p)
{
    double x1 = p->p[0] + p->v[0] * p->T, y1 = p->p[1] + p->v[1] * p->T;
    return 1 + fabs(floor(x1 / CELL) - floor(p->p[0] / CELL)) + fabs(floor(y1 / CELL) - floor(p->p[1] / CELL));
}

#define BATCH 100

/* Feed a batch of trajectories (pc, with off[k] .. off[k + 1] the pieces
 * of trajectory k); with_end: end each one (else only begin and pieces).
 * Returns the CPU time. */
static double feed(rf_terrain_hazard *h, const rf_terrain *dem, const terrain_piece *pc, const size_t *off,
                   int with_end)
{
    double c0 = cpu_seconds();
    for (size_t k = 0; k < BATCH; k++) {
        terrain_hazard_begin(h);
        for (size_t i = off[k]; i < off[k + 1]; i++)
            terrain_hazard_piece(h, dem, 2600 * 0.5236, &pc[i]);
        if (with_end) {
            const terrain_piece *last = &pc[off[k + 1] - 1];
            double end[3] = {last->p[0], last->p[1], 0};
            terrain_hazard_end(h, 1, end);
        }
    }
    return cpu_seconds() - c0;
}

static int run(const rf_terrain *dem, const rf_traj_spec *s, size_t n_traj, int flights)
{
    rf_terrain_hazard *h = terrain_hazard_create(s, dem), *scratch = terrain_hazard_create(s, dem);
    size_t cap = 1000 * BATCH, off[BATCH + 1];
    terrain_piece *pc = malloc(cap * sizeof *pc);
    if (!h || !scratch || !pc)
        return 1;
    double cells = 0, cpu = 0, cpu_pieces = 0;
    size_t pieces = 0, done = 0;
    for (; done < n_traj; done += BATCH) {
        off[0] = 0;
        for (size_t k = 0; k < BATCH; k++)
            off[k + 1] = off[k] + make_trajectory(pc + off[k], cap / BATCH, flights);
        for (size_t i = 0; i < off[BATCH]; i++)
            cells += cells_of(&pc[i]);
        pieces += off[BATCH];
        cpu += feed(h, dem, pc, off, 1);
        cpu_pieces += feed(scratch, dem, pc, off, 0);
    }
    printf("%-14s %zu trajectories, %zu pieces (%.1f per trajectory), %.0f cell visits (%.2f per piece): "
           "CPU %.3f s: %.1f us per trajectory (end: %.2f us), %.0f ns per piece, %.1f ns per cell visit; "
           "%.0f trajectories per second per core for the rasters alone; accumulator %.1f MB\n",
           flights ? "flights:" : "contact steps:", done, pieces, (double)pieces / (double)done, cells,
           cells / (double)pieces, cpu, 1e6 * cpu / (double)done, 1e6 * (cpu - cpu_pieces) / (double)done,
           1e9 * cpu_pieces / (double)pieces, 1e9 * cpu_pieces / cells, (double)done / cpu,
           (double)terrain_hazard_bytes(h) / 1e6);
    free(pc);
    terrain_hazard_free(h);
    terrain_hazard_free(scratch);
    return 0;
}

int main(int argc, char **argv)
{
    size_t n_traj = argc > 1 ? (size_t)atol(argv[1]) : 20000;
    double *z = malloc(N_NODES * N_NODES * sizeof *z);
    for (size_t j = 0; j < N_NODES; j++)
        for (size_t i = 0; i < N_NODES; i++)
            z[j * N_NODES + i] = ground((double)i * CELL, (double)j * CELL);
    rf_terrain *dem;
    rf_error err;
    if (rf_terrain_from_nodes(N_NODES, N_NODES, 0, 0, CELL, CELL, z, &dem, &err) != RF_OK) {
        fprintf(stderr, "bench_terrain_hazard: %s\n", err.msg);
        return 1;
    }
    free(z);
    rf_terrain_def d;
    rf_traj_spec s;
    memset(&d, 0, sizeof d), memset(&s, 0, sizeof s);
    d.raster_cell = CELL;
    d.statistics = RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS;
    if (argc > 2 && !strcmp(argv[2], "point"))
        release_width = 10;
    printf("release %s (%.0f m wide)%s\n", release_width < 100 ? "point" : "wide", release_width,
           argc > 3 && !strcmp(argv[3], "counts") ? ", counts only" : "");
    if (!(argc > 3 && !strcmp(argv[3], "counts")))
        d.statistics |= RF_TERRAIN_ENERGY | RF_TERRAIN_HEIGHT;
    s.terrain = &d;
    int rc = run(dem, &s, n_traj, 1) | run(dem, &s, n_traj, 0);
    rf_terrain_free(dem);
    return rc;
}
