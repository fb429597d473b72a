/* test_terrain_file.c - the terrain file (docs/terrain-file.md) read into
 * rf_traj_spec with spec->terrain: the minimal file of issue 28 loads as it
 * is, with every value where it belongs, and makes a world on a DEM built in
 * memory (barrier lengths, release set; a release point off the DEM or on
 * no data refused by name); bad inputs are refused with file:line, field
 * and value; a file with both profile and terrain or neither is refused;
 * copy and free are deep (run under ASan); the model identity changes with
 * every setting and with the bytes of every file the terrain names. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "trajectory/terrain_internal.h"

static const char *minimal =
    "name: valley\n"                                                                              /* 1 */
    "terrain: {dem: dem.tif, materials: {raster: classes.tif, classes: {1: rock, 2: talus, 3: soil}}}\n"
    "materials:\n"                                                                                /* 3 */
    "  rock:  {R_n: 0.5, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1, roughness: 5}\n"
    "  talus: {R_n: 0.35, R_t: 0.75, friction_angle: 35, rolling_resistance: 0.2, roughness: 10}\n"
    "  soil:  {R_n: 0.25, R_t: 0.6, friction_angle: 38, rolling_resistance: 0.4, roughness: 5}\n"
    "block: {shape: sphere, radius: 0.5, density: 2600}\n"                                         /* 7 */
    "release: {points: [[20, 80], [30, 85]], height: 1.0, velocity: [0, 0, 0]}\n"                  /* 8 */
    "bounce: {law: constant}\n"                                                                   /* 9 */
    "barriers: [{name: fence, line: [[10, 40], [40, 80]], height: 4, capacity: 2.0e6}]\n"          /* 10 */
    "rasters: {cell: 2, statistics: [passages, reach_probability, deposits, energy_p95, height_p95]}\n"
    "samples: 10000\n"                                                                            /* 12 */
    "seed: 1\n";

static rf_status load_text(const char *name, const char *yaml, rf_traj_spec *s, rf_error *err)
{
    return rf_traj_load_buffer(name, yaml, strlen(yaml), s, err);
}

