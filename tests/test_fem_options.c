/* test_fem_options.c - the one table of the public FE options (fem.h,
 * rf_fem_option_fields) reaches every place that reads it: each row's default
 * is the option's default, each row parses and refuses through the solvers'
 * own rule with a message naming it, each row is a study key and an option of
 * `rockfuzz impact` (listed by --help with its default), and the impact
 * model's identity changes when any row's value changes.  The internal
 * numerics (src/fem/fem_tuning.h) are none of these: no CLI option, no study
 * key, and no file of the CLI, the study or the model includes their header.
 * A row added to the table is covered by these loops without a line here. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "rockfuzz/impact_model.h"
#include "rockfuzz/study.h"

/* The defaults, written out here (not read from the table). */
static void test_defaults(void **state)
{
    (void)state;
    rf_fem_options o;
    rf_fem_options_default(&o);
    assert_true(o.refinement == 0 && o.domain_factor == 0 && o.end_time == 0 && o.threads == 1);
    assert_int_equal(o.boundary, RF_FEM_BOUNDARY_AUTO);
    assert_int_equal(o.large_deformation, RF_FEM_KINEMATICS_AUTO);
    assert_int_equal(o.ale, RF_FEM_ALE_OFF);
    assert_null(o.vtk_dir), assert_null(o.tuning), assert_null(o.progress);
    assert_true(rf_fem_n_option_fields >= 7);
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *f = &rf_fem_option_fields[k];
        char value[64], want[64];
        rf_fem_option_format(&o, f, value, sizeof value);
        if (f->kind == RF_FEM_OPTION_CHOICE)
            snprintf(want, sizeof want, "%s", f->choices[(int)f->def]);
        else
            snprintf(want, sizeof want, f->kind == RF_FEM_OPTION_REAL ? "%.17g" : "%.0f", f->def);
        if (strcmp(value, want))
            fail_msg("%s: default %s, table %s", f->name, value, want);
        assert_true(f->help[0] && f->value_name[0] && f->unit);
        assert_ptr_equal(rf_fem_option_find(f->name), f);
    }
    assert_int_equal(rf_fem_options_validate(&o, 0, NULL), RF_OK);
    assert_int_equal(rf_fem_options_validate(&o, 1, NULL), RF_OK);
}

/* A valid value other than the default, as text. */
static void other_text(const rf_fem_option_field *f, char *buf, size_t size)
{
    if (f->kind == RF_FEM_OPTION_CHOICE)
        snprintf(buf, size, "%s", f->choices[f->def == 0 ? 1 : 0]);
    else if (f->kind == RF_FEM_OPTION_COUNT)
        snprintf(buf, size, "%.0f", f->def + 1);
    else if (isinf(f->hi))
        snprintf(buf, size, "%.17g", f->def + 1e-3);
    else
        snprintf(buf, size, "%.17g", 0.5 * (f->lo + f->hi3));
}

/* A value the row refuses, as text. */
static void bad_text(const rf_fem_option_field *f, char *buf, size_t size)
{
    if (f->kind == RF_FEM_OPTION_CHOICE)
        snprintf(buf, size, "sometimes");
    else
        snprintf(buf, size, "%.17g", f->lo - 1);
}

/* Each row parses a good value (and formats it back) and refuses a bad one
 * by name, leaving the options as they were. */
static void test_parse_and_refuse(void **state)
{
    (void)state;
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *f = &rf_fem_option_fields[k];
        rf_fem_options o, before;
        rf_fem_options_default(&o);
        char text[64], back[64];
        other_text(f, text, sizeof text);
        rf_error err = {0};
        if (rf_fem_option_parse(&o, f, text, &err) != RF_OK)
            fail_msg("%s %s: %s", f->name, text, err.msg);
        rf_fem_option_format(&o, f, back, sizeof back);
        assert_string_equal(back, text);
        assert_int_equal(rf_fem_options_validate(&o, 0, NULL), RF_OK);
        before = o;
        bad_text(f, text, sizeof text);
        assert_int_equal(rf_fem_option_parse(&o, f, text, &err), RF_EINVAL);
        if (!strstr(err.msg, f->name) || !strstr(err.msg, f->kind == RF_FEM_OPTION_CHOICE ? text : "must lie in"))
            fail_msg("%s %s: message '%s'", f->name, text, err.msg);
        assert_memory_equal(&o, &before, sizeof o);
        assert_int_equal(rf_fem_option_parse(&o, f, "x", &err), RF_EINVAL);
    }
}

