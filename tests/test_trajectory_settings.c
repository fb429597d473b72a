/* test_trajectory_settings.c - the run settings that are not bindable
 * numbers are rows of rf_traj_settings (src/trajectory/traj_fields.c): counts
 * with their exact range (samples, seed, record, stop.max_steps), names from
 * a list (sampling, bounce.law, bounce.impact.solver), numbers
 * (bounce.impact.tolerance, friction, refinement, max_incidence), a pair
 * (bounce.impact.speeds) and a path (bounce.impact.cache).  For every row (so
 * a new row is covered without a new test line): its probe value is stored
 * as given, its default when left out (and the members by name against the
 * documented defaults, the table's offsets checked independently); a value
 * just outside its range, a name not in its list, a pair out of order are
 * refused at load with file:line, key and value (the messages as they were
 * before the rows, and the solver and friction checked at load, no longer
 * when the impact table is built); the model identity changes with each.
 * The key table of docs/trajectories.md is checked in
 * test_trajectory_fields.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"
#include "rockfuzz/trajectory.h"

static char *identity(const rf_traj_spec *s)
{
    rf_model m;
    rf_error err;
    if (rf_traj_model_create(s, 0, NULL, NULL, &m, &err) != RF_OK)
        fail_msg("%s", err.msg);
    char *id = strdup(m.identity);
    rf_model_free(&m);
    return id;
}

/* The base file with the setting `key` given as `value` (NULL: left out;
 * samples is then left out too); returns the setting's line. */
static int with_setting(char *y, size_t size, const char *key, const char *value)
{
    const char *dot = strrchr(key, '.'), *leaf = dot ? dot + 1 : key;
    int top = !dot, stop = !strncmp(key, "stop.", 5), impact = !strncmp(key, "bounce.impact.", 14);
    char bounce[200] = "", stopin[200] = "", extra[200] = "";
    if (value && impact)
        snprintf(bounce, sizeof bounce, "impact: {%s: %s}, ", leaf, value);
    else if (value && !top && !stop)
        snprintf(bounce, sizeof bounce, "%s: %s, ", leaf, value);
    if (value && stop)
        snprintf(stopin, sizeof stopin, "%s: %s, ", leaf, value);
    int samples = !strcmp(key, "samples");
    if (value && top)
        snprintf(extra, sizeof extra, "%s: %s\n", key, value);
    snprintf(y, size,
             "name: t\n"                                                      /* 1 */
             "gravity: 9.81\n"                                                /* 2 */
             "profile: {points: [[0, 20], [10, 0], [100, 0]], material: m}\n" /* 3 */
             "materials: {m: {R_n: 0.4, R_t: 0.7, friction_angle: 30}}\n"     /* 4 */
             "block: {shape: sphere, radius: 0.5, density: 2600}\n"           /* 5: every law takes a sphere */
             "release: {x: 0.5, y: 21}\n"                                     /* 6 */
             "bounce: {%sscale_speed: 9.144}\n"                               /* 7 */
             "stop: {%sv_stop: 0.1}\n"                                        /* 8 */
             "collectors: [{name: c, x: 60}]\n"                               /* 9 */
             "%s%s",                                                          /* 10: samples, 11: the setting */
             bounce, stopin, samples ? "" : "samples: 4\n", extra);
    return top ? (samples ? 10 : 11) : stop ? 8 : 7;
}

static rf_status load_setting(const char *file, const char *key, const char *value, rf_traj_spec *s, rf_error *err,
                              int *line)
{
    char y[4096];
    int l = with_setting(y, sizeof y, key, value);
    if (line)
        *line = l;
    return rf_traj_load_buffer(file, y, strlen(y), s, err);
}

static long long count_at(const rf_traj_setting *g, const rf_traj_spec *s)
{
    const char *at = (const char *)s + g->offset;
    uint64_t u;
    size_t z;
    if (g->size == sizeof u)
        return memcpy(&u, at, sizeof u), (long long)u;
    return memcpy(&z, at, sizeof z), (long long)z;
}

