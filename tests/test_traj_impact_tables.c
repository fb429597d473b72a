/* test_traj_impact_tables.c - the `impact_model` table per material and over
 * the block radius (traj_impact_table.c):
 *  - a file without `impact:` gives the table and the trajectory of before,
 *    bit for bit (figures recorded with the binary of commit a67ec1a);
 *  - each material that names its impact model gets its own grid, which
 *    matches direct calls of the model with that material's inputs, and the
 *    bounce on a segment uses its material's grid;
 *  - the radius axis: Hunter's loss is scale-free (R_n depends on v/c0 and
 *    rho/E*, not on r), so the grid stays flat in radius (no node added) and
 *    equals the model at every radius; a model that does depend on r (a known
 *    function put in place of the impact model) is refined along r to the
 *    tolerance, checked at random points;
 *  - a material's impact model is checked at load (file:line);
 *  - in a study's store (side rows): a build interrupted by the stop flag
 *    keeps its impacts, the resumed one computes only the missing ones (counted),
 *    a third reuses all, also through the model's prepare; a damaged value or
 *    a conflicting repeat in the store is refused with a message;
 *  - the cache file keeps each material's impacts apart and at every radius;
 *  - a terrain study's model builds its table in the run (prepare), not when
 *    it is created: nothing computed at load, the stop flag answered. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "rockfuzz/store.h"
#include "rockfuzz/trajectory.h"
#include "test_traj_util.h"
#include "trajectory/traj_impact.h"
#include "rockfuzz/impact_model.h"
#include "trajectory/traj_internal.h"
#include "trajectory/terrain_internal.h"
#include "terrain_fixture.h"

#define DEG (3.14159265358979323846 / 180)

static void load(const char *yaml, rf_traj_spec *s)
{
    rf_error err;
    if (rf_traj_load_buffer("t.yaml", yaml, strlen(yaml), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

/* The file of the recorded run: two materials, no `impact:`. */
static const char *plain =
    "profile: {points: [[0, 30], [20, 15], [40, 8], [80, 0], [120, -5]], materials: [rock, rock, soil, soil]}\n"
    "materials: {rock: {R_n: 0.3, R_t: 0.8, friction_angle: 25}, soil: {R_n: 0.2, R_t: 0.6, friction_angle: 35, "
    "rolling_resistance: 0.1}}\n"
    "block: {shape: sphere, radius: 0.4, density: 2600}\n"
    "release: {x: 1, y: 30.5, vx: 2}\n"
    "bounce: {law: impact_model, impact: {solver: rigid, tolerance: 0.01}}\n"
    "samples: 20\n"
    "collectors: [{name: c, x: 60}]\n";

/* Without `impact:` the table and the run are those of before (one grid,
 * the figures of `rockfuzz trajectory --json` at a67ec1a, exact). */
static void test_old_behaviour_bit_identical(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    load(plain, &s);
    rf_traj_world *w;
    assert_int_equal(rf_traj_world_create(&s, &w, &err), RF_OK);
    size_t nv, nt, evals, cached;
    double est;
    traj_impact_table_info(w->impact_table, &nv, &nt, &evals, &cached, &est);
    assert_int_equal(traj_impact_table_grids(w->impact_table), 1);
    assert_int_equal(nv, 5);
    assert_int_equal(nt, 8);
    assert_int_equal(evals, 135);
    assert_true(est == 0.0038606969086589782);
    rf_traj_crossing cr[1];
    rf_traj_result r = {0};
    r.crossings = cr;
    r.impacts = malloc(64 * sizeof *r.impacts), r.impacts_cap = 64;
    r.events = malloc(64 * sizeof *r.events), r.events_cap = 64;
    assert_int_equal(rf_traj_simulate(w, &s, 1, 0, &r, &err), RF_OK);
    assert_traj_invariants(&s, &r);
    assert_int_equal(r.n_impacts, 18);
    const rf_traj_impact *m = &r.impacts[17];
    assert_true(m->vx_out == 3.8526782189230953 && m->vy_out == 4.33848493210264 && m->omega_out == 8.212011339153431);
    assert_true(cr[0].total_energy == 39440.93479474377);
    free(r.impacts);
    free(r.events);
    rf_traj_world_free(w);
    rf_traj_spec_free(&s);
}

