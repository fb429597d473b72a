/* test_impact_model.c - the impact model behind rf_model: binding by name,
 * agreement with direct calls, degrees for slope_angle, constant-volume
 * spheroid, error paths, identity, and concurrent evaluation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "rockfuzz/impact_model.h"

#define DEG (3.14159265358979323846 / 180.0)

static rf_impact_model_spec spec_for(rf_impact_solver solver)
{
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = solver;
    return spec;
}

static void outputs_of(const rf_impact_output *o, double y[RF_IMPACT_N_OUTPUTS])
{
    y[0] = o->contact_force_max;
    y[1] = o->compression_max;
    y[2] = o->contact_duration;
    y[3] = o->contact_radius;
    y[4] = o->R_n;
    y[5] = o->R_t;
    y[6] = o->R_ke;
    y[7] = o->plastic_work;
    y[8] = o->penetration_max;
    y[9] = o->indentation_depth;
    y[10] = o->equivalent_plastic_strain_max;
}

static void assert_same(const double *a, const double *b, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        if (isnan(a[k]) && isnan(b[k]))
            continue;
        if (!(a[k] == b[k]))
            fail_msg("output %s: %.17g != %.17g", rf_impact_output_fields[k].name, a[k], b[k]);
    }
}

static void test_spec_default(void **state)
{
    (void)state;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    assert_int_equal(spec.solver, RF_IMPACT_FEM);
    assert_true(isnan(spec.e_n));
    assert_true(spec.hunter_coefficient == 1.04);
    assert_true(spec.fem.refinement == 0.0 && spec.fem.domain_factor == 0.0); /* 0 = automatic */
    assert_int_equal(spec.fem.boundary, RF_FEM_BOUNDARY_AUTO); /* fixed for elastic bodies, absorbing otherwise */
    assert_int_equal(spec.fem.threads, 1);
    assert_true(spec.base.boulder_E == 68.2e9 && spec.base.radius == 1.0);
    rf_impact_solver s;
    rf_fem_boundary b;
    rf_error err = {0};
    assert_int_equal(rf_impact_solver_parse("hunter", &s, &err), RF_OK);
    assert_int_equal(s, RF_IMPACT_HUNTER);
    assert_string_equal(rf_impact_solver_name(RF_IMPACT_RIGID), "rigid");
    assert_int_equal(rf_impact_solver_parse("abaqus", &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "'abaqus'"));
    assert_int_equal(rf_fem_boundary_parse("absorbing", &b, &err), RF_OK);
    assert_int_equal(b, RF_FEM_BOUNDARY_ABSORBING);
    assert_int_equal(rf_fem_boundary_parse("open", &b, &err), RF_EINVAL);
    assert_int_equal(rf_fem_boundary_parse("auto", &b, &err), RF_OK);
    assert_int_equal(b, RF_FEM_BOUNDARY_AUTO);
    assert_string_equal(rf_fem_boundary_name(RF_FEM_BOUNDARY_AUTO), "auto");
}