static void load_ok(const char *yaml, rf_traj_spec *s)
{
    rf_error err;
    if (load_text("site/t.yaml", yaml, s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

/* `yaml` with the first occurrence of `from` replaced by `to`. */
static char *edit(const char *yaml, const char *from, const char *to)
{
    const char *at = strstr(yaml, from);
    if (!at)
        fail_msg("no '%s' in the file", from);
    size_t n = strlen(yaml) + strlen(to) + 1;
    char *out = malloc(n);
    snprintf(out, n, "%.*s%s%s", (int)(at - yaml), yaml, to, at + strlen(from));
    return out;
}

static void test_minimal_file_loads(void **state)
{
    (void)state;
    rf_traj_spec s;
    load_ok(minimal, &s);
    const rf_terrain_def *d = s.terrain;
    assert_non_null(d);
    assert_string_equal(d->dem, "site/dem.tif"); /* relative to the file's folder */
    assert_string_equal(d->classes, "site/classes.tif");
    assert_int_equal(d->band, 1);
    assert_int_equal(d->classes_band, 1);
    assert_int_equal(d->n_classes, 3);
    for (size_t k = 0; k < 3; k++)
        assert_true(d->class_value[k] == (long)k + 1 && d->class_material[k] == k);
    assert_int_equal(s.release_kind, RF_TRAJ_RELEASE_MAP);
    assert_int_equal(d->release.kind, RF_TERRAIN_POINTS);
    assert_int_equal(d->release.n_features, 2);
    assert_true(d->release.x[1] == 30 && d->release.y[1] == 85 && d->release.weight[1] == 1);
    assert_true(s.height0 == 1.0 && s.vx0 == 0 && s.vy0 == 0 && s.vz0 == 0 && !s.release_by_speed);
    assert_int_equal(s.n_collectors, 1);
    assert_string_equal(s.collectors[0].name, "fence");
    assert_true(s.collectors[0].height == 4 && s.collectors[0].capacity == 2e6);
    assert_int_equal(d->n_barriers, 1);
    assert_true(d->barrier_start[0] == 0 && d->barrier_start[1] == 2 && d->barrier_x[1] == 40 &&
                d->barrier_y[1] == 80);
    assert_true(d->raster_cell == 2);
    assert_int_equal(d->statistics, RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS |
                                        RF_TERRAIN_ENERGY | RF_TERRAIN_HEIGHT);
    assert_true(s.outputs.n_percentiles == 3 && s.outputs.percentiles[1] == 95);
    assert_true(s.samples == 10000 && s.seed == 1 && s.sphere && s.law == RF_BOUNCE_CONSTANT);
    assert_int_equal(d->max_paths, 200);
    assert_true(fabs(s.materials[1].friction_angle - 35 * RF_PI / 180) < 1e-15);
    rf_traj_spec_free(&s);
}

/* A plane z = 100 - 0.5 y on nodes 0..100 m (10 m apart), no data at node (10, 10). */
static rf_terrain *plane(void)
{
    double z[11 * 11];
    for (size_t j = 0; j < 11; j++)
        for (size_t i = 0; i < 11; i++)
            z[j * 11 + i] = 100 - 5.0 * (double)j;
    z[10 * 11 + 10] = NAN;
    rf_terrain *t;
    rf_error err;
    if (rf_terrain_from_nodes(11, 11, 0, 0, 10, 10, z, &t, &err) != RF_OK)
        fail_msg("%s", err.msg);
    return t;
}

static void test_world_on_a_surface(void **state)
{
    (void)state;
    rf_traj_spec s;
    load_ok(minimal, &s);
    rf_terrain_world *w;
    rf_error err;
    rf_terrain *t = plane();
    if (terrain_world_from_surface(&s, t, &w, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_ptr_equal(rf_terrain_world_surface(w), t);
    assert_int_equal(w->ncol, 1);
    assert_int_equal(w->col[0].n, 2);
    assert_true(w->col[0].cum[0] == 0 && fabs(w->col[0].cum[1] - 50) < 1e-12); /* a 30-40-50 line */
    double x, y;
    terrain_release_point(w->release, 0.75, 0.5, 0.5, &x, &y); /* the second point */
    assert_true(x == 30 && y == 85);
    rf_terrain_world_free(w);
    /* release points off the DEM and on the no-data cell, each named */
    const char *bad[2] = {"[[20, 80], [130, 85]]", "[[20, 80], [95, 95]]"};
    const char *want[2] = {"release.points[1]: the point [130, 85]", "release.points[1]: the point [95, 95]"};
    for (int k = 0; k < 2; k++) {
        char *y2 = edit(minimal, "[[20, 80], [30, 85]]", bad[k]);
        rf_traj_spec b;
        load_ok(y2, &b);
        assert_int_equal(terrain_world_from_surface(&b, plane(), &w, &err), RF_EINVAL);
        assert_null(w);
        if (!strstr(err.msg, want[k]) || !strstr(err.msg, "no-data"))
            fail_msg("message: %s", err.msg);
        rf_traj_spec_free(&b);
        free(y2);
    }
    /* a release line that crosses the no-data cell between valid vertices */
    char *y3 = edit(minimal, "points: [[20, 80], [30, 85]]", "lines: [[[20, 80], [50, 80]], [[85, 85], [99, 99]]]");
    rf_traj_spec c;
    load_ok(y3, &c);
    assert_int_equal(terrain_world_from_surface(&c, plane(), &w, &err), RF_EINVAL);
    if (!strstr(err.msg, "release.lines[1]"))
        fail_msg("message: %s", err.msg);
    rf_traj_spec_free(&c);
    free(y3);
    /* a polygon around a no-data hole its edges do not touch */
    double z[11 * 11];
    for (size_t k = 0; k < 121; k++)
        z[k] = 100 - 5.0 * (double)(k / 11);
    z[5 * 11 + 5] = NAN; /* the four cells around (50, 50) */
    rf_terrain *hole;
    assert_int_equal(rf_terrain_from_nodes(11, 11, 0, 0, 10, 10, z, &hole, &err), RF_OK);
    y3 = edit(minimal, "points: [[20, 80], [30, 85]]", "polygons: [[[20, 20], [80, 20], [80, 80], [20, 80]], "
                                                       "[[1, 1], [9, 1], [9, 9]]]");
    load_ok(y3, &c);
    assert_int_equal(terrain_world_from_surface(&c, hole, &w, &err), RF_EINVAL);
    if (!strstr(err.msg, "release.polygons[0]: the no-data cell centred at [45, 45]"))
        fail_msg("message: %s", err.msg);
    assert_int_equal(terrain_world_from_surface(&c, plane(), &w, &err), RF_OK); /* no hole: accepted */
    rf_terrain_world_free(w);
    rf_traj_spec_free(&c);
    free(y3);
    rf_traj_spec_free(&s);
}

/* The impact_model law: the world builds its impact table (none for the other laws). */
static void test_world_impact_table(void **state)
{
    (void)state;
    char *y = edit(minimal, "bounce: {law: constant}", "bounce: {law: impact_model, impact: {solver: rigid, "
                                                        "tolerance: 0.05}}");
    rf_traj_spec s;
    rf_terrain_world *w;
    rf_error err;
    load_ok(minimal, &s);
    assert_int_equal(terrain_world_from_surface(&s, plane(), &w, &err), RF_OK);
    assert_null(w->impact_table);
    rf_terrain_world_free(w);
    rf_traj_spec_free(&s);
    load_ok(y, &s);
    if (terrain_world_from_surface(&s, plane(), &w, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_non_null(w->impact_table);
    double rn, rt, spin;
    traj_impact_table_eval(w->impact_table, 5, 0.3, &rn, &rt, &spin);
    assert_true(rn >= 0 && rn <= 1 && rt >= 0 && rt <= 1);
    rf_terrain_world_free(w);
    rf_traj_spec_free(&s);
    free(y);
}

/* The constant material fills every cell; the reading world fails on the (stub or missing) DEM. */
static void test_world_constant_material(void **state)
{
    (void)state;
    char *y = edit(minimal, "materials: {raster: classes.tif, classes: {1: rock, 2: talus, 3: soil}}",
                   "material: talus");
    char *y2 = edit(y, "  rock:  {R_n: 0.5, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1, roughness: 5}\n",
                    "");
    char *y3 = edit(y2, "  soil:  {R_n: 0.25, R_t: 0.6, friction_angle: 38, rolling_resistance: 0.4, roughness: 5}\n",
                    "");
    rf_traj_spec s;
    load_ok(y3, &s);
    assert_int_equal(s.terrain->material, 0);
    assert_null(s.terrain->classes);
    rf_terrain_world *w;
    rf_error err;
    assert_int_equal(terrain_world_from_surface(&s, plane(), &w, &err), RF_OK);
    assert_int_equal(terrain_material_of(rf_terrain_world_surface(w), 3, 4), 0);
    assert_null(rf_terrain_world_surface(w)->material); /* material 0: no per-cell array */
    rf_terrain_world_free(w);
    s.terrain->material = 3; /* in memory (the validation would refuse it): every cell gets it */
    assert_int_equal(terrain_world_from_surface(&s, plane(), &w, &err), RF_OK);
    for (size_t j = 0; j < 10; j++)
        for (size_t i = 0; i < 10; i++)
            assert_int_equal(terrain_material_of(rf_terrain_world_surface(w), i, j), 3);
    rf_terrain_world_free(w);
    s.terrain->material = 0;
    assert_int_not_equal(rf_terrain_world_create(&s, &w, &err), RF_OK); /* site/dem.tif does not exist */
    assert_null(w);
    assert_non_null(strstr(err.msg, "site/dem.tif"));
    rf_traj_spec_free(&s);
    free(y), free(y2), free(y3);
}

/* Random release values through the rows; speed, azimuth, dip; spin; blocks; p95 added. */
static void test_release_forms(void **state)
{
    (void)state;
    rf_traj_spec s;
    char *y = edit(minimal, "velocity: [0, 0, 0]", "velocity: [1, {uniform: [-1, 1]}, -2], spin: [0, 3, 0], "
                                                   "blocks: [1, 3]");
    load_ok(y, &s);
    assert_int_equal(s.n_random, 1);
    assert_string_equal(s.random[0].path, "release.vy");
    assert_true(s.vx0 == 1 && s.vy0 == 0 && s.vz0 == -2 && s.omega0_xyz[1] == 3);
    assert_true(s.terrain->release.weight[0] == 1 && s.terrain->release.weight[1] == 3);
    rf_traj_spec_free(&s);
    free(y);
    y = edit(minimal, "velocity: [0, 0, 0]", "speed: 2, azimuth: 90, dip: {uniform: [0, 20]}");
    char *y2 = edit(y, "samples: 10000", "outputs: {percentiles: [50, 99], max_paths: 7}\nsamples: 10000");
    load_ok(y2, &s);
    assert_true(s.release_by_speed && s.speed0 == 2 && fabs(s.azimuth0 - RF_PI / 2) < 1e-15);
    assert_true(fabs(s.dip0 - 10 * RF_PI / 180) < 1e-15 && s.n_random == 1);
    assert_true(s.outputs.n_percentiles == 3 && s.outputs.percentiles[0] == 50 && s.outputs.percentiles[1] == 95 &&
                s.outputs.percentiles[2] == 99);
    assert_int_equal(s.terrain->max_paths, 7);
    rf_traj_spec_free(&s);
    free(y), free(y2);
    y = edit(minimal, "points: [[20, 80], [30, 85]]", "polygons: [[[10, 60], [50, 60], [50, 90], [10, 90], [10, 60]]]");
    load_ok(y, &s);
    assert_int_equal(s.terrain->release.kind, RF_TERRAIN_POLYGONS);
    assert_int_equal(s.terrain->release.start[1], 4); /* the repeated closing vertex dropped */
    rf_traj_spec_free(&s);
    free(y);
}

typedef struct {
    const char *from, *to; /* the edit of the minimal file */
    const char *want[3];   /* in the message */
} bad_case;

static const bad_case bad_cases[] = {
    {"dem: dem.tif, ", "", {"t.yaml:2:", "terrain", "dem: FILE is required"}},
    {"dem: dem.tif", "dem: dem.tif, band: 0", {"t.yaml:2:", "terrain.band = 0", "terrain.band"}},
    {"{1: rock", "{a: rock", {"t.yaml:2:", "terrain.materials.classes.a", "integer"}},
    {"3: soil", "3: granite", {"t.yaml:2:", "terrain.materials.classes.3 = granite", "no such material"}},
    {"{raster: classes.tif, ", "{", {"t.yaml:2:", "terrain.materials", "raster: FILE"}},
    {"materials: {raster", "material: rock, materials: {raster", {"t.yaml:2:", "terrain", "not both"}},
    {"3: soil", "3: talus", {"t.yaml:6:", "materials.soil", "not used"}},
    {"[[20, 80], [30, 85]]", "[[20, 80], [30]]", {"t.yaml:8:", "release.points[1]", "expected a list of 2 items"}},
    {"[[20, 80], [30, 85]]", "[[20, 80], [30, 2e7]]", {"t.yaml:8:", "release.points[1]", "finite"}},
    {"points: [[20, 80], [30, 85]]", "points: [[20, 80]], lines: [[[0, 0], [1, 1]]]",
     {"t.yaml:8:", "release", "one of points"}},
    {"points: [[20, 80], [30, 85]], ", "", {"t.yaml:8:", "release", "where blocks start"}},
    {"height: 1.0", "height: 1.0, blocks: [1]", {"t.yaml:8:", "release.blocks", "one count per release feature (2)"}},
    {"height: 1.0", "height: 1.0, blocks: [1, -2]", {"t.yaml:8:", "release.blocks[1] = -2", ">= 0"}},
    {"height: 1.0", "height: -1", {"t.yaml:8:", "release.height = -1", "must be >= 0"}},
    {"velocity: [0, 0, 0]", "velocity: [0, 0, 0], vz: 1", {"t.yaml:8:", "release", "not both"}},
    {"velocity: [0, 0, 0]", "velocity: [0, 0]", {"t.yaml:8:", "release.velocity", "expected a list of 3 items"}},
    {"velocity: [0, 0, 0]", "omega: 2", {"t.yaml:8:", "release.omega = 2", "spin: [wx, wy, wz]"}},
    {"velocity: [0, 0, 0]", "speed: 1, angle: 10", {"t.yaml:8:", "release.angle", "not used here"}},
    {"velocity: [0, 0, 0]", "azimuth: 10", {"t.yaml:8:", "release", "speed [m/s] is required"}},
    {"velocity: [0, 0, 0]", "x: 3", {"t.yaml:8:", "release.x", "not used here"}},
    {"line: [[10, 40], [40, 80]]", "line: [[10, 40]]",
     {"t.yaml:10:", "barriers.fence.line", "expected a list of 2 to"}},
    {"line: [[10, 40], [40, 80]], ", "", {"t.yaml:10:", "barriers.fence", "a barrier needs line"}},
    {"line: [[10, 40], [40, 80]]", "line: [[10, 40], [40, 80]], x: 5", {"t.yaml:10:", "collectors.fence.x",
                                                                        "not used here"}},
    {"capacity: 2.0e6", "capacity: -3", {"t.yaml:10:", "collectors.fence.capacity = -3", ">= 0"}},
    {"cell: 2", "cell: 0", {"t.yaml:11:", "rasters.cell = 0", "> 0"}},
    {"points: [[20, 80], [30, 85]]", "file: {path: r.gpkg, per_area: true}",
     {"t.yaml:8:", "release.file.per_area = true", "needs count"}},
    {"points: [[20, 80], [30, 85]]", "raster: r.tif, blocks: [1]", {"t.yaml:8:", "release.blocks", "come from it"}},
    {"points: [[20, 80], [30, 85]]", "file: {path: r.gpkg, colour: red}", {"t.yaml:8:", "release.file", "layer"}},
    {"seed: 1", "seed: 1\ncollectors: []", {"t.yaml:14:", "collectors", "give one of them"}},
    {"dem: dem.tif", "dem: dem.tif, roughness: r.tif",
     {"t.yaml:2:", "terrain.roughness = r.tif", "expected a mapping"}},
    {"dem: dem.tif", "dem: dem.tif, slope: 3", {"t.yaml:2:", "terrain.slope", "terrain takes dem"}},
    {"deposits, energy_p95", "deposits, energy_p96", {"t.yaml:11:", "rasters.statistics[3] = energy_p96",
                                                      "expected passages"}},
    {"rasters: {cell: 2,", "rasters: {size: 2,", {"t.yaml:11:", "rasters", "rasters takes cell, statistics"}},
    {"seed: 1", "seed: 1\nprofile: {points: [[0, 1], [2, 0]], material: rock}",
     {"t.yaml:2:", "terrain", "not both"}},
    {"seed: 1", "seed: 1\noutputs: {max_path: 3}", {"t.yaml:14:", "outputs.max_path", "max_paths"}},
    {"seed: 1", "seed: 1\nzone: 3", {"t.yaml:14:", "zone", "a terrain file takes"}},
};

static void check_bad(const char *yaml, const char *const want[3])
{
    rf_traj_spec s;
    rf_error err;
    if (load_text("site/t.yaml", yaml, &s, &err) == RF_OK)
        fail_msg("accepted:\n%s", yaml);
    for (int k = 0; k < 3; k++)
        if (!strstr(err.msg, want[k]))
            fail_msg("message '%s' lacks '%s'", err.msg, want[k]);
}

static void test_bad_inputs_located(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
        char *y = edit(minimal, bad_cases[i].from, bad_cases[i].to);
        check_bad(y, bad_cases[i].want);
        free(y);
    }
    /* a self-intersecting polygon, found by the validation, at its line */
    char *y = edit(minimal, "release: {points: [[20, 80], [30, 85]],",
                   "release: {\n  polygons: [[[0, 0], [1, 0], [1, 1], [0, 1]],\n"
                   "    [[0, 0], [2, 2], [2, 0], [0, 2]]],");
    const char *want[3] = {"t.yaml:10:", "release.polygons[1]", "intersects itself"};
    check_bad(y, want);
    free(y);
    /* the release file goes to the vector reader; its failure is located */
    y = edit(minimal, "points: [[20, 80], [30, 85]]", "file: {path: rel.gpkg, count: n}");
    const char *want2[3] = {"t.yaml:8:", "release.file.path = rel.gpkg", "site/rel.gpkg"};
    check_bad(y, want2);
    free(y);
}

static void test_profile_or_terrain(void **state)
{
    (void)state;
    char *y = edit(minimal, "terrain: {dem: dem.tif, materials: {raster: classes.tif, classes: {1: rock, 2: talus, "
                            "3: soil}}}\n", "");
    const char *want[3] = {"t.yaml:1:", "profile: missing", "terrain"};
    check_bad(y, want);
    free(y);
    /* a profile file does not take the terrain keys */
    const char *twod = "profile: {points: [[0, 20], [10, 0], [100, 0]], material: m}\n"
                       "materials: {m: {R_n: 0.4, R_t: 0.7}}\nblock: {mass: 10}\nrelease: {x: 1, y: 21}\n"
                       "rasters: {cell: 2}\n";
    const char *want2[3] = {"t.yaml:5:", "rasters", "a trajectory file takes"};
    check_bad(twod, want2);
    char *y2 = edit(twod, "release: {x: 1, y: 21}", "release: {x: 1, y: 21, vz: 2}");
    char *y3 = edit(y2, "rasters: {cell: 2}\n", "");
    const char *want3[3] = {"t.yaml:4:", "release.vz", "not used here"};
    check_bad(y3, want3);
    free(y2), free(y3);
}

static void test_copy_and_free(void **state)
{
    (void)state;
    rf_traj_spec s, d;
    rf_error err;
    char *y = edit(minimal, "points: [[20, 80], [30, 85]]", "lines: [[[20, 80], [50, 80]], [[5, 5], [6, 6], [7, 9]]]");
    char *y2 = edit(y, "classes: {1:", "band: 2, classes: {1:");
    load_ok(y2, &s);
    uint64_t h = rf_traj_spec_values_hash(&s);
    assert_int_equal(rf_traj_spec_copy(&s, &d, &err), RF_OK);
    assert_ptr_not_equal(d.terrain, s.terrain);
    assert_ptr_not_equal(d.terrain->release.x, s.terrain->release.x);
    rf_traj_spec_free(&s); /* the copy owns all of its own */
    assert_true(d.terrain->release.n_features == 2 && d.terrain->release.start[2] == 5 && d.terrain->release.y[4] == 9);
    assert_string_equal(d.terrain->dem, "site/dem.tif");
    assert_int_equal(d.terrain->classes_band, 2);
    assert_true(d.terrain->n_barriers == 1 && d.terrain->barrier_x[1] == 40);
    assert_true(rf_traj_spec_values_hash(&d) == h);
    rf_traj_spec e;
    assert_int_equal(rf_traj_spec_copy(&d, &e, &err), RF_OK);
    rf_traj_spec_free(&d);
    rf_traj_spec_free(&e);
    free(y), free(y2);
}

/* Every setting of the terrain part changes the identity. */
static void test_hash_covers_every_setting(void **state)
{
    (void)state;
    static const char *const edits[][2] = {
        {"dem: dem.tif", "dem: dem2.tif"},
        {"dem: dem.tif", "dem: dem.tif, band: 2"},
        {"raster: classes.tif", "raster: classes2.tif"},
        {"classes: {1:", "band: 3, classes: {1:"},
        {"2: talus, 3: soil", "2: soil, 3: talus"},
        {"3: soil", "4: soil"},
        {"dem: dem.tif", "dem: dem.tif, roughness: {raster: r.tif}"},
        {"[30, 85]", "[30, 86]"},
        {"height: 1.0", "height: 1.0, blocks: [1, 2]"},
        {"height: 1.0", "height: 1.5"},
        {"velocity: [0, 0, 0]", "velocity: [0, 0, -1]"},
        {"[40, 80]]", "[40, 81]]"},
        {"[40, 80]]", "[40, 80], [50, 90]]"},
        {"cell: 2", "cell: 3"},
        {"deposits, ", ""},
        {"seed: 1", "seed: 1\noutputs: {max_paths: 10}"},
        {"points: [[20, 80], [30, 85]]", "lines: [[[20, 80], [30, 85]]]"},
    };
    rf_traj_spec s;
    load_ok(minimal, &s);
    uint64_t h0 = rf_traj_spec_values_hash(&s);
    rf_traj_spec_free(&s);
    for (size_t k = 0; k < sizeof edits / sizeof edits[0]; k++) {
        char *y = edit(minimal, edits[k][0], edits[k][1]);
        load_ok(y, &s);
        if (rf_traj_spec_values_hash(&s) == h0)
            fail_msg("'%s' -> '%s' does not change the identity", edits[k][0], edits[k][1]);
        rf_traj_spec_free(&s);
        free(y);
    }
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* The bytes of the DEM, the class raster, the roughness raster change the identity. */
static void test_hash_covers_file_bytes(void **state)
{
    (void)state;
    char dir[] = "/tmp/rf_terrain_fileXXXXXX";
    assert_non_null(mkdtemp(dir));
    char p[4][300];
    const char *names[4] = {"t.yaml", "dem.tif", "classes.tif", "r.tif"};
    for (int k = 0; k < 4; k++)
        snprintf(p[k], sizeof p[k], "%s/%s", dir, names[k]);
    char *y = edit(minimal, "dem: dem.tif", "dem: dem.tif, roughness: {raster: r.tif}");
    write_file(p[0], y);
    for (int k = 1; k < 4; k++)
        write_file(p[k], "bytes of a raster");
    rf_traj_spec s;
    rf_error err;
    if (rf_traj_load(p[0], &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    uint64_t h0 = rf_traj_spec_values_hash(&s);
    assert_true(rf_traj_spec_values_hash(&s) == h0); /* a pure function of the files */
    for (int k = 1; k < 4; k++) {
        write_file(p[k], "bytes of a raster, edited");
        uint64_t h1 = rf_traj_spec_values_hash(&s);
        write_file(p[k], "bytes of a raster");
        if (h1 == h0)
            fail_msg("editing %s does not change the identity", names[k]);
        assert_true(rf_traj_spec_values_hash(&s) == h0);
    }
    rf_traj_spec_free(&s);
    for (int k = 0; k < 4; k++)
        unlink(p[k]);
    rmdir(dir);
    free(y);
}

/* The release of the minimal file with the rows of a terrain file's velocity
 * form (speed: speed, azimuth, dip; else vx, vy, vz) and height; `key` set to
 * `value` (as given), or left out when omit. */
static char *release_with(int by_speed, const char *key, double value, int omit)
{
    const char *keys[2][4] = {{"vx", "vy", "vz", "height"}, {"speed", "azimuth", "dip", "height"}};
    const double base[2][4] = {{0.5, 0, -1, 1}, {2, 30, 5, 1}};
    char rel[400] = "release: {points: [[20, 80], [30, 85]]";
    for (int k = 0; k < 4; k++) {
        size_t n = strlen(rel);
        if (!strcmp(keys[by_speed][k], key) && omit)
            continue;
        snprintf(rel + n, sizeof rel - n, ", %s: %.17g", keys[by_speed][k],
                 !strcmp(keys[by_speed][k], key) ? value : base[by_speed][k]);
    }
    strcat(rel, "}");
    return edit(minimal, "release: {points: [[20, 80], [30, 85]], height: 1.0, velocity: [0, 0, 0]}", rel);
}

/* The rows only a terrain file uses (the 2D file's rows: test_trajectory_fields.c):
 * read as given (angles stored in radians), defaults, checks located at their
 * line, bindable as marked, the identity changes with them. */
static void test_terrain_rows(void **state)
{
    (void)state;
    size_t rows = 0;
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        for (const rf_traj_field *f = tb->rows; f < tb->rows + tb->n_rows; f++) {
            if (f->when != RF_TRAJ_WHEN_TERRAIN && f->when != RF_TRAJ_WHEN_TERRAIN_VXVY &&
                f->when != RF_TRAJ_WHEN_TERRAIN_SPEED)
                continue;
            int by_speed = f->when == RF_TRAJ_WHEN_TERRAIN_SPEED;
            char path[200], why[2400], want[300];
            snprintf(path, sizeof path, "%s%s", tb->prefix, f->key);
            double scale = f->degrees ? RF_PI / 180 : 1, given;
            rf_traj_spec s;
            rf_error err;
            char *y = release_with(by_speed, f->key, f->probe, 0);
            load_ok(y, &s);
            assert_true(*rf_traj_spec_field(&s, path) == f->probe * scale);
            assert_true(rf_traj_spec_get(&s, path, &given) && fabs(given - f->probe) <= 1e-13 * fabs(f->probe));
            assert_int_equal(rf_traj_path_bindable(&s, path, why, sizeof why), f->bindable);
            uint64_t h = rf_traj_spec_values_hash(&s);
            assert_true(rf_traj_spec_set(&s, path, f->def));
            assert_true(rf_traj_spec_values_hash(&s) != h);
            rf_traj_spec_free(&s);
            free(y);
            y = release_with(by_speed, f->key, 0, 1);
            load_ok(y, &s);
            assert_true(*rf_traj_spec_field(&s, path) == f->def * scale);
            rf_traj_spec_free(&s);
            free(y);
            double bad = f->check == RF_TRAJ_CHECK_NONNEGATIVE ? -0.5 : f->check == RF_TRAJ_CHECK_ANGLE_180 ? 181 : NAN;
            if (!isnan(bad)) {
                y = release_with(by_speed, f->key, bad, 0);
                assert_int_not_equal(load_text("site/t.yaml", y, &s, &err), RF_OK);
                snprintf(want, sizeof want, "site/t.yaml:8: %s = %g: %s", path, bad, rf_traj_field_rule(f, bad));
                if (strcmp(err.msg, want))
                    fail_msg("'%s', want '%s'", err.msg, want);
                free(y);
            }
            rows++;
        }
    }
    assert_int_equal(rows, 4); /* vz, azimuth, dip, height */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_minimal_file_loads),
        cmocka_unit_test(test_world_on_a_surface),
        cmocka_unit_test(test_world_constant_material),
        cmocka_unit_test(test_world_impact_table),
        cmocka_unit_test(test_release_forms),
        cmocka_unit_test(test_bad_inputs_located),
        cmocka_unit_test(test_profile_or_terrain),
        cmocka_unit_test(test_copy_and_free),
        cmocka_unit_test(test_hash_covers_every_setting),
        cmocka_unit_test(test_hash_covers_file_bytes),
        cmocka_unit_test(test_terrain_rows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
