/* test_impact_fields.c - the one table of the impact inputs (impact.h,
 * rf_impact_fields) reaches every place that reads it: each row's default is
 * the input's default, each row is a study key that sets its field, each
 * bindable row binds a fuzzy parameter (and only those), and the result
 * store's identity changes when any row's value or any material changes, so
 * a store can never serve a result computed for other inputs.  A row added to
 * the table is covered by these loops without a line here. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/impact_model.h"
#include "rockfuzz/study.h"

#define PI 3.14159265358979323846

static double stored(const rf_impact_input *in, const rf_impact_field *f)
{
    return *(const double *)((const char *)in + f->offset);
}

/* A valid value different from the default, as given (degrees for angles). */
static double other_value(const rf_impact_field *f)
{
    switch (f->check) {
    case RF_CHECK_POSITIVE: return 1.5 * f->def;
    case RF_CHECK_NONNEGATIVE: return f->def + 0.5;
    case RF_CHECK_POISSON: return 0.3;
    case RF_CHECK_INCLINATION: return 10.0;
    case RF_CHECK_GRAVITY: return 3.0;
    case RF_CHECK_NONE: return 1.5 * f->def + 1.0;
    }
    return NAN;
}

static char *identity_of(const rf_impact_model_spec *spec, const char *const *names, size_t n)
{
    rf_model model;
    rf_error err = {0};
    if (rf_impact_model_create(spec, names, n, &model, &err) != RF_OK)
        fail_msg("model: %s", err.msg);
    char *id = strdup(model.identity);
    rf_model_free(&model);
    return id;
}

/* The defaults of SYSTEM.md's nominal granite, written out here (not read from the table). */
static void test_defaults(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    assert_true(in.radius == 1.0 && in.boulder_density == 2600.0 && in.slope_density == 2600.0);
    assert_true(in.boulder_E == 68.2e9 && in.slope_E == 68.2e9 && in.layer_E == 68.2e9);
    assert_true(in.boulder_poisson == 0.25 && in.slope_poisson == 0.25 && in.velocity == 10.0);
    assert_true(in.slope_angle == 0.0 && in.friction == 0.0 && in.layer_thickness == 0.0);
    assert_true(in.gravity == RF_GRAVITY_AUTO);
    assert_int_equal(in.boulder_material, RF_MATERIAL_ELASTIC);
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        double want = f->kind == RF_FIELD_DEGREES ? f->def * PI / 180.0 : f->def;
        if (stored(&in, f) != want)
            fail_msg("%s: default %.17g, table %.17g", f->name, stored(&in, f), want);
        assert_true(f->unit && f->help && f->help[0]);
        assert_ptr_equal(rf_impact_field_find(f->name), f);
    }
    assert_int_equal(rf_impact_input_validate(&in, NULL), RF_OK);
}

/* Every field and every material enters the identity. */
static void test_identity_covers_every_field(void **state)
{
    (void)state;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    char *base = identity_of(&spec, NULL, 0);
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        rf_impact_model_spec changed = spec;
        rf_impact_field_store(&changed.base, f, other_value(f));
        if (!strcmp(f->name, "vertical_axis"))
            changed.base.horizontal_axis = 1.2; /* a spheroid's axis needs the other */
        char *id = identity_of(&changed, NULL, 0);
        if (!strcmp(id, base))
            fail_msg("identity does not change with %s", f->name);
        free(id);
    }
    const rf_material_model mats[3] = {RF_MATERIAL_VON_MISES, RF_MATERIAL_DRUCKER_PRAGER, RF_MATERIAL_VON_MISES};
    for (int b = 0; b < 3; b++) {
        rf_impact_model_spec changed = spec;
        changed.base.boulder_yield = changed.base.slope_yield = changed.base.layer_yield = 1e8;
        char *same = identity_of(&changed, NULL, 0);
        rf_material_model *m = b == 0 ? &changed.base.boulder_material
                               : b == 1 ? &changed.base.slope_material : &changed.base.layer_material;
        *m = mats[b];
        changed.base.slope_cohesion = 1e4, changed.base.slope_friction_angle = 30 * PI / 180;
        changed.base.layer_thickness = b == 2 ? 0.5 : 0.0;
        char *id = identity_of(&changed, NULL, 0);
        if (b == 2) { /* the layer's material with the same layer, elastic */
            free(same);
            rf_impact_model_spec elastic = changed;
            elastic.base.layer_material = RF_MATERIAL_ELASTIC;
            same = identity_of(&elastic, NULL, 0);
        }
        if (!strcmp(id, same))
            fail_msg("identity does not change with material %d", b);
        free(id), free(same);
    }
    free(base);
}