/* The value a setting's text stands for, compared with what the reader stored. */
static void assert_stored(const rf_traj_setting *g, const rf_traj_spec *s, const char *text)
{
    const char *at = (const char *)s + g->offset, *name;
    double x[2];
    int idx = -1;
    switch (g->kind) {
    case RF_TRAJ_SETTING_COUNT:
        if (count_at(g, s) != strtoll(text, NULL, 10))
            fail_msg("%s: stored %lld, given %s", g->key, count_at(g, s), text);
        return;
    case RF_TRAJ_SETTING_NAME:
        for (size_t k = 0; (name = g->names(k)); k++)
            if (!strcmp(name, text))
                idx = (int)k;
        assert_true(idx >= 0);
        assert_memory_equal(at, &idx, sizeof idx);
        return;
    case RF_TRAJ_SETTING_WORD: assert_string_equal(at, text); return;
    case RF_TRAJ_SETTING_NUMBER:
        x[0] = strtod(text, NULL) * (g->degrees ? RF_PI / 180 : 1);
        assert_memory_equal(at, x, sizeof(double));
        return;
    case RF_TRAJ_SETTING_PAIR:
        assert_int_equal(sscanf(text, "[%lf, %lf]", &x[0], &x[1]), 2);
        assert_memory_equal(at, x, sizeof x);
        return;
    case RF_TRAJ_SETTING_PATH: assert_string_equal(*(char *const *)at, text); return;
    }
}

/* Every setting: its probe stored as given, and left out its default; the
 * members by name against the documented defaults (docs/trajectories.md). */
static void test_every_setting_parsed_with_default(void **state)
{
    (void)state;
    assert_true(rf_traj_n_settings >= 13);
    for (size_t k = 0; k < rf_traj_n_settings; k++) {
        const rf_traj_setting *g = &rf_traj_settings[k];
        rf_traj_spec s;
        rf_error err;
        if (load_setting("t.yaml", g->key, g->probe, &s, &err, NULL) != RF_OK)
            fail_msg("%s: %s = %s: %s", g->key, g->key, g->probe, err.msg);
        assert_stored(g, &s, g->probe);
        rf_traj_spec_free(&s);
        if (g->kind == RF_TRAJ_SETTING_PATH) { /* relative to the trajectory file */
            assert_int_equal(load_setting("dir/t.yaml", g->key, "c.txt", &s, &err, NULL), RF_OK);
            assert_stored(g, &s, "dir/c.txt");
            rf_traj_spec_free(&s);
            assert_int_equal(load_setting("dir/t.yaml", g->key, "/abs/c.txt", &s, &err, NULL), RF_OK);
            assert_stored(g, &s, "/abs/c.txt");
            rf_traj_spec_free(&s);
        }
        assert_int_equal(load_setting("t.yaml", g->key, NULL, &s, &err, NULL), RF_OK);
        if (g->kind == RF_TRAJ_SETTING_COUNT && strcmp(g->key, "record")) {
            char def[32];
            snprintf(def, sizeof def, "%lld", g->count_def);
            assert_stored(g, &s, def);
        } else if (g->kind == RF_TRAJ_SETTING_NAME || g->kind == RF_TRAJ_SETTING_WORD) {
            assert_stored(g, &s, g->def_name);
        }
        rf_traj_spec_free(&s);
    }
    rf_traj_spec s; /* the defaults by member, every setting left out */
    rf_error err;
    char y[4096];
    with_setting(y, sizeof y, "samples", NULL);
    assert_int_equal(rf_traj_load_buffer("t.yaml", y, strlen(y), &s, &err), RF_OK);
    assert_true(s.samples == 1 && s.seed == 1 && s.record == 1 && s.max_steps == 10000 && !s.lhs);
    assert_true(s.law == RF_BOUNCE_CONSTANT && !strcmp(s.impact_solver, "rigid") && s.impact_tolerance == 0.01);
    assert_true(isnan(s.impact_friction) && s.impact_refinement == 0 && !s.impact_cache);
    assert_true(s.impact_speed_min == 0.25 && s.impact_speed_max == 40 && s.impact_max_incidence == 80 * (RF_PI / 180));
    rf_traj_spec_free(&s);
    assert_int_equal(load_setting("t.yaml", "record", NULL, &s, &err, NULL), RF_OK);
    assert_true(s.samples == 4 && s.record == 4); /* min(samples, 200) */
    rf_traj_spec_free(&s);
    assert_int_equal(load_setting("t.yaml", "samples", "1000", &s, &err, NULL), RF_OK);
    assert_true(s.record == 200);
    rf_traj_spec_free(&s);
    /* The probes by member (the table's offsets checked independently). */
    const struct { const char *key, *value; } by[] = {
        {"sampling", "lhs"}, {"bounce.law", "velocity_scaled"}, {"stop.max_steps", "50"}, {"seed", "77"},
        {"bounce.impact.speeds", "[1, 15]"}, {"bounce.impact.max_incidence", "60"}, {"bounce.impact.solver", "hunter"},
        {"bounce.impact.friction", "0.6"}, {"bounce.impact.tolerance", "0.05"}, {"bounce.impact.refinement", "3"}};
    rf_traj_spec p[10];
    for (int i = 0; i < 10; i++)
        assert_int_equal(load_setting("t.yaml", by[i].key, by[i].value, &p[i], &err, NULL), RF_OK);
    assert_true(p[0].lhs == 1 && p[1].law == RF_BOUNCE_VELOCITY_SCALED && p[2].max_steps == 50 && p[3].seed == 77);
    assert_true(p[4].impact_speed_min == 1 && p[4].impact_speed_max == 15);
    assert_true(p[5].impact_max_incidence == 60 * (RF_PI / 180) && !strcmp(p[6].impact_solver, "hunter"));
    assert_true(p[7].impact_friction == 0.6 && p[8].impact_tolerance == 0.05 && p[9].impact_refinement == 3);
    for (int i = 0; i < 10; i++)
        rf_traj_spec_free(&p[i]);
}

