/* test_trajectory_envelope.c - envelopes along x from all trajectories
 * (envelope.c) against independent references:
 *  - brute force: 50 trajectories all recorded, each one's first passage of
 *    every edge found by scanning rf_traj_state_at and bisecting, the ground
 *    interpolated from the profile points, exact type-7 percentiles: the
 *    counts reaching each edge are equal, the max equal to rounding, p50 and
 *    p95 within the stated accuracy of the streaming histogram;
 *  - the simulator's own collectors placed on every edge (a second code path)
 *    for 400 sphere trajectories, half of them not recorded;
 *  - closed forms: a parabola over flat ground then frictionless sliding; a
 *    sphere rolling down an incline (energy m g dh, 2/7 of it rotation); a
 *    sphere sliding and spinning up on a steep incline;
 *  - the same bits at 1, 2 and 3 threads. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_util.h"
#include "test_traj_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ACC RF_TRAJ_ENVELOPE_ACCURACY

/* Vertices off the 1 m edges of the 160 m profile (a kink exactly on an edge
 * would make "before or after the kink" a rounding question). */
#define PROFILE "profile: {points: [[0, 100], [7.3, 88.1], [21.7, 57.3], [48.9, 38.2], [77.1, 21.7], " \
                "[96.6, 16.2], [121.3, 11.4], [160, 10]], materials: [rock, rock, talus, talus, soil, soil, road]}\n" \
                "materials:\n" \
                "  rock:  {R_n: {normal: [0.35, 0.05], min: 0.2, max: 0.5}, R_t: {uniform: [0.75, 0.95]}, " \
                "friction_angle: 40, roughness: 5}\n" \
                "  talus: {R_n: {uniform: [0.25, 0.4]}, R_t: 0.8, friction_angle: 40, roughness: 6, " \
                "rolling_resistance: 0.25}\n" \
                "  soil:  {R_n: 0.25, R_t: 0.65, friction_angle: 40, roughness: 3, rolling_resistance: 0.4}\n" \
                "  road:  {R_n: 0.4, R_t: 0.9, friction_angle: 40, roughness: 1, rolling_resistance: 0.1}\n" \
                "release: {x: {uniform: [0.5, 2.5]}, y: 101, vx: {uniform: [0.5, 3]}, vy: 0}\n" \
                "stop: {v_stop: 0.3}\nseed: 7\n"

