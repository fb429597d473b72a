/* test_trajectory_fields.c - the tables of the trajectory inputs
 * (rf_traj_field_tables, src/trajectory/traj_fields.c) drive every place that
 * reads an input.  For every row of every table (so a new row is covered
 * without a new test line): the file reader stores the value given (an angle
 * in radians) and the default when it is left out; the validation refuses a
 * value outside the row's check with file:line, path and value; a study may
 * bind it exactly when the row says so; the model identity changes with it;
 * the key table in docs/trajectories.md is the one generated from the rows.
 * The settings that are no such numbers (rf_traj_settings) are checked the
 * same way in tests/test_trajectory_settings.c; their rows are in the key
 * table checked here.
 * And a fuzzy parameter bound to an angle (given in degrees) gives the same
 * bits as the file with that value. */
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

/* The base file's values, as given, by path (one line per section). */
typedef struct {
    const char *path;
    double v;
} kv;

static const kv base_values[] = {
    {"gravity", 9.81}, {"block.mass", 1000}, {"block.radius", 0.5}, {"block.density", 2600},
    {"release.x", 0.5}, {"release.y", 21}, {"release.vx", 1}, {"release.vy", 0}, {"release.speed", 2},
    {"release.angle", 10}, {"release.omega", 0}, {"bounce.scale_speed", 9.144}, {"bounce.contact_speed", 0.1},
    {"stop.v_stop", 0.1}, {"materials.m.R_n", 0.4}, {"materials.m.R_t", 0.7}, {"materials.m.friction_angle", 30},
    {"materials.m.rolling_resistance", 0}, {"materials.m.roughness", 2}, {"collectors.c.x", 60},
    {"collectors.c.capacity", 5e5}, {"collectors.c.height", 0},
    /* a rigid block's rows (written only when the build is a box) */
    {"block.volume", 0.9}, {"block.axis_ratio_b", 1}, {"block.axis_ratio_c", 1}, {"block.time_step", 1e-3},
    {"block.max_time", 60}, {"block.rest_time", 0.5},
};
#define N_BASE (sizeof base_values / sizeof base_values[0])

typedef struct {
    int sphere, by_speed;
    const char *set;     /* this path gets `value` ... */
    double value;
    const char *omit;    /* ... and this one is left out */
    int block;           /* a rigid block (shape: box) */
} build;

/* A row only a rigid block has. */
static int block_only(const char *path)
{
    double *at;
    rf_traj_spec s;
    memset(&s, 0, sizeof s);
    const rf_traj_field *f = rf_traj_field_at(&s, path, &at);
    return f && f->when == RF_TRAJ_WHEN_BLOCK;
}

/* ", key: value" for every base path under `section` (e.g. "block."). */
static void section(char *buf, size_t size, const char *sec, const build *b, const char *skip1, const char *skip2)
{
    size_t n = strlen(buf), ls = strlen(sec);
    int first = 1;
    for (size_t k = 0; k < N_BASE; k++) {
        const char *p = base_values[k].path;
        if (strncmp(p, sec, ls) || strchr(p + ls, '.') || (b->omit && !strcmp(p, b->omit)))
            continue;
        if ((skip1 && !strcmp(p + ls, skip1)) || (skip2 && !strcmp(p + ls, skip2)))
            continue;
        if (!b->block && block_only(p))
            continue;
        double v = b->set && !strcmp(p, b->set) ? b->value : base_values[k].v;
        n += (size_t)snprintf(buf + n, size - n, "%s%s: %.17g", first ? "" : ", ", p + ls, v);
        first = 0;
    }
}

/* Lines: 1 name, 2 gravity, 3 profile, 4 materials, 5 block, 6 release,
 * 7 bounce, 8 stop, 9 collectors, 10 samples. */