static void refused(const rf_traj_setting *g, const char *value)
{
    rf_traj_spec s;
    rf_error err;
    int line;
    if (load_setting("t.yaml", g->key, value, &s, &err, &line) == RF_OK)
        fail_msg("%s = %s accepted", g->key, value);
    char want[400], rule[300];
    rf_traj_setting_rule(g, rule, sizeof rule);
    snprintf(want, sizeof want, "t.yaml:%d: %s = %s: %s", line, g->key, value, rule);
    if (g->kind == RF_TRAJ_SETTING_PATH)
        snprintf(want, sizeof want, "t.yaml:%d: %s = %s: expected a string", line, g->key, value);
    if (strncmp(err.msg, want, strlen(want)))
        fail_msg("'%s' does not open with '%s'", err.msg, want);
}

static void accepted(const rf_traj_setting *g, const char *value)
{
    rf_traj_spec s;
    rf_error err;
    if (load_setting("t.yaml", g->key, value, &s, &err, NULL) != RF_OK)
        fail_msg("%s = %s refused: %s", g->key, value, err.msg);
    rf_traj_spec_free(&s);
}

/* Every setting checked at load, located: a count just outside its exact
 * range (the ends inside), a name not in its list, a number past an end, a
 * pair out of order, a path that is no string. */
