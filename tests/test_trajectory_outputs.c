/* test_trajectory_outputs.c - what a barrier designer reads: passing heights
 * of the lowest point and the centre (exact for a sphere rolling on a line),
 * total = translational + rotational energy on every crossing, the chosen
 * percentiles, exceedance probabilities and runout histogram against a
 * brute-force computation over the per-sample arrays, the `outputs:` keys and
 * their errors, and the study model's output names and values. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_util.h"
#include "test_traj_util.h"

#define PI 3.14159265358979323846

static void load(const char *yaml, rf_traj_spec *s)
{
    rf_error err;
    if (rf_traj_load_buffer("out.yaml", yaml, strlen(yaml), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

static void simulate(const rf_traj_spec *s, rf_traj_crossing *cross, rf_traj_result *res)
{
    rf_error err;
    rf_traj_world *w;
    memset(res, 0, sizeof *res);
    res->crossings = cross;
    assert_int_equal(rf_traj_world_create(s, &w, &err), RF_OK);
    assert_int_equal(rf_traj_simulate(w, s, s->seed, 0, res, &err), RF_OK);
    rf_traj_world_free(w);
}

/* A sphere (r = 0.5) rolling on a line of slope angle b past five lines, the
 * last a barrier that holds it: its lowest point is on the ground (height 0)
 * and its centre r above it, exactly; rolling without slip (after the first
 * metres of slip from the release without spin): E_rot = m v^2 / 5. */
static void rolling_heights(double b_deg)
{
    double b = b_deg * PI / 180, L = 100, top = L * tan(b);
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[0, %.17g], [%.17g, 0]], material: m}\n"
             "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.05}}\n"
             "block: {shape: sphere, radius: 0.5, density: 2600}\n"
             "release: {x: 0, y: %.17g, vx: %.17g, vy: %.17g}\n"
             "collectors: [{name: a, x: 5.5}, {name: b, x: 9.1}, {name: c, x: 13.7}, {name: d, x: 17.3},\n"
             "             {name: barrier, x: 20.25, capacity: 1e12, height: 3}]\n",
             top, L, top, 6 * cos(b), -6 * sin(b));
    rf_traj_spec s;
    load(yaml, &s);
    rf_traj_crossing c[5];
    rf_traj_result res;
    simulate(&s, c, &res);
    double m = 4.0 / 3.0 * PI * 0.125 * 2600;
    for (int k = 0; k < 5; k++) {
        assert_true(c[k].reached);
        assert_true(c[k].height_lowest == 0);
        assert_true(c[k].height_centre == 0.5);
        assert_true(c[k].normal_height == 0);
        assert_true(c[k].total_energy == c[k].translational_energy + c[k].rotational_energy);
        assert_close(c[k].translational_energy, 0.5 * m * c[k].speed * c[k].speed, 1e-13);
        assert_close(c[k].rotational_energy, 0.2 * m * c[k].speed * c[k].speed, 1e-12);
    }
    assert_true(c[4].stopped_by_barrier);
    rf_traj_spec_free(&s);
}

static void test_rolling_height_flat(void **state)
{
    (void)state;
    rolling_heights(0);
}

static void test_rolling_height_incline(void **state)
{
    (void)state;
    rolling_heights(17);
}

/* A point block in flight: its centre is its lowest point. */
static void test_point_block_heights(void **state)
{
    (void)state;
    rf_traj_spec s;
    load("profile: {points: [[-10, 20], [0, 20], [0, 0], [100, 0]], material: rock}\n"
         "materials: {rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}}\n"
         "block: {shape: point, mass: 1000}\n"
         "release: {x: -0.5, y: 20.5, vx: 5, vy: 2}\n"
         "collectors: [{name: c, x: 6}]\n", &s);
    rf_traj_crossing c[1];
    rf_traj_result res;
    simulate(&s, c, &res);
    double G = 9.81, tc = 6.5 / 5;
    assert_close(c[0].height_lowest, 20.5 + 2 * tc - 0.5 * G * tc * tc, 1e-12);
    assert_true(c[0].height_centre == c[0].height_lowest);
    assert_true(c[0].rotational_energy == 0 && c[0].total_energy == c[0].translational_energy);
    rf_traj_spec_free(&s);
}