/* Three materials: hunter on granite, the rigid model on a soft rock (Hunter's
 * e_n from its modulus), and one without impact: (bounce.impact: rigid on granite). */
static const char *three =
    "profile: {points: [[-10, 5.773502691896258], [0, 0], [10, -5.773502691896258], [20, -11.547005383792516]], "
    "materials: [hard, soft, plain]}\n"
    "materials: {hard: {R_n: 0.3, R_t: 0.8, friction_angle: 25, impact: {solver: hunter}},\n"
    "  soft: {R_n: 0.3, R_t: 0.8, friction_angle: 35, impact: {solver: rigid, slope_E: 50e6, slope_density: 1800, "
    "slope_poisson: 0.3}},\n"
    "  plain: {R_n: 0.3, R_t: 0.8, friction_angle: 20}}\n"
    "block: {shape: sphere, radius: 0.5, density: 2600}\n"
    "release: {x: 5, y: 3}\n"
    "bounce: {law: impact_model, impact: {solver: rigid, tolerance: 0.005%s}}\n";

static void load_three(rf_traj_spec *s, const char *extra)
{
    char y[2048];
    snprintf(y, sizeof y, three, extra);
    load(y, s);
}

/* The table of each material against direct calls of the model with its inputs. */
static void test_per_material_grids(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    load_three(&s, "");
    assert_true(s.materials[0].impact.given && s.materials[1].impact.given && !s.materials[2].impact.given);
    traj_impact_table *t;
    assert_int_equal(traj_impact_table_build(&s, &t, &err), RF_OK);
    assert_int_equal(traj_impact_table_grids(t), 3);
    double worst = 0, at10[3], rt10[3];
    for (size_t k = 0; k < 3; k++) {
        traj_impact_setup setup;
        assert_int_equal(traj_impact_setup_material(&setup, &s, k, &err), RF_OK);
        for (int i = 0; i < 60; i++) {
            double v = 0.25 * pow(160, rf_traj_uniform(5, 2 * k, (uint64_t)i));
            double th = 80 * DEG * rf_traj_uniform(5, 2 * k + 1, (uint64_t)i);
            double rn, rt, sp, an, at, as;
            traj_impact_table_lookup(t, k, 0.5, v, th, &rn, &rt, &sp);
            assert_int_equal(traj_impact_coefficients(&setup, v, th, &an, &at, &as, &err), RF_OK);
            worst = fmax(worst, fmax(fabs(rn - an), fabs(rt - at)));
        }
        double sp;
        traj_impact_table_lookup(t, k, 0.5, 10, 30 * DEG, &at10[k], &rt10[k], &sp);
    }
    print_message("R_n, R_t at 10 m/s, 30 deg: hard %.4f %.4f, soft %.4f %.4f, plain %.4f %.4f; worst miss %.3g "
                  "(tolerance 0.005)\n", at10[0], rt10[0], at10[1], rt10[1], at10[2], rt10[2], worst);
    assert_true(worst <= 3 * 0.005);
    /* the materials' own models differ by far more than the tolerance: a wrong grid would be seen */
    assert_true(fabs(at10[0] - at10[1]) > 0.05 && fabs(at10[1] - at10[2]) > 0.05); /* soft rock: lower R_n */
    traj_impact_table_free(t);
    rf_traj_spec_free(&s);
}

