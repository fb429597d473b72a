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

#include "fem_tune.h"
#include "fem/fem3d_spec.h"       /* f3_layer_contact_estimate */
#include "fem3d_layer_inputs.h" /* granite, coarse, run3d_ex, show, dp_layer, s5_soil */

/* (a) A layer of the slope's own material is the homogeneous slope on the same (extruded) mesh, bit
   for bit (both through the linear point law; layered_mesh forces that mesh without a layer). */
static void test_layer_of_slope_material(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    rf_fem_options o = coarse(2);
    TUNE(o).kernel[1] = RF_FEM_KERNEL_POINTS;
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
    /* the faceted contact (sphere_contact_3d off) on the same problem: the same impact within the
       two discretisations' difference at this coarse mesh (measured 0.013 in R_n, 3e-4 in R_t) */
    rf_impact_output fa;
    TUNE(o).sphere_contact_3d = 0;
    run3d_ex(&in, &o, NULL, &fa, NULL, NULL);
    show("rigid 45 deg DP, faceted", &fa);
    assert_true(fabs(fa.energy_error) < 5e-3);
    assert_true(fabs(fa.R_n - dp.R_n) < 0.02 && fabs(fa.R_t - dp.R_t) < 0.02);
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

/* The layer's contact estimate (fem3d_spec.h) against closed forms: an elastic layer is the layer's
   Hertz impact; a cap with X0 -> 0 is Hertz with E*_p = E* H_c / (H_c + M); a von Mises layer with a
   small Y takes the energy at 3 Y: pi R 3Y d^2 / 2 = KE.  And which layers are thick. */
static void test_soft_layer_estimate(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    s5_soil(&in);
    in.layer_material = RF_MATERIAL_ELASTIC;
    rf_impact_input lay = in;
    lay.slope_density = in.layer_density, lay.slope_E = in.layer_E, lay.slope_poisson = in.layer_poisson;
    rf_hertz_reference HL;
    rf_impact_hertz_reference(&lay, &HL);
    f3_layer_contact lc;
    f3_layer_contact_estimate(&in, &lc);
    assert_true(lc.compression == HL.compression && lc.radius == HL.contact_radius && lc.duration == HL.duration);
    assert_true(lc.zone_radius == lc.radius && lc.thick);
    const double R = HL.curvature_radius, ke = 0.5 * HL.mass * in.velocity * in.velocity;
    in.layer_material = RF_MATERIAL_DRUCKER_PRAGER, in.layer_cap_pressure = 1; /* 1 Pa */
    f3_layer_contact_estimate(&in, &lc);
    const double M = in.layer_E * 0.7 / (1.3 * 0.4), Ep = HL.effective_modulus * 40e6 / (40e6 + M);
    const double dp = pow(15 * HL.mass * in.velocity * in.velocity / (16 * Ep * sqrt(R)), 0.4);
    print_message("cap, X0 = 1 Pa: depth %.5f m, Hertz with E*_p %.5f m\n", lc.compression, dp);
    assert_true(fabs(lc.compression / dp - 1) < 1e-4);
    assert_true(fabs(lc.radius - sqrt(R * lc.compression)) < 1e-12);
    const double d2 = 2 * lc.compression;
    assert_true(fabs(lc.zone_radius - fmax(lc.radius, sqrt(2 * R * d2 - d2 * d2))) < 1e-12);
    in.layer_material = RF_MATERIAL_VON_MISES, in.layer_yield = 1e6;
    f3_layer_contact_estimate(&in, &lc);
    const double dv = sqrt(2 * ke / (3 * RF_PI * R * in.layer_yield));
    print_message("von Mises, Y = 1 MPa: depth %.5f m, energy at 3Y %.5f m\n", lc.compression, dv);
    assert_true(fabs(lc.compression / dv - 1) < 2e-3); /* the elastic start: (d_cross / d)^2 ~ 1e-4 */
    assert_true(lc.zone_radius <= 0.95 * in.radius); /* the ball's chord is capped */
    s5_soil(&in);
    f3_layer_contact_estimate(&in, &lc);
    print_message("S5 soil: depth %.4f m, radius %.4f m, zone %.4f m\n", lc.compression, lc.radius, lc.zone_radius);
    assert_true(lc.thick);
    rf_impact_input thin = granite(0, 0);
    dp_layer(&thin, 0.1); /* the 0.1 m rock-like layer: the rock's contact still sizes the mesh */
    f3_layer_contact_estimate(&thin, &lc);
    assert_false(lc.thick);
}

/* A soft layer (the S5 soil, a Hertz radius of 0.4 r0) is accepted with a rigid boulder, its mesh sized
   by its own contact, and the contact stays inside the fine zone (no edge warning) through the loading
   half of the impact (large deformation, the default), on the mesh f3_impact_mesh_spec describes; an
   elastic boulder on it is still refused (its fine box must stay within 0.6 r0). */
static void test_soft_layer_zone(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    s5_soil(&in);
    rf_fem_options o = coarse(2);
    o.domain_factor = 9, o.end_time = 0.02;
    rf_impact_output out;
    rf_fem_history H = {0};
    run3d_ex(&in, &o, NULL, &out, &H, NULL);
    show("rigid on the S5 soil", &out);
    f3_layer_contact lc;
    f3_layer_contact_estimate(&in, &lc);
    print_message("h %.4f m, estimate: depth %.4f m, radius %.4f m; warning: %s\n", H.h_contact, lc.compression,
                  lc.radius, H.warning);
    assert_true(fabs(H.h_contact - lc.radius / 2) < 1e-12);
    assert_null(strstr(H.warning, "edge of the fine zone"));
    assert_true(out.penetration_max > 0.05 && out.plastic_work > 0.5);
    rf_fem_history_free(&H);
    rf_fem3d_options o3; /* the mesh specification benches and tests build is the solver's */
    rf_fem3d_options_default(&o3);
    f3_mesh_spec ms;
    f3_mesh mesh;
    rf_error err = {0};
    f3_impact_mesh_spec(&in, &o, &o3, &ms, NULL, NULL);
    assert_int_equal(f3_mesh_build(&ms, &mesh, TUNE(o).max_elements, &err), RF_OK);
    assert_true((double)mesh.n_elems == out.elements);
    f3_mesh_free(&mesh);
    in.boulder_material = RF_MATERIAL_ELASTIC;
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "too large for an elastic boulder"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layer_of_slope_material),
        cmocka_unit_test(test_threads),
        cmocka_unit_test(test_rigid_oblique_layer),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_soft_layer_estimate),
        cmocka_unit_test(test_soft_layer_zone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