static const char *ensemble_yaml =
    "profile: {points: [[0, 60], [20, 45], [30, 44], [45, 20], [50, 19], [70, 5], [80, 6], [120, 0]], material: m}\n"
    "materials: {m: {R_n: {uniform: [0.2, 0.6]}, R_t: {normal: [0.8, 0.1], min: 0.5, max: 1}, friction_angle: 30,\n"
    "                roughness: 10, rolling_resistance: 0.1}}\n"
    "block: {shape: sphere, radius: 0.4, density: 2700}\n"
    "release: {x: 1, y: 62, vx: {uniform: [0, 5]}, vy: 0}\n"
    "bounce: {law: rigid_sphere}\n"
    "collectors: [{name: a, x: 40, energy_thresholds: [1e5, 3e5], height_thresholds: [0.5, 2]},\n"
    "             {name: b, x: 75, capacity: 2e5, height: 1.5, energy_thresholds: [5e4]}]\n"
    "outputs: {percentiles: [10, 50, 90, 95, 98, 99.5], runout_thresholds: [70, 90, 110], runout_bins: 9}\n"
    "samples: 613\nseed: 7\n";

static void test_total_energy_every_crossing(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(ensemble_yaml, &s);
    rf_traj_ensemble e;
    rf_error err;
    assert_int_equal(rf_traj_run(&s, 2, &e, &err), RF_OK);
    assert_ensemble_invariants(&s, &e);
    size_t reached = 0;
    double I_over_m = 0.4 * 0.4 * 0.4, m = 4.0 / 3.0 * PI * 0.064 * 2700;
    for (size_t i = 0; i < e.samples * 2; i++) {
        const rf_traj_crossing *c = &e.crossings[i];
        if (!c->reached)
            continue;
        reached++;
        assert_true(c->total_energy == c->translational_energy + c->rotational_energy);
        assert_true(c->height_centre == c->height_lowest + 0.4);
        assert_close(c->translational_energy, 0.5 * m * c->speed * c->speed, 1e-12);
        assert_true(c->rotational_energy >= 0 && I_over_m > 0);
    }
    assert_true(reached > e.samples / 2);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

/* Type 7 from its definition, independently: the rank (N - 1) p + 1 (1-based)
 * between the order statistics floor and ceil of it. */
static double brute_quantile(double *v, size_t n, double p)
{
    for (size_t i = 1; i < n; i++) /* insertion sort */
        for (size_t j = i; j > 0 && v[j - 1] > v[j]; j--) {
            double t = v[j];
            v[j] = v[j - 1], v[j - 1] = t;
        }
    double rank = (double)(n - 1) * p + 1;
    size_t lo = (size_t)rank;
    double frac = rank - (double)lo;
    return lo >= n ? v[n - 1] : v[lo - 1] + frac * (v[lo] - v[lo - 1]);
}

static void check_pct(const rf_traj_percentiles *p, const double *v, size_t n, const rf_traj_outputs *o)
{
    double *w = malloc(n * sizeof *w), mx = -INFINITY;
    assert_int_equal(p->n, o->n_percentiles);
    for (size_t k = 0; k < o->n_percentiles; k++) {
        memcpy(w, v, n * sizeof *w);
        assert_true(p->level[k] == o->percentiles[k]);
        assert_close(p->value[k], brute_quantile(w, n, o->percentiles[k] / 100), 1e-13);
    }
    for (size_t i = 0; i < n; i++)
        mx = fmax(mx, v[i]);
    assert_true(p->max == mx);
    free(w);
}

static double brute_above(const double *v, size_t n, size_t N, double x)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        k += v[i] > x;
    return (double)k / (double)N;
}

