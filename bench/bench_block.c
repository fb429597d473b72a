/* bench_block.c - speed of the rigid-block core (issue 30; block_*.c).
 *
 * 1. Steps per second of the EOTA cube stand-in (24 vertices) in flight and
 *    sliding on a plane (7 contacts, prox Gauss-Seidel), fixed h = 1 ms.
 * 2. The measurement: polyhedral blocks released on the synthetic
 *    DEM of bench/bench_terrain.c (1 km^2 at 2 m cells, 35 deg rock, then
 *    talus at 20, 8 and 2 deg, gullies and bumps; the same ground(x, y)),
 *    held here as a height grid with a bilinear ground callback and its
 *    exact bound above a plane (rf_block_ground_bound_fn).  Three shapes of 1 m^3,
 *    2650 kg/m^3: the EOTA cube and wheel stand-ins (24 vertices) and a
 *    scanned-rock-like hull (20 points on an ellipsoid of semi-axes 0.8 :
 *    0.62 : 0.48 m, all hull vertices).  Released from rest with a random
 *    orientation and a spin of up to 1 rad/s about each axis, the lowest
 *    point 1 m above the ground at (450 | 500 | 550, 850), e_n 0.3, e_t 0,
 *    mu 0.6, h 1 ms, prox tol 1e-8; run until at rest (every point slower
 *    than 0.05 m/s for 0.5 s), out of the DEM, or 60 s.  Three ways:
 *    "fixed": rf_block_step at h, every vertex against the ground (the
 *    core before this bench); "fixed+bound": the same with the ground's
 *    bound (only vertices below it evaluated); "adaptive": rf_block_advance
 *    with h_max 64 ms.  One thread, CPU seconds; prints trajectories per
 *    second, steps per trajectory, time per step, contacts per step, the
 *    energy the contact step's cap removed per trajectory, runout.
 * 3. "engine": the same DEM and shapes end to end through the terrain
 *    engine (rf_terrain_run on one thread: block_traj_terrain.c with its
 *    ground and ground bound, events, barriers off), from a trajectory file
 *    written to a temporary folder: e_n 0.3 (R_n), e_t 0 (R_t 0.9),
 *    friction angle atan 0.6, v_stop 0.05 m/s (rest: the kinetic energy
 *    below m v_stop^2 / 2 for 0.5 s), 60 s, random orientation, spin
 *    (0.5, -0.5, 0.5) rad/s, released 1 m above (450 | 500 | 550, 850).
 * Usage: bench_block [adaptive trajectories per shape (default 1000)]
 *                    [fixed-step trajectories per shape (default 20)] [h (default 0.001 s)]
 *                    [folder: one trajectory per shape for ParaView, every 20 ms; "-": none]
 *                    [engine trajectories per shape (default 0)] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <math.h>

#include "rockfuzz/block.h"
#include "rockfuzz/terrain.h"
#include "rockfuzz/trajectory.h"

#define G 9.81
#define PI 3.14159265358979323846
#define NODES 501
#define CELL 2.0

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / 16777216.0;
}

/* bench_terrain.c's ground [m]. */
static double terrain(double x, double y)
{
    const double z400 = 12.5, z550 = z400 + 0.14 * 150, z700 = z550 + 0.364 * 150;
    double z = y > 700 ? z700 + 0.7 * (y - 700)
             : y > 550 ? z550 + 0.364 * (y - 550)
             : y > 400 ? z400 + 0.14 * (y - 400)
                       : z400 - 0.035 * (400 - y);
    return z + 2.0 * cos(2 * PI * x / 120) + 0.4 * sin(x / 9.0) * cos(y / 11.0);
}

static double dem[NODES * NODES]; /* dem[j NODES + i] at (i CELL, j CELL) */