/* All eleven names, in a shuffled order, against direct calls. */
static void test_eval_matches_direct(void **state)
{
    (void)state;
    const char *names[] = {"velocity", "boulder_E", "slope_E", "radius", "boulder_density",
                           "slope_density", "boulder_poisson", "slope_poisson", "slope_angle",
                           "friction"};
    const double x[] = {12.0, 60e9, 70e9, 0.8, 2500.0, 2700.0, 0.22, 0.27, 40.0, 0.3};
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = 12.0;
    in.boulder_E = 60e9;
    in.slope_E = 70e9;
    in.radius = 0.8;
    in.boulder_density = 2500.0;
    in.slope_density = 2700.0;
    in.boulder_poisson = 0.22;
    in.slope_poisson = 0.27;
    in.slope_angle = 40.0 * DEG;
    in.friction = 0.3;
    const rf_impact_solver solvers[] = {RF_IMPACT_HERTZ, RF_IMPACT_HUNTER, RF_IMPACT_RIGID};
    for (int s = 0; s < 3; s++) {
        rf_impact_model_spec spec = spec_for(solvers[s]);
        rf_model model;
        rf_error err = {0};
        assert_int_equal(rf_impact_model_create(&spec, names, 10, &model, &err), RF_OK);
        assert_int_equal(model.n_inputs, 10);
        assert_int_equal(model.n_outputs, RF_IMPACT_N_OUTPUTS);
        assert_int_equal(model.threads_per_eval, 1);
        assert_string_equal(model.output_names[0], "contact_force_max");
        assert_string_equal(model.output_units[0], "N");
        assert_string_equal(model.output_names[6], "R_ke");
        assert_string_equal(model.output_units[6], "");
        double y[RF_IMPACT_N_OUTPUTS], want[RF_IMPACT_N_OUTPUTS];
        assert_int_equal(rf_model_eval(&model, x, y, &err), RF_OK);
        rf_impact_output o;
        if (solvers[s] == RF_IMPACT_HERTZ) {
            assert_int_equal(rf_impact_hertz(&in, &o, &err), RF_OK);
        } else if (solvers[s] == RF_IMPACT_HUNTER) {
            assert_int_equal(rf_impact_hunter(&in, &o, &err), RF_OK);
        } else {
            /* rigid with e_n unset takes Hunter's e_n of the current inputs */
            rf_impact_output h;
            assert_int_equal(rf_impact_hunter(&in, &h, &err), RF_OK);
            assert_int_equal(rf_impact_rigid(&in, h.R_n, &o, &err), RF_OK);
            assert_true(isnan(y[0]) && isnan(y[3]));
        }
        outputs_of(&o, want);
        assert_same(y, want, RF_IMPACT_N_OUTPUTS);
        assert_non_null(strstr(model.identity, rf_impact_solver_name(solvers[s])));
        rf_model_free(&model);
    }
}

/* Each solver's own settings reach the identity through its registry entry
 * (rf_impact_law.identity): Hunter's A changes the identity exactly of the
 * solvers whose results depend on it (hunter; rigid and mdr when e_n comes
 * from Hunter's loss), and a fixed e_n that of rigid and mdr. */
static void test_identity_from_registry(void **state)
{
    (void)state;
    const char *names[] = {"friction"};
    for (size_t k = 0; k < rf_impact_n_solvers(); k++) {
        rf_impact_solver sv = (rf_impact_solver)k;
        int uses_en = sv == RF_IMPACT_RIGID || sv == RF_IMPACT_MDR, uses_A = uses_en || sv == RF_IMPACT_HUNTER;
        char id[3][8192];
        for (int v = 0; v < 3; v++) {
            rf_impact_model_spec spec = spec_for(sv);
            spec.hunter_coefficient = v == 1 ? 2.0 : 1.04;
            spec.e_n = v == 2 ? 0.5 : NAN;
            rf_model m;
            rf_error err = {0};
            assert_int_equal(rf_impact_model_create(&spec, names, 1, &m, &err), RF_OK);
            snprintf(id[v], sizeof id[v], "%s", m.identity);
            rf_model_free(&m);
        }
        assert_int_equal(strcmp(id[0], id[1]) != 0, uses_A);
        assert_int_equal(strcmp(id[0], id[2]) != 0, uses_en);
    }
}

static void test_rigid_fixed_en_and_identity(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_RIGID);
    spec.e_n = 0.98;
    spec.base.velocity = 10.0;
    spec.base.slope_angle = 60 * DEG; /* base in radians */
    const char *names[] = {"friction"};
    rf_model model;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &model, &err), RF_OK);
    double x = 0.2, y[RF_IMPACT_N_OUTPUTS];
    assert_int_equal(rf_model_eval(&model, &x, y, &err), RF_OK);
    assert_true(fabs(y[5] - 0.771) < 6e-4); /* impact_refs 4.1, sliding row */
    assert_true(fabs(y[6] - 0.784) < 6e-4);
    assert_true(y[4] == 0.98);
    assert_non_null(strstr(model.identity, "solver=rigid"));
    assert_non_null(strstr(model.identity, "e_n=0.97999999999999998"));
    assert_non_null(strstr(model.identity, "params:friction"));
    /* a different setting gives a different identity */
    rf_model other;
    spec.e_n = 0.9;
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &other, &err), RF_OK);
    assert_string_not_equal(model.identity, other.identity);
    rf_model_free(&other);
    rf_model_free(&model);
}