static void check_collector(const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st, size_t c)
{
    size_t N = e->samples, m = 0;
    double *E = malloc(N * sizeof *E), *H = malloc(N * sizeof *H), *V = malloc(N * sizeof *V);
    for (size_t i = 0; i < N; i++) {
        const rf_traj_crossing *x = &e->crossings[i * s->n_collectors + c];
        if (x->reached)
            E[m] = x->total_energy, H[m] = x->height_lowest, V[m++] = x->speed;
    }
    const rf_traj_collector_stats *cs = &st->collectors[c];
    assert_true(cs->reach_probability == (double)m / (double)N);
    check_pct(&cs->total_energy, E, m, &s->outputs);
    check_pct(&cs->height_lowest, H, m, &s->outputs);
    check_pct(&cs->speed, V, m, &s->outputs);
    const rf_traj_collector *col = &s->collectors[c];
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own;
    size_t n = rf_traj_thresholds(col, 0, t, &own);
    assert_int_equal(n, col->n_energy_thresholds + (col->capacity > 0));
    for (size_t k = 0; k < n; k++)
        assert_true(cs->p_energy_above[k] == brute_above(E, m, N, t[k]));
    n = rf_traj_thresholds(col, 1, t, &own);
    assert_int_equal(n, col->n_height_thresholds + (col->height > 0));
    for (size_t k = 0; k < n; k++)
        assert_true(cs->p_height_above[k] == brute_above(H, m, N, t[k]));
    free(E), free(H), free(V);
}

/* The ensemble of spec s on `threads` threads, its invariants asserted, and
 * its statistics with the spec's outputs settings. */
static void run_stats(const rf_traj_spec *s, int threads, rf_traj_ensemble *e, rf_traj_stats *st)
{
    rf_error err;
    assert_int_equal(rf_traj_run(s, threads, e, &err), RF_OK);
    assert_ensemble_invariants(s, e);
    assert_int_equal(rf_traj_stats_compute_spec(s, e, st, &err), RF_OK);
}

static void test_percentiles_exceedance_brute_force(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(ensemble_yaml, &s);
    rf_traj_ensemble e;
    rf_traj_stats st;
    run_stats(&s, 2, &e, &st);
    size_t N = e.samples;
    check_pct(&st.runout_x, e.runout_x, N, &s.outputs);
    check_pct(&st.rebound_height, e.rebound_height, N, &s.outputs);
    for (size_t k = 0; k < 3; k++)
        assert_true(st.p_runout_above[k] == brute_above(e.runout_x, N, N, s.outputs.runout_thresholds[k]));
    assert_true(st.p_runout_above[1] > 0 && st.p_runout_above[1] < 1);
    /* the barrier's own thresholds come first */
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own;
    assert_int_equal(rf_traj_thresholds(&s.collectors[1], 0, t, &own), 2);
    assert_true(own && t[0] == 2e5 && t[1] == 5e4);
    assert_int_equal(rf_traj_thresholds(&s.collectors[0], 1, t, &own), 2);
    assert_true(!own && t[0] == 0.5 && t[1] == 2);
    for (size_t c = 0; c < 2; c++)
        check_collector(&s, &e, &st, c);
    assert_true(st.collectors[0].p_energy_above[0] > 0);
    /* the fixed p50/p95/p99 stay (plots read them) */
    double *w = malloc(N * sizeof *w);
    memcpy(w, e.runout_x, N * sizeof *w);
    assert_close(st.runout_x.p95, brute_quantile(w, N, 0.95), 1e-13);
    free(w);
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

static void test_runout_histogram(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(ensemble_yaml, &s);
    rf_traj_ensemble e;
    rf_traj_stats st;
    run_stats(&s, 1, &e, &st);
    const rf_traj_histogram *h = &st.runout_histogram;
    size_t N = e.samples, sum = 0;
    assert_int_equal(h->bins, 9);
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < N; i++)
        lo = fmin(lo, e.runout_x[i]), hi = fmax(hi, e.runout_x[i]);
    assert_true(h->edge[0] == lo && h->edge[9] == hi);
    for (size_t k = 0; k < 9; k++) {
        size_t cnt = 0;
        for (size_t i = 0; i < N; i++)
            cnt += e.runout_x[i] >= h->edge[k] && (e.runout_x[i] < h->edge[k + 1] || (k == 8 && e.runout_x[i] == hi));
        assert_int_equal(h->count[k], cnt);
        assert_close(h->edge[k + 1] - h->edge[k], (hi - lo) / 9, 1e-9);
        sum += cnt;
    }
    assert_int_equal(sum, N);
    assert_int_equal(h->total, N);
    /* all values equal: one bin holding them all */
    double same[4] = {3, 3, 3, 3};
    rf_traj_histogram one;
    rf_traj_histogram_of(same, 4, 10, &one);
    assert_int_equal(one.bins, 1);
    assert_int_equal(one.count[0], 4);
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

static void test_percentile_names(void **state)
{
    (void)state;
    char b[32];
    rf_traj_percentile_name(50, b, sizeof b);
    assert_string_equal(b, "p50");
    rf_traj_percentile_name(99.5, b, sizeof b);
    assert_string_equal(b, "p99_5");
    /* the defaults: 50, 95, 99 */
    rf_traj_spec s;
    load("profile: {points: [[0, 1], [10, 0]], material: m}\nmaterials: {m: {R_n: 0.3, R_t: 0.8}}\n"
         "block: {mass: 1}\nrelease: {x: 1, y: 2}\n", &s);
    assert_int_equal(s.outputs.n_percentiles, 3);
    assert_true(s.outputs.percentiles[1] == 95 && s.outputs.runout_bins == 20);
    rf_traj_spec_free(&s);
}

static void expect_error(const char *tail, const char *msg)
{
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[0, 1], [10, 0]], material: m}\nmaterials: {m: {R_n: 0.3, R_t: 0.8}}\n"
             "block: {mass: 1}\nrelease: {x: 1, y: 2}\n%s", tail);
    rf_traj_spec s;
    rf_error err;
    assert_int_not_equal(rf_traj_load_buffer("bad.yaml", yaml, strlen(yaml), &s, &err), RF_OK);
    if (!strstr(err.msg, msg))
        fail_msg("expected '%s' in: %s", msg, err.msg);
}