static void load(const char *yaml, rf_traj_spec *s)
{
    rf_error err;
    if (rf_traj_load_buffer("env.yaml", yaml, strlen(yaml), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

static void run(const rf_traj_spec *s, int threads, rf_traj_ensemble *e)
{
    rf_error err;
    if (rf_traj_run(s, threads, e, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(e->envelope.n_edges, RF_TRAJ_ENVELOPE_EDGES);
    assert_ensemble_invariants(s, e);
}

/* Ground under x by linear interpolation between the profile points. */
static double ground(const rf_traj_spec *s, double x)
{
    for (size_t i = 0; i + 1 < s->n_points; i++)
        if (x <= s->px[i + 1])
            return s->py[i] + (s->py[i + 1] - s->py[i]) * (x - s->px[i]) / (s->px[i + 1] - s->px[i]);
    return s->py[s->n_points - 1];
}

static double x_at(const rf_traj_result *r, double t, double *y, double *v2)
{
    double x, vx, vy;
    assert_true(rf_traj_state_at(r, t, &x, y, &vx, &vy));
    *v2 = vx * vx + vy * vy;
    return x;
}

/* First time the recorded path r reaches x = xk (scan of every stretch at
 * 256 points, then bisection); its height above the ground and speed^2.
 * Returns 0 if it never does. */
static int first_passage(const rf_traj_spec *s, const rf_traj_result *r, double xk, double *h, double *v2)
{
    double y, t0 = r->events[0].t, f0 = x_at(r, t0, &y, v2) - xk;
    if (f0 == 0)
        return *h = y - ground(s, xk), 1;
    for (size_t q = 0; q + 1 < r->n_events; q++) {
        double ta = r->events[q].t, tb = r->events[q + 1].t;
        for (int j = 1; j <= 256 && tb > ta; j++) {
            double t1 = j < 256 ? ta + (tb - ta) * j / 256.0 : tb, f1 = x_at(r, t1, &y, v2) - xk;
            if (f0 * f1 <= 0) {
                for (int it = 0; it < 200 && t1 - t0 > 0; it++) {
                    double tm = 0.5 * (t0 + t1), fm = x_at(r, tm, &y, v2) - xk;
                    if (tm <= t0 || tm >= t1)
                        break;
                    if (f0 * fm <= 0)
                        t1 = tm;
                    else
                        t0 = tm, f0 = fm;
                }
                x_at(r, t1, &y, v2);
                *h = y - ground(s, xk);
                return 1;
            }
            t0 = t1, f0 = f1;
        }
    }
    return 0;
}

/* |estimate - exact| within the histogram's accuracy (plus 1e-9 relative
 * for the bisection of the reference). */
static void assert_within(double est, double exact, double floor)
{
    double tol = (ACC + 1e-9) * fabs(exact) + floor;
    if (!(fabs(est - exact) <= tol))
        fail_msg("envelope %.10g vs brute force %.10g (tolerance %.3g)", est, exact, tol);
}

static void test_brute_force(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(PROFILE "block: {mass: 1500}\nsamples: 50\nrecord: 50\n", &s);
    rf_traj_ensemble e;
    run(&s, 2, &e);
    const rf_traj_envelope *v = &e.envelope;
    double h[50], k[50];
    size_t partial = 0, moving = 0;
    for (size_t j = 0; j < v->n_edges; j++) {
        assert_true(fabs(v->x[j] - 160.0 * (double)j / 160.0) < 1e-12);
        size_t m = 0;
        for (size_t i = 0; i < 50; i++) {
            double hh, v2;
            if (first_passage(&s, &e.recorded[i], v->x[j], &hh, &v2))
                h[m] = hh, k[m++] = 0.5 * 1500 * v2;
        }
        assert_int_equal(v->reached[j], m);
        partial += m > 0 && m < 50;
        if (!m) {
            assert_true(isnan(v->height[0][j]) && isnan(v->energy[2][j]));
            continue;
        }
        rf_traj_percentiles ph = rf_traj_percentiles_of(h, m), pk = rf_traj_percentiles_of(k, m);
        moving += pk.p50 > 1e3;
        assert_within(v->height[0][j], ph.p50, RF_TRAJ_ENVELOPE_HEIGHT_FLOOR);
        assert_within(v->height[1][j], ph.p95, RF_TRAJ_ENVELOPE_HEIGHT_FLOOR);
        assert_within(v->energy[0][j], pk.p50, RF_TRAJ_ENVELOPE_ENERGY_FLOOR);
        assert_within(v->energy[1][j], pk.p95, RF_TRAJ_ENVELOPE_ENERGY_FLOOR);
        assert_true(fabs(v->height[2][j] - ph.max) <= 1e-9 * (1 + fabs(ph.max)));
        assert_true(fabs(v->energy[2][j] - pk.max) <= 1e-9 * pk.max);
    }
    assert_true(partial >= 5);   /* edges before every release and where some stopped */
    assert_true(moving >= 100);  /* the comparison is not one of zeros */
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

/* A sphere spec with a pure collector on every interior edge. */
static void sphere_with_collectors(rf_traj_spec *s)
{
    size_t cap = strlen(PROFILE) + 64 * RF_TRAJ_ENVELOPE_EDGES + 256, n;
    char *y = malloc(cap);
    assert_non_null(y);
    n = (size_t)snprintf(y, cap, "%sblock: {shape: sphere, radius: 0.5, density: 2600}\nbounce: {law: rigid_sphere}\n"
                                 "samples: 400\ncollectors:\n", PROFILE);
    for (int j = 1; j + 1 < RF_TRAJ_ENVELOPE_EDGES; j++)
        n += (size_t)snprintf(y + n, cap - n, "  - {name: c%d, x: %d}\n", j, j);
    load(y, s);
    free(y);
}

/* Collector crossings (first passage, recorded by the simulation for every
 * sample) equal the envelopes at the edges: rolling spheres, rotation included. */
static void test_collectors_every_edge(void **state)
{
    (void)state;
    rf_traj_spec s;
    sphere_with_collectors(&s);
    rf_traj_ensemble e;
    run(&s, 2, &e);
    assert_true(e.n_recorded < e.samples); /* unrecorded trajectories count too */
    const rf_traj_envelope *v = &e.envelope;
    double *h = malloc(s.samples * sizeof *h), *k = malloc(s.samples * sizeof *k);
    size_t nc = s.n_collectors, rotating = 0;
    for (size_t c = 0; c < nc; c++) {
        size_t j = c + 1, m = 0;
        for (size_t i = 0; i < s.samples; i++) {
            const rf_traj_crossing *x = &e.crossings[i * nc + c];
            if (x->reached)
                h[m] = x->height_lowest, k[m++] = x->total_energy;
            rotating += x->reached && x->rotational_energy > 0.1 * x->translational_energy;
        }
        assert_int_equal(v->reached[j], m);
        if (!m)
            continue;
        rf_traj_percentiles ph = rf_traj_percentiles_of(h, m), pk = rf_traj_percentiles_of(k, m);
        assert_within(v->height[0][j], ph.p50, RF_TRAJ_ENVELOPE_HEIGHT_FLOOR);
        assert_within(v->height[1][j], ph.p95, RF_TRAJ_ENVELOPE_HEIGHT_FLOOR);
        assert_within(v->energy[0][j], pk.p50, RF_TRAJ_ENVELOPE_ENERGY_FLOOR);
        assert_within(v->energy[1][j], pk.p95, RF_TRAJ_ENVELOPE_ENERGY_FLOOR);
        assert_true(fabs(v->height[2][j] - ph.max) <= 1e-9 * (1 + fabs(ph.max)));
        assert_true(fabs(v->energy[2][j] - pk.max) <= 1e-9 * pk.max);
    }
    assert_true(rotating > 1000);
    free(h), free(k);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

static void test_same_bits_any_threads(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(PROFILE "block: {shape: sphere, radius: 0.5, density: 2600}\nsamples: 301\n", &s);
    rf_traj_ensemble e[3];
    for (int t = 0; t < 3; t++)
        run(&s, t + 1, &e[t]);
    size_t n = RF_TRAJ_ENVELOPE_EDGES * sizeof(double);
    for (int t = 1; t < 3; t++) {
        const rf_traj_envelope *a = &e[0].envelope, *b = &e[t].envelope;
        assert_memory_equal(a->reached, b->reached, RF_TRAJ_ENVELOPE_EDGES * sizeof(size_t));
        for (int q = 0; q < 3; q++) {
            assert_memory_equal(a->height[q], b->height[q], n);
            assert_memory_equal(a->energy[q], b->energy[q], n);
        }
    }
    for (int t = 0; t < 3; t++)
        rf_traj_ensemble_free(&e[t]);
    rf_traj_spec_free(&s);
}

/* Release at (10.3, 20) with vx = 3 over flat ground: before the impact the
 * parabola y = 20 - g t^2 / 2, t = (x - 10.3) / 3; then no bounce (R_n 0)
 * and no friction: sliding at 3 m/s to the end.  Edges left of the release
 * are not reached. */
static void test_parabola_then_slide(void **state)
{
    (void)state;
    rf_traj_spec s;
    load("profile: {points: [[0, 0], [100, 0]], material: m}\nmaterials: {m: {R_n: 0, R_t: 1, friction_angle: 0}}\n"
         "block: {mass: 2}\nrelease: {x: 10.3, y: 20, vx: 3, vy: 0}\n", &s);
    rf_traj_ensemble e;
    run(&s, 1, &e);
    const rf_traj_envelope *v = &e.envelope;
    double g = 9.81, xi = 10.3 + 3 * sqrt(2 * 20 / g);
    size_t flight = 0;
    for (size_t j = 0; j < v->n_edges; j++) {
        double x = v->x[j], t = (x - 10.3) / 3, h = x < xi ? 20 - 0.5 * g * t * t : 0;
        double E = x < xi ? 0.5 * 2 * (9 + g * g * t * t) : 0.5 * 2 * 9;
        if (x < 10.3) {
            assert_int_equal(v->reached[j], 0);
            assert_true(isnan(v->height[2][j]) && isnan(v->energy[0][j]));
            continue;
        }
        flight += x < xi;
        assert_int_equal(v->reached[j], 1);
        assert_true(fabs(v->height[2][j] - h) <= 1e-12 * 20);
        assert_true(fabs(v->energy[2][j] - E) <= 1e-12 * E);
        assert_within(v->energy[0][j], E, RF_TRAJ_ENVELOPE_ENERGY_FLOOR);
        assert_within(v->height[1][j], h, RF_TRAJ_ENVELOPE_HEIGHT_FLOOR);
    }
    assert_int_equal(flight, 10); /* edges 10.625 .. 16.25 */
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

/* A sphere let go on the ground of an incline (no rolling resistance):
 * rolling, so its energy at x is m g (y0 - y(x)) exactly. */
static void test_rolling_energy(void **state)
{
    (void)state;
    rf_traj_spec s;
    load("profile: {points: [[0, 50], [100, 0]], material: m}\n"
         "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30, rolling_resistance: 0}}\n"
         "block: {shape: sphere, radius: 0.5, density: 2000}\nrelease: {x: 0.3, y: 49.85, vx: 0, vy: 0}\n", &s);
    rf_traj_ensemble e;
    run(&s, 1, &e);
    double m = 4.0 / 3.0 * 3.14159265358979323846 * 0.125 * 2000;
    const rf_traj_envelope *v = &e.envelope;
    for (size_t j = 0; j < v->n_edges; j++) {
        if (v->x[j] < 0.3) {
            assert_int_equal(v->reached[j], 0);
            continue;
        }
        double E = m * 9.81 * 0.5 * (v->x[j] - 0.3);
        assert_int_equal(v->reached[j], 1);
        assert_true(fabs(v->energy[2][j] - E) <= 1e-9 * (E + 1));
        assert_true(fabs(v->height[2][j]) <= 1e-9);
    }
    assert_true(e.recorded[0].crossings != NULL && e.state[0] == RF_TRAJ_EXITED);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

/* On a 5:1 incline with friction 30 deg a sphere cannot roll (tan > 3.5 mu):
 * it slides with a = g (sin - mu cos) while friction spins it up,
 * omega = (5/2) mu g cos t / r. */
static void test_sliding_spin(void **state)
{
    (void)state;
    rf_traj_spec s;
    load("profile: {points: [[0, 100], [20, 0]], material: m}\n"
         "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1}}\n"
         "block: {shape: sphere, radius: 0.4, density: 2500}\nrelease: {x: 0.05, y: 99.75, vx: 0, vy: 0}\n", &s);
    rf_traj_ensemble e;
    run(&s, 1, &e);
    double r = 0.4, m = 4.0 / 3.0 * 3.14159265358979323846 * r * r * r * 2500, I = 0.4 * m * r * r;
    double c = 1 / sqrt(26.0), sn = 5 / sqrt(26.0), mu = tan(30 * 3.14159265358979323846 / 180), g = 9.81;
    double a = g * (sn - mu * c);
    const rf_traj_envelope *v = &e.envelope;
    size_t n = 0;
    for (size_t j = 0; j < v->n_edges; j++) {
        if (v->x[j] < 0.05)
            continue;
        double d = (v->x[j] - 0.05) / c, t = sqrt(2 * d / a), w = 2.5 * mu * g * c * t / r;
        double E = 0.5 * m * (a * t) * (a * t) + 0.5 * I * w * w;
        assert_int_equal(v->reached[j], 1);
        assert_true(fabs(v->energy[2][j] - E) <= 1e-9 * (E + 1));
        n++;
    }
    assert_int_equal(n, 160);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_brute_force),
        cmocka_unit_test(test_collectors_every_edge),
        cmocka_unit_test(test_same_bits_any_threads),
        cmocka_unit_test(test_parabola_then_slide),
        cmocka_unit_test(test_rolling_energy),
        cmocka_unit_test(test_sliding_spin),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
