/* test_trajectory_impact.c - the `impact_model` bounce law: the adaptive
 * table of R_n, R_t and spin from rockfuzz's rigid impact model (Hunter's
 * e_n, Coulomb friction) reproduces the model at its nodes, misses it by no
 * more than a small multiple of the tolerance at random points, and its
 * reported error estimate is of the size of the misses actually observed;
 * a trajectory under the law bounces with the tabulated coefficients. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_traj_util.h"
#include "test_util.h"
#include "trajectory/traj_impact.h"
#include "trajectory/traj_internal.h"

static const char *yaml =
    "profile: {points: [[-10, 5.773502691896258], [10, -5.773502691896258]], material: m}\n"
    "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 25}}\n"
    "block: {shape: sphere, radius: 0.5, density: 2600}\n"
    "release: {x: 0, y: 5.1}\n"
    "bounce: {law: impact_model, impact: {solver: rigid, tolerance: 0.005}}\n";

static void test_table_accuracy(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    if (rf_traj_load_buffer("im.yaml", yaml, strlen(yaml), &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    traj_impact_table *t;
    assert_int_equal(traj_impact_table_build(&s, &t, &err), RF_OK);
    traj_impact_setup setup;
    assert_int_equal(traj_impact_setup_init(&setup, &s, &err), RF_OK);
    size_t nv, nt, evals, cached;
    double est, worst = 0;
    traj_impact_table_info(t, &nv, &nt, &evals, &cached, &est);
    for (int k = 0; k < 400; k++) {
        double v = 0.25 * pow(160, rf_traj_uniform(3, 0, (uint64_t)k)), th = 80 * rf_traj_uniform(3, 1, (uint64_t)k) * 3.14159265358979 / 180;
        double rn, rt, sp, an, at, as;
        traj_impact_table_eval(t, v, th, &rn, &rt, &sp);
        assert_int_equal(traj_impact_coefficients(&setup, v, th, &an, &at, &as, &err), RF_OK);
        worst = fmax(worst, fmax(fabs(rn - an), fabs(rt - at)));
    }
    print_message("table %zu x %zu nodes, %zu impacts computed; estimate %.3g, worst of 400 random points %.3g "
                  "(tolerance 0.005)\n", nv, nt, evals, est, worst);
    assert_true(worst <= 3 * 0.005);
    assert_true(est <= 3 * 0.005);
    assert_true(worst <= 3 * est + 1e-12 && est <= worst * 3 + 1e-12);
    traj_impact_table_free(t);
    rf_traj_spec_free(&s);
}

/* Vertical fall at V onto a 30 deg slope: the bounce uses the table's
 * R_n at (V cos 30, 30 deg); the table matches the model there within the tolerance. */
static void test_bounce_uses_table(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    assert_int_equal(rf_traj_load_buffer("im.yaml", yaml, strlen(yaml), &s, &err), RF_OK);
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
    double b = 30 * 3.14159265358979323846 / 180, nx = sin(b), ny = cos(b);
    double vn_in = -(m->vx_in * nx + m->vy_in * ny), vn_out = m->vx_out * nx + m->vy_out * ny;
    traj_impact_setup setup;
    double an, at, as;
    assert_int_equal(traj_impact_setup_init(&setup, &s, &err), RF_OK);
    assert_int_equal(traj_impact_coefficients(&setup, vn_in, b, &an, &at, &as, &err), RF_OK);
    assert_true(fabs(vn_out / vn_in - an) <= 0.005);
    assert_true(an > 0.5 && an < 1); /* elastic granite: Hunter's small wave loss */
    free(r.impacts);
    free(r.events);
    rf_traj_world_free(w);
    rf_traj_spec_free(&s);
}

/* In a study the table is built once and shared by every evaluation; the
 * model stays a deterministic function of its inputs. */
static void test_model_shares_table(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    assert_int_equal(rf_traj_load_buffer("im.yaml", yaml, strlen(yaml), &s, &err), RF_OK);
    s.samples = 20;
    const char *names[1] = {"vx"}, *paths[1] = {"release.vx"};
    rf_model m;
    assert_int_equal(rf_traj_model_create(&s, 1, names, paths, &m, &err), RF_OK);
    double x = 1, y1[32], y2[32];
    assert_true(m.n_outputs <= 32);
    assert_int_equal(rf_model_eval(&m, &x, y1, &err), RF_OK);
    assert_int_equal(rf_model_eval(&m, &x, y2, &err), RF_OK);
    assert_memory_equal(y1, y2, m.n_outputs * sizeof(double));
    x = 3;
    assert_int_equal(rf_model_eval(&m, &x, y2, &err), RF_OK);
    assert_true(memcmp(y1, y2, m.n_outputs * sizeof(double)) != 0);
    rf_model_free(&m);
    rf_traj_spec_free(&s);
}