static void test_outputs_errors(void **state)
{
    (void)state;
    expect_error("outputs: {percentiles: [50, 100]}\n", "bad.yaml:5: outputs.percentiles = [50, 100]: percentiles lie in (0, 100)");
    expect_error("outputs: {percentiles: [95, 50]}\n", "bad.yaml:5: outputs.percentiles = [95, 50]: the values must increase");
    expect_error("outputs: {runout_bins: 0}\n", "bad.yaml:5: outputs.runout_bins");
    expect_error("outputs: {bins: 3}\n", "bad.yaml:5: outputs.bins: unknown key");
    expect_error("collectors: [{name: c, x: 5, energy_thresholds: [-1]}]\n", "thresholds must be >= 0");
    expect_error("collectors: [{name: c, x: 5, height_thresholds: [2, 1]}]\n",
                 "bad.yaml:5: collectors.c.height_thresholds = [2, 1]: the values must increase");
    /* a spec built in code is checked too */
    rf_traj_spec s;
    rf_error err;
    load("profile: {points: [[0, 1], [10, 0]], material: m}\nmaterials: {m: {R_n: 0.3, R_t: 0.8}}\n"
         "block: {mass: 1}\nrelease: {x: 1, y: 2}\ncollectors: [{name: c, x: 5}]\n", &s);
    s.outputs.percentiles[1] = 100;
    assert_int_not_equal(rf_traj_spec_validate(&s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "outputs.percentiles[1] = 100: must lie in"));
    s.outputs.percentiles[1] = 95;
    s.collectors[0].n_height_thresholds = RF_TRAJ_MAX_THRESHOLDS;
    assert_int_not_equal(rf_traj_spec_validate(&s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "collectors.c.height_thresholds: 16 values; at most 15"));
    s.collectors[0].n_height_thresholds = 0;
    assert_int_equal(rf_traj_spec_validate(&s, &err), RF_OK);
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

/* The study model: names follow the chosen percentiles and thresholds, and
 * the values equal the ensemble's statistics at the bound inputs. */
static void test_study_model_outputs(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(ensemble_yaml, &s);
    const char *pn[1] = {"Rt"}, *pp[1] = {"materials.m.R_t.mean"};
    rf_model model;
    rf_error err;
    assert_int_equal(rf_traj_model_create(&s, 1, pn, pp, &model, &err), RF_OK);
    /* per collector 4 quantities x (6 levels + max) + reach + thresholds; runout, rebound; runout thresholds */
    assert_int_equal(model.n_outputs, (4 * 7 + 1 + 2 + 2) + (4 * 7 + 1 + 2 + 1) + 2 * 7 + 3);
    const char *names[] = {"a_total_energy_p10", "a_total_energy_p99_5", "a_total_energy_max", "a_height_lowest_p90",
                           "a_height_centre_p95", "a_speed_p98", "a_reach_probability",
                           "a_p_total_energy_above_100000J", "a_p_total_energy_above_300000J",
                           "a_p_height_lowest_above_0_5m", "a_p_height_lowest_above_2m",
                           "b_p_total_energy_above_capacity", "b_p_total_energy_above_50000J",
                           "b_p_height_lowest_above_barrier", "runout_x_p50", "runout_x_max", "rebound_height_p95",
                           "p_runout_x_above_70m", "p_runout_x_above_110m"};
    size_t idx[sizeof names / sizeof names[0]];
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        idx[k] = output_index(&model, names[k]);
    assert_string_equal(model.output_units[idx[0]], "J");
    assert_string_equal(model.output_units[idx[5]], "m/s");
    assert_string_equal(model.output_units[idx[3]], "m");
    double x = 0.7, *y = calloc(model.n_outputs, sizeof *y);
    assert_int_equal(model.eval(model.ctx, &x, y, &err), RF_OK);
    /* the same run by hand */
    rf_traj_spec s2;
    assert_int_equal(rf_traj_spec_copy(&s, &s2, &err), RF_OK);
    *rf_traj_spec_field(&s2, "materials.m.R_t.mean") = 0.7;
    s2.record = 0;
    rf_traj_ensemble e;
    rf_traj_stats st;
    run_stats(&s2, 1, &e, &st);
    const rf_traj_collector_stats *a = &st.collectors[0], *b = &st.collectors[1];
    double want[] = {a->total_energy.value[0], a->total_energy.value[5], a->total_energy.max, a->height_lowest.value[2],
                     a->height_centre.value[3], a->speed.value[4], a->reach_probability, a->p_energy_above[0],
                     a->p_energy_above[1], a->p_height_above[0], a->p_height_above[1], b->p_energy_above[0],
                     b->p_energy_above[1], b->p_height_above[0], st.runout_x.value[1], st.runout_x.max,
                     st.rebound_height.value[3], st.p_runout_above[0], st.p_runout_above[2]};
    for (size_t k = 0; k < sizeof want / sizeof want[0]; k++)
        if (!(y[idx[k]] == want[k]))
            fail_msg("%s: model %.17g, by hand %.17g", names[k], y[idx[k]], want[k]);
    assert_true(want[7] > 0 && want[7] < 1);
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s2);
    free(y);
    rf_model_free(&model);
    rf_traj_spec_free(&s);
}