static void test_angle_in_degrees_and_spheroid(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_HERTZ);
    const char *names[] = {"slope_angle"};
    rf_model model;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &model, &err), RF_OK);
    double x = 60.0, y[RF_IMPACT_N_OUTPUTS];
    assert_int_equal(rf_model_eval(&model, &x, y, &err), RF_OK);
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = 5.0; /* 10 cos 60 */
    rf_impact_output o;
    assert_int_equal(rf_impact_hertz(&in, &o, &err), RF_OK);
    assert_true(fabs(y[0] / o.contact_force_max - 1) < 1e-12);
    x = 90.0;
    assert_int_equal(rf_model_eval(&model, &x, y, &err), RF_EMODEL);
    assert_non_null(strstr(err.msg, "(90 deg)"));
    rf_model_free(&model);

    /* horizontal_axis binds c; d follows from constant volume */
    const char *cn[] = {"horizontal_axis"};
    assert_int_equal(rf_impact_model_create(&spec, cn, 1, &model, &err), RF_OK);
    x = 1.1;
    assert_int_equal(rf_model_eval(&model, &x, y, &err), RF_OK);
    rf_impact_input_default(&in);
    in.horizontal_axis = 1.1;
    in.vertical_axis = 1.0 / (1.1 * 1.1);
    assert_int_equal(rf_impact_hertz(&in, &o, &err), RF_OK);
    assert_true(fabs(y[1] / o.compression_max - 1) < 1e-14);
    rf_model_free(&model);
}

static void test_errors(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_HUNTER);
    rf_model model;
    rf_error err = {0};
    const char *bad[] = {"radius", "youngs_modulus"};
    assert_int_equal(rf_impact_model_create(&spec, bad, 2, &model, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "'youngs_modulus'"));
    assert_non_null(strstr(err.msg, "boulder_poisson"));
    assert_null(model.ctx);
    const char *twice[] = {"radius", "radius"};
    assert_int_equal(rf_impact_model_create(&spec, twice, 2, &model, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "twice"));

    /* a fuzzy Poisson's cut reaching 0.5 is a clear model error */
    const char *nu[] = {"boulder_poisson"};
    assert_int_equal(rf_impact_model_create(&spec, nu, 1, &model, &err), RF_OK);
    double x = 0.5, y[RF_IMPACT_N_OUTPUTS];
    assert_int_equal(rf_model_eval(&model, &x, y, &err), RF_EMODEL);
    assert_non_null(strstr(err.msg, "boulder_poisson = 0.5"));
    x = 0.49;
    assert_int_equal(rf_model_eval(&model, &x, y, &err), RF_OK);
    rf_model_free(&model);

    /* invalid base (unbound field) is caught at creation */
    spec.base.slope_E = -1.0;
    assert_int_equal(rf_impact_model_create(&spec, nu, 1, &model, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "slope_E = -1"));
    /* ... unless it is bound */
    const char *se[] = {"slope_E"};
    assert_int_equal(rf_impact_model_create(&spec, se, 1, &model, &err), RF_OK);
    rf_model_free(&model);

    spec = spec_for(RF_IMPACT_RIGID);
    spec.e_n = 1.2;
    assert_int_equal(rf_impact_model_create(&spec, nu, 1, &model, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "e_n = 1.2"));

    /* an FE refinement inside the axisymmetric limit (400) but beyond the 3D
     * one (100) is refused at creation when the model can run the 3D solver */
    spec = spec_for(RF_IMPACT_FEM);
    spec.fem.refinement = 200;
    assert_int_equal(rf_impact_model_create(&spec, nu, 1, &model, &err), RF_OK);
    rf_model_free(&model);
    const char *angle[] = {"slope_angle"};
    assert_int_equal(rf_impact_model_create(&spec, angle, 1, &model, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "refinement = 200"));
    assert_non_null(strstr(err.msg, "3D solver"));

