/* test_fem_gravity.c - gravity in the axisymmetric FE model
 * (docs/validation-plastic.md "Gravity"): the slope at rest under its own
 * weight (the solver's own assembly and steps, no contact) stays at rest to
 * round-off, with the closed-form geostatic stress at its points, in small
 * strain and updated Lagrangian, fixed and absorbing boundaries, with and
 * without a layer; the geostatic state of a cohesionless Drucker-Prager soil
 * is elastic and gives it the closed-form shear strength eta p; the rest rule
 * of the run account; a slow block on sand ends without failing, with the
 * energy closure counting gravity's work; gravity 0 is the old model bit for
 * bit; the 3D model and the analytic solvers refuse gravity > 0. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem/fem_core.h"
#include "fem/fem_internal.h"
#include "rockfuzz/fem.h"
#include "rockfuzz/fem3d.h"
#include "rockfuzz/impact_model.h"
#include "rockfuzz/material.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define DEG (M_PI / 180)

/* Dense sand of docs/materials.md (nominal row), cohesionless. */
static void dense_sand_slope(rf_impact_input *in)
{
    rf_impact_input_default(in);
    in->radius = 0.21, in->boulder_density = 117 / (4.0 / 3 * M_PI * pow(0.21, 3));
    in->boulder_material = RF_MATERIAL_RIGID_BODY, in->velocity = 1;
    in->slope_density = 1850, in->slope_E = 200e6, in->slope_poisson = 0.3;
    in->slope_material = RF_MATERIAL_DRUCKER_PRAGER, in->slope_cohesion = 0;
    in->slope_friction_angle = 39 * DEG, in->slope_dilatancy_angle = 9 * DEG;
    in->gravity = 9.81;
}

/* Closed form: sigma_v at depth d of a layer (rho_l, t) over a base rho_b. */
static double sigma_v(double g, double rho_l, double t, double rho_b, double d)
{
    return -g * (rho_l * fmin(d, t) + rho_b * fmax(d - t, 0));
}

/* The mean over the 2x2 Gauss points of the closed form in the element of node heights zn. */
static double sigma_v_element(double g, double rho_l, double t, double rho_b, const double zn[4])
{
    static const double XI[4] = {-1, 1, 1, -1}, ETA[4] = {-1, -1, 1, 1};
    const double q = 1 / sqrt(3.0);
    double s = 0;
    for (int k = 0; k < 4; k++) {
        double z = 0;
        for (int a = 0; a < 4; a++)
            z += 0.25 * (1 + XI[a] * XI[k] * q) * (1 + ETA[a] * ETA[k] * q) * zn[a];
        s += 0.25 * sigma_v(g, rho_l, t, rho_b, -z);
    }
    return s;
}

static void check_at_rest(const rf_impact_input *in, rf_fem_kinematics kin, rf_fem_boundary bnd, double k0,
                          double rho_l, double t, double rho_b)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3, o.large_deformation = kin, o.boundary = bnd;
    fem_rest_check c;
    rf_error err = {0};
    const long steps = 100;
    if (fem_axi_slope_at_rest(in, &o, steps, &c, &err) != RF_OK)
        fail_msg("%s", err.msg);
    /* an unbalanced weight would move the slope at g t after t = steps dt */
    const double gt = in->gravity * (double)steps * c.dt;
    const double sv = sigma_v_element(in->gravity, rho_l, t, rho_b, c.zn);
    printf("at rest (%s, %s%s): %ld elements, %ld steps, max |v| = %.2e m/s (g t = %.2e), max |u| = %.2e m; "
           "deepest %s element (centre %.3f m): sigma_zz %.6g Pa (closed form %.6g), sigma_rr/sigma_zz %.6f "
           "(K0 %.6f)\n", kin == RF_FEM_SMALL_STRAIN ? "small strain" : "updated Lagrangian",
           rf_fem_boundary_name(bnd), isfinite(t) ? ", layer" : "", c.elements, steps, c.v_max,
           gt, c.u_max, c.layer_elem ? "layer" : "slope", c.depth, c.sig[1], sv, c.sig[0] / c.sig[1], k0);
    printf("  body load / lumped weight: interior nodes %.4f .. %.4f, sum over the free nodes %.4f\n",
           c.load_ratio_min, c.load_ratio_max, c.load_sum / c.weight_sum);
    assert_true(c.v_max <= 1e-12 * gt);
    assert_true(c.u_max <= 1e-12 * gt * (double)steps * c.dt);
    assert_true(fabs(c.sig[1] - sv) <= 1e-12 * fabs(sv));
    assert_true(fabs(c.sig[0] - k0 * sv) <= 1e-12 * fabs(sv) && fabs(c.sig[2] - k0 * sv) <= 1e-12 * fabs(sv));
    assert_true(fabs(c.sig[3]) <= 1e-12 * fabs(sv));
    assert_int_equal(c.outside, 0);         /* every point inside the cone (and the cap) */
    assert_true(c.plastic_strain_max == 0); /* no point yielded */
}

