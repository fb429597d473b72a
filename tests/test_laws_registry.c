/* test_laws_registry.c - the registries of laws (issue 26, point 5): the
 * material laws (material.h) and the impact solvers (impact_model.h).
 * Every row of every table is checked in every place that loops over it, so
 * a new law or parameter is covered without a new test line: names round
 * trip and are unique, each parameter is a distinct double of
 * rf_material_params that rf_material_params_default sets to its default,
 * that rf_material_param_find finds, whose rule rejects a bad value with a
 * message naming it (alone and through rf_material_init of its law); each
 * solver of the registry gives through rf_impact_solve the same bits as its
 * own function, and the refusals name the solver. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rockfuzz/impact_model.h"
#include "rockfuzz/material.h"
#include "rockfuzz/mdr.h"

static void assert_prefix(const char *msg, const char *prefix)
{
    if (strncmp(msg, prefix, strlen(prefix)) != 0)
        fail_msg("message '%s' does not start with '%s'", msg, prefix);
}

/* Names round trip, are unique, and the unknown one lists them all. */
static void test_material_names(void **state)
{
    (void)state;
    const size_t n = rf_material_n_laws();
    assert_int_equal(n, 3);
    assert_string_equal(rf_material_model_name(RF_MATERIAL_DRUCKER_PRAGER), "drucker_prager");
    for (size_t k = 0; k < n; k++) {
        rf_material_model m = (rf_material_model)99;
        const char *name = rf_material_law((rf_material_model)k)->name;
        assert_int_equal(rf_material_model_parse(name, &m, NULL), RF_OK);
        assert_int_equal(m, (rf_material_model)k);
        for (size_t j = 0; j < k; j++)
            assert_string_not_equal(name, rf_material_law((rf_material_model)j)->name);
    }
    assert_null(rf_material_law((rf_material_model)n));
    assert_string_equal(rf_material_model_name((rf_material_model)n), "unknown");
    rf_material_model m;
    rf_error err = {0};
    assert_int_equal(rf_material_model_parse("cam_clay", &m, &err), RF_EINVAL);
    for (size_t k = 0; k < n; k++)
        assert_non_null(strstr(err.msg, rf_material_law((rf_material_model)k)->name));
}

/* A value breaking the rule: the first one past each boundary. */
static double bad_value(const rf_material_param *p)
{
    switch (p->rule) {
    case RF_MATERIAL_RULE_POSITIVE: return 0.0;
    case RF_MATERIAL_RULE_NONNEGATIVE: return -1.0;
    case RF_MATERIAL_RULE_POISSON: return 0.5;
    case RF_MATERIAL_RULE_ANGLE: return 0.5 * acos(-1.0);
    }
    return NAN;
}

/* Valid values of every law's required parameters (others at their defaults). */
static void valid_params(rf_material_model model, rf_material_params *p)
{
    rf_material_params_default(p);
    p->model = model;
    p->yield = 1e8;
    p->cohesion = 1e4;
    p->friction_angle = 0.5;
}

/* One parameter everywhere it is used; `seen` collects the offsets. */
static void check_param(const rf_material_param *p, rf_material_model owner, int common, size_t *seen, size_t *n_seen)
{
    assert_true(p->offset % sizeof(double) == 0 && p->offset + sizeof(double) <= sizeof(rf_material_params));
    assert_true(p->offset != offsetof(rf_material_params, model));
    for (size_t i = 0; i < *n_seen; i++)
        if (seen[i] == p->offset)
            fail_msg("%s: offset %zu taken twice", p->name, p->offset);
    seen[(*n_seen)++] = p->offset;
    assert_ptr_equal(rf_material_param_find(p->name), p);
    assert_non_null(p->unit);
    assert_non_null(p->metavar);
    assert_non_null(p->help);
    rf_material_params d;
    rf_material_params_default(&d);
    assert_true(*rf_material_param_field(&d, p) == p->default_value);
    assert_int_equal(rf_material_param_check(p, p->default_value + (p->rule == RF_MATERIAL_RULE_POSITIVE), NULL),
                     RF_OK);
    char prefix[80];
    snprintf(prefix, sizeof prefix, "%s = ", p->name);
    rf_error err = {0};
    assert_int_equal(rf_material_param_check(p, bad_value(p), &err), RF_EINVAL);
    assert_prefix(err.msg, prefix);
    assert_int_equal(rf_material_param_check(p, NAN, &err), RF_EINVAL);
    for (size_t k = 0; k < rf_material_n_laws(); k++) {
        if (!common && (rf_material_model)k != owner)
            continue;
        rf_material_params q;
        rf_material m;
        valid_params((rf_material_model)k, &q);
        assert_int_equal(rf_material_init(&m, &q, NULL), RF_OK);
        *rf_material_param_field(&q, p) = bad_value(p);
        assert_int_equal(rf_material_init(&m, &q, &err), RF_EINVAL);
        assert_prefix(err.msg, prefix);
    }
    if (p->together) {
        const rf_material_param *partner = rf_material_param_find(p->together);
        assert_non_null(partner);
        assert_string_equal(partner->together, p->name);
        assert_non_null(p->feature);
    }
}

