/* test_traj_presets.c - the material presets of trajectory files (presets.h,
 * traj_presets.c, traj_presets_yaml.c; docs/presets.md): the shorthand and
 * the override forms load to the documented values (angles given in degrees
 * stored in radians), an override is checked like a row (file:line, field,
 * value), an unknown name is refused with its line and the list of names,
 * every preset's ground passes the impact model's check at its nominal values
 * and at both ends of every fuzzy support, and every value lies in its fuzzy
 * support, itself inside the row's rule; the steepest slope a layer preset
 * stands on (rf_traj_preset_steepest_slope) is where the 3D FE's own
 * stability check (f3_gravity_stability) flips from accepting to refusing
 * the preset's ground, and equals the closed form solved by hand. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "rockfuzz/presets.h"
#include "rockfuzz/trajectory.h"
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"
#include "rockfuzz/impact.h"
#include "fem/fem3d_gravity.h"

#define DEG (3.14159265358979323846 / 180)

static const char *head = "profile: {points: [[0, 10], [20, 0]], material: scree}\n"
                          "block: {shape: sphere, radius: 0.5, density: 2600}\n"
                          "release: {x: 1, y: 11}\n";

/* Load head + the materials text; RF_OK or the error in *err. */
static rf_status load(const char *materials, rf_traj_spec *s, rf_error *err)
{
    char buf[2048];
    snprintf(buf, sizeof buf, "%s%s", head, materials);
    return rf_traj_load_buffer("p.yaml", buf, strlen(buf), s, err);
}

static const rf_traj_material *material(const rf_traj_spec *s, const char *name)
{
    for (size_t k = 0; k < s->n_materials; k++)
        if (!strcmp(s->materials[k].name, name))
            return &s->materials[k];
    fail_msg("no material %s", name);
    return NULL;
}