/* A vertical fall onto the 30 deg segment of `soft` bounces with soft's coefficients. */
static void test_bounce_uses_material(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    load_three(&s, "");
    rf_traj_world *w;
    assert_int_equal(rf_traj_world_create(&s, &w, &err), RF_OK);
    rf_traj_crossing cr[1];
    rf_traj_result r = {0};
    r.crossings = cr;
    r.impacts = malloc(16 * sizeof *r.impacts), r.impacts_cap = 16;
    r.events = malloc(16 * sizeof *r.events), r.events_cap = 16;
    assert_int_equal(rf_traj_simulate(w, &s, 1, 0, &r, &err), RF_OK);
    assert_traj_invariants(&s, &r);
    const rf_traj_impact *m = &r.impacts[0];
    assert_int_equal(m->segment, 1);
    double b = 30 * DEG, nx = sin(b), ny = cos(b);
    double vn_in = -(m->vx_in * nx + m->vy_in * ny), vn_out = m->vx_out * nx + m->vy_out * ny;
    double rn[3];
    for (size_t k = 0; k < 3; k++) {
        traj_impact_setup setup;
        double at, as;
        assert_int_equal(traj_impact_setup_material(&setup, &s, k, &err), RF_OK);
        assert_int_equal(traj_impact_coefficients(&setup, vn_in, b, &rn[k], &at, &as, &err), RF_OK);
    }
    print_message("fall on soft: R_n %.4f; soft's model %.4f, hard's %.4f, plain's %.4f\n", vn_out / vn_in, rn[1],
                  rn[0], rn[2]);
    assert_true(fabs(vn_out / vn_in - rn[1]) <= 0.005);
    assert_true(fabs(vn_out / vn_in - rn[0]) > 0.05 && fabs(vn_out / vn_in - rn[2]) > 0.05); /* not the others' */
    free(r.impacts);
    free(r.events);
    rf_traj_world_free(w);
    rf_traj_spec_free(&s);
}

/* Hunter's R_n is scale-free: over radii [0.2, 2] m the grid keeps its three
 * first radius nodes and equals the model at any radius. */
static void test_radius_axis_flat_for_hunter(void **state)
{
    (void)state;
    const char *y = "profile: {points: [[0, 10], [10, 0]], material: m}\n"
                    "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 25}}\n"
                    "block: {shape: sphere, radius: {uniform: [0.2, 2.0]}, density: 2600}\n"
                    "release: {x: 1, y: 10}\n"
                    "bounce: {law: impact_model, impact: {solver: hunter, tolerance: 0.005}}\n";
    rf_traj_spec s;
    rf_error err;
    load(y, &s);
    traj_impact_table *t;
    assert_int_equal(traj_impact_table_build(&s, &t, &err), RF_OK);
    size_t nodes[3], evals, cached;
    double est;
    traj_impact_table_grid_info(t, 0, nodes, &evals, &cached, &est);
    assert_int_equal(nodes[2], 3);
    traj_impact_setup setup;
    assert_int_equal(traj_impact_setup_material(&setup, &s, 0, &err), RF_OK);
    double worst = 0, spread = 0;
    for (int i = 0; i < 40; i++) {
        double v = 0.25 * pow(160, rf_traj_uniform(9, 0, (uint64_t)i)), th = 80 * DEG * rf_traj_uniform(9, 1, (uint64_t)i);
        double r = 0.2 * pow(10, rf_traj_uniform(9, 2, (uint64_t)i)), rn, rt, sp, rn2, an, at, as;
        traj_impact_table_lookup(t, 0, r, v, th, &rn, &rt, &sp);
        traj_impact_table_lookup(t, 0, 0.2, v, th, &rn2, &rt, &sp);
        setup.radius = r;
        assert_int_equal(traj_impact_coefficients(&setup, v, th, &an, &at, &as, &err), RF_OK);
        worst = fmax(worst, fabs(rn - an));
        spread = fmax(spread, fabs(rn - rn2));
    }
    print_message("hunter over radii 0.2..2 m: %zu x %zu x %zu nodes, worst miss %.3g, spread over r %.3g\n",
                  nodes[0], nodes[1], nodes[2], worst, spread);
    assert_true(worst <= 3 * 0.005);
    assert_true(spread <= 1e-12);
    traj_impact_table_free(t);
    rf_traj_spec_free(&s);
}

