/* test_soil.c - soil impacts (docs/soil-impacts.md): the soil moduli and
 * Gerber's penetration law of src/fem/fem_soil.c, and the axisymmetric mesh
 * sized from a thick layer's own contact (option mesh_sizing soil):
 *   - the oedometric modulus against the constrained modulus lambda + 2 mu
 *     computed from the Lame constants (a second formula), nu = 0 gives
 *     E_oed = E, the inverse round-trips;
 *   - Gerber's law against a hand-computed point and its exponents (M^(1/3),
 *     M_E^(-0.4), V^0.8), with M_E given in Pa and the law's kN/m^2;
 *   - with mesh_sizing soil, the S5 layer's mesh is the one
 *     fem_impact_mesh_spec describes (element count of a solver run), its
 *     element size is the layer contact's estimated radius / refinement and its
 *     uniform zone covers that radius; a thin layer and the option off keep
 *     the default sizing (the same element count as without the option); a
 *     soil contact wider than the boulder's fine zone (15 m/s) is meshed with
 *     that zone capped, not refused;
 *   - the table preset (rf_fem_soil_table_preset) sets its three options and
 *     nothing else, validates in both models, and sizes the S5 mesh at the
 *     estimated layer contact radius / the preset's a/h;
 *   - the tuning's end_at_separation: with gravity a run whose contact ends
 *     before the least time ends 0.1 Hertz durations after the separation,
 *     with the plain run's R_n and contact duration to the bit; without
 *     gravity it changes nothing.
 * No check of the FE model against the law: the law's scatter band is not
 * published in a source read here (the comparison is in the docs only). */
#include <math.h>
#include <stdio.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "core/util.h"
#include "fem_tune.h"
#include "fem/fem3d_spec.h"
#include "fem/fem_internal.h"
#include "fem/fem_soil.h"
#include "fem/fem_spec.h"
#include "rockfuzz/fem.h"

static void test_oedometric_modulus(void **state)
{
    (void)state;
    const double nus[] = {0.0, 0.2, 0.3, 0.35, 0.45};
    for (size_t i = 0; i < sizeof nus / sizeof *nus; i++) {
        const double E = 80e6, nu = nus[i];
        const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
        const double M = fem_soil_oedometric_modulus(E, nu);
        assert_true(fabs(M - (lambda + 2 * mu)) <= 1e-12 * M);
        assert_true(fabs(fem_soil_E_from_oedometric(M, nu) - E) <= 1e-12 * E);
    }
    assert_true(fabs(fem_soil_oedometric_modulus(50e6, 0) - 50e6) < 1e-6);
    /* nu = 0.3: E = M_E * 1.3 * 0.4 / 0.7 */
    assert_true(fabs(fem_soil_E_from_oedometric(35e6, 0.3) - 26e6) < 1e-6);
}

static void test_gerber_law(void **state)
{
    (void)state;
    /* M = 1000 kg, M_E = 10 000 kN/m^2 = 1e7 Pa, V = 10 m/s:
       0.1 * 10 * 10^(-1.6) * 10^0.8 = 10^(-0.8) m */
    const double d = fem_soil_gerber_penetration(1000, 1e7, 10);
    assert_true(fabs(d - pow(10, -0.8)) < 1e-12);
    const double M = 700, ME = 3e7, V = 7;
    const double d0 = fem_soil_gerber_penetration(M, ME, V);
    assert_true(fabs(fem_soil_gerber_penetration(8 * M, ME, V) / d0 - 2) < 1e-12);
    assert_true(fabs(fem_soil_gerber_penetration(M, 32 * ME, V) / d0 - 0.25) < 1e-12);
    assert_true(fabs(fem_soil_gerber_penetration(M, ME, 32 * V) / d0 - 16) < 1e-12);
}

/* The S5 nominal layer (examples/s5_v5.yaml) at 5 m/s. */
static void s5_layer(rf_impact_input *in)
{
    rf_impact_input_default(in);
    in->radius = 0.5, in->velocity = 5, in->boulder_material = RF_MATERIAL_RIGID_BODY;
    in->layer_thickness = 1.0, in->layer_density = 1900, in->layer_E = 100e6, in->layer_poisson = 0.3;
    in->layer_material = RF_MATERIAL_DRUCKER_PRAGER, in->layer_cohesion = 10e3;
    in->layer_friction_angle = 40 * RF_PI / 180, in->layer_dilatancy_angle = 5 * RF_PI / 180;
    in->layer_cap_pressure = 200e3, in->layer_cap_hardening = 40e6;
}