static int dem_ground(void *ctx, double x, double y, double *z, double n[3])
{
    (void)ctx;
    double u = x / CELL, v = y / CELL;
    if (!(u >= 0 && v >= 0 && u <= NODES - 1 && v <= NODES - 1))
        return 0;
    int i = u >= NODES - 1 ? NODES - 2 : (int)u, j = v >= NODES - 1 ? NODES - 2 : (int)v;
    double fu = u - i, fv = v - j, *c = dem + j * NODES + i;
    double z00 = c[0], z10 = c[1], z01 = c[NODES], z11 = c[NODES + 1];
    *z = (1 - fv) * ((1 - fu) * z00 + fu * z10) + fv * ((1 - fu) * z01 + fu * z11);
    double dx = ((1 - fv) * (z10 - z00) + fv * (z11 - z01)) / CELL, dy = ((1 - fu) * (z01 - z00) + fu * (z11 - z10)) / CELL;
    double l = sqrt(1 + dx * dx + dy * dy);
    n[0] = -dx / l, n[1] = -dy / l, n[2] = 1 / l;
    return 1;
}

/* The largest height of the ground above the plane z = p0 + p1 x + p2 y
 * over the rectangle (rf_block_ground_bound_fn), exact: bilinear minus
 * linear is bilinear in each cell, so its largest value over a rectangle
 * lies at x in {x0, x1, the grid lines between} times y likewise. */
static int dem_bound(void *ctx, double x0, double y0, double x1, double y1, const double p[3], double *dz)
{
    (void)ctx;
    double top = (NODES - 1) * CELL, xs[64], ys[64], z, n[3];
    x0 = fmax(x0, 0), y0 = fmax(y0, 0), x1 = fmin(x1, top), y1 = fmin(y1, top);
    if (!(x0 <= x1 && y0 <= y1))
        return 0;
    int nx = 0, ny = 0;
    xs[nx++] = x0, ys[ny++] = y0;
    for (double g = (floor(x0 / CELL) + 1) * CELL; g < x1 && nx < 62; g += CELL)
        xs[nx++] = g;
    for (double g = (floor(y0 / CELL) + 1) * CELL; g < y1 && ny < 62; g += CELL)
        ys[ny++] = g;
    xs[nx++] = x1, ys[ny++] = y1;
    double m = -INFINITY;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++)
            if (dem_ground(NULL, xs[i], ys[j], &z, n))
                m = fmax(m, z - p[0] - p[1] * xs[i] - p[2] * ys[j]);
    if (nx >= 64 || ny >= 64) /* a rectangle beyond 120 m: never asked by a block of metres */
        return *dz = INFINITY, 1;
    *dz = m;
    return 1;
}

typedef struct {
    double steps, contact_steps, contacts, iters, cap, runout, path, duration, cpu;
    int stopped, exited, n;
} stats;

/* A random orientation and spin; the lowest point 1 m above the ground. */
static rf_block_state release(const rf_block_shape *s, int k, unsigned *seed)
{
    rf_block_state st = {{400 + 50 * (k % 3 + 1), 850, 0}, {0}, {0}, {0}};
    double qn = 0;
    for (int i = 0; i < 4; i++)
        st.q[i] = urand(seed) - 0.5, qn += st.q[i] * st.q[i];
    for (int i = 0; i < 4; i++)
        st.q[i] /= sqrt(qn);
    for (int i = 0; i < 3; i++)
        st.w[i] = 2 * urand(seed) - 1;
    double zg = 0, n[3], up[3] = {0, 0, 1}, p[3];
    dem_ground(NULL, st.x[0], st.x[1], &zg, n);
    st.x[2] = zg + 1 - rf_block_lowest_point(s, &st, up, p);
    return st;
}

enum { FIXED, FIXED_BOUND, ADAPTIVE };

static void trajectory(const rf_block_shape *s, const rf_block_world *w, int mode, rf_block_state st, stats *a)
{
    double t = 0, still = 0, x0 = st.x[0], y0 = st.x[1];
    while (t < 60) {
        rf_block_step_info info;
        double p[3] = {st.x[0], st.x[1], st.x[2]}, h = w->h;
        if (mode == ADAPTIVE)
            h = rf_block_advance(s, w, &st, 0.064, &info);
        else
            rf_block_step(s, w, &st, &info);
        t += h;
        a->steps++, a->contact_steps += info.n_contacts > 0, a->contacts += info.n_contacts, a->iters += info.iterations;
        a->cap += info.energy_cap;
        a->path += sqrt(pow(st.x[0] - p[0], 2) + pow(st.x[1] - p[1], 2) + pow(st.x[2] - p[2], 2));
        if (!(st.x[0] > 1 && st.x[0] < 999 && st.x[1] > 1 && st.x[1] < 999)) {
            a->exited++;
            break;
        }
        double wn = sqrt(st.w[0] * st.w[0] + st.w[1] * st.w[1] + st.w[2] * st.w[2]);
        still = sqrt(st.v[0] * st.v[0] + st.v[1] * st.v[1] + st.v[2] * st.v[2]) + wn * s->bound_radius < 0.05
                    ? still + h : 0;
        if (still >= 0.5) {
            a->stopped++;
            break;
        }
    }
    a->duration += t;
    a->runout += hypot(st.x[0] - x0, st.x[1] - y0);
}