/* A model with a known dependence on the radius in place of the impact model. */
static rf_status wavy(const struct traj_impact_setup_s *s, double vn, double theta, double c[3], rf_error *err)
{
    (void)err;
    double r = s->radius;
    c[0] = 0.5 + 0.3 * sin(3 * r) * exp(-0.02 * vn);
    c[1] = 0.8 - 0.1 * cos(theta) * r;
    c[2] = 0;
    return RF_OK;
}

/* The radius axis is refined where the model changes with r, to the tolerance. */
static void test_radius_axis_refined(void **state)
{
    (void)state;
    const char *y = "profile: {points: [[0, 10], [10, 0]], material: m}\n"
                    "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 25}}\n"
                    "block: {shape: sphere, radius: {uniform: [0.2, 2.0]}, density: 2600}\n"
                    "release: {x: 1, y: 10}\n"
                    "bounce: {law: impact_model, impact: {solver: hunter, tolerance: 0.005}}\n";
    rf_traj_spec s;
    rf_error err;
    load(y, &s);
    traj_table_watch w = {NULL, NULL, NULL, NULL, wavy};
    traj_impact_table *t;
    assert_int_equal(traj_impact_table_build_watched(&s, &w, &t, &err), RF_OK);
    size_t nodes[3], evals, cached;
    double est, worst = 0;
    traj_impact_table_grid_info(t, 0, nodes, &evals, &cached, &est);
    traj_impact_setup setup = {0};
    for (int i = 0; i < 400; i++) {
        double v = 0.25 * pow(160, rf_traj_uniform(11, 0, (uint64_t)i)), th = 80 * DEG * rf_traj_uniform(11, 1, (uint64_t)i);
        double r = 0.2 + 1.8 * rf_traj_uniform(11, 2, (uint64_t)i), rn, rt, sp, c[3];
        traj_impact_table_lookup(t, 0, r, v, th, &rn, &rt, &sp);
        setup.radius = r;
        wavy(&setup, v, th, c, &err);
        worst = fmax(worst, fmax(fabs(rn - c[0]), fabs(rt - c[1])));
    }
    print_message("sin(3 r) model: %zu x %zu x %zu nodes, %zu evaluations, estimate %.3g, worst of 400 %.3g\n",
                  nodes[0], nodes[1], nodes[2], evals, est, worst);
    assert_true(nodes[2] > 5);
    assert_true(worst <= 3 * 0.005 && est <= 3 * 0.005);
    assert_true(worst <= 3 * est + 1e-12 && est <= 3 * worst + 1e-12);
    traj_impact_table_free(t);
    rf_traj_spec_free(&s);
}