/* Each bindable row binds; the others are refused by name. */
static void test_bind_every_bindable(void **state)
{
    (void)state;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    size_t bound = 0;
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        const char *names[1] = {f->name};
        rf_model model;
        rf_error err = {0};
        rf_status st = rf_impact_model_create(&spec, names, 1, &model, &err);
        if (!f->bindable) {
            assert_int_not_equal(st, RF_OK);
            assert_non_null(strstr(err.msg, f->name));
            continue;
        }
        if (st != RF_OK)
            fail_msg("%s: %s", f->name, err.msg);
        char tail[96];
        snprintf(tail, sizeof tail, " params:%s", f->name);
        assert_non_null(strstr(model.identity, tail));
        rf_model_free(&model);
        bound++;
    }
    assert_true(bound >= 30);
}

/* Each row is a key of a study's impact block that sets its field (as given:
 * degrees for angles), seen through the identity of the model built. */
static void test_study_key_per_field(void **state)
{
    (void)state;
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        const char *fuzzy = strcmp(f->name, "velocity") ? "velocity" : "radius";
        char text[1024];
        snprintf(text, sizeof text,
                 "name: t\nparameters:\n  %s: {tfn: [10, 1, 1]}\nmodel:\n  impact:\n    solver: fem\n"
                 "    %s: %.17g\n%s", fuzzy, f->name, other_value(f),
                 strcmp(f->name, "vertical_axis") ? "" : "    horizontal_axis: 1.2\n");
        rf_study s;
        rf_error err = {0};
        if (rf_study_load_buffer("fields.yaml", text, strlen(text), &s, &err) != RF_OK)
            fail_msg("%s: %s", f->name, err.msg);
        rf_impact_input in;
        rf_impact_input_default(&in);
        rf_impact_field_store(&in, f, other_value(f));
        char want[128];
        snprintf(want, sizeof want, " %s=%.17g ", f->name, stored(&in, f));
        if (!strstr(s.model.identity, want))
            fail_msg("%s: '%s' not in %s", f->name, want, s.model.identity);
        rf_study_free(&s);
    }
}

/* A misspelt key is refused with the nearest name. */
static void test_study_key_typo(void **state)
{
    (void)state;
    const char *text = "name: t\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact:\n    slope_E2: 1e9\n";
    rf_study s;
    rf_error err = {0};
    assert_int_not_equal(rf_study_load_buffer("typo.yaml", text, strlen(text), &s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "typo.yaml:6: model.impact.slope_E2"));
    assert_non_null(strstr(err.msg, "did you mean 'slope_E'?"));
}

/* Each row is an option of `rockfuzz impact` (the name with '-'), listed by --help with its unit. */
static void test_cli_option_per_field(void **state)
{
    (void)state;
    FILE *p = popen(ROCKFUZZ_CLI " impact --help", "r");
    assert_non_null(p);
    static char help[65536];
    size_t len = fread(help, 1, sizeof help - 1, p);
    help[len] = '\0';
    assert_int_equal(pclose(p), 0);
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        char opt[80];
        int n = snprintf(opt, sizeof opt, "\n  --%s ", f->name);
        for (int q = 5; q < n; q++)
            opt[q] = opt[q] == '_' ? '-' : opt[q];
        const char *at = strstr(help, opt);
        if (!at)
            fail_msg("--help lacks '%s'", opt + 3);
        char unit[32];
        snprintf(unit, sizeof unit, "[%s]", f->unit);
        const char *next = strstr(at + 1, "\n  --");
        const char *u = strstr(at, unit);
        if (f->unit[0] && (!u || (next && u > next)))
            fail_msg("--help: %s without its unit %s", opt + 3, unit);
    }
    /* an option sets its field: the same result as the study's default with that value */
    p = popen(ROCKFUZZ_CLI " impact --solver hertz --slope-E 30e9 --json", "r");
    assert_non_null(p);
    len = fread(help, 1, sizeof help - 1, p);
    help[len] = '\0';
    assert_int_equal(pclose(p), 0);
    rf_impact_input in;
    rf_impact_input_default(&in);
    rf_impact_field_store(&in, rf_impact_field_find("slope_E"), 30e9);
    rf_impact_output out;
    assert_int_equal(rf_impact_hertz(&in, &out, NULL), RF_OK);
    char want[96];
    snprintf(want, sizeof want, "\"contact_force_max\": %.17g", out.contact_force_max);
    if (!strstr(help, want))
        fail_msg("'%s' not in %s", want, help);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_identity_covers_every_field),
        cmocka_unit_test(test_bind_every_bindable),
        cmocka_unit_test(test_study_key_per_field),
        cmocka_unit_test(test_study_key_typo),
        cmocka_unit_test(test_cli_option_per_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
