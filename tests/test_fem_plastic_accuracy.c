/* test_fem_plastic_accuracy.c - the axisymmetric elasto-plastic model against
 * closed forms at the meshes those need (labelled `accuracy`: the sanitizer
 * half of scripts/test.sh leaves it out; tests/test_fem_plastic.c runs the same
 * code paths on coarse meshes there):
 *   - limit: with a huge yield stress (or cohesion) every plastic model gives
 *     the elastic R_n (1e-4) and no plastic work, in both kinematics, and
 *     B-bar's F_max within 1 % of full integration's at a/h = 3;
 *   - first yield: Hertz theory puts it at p0 = C(nu) Y on the axis below the
 *     surface (Johnson 1985 sec. 4.2; C and the depth recomputed here from the
 *     Hertz axis stresses), hence the yield velocity V_y: no plastic strain
 *     at 0.85 V_y, plastic strain on the axis at the predicted depth at
 *     1.25 V_y (a/h = 6);
 *   - a layer: of the slope's own material it changes nothing; a soft layer
 *     moves F_max between the rock's and the soft material's; a J2 layer
 *     confines the plastic zone. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/fem.h"
#include "fem_plastic_inputs.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* --- limit: huge strength = elastic --- */

static void huge_yield_is_elastic(rf_fem_kinematics kin);

static void test_huge_yield_is_elastic(void **state)
{
    (void)state;
    for (int kin = RF_FEM_SMALL_STRAIN; kin <= RF_FEM_LARGE_DEFORMATION; kin++) /* the elastic run in the same kinematics */
        huge_yield_is_elastic((rf_fem_kinematics)kin);
}

static void huge_yield_is_elastic(rf_fem_kinematics kin)
{
    rf_fem_options o = coarse(3);
    o.large_deformation = kin;
    o.boundary = RF_FEM_BOUNDARY_FIXED; /* one boundary for both (auto: absorbing for the plastic models) */
    rf_impact_input el = granite(10);
    rf_impact_output ref, out;
    rf_error err = {0};
    assert_int_equal(rf_fem_impact(&el, &o, &ref, NULL, &err), RF_OK);
    for (int m = 0; m < 3; m++) {
        rf_impact_input in = el;
        if (m == 0) { /* J2 in both bodies */
            in.boulder_material = in.slope_material = RF_MATERIAL_VON_MISES;
            in.boulder_yield = in.slope_yield = 1e15;
        } else if (m == 1) { /* DP cone + cap */
            in.slope_material = RF_MATERIAL_DRUCKER_PRAGER;
            in.slope_cohesion = 1e15, in.slope_friction_angle = 30 * M_PI / 180;
            in.slope_cap_pressure = 1e15;
        } else { /* DP without cap, phi = 0 (a Tresca-like cone) */
            in.slope_material = RF_MATERIAL_DRUCKER_PRAGER;
            in.slope_cohesion = 1e15;
        }
        if (rf_fem_impact(&in, &o, &out, NULL, &err) != RF_OK)
            fail_msg("%s", err.msg);
        printf("huge strength model %d (large deformation %s): R_n %.8f vs elastic %.8f, F_max ratio %.6f, "
               "energy error %.2e\n", m, rf_fem_kinematics_name(kin), out.R_n, ref.R_n, out.contact_force_max / ref.contact_force_max, out.energy_error);
        if (!(fabs(out.R_n - ref.R_n) < 1e-4))
            fail_msg("model %d: R_n %.8f vs elastic %.8f", m, out.R_n, ref.R_n);
        assert_true(out.plastic_work == 0 && out.equivalent_plastic_strain_max == 0);
        /* B-bar (plastic bodies) vs full 2x2 integration (the elastic kernel) at a/h = 3 */
        assert_true(fabs(out.contact_force_max / ref.contact_force_max - 1) < 1e-2);
    }
}

/* --- first yield and the yield velocity (Hertz) --- */

/* C(nu) = p0 / Y at first yield on the axis, and the depth z / a there, from
 * Hertz's axis stresses (Johnson 1985 eq. 3.45 with the 1 + nu factor):
 * sigma_z = -p0 / (1 + s^2), sigma_r = p0 (-(1 + nu)(1 - s atan(1/s)) + 1 / (2 (1 + s^2))). */
static void hertz_first_yield(double nu, double *C, double *depth)
{
    double best = 0;
    for (int i = 1; i <= 200000; i++) {
        double s = i * 1e-5, sz = -1 / (1 + s * s);
        double sr = -(1 + nu) * (1 - s * atan(1 / s)) + 0.5 / (1 + s * s);
        if (fabs(sr - sz) > best)
            best = fabs(sr - sz), *depth = s;
    }
    *C = 1 / best;
}