/* A material's impact model is checked at load, with the file and line. */
static void test_checked_at_load(void **state)
{
    (void)state;
    const char *bad[][2] = {
        {"impact: {solver: hertz, layer_thickness: 0.5}", "t.yaml:2: materials.m.impact: layer_thickness = 0.5 m: "
                                                          "the hertz solver has no layer"},
        {"impact: {slope_material: granite}", "t.yaml:2: materials.m.impact: slope_material: material model 'granite'"},
        {"impact: {slope_E: -3}", "t.yaml:2: materials.m.impact.slope_E = -3: must be > 0"},
        {"impact: {slope_poisson: 0.7}", "t.yaml:2: materials.m.impact: "},
        {"impact: {solver: magic}", "t.yaml:2: materials.m.impact: solver"},
        {"impact: {E: 3}", "t.yaml:2: materials.m.impact.E: unknown key; materials.m.impact takes: slope_E "
                            "slope_poisson"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char y[1024];
        snprintf(y, sizeof y, "profile: {points: [[0, 10], [10, 0]], material: m}\n"
                              "materials: {m: {R_n: 0.3, R_t: 0.8, %s}}\n"
                              "block: {shape: sphere, radius: 0.5, density: 2600}\nrelease: {x: 1, y: 10}\n"
                              "bounce: {law: impact_model}\n", bad[k][0]);
        rf_traj_spec s;
        rf_error err;
        assert_int_not_equal(rf_traj_load_buffer("t.yaml", y, strlen(y), &s, &err), RF_OK);
        if (!strstr(err.msg, bad[k][1]))
            fail_msg("%s: '%s' lacks '%s'", bad[k][0], err.msg, bad[k][1]);
    }
}

/* The model's identity covers a material's impact model: its words and its presence. */
static void test_identity_covers_impact(void **state)
{
    (void)state;
    const char *impacts[] = {"", ", impact: {}", ", impact: {solver: hunter}", ", impact: {slope_material: von_mises, "
                             "slope_yield: 1e8, solver: fem}", ", impact: {boulder_material: rigid}"};
    char ids[5][512];
    for (int k = 0; k < 5; k++) {
        char y[1024];
        snprintf(y, sizeof y, "profile: {points: [[0, 10], [10, 0]], material: m}\n"
                              "materials: {m: {R_n: 0.3, R_t: 0.8%s}}\n"
                              "block: {shape: sphere, radius: 0.5, density: 2600}\nrelease: {x: 1, y: 10}\n"
                              "bounce: {law: impact_model}\n", impacts[k]);
        rf_traj_spec s;
        load(y, &s);
        s.text_hash = 0; /* the values alone, not the file's text */
        rf_model m;
        rf_error err;
        assert_int_equal(rf_traj_model_create(&s, 0, NULL, NULL, &m, &err), RF_OK);
        snprintf(ids[k], sizeof ids[k], "%s", m.identity);
        for (int j = 0; j < k; j++)
            if (!strcmp(ids[j], ids[k]))
                fail_msg("'%s' and '%s' have the same identity", impacts[j], impacts[k]);
        rf_model_free(&m);
        rf_traj_spec_free(&s);
    }
}

/* bounce.impact.cache: a second build reads every impact of every grid from the file. */
static void test_cache_per_material(void **state)
{
    (void)state;
    remove("traj_impact_tables_cache.txt");
    rf_traj_spec s;
    rf_error err;
    load_three(&s, ", cache: traj_impact_tables_cache.txt");
    size_t nv, nt, evals[2], cached[2];
    double est, a[3], b[3];
    traj_impact_table *t[2];
    for (int k = 0; k < 2; k++) {
        assert_int_equal(traj_impact_table_build(&s, &t[k], &err), RF_OK);
        traj_impact_table_info(t[k], &nv, &nt, &evals[k], &cached[k], &est);
    }
    assert_true(evals[0] > 0 && cached[0] == 0);
    assert_true(evals[1] == 0 && cached[1] == evals[0]);
    for (size_t m = 0; m < 3; m++)
        for (int i = 0; i < 20; i++) {
            traj_impact_table_lookup(t[0], m, 0.5, 0.3 + 2 * i, 0.04 * i, &a[0], &a[1], &a[2]);
            traj_impact_table_lookup(t[1], m, 0.5, 0.3 + 2 * i, 0.04 * i, &b[0], &b[1], &b[2]);
            assert_memory_equal(a, b, sizeof a);
        }
    traj_impact_table_free(t[0]);
    traj_impact_table_free(t[1]);
    rf_traj_spec_free(&s);
    remove("traj_impact_tables_cache.txt");
}

/* ---- the study store ---- */

static rf_status side_put(void *user, const char *key, const double *row, size_t width, rf_error *err)
{
    return rf_store_side_put(user, key, row, width, err);
}

static rf_status side_each(void *user, const char *key, size_t width, rf_status (*fn)(void *u, const double *row),
                           void *u, rf_error *err)
{
    return rf_store_side_each(user, key, width, fn, u, err);
}

typedef struct {
    atomic_int stop;
    size_t after, computed; /* set stop once `after` impacts are computed */
} stopper;

static void stop_after(void *user, size_t computed, size_t from_cache, size_t nv, size_t nt)
{
    (void)from_cache, (void)nv, (void)nt;
    stopper *p = user;
    p->computed = computed;
    if (computed >= p->after)
        atomic_store(&p->stop, 1);
}

static rf_store *open_store(const char *path)
{
    const char *in[1] = {"x"}, *out[1] = {"y"};
    rf_store_key key = {"test model", "0", 1, 1, in, out};
    rf_store *st;
    rf_error err;
    remove(path);
    if (rf_store_open(path, &key, 1, &st, &err) != RF_OK)
        fail_msg("%s", err.msg);
    return st;
}

static void build_counts(const rf_traj_spec *s, const traj_table_watch *w, rf_status want, size_t *evals,
                         size_t *cached, rf_error *err)
{
    traj_impact_table *t = NULL;
    rf_status st = traj_impact_table_build_watched(s, w, &t, err);
    if (st != want)
        fail_msg("build: status %d, want %d: %s", st, want, st != RF_OK ? err->msg : "");
    size_t nv, nt;
    double est;
    *evals = *cached = 0;
    if (t)
        traj_impact_table_info(t, &nv, &nt, evals, cached, &est);
    traj_impact_table_free(t);
}

static void test_store_resume_and_reuse(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    load_three(&s, "");
    size_t e0, c0, e, c;
    build_counts(&s, NULL, RF_OK, &e0, &c0, &err); /* without a store: every impact computed */
    rf_store *db = open_store("traj_impact_tables.sqlite");
    rf_model_side_store side = {db, side_put, side_each};
    traj_impact_store ts;
    traj_impact_store_from_side(&side, &ts);
    stopper p = {0, 20, 0};
    traj_table_watch w = {&p.stop, stop_after, &p, &ts, NULL};
    build_counts(&s, &w, RF_EINTERRUPTED, &e, &c, &err);
    assert_non_null(strstr(err.msg, "kept in the study store"));
    assert_int_equal(p.computed, 20);
    traj_table_watch w2 = {NULL, NULL, NULL, &ts, NULL};
    build_counts(&s, &w2, RF_OK, &e, &c, &err); /* resumed: only the missing ones */
    print_message("store: %zu impacts without it; interrupted after 20, resumed computed %zu and took %zu\n", e0, e, c);
    assert_int_equal(c, 20);
    assert_int_equal(e, e0 - 20);
    build_counts(&s, &w2, RF_OK, &e, &c, &err); /* a second study on the store: all reused */
    assert_int_equal(e, 0);
    assert_int_equal(c, e0);
    /* through the model: prepare builds the table from the store alone */
    rf_model m;
    assert_int_equal(rf_traj_model_create(&s, 0, NULL, NULL, &m, &err), RF_OK);
    rf_model_set_side_store(&m, &side);
    char *log = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&log, &len);
    assert_int_equal(rf_model_prepare(&m, f, &err), RF_OK);
    fclose(f);
    char want[80];
    snprintf(want, sizeof want, "0 impacts computed, %zu taken from", e0);
    if (!strstr(log, want))
        fail_msg("prepare's log lacks '%s': %s", want, log);
    free(log);
    rf_model_free(&m);
    /* damaged values: refused, naming the row */
    traj_impact_setup setup;
    assert_int_equal(traj_impact_setup_material(&setup, &s, 1, &err), RF_OK);
    double bad[6] = {40, 0.1, 0.5, 5, 0.5, 0};
    assert_int_equal(ts.put(ts.user, &setup, bad, &err), RF_EMODEL); /* never stored through the table's put */
    assert_non_null(strstr(err.msg, "R_n must lie in [0, 1]"));
    char id[300], key[400];
    traj_impact_setup_key(&setup, id, sizeof id);
    snprintf(key, sizeof key, "impact_model %s", id);
    assert_int_equal(side.put(side.user, key, bad, 6, &err), RF_OK); /* a damaged store */
    build_counts(&s, &w2, RF_EIO, &e, &c, &err);
    if (!strstr(err.msg, "R_n must lie in [0, 1]") || !strstr(err.msg, "damaged"))
        fail_msg("%s", err.msg);
    rf_store_close(db);
    db = open_store("traj_impact_tables.sqlite");
    side.user = db;
    double r1[6] = {3, 0.2, 0.5, 0.6, 0.7, 1}, r2[6] = {3, 0.2, 0.5, 0.61, 0.7, 1};
    assert_int_equal(ts.put(ts.user, &setup, r1, &err), RF_OK);
    assert_int_equal(ts.put(ts.user, &setup, r1, &err), RF_OK); /* an identical repeat: once */
    build_counts(&s, &w2, RF_OK, &e, &c, &err);
    assert_int_equal(ts.put(ts.user, &setup, r2, &err), RF_OK);
    build_counts(&s, &w2, RF_EIO, &e, &c, &err);
    if (!strstr(err.msg, "two different results"))
        fail_msg("%s", err.msg);
    rf_store_close(db);
    remove("traj_impact_tables.sqlite");
    rf_traj_spec_free(&s);
}