static void make_yaml(const build *b, char *y, size_t size)
{
    snprintf(y, size, "name: t\n");
    if (!(b->omit && !strcmp(b->omit, "gravity")))
        section(y, size, "", b, NULL, NULL); /* gravity (the only top-level row) */
    size_t n = strlen(y);
    snprintf(y + n, size - n, "\nprofile: {points: [[0, 20], [10, 0], [100, 0]], material: m}\nmaterials: {m: {");
    section(y, size, "materials.m.", b, NULL, NULL);
    n = strlen(y);
    if (b->set && !strncmp(b->set, "materials.m.impact.", 19)) /* a row of the material's impact model */
        n += (size_t)snprintf(y + n, size - n, ", impact: {solver: fem, %s: %.17g}", b->set + 19, b->value);
    snprintf(y + n, size - n, "}}\nblock: {shape: %s, ",
             b->block ? "box, edges: [1, 0.9, 0.8]" : b->sphere ? "sphere" : "point");
    section(y, size, "block.", b, b->sphere || b->block ? "mass" : "radius",
            b->block ? "radius" : b->sphere ? NULL : "density");
    n = strlen(y);
    snprintf(y + n, size - n, "}\nrelease: {");
    section(y, size, "release.", b, b->by_speed ? "vx" : "speed", b->by_speed ? "vy" : "angle");
    n = strlen(y);
    snprintf(y + n, size - n, "}\nbounce: {");
    section(y, size, "bounce.", b, NULL, NULL);
    n = strlen(y);
    snprintf(y + n, size - n, "}\nstop: {");
    section(y, size, "stop.", b, NULL, NULL);
    n = strlen(y);
    snprintf(y + n, size - n, "}\ncollectors: [{name: c, ");
    section(y, size, "collectors.c.", b, NULL, NULL);
    n = strlen(y);
    snprintf(y + n, size - n, "}]\nsamples: 4\n");
}

static int section_line(const char *path)
{
    const char *pre[] = {"materials.", "block.", "release.", "bounce.", "stop.", "collectors."};
    const int line[] = {4, 5, 6, 7, 8, 9};
    for (int k = 0; k < 6; k++)
        if (!strncmp(path, pre[k], strlen(pre[k])))
            return line[k];
    return 2;
}

/* The full path of a row in the base file ("materials.m.R_n"). */
static void row_path(const rf_traj_field_table *t, const rf_traj_field *f, char *buf, size_t size)
{
    if (t->owner == RF_TRAJ_OWNER_MATERIAL)
        snprintf(buf, size, "materials.m.%s", f->key);
    else if (t->owner == RF_TRAJ_OWNER_COLLECTOR)
        snprintf(buf, size, "collectors.c.%s", f->key);
    else
        snprintf(buf, size, "%s%s", t->prefix, f->key);
}

static build build_for(const rf_traj_field *f)
{
    build b = {f->when == RF_TRAJ_WHEN_SPHERE || f->when == RF_TRAJ_WHEN_RIGID,
               f->when == RF_TRAJ_WHEN_SPEED || f->when == RF_TRAJ_WHEN_PROFILE_SPEED, NULL, 0, NULL,
               f->when == RF_TRAJ_WHEN_BLOCK};
    return b;
}

/* A row only a terrain file uses: its checks are in tests/test_terrain_file.c
 * (the base file here is a profile). */
static int terrain_row(const rf_traj_field *f)
{
    return f->when == RF_TRAJ_WHEN_TERRAIN || f->when == RF_TRAJ_WHEN_TERRAIN_VXVY ||
           f->when == RF_TRAJ_WHEN_TERRAIN_SPEED;
}

static rf_status load(const build *b, rf_traj_spec *s, rf_error *err)
{
    char y[4096];
    make_yaml(b, y, sizeof y);
    return rf_traj_load_buffer("t.yaml", y, strlen(y), s, err);
}

static double stored(const rf_traj_field *f, double given) { return f->degrees ? given * (RF_PI / 180) : given; }

