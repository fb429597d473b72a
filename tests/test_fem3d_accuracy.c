/* test_fem3d_accuracy.c - the 3D explicit impact solver against independent
 * references at the meshes those need (a/h = 3; labelled `accuracy`: the
 * sanitizer half of scripts/test.sh leaves it out; tests/test_fem3d.c runs the
 * same code paths on coarse meshes there): Hertz at low speed with energy
 * closure, a frictionless oblique impact (R_t = 1, R_n of the normal impact at
 * v_n), the rigid-body sliding regime at 60 degrees, and R_n of an oblique
 * frictional impact against the normal one.  The converged figures are in
 * docs/validation-3d.md. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/fem3d.h"
#include "fem3d_inputs.h"

/* Normal impact at 2 m/s (a/R = 0.07): Hertz within 6 % (coarse mesh, finite-body stiffening
   ~ -19 a/R % in compression, fem_notes.md), energy closure < 1e-3 of KE0. */
static void test_normal_hertz(void **state)
{
    (void)state;
    rf_impact_input in = granite(2, 0, 0);
    rf_impact_output out, hz;
    rf_fem3d_report rep;
    run(&in, 3, 1, 0, &out, &rep);
    rf_error err;
    assert_int_equal(rf_impact_hertz(&in, &hz, &err), RF_OK);
    printf("# normal 2 m/s: F %.4g (Hertz %.4g), delta %.4g (%.4g), t_c %.4g (%.4g), R_n %.5f, closure %.2e\n",
           out.contact_force_max, hz.contact_force_max, out.compression_max, hz.compression_max,
           out.contact_duration, hz.contact_duration, out.R_n, out.energy_error);
    assert_true(fabs(out.contact_force_max / hz.contact_force_max - 1) < 0.06);
    assert_true(fabs(out.compression_max / hz.compression_max - 1) < 0.06);
    assert_true(fabs(out.contact_duration / hz.contact_duration - 1) < 0.06);
    assert_true(fabs(out.contact_radius / hz.contact_radius - 1) < 0.10);
    assert_true(out.R_n > 0.97 && out.R_n < 1.0);
    assert_true(out.energy_error < 1e-3);
    assert_true(fabs(out.omega_after) < 1e-6);
    rf_fem3d_report_free(&rep);
}

/* R_n of the normal impact at v_n = 10 cos 45 m/s, the axisymmetric model at a/h = 8 (converged to
   1e-5): the reference of the 45 degree impacts below. */
static double normal_rn_at_vn(void)
{
    rf_impact_input nin = granite(10 * cos(M_PI / 4), 0, 0);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 8;
    rf_impact_output ax;
    rf_error err;
    assert_int_equal(rf_fem_impact(&nin, &o, &ax, NULL, &err), RF_OK);
    return ax.R_n;
}

/* Frictionless 45 degrees: the tangential velocity survives, no spin, and the normal response is
   that of a normal impact at v_n (the axisymmetric model at a/h = 8).  With the bilinear (C0)
   master face the sliding boulder met a spurious tangential force: R_t 0.99865 and R_n 1.2e-3
   above the normal impact at this a/h; the C1 face gives 2e-4 and 1.5e-4. */
static void test_frictionless_45(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 45, 0);
    rf_impact_output out;
    rf_fem3d_report rep;
    run(&in, 3, 1, 0, &out, &rep);
    const double rn = normal_rn_at_vn();
    printf("# 45 deg f=0: R_n %.6f (normal impact at v_n %.6f) R_t %.6f omega %.4f closure %.2e\n", out.R_n,
           rn, out.R_t, out.omega_after, out.energy_error);
    assert_true(fabs(out.R_t - 1) < 1e-3);
    assert_true(fabs(out.R_n - rn) < 5e-4);
    assert_true(fabs(out.omega_after) * 1.0 < 0.02 * out.v_t_before);
    assert_true(rep.friction_work == 0);
    assert_true(out.energy_error < 1e-3);
    rf_fem3d_report_free(&rep);
}

/* 60 degrees, f = 0.1: gross sliding throughout (psi1 = 14.8 > 5), so the rigid-body formulas
   hold with the FE's own R_n: R_t = 1 - f (1 + R_n)/tan(alpha), omega r = 2.5 f (1 + R_n) v_n. */
static void test_sliding_60(void **state)
{
    (void)state;
    const double f = 0.1, al = 60 * M_PI / 180;
    rf_impact_input in = granite(10, 60, f);
    rf_impact_output out;
    rf_fem3d_report rep;
    run(&in, 3, 1, 0, &out, &rep);
    double Rt = 1 - f * (1 + out.R_n) / tan(al);
    double w = 2.5 * f * (1 + out.R_n) * 10 * cos(al) / 1.0;
    printf("# 60 deg f=0.1: R_n %.5f R_t %.5f (rigid %.5f) omega %.4f (rigid %.4f) stick %.3f closure %.2e\n",
           out.R_n, out.R_t, Rt, out.omega_after, w, rep.stick_fraction, out.energy_error);
    assert_true(fabs(out.R_t - Rt) < 0.005);
    assert_true(fabs(out.omega_after / w - 1) < 0.03);
    /* the faceted mesh's lumped I_yy is corrected to the sphere's (before: +1 % at a/h = 3); what is
       left is the boulder's deformation at the end of the run */
    printf("# lumped I_yy / exact - 1 = %.2e\n", rep.inertia_lumped / rep.inertia_exact - 1);
    assert_true(fabs(rep.inertia_lumped / rep.inertia_exact - 1) < 1e-4);
    assert_true(rep.friction_work > 0);
    assert_true(out.energy_error < 1e-3);
    rf_fem3d_report_free(&rep);
}

/* For identical elastic bodies (Dundurs beta = 0) the quasi-static normal contact problem does not
   feel the tangential tractions, so R_n of the 10 m/s, 45 degree, f = 0.6 impact is close to that
   of a normal impact at v_n = 7.07 m/s (the axisymmetric model, converged to 1e-5 at a/h = 8).
   The lumped centre of mass 1e-3 r down-slope turned the frictional spin into a normal
   contact-point velocity and put the 3D R_n 2.0e-3 low at a/h = 3 (docs/fem-speed.md section 5).
   Now: 4.0e-4 above at a/h = 3, of which 2e-4 is the converged 3D value's own offset (0.98886
   against 0.98866) and 1.7e-4 the a/h = 3 mesh. */
static void test_oblique_rn_uncoupled(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 45, 0.6);
    rf_impact_output out;
    rf_fem3d_report rep;
    run(&in, 3, 1, 0, &out, &rep);
    const double rn = normal_rn_at_vn();
    printf("# 45 deg f=0.6 R_n %.6f, normal impact at v_n (axisymmetric) %.6f\n", out.R_n, rn);
    assert_true(fabs(out.R_n - rn) < 5e-4);
    rf_fem3d_report_free(&rep);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_hertz),
        cmocka_unit_test(test_frictionless_45),
        cmocka_unit_test(test_sliding_60),
        cmocka_unit_test(test_oblique_rn_uncoupled),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