static void run(const char *name, const rf_block_shape *s, rf_block_world w, int mode, int n)
{
    static const char *modes[] = {"fixed", "fixed+bound", "adaptive"};
    stats a = {0};
    unsigned seed = 7;
    if (mode == FIXED)
        w.ground_bound = NULL;
    double c0 = cpu_seconds();
    for (int k = 0; k < n; k++)
        trajectory(s, &w, mode, release(s, k, &seed), &a);
    double cpu = cpu_seconds() - c0;
    printf("%-6s %-11s %5d: %8.1f traj/s  %8.0f steps/traj  %6.3f us/step  %5.2f contacts/step (%4.1f %% of steps, %4.1f sweeps)  "
           "cap %6.2f J/traj  run %5.1f s, path %5.1f m, runout %5.1f m  stopped %3.0f %% exited %3.0f %%\n",
           name, modes[mode], n, n / cpu, a.steps / n, 1e6 * cpu / a.steps, a.contacts / a.steps,
           100 * a.contact_steps / a.steps, a.iters / fmax(a.contact_steps, 1), a.cap / n, a.duration / n, a.path / n, a.runout / n, 100.0 * a.stopped / n,
           100.0 * a.exited / n);
}

/* One adaptive trajectory per shape recorded every 20 ms (or each step, if
 * longer) for ParaView: dir/<shape>.pvd and its .vtp files. */
static int write_vtk(const char *dir, const char *name, const rf_block_shape *s, const rf_block_world *w)
{
    enum { CAP = 4000 };
    static rf_block_state st[CAP];
    static double t[CAP];
    unsigned seed = 7;
    rf_block_state b = release(s, 1, &seed);
    size_t n = 0;
    double time = 0, next = 0;
    while (time < 60 && n < CAP && b.x[0] > 1 && b.x[0] < 999 && b.x[1] > 1 && b.x[1] < 999) {
        if (time >= next)
            st[n] = b, t[n++] = time, next = time + 0.02;
        time += rf_block_advance(s, w, &b, 0.064, NULL);
    }
    rf_error err;
    if (rf_block_write_vtk(dir, name, s, st, t, n, &err)) {
        fprintf(stderr, "bench_block: %s\n", err.msg);
        return 1;
    }
    printf("%s: %zu states over %.1f s written to %s/%s.pvd\n", name, n, time, dir, name);
    return 0;
}

static double steps_per_second(const rf_block_shape *s, const rf_block_world *w, rf_block_state st, long n,
                               double *contacts)
{
    double t0 = cpu_seconds(), nc = 0;
    for (long k = 0; k < n; k++) {
        rf_block_step_info info;
        rf_block_step(s, w, &st, &info);
        nc += info.n_contacts;
    }
    *contacts = nc / n;
    return n / (cpu_seconds() - t0);
}