#define EACH_ROW(t, f)                                                  \
    for (size_t t##i = 0; t##i < rf_traj_n_field_tables; t##i++)       \
        for (const rf_traj_field_table *t = &rf_traj_field_tables[t##i]; t; t = NULL) \
            for (const rf_traj_field *f = t->rows; f < t->rows + t->n_rows; f++) \
                if (!terrain_row(f))

static void test_every_row_parsed_with_default(void **state)
{
    (void)state;
    size_t rows = 0;
    EACH_ROW(t, f) {
        char path[200];
        row_path(t, f, path, sizeof path);
        build b = build_for(f);
        b.set = path, b.value = f->probe;
        rf_traj_spec s;
        rf_error err;
        if (load(&b, &s, &err) != RF_OK)
            fail_msg("%s = %g: %s", path, f->probe, err.msg);
        double *p = rf_traj_spec_field(&s, path), given = NAN;
        assert_non_null(p);
        if (*p != stored(f, f->probe)) /* an angle in radians, converted once */
            fail_msg("%s: stored %.17g, want %.17g", path, *p, stored(f, f->probe));
        assert_true(rf_traj_spec_get(&s, path, &given) && fabs(given - f->probe) <= 1e-13 * fabs(f->probe));
        rf_traj_spec_free(&s);
        if (!isnan(f->def)) { /* left out: the row's default */
            b.set = NULL, b.omit = path;
            if (load(&b, &s, &err) != RF_OK)
                fail_msg("%s left out: %s", path, err.msg);
            if (*rf_traj_spec_field(&s, path) != stored(f, f->def))
                fail_msg("%s: default %.17g, want %.17g", path, *rf_traj_spec_field(&s, path), stored(f, f->def));
            rf_traj_spec_free(&s);
        }
        rows++;
    }
    assert_true(rows >= 22);
}

/* A value each check refuses (as given), or NaN for "finite" (not writable in YAML). */
static double bad_value(rf_traj_check c)
{
    switch (c) {
    case RF_TRAJ_CHECK_POSITIVE: return -1;
    case RF_TRAJ_CHECK_NONNEGATIVE: return -0.5;
    case RF_TRAJ_CHECK_UNIT: return 1.5;
    case RF_TRAJ_CHECK_ANGLE_90: return 90;
    case RF_TRAJ_CHECK_ANGLE_45: return 46;
    case RF_TRAJ_CHECK_ANGLE_180: return 181;
    case RF_TRAJ_CHECK_HEIGHT: return 2e7;
    default: return NAN;
    }
}

static void test_every_row_validated(void **state)
{
    (void)state;
    EACH_ROW(t, f) {
        if (f->check == RF_TRAJ_CHECK_NONE)
            continue;
        char path[200], want[300], at[32];
        row_path(t, f, path, sizeof path);
        build b = build_for(f);
        rf_traj_spec s;
        rf_error err;
        double bad = bad_value(f->check);
        if (isnan(bad)) { /* in memory: set, then validate */
            assert_int_equal(load(&b, &s, &err), RF_OK);
            assert_true(rf_traj_spec_set(&s, path, INFINITY));
            assert_int_not_equal(rf_traj_spec_validate(&s, &err), RF_OK);
            snprintf(want, sizeof want, "%s = inf: must be finite", path);
            if (strncmp(err.msg, want, strlen(want)))
                fail_msg("'%s' does not open with '%s'", err.msg, want);
            rf_traj_spec_free(&s);
            continue;
        }
        b.set = path, b.value = bad;
        assert_int_not_equal(load(&b, &s, &err), RF_OK);
        snprintf(want, sizeof want, "%s = %g: %s", path, bad, rf_traj_field_rule(f, bad));
        snprintf(at, sizeof at, "t.yaml:%d: ", section_line(path));
        if (strncmp(err.msg, at, strlen(at)) || !strstr(err.msg, want))
            fail_msg("'%s' lacks '%s' or '%s'", err.msg, at, want);
        assert_non_null(rf_traj_field_rule(f, bad));
        assert_null(rf_traj_field_rule(f, f->probe));
    }
}

static void test_bindable_where_marked(void **state)
{
    (void)state;
    EACH_ROW(t, f) {
        char path[200], why[2400], list[4096];
        row_path(t, f, path, sizeof path);
        build b = build_for(f);
        rf_traj_spec s;
        rf_error err;
        assert_int_equal(load(&b, &s, &err), RF_OK);
        why[0] = '\0';
        if (rf_traj_path_bindable(&s, path, why, sizeof why) != f->bindable)
            fail_msg("%s: bindable %d, the row says %d (%s)", path, !f->bindable, f->bindable, why);
        rf_traj_bindable_list(&s, list, sizeof list);
        char item[240];
        snprintf(item, sizeof item, "%s%s", path, f->unit[0] ? " [" : ",");
        assert_true((strstr(list, item) != NULL) == f->bindable);
        rf_traj_spec_free(&s);
    }
    char why[2400];
    rf_traj_spec s;
    rf_error err;
    build b = {1, 0, NULL, 0, NULL, 0}; /* a sphere: block.mass is not used */
    assert_int_equal(load(&b, &s, &err), RF_OK);
    assert_false(rf_traj_path_bindable(&s, "block.mass", why, sizeof why));
    assert_non_null(strstr(why, "only a point block"));
    assert_false(rf_traj_path_bindable(&s, "materials.m.R_m", why, sizeof why)); /* a typo */
    assert_non_null(strstr(why, "did you mean 'materials.m.R_n'?"));
    rf_traj_spec_free(&s);
}

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

/* The identity changes with every row's value (the file's text stays the same). */
static void test_identity_covers_every_row(void **state)
{
    (void)state;
    EACH_ROW(t, f) {
        char path[200];
        row_path(t, f, path, sizeof path);
        build b = build_for(f);
        rf_traj_spec s, d;
        rf_error err;
        assert_int_equal(load(&b, &s, &err), RF_OK);
        char *id0 = identity(&s);
        assert_int_equal(rf_traj_spec_copy(&s, &d, &err), RF_OK);
        assert_true(rf_traj_spec_set(&d, path, f->probe));
        char *id1 = identity(&d);
        if (!strcmp(id0, id1))
            fail_msg("%s = %g does not change the identity %s", path, f->probe, id0);
        *rf_traj_spec_field(&d, path) = *rf_traj_spec_field(&s, path); /* back: the same identity */
        char *id2 = identity(&d);
        assert_string_equal(id0, id2);
        free(id0), free(id1), free(id2);
        rf_traj_spec_free(&d);
        rf_traj_spec_free(&s);
    }
}

/* docs/trajectories.md holds the table generated from the rows, verbatim. */
static void test_docs_table(void **state)
{
    (void)state;
    char *table = NULL, *docs = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&table, &len);
    assert_non_null(m);
    rf_traj_fields_markdown(m);
    fclose(m);
    FILE *f = fopen(ROCKFUZZ_SOURCE_DIR "/docs/trajectories.md", "r");
    assert_non_null(f);
    docs = calloc(1, 1 << 20);
    size_t n = fread(docs, 1, (1 << 20) - 1, f);
    fclose(f);
    assert_true(n > 0);
    if (!strstr(docs, table)) { /* written out for the docs' update */
        FILE *o = fopen("trajectory_keys.md", "w");
        if (o)
            fputs(table, o), fclose(o);
        fail_msg("docs/trajectories.md lacks the key table generated from the rows (in trajectory_keys.md)");
    }
    free(table);
    free(docs);
}

/* A fuzzy parameter bound to an angle is given in degrees: the model at 33
 * deg is the same bits as the file with friction_angle: 33 (and 7 deg of
 * roughness likewise). */
static void test_bound_angle_in_degrees(void **state)
{
    (void)state;
    build b = {0, 0, NULL, 0, NULL, 0};
    rf_traj_spec s;
    rf_error err;
    assert_int_equal(load(&b, &s, &err), RF_OK);
    s.samples = 50;
    const char *names[2] = {"phi", "rough"}, *paths[2] = {"materials.m.friction_angle", "materials.m.roughness"};
    rf_model m;
    assert_int_equal(rf_traj_model_create(&s, 2, names, paths, &m, &err), RF_OK);
    double x[2] = {33, 7}, *y = calloc(m.n_outputs, sizeof *y), *z = calloc(m.n_outputs, sizeof *z);
    assert_int_equal(m.eval(m.ctx, x, y, &err), RF_OK);
    rf_traj_spec s2;
    build b2 = {0, 0, "materials.m.friction_angle", 33, NULL, 0};
    assert_int_equal(load(&b2, &s2, &err), RF_OK);
    s2.samples = 50;
    s2.materials[0].roughness = 7 * (RF_PI / 180);
    rf_model m2;
    assert_int_equal(rf_traj_model_create(&s2, 0, NULL, NULL, &m2, &err), RF_OK);
    assert_int_equal(m2.n_outputs, m.n_outputs);
    assert_int_equal(m2.eval(m2.ctx, NULL, z, &err), RF_OK);
    assert_memory_equal(y, z, m.n_outputs * sizeof *y);
    x[0] = 45; /* and the angle matters */
    assert_int_equal(m.eval(m.ctx, x, y, &err), RF_OK);
    assert_true(memcmp(y, z, m.n_outputs * sizeof *y) != 0);
    free(y), free(z);
    rf_model_free(&m), rf_model_free(&m2);
    rf_traj_spec_free(&s), rf_traj_spec_free(&s2);
}

/* The bounce-law registry: every law by its name selects itself, names its
 * parameters, and its own check (a sphere for rigid_sphere and impact_model)
 * refuses a point block. */
static void test_bounce_law_registry(void **state)
{
    (void)state;
    for (int law = 0; law < RF_BOUNCE_N_LAWS; law++) {
        const char *name = rf_traj_bounce_law_names[law];
        assert_true(name && name[0] && rf_traj_bounce_law_parameters((rf_bounce_law)law)[0]);
        for (int other = 0; other < law; other++)
            assert_string_not_equal(name, rf_traj_bounce_law_names[other]);
        for (int sphere = 0; sphere < 2; sphere++) {
            char y[1024];
            snprintf(y, sizeof y, "profile: {points: [[0, 20], [10, 0], [100, 0]], material: m}\n"
                     "materials: {m: {R_n: 0.4, R_t: 0.7, friction_angle: 30}}\nblock: %s\n"
                     "release: {x: 0.5, y: 21}\nbounce: {law: %s, impact: {speeds: [1, 2]}}\n",
                     sphere ? "{shape: sphere, radius: 0.5, density: 2600}" : "{shape: point, mass: 10}", name);
            rf_traj_spec s;
            rf_error err;
            rf_status st = rf_traj_load_buffer("t.yaml", y, strlen(y), &s, &err);
            int needs_sphere = law == RF_BOUNCE_RIGID_SPHERE || law == RF_BOUNCE_IMPACT_MODEL;
            if (!sphere && needs_sphere) {
                assert_int_not_equal(st, RF_OK);
                assert_non_null(strstr(err.msg, "needs block.shape: sphere"));
                continue;
            }
            if (st != RF_OK)
                fail_msg("%s: %s", name, err.msg);
            assert_int_equal(s.law, law);
            rf_traj_spec_free(&s);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_row_parsed_with_default),
        cmocka_unit_test(test_every_row_validated),
        cmocka_unit_test(test_bindable_where_marked),
        cmocka_unit_test(test_identity_covers_every_row),
        cmocka_unit_test(test_docs_table),
        cmocka_unit_test(test_bound_angle_in_degrees),
        cmocka_unit_test(test_bounce_law_registry),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
