/* bench_fem3d.c - wall time of one 3D impact (10 m/s, 45 degree slope,
 * f = 0.6, half model) on 1 and 2 threads, and ns per element-step.
 *   bench_fem3d [refinement (a/h), default 6] [max threads, default 2] [domain factor, default 0 = automatic]
 * The results must not depend on the thread count: the state hashes are
 * printed and compared. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"
#include "rockfuzz/fem3d.h"

int main(int argc, char **argv)
{
    double ref = argc > 1 ? atof(argv[1]) : 6;
    int tmax = argc > 2 ? atoi(argv[2]) : 2;
    double domain = argc > 3 ? atof(argv[3]) : 0;
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10,
                          .slope_angle = 45 * RF_PI / 180, .friction = 0.6};
    unsigned long long h1 = 0;
    int same = 1;
    for (int t = 1; t <= tmax; t++) {
        rf_fem_options o;
        rf_fem_options_default(&o);
        o.refinement = ref;
        o.threads = t;
        o.domain_factor = domain;
        rf_impact_output out;
        rf_fem3d_report rep;
        rf_error err;
        if (rf_fem3d_impact_ex(&in, &o, NULL, &out, NULL, &rep, &err) != RF_OK) {
            fprintf(stderr, "bench_fem3d: %s\n", err.msg);
            return 1;
        }
        double ns = 1e9 * out.wall_seconds / (out.elements * out.steps);
        printf("threads=%d ref=%g domain=%g elements=%.0f steps=%.0f wall=%.3f s ns_per_element_step=%.1f R_t=%.6f "
               "omega=%.5f hash=%016llx\n",
               t, ref, rf_fem_domain_factor(&o, &in), out.elements, out.steps, out.wall_seconds, ns, out.R_t, out.omega_after,
               (unsigned long long)rep.state_hash);
        if (t == 1)
            h1 = rep.state_hash;
        else if (rep.state_hash != h1)
            same = 0;
        rf_fem3d_report_free(&rep);
    }
    printf("identical results across thread counts: %s\n", same ? "yes" : "NO");
    return same ? 0 : 1;
}