/* Elements of the spec's mesh, and of a solver run of a few steps. */
static void spec_and_solver(const rf_impact_input *in, rf_fem_options *o, long *spec, long *solver, double *h)
{
    fem_body_spec bs, ss;
    rf_error err = {0};
    assert_int_equal(fem_impact_mesh_spec(in, o, &bs, &ss, &err), RF_OK);
    fem_mesh mesh = {0};
    assert_int_equal(fem_mesh_build(&bs, &ss, &mesh, TUNE(*o).max_elements, &err), RF_OK);
    *spec = mesh.n_elems, *h = ss.h;
    fem_mesh_free(&mesh);
    o->end_time = 1e-6;
    rf_impact_output out;
    assert_int_equal(rf_fem_impact(in, o, &out, NULL, &err), RF_OK);
    *solver = (long)out.elements;
}

static void test_soil_mesh(void **state)
{
    (void)state;
    rf_impact_input in;
    s5_layer(&in);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 4;
    long n_def, n_def_solver, n_soil, n_soil_solver;
    double h_def, h_soil;
    spec_and_solver(&in, &o, &n_def, &n_def_solver, &h_def);
    assert_int_equal(n_def, n_def_solver);
    o.mesh_sizing = RF_FEM_SIZING_SOIL;
    spec_and_solver(&in, &o, &n_soil, &n_soil_solver, &h_soil);
    assert_int_equal(n_soil, n_soil_solver);
    f3_layer_contact lc;
    f3_layer_contact_estimate(&in, &lc);
    assert_true(lc.thick);
    assert_true(fabs(h_soil - lc.radius / 4) < 1e-12);
    assert_true(h_soil > 2 * h_def); /* the rock's Hertz radius sized the default: far finer */
    fem_body_spec bs, ss;
    rf_error err = {0};
    assert_int_equal(fem_impact_mesh_spec(&in, &o, &bs, &ss, &err), RF_OK);
    assert_true(ss.n * ss.h >= lc.zone_radius - 1e-12); /* the uniform zone covers the estimated contact */
    assert_true(bs.n * bs.h >= lc.radius);               /* and so do the boulder's slaves */
    /* 15 m/s: the soil contact is wider than the boulder's fine zone may be (0.55 r0); the zone is
       capped there, not refused, and the spec is still the solver's mesh */
    in.velocity = 15;
    long n15, n15_solver;
    double h15;
    spec_and_solver(&in, &o, &n15, &n15_solver, &h15);
    assert_int_equal(n15, n15_solver);
    f3_layer_contact_estimate(&in, &lc);
    assert_true(lc.thick && lc.radius > 0.55 * in.radius);
    assert_int_equal(fem_impact_mesh_spec(&in, &o, &bs, &ss, &err), RF_OK);
    assert_true(bs.n * bs.h <= 0.6 * in.radius + 1e-12 && ss.n * ss.h >= lc.zone_radius - 1e-12);
    in.velocity = 5;
    /* a thin layer (0.1 m: the boulder reaches through it) keeps the default sizing */
    in.layer_thickness = 0.1;
    long n_thin, n_thin_solver, n_thin_off, n_off_solver;
    double h_thin, h_off;
    spec_and_solver(&in, &o, &n_thin, &n_thin_solver, &h_thin);
    o.mesh_sizing = RF_FEM_SIZING_HERTZ;
    spec_and_solver(&in, &o, &n_thin_off, &n_off_solver, &h_off);
    assert_int_equal(n_thin, n_thin_off);
    assert_int_equal(n_thin_solver, n_off_solver);
    assert_true(h_thin == h_off);
}

/* The table preset (rf_fem_soil_table_preset): the three settings of
   docs/soil-impacts.md section 4 and nothing else; valid for both models; on
   S5 the mesh it gives has the element size of the layer contact's estimated
   radius over the preset's a/h (the estimate of fem3d_spec.c, a second
   route to h). */
