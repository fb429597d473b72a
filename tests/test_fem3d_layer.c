/* test_fem3d_layer.c - a soil layer over bedrock and a rigid boulder in the
 * 3D FE model (fem3d_layer.c, fem3d_rigid.c), on coarse meshes: the
 * homogeneous slope (a layer of the slope's own material, bit for bit),
 * thread independence, an oblique impact of a rigid boulder ploughing a
 * Drucker-Prager layer (energy balance), and the refusals.  The comparisons
 * with Hertz, stiff elastic boulders and the axisymmetric model need finer
 * meshes: test_fem3d_layer_accuracy.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fem3d_layer_inputs.h" /* granite, coarse, run3d_ex, show, dp_layer */

/* (a) A layer of the slope's own material is the homogeneous slope on the same (extruded) mesh, bit
   for bit (both through the linear point law; layered_mesh forces that mesh without a layer). */
static void test_layer_of_slope_material(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    rf_fem_options o = coarse(2);
    o.kernel[1] = RF_FEM_KERNEL_POINTS;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    o3.layered_mesh = 1;
    o.boundary = RF_FEM_BOUNDARY_FIXED; /* (the layer's dashpot areas are summed apart: other round-off) */
    rf_impact_output hom, lay, og;
    rf_fem_history hh = {0};
    uint64_t h1, h2;
    run3d_ex(&in, &o, &o3, &hom, &hh, &h1);
    /* the interface on the second node plane (z = -2 h): the same mesh */
    in.layer_thickness = 2 * hh.h_contact, in.layer_density = in.slope_density, in.layer_E = in.slope_E;
    in.layer_poisson = in.slope_poisson, in.layer_material = RF_MATERIAL_ELASTIC;
    run3d_ex(&in, &o, NULL, &lay, NULL, &h2);
    show("homogeneous, extruded mesh", &hom);
    show("layer = slope", &lay);
    assert_true(h1 == h2);
    assert_true(hom.R_n == lay.R_n && hom.contact_force_max == lay.contact_force_max);
    /* the hemispherical O-grid: another mesh of the same problem */
    in.layer_thickness = 0;
    run3d_ex(&in, &o, NULL, &og, NULL, NULL);
    show("homogeneous, O-grid", &og);
    rf_fem_history_free(&hh);
    assert_true(fabs(og.R_n - hom.R_n) < 0.01 && fabs(og.contact_force_max / hom.contact_force_max - 1) < 0.02);
}






/* (e) The same bits on 1 and 2 threads: rigid boulder, DP layer, 30 degrees, f = 0.5. */
static void test_threads(void **state)
{
    (void)state;
    rf_impact_input in = granite(30, 0.5);
    in.boulder_material = RF_MATERIAL_RIGID_BODY;
    dp_layer(&in, 0.1);
    rf_fem_options o = coarse(2);
    o.domain_factor = 3, o.end_time = 2e-3; /* the loading half of the impact is enough */
    rf_impact_output a, b;
    uint64_t ha, hb;
    run3d_ex(&in, &o, NULL, &a, NULL, &ha);
    o.threads = 2;
    run3d_ex(&in, &o, NULL, &b, NULL, &hb);
    assert_true(ha == hb);
    assert_true(a.contact_force_max == b.contact_force_max);
}

/* (f) 45 degrees, f = 0.6: a rigid boulder on the DP layer ploughs (plastic work, a permanent crater)
   and leaves with less tangential velocity than on bare granite; the energy closes. */
static void test_rigid_oblique_layer(void **state)
{
    (void)state;
    rf_impact_input in = granite(45, 0.6);
    in.boulder_material = RF_MATERIAL_RIGID_BODY;
    rf_fem_options o = coarse(2);
    o.domain_factor = 3;
    rf_impact_output el, dp;
    run3d_ex(&in, &o, NULL, &el, NULL, NULL);
    dp_layer(&in, 0.1);
    rf_fem3d_report rep = {0};
    rf_error err = {0};
    assert_int_equal(rf_fem3d_impact_ex(&in, &o, NULL, &dp, NULL, &rep, &err), RF_OK);
    show("rigid 45 deg granite", &el);
    show("rigid 45 deg DP layer", &dp);
    print_message("friction work %.4f KE0, stick fraction %.3f, omega %.3f rad/s\n",
                  rep.friction_work / (0.5 * rf_impact_mass(&in) * in.velocity * in.velocity), rep.stick_fraction,
                  dp.omega_after);
    assert_true(dp.R_t > 0 && dp.R_t < el.R_t);
    assert_true(dp.R_n < 0.7 * el.R_n);
    assert_true(dp.plastic_work > 0.2 && rep.friction_work > 0);
    assert_true(dp.indentation_depth > 0 && dp.indentation_depth < dp.penetration_max);
    assert_true(dp.omega_after > 0); /* rolls down-slope */
    assert_true(fabs(dp.energy_error) < 5e-3 && fabs(el.energy_error) < 5e-3);
    rf_fem3d_report_free(&rep);
}

/* Refusals naming the field and value: a layer thinner than the contact element; one reaching the
   bottom of the domain. */
static void test_refusals(void **state)
{
    (void)state;
    rf_impact_input in = granite(30, 0);
    dp_layer(&in, 0.01);
    rf_fem_options o = coarse(2);
    rf_impact_output out;
    rf_error err = {0};
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "layer_thickness = 0.01 m is thinner than the element"));
    in.layer_thickness = 6;
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "layer_thickness = 6 m"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layer_of_slope_material),
        cmocka_unit_test(test_threads),
        cmocka_unit_test(test_rigid_oblique_layer),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