/* (a) A cohesionless dense-sand half-space, and a dense-sand layer 1 m thick
 * over elastic granite (K0 = nu/(1 - nu) there), stay at rest. */
static void test_slope_at_rest(void **state)
{
    (void)state;
    rf_impact_input in;
    dense_sand_slope(&in);
    const double k0 = 1 - sin(39 * DEG);
    check_at_rest(&in, RF_FEM_SMALL_STRAIN, RF_FEM_BOUNDARY_FIXED, k0, 1850, INFINITY, 0);
    check_at_rest(&in, RF_FEM_LARGE_DEFORMATION, RF_FEM_BOUNDARY_ABSORBING, k0, 1850, INFINITY, 0);
    rf_impact_input lay = in;
    lay.slope_material = RF_MATERIAL_ELASTIC, lay.slope_density = 2600, lay.slope_E = 68.2e9;
    lay.slope_poisson = 0.25;
    lay.layer_thickness = 1, lay.layer_density = 1850, lay.layer_E = 200e6, lay.layer_poisson = 0.3;
    lay.layer_material = RF_MATERIAL_DRUCKER_PRAGER, lay.layer_cohesion = 0;
    lay.layer_friction_angle = 39 * DEG, lay.layer_dilatancy_angle = 9 * DEG;
    lay.layer_cap_pressure = 20e3, lay.layer_cap_hardening = 37e6; /* the cap goes through the geostatic p */
    check_at_rest(&lay, RF_FEM_LARGE_DEFORMATION, RF_FEM_BOUNDARY_ABSORBING, k0, 1850, 1, 2600);
    /* the defaults (auto: large deformation, absorbing dashpots for the layer) */
    assert_int_equal(rf_fem_boundary_resolve(RF_FEM_BOUNDARY_AUTO, &lay), RF_FEM_BOUNDARY_ABSORBING);
    check_at_rest(&lay, RF_FEM_KINEMATICS_AUTO, RF_FEM_BOUNDARY_AUTO, k0, 1850, 1, 2600);
}

/* (b) The geostatic state of a cohesionless Drucker-Prager soil at depth d
 * (sigma_v = -rho g d, sigma_h = K0 sigma_v, Jaky) is elastic; sheared at
 * constant volume (psi = 0: p stays) it reaches the closed-form limit
 * sqrt(J2) = eta p, eta of the Mohr-Coulomb compressive meridian: the
 * strength gravity gives a soil with c = 0 (0 without gravity). */
