/* test_impact_surrogate.c - the impact model's surrogate over the bound
 * material parameters (traj_impact_surrogate.c), with a model whose
 * dependence on the soil's layer_E and layer_friction_angle is a known closed
 * form (put in place of the impact model through the table's watch):
 *  - the reported error is a prediction bound: at 400 independent random
 *    points (another sequence than the checks) at most 1/4 miss by more than
 *    it (for N = 16 exchangeable checks the chance that one new point exceeds
 *    their maximum is 1/(N+1) = 6 %; the fraction over the 400 is Beta(1, 16)
 *    distributed, above 0.25 with probability 0.75^16 = 1 %), and the checks
 *    are no nodes (their miss is not zero);
 *  - convergence: a tighter tolerance adds parameter nodes and the largest
 *    true error at the 400 points falls (by >= 2x over a 16x tighter tolerance);
 *  - the store: a second surrogate on the same store computes no impact,
 *    the check runs included, and reports the same error;
 *  - through the trajectory model (a study's path): the bound layer_E and
 *    friction angle change the Monte Carlo's outputs at every point; the
 *    model's evaluation at a point equals a run on the surrogate's table
 *    there; a binding that would change nothing is refused. */
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
#include "trajectory/traj_impact_surrogate.h"
#include "trajectory/traj_internal.h"

#define DEG (3.14159265358979323846 / 180)

static const char *file_text =
    "profile: {points: [[0, 30], [30, 12], [60, 4], [100, 0]], materials: [rock, soil, soil]}\n"
    "materials: {rock: {R_n: 0.3, R_t: 0.8, friction_angle: 25},\n"
    "  soil: {R_n: 0.2, R_t: 0.6, friction_angle: 30, impact: {solver: fem, layer_thickness: 0.5,\n"
    "         layer_E: 50e6, layer_friction_angle: 30}}}\n"
    "block: {shape: sphere, radius: 0.4, density: 2600}\n"
    "release: {x: 1, y: 30.5, vx: 2}\n"
    "bounce: {law: impact_model, impact: {solver: hunter, tolerance: %g, speeds: [0.5, 30]}}\n"
    "samples: 30\n"
    "collectors: [{name: c, x: 70}]\n";

static const char *paths[2] = {"materials.soil.impact.layer_E", "materials.soil.impact.layer_friction_angle"};
static const double lo[2] = {20e6, 25}, hi[2] = {100e6, 40};

