/* test_fem3d_large_accuracy.c - large deformation in the 3D FE model against
 * independent references at meshes fine enough for the tolerances (label
 * `accuracy`; the code paths run coarse in tests/test_fem3d_large.c): the
 * small-strain model at a small speed (elastic), and the axisymmetric
 * large-deformation model on soft Drucker-Prager + cap soil, whose gap to
 * the 3D one must close as both meshes are refined (docs/validation-plastic.md
 * section 9c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>

#include "fem3d_large_inputs.h"

/* (c) Elastic granite on granite at 1 m/s (a/h = 2, absorbing boundary at
 * 3 r0): the contact strains are ~a/r0, and the updated-Lagrangian kernel
 * (the linear, hypoelastic law on the current geometry, every deformable
 * body) must give the small-strain result up to geometric terms of that
 * order, which act on the energy lost to waves: |dR_n| < (a / r0)(1 - R_n),
 * F_max within a / r0. */
static void test_small_velocity_agrees(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    in.velocity = 1;
    rf_impact_output on, off;
    rf_fem_options o = large_options(2, RF_FEM_LARGE_DEFORMATION);
    run3d_ex(&in, &o, NULL, &on, NULL, NULL);
    o.large_deformation = RF_FEM_SMALL_STRAIN;
    run3d_ex(&in, &o, NULL, &off, NULL, NULL);
    rf_hertz_reference H;
    rf_impact_hertz_reference(&in, &H);
    const double strain = H.contact_radius / in.radius, bound = strain * (1 - off.R_n);
    show("elastic 1 m/s, large", &on);
    show("elastic 1 m/s, small strain", &off);
    print_message("dR_n %.2e (bound (a/r0)(1 - R_n) = %.2e), dF_max/F_max %.2e (bound a/r0 = %.2e)\n",
                  on.R_n - off.R_n, bound, on.contact_force_max / off.contact_force_max - 1, strain);
    assert_true(fabs(on.R_n - off.R_n) < bound);
    assert_true(fabs(on.contact_force_max / off.contact_force_max - 1) < strain);
    assert_true(fabs(on.energy_error) < 5e-3);
}

/* auto keeps an elastic body on its small-strain kernel (its strains stay ~a/r0; test above): a
 * von Mises boulder (Y = 200 MPa) at 10 m/s on elastic granite, a/h = 2, auto (the slope small
 * strain, matrix-free) against on (the slope on the UL kernel too): the same bound on R_n. */
static void test_auto_keeps_elastic_slope(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    in.boulder_material = RF_MATERIAL_VON_MISES, in.boulder_yield = 200e6;
    rf_impact_output au, on;
    rf_fem_options o = large_options(2, RF_FEM_KINEMATICS_AUTO);
    run3d_ex(&in, &o, NULL, &au, NULL, NULL);
    o.large_deformation = RF_FEM_LARGE_DEFORMATION;
    run3d_ex(&in, &o, NULL, &on, NULL, NULL);
    rf_hertz_reference H;
    rf_impact_hertz_reference(&in, &H);
    const double strain = H.contact_radius / in.radius, bound = strain * (1 - on.R_n);
    show("J2 boulder 10 m/s, auto", &au);
    show("J2 boulder 10 m/s, on", &on);
    print_message("dR_n %.2e (bound (a/r0)(1 - R_n) = %.2e), dW_p/W_p %.2e; wall %.2f / %.2f s (shared machine)\n",
                  au.R_n - on.R_n, bound, au.plastic_work / on.plastic_work - 1, au.wall_seconds, on.wall_seconds);
    assert_true(fabs(au.R_n - on.R_n) < bound);
    assert_true(fabs(au.plastic_work / on.plastic_work - 1) < strain);
}

/* (d) A rigid boulder at 5 m/s on soft soil (fem3d_large_inputs.h, penetration 6 % of r0, plastic
 * strains 0.15-0.2), 3D against the axisymmetric model, both in large deformation.  The two meshes
 * (cubes, quads) differ; their gap must shrink with refinement (measured in R_n: 1.7 % at a/h = 2,
 * 0.4 % at 6) and at a/h = 6 be below 1 % in R_n, the penetration and W_p / KE; energy within
 * 5e-3 KE0. */
static void test_soft_soil_converges(void **state)
{
    (void)state;
    const rf_impact_input in = soft_soil_3d(0);
    const rf_fem3d_options o3 = large_options3d();
    double gap[2];
    rf_impact_output r3, ax;
    for (int k = 0; k < 2; k++) {
        const rf_fem_options o = large_options(k ? 6 : 2, RF_FEM_KINEMATICS_AUTO);
        run3d_ex(&in, &o, &o3, &r3, NULL, NULL);
        rf_error err = {0};
        assert_int_equal(rf_fem_impact(&in, &o, &ax, NULL, &err), RF_OK);
        print_message("a/h = %g\n", o.refinement);
        show("soft soil 3D, large", &r3);
        show("soft soil axisym., large", &ax);
        gap[k] = fabs(r3.R_n / ax.R_n - 1);
        assert_true(fabs(r3.energy_error) < 5e-3 && fabs(ax.energy_error) < 5e-3);
    }
    assert_true(gap[1] < gap[0]);
    assert_true(gap[1] < 0.01);
    assert_true(fabs(r3.penetration_max / ax.penetration_max - 1) < 0.01);
    assert_true(fabs(r3.plastic_work / ax.plastic_work - 1) < 0.01);
}

/* (d) on a layer: section 9b's layer case (rigid boulder, 10 m/s, a 0.1 m DP + cap layer over
 * granite), both models in large deformation at a/h = 2 and 3, against section 9b's tolerances for
 * the same problem in small strain (measured there 1.1-3 % in R_n): 4 % in R_n, 2 % in W_p / KE and
 * the penetration, 3 % in the crater; energy within 5e-3 KE0.  Measured: 3D - axisymmetric in R_n
 * +1.5 % at a/h 2, +1.3 % at 3 (small strain: -1.1 %, -2.1 %). */
static void test_layer_vs_axisymmetric(void **state)
{
    (void)state;
    const rf_impact_input in = dp_layer_case();
    for (int ref = 2; ref <= 3; ref++) {
        const rf_fem_options o = large_options(ref, RF_FEM_KINEMATICS_AUTO);
        rf_impact_output l3, ax;
        rf_fem_history h3 = {0};
        run3d_ex(&in, &o, NULL, &l3, &h3, NULL);
        rf_error err = {0};
        assert_int_equal(rf_fem_impact(&in, &o, &ax, NULL, &err), RF_OK);
        print_message("a/h = %d\n", ref);
        show("DP layer 3D, large", &l3);
        show("DP layer axisym., large", &ax);
        assert_true(fabs(l3.R_n / ax.R_n - 1) < 0.04);
        assert_true(fabs(l3.plastic_work / ax.plastic_work - 1) < 0.02);
        assert_true(fabs(l3.penetration_max / ax.penetration_max - 1) < 0.02);
        assert_true(fabs(l3.indentation_depth / ax.indentation_depth - 1) < 0.03);
        assert_true(fabs(l3.energy_error) < 5e-3 && fabs(ax.energy_error) < 5e-3);
        assert_true(h3.plastic_work_boulder == 0 && h3.plastic_work_slope > 0 && h3.plastic_strain_max_in == 2);
        rf_fem_history_free(&h3);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_velocity_agrees),
        cmocka_unit_test(test_auto_keeps_elastic_slope),
        cmocka_unit_test(test_soft_soil_converges),
        cmocka_unit_test(test_layer_vs_axisymmetric),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
