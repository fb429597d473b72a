/* bench_tta.c - time to accuracy of the FE impact solvers (issue 9,
 * docs/fem-speed.md "Time to accuracy"): for each refinement a/h, one run of
 *   3d:  10 m/s vertical impact on a 45 degree slope, f = 0.6 (half model)
 *   axi: 10 m/s normal impact (axisymmetric)
 * at the default settings otherwise (automatic domain, fixed boundary), with
 * wall and CPU time, ns per element-step and the error of R_n, R_t, R_ke
 * against the converged values below (refinement study + Richardson
 * extrapolation, docs/fem-speed.md).  One line per run, key=value.
 *   bench_tta 3d|axi THREADS A [A ...] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/util.h"
#include "rockfuzz/fem3d.h"

/* Converged values (docs/fem-speed.md, "Converged values"). */
/* R_n, R_t, R_ke (+- 6e-5, 3e-5, 3e-5); R_t and R_ke moved by -3.7e-4 and +9e-5 with the friction
   along the face's tangents (measured at a/h 6-8, docs/fem-speed.md) */
static const double CONV_3D[3] = {0.98886, 0.63576, 0.85603};
static const double CONV_AXI_RN = 0.985958; /* +- 5e-6 */

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 4 || (strcmp(argv[1], "3d") && strcmp(argv[1], "axi"))) {
        fprintf(stderr, "usage: bench_tta 3d|axi THREADS A [A ...]\n");
        return 2;
    }
    const int three_d = !strcmp(argv[1], "3d"), threads = atoi(argv[2]);
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10};
    if (three_d)
        in.slope_angle = 45 * RF_PI / 180, in.friction = 0.6;
    for (int i = 3; i < argc; i++) {
        rf_fem_options o;
        rf_fem_options_default(&o);
        o.refinement = atof(argv[i]);
        o.threads = threads;
        rf_impact_output out;
        rf_error err;
        const double c0 = cpu_seconds();
        rf_status st = three_d ? rf_fem3d_impact_ex(&in, &o, NULL, &out, NULL, NULL, &err)
                               : rf_fem_impact(&in, &o, &out, NULL, &err);
        const double cpu = cpu_seconds() - c0;
        if (st != RF_OK) {
            fprintf(stderr, "bench_tta: %s\n", err.msg);
            return 1;
        }
        const double es = out.elements * out.steps;
        printf("model=%s threads=%d ref=%g elements=%.0f steps=%.0f wall=%.3f cpu=%.3f ns_wall=%.1f ns_cpu=%.1f "
               "R_n=%.9f R_t=%.9f R_ke=%.9f",
               argv[1], threads, o.refinement, out.elements, out.steps, out.wall_seconds, cpu,
               1e9 * out.wall_seconds / es, 1e9 * cpu / es, out.R_n, three_d ? out.R_t : 0.0, out.R_ke);
        if (three_d)
            printf(" err_R_n=%.2e err_R_t=%.2e err_R_ke=%.2e\n", fabs(out.R_n - CONV_3D[0]),
                   fabs(out.R_t - CONV_3D[1]), fabs(out.R_ke - CONV_3D[2]));
        else
            printf(" err_R_n=%.2e\n", fabs(out.R_n - CONV_AXI_RN));
        fflush(stdout);
    }
    return 0;
}