static void test_material_params(void **state)
{
    (void)state;
    size_t seen[64], n_seen = 0;
    for (size_t i = 0; i < 2; i++)
        check_param(&rf_material_common_params[i], RF_MATERIAL_ELASTIC, 1, seen, &n_seen);
    for (size_t k = 0; k < rf_material_n_laws(); k++) {
        const rf_material_law_info *law = rf_material_law((rf_material_model)k);
        for (size_t i = 0; i < law->n_params; i++)
            check_param(&law->params[i], (rf_material_model)k, 0, seen, &n_seen);
    }
    assert_int_equal(n_seen, 10); /* every double of rf_material_params has its row */
    assert_null(rf_material_param_find("no_such"));
    assert_null(rf_material_param_find(NULL));
}

/* Every output, bit for bit (NaN equal to NaN). */
static void assert_same_outputs(const rf_impact_output *a, const rf_impact_output *b)
{
    for (size_t k = 0; k < RF_IMPACT_N_OUTPUTS; k++) {
        const size_t off = rf_impact_output_fields[k].offset;
        assert_memory_equal((const char *)a + off, (const char *)b + off, sizeof(double));
    }
}

/* Each solver through the registry gives the bits of its own function. */
static void test_solvers_same_bits(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = 12.0, in.slope_angle = 0.6, in.friction = 0.4;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.base = in;
    rf_impact_output a, b, h;
    for (int s = RF_IMPACT_HERTZ; s <= RF_IMPACT_MDR; s++) {
        spec.solver = (rf_impact_solver)s;
        for (int en = 0; en < 2; en++) {
            spec.e_n = en ? 0.7 : NAN;
            assert_int_equal(rf_impact_solve(&spec, &in, &a, NULL), RF_OK);
            if (s == RF_IMPACT_HERTZ)
                assert_int_equal(rf_impact_hertz(&in, &b, NULL), RF_OK);
            else if (s == RF_IMPACT_HUNTER)
                assert_int_equal(rf_impact_hunter_A(&in, RF_HUNTER_A_JOHNSON, &b, NULL), RF_OK);
            else if (s == RF_IMPACT_MDR)
                assert_int_equal(rf_impact_mdr_hunter(&in, spec.e_n, RF_HUNTER_A_JOHNSON, &b, NULL), RF_OK);
            else {
                assert_int_equal(rf_impact_hunter_A(&in, RF_HUNTER_A_JOHNSON, &h, NULL), RF_OK);
                assert_int_equal(rf_impact_rigid(&in, en ? 0.7 : h.R_n, &b, NULL), RF_OK);
            }
            assert_same_outputs(&a, &b);
        }
    }
}

/* Names round trip; the refusals name the solver; the unknown lists them all. */
static void test_solver_registry(void **state)
{
    (void)state;
    const size_t n = rf_impact_n_solvers();
    assert_int_equal(n, 5);
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.layer_thickness = 0.2;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    rf_error err = {0};
    for (size_t k = 0; k < n; k++) {
        const rf_impact_law *law = rf_impact_solver_law((rf_impact_solver)k);
        rf_impact_solver s = (rf_impact_solver)99;
        assert_int_equal(rf_impact_solver_parse(law->name, &s, NULL), RF_OK);
        assert_int_equal(s, (rf_impact_solver)k);
        assert_string_equal(rf_impact_solver_name(s), law->name);
        assert_true(law->help && *law->help && law->validate && law->solve);
        if (k == RF_IMPACT_FEM)
            continue;
        spec.solver = s;
        rf_impact_output out;
        assert_int_equal(rf_impact_solve(&spec, &in, &out, &err), RF_EINVAL);
        char want[80];
        snprintf(want, sizeof want, "the %s solver has no layer", law->name);
        assert_non_null(strstr(err.msg, want));
        assert_true(isnan(out.R_n));
    }
    assert_null(rf_impact_solver_law((rf_impact_solver)n));
    rf_impact_solver s;
    assert_int_equal(rf_impact_solver_parse("dem", &s, &err), RF_EINVAL);
    for (size_t k = 0; k < n; k++)
        assert_non_null(strstr(err.msg, rf_impact_solver_name((rf_impact_solver)k)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_material_names),
        cmocka_unit_test(test_material_params),
        cmocka_unit_test(test_solvers_same_bits),
        cmocka_unit_test(test_solver_registry),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
