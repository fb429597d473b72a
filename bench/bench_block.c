/* bench_block.c - speed of the rigid-block core (issue 30; block_*.c): Moreau
 * steps per second of a polyhedral block (the EOTA cube stand-in, 24
 * vertices) in flight (every vertex tested against the ground each step)
 * and sliding on a plane (4..8 contacts, prox Gauss-Seidel), and
 * drop-and-tumble trajectories per second: an EOTA wheel dropped 2 m with a
 * random orientation and spin onto a 30 deg plane, e_n 0.3, mu 0.6, h 1 ms,
 * run 4 s of motion (the issue asks 2 000 polyhedral trajectories per second
 * per core on the terrain benchmark later; this is the plane's figure).
 * CPU seconds, one thread.  Usage: bench_block [trajectories (default 200)] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <math.h>

#include "rockfuzz/block.h"

#define G 9.81
#define PI 3.14159265358979323846

static double cpu_seconds(void)
{
    return (double)clock() / CLOCKS_PER_SEC;
}

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / 16777216.0;
}

static double steps_per_second(const rf_block_shape *s, const rf_block_world *w, rf_block_state st0, long n,
                               double *contacts)
{
    rf_block_state st = st0;
    double t0 = cpu_seconds(), nc = 0;
    for (long k = 0; k < n; k++) {
        rf_block_step_info info;
        rf_block_step(s, w, &st, &info);
        nc += info.n_contacts;
    }
    *contacts = nc / n;
    return n / (cpu_seconds() - t0);
}

int main(int argc, char **argv)
{
    int n_traj = argc > 1 ? atoi(argv[1]) : 200;
    rf_block_shape cube, wheel;
    rf_error err;
    if (rf_block_eota_cube(1.0, 2650, &cube, &err) || rf_block_eota_wheel(1.0, 2650, &wheel, &err)) {
        fprintf(stderr, "bench_block: %s\n", err.msg);
        return 1;
    }
    double beta = 30 * PI / 180;
    rf_block_plane flat = {{0, 0, 0}, {0, 0, 1}}, slope = {{0, 0, 0}, {sin(beta), 0, cos(beta)}};
    rf_block_world w = {.e_n = 0.3, .e_t = 0, .mu = 0.6, .g = G, .h = 1e-3, .tol = 1e-8, .max_iter = 200,
                        .n_planes = 1, .planes = &flat};
    rf_block_state fly = {{0, 0, 1e6}, {1, 0, 0, 0}, {10, 0, 0}, {1, 2, 3}}, rest = {{0, 0, 0}, {1, 0, 0, 0}, {0}, {0}};
    rf_block_quat_from_matrix(cube.axes, rest.q);
    double pz[3], up[3] = {0, 0, 1}, nc;
    rest.x[2] = -rf_block_lowest_point(&cube, &rest, up, pz);
    rest.v[0] = 5;
    printf("EOTA cube (%zu vertices), h = 1 ms, prox tol 1e-8:\n", cube.n_vertices);
    printf("  flight:  %.3g steps/s\n", steps_per_second(&cube, &w, fly, 1000000, &nc));
    double sps = steps_per_second(&cube, &w, rest, 200000, &nc);
    printf("  sliding on a plane: %.3g steps/s (%.1f contacts per step)\n", sps, nc);

    w.planes = &slope;
    unsigned seed = 11;
    long steps = 0, contact_steps = 0;
    double t0 = cpu_seconds(), run = 0;
    for (int k = 0; k < n_traj; k++) {
        rf_block_state st = {{0, 0, 0}, {urand(&seed) - 0.5, urand(&seed) - 0.5, urand(&seed) - 0.5,
                                           urand(&seed) - 0.5}, {3, 0, 0}, {0}};
        double qn = sqrt(st.q[0] * st.q[0] + st.q[1] * st.q[1] + st.q[2] * st.q[2] + st.q[3] * st.q[3]);
        for (int i = 0; i < 4; i++)
            st.q[i] /= qn;
        for (int i = 0; i < 3; i++)
            st.w[i] = 10 * (urand(&seed) - 0.5);
        double nrm[3] = {sin(beta), 0, cos(beta)};
        double low = rf_block_lowest_point(&wheel, &st, nrm, pz);
        for (int i = 0; i < 3; i++)
            st.x[i] += (2.0 - low) * nrm[i];
        for (int n = 0; n < 4000; n++) {
            rf_block_step_info info;
            rf_block_step(&wheel, &w, &st, &info);
            steps++, contact_steps += info.n_contacts > 0;
        }
        run += st.x[0];
    }
    double dt = cpu_seconds() - t0;
    printf("EOTA wheel (%zu vertices) dropped onto a 30 deg plane, 4 s each: %.1f trajectories/s, %.3g steps/s "
           "(%.0f%% of steps in contact), mean run %.1f m along x\n",
           wheel.n_vertices, n_traj / dt, steps / dt, 100.0 * contact_steps / steps, run / n_traj);
    rf_block_shape_free(&cube);
    rf_block_shape_free(&wheel);
    return 0;
}