static void test_cohesionless_strength(void **state)
{
    (void)state;
    rf_material_params p;
    rf_material_params_default(&p);
    p.model = RF_MATERIAL_DRUCKER_PRAGER, p.E = 200e6, p.poisson = 0.3, p.cohesion = 0;
    p.friction_angle = 39 * DEG, p.dilatancy_angle = 0;
    rf_material m;
    assert_int_equal(rf_material_init(&m, &p, NULL), RF_OK);
    const double d = 0.5, sv = -1850 * 9.81 * d, k0 = 1 - sin(p.friction_angle);
    double sig[6] = {k0 * sv, sv, k0 * sv, 0, 0, 0};
    rf_material_state st = {0, 0, 0};
    assert_true(rf_material_admissible(&m, sig, &st, 1e-12));
    const double pm = -(1 + 2 * k0) * sv / 3, eta = 6 * sin(p.friction_angle) / (sqrt(3) * (3 - sin(p.friction_angle)));
    /* sqrt(J2) before shearing: the state is inside the cone with a margin */
    const double q0 = fabs(sv - k0 * sv) / sqrt(3);
    printf("cohesionless sand at %.2f m: p = %.1f Pa, sqrt(J2) = %.1f Pa, cone eta p = %.1f Pa\n", d, pm, q0, eta * pm);
    assert_true(q0 < eta * pm);
    for (int k = 0; k < 2000; k++) {
        const double de[6] = {0, 0, 0, 1e-6, 0, 0};
        rf_material_update(&m, de, sig, &st, NULL);
    }
    const double mean = (sig[0] + sig[1] + sig[2]) / 3, s[3] = {sig[0] - mean, sig[1] - mean, sig[2] - mean};
    const double j2 = 0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) + sig[3] * sig[3];
    printf("  sheared: p = %.1f Pa, sqrt(J2) = %.2f Pa (closed form %.2f), eps_p %.2e\n", -mean, sqrt(j2), eta * pm,
           st.plastic_strain_eq);
    assert_true(st.plastic_strain_eq > 0);
    assert_true(fabs(-mean - pm) <= 1e-9 * pm);
    assert_true(fabs(sqrt(j2) - eta * pm) <= 1e-9 * eta * pm);
}

/* A run account of the fed motions below: Hertz duration 1 ms, steps of 1 us, gravity g. */
#define FEED_TH 1e-3
#define FEED_DT 1e-6
static void feed_begin(fem_run *R, double g, rf_error *err)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    assert_int_equal(fem_run_begin(R, "fem", &o, FEED_DT, FEED_TH, 0, 12, err), RF_OK);
    R->gravity = g;
}

/* The rest rule of the run account on a closed-form motion: a boulder at
 * V = 1 m/s decelerated uniformly to rest in 3 t_h then held in contact
 * (no rebound): with gravity the run ends 2 t_h after its speed fell below
 * 2 % of V, at rest (no failure); without gravity the same motion fails at
 * the automatic end's bound (the old behaviour). */
static rf_status feed_motion(double g, double V, double v_sep, double *t_end, int *at_rest, double *v_end,
                             rf_error *err)
{
    const double t_h = FEED_TH, dt = FEED_DT;
    fem_run R;
    feed_begin(&R, g, err);
    rf_status st = RF_OK;
    for (long n = 0;; n++) {
        const double t = (double)n * dt;
        double row[12] = {0};
        row[11] = t < 3 * t_h ? -V * (1 - t / (3 * t_h)) : v_sep > 0 ? v_sep - g * (t - 3 * t_h) : 0;
        *t_end = (double)(n + 1) * dt;
        const double Fc = t < 3 * t_h || !(v_sep > 0) ? 1.0 : 0.0; /* v_sep > 0: the contact opens at 3 t_h */
        if ((st = fem_run_account(&R, n, Fc, 0, 0, 0, 1, row, err)) != RF_OK || fem_run_stop(&R, n))
            break;
    }
    *at_rest = R.at_rest, *v_end = R.v_now;
    fem_run_free(&R);
    return st;
}

static rf_status feed_rest(double g, double *t_end, int *at_rest, rf_error *err)
{
    double v_end;
    return feed_motion(g, 1, 0, t_end, at_rest, &v_end, err);
}

/* The roll rule: a boulder at V = 1 m/s stopped in 2 t_h, then riding in contact with a normal speed
 * of +-0.1 V (above the rest rule's 2 %, as a block rolling over its crater's rim) while its centre
 * accelerates along the slope, x = a t^2 / 2, contact radius 0.1 m: with gravity the run ends, as at
 * rest and rolled out, at the first step past t_max = 3 t_h where x > 0.2 m (closed form
 * t = sqrt(0.4 / a)); with the centre held (x = 0.15 m) it fails at the bound as before; without
 * gravity the rule does not apply. */