static void test_every_setting_validated(void **state)
{
    (void)state;
    char v[64];
    for (size_t k = 0; k < rf_traj_n_settings; k++) {
        const rf_traj_setting *g = &rf_traj_settings[k];
        switch (g->kind) {
        case RF_TRAJ_SETTING_COUNT:
            snprintf(v, sizeof v, "%lld", g->count_min - 1), refused(g, v);
            snprintf(v, sizeof v, "%lld", g->count_max + 1), refused(g, v);
            snprintf(v, sizeof v, "%lld", g->count_min), accepted(g, v);
            snprintf(v, sizeof v, "%lld", g->count_max), accepted(g, v);
            break;
        case RF_TRAJ_SETTING_NAME:
        case RF_TRAJ_SETTING_WORD:
            refused(g, "nosuch");
            for (size_t i = 0; g->names(i); i++)
                accepted(g, g->names(i));
            break;
        case RF_TRAJ_SETTING_NUMBER:
            snprintf(v, sizeof v, "%g", g->lo_open ? g->lo : g->lo - 1), refused(g, v);
            if (!g->lo_open)
                snprintf(v, sizeof v, "%g", g->lo), accepted(g, v);
            if (!isinf(g->hi)) { /* (a file cannot write inf: the reader refuses it for every number) */
                snprintf(v, sizeof v, "%g", g->hi_open ? g->hi : g->hi + 1), refused(g, v);
                if (!g->hi_open)
                    snprintf(v, sizeof v, "%g", g->hi), accepted(g, v);
            }
            break;
        case RF_TRAJ_SETTING_PAIR:
            refused(g, "[2, 1]");
            snprintf(v, sizeof v, "[%g, 1]", g->lo), refused(g, v);
            break;
        case RF_TRAJ_SETTING_PATH: refused(g, "[a]"); break;
        }
    }
    /* The messages as they were (before the rows) and the late checks now at load. */
    const char *const msg[][3] = {
        {"samples", "0", "t.yaml:10: samples = 0: must lie in [1, 100000000]"},
        {"seed", "9007199254740993", "t.yaml:11: seed = 9007199254740993: must lie in [0, 9007199254740992]"},
        {"sampling", "lh", "t.yaml:11: sampling = lh: expected random or lhs (Latin hypercube)"},
        {"stop.max_steps", "0", "t.yaml:8: stop.max_steps = 0: must lie in [1, 100000000]"},
        {"bounce.law", "nope", "t.yaml:7: bounce.law = nope: expected constant, velocity_scaled, rigid_sphere or "
                               "impact_model"},
        {"bounce.impact.tolerance", "1", "t.yaml:7: bounce.impact.tolerance = 1: must lie in (0, 1)"},
        {"bounce.impact.max_incidence", "81", "t.yaml:7: bounce.impact.max_incidence = 81: must lie in (0, 80] "
                                              "degrees"},
        {"bounce.impact.speeds", "[2, 1]", "t.yaml:7: bounce.impact.speeds = [2, 1]: expected [lo, hi] normal "
                                           "speeds [m/s] with 0 < lo < hi"},
        {"bounce.impact.refinement", "-1", "t.yaml:7: bounce.impact.refinement = -1: must be >= 0 (0: the FE "
                                           "solver's default)"},
        {"bounce.impact.solver", "nosuch", "t.yaml:7: bounce.impact.solver = nosuch: expected fem, hertz, hunter, "
                                           "rigid or mdr"},
        {"bounce.impact.friction", "-1", "t.yaml:7: bounce.impact.friction = -1: must be >= 0"},
    };
    for (size_t i = 0; i < sizeof msg / sizeof msg[0]; i++) {
        rf_traj_spec s;
        rf_error err;
        assert_int_not_equal(load_setting("t.yaml", msg[i][0], msg[i][1], &s, &err, NULL), RF_OK);
        assert_string_equal(err.msg, msg[i][2]);
    }
    /* An unknown key under bounce.impact lists every setting there. */
    rf_traj_spec s;
    rf_error err;
    assert_int_not_equal(load_setting("t.yaml", "bounce.impact.foo", "1", &s, &err, NULL), RF_OK);
    assert_non_null(strstr(err.msg, "t.yaml:7: bounce.impact.foo: unknown key"));
    for (size_t k = 0; k < rf_traj_n_settings; k++)
        if (!strncmp(rf_traj_settings[k].key, "bounce.impact.", 14))
            assert_non_null(strstr(err.msg, rf_traj_settings[k].key + 14));
}

/* The identity changes with every setting (the file's text hash made equal:
 * only the setting differs). */
static void test_identity_covers_every_setting(void **state)
{
    (void)state;
    for (size_t k = 0; k < rf_traj_n_settings; k++) {
        const rf_traj_setting *g = &rf_traj_settings[k];
        rf_traj_spec s, p;
        rf_error err;
        assert_int_equal(load_setting("t.yaml", g->key, NULL, &s, &err, NULL), RF_OK);
        assert_int_equal(load_setting("t.yaml", g->key, g->probe, &p, &err, NULL), RF_OK);
        p.text_hash = s.text_hash;
        char *id0 = identity(&s), *id1 = identity(&p);
        if (!strcmp(id0, id1))
            fail_msg("%s = %s does not change the identity %s", g->key, g->probe, id0);
        free(id0), free(id1);
        rf_traj_spec_free(&s), rf_traj_spec_free(&p);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_setting_parsed_with_default),
        cmocka_unit_test(test_every_setting_validated),
        cmocka_unit_test(test_identity_covers_every_setting),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