/* ---- a terrain model: the table in the run ---- */

static double slope(double x, double y) { return 0.5 * y + 0.01 * x; }

static void test_terrain_table_in_run(void **state)
{
    (void)state;
    char dir[] = "/tmp/rf_impact_tables_XXXXXX";
    const terrain_fixture t = {30, 60, 2, slope, 60};
    assert_int_equal(fixture_setup(dir, &t), 0);
    char yaml[2048], cache[300];
    snprintf(cache, sizeof cache, "%s/cache.txt", dir);
    snprintf(yaml, sizeof yaml,
             "name: tt\n"
             "terrain: {dem: %s/dem.asc, materials: {raster: %s/classes.asc, classes: {1: rock, 2: talus}}}\n"
             "materials:\n"
             "  rock:  {R_n: 0.4, R_t: 0.8, friction_angle: 30, impact: {solver: hunter}}\n"
             "  talus: {R_n: 0.35, R_t: 0.75, friction_angle: 35, impact: {slope_E: 50e6, slope_density: 1800}}\n"
             "block: {shape: sphere, radius: 0.5, density: 2600}\n"
             "release: {points: [[30, 110]], height: 1, velocity: [0, 0, 0]}\n"
             "bounce: {law: impact_model, impact: {solver: rigid, tolerance: 0.02, cache: %s}}\n"
             "barriers: [{name: fence, line: [[2, 40], [58, 40]]}]\n"
             "samples: 2\n", dir, dir, cache);
    rf_traj_spec s;
    fixture_load(dir, "tt.yaml", yaml, &s);
    rf_model m;
    rf_error err;
    assert_int_equal(rf_traj_model_create(&s, 0, NULL, NULL, &m, &err), RF_OK);
    assert_int_equal(access(cache, F_OK), -1); /* nothing computed at load */
    atomic_int stop = 1;
    rf_model_set_interrupt(&m, &stop);
    assert_int_equal(rf_model_prepare(&m, NULL, &err), RF_EINTERRUPTED);
    atomic_store(&stop, 0);
    assert_int_equal(rf_model_prepare(&m, NULL, &err), RF_OK);
    assert_int_equal(access(cache, F_OK), 0);
    double y[64];
    assert_true(m.n_outputs <= 64);
    if (rf_model_eval(&m, NULL, y, &err) != RF_OK)
        fail_msg("%s", err.msg);
    rf_model_free(&m);
    /* the world of a standalone run: one grid per class, each its own model */
    rf_terrain_world *w;
    assert_int_equal(rf_terrain_world_create(&s, &w, &err), RF_OK);
    assert_int_equal(traj_impact_table_grids(w->impact_table), 2);
    double rn[2], rt, sp;
    for (size_t k = 0; k < 2; k++)
        traj_impact_table_lookup(w->impact_table, k, 0.5, 10, 30 * DEG, &rn[k], &rt, &sp);
    assert_true(rn[0] - rn[1] > 0.05); /* the soft talus keeps less of v_n */
    rf_terrain_world_free(w);
    rf_traj_spec_free(&s);
    unlink(cache);
    fixture_teardown(dir, "tt.yaml");
}