#if !__has_include("rockfuzz/fem.h")
    spec = spec_for(RF_IMPACT_FEM);
    assert_int_equal(rf_impact_model_create(&spec, nu, 1, &model, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "FE solver not built"));
#endif
}

#if __has_include("rockfuzz/fem.h")
#include "rockfuzz/fem.h"
#include "fem/fem_tuning.h" /* a spec with internal tuning, refused */
/* The identity names the automatic end of section 10a (docs/validation-plastic.md) when a body may be
 * plastic (a study store never mixes results of the old fixed end), not
 * with a given end_time, not for elastic bodies. */
static void test_fem_identity_end(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
    spec.base.slope_material = RF_MATERIAL_VON_MISES, spec.base.slope_yield = 2e8;
    const char *names[] = {"velocity"};
    rf_model model;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &model, &err), RF_OK);
    assert_non_null(strstr(model.identity, " end=impact_ended"));
    rf_model_free(&model);
    spec.fem.end_time = 0.01;
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &model, &err), RF_OK);
    assert_null(strstr(model.identity, " end=impact_ended"));
    assert_non_null(strstr(model.identity, "end_time=0.01"));
    rf_model_free(&model);
}

/* The rigid sphere's exact-surface 3D contact (docs/validation-plastic.md 9g) is named in the identity
 * of a study whose boulder is rigid and which may run the 3D model (a store never mixes its results
 * with the faceted contact's of the stores made before); an elastic boulder's identity does not change.
 * A model runs the validated numerics only: a spec with internal tuning is refused. */
static void test_fem_identity_sphere_contact(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
    spec.base.slope_angle = 0.5, spec.base.friction = 0.3;
    const char *names[] = {"velocity"};
    rf_model a, b, c;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &c, &err), RF_OK); /* elastic boulder */
    spec.base.boulder_material = RF_MATERIAL_RIGID_BODY;
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &a, &err), RF_OK);
    assert_non_null(strstr(a.identity, " fem3d_contact=exact_sphere"));
    assert_null(strstr(c.identity, "fem3d_contact="));
    rf_fem_tuning tu;
    fem_tune(&spec.fem, &tu);
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &b, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "fem.tuning"));
    rf_model_free(&a), rf_model_free(&c);
}

/* The axisymmetric contact's friction is named where an evaluation may run
 * it with friction (slope angle 0 or fuzzy, friction > 0 or fuzzy), and
 * nowhere else: oblique stores (3D) and frictionless ones keep their identity. */
static void test_fem_identity_axi_friction(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
    const char *names[] = {"friction", "slope_angle"};
    rf_model m;
    rf_error err = {0};
    const struct { double angle, mu; size_t n; int named; } cases[] = {
        {0, 0, 0, 0}, {0, 0.5, 0, 1}, {0.5, 0.5, 0, 0}, {0.5, 0, 1, 0}, {0, 0, 1, 1}, {0.5, 0.5, 2, 1}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        spec.base.slope_angle = cases[k].angle, spec.base.friction = cases[k].mu;
        assert_int_equal(rf_impact_model_create(&spec, names, cases[k].n, &m, &err), RF_OK);
        if (!strstr(m.identity, " axi_contact=coulomb_friction") != !cases[k].named)
            fail_msg("case %zu: identity '%s'", k, m.identity);
        rf_model_free(&m);
    }
}

/* The default boundary (auto) in the identity: elastic bodies without a layer
 * resolve it to fixed everywhere and keep the identity of the old default
 * (fixed) to the byte; with a plastic body or a possible layer (the absorbing
 * dashpots) it is named by its rule, so that a store never mixes it with
 * results of the fixed boundary. */
