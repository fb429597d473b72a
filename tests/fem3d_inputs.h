/* fem3d_inputs.h - shared by tests/test_fem3d.c (logic, coarse meshes) and
 * tests/test_fem3d_accuracy.c (against Hertz, the rigid-body formulas and the
 * axisymmetric model): elastic granite and one 3D run.  Include after
 * cmocka.h. */
#ifndef ROCKFUZZ_FEM3D_INPUTS_H
#define ROCKFUZZ_FEM3D_INPUTS_H

#include <stdio.h>
#include <string.h>

#include "rockfuzz/fem3d.h"
#include "fem/fem_tuning.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static inline rf_impact_input granite(double v, double angle_deg, double f)
{
    rf_impact_input in;
    memset(&in, 0, sizeof in);
    in.radius = 1;
    in.boulder_density = in.slope_density = 2600;
    in.boulder_E = in.slope_E = 68.2e9;
    in.boulder_poisson = in.slope_poisson = 0.25;
    in.velocity = v;
    in.slope_angle = angle_deg * M_PI / 180;
    in.friction = f;
    return in;
}

static inline void run(const rf_impact_input *in, double ref, int threads, int full, rf_impact_output *out,
                       rf_fem3d_report *rep)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = ref;
    o.threads = threads;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    o3.full_model = full;
    rf_error err = {0};
    rf_status st = rf_fem3d_impact_ex(in, &o, &o3, out, NULL, rep, &err);
    if (st != RF_OK)
        fprintf(stderr, "fem3d failed: %s\n", err.msg);
    assert_int_equal(st, RF_OK);
}

#endif