/* A fuzzy capacity keeps its output's name; where it reaches 0 the output
 * would vanish: that evaluation fails with a message instead of shifting
 * the outputs. */
static void test_study_model_bound_capacity(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(ensemble_yaml, &s);
    const char *pn[1] = {"cap"}, *pp[1] = {"collectors.b.capacity"};
    rf_model model;
    rf_error err;
    assert_int_equal(rf_traj_model_create(&s, 1, pn, pp, &model, &err), RF_OK);
    size_t k = output_index(&model, "b_p_total_energy_above_capacity");
    double *y = calloc(model.n_outputs, sizeof *y), x[3] = {1e4, 1e6, 0};
    assert_int_equal(model.eval(model.ctx, &x[0], y, &err), RF_OK);
    double p_small = y[k];
    assert_int_equal(model.eval(model.ctx, &x[1], y, &err), RF_OK);
    assert_true(p_small > y[k]);     /* a larger capacity is exceeded less often */
    assert_true(y[k] == 0);          /* no block carries 1 MJ here */
    assert_int_not_equal(model.eval(model.ctx, &x[2], y, &err), RF_OK);
    assert_non_null(strstr(err.msg, "capacity or height reaches 0"));
    free(y);
    rf_model_free(&model);
    rf_traj_spec_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rolling_height_flat),
        cmocka_unit_test(test_rolling_height_incline),
        cmocka_unit_test(test_point_block_heights),
        cmocka_unit_test(test_total_energy_every_crossing),
        cmocka_unit_test(test_percentiles_exceedance_brute_force),
        cmocka_unit_test(test_runout_histogram),
        cmocka_unit_test(test_percentile_names),
        cmocka_unit_test(test_outputs_errors),
        cmocka_unit_test(test_study_model_outputs),
        cmocka_unit_test(test_study_model_bound_capacity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