static void test_fem_identity_boundary(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
    const char *names[] = {"velocity", "layer_thickness"};
    rf_model a, b;
    rf_error err = {0};
    assert_int_equal(spec.fem.boundary, RF_FEM_BOUNDARY_AUTO);
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &a, &err), RF_OK);
    spec.fem.boundary = RF_FEM_BOUNDARY_FIXED;
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &b, &err), RF_OK);
    assert_string_equal(a.identity, b.identity); /* elastic: auto is fixed */
    assert_null(strstr(a.identity, "dashpots="));
    rf_model_free(&a), rf_model_free(&b);
    for (int k = 0; k < 2; k++) { /* a plastic slope; an elastic layer that some point may have */
        spec = spec_for(RF_IMPACT_FEM);
        if (k == 0)
            spec.base.slope_material = RF_MATERIAL_VON_MISES, spec.base.slope_yield = 2e8;
        assert_int_equal(rf_impact_model_create(&spec, names, 1 + k, &a, &err), RF_OK);
        spec.fem.boundary = RF_FEM_BOUNDARY_FIXED;
        assert_int_equal(rf_impact_model_create(&spec, names, 1 + k, &b, &err), RF_OK);
        assert_non_null(strstr(a.identity, "boundary=auto_absorbing_if_layer_or_plastic"));
        assert_non_null(strstr(a.identity, "dashpots=face_impedance_semi_implicit"));
        assert_string_not_equal(a.identity, b.identity);
        rf_model_free(&a), rf_model_free(&b);
    }
}

/* The FE model on the coarsest mesh (a/h = 2): same numbers as a direct
 * rf_fem_impact call with the same options, and near Hertz. */
static void test_fem_model(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
    spec.fem.refinement = 2.0;
    spec.fem.boundary = RF_FEM_BOUNDARY_ABSORBING;
    const char *names[] = {"velocity", "slope_angle"};
    rf_model model;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 2, &model, &err), RF_OK);
    assert_non_null(strstr(model.identity, "refinement_axi=2 refinement_3d=2 "));
    assert_non_null(strstr(model.identity, "boundary=absorbing"));
    assert_non_null(strstr(model.identity, "dashpots=face_impedance_semi_implicit"));
    assert_null(strstr(model.identity, "end=impact_ended")); /* elastic: the end as it was */
    double x[2] = {10.0, 0.0}, y[RF_IMPACT_N_OUTPUTS], want[RF_IMPACT_N_OUTPUTS];
    if (rf_model_eval(&model, x, y, &err) != RF_OK)
        fail_msg("FE eval: %s", err.msg);
    rf_fem_options opt;
    rf_fem_options_default(&opt);
    opt.refinement = 2.0;
    opt.boundary = RF_FEM_BOUNDARY_ABSORBING;
    rf_impact_input in = spec.base;
    rf_impact_output o;
    assert_int_equal(rf_fem_impact(&in, &opt, &o, NULL, &err), RF_OK);
    outputs_of(&o, want);
    assert_same(y, want, RF_IMPACT_N_OUTPUTS);
    rf_impact_output h;
    assert_int_equal(rf_impact_hertz(&in, &h, &err), RF_OK);
    assert_true(fabs(y[0] / h.contact_force_max - 1) < 0.1);
    assert_true(fabs(y[2] / h.contact_duration - 1) < 0.1);
    assert_true(y[4] > 0.95 && y[4] < 1.0);
    /* an inclined slope goes to the 3D model: frictionless 45 deg keeps the
     * tangential velocity (R_t = 1) and its normal response is that of a
     * normal impact at V cos 45 (R_n within the mesh's scatter) */
    rf_model_free(&model);
    spec.fem.refinement = 3.0; /* a/h = 2 facets the 3D sphere too coarsely: R_t = 0.990 */
    assert_int_equal(rf_impact_model_create(&spec, names, 2, &model, &err), RF_OK);
    x[1] = 45.0;
    if (rf_model_eval(&model, x, y, &err) != RF_OK)
        fail_msg("3D FE eval: %s", err.msg);
    if (!(fabs(y[5] - 1.0) < 2e-3))
        fail_msg("frictionless 45 deg: R_t = %.6f", y[5]);
    double normal[RF_IMPACT_N_OUTPUTS];
    double xn[2] = {10.0 * sqrt(0.5), 0.0}; /* V cos 45 deg */
    assert_int_equal(rf_model_eval(&model, xn, normal, &err), RF_OK);
    if (!(fabs(y[4] - normal[4]) < 3e-3))
        fail_msg("R_n 3D %.6f vs axisymmetric %.6f", y[4], normal[4]);
    rf_model_free(&model);
}

