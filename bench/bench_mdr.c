/* bench_mdr.c - cost of one analytic oblique impact: the rigid-body model and
 * the MDR partial-slip model (rockfuzz/mdr.h) with its default discretisation
 * and a fine one, through rf_impact_solve, on 10 m/s granite impacts on 30, 45
 * and 60 deg slopes with f from 0.1 to 5 (the S4 range and beyond).
 * Usage: bench_mdr [repeats] (default 20). Prints microseconds per impact. */
#include <stdio.h>
#include <stdlib.h>

#include "core/util.h"
#include "rockfuzz/impact_model.h"
#include "rockfuzz/mdr.h"

static double time_solver(rf_impact_solver solver, int repeats, double *checksum)
{
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = solver;
    const double angle[] = {30, 45, 60}, friction[] = {0.1, 0.3, 0.6, 1.0, 5.0};
    double t0 = rf_monotonic_seconds();
    for (int r = 0; r < repeats; r++)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 5; j++) {
                rf_impact_input in = spec.base;
                in.slope_angle = angle[i] * RF_PI / 180.0;
                in.friction = friction[j];
                rf_impact_output out;
                if (rf_impact_solve(&spec, &in, &out, NULL) == RF_OK)
                    *checksum += out.R_t;
            }
    return (rf_monotonic_seconds() - t0) / (repeats * 15.0) * 1e6;
}

static double time_fine_mdr(int repeats, double *checksum)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    rf_mdr_problem p = {.radius = 1.0, .mass = rf_impact_mass(&in), .inertia = rf_impact_moment_of_inertia(&in),
                        .E_star = rf_impact_effective_modulus(&in), .G_star = rf_mdr_tangential_modulus(&in),
                        .friction = 0.6, .e_n = 1.0, .v_n = 7.0710678, .v_t = 7.0710678};
    rf_mdr_options o = {800, 3200};
    double t0 = rf_monotonic_seconds();
    for (int r = 0; r < repeats; r++) {
        rf_mdr_result res;
        if (rf_mdr_impact(&p, &o, &res, NULL) == RF_OK)
            *checksum += res.v_t_after;
    }
    return (rf_monotonic_seconds() - t0) / repeats * 1e6;
}

int main(int argc, char **argv)
{
    int repeats = argc > 1 ? atoi(argv[1]) : 20;
    if (repeats < 1)
        repeats = 1;
    double checksum = 0.0;
    printf("rigid (Hunter e_n):              %10.2f us per impact\n",
           time_solver(RF_IMPACT_RIGID, repeats * 100, &checksum));
    printf("mdr (Hunter e_n, 100 x 400):     %10.2f us per impact\n", time_solver(RF_IMPACT_MDR, repeats, &checksum));
    printf("mdr fine (800 springs x 3200):   %10.2f us per impact\n", time_fine_mdr(repeats, &checksum));
    printf("(checksum %.6f)\n", checksum);
    return 0;
}
