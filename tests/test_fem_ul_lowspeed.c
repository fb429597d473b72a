/* test_fem_ul_lowspeed.c - issue 29 item 1: von Mises granite on von Mises
 * granite below the yield velocity must reproduce the elastic impact in the
 * updated-Lagrangian (large deformation) path: no plastic work, R_n of the
 * small-strain run, a closed energy account.
 *
 * The case (0.02 m/s, Y 200 MPa, a/h 10) takes 5-15 min.  Its fast
 * stand-in: the same impact scaled to 2 m/s.  Hertz's peak stress grows as
 * V^(2/5), so Y = 200 MPa * 100^(2/5) = 1.262 GPa keeps the impact at half
 * the yield velocity (peak von Mises stress ~0.76 Y), and the mesh, sized
 * from the Hertz radius a ~ V^(2/5), keeps a/h = 10 with 16x fewer steps
 * (10 907, ~30 s).  Measured on h/ul (ref 10, gravity 0, boundary auto),
 * before the fix:
 *   small strain:               R_n 0.994783, W_p 0, energy error 7.0e-7;
 *   updated Lagrangian:         R_n 0.992273, W_p 0.380 KE0, eps_p 4.36,
 *                               energy error 0.338, 15 re-contacts
 *                               (the defect, reproduced);
 *   elastic bodies, updated L.: R_n 0.995130, energy error 0.0525 (also wrong).
 * After (the contact's impulse along the gap's gradient at the start of the
 * step, on a C1 master surface: the surface polygon with rounded corners,
 * fem_contact.c and fem_contact_surface.c):
 *   updated Lagrangian:         R_n 0.994812, W_p 0, eps_p 0, energy error 7.7e-7;
 *   elastic bodies, updated L.: R_n 0.994814, energy error 7.3e-7;
 *   the issue's own 0.02 m/s case (CLI, 352 s CPU): R_n 0.999681 (elastic
 *   0.99968), W_p 0, eps_p 0, energy error 3.5e-9.
 * (The same gradient on the Hermite surface of branch h/ul2 gave 0.994806 and
 * 0.994809; that surface failed the soil checks: docs 6f.)
 * The checks: both bodies below yield in updated Lagrangian reproduce the
 * small-strain result (R_n within 1e-4, no plastic work or strain, the
 * energy account closed to 1e-5), and so do elastic bodies.  The cause, and
 * how it was found, is in the comment of test_ul_below_yield and in
 * docs/validation-plastic.md section 6f. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem_tune.h"
#include "rockfuzz/fem.h"

#define V_SCALED 2.0      /* m/s */
#define Y_SCALED 1.262e9  /* Pa: 200 MPa * (V_SCALED / 0.02)^(2/5) */
#define REFINEMENT 10     /* the default a/h, which the defect needs (a/h 6 is clean) */

static rf_impact_input below_yield(int plastic)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = V_SCALED, in.gravity = 0;
    if (plastic) {
        in.boulder_material = RF_MATERIAL_VON_MISES, in.boulder_yield = Y_SCALED;
        in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = Y_SCALED;
    }
    return in;
}

static rf_impact_output run(const rf_impact_input *in, rf_fem_kinematics kin)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = REFINEMENT, o.large_deformation = kin;
    rf_impact_output out;
    rf_error err = {0};
    assert_int_equal(rf_fem_impact(in, &o, &out, NULL, &err), RF_OK);
    printf("%s %s: R_n %.6f plastic work %.4g KE0 eps_p %.4g energy error %.3g steps %.0f\n",
           in->slope_material == RF_MATERIAL_VON_MISES ? "von Mises" : "elastic",
           kin == RF_FEM_SMALL_STRAIN ? "small strain" : "updated Lagrangian", out.R_n, out.plastic_work,
           out.equivalent_plastic_strain_max, out.energy_error, out.steps);
    return out;
}

/* The reference: in small strain the scaled impact stays elastic (the
 * scaling keeps it below yield) and its account closes. */
static double ss_R_n = -1; /* the small-strain R_n, run once */

static double small_strain_R_n(void)
{
    if (ss_R_n < 0) {
        const rf_impact_input in = below_yield(1);
        ss_R_n = run(&in, RF_FEM_SMALL_STRAIN).R_n;
    }
    return ss_R_n;
}