/* The FE solver's warnings reach the caller through rf_model.warnings: a
 * fixed boundary at 10 r0 (the seed paper's model) reflects P waves back
 * before a 10 m/s contact ends (2L/c_p = 3.56 ms < 4.45 ms); absorbing
 * dashpots and the default (automatic) domain do not warn. */
static void test_fem_warnings(void **state)
{
    (void)state;
    const char *names[] = {"velocity"};
    double x[1] = {10.0}, y[RF_IMPACT_N_OUTPUTS];
    char text[1024];
    rf_error err = {0};
    for (int kind = 0; kind <= 2; kind++) { /* fixed 10 r0, absorbing 10 r0, default */
        const int absorbing = kind > 0;
        rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
        spec.fem.refinement = 2.0;
        spec.fem.boundary = kind == 1 ? RF_FEM_BOUNDARY_ABSORBING : RF_FEM_BOUNDARY_FIXED;
        spec.fem.domain_factor = kind < 2 ? 10 : 0;
        rf_model model;
        assert_int_equal(rf_impact_model_create(&spec, names, 1, &model, &err), RF_OK);
        assert_non_null(model.warnings);
        assert_int_equal(model.warnings(model.ctx, text, sizeof text), 0);
        assert_int_equal(rf_model_eval(&model, x, y, &err), RF_OK);
        assert_int_equal(rf_model_eval(&model, x, y, &err), RF_OK);
        size_t warned = model.warnings(model.ctx, text, sizeof text);
        if (absorbing) {
            assert_int_equal(warned, 0);
            assert_string_equal(text, "");
        } else {
            assert_int_equal(warned, 2);
            if (!strstr(text, "2 of the 2 FE evaluations") || !strstr(text, "reflected"))
                fail_msg("warning summary: %s", text);
        }
        rf_model_free(&model);
    }
}

/* Which FE model an impact needs: 3D for a slope, or for friction between
 * dissimilar bodies (Dundurs beta != 0); axisymmetric otherwise. */
static void test_fem_dispatch(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    assert_int_equal(rf_fem_needs_3d(&in), 0);
    in.friction = 0.6; /* identical materials: no tangential traction in a normal impact */
    assert_int_equal(rf_fem_needs_3d(&in), 0);
    in.slope_E = 30e9;
    assert_int_equal(rf_fem_needs_3d(&in), 1);
    in.friction = 0;
    assert_int_equal(rf_fem_needs_3d(&in), 0);
    in.slope_angle = 0.5;
    assert_int_equal(rf_fem_needs_3d(&in), 1);
    in.slope_angle = 0, in.slope_E = in.boulder_E, in.friction = 0.6;
    in.boulder_material = RF_MATERIAL_RIGID_BODY; /* beta = (1 - 2 nu) / (2 (1 - nu)) = 1/3 at nu = 0.25 */
    assert_int_equal(rf_fem_needs_3d(&in), 1);
    in.boulder_material = RF_MATERIAL_ELASTIC, in.layer_thickness = 0.2, in.layer_E = 1e8;
    assert_int_equal(rf_fem_needs_3d(&in), 1); /* granite on a soft elastic layer */
    in.layer_E = in.boulder_E;
    assert_int_equal(rf_fem_needs_3d(&in), 0); /* the layer is the boulder's material */
    in.layer_material = RF_MATERIAL_DRUCKER_PRAGER;
    assert_int_equal(rf_fem_needs_3d(&in), 0); /* plastic: axisymmetric, frictionless */
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    assert_true(rf_fem_refinement(&spec.fem, 0) == 10.0 && rf_fem_refinement(&spec.fem, 1) == 3.0);
    spec.fem.refinement = 4;
    assert_true(rf_fem_refinement(&spec.fem, 0) == 4.0 && rf_fem_refinement(&spec.fem, 1) == 4.0);
}
#else
static void test_fem_model(void **state) { skip(); (void)state; }
static void test_fem_dispatch(void **state) { skip(); (void)state; }
static void test_fem_warnings(void **state) { skip(); (void)state; }
#endif