/* The rows materials.NAME.impact.* and the impact inputs they feed are paired by index. */
static void test_rows_name_impact_inputs(void **state)
{
    (void)state;
    size_t found = 0;
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        for (size_t k = 0; tb->owner == RF_TRAJ_OWNER_MATERIAL && k < tb->n_rows; k++) {
            if (strncmp(tb->rows[k].key, "impact.", 7))
                continue;
            size_t i = (tb->rows[k].offset - offsetof(rf_traj_material, impact.v)) / sizeof(double);
            assert_true(i < RF_TRAJ_IMPACT_N);
            assert_string_equal(tb->rows[k].key + 7, traj_impact_ground_field(i));
            found++;
        }
    }
    assert_int_equal(found, RF_TRAJ_IMPACT_N);
}

/* The soil layer's table preset (rock_mass_scale 100) applies to an FE setup
 * on a layer at any refinement, and enters the setup's key (with the
 * refinement), so rows computed without it are not reused. */
static void test_layer_preset_in_key(void **state)
{
    (void)state;
    traj_impact_setup s = {0};
    s.solver = RF_IMPACT_FEM, s.radius = 0.5, s.density = 2600, s.friction = 0.5, s.has_ground = 1;
    size_t k = 0;
    while (traj_impact_ground_field(k) && strcmp(traj_impact_ground_field(k), "layer_thickness"))
        k++;
    assert_non_null(traj_impact_ground_field(k));
    char key[300];
    assert_false(traj_impact_layer_preset(&s)); /* no layer */
    traj_impact_setup_key(&s, key, sizeof key);
    assert_null(strstr(key, "rock_mass_scale"));
    s.ground.v[k] = 1.0;
    assert_true(traj_impact_layer_preset(&s));
    traj_impact_setup_key(&s, key, sizeof key);
    assert_non_null(strstr(key, ",rock_mass_scale=100"));
    assert_non_null(strstr(key, ",fem_ground=stable")); /* the FE's ground, docs/soil-impacts.md 4b */
    char key0[300];
    memcpy(key0, key, sizeof key);
    s.refinement = 2; /* a mesh of the user's own: the rock scaled too, the key says both */
    assert_true(traj_impact_layer_preset(&s));
    traj_impact_setup_key(&s, key, sizeof key);
    assert_non_null(strstr(key, ",rock_mass_scale=100"));
    assert_non_null(strstr(key, "ref=2,"));
    assert_string_not_equal(key, key0);
    s.refinement = 0, s.solver = RF_IMPACT_MDR;
    assert_false(traj_impact_layer_preset(&s));
    traj_impact_setup_key(&s, key, sizeof key); /* no FE: neither FE setting */
    assert_null(strstr(key, "rock_mass_scale"));
    assert_null(strstr(key, "fem_ground"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_old_behaviour_bit_identical),
        cmocka_unit_test(test_per_material_grids),
        cmocka_unit_test(test_bounce_uses_material),
        cmocka_unit_test(test_radius_axis_flat_for_hunter),
        cmocka_unit_test(test_radius_axis_refined),
        cmocka_unit_test(test_checked_at_load),
        cmocka_unit_test(test_cache_per_material),
        cmocka_unit_test(test_identity_covers_impact),
        cmocka_unit_test(test_rows_name_impact_inputs),
        cmocka_unit_test(test_store_resume_and_reuse),
        cmocka_unit_test(test_terrain_table_in_run),
        cmocka_unit_test(test_layer_preset_in_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