static void test_yield_velocity(void **state)
{
    (void)state;
    rf_impact_input in = granite(1);
    in.slope_material = RF_MATERIAL_VON_MISES;
    in.slope_yield = 1e9;
    double C = 0, depth = 0;
    hertz_first_yield(in.slope_poisson, &C, &depth);
    assert_true(fabs(C - 1.554) < 2e-3 && fabs(depth - 0.46) < 0.01); /* plasticity_refs.md sec. 1.1 */
    /* V_y^2 = (pi^5/30) R^3 p_y^5 / (m E*^4): the energy to reach delta_y */
    const double Es = rf_impact_effective_modulus(&in), m = rf_impact_mass(&in), py = C * in.slope_yield;
    const double Vy = sqrt(pow(M_PI, 5) / 30 * pow(py, 5) / (m * pow(Es, 4)));
    rf_fem_options o = coarse(6);
    rf_error err = {0};
    rf_impact_output out;
    rf_fem_history h;
    in.velocity = 0.85 * Vy;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_OK);
    printf("V_y = %.4f m/s; at 0.85 V_y: eps_p max %.3g\n", Vy, out.equivalent_plastic_strain_max);
    assert_true(out.equivalent_plastic_strain_max == 0 && out.plastic_work == 0);
    in.velocity = 1.25 * Vy;
    assert_int_equal(rf_fem_impact(&in, &o, &out, &h, &err), RF_OK);
    rf_impact_output hz;
    assert_int_equal(rf_impact_hertz(&in, &hz, &err), RF_OK);
    const double a = hz.contact_radius;
    printf("at 1.25 V_y: eps_p max %.3g in body %d at r = %.3f a, depth %.3f a (Hertz: on the axis, first "
           "yield at %.2f a); plastic work %.2e KE\n",
           out.equivalent_plastic_strain_max, h.plastic_strain_max_in, h.plastic_strain_max_r / a,
           -h.plastic_strain_max_z / a, depth, out.plastic_work);
    assert_true(out.equivalent_plastic_strain_max > 0 && out.plastic_work > 0 && out.plastic_work < 0.01);
    assert_int_equal(h.plastic_strain_max_in, 2);
    /* element centres, h = a/6: on the axis (first ring) and at the depth within one element */
    assert_true(h.plastic_strain_max_r < 0.2 * a);
    assert_true(fabs(-h.plastic_strain_max_z / a - depth) < 1.0 / 6 + 0.05);
    rf_fem_history_free(&h);
}

/* A layer over the slope: of the slope's own material it changes nothing; a
 * soft elastic layer moves the peak force from the rock's Hertz value to the
 * soft material's as it thickens; a plastic layer confines the plastic zone. */
static void test_layer(void **state)
{
    (void)state;
    rf_fem_options o = coarse(4);
    rf_error err = {0};
    rf_impact_output a, b;
    rf_impact_input in = granite(5);
    for (int kin = RF_FEM_SMALL_STRAIN; kin <= RF_FEM_LARGE_DEFORMATION; kin++) { /* auto would differ */
        o.large_deformation = (rf_fem_kinematics)kin;
        in.gravity = 0; /* auto would give the plastic slope gravity and not the elastic layer */
        in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = 1e15, in.layer_thickness = 0;
        assert_int_equal(rf_fem_impact(&in, &o, &a, NULL, &err), RF_OK);
        in.slope_material = RF_MATERIAL_ELASTIC;
        in.layer_thickness = 0.3; /* granite on granite, elastic */
        assert_int_equal(rf_fem_impact(&in, &o, &b, NULL, &err), RF_OK);
        assert_true(a.R_n == b.R_n && a.contact_force_max == b.contact_force_max);
    }
    o.large_deformation = RF_FEM_KINEMATICS_AUTO;
    /* soft (10 GPa) layer: thin, thick, and a homogeneous soft slope */
    double F[4];
    const double t[3] = {0.0, 0.05, 5.0}; /* h = 2.3 cm at the contact */
    for (int k = 0; k < 3; k++) {
        rf_impact_input q = granite(5);
        q.layer_thickness = t[k], q.layer_E = 10e9;
        assert_int_equal(rf_fem_impact(&q, &o, &a, NULL, &err), RF_OK);
        F[k] = a.contact_force_max;
    }
    rf_impact_input q = granite(5);
    q.slope_E = 10e9;
    assert_int_equal(rf_fem_impact(&q, &o, &a, NULL, &err), RF_OK);
    F[3] = a.contact_force_max;
    printf("soft layer: F_max granite %.4g N, 5 cm layer %.4g, 5 m layer %.4g, soft slope %.4g\n", F[0], F[1], F[2],
           F[3]);
    assert_true(F[1] < F[0] && F[1] > F[2]);
    assert_true(fabs(F[2] / F[3] - 1) < 0.03); /* different meshes (sized for the stiffer contact) */
    /* a thin J2 layer (Y = 200 MPa, 4 cm: h = 3 cm at the contact) on elastic granite, at 10 m/s */
    rf_impact_input p = granite(10);
    p.layer_thickness = 0.04, p.layer_material = RF_MATERIAL_VON_MISES, p.layer_yield = 200e6;
    rf_fem_history h;
    assert_int_equal(rf_fem_impact(&p, &o, &a, &h, &err), RF_OK);
    rf_impact_input r = granite(10);
    r.slope_material = RF_MATERIAL_VON_MISES, r.slope_yield = 200e6;
    assert_int_equal(rf_fem_impact(&r, &o, &b, NULL, &err), RF_OK);
    printf("J2 layer 4 cm: R_n %.4f, W_p %.4f KE, eps_p max at depth %.4f m; homogeneous J2 slope: R_n %.4f, "
           "W_p %.4f KE; energy error %.1e\n",
           a.R_n, a.plastic_work, -h.plastic_strain_max_z, b.R_n, b.plastic_work, a.energy_error);
    assert_true(a.plastic_work > 0 && a.plastic_work < b.plastic_work && a.R_n > b.R_n);
    assert_true(h.plastic_strain_max_in == 2 && -h.plastic_strain_max_z < 0.04 + 0.03);
    /* thinner than half an element: refused, not silently homogeneous */
    p.layer_thickness = 0.005;
    assert_int_equal(rf_fem_impact(&p, &o, &a, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "layer_thickness"));
    assert_true(a.energy_error < 5e-3);
    rf_fem_history_free(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_huge_yield_is_elastic),
        cmocka_unit_test(test_yield_velocity),
        cmocka_unit_test(test_layer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