typedef struct {
    const rf_model *model;
    int fails;
} worker_arg;

static void *worker(void *p)
{
    worker_arg *a = p;
    for (int i = 0; i < 2000; i++) {
        double x[2] = {1.0 + (i % 30), 0.1 * (i % 11)}, y[RF_IMPACT_N_OUTPUTS];
        rf_error err = {0};
        if (rf_model_eval(a->model, x, y, &err) != RF_OK || !(y[4] > 0.9 && y[4] < 1.0))
            a->fails++;
    }
    return NULL;
}

static void test_concurrent(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_RIGID);
    spec.base.slope_angle = 45 * DEG;
    const char *names[] = {"velocity", "friction"};
    rf_model model;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 2, &model, &err), RF_OK);
    pthread_t t[4];
    worker_arg a[4];
    for (int k = 0; k < 4; k++) {
        a[k] = (worker_arg){&model, 0};
        pthread_create(&t[k], NULL, worker, &a[k]);
    }
    for (int k = 0; k < 4; k++) {
        pthread_join(t[k], NULL);
        assert_int_equal(a[k].fails, 0);
    }
    rf_model_free(&model);
}

/* Material parameters are study parameters (angles in degrees); the model
 * returns the plastic outputs, equal to a direct FE call. */
static void test_plastic_parameters(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
    spec.fem.refinement = 2.0;
    spec.base.slope_material = RF_MATERIAL_DRUCKER_PRAGER;
    spec.base.slope_cohesion = 1e6;
    const char *names[] = {"slope_friction_angle", "slope_dilatancy_angle", "slope_cap_pressure",
                           "slope_cap_hardening"};
    const double x[] = {35.0, 5.0, 2e8, 1e9};
    rf_model model;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 4, &model, &err), RF_OK);
    assert_non_null(strstr(model.identity, "slope_material=drucker_prager"));
    assert_string_equal(model.output_names[7], "plastic_work");
    assert_string_equal(model.output_units[8], "m");
    double y[RF_IMPACT_N_OUTPUTS], want[RF_IMPACT_N_OUTPUTS];
    if (rf_model_eval(&model, x, y, &err) != RF_OK)
        fail_msg("plastic eval: %s", err.msg);
    rf_impact_input in = spec.base;
    in.slope_friction_angle = 35.0 * DEG, in.slope_dilatancy_angle = 5.0 * DEG;
    in.slope_cap_pressure = 2e8, in.slope_cap_hardening = 1e9;
    rf_impact_output o;
    assert_int_equal(rf_fem_impact(&in, &spec.fem, &o, NULL, &err), RF_OK);
    outputs_of(&o, want);
    assert_same(y, want, RF_IMPACT_N_OUTPUTS);
    assert_true(y[7] > 0 && y[10] > 0 && y[4] < 0.98);
    rf_model_free(&model);
    /* the layer's inputs are parameters too (the same bits as a direct call: the loading part is
       enough, and keeps this test short under the sanitizers) */
    const char *lnames[] = {"layer_thickness", "layer_E", "layer_friction_angle"};
    const double lx[] = {0.2, 20e9, 30.0};
    spec.base.layer_material = RF_MATERIAL_DRUCKER_PRAGER, spec.base.layer_cohesion = 1e6;
    spec.fem.end_time = 1.5e-3;
    assert_int_equal(rf_impact_model_create(&spec, lnames, 3, &model, &err), RF_OK);
    assert_non_null(strstr(model.identity, "layer_material=drucker_prager"));
    if (rf_model_eval(&model, lx, y, &err) != RF_OK)
        fail_msg("layer eval: %s", err.msg);
    in = spec.base;
    in.layer_thickness = 0.2, in.layer_E = 20e9, in.layer_friction_angle = 30.0 * DEG;
    assert_int_equal(rf_fem_impact(&in, &spec.fem, &o, NULL, &err), RF_OK);
    outputs_of(&o, want);
    assert_same(y, want, RF_IMPACT_N_OUTPUTS);
    rf_model_free(&model);
    assert_int_equal(rf_impact_model_create(&spec, names, 4, &model, &err), RF_OK);
    /* an inadmissible value is named */
    const double bad[] = {30.0, 40.0, 2e8, 1e9};
    assert_int_not_equal(rf_model_eval(&model, bad, y, &err), RF_OK);
    assert_non_null(strstr(err.msg, "slope_dilatancy_angle"));
    rf_model_free(&model);
}