static rf_status feed_roll(double g, double acc, double x_cap, double *t_end, int *rolled, rf_error *err)
{
    const double t_h = FEED_TH, dt = FEED_DT, V = 1;
    fem_run R;
    feed_begin(&R, g, err);
    rf_status st = RF_OK;
    for (long n = 0;; n++) {
        const double t = (double)n * dt;
        double row[12] = {0};
        row[11] = t < 2 * t_h ? -V * (1 - t / (2 * t_h)) : 0.1 * V * sin(2 * M_PI * t / t_h);
        R.roll.travel = fmin(0.5 * acc * t * t, x_cap);
        *t_end = t;
        if ((st = fem_run_account(&R, n, 1.0, 0.1, 0, 0, 1, row, err)) != RF_OK || fem_run_stop(&R, n))
            break;
    }
    *rolled = R.roll.out && R.at_rest;
    fem_run_free(&R);
    return st;
}

static void test_roll_rule(void **state)
{
    (void)state;
    rf_error err = {0};
    double t_end;
    int rolled;
    const double acc = 1e4; /* x = 0.2 m at t = sqrt(0.4 / a) = 6.32 t_h, past t_max */
    assert_int_equal(feed_roll(9.81, acc, INFINITY, &t_end, &rolled, &err), RF_OK);
    printf("roll rule: ended at %.6g s (closed form %.6g s), rolled out %d\n", t_end, sqrt(0.4 / acc), rolled);
    assert_true(rolled);
    assert_true(t_end >= sqrt(0.4 / acc) && t_end < sqrt(0.4 / acc) + 2e-6);
    assert_int_equal(feed_roll(9.81, 1e6, INFINITY, &t_end, &rolled, &err), RF_OK); /* out early: at t_max */
    assert_true(rolled && fabs(t_end - 3e-3) < 2e-6);
    assert_int_equal(feed_roll(9.81, acc, 0.15, &t_end, &rolled, &err), RF_EMODEL); /* held in its crater */
    assert_false(rolled);
    assert_int_equal(feed_roll(0, acc, INFINITY, &t_end, &rolled, &err), RF_EMODEL); /* no gravity: old rules */
    assert_false(rolled);
}

/* A slow boulder (V = 1 cm/s) that separates at 3 t_h with v_sep = 5 mm/s
 * (above the rest resolution 2 % V) is turned by its weight within 0.05 t_h:
 * the impact has ended (a later fall is a new impact): the run ends 0.1 t_h
 * after the separation, not at rest, with the boulder already falling. */
static void test_bounce_then_fall(void **state)
{
    (void)state;
    double t_end, v_end;
    int rest;
    rf_error err = {0};
    assert_int_equal(feed_motion(9.81, 0.01, 5e-4, &t_end, &rest, &v_end, &err), RF_OK);
    printf("bounce: the run ends at %.4f t_h, velocity then %.2e m/s, at rest %d\n", t_end / 1e-3, v_end, rest);
    assert_false(rest);
    assert_true(v_end < 0 && fabs(t_end - 3.1e-3) < 3e-6);
}

static void test_rest_rule(void **state)
{
    (void)state;
    double t_end;
    int rest;
    rf_error err = {0};
    assert_int_equal(feed_rest(9.81, &t_end, &rest, &err), RF_OK);
    printf("rest rule: at rest %d, the run ends at %.4f t_h (slow from %.4f t_h)\n", rest, t_end / 1e-3,
           3 * (1 - FEM_REST_SPEED));
    assert_true(rest);
    assert_true(fabs(t_end - (3 * (1 - FEM_REST_SPEED) + FEM_REST_WINDOW) * 1e-3) < 3e-6);
    assert_int_equal(feed_rest(0, &t_end, &rest, &err), RF_EMODEL);
    assert_false(rest);
}

/* (c, d) A 117 kg block at 1 m/s on dense sand (cohesionless; a/h = 3):
 * the run ends (rest or separation, not at the bound), R_n in [0, 0.3],
 * the energy closure with gravity's work < 0.5 % of KE0, and gravity's work
 * is the weight times the boulder's final drop plus the slope's share. */
