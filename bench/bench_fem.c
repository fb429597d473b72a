/* bench_fem.c - speed of the axisymmetric FE impact solver: wall time per
 * impact and nanoseconds per element-step, granite sphere at 1, 10, 30 m/s.
 *   bench_fem [refinement=10] [threads=1] [repeats=3] [domain_factor=0]
 * domain_factor 0 is the automatic default (sized from the Hertz duration);
 * 10 is the seed paper's domain.
 * Prints the best of `repeats` runs (other jobs share the machine). */
#include <stdio.h>
#include <stdlib.h>

#include "rockfuzz/fem.h"

int main(int argc, char **argv)
{
    double ref = argc > 1 ? atof(argv[1]) : 10;
    int threads = argc > 2 ? atoi(argv[2]) : 1;
    int repeats = argc > 3 ? atoi(argv[3]) : 3;
    double domain = argc > 4 ? atof(argv[4]) : 0;
    const double speeds[3] = {1, 10, 30};
    printf("# refinement a/h = %g, threads = %d, domain factor %g (0 = automatic), best of %d\n", ref, threads,
           domain, repeats);
    printf("%8s %9s %9s %8s %10s %12s\n", "v[m/s]", "elements", "steps", "wall[s]", "ns/el-step", "R_n");
    for (int k = 0; k < 3; k++) {
        rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                              .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25,
                              .velocity = speeds[k]};
        rf_fem_options o;
        rf_fem_options_default(&o);
        o.refinement = ref;
        o.threads = threads;
        o.domain_factor = domain;
        double best = 1e300;
        rf_impact_output out = {0};
        for (int r = 0; r < repeats; r++) {
            rf_error err = {0};
            if (rf_fem_impact(&in, &o, &out, NULL, &err) != RF_OK) {
                fprintf(stderr, "bench_fem: %s\n", err.msg);
                return 1;
            }
            if (out.wall_seconds < best)
                best = out.wall_seconds;
        }
        printf("%8g %9.0f %9.0f %8.3f %10.2f %12.7f\n", speeds[k], out.elements, out.steps, best,
               1e9 * best / (out.elements * out.steps), out.R_n);
    }
    return 0;
}