/* The dilatancy cutoff is an input and a study parameter, and the identity
 * carries its value (as every input's: test_impact_fields). */
static void test_dilatancy_cutoff_identity(void **state)
{
    (void)state;
    rf_impact_model_spec spec = spec_for(RF_IMPACT_FEM);
    spec.base.slope_material = RF_MATERIAL_DRUCKER_PRAGER;
    spec.base.slope_cohesion = 1e6, spec.base.slope_friction_angle = 35.0 * DEG;
    spec.base.slope_dilatancy_angle = 5.0 * DEG;
    const char *names[] = {"slope_dilatancy_cutoff"};
    rf_model model;
    rf_error err = {0};
    assert_int_equal(rf_impact_model_create(&spec, names, 0, &model, &err), RF_OK);
    assert_non_null(strstr(model.identity, " slope_dilatancy_cutoff=0 "));
    rf_model_free(&model);
    spec.base.slope_dilatancy_cutoff = 0.02;
    assert_int_equal(rf_impact_model_create(&spec, names, 0, &model, &err), RF_OK);
    assert_non_null(strstr(model.identity, " slope_dilatancy_cutoff=0.02"));
    assert_non_null(strstr(model.identity, " layer_dilatancy_cutoff=0 "));
    rf_model_free(&model);
    spec.base.slope_dilatancy_cutoff = 0.0;
    assert_int_equal(rf_impact_model_create(&spec, names, 1, &model, &err), RF_OK);
    assert_non_null(strstr(model.identity, " slope_dilatancy_cutoff="));
    /* an inadmissible value is named */
    const double bad[] = {-0.01};
    double y[RF_IMPACT_N_OUTPUTS];
    assert_int_not_equal(rf_model_eval(&model, bad, y, &err), RF_OK);
    assert_non_null(strstr(err.msg, "slope_dilatancy_cutoff"));
    rf_model_free(&model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spec_default),
        cmocka_unit_test(test_eval_matches_direct),
        cmocka_unit_test(test_rigid_fixed_en_and_identity),
        cmocka_unit_test(test_identity_from_registry),
        cmocka_unit_test(test_angle_in_degrees_and_spheroid),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_concurrent),
        cmocka_unit_test(test_fem_model),
        cmocka_unit_test(test_fem_identity_end),
        cmocka_unit_test(test_fem_identity_sphere_contact),
        cmocka_unit_test(test_fem_identity_axi_friction),
        cmocka_unit_test(test_fem_identity_boundary),
        cmocka_unit_test(test_plastic_parameters),
        cmocka_unit_test(test_dilatancy_cutoff_identity),
        cmocka_unit_test(test_fem_dispatch),
        cmocka_unit_test(test_fem_warnings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