/* The values of docs/presets.md, written out here (not read from the table). */
static void test_shorthand(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    if (load("materials: {scree: talus, rock: bedrock}\n", &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    const rf_traj_material *m = material(&s, "scree");
    assert_true(m->R_n == 0.38 && m->R_t == 0.80 && m->rolling_resistance == 0.55);
    assert_true(fabs(m->friction_angle - 35 * DEG) < 1e-15 && fabs(m->roughness - 6 * DEG) < 1e-15);
    assert_int_equal(m->impact.given, 1);
    assert_string_equal(m->impact.solver, "fem");
    assert_string_equal(m->impact.boulder_material, "rigid");
    assert_string_equal(m->impact.layer_material, "drucker_prager");
    double v;
    assert_true(rf_traj_spec_get(&s, "materials.scree.impact.layer_E", &v) && v == 100e6);
    assert_true(rf_traj_spec_get(&s, "materials.scree.impact.layer_thickness", &v) && v == 1.0);
    assert_true(rf_traj_spec_get(&s, "materials.scree.impact.layer_friction_angle", &v) && v == 40); /* as given */
    assert_true(rf_traj_spec_get(&s, "materials.scree.impact.layer_cap_pressure", &v) && v == 20e3);
    assert_true(rf_traj_spec_get(&s, "materials.scree.friction_angle", &v) && fabs(v - 35) < 1e-12);
    const rf_traj_material *r = material(&s, "rock");
    assert_true(r->R_n == 0.53 && r->R_t == 0.85);
    assert_string_equal(r->impact.slope_material, "von_mises");
    assert_true(rf_traj_spec_get(&s, "materials.rock.impact.slope_yield", &v) && v == 150e6);
    assert_true(rf_traj_spec_get(&s, "materials.rock.impact.layer_thickness", &v) && v == 0); /* no layer */
    rf_traj_spec_free(&s);
}

/* The preset first, then the keys given (rows and the impact mapping). */
static void test_override(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    if (load("materials:\n  scree: {preset: colluvium, R_n: 0.3, friction_angle: 28,\n"
             "          impact: {layer_E: 5e7, layer_thickness: 0.4}}\n", &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    const rf_traj_material *m = material(&s, "scree");
    assert_true(m->R_n == 0.3 && fabs(m->friction_angle - 28 * DEG) < 1e-15);
    assert_true(m->R_t == 0.80 && m->rolling_resistance == 0.40); /* kept from the preset */
    double v;
    assert_true(rf_traj_spec_get(&s, "materials.scree.impact.layer_E", &v) && v == 5e7);
    assert_true(rf_traj_spec_get(&s, "materials.scree.impact.layer_thickness", &v) && v == 0.4);
    assert_true(rf_traj_spec_get(&s, "materials.scree.impact.layer_cap_pressure", &v) && v == 200e3);
    assert_string_equal(m->impact.layer_material, "drucker_prager");
    rf_traj_spec_free(&s);
    /* a random override, as on any row */
    if (load("materials: {scree: {preset: talus, R_n: {uniform: [0.3, 0.4]}}}\n", &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s.n_random, 1);
    assert_string_equal(s.random[0].path, "materials.scree.R_n");
    rf_traj_spec_free(&s);
}

static void expect_error(const char *materials, const char *a, const char *b, const char *c)
{
    rf_traj_spec s;
    rf_error err;
    if (load(materials, &s, &err) == RF_OK)
        fail_msg("accepted: %s", materials);
    print_message("refused: %s\n", err.msg);
    assert_non_null(strstr(err.msg, a));
    assert_non_null(strstr(err.msg, b));
    assert_non_null(strstr(err.msg, c));
}

/* An override is checked like a row: file:line, the field's path, the value. */
static void test_override_checked(void **state)
{
    (void)state;
    expect_error("materials:\n  scree: {preset: talus,\n          R_n: 1.5}\n", "p.yaml:6", "materials.scree.R_n",
                 "1.5");
    expect_error("materials: {scree: {preset: talus, friction_angle: 95}}\n", "p.yaml:4",
                 "materials.scree.friction_angle", "95");
    expect_error("materials: {scree: {preset: talus, impact: {layer_E: -5}}}\n", "p.yaml:4",
                 "materials.scree.impact.layer_E", "-5");
    expect_error("materials: {scree: {preset: talus, R_m: 0.3}}\n", "p.yaml:4", "materials.scree.R_m",
                 "unknown key");
    /* a ground made inadmissible by an override: the impact model's own check */
    expect_error("materials:\n  scree: {preset: talus, impact: {layer_dilatancy_angle: 50}}\n", "p.yaml:5",
                 "materials.scree", "dilatancy");
}

static void test_unknown_name(void **state)
{
    (void)state;
    expect_error("materials:\n  scree: granite\n", "p.yaml:5", "materials.scree", "bedrock, talus, colluvium, loose_soil");
    expect_error("materials:\n  rock: bedrock\n  scree: {R_t: 0.5,\n    preset: Talus}\n", "p.yaml:7",
                 "materials.scree.preset", "unknown preset");
    expect_error("materials: {scree: [talus]}\n", "p.yaml:4", "materials.scree", "");
}

static void set_row(const rf_traj_preset_value *v, double given, rf_traj_material *m)
{
    const rf_traj_field *f = rf_traj_preset_row(v);
    *(double *)((char *)m + f->offset) = f->degrees ? given * DEG : given;
}

/* Every preset's ground passes the impact model's check at its nominal values
 * and with each value at either end of its fuzzy support. */
static void test_ground_check(void **state)
{
    (void)state;
    const rf_traj_preset *p;
    size_t n = 0;
    for (size_t k = 0; (p = rf_traj_preset_at(k)); k++, n++) {
        rf_traj_material m;
        memset(&m, 0, sizeof m);
        rf_traj_spec s;
        memset(&s, 0, sizeof s);
        rf_error err;
        /* the impact model's defaults first, as a file's material gets them */
        char yaml[64];
        snprintf(yaml, sizeof yaml, "materials: {scree: %s}\n", p->name);
        if (load(yaml, &s, &err) != RF_OK)
            fail_msg("%s: %s", p->name, err.msg);
        m = s.materials[0];
        if (traj_impact_ground_check(&m.impact, "rigid", &err) != RF_OK)
            fail_msg("%s: %s", p->name, err.msg);
        for (size_t i = 0; i < p->n_values; i++)
            for (int end = 0; end < 2; end++) {
                rf_traj_material e = m;
                set_row(&p->values[i], end ? p->values[i].hi : p->values[i].lo, &e);
                if (traj_impact_ground_check(&e.impact, "rigid", &err) != RF_OK)
                    fail_msg("%s, %s at %g: %s", p->name, p->values[i].key,
                             end ? p->values[i].hi : p->values[i].lo, err.msg);
            }
        rf_traj_spec_free(&s);
    }
    assert_true(n >= 4);
}

/* Each value: a row of the material table, inside its fuzzy support, the
 * support inside the row's rule, a source named; the classical coefficients
 * of every law present. */
static void test_values_in_support(void **state)
{
    (void)state;
    const char *classic[] = {"R_n", "R_t", "friction_angle", "rolling_resistance", "roughness"};
    const rf_traj_preset *p;
    for (size_t k = 0; (p = rf_traj_preset_at(k)); k++) {
        assert_ptr_equal(rf_traj_preset_named(p->name), p);
        for (size_t i = 0; i < p->n_values; i++) {
            const rf_traj_preset_value *v = &p->values[i];
            const rf_traj_field *f = rf_traj_preset_row(v);
            if (!f)
                fail_msg("%s: %s is no material row", p->name, v->key);
            if (!(v->lo <= v->value && v->value <= v->hi && v->lo < v->hi))
                fail_msg("%s: %s = %g outside [%g, %g]", p->name, v->key, v->value, v->lo, v->hi);
            const char *why = rf_traj_field_rule(f, v->lo);
            if (!why)
                why = rf_traj_field_rule(f, v->hi);
            if (why)
                fail_msg("%s: %s support [%g, %g]: %s", p->name, v->key, v->lo, v->hi, why);
            const char *tags[] = {"RF3D", "ROCF", "STONE", "MAT", "S5", "JUDG"}; /* traj_presets.c, docs/presets.md */
            size_t t = 0;
            while (t < 6 && strncmp(v->source, tags[t], strlen(tags[t])))
                t++;
            if (t == 6)
                fail_msg("%s: %s: the source '%s' names none of the sources", p->name, v->key, v->source);
            for (size_t j = 0; j < i; j++)
                assert_string_not_equal(p->values[j].key, v->key);
        }
        for (size_t c = 0; c < 5; c++) {
            size_t i = 0;
            while (i < p->n_values && strcmp(p->values[i].key, classic[c]))
                i++;
            if (i == p->n_values)
                fail_msg("%s has no %s", p->name, classic[c]);
        }
    }
    const char *need[] = {"bedrock", "talus", "colluvium", "loose_soil"};
    char names[200];
    rf_traj_preset_names(names, sizeof names);
    assert_string_equal(names, "bedrock, talus, colluvium, loose_soil");
    for (size_t c = 0; c < 4; c++)
        assert_non_null(rf_traj_preset_named(need[c]));
    assert_null(rf_traj_preset_named("granite"));
    assert_null(rf_traj_preset_named(NULL));
}

/* The soil presets' R_n falls from the stiffest ground to the softest, as the
 * practitioners' tables order bedrock, talus, compact soil, fine soil. */
static void test_practitioner_order(void **state)
{
    (void)state;
    const char *order[] = {"bedrock", "talus", "colluvium", "loose_soil"};
    double last = 2;
    for (size_t c = 0; c < 4; c++) {
        const rf_traj_preset *p = rf_traj_preset_named(order[c]);
        assert_string_equal(p->values[0].key, "R_n");
        assert_true(p->values[0].value < last);
        last = p->values[0].value;
    }
}

/* The preset's ground as the impact input (its impact.* values by name, its words). */
static void preset_ground(const rf_traj_preset *p, rf_impact_input *in)
{
    rf_error e;
    rf_impact_input_default(in);
    for (size_t i = 0; i < p->n_values; i++)
        if (!strncmp(p->values[i].key, "impact.", 7)) {
            const rf_impact_field *f = rf_impact_field_find(p->values[i].key + 7);
            assert_non_null(f);
            rf_impact_field_store(in, f, p->values[i].value);
        }
    if (p->layer_material[0])
        assert_int_equal(rf_material_model_parse(p->layer_material, &in->layer_material, &e), RF_OK);
}

/* Where the FE's check flips, and the hand solutions of c / (rho g d sin t) +
 * tan phi / tan t = 1 (talus 44.715, loose soil 33.086, colluvium 64.267 deg). */
static void test_steepest_slope(void **state)
{
    (void)state;
    const char *names[] = {"talus", "loose_soil", "colluvium", "bedrock"};
    const double hand[] = {44.715, 33.086, 64.267, 90};
    for (int k = 0; k < 4; k++) {
        const rf_traj_preset *p = rf_traj_preset_named(names[k]);
        const double t = rf_traj_preset_steepest_slope(p, 9.81);
        assert_true(fabs(t - hand[k]) < 0.002);
        assert_true(rf_traj_preset_steepest_slope(p, 0) == 90);
        if (k == 3)
            continue; /* no layer */
        rf_impact_input in;
        preset_ground(p, &in);
        double fs;
        rf_error e;
        in.slope_angle = (t - 0.05) * DEG;
        assert_int_equal(f3_gravity_stability(&in, 9.81, 0, &fs, &e), RF_OK);
        assert_true(fs >= 1 && fs < 1.01);
        in.slope_angle = (t + 0.05) * DEG;
        assert_int_equal(f3_gravity_stability(&in, 9.81, 0, &fs, &e), RF_EINVAL);
        assert_true(fs < 1 && fs > 0.99);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shorthand),        cmocka_unit_test(test_override),
        cmocka_unit_test(test_override_checked), cmocka_unit_test(test_unknown_name),
        cmocka_unit_test(test_ground_check),     cmocka_unit_test(test_values_in_support),
        cmocka_unit_test(test_practitioner_order), cmocka_unit_test(test_steepest_slope),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