static void load(double tol, rf_traj_spec *s)
{
    char y[2048];
    rf_error err;
    snprintf(y, sizeof y, file_text, tol);
    if (rf_traj_load_buffer("t.yaml", y, strlen(y), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

/* The known model: R_n grows like sqrt(E), falls with v_n and incidence;
 * R_t falls with tan(phi); the rock (no own ground) is constant. */
static void known(double E, double phi_deg, double vn, double theta, double c[3])
{
    c[0] = 0.08 + 0.45 * sqrt(E / 1e8) * (1 - 0.3 * sin(theta)) / (1 + 0.04 * vn);
    c[1] = 0.95 - 0.5 * tan(phi_deg * DEG) * (0.5 + 0.5 * cos(theta));
    c[2] = 0;
}

static size_t model_calls;

static rf_status model(const struct traj_impact_setup_s *s, double vn, double theta, double c[3], rf_error *err)
{
    (void)err;
    model_calls++;
    if (!s->has_ground) {
        c[0] = 0.3, c[1] = 0.8, c[2] = 0;
        return RF_OK;
    }
    known(s->ground.v[6], s->ground.v[12], vn, theta, c);
    return RF_OK;
}

static traj_impact_surrogate *build(const rf_traj_spec *s, const traj_impact_store *store, traj_impact_surrogate_info *i)
{
    traj_impact_surrogate *sur;
    rf_error err;
    char *const p[2] = {(char *)paths[0], (char *)paths[1]};
    assert_int_equal(traj_impact_surrogate_for_model(s, 2, p, lo, hi, 16, &sur, &err), RF_OK);
    assert_non_null(sur);
    traj_table_watch w = {NULL, NULL, NULL, store, model};
    if (traj_impact_surrogate_build(sur, &w, NULL, &err) != RF_OK)
        fail_msg("%s", err.msg);
    traj_impact_surrogate_get(sur, i);
    return sur;
}

/* The true error at 400 points of a sequence other than the checks': the largest, and the fraction above `bound`. */
static void true_error(const rf_traj_spec *s, const traj_impact_surrogate *sur, double bound, double *worst,
                       double *above)
{
    size_t n_above = 0, n = 400;
    *worst = 0;
    for (size_t i = 0; i < n; i++) {
        double x[2] = {lo[0] + (hi[0] - lo[0]) * rf_traj_uniform(77, 0, i), lo[1] + (hi[1] - lo[1]) * rf_traj_uniform(77, 1, i)};
        double vn = s->impact_speed_min * pow(s->impact_speed_max / s->impact_speed_min, rf_traj_uniform(77, 2, i));
        double th = s->impact_max_incidence * rf_traj_uniform(77, 3, i), c[3], q[3];
        rf_error err;
        assert_int_equal(traj_impact_surrogate_lookup_at(sur, x, 1, 0.4, vn, th, q, &err), RF_OK);
        known(x[0], x[1], vn, th, c);
        double e = fmax(fabs(q[0] - c[0]), fabs(q[1] - c[1]));
        *worst = fmax(*worst, e);
        n_above += e > bound;
    }
    *above = (double)n_above / (double)n;
}

static void test_reported_error_bounds_true_error(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(0.005, &s);
    traj_impact_surrogate_info i;
    traj_impact_surrogate *sur = build(&s, NULL, &i);
    double bound = fmax(i.err_rn, i.err_rt), worst, above;
    true_error(&s, sur, bound, &worst, &above);
    print_message("surrogate: grid %zu x %zu, %zu tables, reported R_n %.3g R_t %.3g; true: largest %.3g, "
                  "%.1f %% of 400 points above the reported\n", i.nodes[0], i.nodes[1], i.tables, i.err_rn, i.err_rt,
                  worst, 100 * above);
    assert_int_equal(i.check_runs, 16);
    assert_true(bound > 0);    /* the checks are not nodes */
    assert_true(above <= 0.25);
    traj_impact_surrogate_free(sur);
    rf_traj_spec_free(&s);
}

static void test_convergence(void **state)
{
    (void)state;
    double tol[3] = {0.04, 0.01, 0.0025}, worst[3], above;
    size_t nodes[3];
    for (int k = 0; k < 3; k++) {
        rf_traj_spec s;
        load(tol[k], &s);
        traj_impact_surrogate_info i;
        traj_impact_surrogate *sur = build(&s, NULL, &i);
        true_error(&s, sur, 1, &worst[k], &above);
        nodes[k] = i.nodes[0] * i.nodes[1];
        print_message("tolerance %g: %zu parameter nodes, %zu tables, largest true error %.4g (reported %.4g)\n",
                      tol[k], nodes[k], i.tables, worst[k], fmax(i.err_rn, i.err_rt));
        traj_impact_surrogate_free(sur);
        rf_traj_spec_free(&s);
    }
    assert_true(nodes[0] < nodes[2]);
    assert_true(worst[1] <= worst[0] && worst[2] <= worst[1]);
    assert_true(worst[2] * 2 <= worst[0]);
}

/* ---- the store ---- */

static rf_status side_put(void *user, const char *key, const double *row, size_t width, rf_error *err)
{
    return rf_store_side_put(user, key, row, width, err);
}

static rf_status side_each(void *user, const char *key, size_t width, rf_status (*fn)(void *u, const double *row),
                           void *u, rf_error *err)
{
    return rf_store_side_each(user, key, width, fn, u, err);
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

static void test_store_reuse(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(0.01, &s);
    rf_store *db = open_store("impact_surrogate.sqlite");
    rf_model_side_store side = {db, side_put, side_each};
    traj_impact_store ts;
    traj_impact_store_from_side(&side, &ts);
    traj_impact_surrogate_info a, b;
    model_calls = 0;
    traj_impact_surrogate_free(build(&s, &ts, &a));
    size_t first = model_calls;
    model_calls = 0;
    traj_impact_surrogate_free(build(&s, &ts, &b));
    print_message("store: first build %zu model calls (%zu table impacts, %zu check runs); second %zu calls, "
                  "%zu + %zu from the store\n", first, a.computed, a.check_computed, model_calls, b.from_store,
                  b.check_from_store);
    assert_true(first > 0 && a.check_computed == 16);
    assert_int_equal(model_calls, 0);
    assert_int_equal(b.computed, 0);
    assert_int_equal(b.check_computed, 0);
    assert_int_equal(b.check_from_store, 16);
    assert_true(b.err_rn == a.err_rn && b.err_rt == a.err_rt);
    rf_store_close(db);
    remove("impact_surrogate.sqlite");
    rf_traj_spec_free(&s);
}


/* ---- the real impact model: Hunter's elastic wave loss, bound slope_E ---- */

static const char *hunter_text =
    "profile: {points: [[0, 30], [30, 12], [60, 4], [100, 0]], materials: [rock, soil, soil]}\n"
    "materials: {rock: {R_n: 0.3, R_t: 0.8, friction_angle: 25},\n"
    "  soil: {R_n: 0.2, R_t: 0.6, friction_angle: 30, impact: {solver: hunter, slope_E: 1e9, slope_density: 2000}}}\n"
    "block: {shape: sphere, radius: 0.4, density: 2600}\n"
    "release: {x: 1, y: 30.5, vx: 2}\n"
    "bounce: {law: impact_model, impact: {solver: hunter, tolerance: 0.005, speeds: [0.5, 30]}}\n"
    "samples: 30\n"
    "collectors: [{name: c, x: 70}]\n";

/* Hunter: R_n = sqrt(1 - A (v_n / c0)^0.6), c0 = sqrt(E / rho), A = 1.04 (src/impact/hertz.c's law, written out). */
static double hunter_rn(double E, double vn) { return sqrt(1 - 1.04 * pow(vn / sqrt(E / 2000), 0.6)); }

/* The surrogate over slope_E of the real adapter against the closed form at 300 independent points. */
static void test_hunter_surrogate_against_closed_form(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    assert_int_equal(rf_traj_load_buffer("h.yaml", hunter_text, strlen(hunter_text), &s, &err), RF_OK);
    char *const p[1] = {"materials.soil.impact.slope_E"};
    double a[1] = {0.1e9}, b[1] = {5e9};
    traj_impact_surrogate *sur;
    assert_int_equal(traj_impact_surrogate_for_model(&s, 1, p, a, b, 16, &sur, &err), RF_OK);
    if (traj_impact_surrogate_build(sur, NULL, NULL, &err) != RF_OK)
        fail_msg("%s", err.msg);
    traj_impact_surrogate_info i;
    traj_impact_surrogate_get(sur, &i);
    double worst = 0;
    size_t above = 0;
    for (size_t k = 0; k < 300; k++) {
        double x = a[0] + (b[0] - a[0]) * rf_traj_uniform(99, 0, k);
        double vn = 0.5 * pow(60, rf_traj_uniform(99, 1, k)), th = s.impact_max_incidence * rf_traj_uniform(99, 2, k);
        double q[3];
        assert_int_equal(traj_impact_surrogate_lookup_at(sur, &x, 1, 0.4, vn, th, q, &err), RF_OK);
        double e = fabs(q[0] - hunter_rn(x, vn));
        worst = fmax(worst, e);
        above += e > i.err_rn;
    }
    print_message("hunter over slope_E [0.1, 5] GPa: %zu nodes, reported R_n %.3g, true largest %.3g, %zu of 300 "
                  "above the reported\n", i.nodes[0], i.err_rn, worst, above);
    assert_true(i.err_rn > 0);
    assert_true(above <= 75);
    traj_impact_surrogate_free(sur);
    rf_traj_spec_free(&s);
}

static size_t output_index(const rf_model *m, const char *name)
{
    for (size_t k = 0; k < m->n_outputs; k++)
        if (!strcmp(m->output_names[k], name))
            return k;
    fail_msg("no output %s", name);
    return 0;
}

/* Through the trajectory model: the bound modulus changes the outputs at every
 * point, each point's run is the run on the surrogate's table there, the error
 * is reported in its own channel (rf_model.surrogate_error, with the figures of
 * a surrogate built alone over the same box), not as a warning; a binding that
 * changes nothing is refused. */
static void test_model_binds_impact_input(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    assert_int_equal(rf_traj_load_buffer("h.yaml", hunter_text, strlen(hunter_text), &s, &err), RF_OK);
    const char *bind[1] = {"materials.soil.impact.slope_E"};
    rf_model m;
    assert_int_equal(rf_traj_model_create(&s, 1, bind, bind, &m, &err), RF_OK);
    double a = 0.1e9, b = 5e9;
    assert_int_equal(rf_traj_model_set_ranges(&m, &a, &b, &err), RF_OK);
    char *log = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&log, &len);
    assert_int_equal(rf_model_prepare(&m, f, &err), RF_OK);
    fclose(f);
    assert_non_null(strstr(log, "impact surrogate error R_n"));
    free(log);
    size_t k = output_index(&m, "c_total_energy_p95"), r = output_index(&m, "runout_x_p50");
    double x[3] = {0.1e9, 1e9, 5e9}, y[3][256];
    assert_true(m.n_outputs <= 256);
    for (int p = 0; p < 3; p++) {
        if (rf_model_eval(&m, &x[p], y[p], &err) != RF_OK)
            fail_msg("%s", err.msg);
        print_message("slope_E %g Pa: c_total_energy_p95 %.6g J, runout_x_p50 %.4g m\n", x[p], y[p][k], y[p][r]);
    }
    for (int p = 0; p < 2; p++)
        assert_true(y[p][k] != y[p + 1][k] || y[p][r] != y[p + 1][r]);
    /* the point's run is the Monte Carlo on the surrogate's table there: a second
     * surrogate over the same box (the same nodes) and traj_run_with give the same bits */
    traj_impact_surrogate *sur;
    char *const p1[1] = {(char *)bind[0]};
    assert_int_equal(traj_impact_surrogate_for_model(&s, 1, p1, &a, &b, TRAJ_SURROGATE_CHECKS, &sur, &err), RF_OK);
    assert_int_equal(traj_impact_surrogate_build(sur, NULL, NULL, &err), RF_OK);
    rf_traj_spec at;
    assert_int_equal(rf_traj_spec_copy(&s, &at, &err), RF_OK);
    assert_true(rf_traj_spec_set(&at, bind[0], x[1]));
    at.record = 0;
    traj_impact_table *t;
    assert_int_equal(traj_impact_surrogate_table(sur, &at, &t, &err), RF_OK);
    rf_traj_ensemble e;
    rf_traj_stats st;
    double again[256];
    assert_int_equal(traj_run_with(&at, 1, t, 0, &e, &err), RF_OK);
    assert_int_equal(rf_traj_stats_compute_spec(&at, &e, &st, &err), RF_OK);
    traj_model_outputs(&m, &at, &st, again);
    assert_memory_equal(again, y[1], m.n_outputs * sizeof(double));
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&e);
    traj_impact_table_free(t);
    traj_impact_surrogate_info si; /* the same box, nodes and checks: the model's figures */
    traj_impact_surrogate_get(sur, &si);
    traj_impact_surrogate_free(sur);
    rf_traj_spec_free(&at);
    char w[1024];
    assert_non_null(m.surrogate_error); /* its own channel, not the warnings */
    assert_true(m.surrogate_error(m.ctx, w, sizeof w) == 1);
    assert_non_null(strstr(w, "impact surrogate error R_n"));
    char expect[64];
    snprintf(expect, sizeof expect, "R_n %.3g, R_t %.3g", si.err_rn, si.err_rt);
    assert_non_null(strstr(w, expect));
    assert_true(!m.warnings || m.warnings(m.ctx, w, sizeof w) == 0);
    double z = 6e9; /* outside the box: refused */
    assert_int_not_equal(rf_model_eval(&m, &z, y[0], &err), RF_OK);
    assert_non_null(strstr(err.msg, "outside the range"));
    rf_model_free(&m);
    const char *rock[1] = {"materials.rock.impact.slope_E"};
    assert_int_not_equal(rf_traj_model_create(&s, 1, rock, rock, &m, &err), RF_OK);
    assert_non_null(strstr(err.msg, "names no impact model of its own"));
    rf_traj_spec_free(&s);
}

/* bounce.impact.start_nodes and bounce.impact.surrogate_nodes: the first grids.
 * At a tolerance no midpoint misses by (0.5), a table keeps its 3 x 3 first
 * grid (v_n geometric, incidence uniform: its middle node is exact) and the
 * surrogate its 2 x 2 corners, with 4 tested midpoints (8 tables); at a
 * corner and a table node the surrogate is the model itself. */
static void test_first_grids(void **state)
{
    (void)state;
    char y[2048];
    rf_error err;
    rf_traj_spec s;
    snprintf(y, sizeof y, file_text, 0.5);
    char *b = strstr(y, "speeds: [0.5, 30]");
    assert_non_null(b);
    memcpy(b, "speeds: [0.5, 32]", 17); /* 0.5 .. 32: the middle node is 4 m/s */
    char *e = strstr(y, "}}\nsamples");
    assert_non_null(e);
    char tail[256];
    snprintf(tail, sizeof tail, "%s", e);
    snprintf(e, sizeof y - (size_t)(e - y), ", start_nodes: 3, surrogate_nodes: 2%s", tail);
    if (rf_traj_load_buffer("t.yaml", y, strlen(y), &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s.impact_start_nodes, 3);
    assert_int_equal(s.impact_surrogate_nodes, 2);
    traj_impact_surrogate_info i;
    traj_impact_surrogate *sur = build(&s, NULL, &i);
    assert_int_equal(i.nodes[0], 2);
    assert_int_equal(i.nodes[1], 2);
    assert_int_equal(i.tables, 8);
    double x[2] = {lo[0], hi[1]}, q[3], c[3];
    assert_int_equal(traj_impact_surrogate_lookup_at(sur, x, 1, 0.4, 4, s.impact_max_incidence / 2, q, &err), RF_OK);
    known(x[0], x[1], 4, s.impact_max_incidence / 2, c);
    assert_true(fabs(q[0] - c[0]) < 1e-12 && fabs(q[1] - c[1]) < 1e-12);
    /* off the nodes (v_n 2 m/s, between 0.5 and 4): interpolated, not the model */
    assert_int_equal(traj_impact_surrogate_lookup_at(sur, x, 1, 0.4, 2, s.impact_max_incidence / 2, q, &err), RF_OK);
    known(x[0], x[1], 2, s.impact_max_incidence / 2, c);
    assert_true(fabs(q[0] - c[0]) > 1e-6);
    traj_impact_surrogate_free(sur);
    traj_impact_table *t;
    traj_table_watch w = {NULL, NULL, NULL, NULL, model};
    assert_int_equal(traj_impact_table_build_watched(&s, &w, &t, &err), RF_OK);
    size_t nv, nt, evals, cached;
    double est;
    traj_impact_table_info(t, &nv, &nt, &evals, &cached, &est);
    assert_int_equal(nv, 3);
    assert_int_equal(nt, 3);
    traj_impact_table_free(t);
    rf_traj_spec_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reported_error_bounds_true_error),
        cmocka_unit_test(test_convergence),
        cmocka_unit_test(test_store_reuse),
        cmocka_unit_test(test_hunter_surrogate_against_closed_form),
        cmocka_unit_test(test_model_binds_impact_input),
        cmocka_unit_test(test_first_grids),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