static char *identity_of(const rf_impact_model_spec *spec)
{
    rf_model model;
    rf_error err = {0};
    if (rf_impact_model_create(spec, NULL, 0, &model, &err) != RF_OK)
        fail_msg("model: %s", err.msg);
    char *id = strdup(model.identity);
    rf_model_free(&model);
    return id;
}

/* A plastic slope: every row acts (large deformation, ALE, the boundary's auto rule). */
static void plastic_spec(rf_impact_model_spec *spec)
{
    rf_impact_model_spec_default(spec);
    spec->base.slope_material = RF_MATERIAL_VON_MISES, spec->base.slope_yield = 2e8;
}

/* Each row enters the identity: a store never serves a result of other options. */
static void test_identity_covers_every_option(void **state)
{
    (void)state;
    rf_impact_model_spec spec;
    plastic_spec(&spec);
    char *base = identity_of(&spec);
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *f = &rf_fem_option_fields[k];
        const int n = f->kind == RF_FEM_OPTION_CHOICE ? 8 : 1;
        for (int c = 0; c < n && (c == 0 || f->choices[c]); c++) { /* every other choice */
            rf_impact_model_spec changed = spec;
            char text[64];
            other_text(f, text, sizeof text);
            if (f->kind == RF_FEM_OPTION_CHOICE) {
                if (c == (int)f->def)
                    continue;
                snprintf(text, sizeof text, "%s", f->choices[c]);
            }
            assert_int_equal(rf_fem_option_parse(&changed.fem, f, text, NULL), RF_OK);
            char *id = identity_of(&changed);
            if (!strcmp(id, base))
                fail_msg("identity does not change with %s = %s", f->name, text);
            free(id);
        }
    }
    free(base);
}

/* Each row is a key of a study's impact block that sets its option, seen in the identity. */
static void test_study_key_per_option(void **state)
{
    (void)state;
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *f = &rf_fem_option_fields[k];
        char value[64], text[1024], want[128];
        other_text(f, value, sizeof value);
        snprintf(text, sizeof text,
                 "name: t\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact:\n    solver: fem\n"
                 "    slope_material: von_mises\n    slope_yield: 2e8\n    %s: %s\n", f->name, value);
        rf_study s;
        rf_error err = {0};
        if (rf_study_load_buffer("options.yaml", text, strlen(text), &s, &err) != RF_OK)
            fail_msg("%s: %s", f->name, err.msg);
        rf_impact_model_spec spec;
        plastic_spec(&spec);
        assert_int_equal(rf_fem_option_parse(&spec.fem, f, value, NULL), RF_OK);
        char *id = identity_of(&spec);
        const char *fem = strstr(id, " fem:"), *end = strstr(id, " base:");
        assert_non_null(fem), assert_non_null(end);
        snprintf(want, sizeof want, "%.*s", (int)(strstr(fem, " refinement_axi") - fem), fem);
        if (!strstr(s.model.identity, want))
            fail_msg("%s: '%s' not in %s", f->name, want, s.model.identity);
        free(id);
        rf_study_free(&s);
        /* and a bad value is refused at its line, naming the key */
        bad_text(f, value, sizeof value);
        snprintf(text, sizeof text,
                 "name: t\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact:\n    %s: %s\n", f->name,
                 value);
        assert_int_not_equal(rf_study_load_buffer("bad.yaml", text, strlen(text), &s, &err), RF_OK);
        snprintf(want, sizeof want, "bad.yaml:6: model.impact.%s", f->name);
        if (!strstr(err.msg, want))
            fail_msg("'%s' not in '%s'", want, err.msg);
    }
}