static void test_slow_block_on_sand(void **state)
{
    (void)state;
    rf_impact_input in;
    dense_sand_slope(&in);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3, o.boundary = RF_FEM_BOUNDARY_ABSORBING;
    rf_impact_output out;
    rf_fem_history h;
    rf_error err = {0};
    if (rf_fem_impact(&in, &o, &out, &h, &err) != RF_OK)
        fail_msg("%s", err.msg);
    printf("block on sand at 1 m/s: R_n %.4f (at rest %d), contact %.4f s, penetration %.4f m, W_p %.3f KE0, "
           "gravity work %.3f KE0, energy error %.2e, %.0f steps\n", out.R_n, h.at_rest, out.contact_duration,
           out.penetration_max, out.plastic_work, h.gravity_work / h.ke0, out.energy_error, out.steps);
    assert_true(out.R_n >= 0 && out.R_n <= 0.3);
    assert_true(out.energy_error < 5e-3);
    assert_true(h.gravity == 9.81 && h.gravity_work > 0);
    assert_true(h.at_rest && out.R_n == 0); /* cohesionless: the block stays in its crater */
    rf_fem_history_free(&h);
}

/* (e) gravity 0 is the old model: a plastic impact (rigid block at 3 m/s on
 * dense sand, small strain) with gravity 0 ends in the state of the
 * code before gravity, bit for bit: the FNV hash of u and v below is the one
 * the commit before gravity (3056873) gives for this input (measured with
 * both builds, docs/validation-plastic.md section 11; also the updated
 * Lagrangian run and a von Mises boulder on an absorbing slope).  The automatic
 * gravity of elastic bodies is 0. */
static void test_gravity_zero_is_old_model(void **state)
{
    (void)state;
    rf_impact_input in;
    dense_sand_slope(&in);
    in.slope_cohesion = 1e3, in.velocity = 3, in.gravity = 0;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3, o.large_deformation = RF_FEM_SMALL_STRAIN;
    o.boundary = RF_FEM_BOUNDARY_FIXED; /* the default of the code before gravity (now auto: absorbing here) */
    rf_impact_output out;
    rf_fem_history h;
    rf_error err = {0};
    if (rf_fem_impact(&in, &o, &out, &h, &err) != RF_OK)
        fail_msg("%s", err.msg);
    printf("gravity 0: R_n %.17g, hash %016llx, gravity work %g\n", out.R_n, (unsigned long long)h.state_hash,
           h.gravity_work);
    assert_true(h.gravity == 0 && h.gravity_work == 0 && !h.at_rest);
    assert_true(h.state_hash == 0x1b8d438b0bb899f1ULL);
    rf_fem_history_free(&h);
    rf_impact_input el;
    rf_impact_input_default(&el);
    assert_true(rf_impact_gravity(&el, 0) == 0);
    el.slope_material = RF_MATERIAL_DRUCKER_PRAGER;
    assert_true(rf_impact_gravity(&el, 0) == RF_GRAVITY_STANDARD && rf_impact_gravity(&el, 1) == RF_GRAVITY_STANDARD);
}

/* Refusals: the analytic solvers (the 3D model has gravity: test_fem3d_gravity). */
static void test_refusals(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.gravity = 9.81;
    rf_impact_output out;
    rf_error err = {0};
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = RF_IMPACT_HERTZ;
    assert_int_equal(rf_impact_solve(&spec, &in, &out, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "gravity"));
    in.gravity = NAN;
    assert_int_equal(rf_impact_input_validate(&in, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "gravity"));
    in.gravity = -9.81; /* a signed component is not a magnitude, and not auto either */
    assert_int_equal(rf_impact_input_validate(&in, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "gravity"));
    in.gravity = RF_GRAVITY_AUTO;
    assert_int_equal(rf_impact_input_validate(&in, &err), RF_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slope_at_rest),        cmocka_unit_test(test_cohesionless_strength),
        cmocka_unit_test(test_rest_rule),            cmocka_unit_test(test_bounce_then_fall),
        cmocka_unit_test(test_slow_block_on_sand),   cmocka_unit_test(test_roll_rule),
        cmocka_unit_test(test_gravity_zero_is_old_model), cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