/* The test file with bounce.impact.cache: traj_impact_cache.txt, which starts empty. */
static void load_with_cache(rf_traj_spec *s)
{
    remove("traj_impact_cache.txt");
    char buf[2048];
    snprintf(buf, sizeof buf, "%s", yaml);
    char *p = strstr(buf, "tolerance: 0.005}");
    snprintf(p, sizeof buf - (size_t)(p - buf), "tolerance: 0.005, cache: traj_impact_cache.txt}}\n");
    rf_error err;
    if (rf_traj_load_buffer("im.yaml", buf, strlen(buf), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

/* bounce.impact.cache: the second table reads every impact from the file
 * the first wrote, computes none, and is the same table. */
static void test_cache(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    load_with_cache(&s);
    traj_impact_table *t[2];
    size_t nv, nt, evals[2], cached[2];
    double est;
    for (int k = 0; k < 2; k++) {
        assert_int_equal(traj_impact_table_build(&s, &t[k], &err), RF_OK);
        traj_impact_table_info(t[k], &nv, &nt, &evals[k], &cached[k], &est);
    }
    assert_true(evals[0] > 0 && cached[0] == 0);
    assert_true(evals[1] == 0 && cached[1] == evals[0]);
    for (int k = 0; k < 50; k++) {
        double v = 0.3 + k, th = 0.03 * k, a[3], b[3];
        traj_impact_table_eval(t[0], v, th, &a[0], &a[1], &a[2]);
        traj_impact_table_eval(t[1], v, th, &b[0], &b[1], &b[2]);
        assert_memory_equal(a, b, sizeof a);
    }
    traj_impact_table_free(t[0]);
    traj_impact_table_free(t[1]);
    rf_traj_spec_free(&s);
}

/* Build a table from spec s and return its status; *cached gets how many of its impacts came from the file. */
static rf_status build_cached(const rf_traj_spec *s, size_t *evals, size_t *cached, rf_error *err)
{
    traj_impact_table *t = NULL;
    rf_status st = traj_impact_table_build(s, &t, err);
    size_t nv, nt;
    double est;
    if (st == RF_OK)
        traj_impact_table_info(t, &nv, &nt, evals, cached, &est);
    traj_impact_table_free(t);
    return st;
}

/* Every row read from the cache is checked: a non-finite value, an R_n out of
 * [0, 1] and a second, different result for the same impact are refused with
 * the file and line; an identical repeat is kept once and counted once. */
static void test_cache_rows_checked(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    load_with_cache(&s);
    size_t evals, cached, n0;
    assert_int_equal(build_cached(&s, &n0, &cached, &err), RF_OK);
    /* the whole file once more: the same impacts, kept and counted once */
    FILE *f = fopen("traj_impact_cache.txt", "r");
    assert_non_null(f);
    char all[65536], first[512], key[256];
    size_t len = fread(all, 1, sizeof all - 1, f);
    fclose(f);
    all[len] = '\0';
    snprintf(first, sizeof first, "%.*s", (int)(strchr(all, '\n') - all + 1), all);
    double r[5];
    assert_int_equal(sscanf(first, "%255s %lf %lf %lf %lf %lf", key, &r[0], &r[1], &r[2], &r[3], &r[4]), 6);
    f = fopen("traj_impact_cache.txt", "a");
    assert_non_null(f);
    fputs(all, f);
    fclose(f);
    assert_int_equal(build_cached(&s, &evals, &cached, &err), RF_OK);
    assert_int_equal(evals, 0);
    assert_int_equal(cached, n0);
    size_t lines = 2 * (size_t)n0;
    const char *bad[3][2] = {{"nan", "not a finite number"}, {"5", "R_n must lie in [0, 1]"},
                             {"other", "other results than at line 1"}};
    for (int k = 0; k < 3; k++) {
        char row[600];
        double rn = k == 2 ? r[2] * 0.5 : 0;
        if (k == 2)
            snprintf(row, sizeof row, "%s %.17g %.17g %.17g %.17g %.17g\n", key, r[0], r[1], rn, r[3], r[4]);
        else
            snprintf(row, sizeof row, "%s %.17g %.17g %s %.17g %.17g\n", key, r[0] * 3.1, r[1], bad[k][0], r[3], r[4]);
        f = fopen("traj_impact_cache.txt", "w");
        assert_non_null(f);
        fputs(all, f);
        fputs(all, f);
        fputs(row, f);
        fclose(f);
        assert_int_not_equal(build_cached(&s, &evals, &cached, &err), RF_OK);
        char where[64];
        snprintf(where, sizeof where, "traj_impact_cache.txt:%zu:", lines + 1);
        if (!strstr(err.msg, where) || !strstr(err.msg, bad[k][1]))
            fail_msg("case %d: %s", k, err.msg);
    }
    rf_traj_spec_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_accuracy),
        cmocka_unit_test(test_bounce_uses_table),
        cmocka_unit_test(test_model_shares_table),
        cmocka_unit_test(test_cache),
        cmocka_unit_test(test_cache_rows_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
