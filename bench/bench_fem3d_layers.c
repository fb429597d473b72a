/* bench_fem3d_layers.c - how the graded layers' aspect (rf_fem3d_options
 * layer_aspect, radial / tangential size, default 1.6) trades elements for
 * accuracy in the 10 m/s, 45 degree, f = 0.6 impact: the layers hold 90 % of
 * the elements (docs/fem-speed.md), so fewer layers is a speed lever if the
 * coefficients of restitution do not move.
 *   bench_fem3d_layers [a/h, default 4] [aspect ...]   default 1.6 3.2 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/util.h"
#include "rockfuzz/fem3d.h"

int main(int argc, char **argv)
{
    const double ref = argc > 1 ? atof(argv[1]) : 4;
    double aspects[8] = {1.6, 3.2};
    int na = 2;
    if (argc > 2)
        for (na = 0; na < 8 && na + 2 < argc; na++)
            aspects[na] = atof(argv[na + 2]);
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10,
                          .slope_angle = 45 * RF_PI / 180, .friction = 0.6};
    printf("a/h = %g\n%8s %9s %7s %10s %10s %10s %8s\n", ref, "aspect", "elements", "steps", "R_n", "R_t", "R_ke",
           "wall[s]");
    for (int k = 0; k < na; k++) {
        rf_fem_options o;
        rf_fem_options_default(&o);
        o.refinement = ref;
        rf_fem3d_options o3;
        rf_fem3d_options_default(&o3);
        o3.layer_aspect = aspects[k];
        rf_impact_output out;
        rf_error err = {0};
        if (rf_fem3d_impact_ex(&in, &o, &o3, &out, NULL, NULL, &err) != RF_OK) {
            fprintf(stderr, "bench_fem3d_layers: %s\n", err.msg);
            return 1;
        }
        printf("%8.2f %9.0f %7.0f %10.6f %10.6f %10.6f %8.2f\n", aspects[k], out.elements, out.steps, out.R_n, out.R_t,
               out.R_ke, out.wall_seconds);
        fflush(stdout);
    }
    return 0;
}