static void test_small_strain_below_yield(void **state)
{
    (void)state;
    const rf_impact_input in = below_yield(1);
    const rf_impact_output s = run(&in, RF_FEM_SMALL_STRAIN);
    ss_R_n = s.R_n;
    assert_true(s.plastic_work == 0 && s.equivalent_plastic_strain_max == 0);
    assert_true(fabs(s.energy_error) < 1e-5);
    assert_true(s.R_n > 0.99 && s.R_n < 1);
}

/* Issue 29 item 1.  The diagnosis (fast case above; each row one change,
 * measured with a throw-away driver):
 *  - not the J2 return map or its shear convention: one B-bar or plain
 *    element, updated Lagrangian, 1e5 steps of a rotating strain history
 *    below yield, gives the linear law's stresses to 1e-7 and no plastic
 *    work with the von Mises law;
 *  - not the contact-face mass redistribution (surface_mass_kappa 0: the
 *    same W_p 0.381, E error 0.339);
 *  - the updated-Lagrangian contact together with the updated-Lagrangian
 *    kernel: elastic bodies, UL kernel + small-strain contact: E error
 *    6.8e-7; small-strain kernel + UL contact: 8.6e-6; both UL: 0.0525.
 *    The whole closure error is the contact work, in the unloading half,
 *    growing exponentially (elastic: 0.1 J at the force peak, then x10 every
 *    0.3 ms to 5 kJ of KE0 21.8 kJ);
 *  - the same elastic run at half the time step (dt_safety 0.45): E error
 *    2.9e-6, R_n 0.994810: the growth is a property of the time
 *    integration, its rate per unit time proportional to dt;
 *  - logged at every change of master segment of a closed pair: 6709
 *    crossings, the relinearised gap at the step's start 7e-7 m on average
 *    (kink angle x radial offset 4.5e-7 m), lambda x jump summed 2.07 kJ of
 *    the 7.36 kJ contact work (von Mises run);
 *  - a smooth (G1 Hermite) master surface alone, gradient still at the
 *    predicted end of the step: worse (elastic E error 0.23, von Mises W_p
 *    0.44): smoothing spreads the kink's curvature but keeps its sign.
 * The cause: the forward-increment multiplier's impulse was applied along
 * the gap's gradient at the predicted end of the step (u_{n+1}).  Its work on
 * a closed pair, lambda c . (u_{n+1} - u_{n-1}) / 2, is then not the gap's
 * change (zero) but lambda dt^2 v' H v (H the gap's curvature), of one sign:
 * energy fed to the relative sliding of closed pairs in proportion to its own
 * kinetic energy, an exponential instability whose rate is proportional to
 * dt.  Boulder nodes on slope nodes (matching meshes) slide across the
 * faceted surface's kinks, where H is a delta.  Fixed at the root: the
 * gradient at u_n, the midpoint of u_{n-1} and u_{n+1}, as central
 * differences (and SHAKE) use for every force (the error falls to third
 * order, of no fixed sign), on a G1 master surface so that H is bounded
 * (fem_contact.c pair_midpoint, fem_contact_surface.c).  Tried and rejected
 * before: flooring the relinearised gap at the step's start at 0 (elastic
 * R_n 0.986337, energy error 6.0e-3; von Mises R_n 0.9087, W_p 0.093). */
static void test_ul_below_yield(void **state)
{
    (void)state;
    const rf_impact_input in = below_yield(1);
    const rf_impact_output l = run(&in, RF_FEM_LARGE_DEFORMATION);
    assert_true(l.plastic_work == 0 && l.equivalent_plastic_strain_max == 0);
    assert_true(fabs(l.energy_error) < 1e-5);
    assert_true(fabs(l.R_n - small_strain_R_n()) < 1e-4);
}

/* Elastic bodies in updated Lagrangian: the same R_n (the elastic result is
 * the von Mises one below yield) and a closed account (it was 0.0525). */
static void test_ul_elastic(void **state)
{
    (void)state;
    const rf_impact_input in = below_yield(0);
    const rf_impact_output l = run(&in, RF_FEM_LARGE_DEFORMATION);
    assert_true(fabs(l.energy_error) < 1e-5);
    assert_true(fabs(l.R_n - small_strain_R_n()) < 1e-4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_strain_below_yield),
        cmocka_unit_test(test_ul_elastic),
        cmocka_unit_test(test_ul_below_yield),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