static void test_table_preset(void **state)
{
    (void)state;
    rf_fem_options o, before;
    rf_fem_options_default(&o);
    o.domain_factor = 7, o.threads = 3, o.end_time = 0.5, o.large_deformation = RF_FEM_LARGE_DEFORMATION;
    before = o;
    rf_fem_soil_table_preset(&o);
    assert_int_equal(o.mesh_sizing, RF_FEM_SIZING_SOIL);
    assert_true(o.refinement == RF_FEM_SOIL_PRESET_REFINEMENT && o.refinement >= 2);
    assert_true(o.rock_mass_scale == RF_FEM_SOIL_PRESET_ROCK_SCALE && o.rock_mass_scale > 1);
    assert_true(o.domain_factor == before.domain_factor && o.threads == before.threads);
    assert_true(o.end_time == before.end_time && o.large_deformation == before.large_deformation);
    rf_error err = {0};
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_OK);
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_OK);
    rf_impact_input in;
    s5_layer(&in);
    rf_fem_options_default(&o);
    rf_fem_soil_table_preset(&o);
    long n, n_solver;
    double h;
    spec_and_solver(&in, &o, &n, &n_solver, &h);
    assert_int_equal(n, n_solver);
    f3_layer_contact lc;
    f3_layer_contact_estimate(&in, &lc);
    assert_true(fabs(h - lc.radius / RF_FEM_SOIL_PRESET_REFINEMENT) < 1e-12);
}

/* One impact with the tuning's end_at_separation set or not: its output and
   time step, and the Hertz duration the run used. */
static void run_end(const rf_impact_input *in, int early, rf_impact_output *out, double *dt, double *t_h)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 4;
    rf_fem_tuning t;
    fem_tune(&o, &t)->end_at_separation = early;
    rf_fem_history H = {0};
    rf_error err = {0};
    if (rf_fem_impact(in, &o, out, &H, &err) != RF_OK)
        fail_msg("end_at_separation %d: %s", early, err.msg);
    *dt = H.dt, *t_h = H.hertz_duration;
    rf_fem_history_free(&H);
}

/* The tuning's end_at_separation (docs/soil-impacts.md section 3, "Where the
   time goes"): an elastic layer of S5's modulus, with gravity, whose contact
   (the layer's Hertz duration, about t_h) ends before the least time 1.3 t_h.
   With it the run ends 0.1 t_h after the separation, before 1.3 t_h, with
   R_n, R_t and the contact duration of the plain run to the bit (they are the
   state at separation); the plain run lasts at least 1.3 t_h.  Without
   gravity the rule is off: the same steps. */
static void test_end_at_separation(void **state)
{
    (void)state;
    rf_impact_input in;
    s5_layer(&in);
    in.layer_material = RF_MATERIAL_ELASTIC, in.gravity = 9.81;
    rf_impact_output plain, early;
    double dt, t_h, dt2, t_h2;
    run_end(&in, 0, &plain, &dt, &t_h);
    run_end(&in, 1, &early, &dt2, &t_h2);
    assert_true(dt == dt2 && t_h == t_h2);
    assert_true(plain.steps * dt >= 1.3 * t_h - dt);
    assert_true(plain.contact_duration < 1.2 * t_h); /* the case: the contact ends before the least time */
    assert_true(early.steps < plain.steps);
    const double t_end = early.steps * dt, t_sep = early.contact_duration;
    assert_true(t_end >= t_sep + 0.1 * t_h - 2 * dt && t_end <= t_sep + 0.1 * t_h + 0.05 * t_h);
    assert_true(early.R_n == plain.R_n && early.R_n > 0.5);
    assert_true(early.contact_duration == plain.contact_duration);
    assert_true(early.penetration_max == plain.penetration_max);
    in.gravity = 0;
    run_end(&in, 0, &plain, &dt, &t_h);
    run_end(&in, 1, &early, &dt2, &t_h2);
    assert_true(early.steps == plain.steps && early.R_n == plain.R_n);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_oedometric_modulus),
        cmocka_unit_test(test_gerber_law),
        cmocka_unit_test(test_soil_mesh),
        cmocka_unit_test(test_table_preset),
        cmocka_unit_test(test_end_at_separation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