static void planes(const rf_block_shape *cube)
{
    rf_block_plane flat = {{0, 0, 0}, {0, 0, 1}};
    rf_block_world w = {.e_n = 0.3, .e_t = 0, .mu = 0.6, .g = G, .h = 1e-3, .tol = 1e-8, .max_iter = 200,
                        .n_planes = 1, .planes = &flat};
    rf_block_state fly = {{0, 0, 1e6}, {1, 0, 0, 0}, {10, 0, 0}, {1, 2, 3}}, rest = {{0, 0, 0}, {1, 0, 0, 0}, {0}, {0}};
    rf_block_quat_from_matrix(cube->axes, rest.q);
    double pz[3], up[3] = {0, 0, 1}, nc;
    rest.x[2] = -rf_block_lowest_point(cube, &rest, up, pz);
    rest.v[0] = 5;
    printf("EOTA cube (%zu vertices), h = 1 ms, prox tol 1e-8:\n", cube->n_vertices);
    printf("  flight:  %.3g steps/s\n", steps_per_second(cube, &w, fly, 1000000, &nc));
    double sps = steps_per_second(cube, &w, rest, 200000, &nc);
    printf("  sliding on a plane: %.3g steps/s (%.1f contacts per step)\n", sps, nc);
}

/* 20 points on the ellipsoid 0.8 : 0.62 : 0.48 (a Fibonacci sphere stretched): all are hull vertices. */
static int rock20(rf_block_shape *s, rf_error *err)
{
    double p[60];
    for (int k = 0; k < 20; k++) {
        double z = 1 - (2 * k + 1) / 20.0, r = sqrt(1 - z * z), a = k * PI * (3 - sqrt(5.0));
        p[3 * k] = 0.8 * r * cos(a), p[3 * k + 1] = 0.62 * r * sin(a), p[3 * k + 2] = 0.48 * z;
    }
    if (rf_block_polyhedron(20, p, 2650, s, err))
        return 1;
    return rf_block_scale_to_volume(s, 1.0, err) != RF_OK;
}

/* The DEM as an ESRI ASCII grid (north first) and the trajectory file of the engine run. */
static int write_engine_files(const char *dir, const char *block)
{
    char path[512];
    snprintf(path, sizeof path, "%s/dem.asc", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f, "ncols %d\nnrows %d\nxllcenter 0\nyllcenter 0\ncellsize %g\nNODATA_value -9999\n", NODES, NODES, CELL);
    for (int j = NODES - 1; j >= 0; j--)
        for (int i = 0; i < NODES; i++)
            fprintf(f, "%.17g%c", dem[j * NODES + i], i == NODES - 1 ? '\n' : ' ');
    if (fclose(f))
        return 1;
    snprintf(path, sizeof path, "%s/block.yaml", dir);
    if (!(f = fopen(path, "w")))
        return 1;
    fprintf(f, "name: bench_block\nterrain: {dem: %s/dem.asc}\n"
               "materials:\n  rock: {R_n: 0.3, R_t: 0.9, friction_angle: 30.963756532073521}\n"
               "block: %s\n"
               "release: {points: [[450, 850], [500, 850], [550, 850]], height: 1.0, velocity: [0, 0, 0]}\n"
               "stop: {v_stop: 0.05}\nsamples: 10\nseed: 7\n", dir, block);
    return fclose(f) != 0;
}

/* n trajectories of a shape through the terrain engine (one thread, CPU seconds). */
static int engine(const char *name, const char *block, size_t n)
{
    char dir[] = "/tmp/bench_block_XXXXXX", path[512];
    if (!mkdtemp(dir))
        return 1;
    rf_traj_spec s;
    rf_traj_ensemble e;
    rf_error err;
    int rc = 1;
    snprintf(path, sizeof path, "%s/block.yaml", dir);
    if (write_engine_files(dir, block) || rf_traj_load(path, &s, &err) != RF_OK) {
        fprintf(stderr, "bench_block: engine files: %s\n", err.msg);
    } else {
        s.samples = n, s.record = n < 10 ? n : 10; /* the steps per trajectory from these */
        double c0 = cpu_seconds();
        if (rf_terrain_run(&s, 1, NULL, NULL, &e, &err) != RF_OK) {
            fprintf(stderr, "bench_block: %s\n", err.msg);
        } else {
            double cpu = cpu_seconds() - c0, runout = 0, steps = 0, stopped = 0, t = 0;
            for (size_t i = 0; i < e.samples; i++)
                runout += e.runout_x[i], stopped += e.state[i] == RF_TRAJ_STOPPED;
            for (size_t i = 0; i < e.terrain->n_recorded; i++)
                steps += (double)e.terrain->recorded[i].n_steps, t += e.terrain->recorded[i].t_end;
            size_t nr = e.terrain->n_recorded;
            printf("%-6s engine      %5zu: %8.1f traj/s  %8.0f steps/traj  %5.1f s/traj (%zu recorded)  runout %5.1f m  "
                   "stopped %3.0f %%\n", name, n, (double)n / cpu, steps / (double)nr, t / (double)nr, nr,
                   runout / (double)n, 100 * stopped / (double)n);
            rf_traj_ensemble_free(&e);
            rc = 0;
        }
        rf_traj_spec_free(&s);
    }
    const char *files[2] = {"dem.asc", "block.yaml"};
    for (int k = 0; k < 2; k++)
        snprintf(path, sizeof path, "%s/%s", dir, files[k]), unlink(path);
    rmdir(dir);
    return rc;
}

