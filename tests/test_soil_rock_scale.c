/* test_soil_rock_scale.c - the FE option rock_mass_scale (fem.h; the rock
 * under a soil layer with its inertia times K, its stiffness and weight kept;
 * docs/soil-impacts.md section 3), in the axisymmetric model:
 *   - the mechanism: while the rock's elements set the explicit step, the
 *     element eigenvalue bound is sqrt(K) times the unscaled one (lumped
 *     masses times K, stiffness kept: every rock eigenvalue over K); once
 *     the layer's elements set it (its contact face, redistributed as in the
 *     full model, at kappa = 0.1 of the unscaled largest eigenvalue), a
 *     larger K changes nothing (the same bound for K = 1e3 and 1e4, between
 *     2 and sqrt(1e3) times the unscaled one);
 *   - the same in the 3D model (S5 on a 30 deg incline, a/h 2): x2 at K = 4;
 *   - without a layer the option is ignored: the same result to the bit;
 *   - the physics: on the S5 layer at 5 m/s (mesh sizing soil, a/h 6) R_n
 *     with K = 100 is within 0.002 of the full model's and the largest
 *     penetration within 0.5 % (measured: 5e-5 and 0.01 %), and the scaled
 *     run's energy account closes below 5e-4 of KE0 (measured 2.0e-4, the
 *     full model's; scaling the rock before the face's mass redistribution,
 *     which then lost its reference, gave 2.0e-3). */
#include <math.h>
#include <stdio.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "core/util.h"
#include "rockfuzz/fem.h"
#include "rockfuzz/fem3d.h"

/* The S5 nominal layer (examples/s5_v5.yaml) at 5 m/s, rigid boulder. */
static void s5_layer(rf_impact_input *in)
{
    rf_impact_input_default(in);
    in->radius = 0.5, in->velocity = 5, in->boulder_material = RF_MATERIAL_RIGID_BODY;
    in->gravity = RF_GRAVITY_AUTO;
    in->layer_thickness = 1.0, in->layer_density = 1900, in->layer_E = 100e6, in->layer_poisson = 0.3;
    in->layer_material = RF_MATERIAL_DRUCKER_PRAGER, in->layer_cohesion = 10e3;
    in->layer_friction_angle = 40 * RF_PI / 180, in->layer_dilatancy_angle = 5 * RF_PI / 180;
    in->layer_cap_pressure = 200e3, in->layer_cap_hardening = 40e6;
}

typedef struct {
    double R_n, pen, dt_bound, closure;
} run_result;

static run_result run(const rf_impact_input *in, double refinement, double K, double end_time)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = refinement, o.mesh_sizing = RF_FEM_SIZING_SOIL, o.rock_mass_scale = K, o.end_time = end_time;
    rf_impact_output out;
    rf_fem_history H = {0};
    rf_error err = {0};
    if (rf_fem_impact(in, &o, &out, &H, &err) != RF_OK)
        fail_msg("K = %g: %s", K, err.msg);
    run_result r = {out.R_n, out.penetration_max, H.dt_bound, H.closure[H.n - 1] / H.ke0};
    rf_fem_history_free(&H);
    return r;
}

static void test_step_bound(void **state)
{
    (void)state;
    rf_impact_input in;
    s5_layer(&in);
    const double b1 = run(&in, 4, 1, 1e-6).dt_bound, b4 = run(&in, 4, 4, 1e-6).dt_bound;
    if (fabs(b4 / b1 - 2) > 1e-9)
        fail_msg("K = 4: bound %g s against %g s unscaled (ratio %.12g, want 2)", b4, b1, b4 / b1);
    const double b1e3 = run(&in, 4, 1e3, 1e-6).dt_bound, b1e4 = run(&in, 4, 1e4, 1e-6).dt_bound;
    assert_true(b1e3 == b1e4);
    assert_true(b1e3 < sqrt(1e3) * b1 * (1 - 1e-6) && b1e3 > 2 * b1);
}

static double bound_3d(const rf_impact_input *in, double K)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 2, o.rock_mass_scale = K, o.end_time = 1e-6;
    rf_impact_output out;
    rf_fem_history H = {0};
    rf_error err = {0};
    if (rf_fem3d_impact(in, &o, &out, &H, &err) != RF_OK)
        fail_msg("3D, K = %g: %s", K, err.msg);
    const double b = H.dt_bound;
    rf_fem_history_free(&H);
    return b;
}

static void test_step_bound_3d(void **state)
{
    (void)state;
    rf_impact_input in;
    s5_layer(&in);
    in.velocity = 10, in.slope_angle = 30 * RF_PI / 180, in.friction = 0.5;
    const double b1 = bound_3d(&in, 1), b4 = bound_3d(&in, 4);
    if (fabs(b4 / b1 - 2) > 1e-9)
        fail_msg("3D K = 4: bound %g s against %g s unscaled (ratio %.12g, want 2)", b4, b1, b4 / b1);
}

static void test_ignored_without_layer(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = 2;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 4;
    rf_impact_output a, b;
    assert_int_equal(rf_fem_impact(&in, &o, &a, NULL, NULL), RF_OK);
    o.rock_mass_scale = 100;
    assert_int_equal(rf_fem_impact(&in, &o, &b, NULL, NULL), RF_OK);
    assert_true(a.R_n == b.R_n && a.steps == b.steps && a.contact_force_max == b.contact_force_max);
}

static void test_against_full_model(void **state)
{
    (void)state;
    rf_impact_input in;
    s5_layer(&in);
    const run_result full = run(&in, 6, 1, 0), scaled = run(&in, 6, 100, 0);
    print_message("S5 5 m/s a/h 6: R_n %.5f (K 100) against %.5f, penetration %.5f against %.5f m, "
                  "closure %.2e KE0, step bound %.3g against %.3g s\n",
                  scaled.R_n, full.R_n, scaled.pen, full.pen, scaled.closure, scaled.dt_bound, full.dt_bound);
    assert_true(fabs(scaled.R_n - full.R_n) < 0.002);
    assert_true(fabs(scaled.pen - full.pen) < 0.005 * full.pen);
    assert_true(fabs(scaled.closure) < 5e-4);
    assert_true(scaled.dt_bound > 3 * full.dt_bound); /* the lever took: the rock no longer sets the step */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_step_bound),
        cmocka_unit_test(test_step_bound_3d),
        cmocka_unit_test(test_ignored_without_layer),
        cmocka_unit_test(test_against_full_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