static void read_all(const char *cmd, char *buf, size_t size, int *status)
{
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t len = fread(buf, 1, size - 1, p);
    buf[len] = '\0';
    *status = pclose(p);
}

/* Each row is an option of `rockfuzz impact` (the name with '-'), listed by
 * --help with its default, whose bad value is refused naming the option. */
static void test_cli_option_per_option(void **state)
{
    (void)state;
    static char help[65536], out[4096];
    int status;
    read_all(ROCKFUZZ_CLI " impact --help", help, sizeof help, &status);
    assert_int_equal(status, 0);
    rf_fem_options o;
    rf_fem_options_default(&o);
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *f = &rf_fem_option_fields[k];
        char opt[80], def[80], bad[64], cmd[256];
        int n = snprintf(opt, sizeof opt, "\n  --%s %s ", f->name, f->value_name);
        for (int q = 5; q < n && opt[q] != ' '; q++)
            opt[q] = opt[q] == '_' ? '-' : opt[q];
        const char *at = strstr(help, opt), *next = at ? strstr(at + 1, "\n  --") : NULL;
        if (!at)
            fail_msg("--help lacks '%s'", opt + 3);
        rf_fem_option_format(&o, f, def + 64, 16);
        snprintf(def, 64, "(default %s)", def + 64);
        char para[2048]; /* the option's text with its line breaks and indents as single spaces */
        size_t m = 0;
        for (const char *c = at + 1; *c && c != next && m + 1 < sizeof para; c++)
            if (!(*c == ' ' || *c == '\n') || (m > 0 && para[m - 1] != ' '))
                para[m++] = *c == '\n' ? ' ' : *c;
        para[m] = '\0';
        if (!strstr(para, def))
            fail_msg("--help: %s without '%s': %s", opt + 3, def, para);
        bad_text(f, bad, sizeof bad);
        snprintf(cmd, sizeof cmd, ROCKFUZZ_CLI " impact %.*s '%s' 2>&1", (int)strcspn(opt + 3, " "), opt + 3, bad);
        read_all(cmd, out, sizeof out, &status);
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 2 || !strstr(out, f->name))
            fail_msg("'%s': status %d, '%s'", cmd, status, out);
    }
}

/* The internal numerics are no option: no row, no CLI option, and no file of
 * the CLI, the study or the model includes their header. */
static void test_tuning_unreachable(void **state)
{
    (void)state;
    const char *internal[] = {"dt_safety", "grading", "surface_mass_3d", "sphere_contact_3d", "kernel",
                              "surface_mass_kappa", "max_elements", "core_factor", "contact_single_pivot"};
    for (size_t k = 0; k < sizeof internal / sizeof *internal; k++)
        assert_null(rf_fem_option_find(internal[k]));
    static char out[4096];
    int status;
    read_all(ROCKFUZZ_CLI " impact --dt-safety 0.5 2>&1", out, sizeof out, &status);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 2 && strstr(out, "unknown option '--dt-safety'"));
    const char *dirs[] = {"cli", "study", "model"};
    int files = 0;
    for (size_t d = 0; d < 3; d++) {
        char path[512];
        snprintf(path, sizeof path, "%s/src/%s", ROCKFUZZ_SOURCE_DIR, dirs[d]);
        DIR *dir = opendir(path);
        assert_non_null(dir);
        for (struct dirent *e; (e = readdir(dir));) {
            if (e->d_name[0] == '.')
                continue;
            char file[800], line[1024];
            snprintf(file, sizeof file, "%s/%s", path, e->d_name);
            FILE *fp = fopen(file, "r");
            assert_non_null(fp);
            while (fgets(line, sizeof line, fp))
                if (strstr(line, "#include") && strstr(line, "fem_tuning.h"))
                    fail_msg("%s includes the internal fem_tuning.h", file);
            fclose(fp);
            files++;
        }
        closedir(dir);
    }
    assert_true(files > 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_parse_and_refuse),
        cmocka_unit_test(test_identity_covers_every_option),
        cmocka_unit_test(test_study_key_per_option),
        cmocka_unit_test(test_cli_option_per_option),
        cmocka_unit_test(test_tuning_unreachable),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