int main(int argc, char **argv)
{
    int n_adapt = argc > 1 ? atoi(argv[1]) : 1000, n_fixed = argc > 2 ? atoi(argv[2]) : 20;
    double h = argc > 3 ? atof(argv[3]) : 1e-3;
    const char *vtk_dir = argc > 4 && strcmp(argv[4], "-") ? argv[4] : NULL;
    size_t n_engine = argc > 5 ? (size_t)strtoull(argv[5], NULL, 10) : 0;
    rf_block_shape shape[3];
    const char *names[3] = {"cube", "wheel", "rock20"};
    rf_error err;
    if (rf_block_eota_cube(1.0, 2650, &shape[0], &err) || rf_block_eota_wheel(1.0, 2650, &shape[1], &err) ||
        rock20(&shape[2], &err)) {
        fprintf(stderr, "bench_block: %s\n", err.msg);
        return 1;
    }
    planes(&shape[0]);
    for (int j = 0; j < NODES; j++)
        for (int i = 0; i < NODES; i++)
            dem[j * NODES + i] = terrain(i * CELL, j * CELL);
    rf_block_world w = {.e_n = 0.3, .e_t = 0, .mu = 0.6, .g = G, .h = h, .tol = 1e-8, .max_iter = 200,
                        .ground = dem_ground, .ground_bound = dem_bound};
    printf("DEM of bench_terrain (1 km^2, 2 m cells), 1 m^3 blocks released 1 m above (450|500|550, 850), h = %g ms:\n", 1e3 * h);
    for (int k = 0; k < 3; k++) {
        printf("%s: %zu vertices, bounding radius %.3f m\n", names[k], shape[k].n_vertices, shape[k].bound_radius);
        if (n_fixed > 0) {
            run(names[k], &shape[k], w, FIXED, n_fixed);
            run(names[k], &shape[k], w, FIXED_BOUND, n_fixed);
        }
        if (n_adapt > 0)
            run(names[k], &shape[k], w, ADAPTIVE, n_adapt);
        if (vtk_dir && write_vtk(vtk_dir, names[k], &shape[k], &w))
            return 1;
    }
    for (int k = 0; k < 3; k++)
        rf_block_shape_free(&shape[k]);
    char rock[1024];
    int len = snprintf(rock, sizeof rock, "{shape: polyhedron, volume: 1, density: 2650, points: [");
    for (int k = 0; k < 20; k++) { /* rock20's points */
        double z = 1 - (2 * k + 1) / 20.0, r = sqrt(1 - z * z), a = k * PI * (3 - sqrt(5.0));
        len += snprintf(rock + len, sizeof rock - (size_t)len, "%s[%.6f, %.6f, %.6f]", k ? ", " : "",
                        0.8 * r * cos(a), 0.62 * r * sin(a), 0.48 * z);
    }
    snprintf(rock + len, sizeof rock - (size_t)len, "], orientation: random, spin: [0.5, -0.5, 0.5], max_time: 60}");
    const char *blocks[3] = {"{shape: eota_cube, volume: 1, density: 2650, orientation: random, spin: [0.5, -0.5, 0.5], max_time: 60}",
                             "{shape: eota_wheel, volume: 1, density: 2650, orientation: random, spin: [0.5, -0.5, 0.5], max_time: 60}",
                             rock};
    for (int k = 0; k < 3 && n_engine > 0; k++)
        if (engine(names[k], blocks[k], n_engine))
            return 1;
    return 0;
}
