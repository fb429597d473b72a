/* test_traj_ground.c - nothing falls through the ground (issue 31, items 1-3):
 * a block sliding into a vertical step rebounds along the floor and stays on
 * it (a wall at either end, in the middle, both directions, in a pit, a
 * rolling sphere), a block sliding into a V-notch with sides of 45 deg or
 * steeper stops at the vertex, and the ground tolerance is local (a far
 * vertex changes nothing near the release; non-physical heights are refused),
 * and a sliding sphere's friction opposes its slip (found by the generated
 * profiles of tests/traj_gen.h, also run here).
 * References are closed forms of 1D sliding/rolling with friction and the
 * constant bounce law; every run also passes traj_check_invariants. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_traj_util.h"
#include "test_util.h"
#include "traj_gen.h"

#define G 9.81
#define DEG (3.14159265358979323846 / 180.0)

static void expect_rest(const traj_case *c, double x, double y, double tol)
{
    if (c->res.state != RF_TRAJ_STOPPED || !(fabs(c->res.x_end - x) <= tol) || !(fabs(c->res.y_end - y) <= tol))
        fail_msg("%s at (%.12g, %.12g) after %zu events; expected stopped at (%.12g, %.12g)",
                 rf_traj_state_name(c->res.state), c->res.x_end, c->res.y_end, c->res.n_steps, x, y);
}

/* Sliding at `v` over distance `d` with deceleration `a`, then hitting a wall
 * (constant law: normal speed times R_n, no tangential part): the rebound speed. */
static double rebound_after(double v, double d, double a, double Rn)
{
    return Rn * sqrt(v * v - 2 * a * d);
}

/* The step: sliding at 5 m/s from x = 5 to the wall at x = 10 with
 * a = g tan 5 deg, rebound R_n v_w along the floor, slide back v'^2 / (2a).
 * Mirrored: the wall at the left end, a step up in the middle going left,
 * the wall at the right end.  Collectors the block never reaches stay unreached. */
static void test_step_point_block(void **state)
{
    (void)state;
    const char *profiles[4] = {"[[-20, 5], [0, 0], [10, 0], [10, 10], [20, 10]]", "[[0, 10], [0, 0], [20, 0]]",
                               "[[-20, 10], [0, 10], [0, 0], [20, 0]]", "[[0, 0], [10, 0], [10, 10]]"};
    const double vx[4] = {5, -5, -5, 5}, wall[4] = {10, 0, 0, 10}, far[4] = {2, 18, 18, 1};
    double a = G * tan(5 * DEG), v1 = rebound_after(5, 5, a, 0.5);
    for (int k = 0; k < 4; k++) {
        char yaml[1024];
        snprintf(yaml, sizeof yaml,
                 "profile: {points: %s, material: rock}\n"
                 "materials: {rock: {R_n: 0.5, R_t: 0.8, friction_angle: 5}}\n"
                 "block: {shape: point, mass: 1000}\n"
                 "release: {x: 5, y: 0, vx: %g}\n"
                 "collectors: [{name: a, x: %g}]\n",
                 profiles[k], vx[k], far[k]);
        traj_case c;
        traj_case_run(&c, yaml);
        double back = v1 * v1 / (2 * a);
        expect_rest(&c, wall[k] + (vx[k] > 0 ? -back : back), 0, 1e-9);
        assert_int_equal(c.res.n_impacts, 1);
        assert_int_equal(c.cross[0].reached, 0);
        traj_case_free(&c);
    }
}

/* A pit 10 m wide between two 5 m walls: the block goes back and forth,
 * each wall taking 30 % of its speed, until it slides to rest or its rebound is
 * below v_stop; the reference walks the same 1D sequence. */
static void test_pit(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[-20, 5], [0, 5], [0, 0], [10, 0], [10, 5], [20, 5]], material: rock}\n"
                 "materials: {rock: {R_n: 0.7, R_t: 0.8, friction_angle: 1}}\n"
                 "block: {shape: point, mass: 1000}\n"
                 "release: {x: 5, y: 0, vx: 8}\n");
    double a = G * tan(1 * DEG), p = 5, v = 8;
    int dir = 1, walls = 0;
    for (;;) {
        double d = dir > 0 ? 10 - p : p;
        if (v * v <= 2 * a * d) {
            p += dir * v * v / (2 * a);
            break;
        }
        v = rebound_after(v, d, a, 0.7), walls++;
        p = dir > 0 ? 10 : 0, dir = -dir;
        if (v < 0.1)
            break;
    }
    assert_true(walls >= 3);
    assert_int_equal(c.res.n_impacts, walls);
    expect_rest(&c, p, 0, 1e-9);
    traj_case_free(&c);
}

/* A rolling sphere (rolling resistance mu_r): released with vx = 5 and no spin,
 * brought to rolling u0 = 5/(1+k); a = mu_r g / (1+k); the wall (constant law)
 * sends it back at R_n v_w without spin, brought to rolling again: R_n v_w/(1+k). */
static void test_step_rolling_sphere(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[-20, 5], [0, 0], [10, 0], [10, 10], [20, 10]], material: rock}\n"
                 "materials: {rock: {R_n: 0.5, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1}}\n"
                 "block: {shape: sphere, radius: 0.5, density: 2700}\n"
                 "release: {x: 5, y: 0, vx: 5}\n");
    double k = 0.4, a = 0.1 * G / (1 + k), u1 = rebound_after(5 / (1 + k), 5, a, 0.5) / (1 + k);
    expect_rest(&c, 10 - u1 * u1 / (2 * a), 0, 1e-9);
    traj_case_free(&c);
}

/* A sphere on a 60 deg slope (too steep to roll with phi = 9 deg), released at
 * rest spinning forward at w0 = 20 rad/s: its contact point slips backwards,
 * so friction R = mu N pushes it down the slope and spins it down:
 * a1 = g_t + R until the slip u - w r reaches 0 at t1 = w0 r / (g_t + R + R/k),
 * then a2 = g_t - R.  Speed at the collector D = 10 m down the slope:
 * sqrt(u1^2 + 2 a2 (D - d1)).  (Friction taken along the motion instead of
 * against the slip spun the sphere further up and gained energy.) */
static void test_sliding_sphere_spin(void **state)
{
    (void)state;
    double t60 = tan(60 * DEG);
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[0, %.17g], [10, 0], [60, 0]], material: rock}\n"
             "materials: {rock: {R_n: 0.3, R_t: 0.8, friction_angle: 9}}\n"
             "block: {shape: sphere, radius: 0.5, density: 2700}\n"
             "release: {x: 1, y: %.17g, omega: 20}\n"
             "collectors: [{name: c, x: 6}]\n", 10 * t60, 9 * t60);
    traj_case c;
    traj_case_run(&c, yaml);
    double gt = G * sin(60 * DEG), R = tan(9 * DEG) * G * cos(60 * DEG), k = 0.4;
    double t1 = 20 * 0.5 / (gt + R + R / k), u1 = (gt + R) * t1, d1 = 0.5 * (gt + R) * t1 * t1;
    assert_true(c.cross[0].reached);
    assert_close(c.cross[0].speed, sqrt(u1 * u1 + 2 * (gt - R) * (10 - d1)), 1e-9);
    traj_case_free(&c);
}

/* Sliding from rest down a side of slope angle b (friction phi) over length L
 * into a notch whose other side is at least as steep (sum of the angles >= 90):
 * the kink keeps no velocity that leaves the vertex, so it stops there at
 * t = sqrt(2 L / (g (sin b - tan phi cos b))). */
static void test_notch(void **state)
{
    (void)state;
    struct { double left, right; int sphere; } cases[4] = {{45, 45, 0}, {60, 60, 0}, {50, 45, 0}, {45, 45, 1}};
    for (int k = 0; k < 4; k++) {
        double tl = tan(cases[k].left * DEG), tr = tan(cases[k].right * DEG);
        char yaml[1024];
        snprintf(yaml, sizeof yaml,
                 "profile: {points: [[-10, %.17g], [0, 0], [10, %.17g]], material: rock}\n"
                 "materials: {rock: {R_n: 0.3, R_t: 1, friction_angle: 30}}\n"
                 "block: %s\n"
                 "release: {x: -9, y: %.17g}\n",
                 10 * tl, 10 * tr, cases[k].sphere ? "{shape: sphere, radius: 0.5, density: 2700}"
                                                   : "{shape: point, mass: 1000}", 9 * tl);
        traj_case c;
        traj_case_run(&c, yaml);
        double b = cases[k].left * DEG, L = 9 / cos(b);
        double acc = cases[k].sphere ? G * sin(b) / 1.4 : G * (sin(b) - tan(30 * DEG) * cos(b));
        expect_rest(&c, 0, 0, 1e-9);
        assert_close(c.res.t_end, sqrt(2 * L / acc), 1e-9);
        assert_true(c.res.n_steps < 10);
        traj_case_free(&c);
    }
}

/* The same motion on a profile with and without a far vertex (the floor
 * continued to x = 9e6 m): a release 5 mm above the slope falls 5 mm
 * (t = sqrt(2 h / g)) and everything after is the same bits. */
static void test_far_vertex_changes_nothing(void **state)
{
    (void)state;
    const char *tail[2] = {"", ", [9e6, 0]"};
    traj_case c[2];
    for (int k = 0; k < 2; k++) {
        char yaml[1024];
        snprintf(yaml, sizeof yaml,
                 "profile: {points: [[0, 10], [20, 0], [40, 0]%s], material: rock}\n"
                 "materials: {rock: {R_n: 0.3, R_t: 0.8, friction_angle: 20}}\n"
                 "block: {shape: point, mass: 1000}\n"
                 "release: {x: 2, y: 9.005}\n", tail[k]);
        traj_case_run(&c[k], yaml);
        assert_true(c[k].res.n_impacts >= 1);
        assert_close(c[k].res.impacts[0].t, sqrt(2 * 0.005 / G), 1e-9);
    }
    assert_int_equal(c[0].res.state, RF_TRAJ_STOPPED);
    assert_int_equal(c[0].res.n_events, c[1].res.n_events);
    for (size_t i = 0; i < c[0].res.n_events; i++)
        assert_memory_equal(&c[0].res.events[i], &c[1].res.events[i], sizeof c[0].res.events[i]);
    traj_case_free(&c[0]);
    traj_case_free(&c[1]);
}

static void expect_refused(const char *yaml, const char *want1, const char *want2)
{
    rf_traj_spec s;
    rf_error err;
    assert_int_not_equal(rf_traj_load_buffer("far.yaml", yaml, strlen(yaml), &s, &err), RF_OK);
    if (!strstr(err.msg, want1) || !strstr(err.msg, want2))
        fail_msg("message '%s' lacks '%s' or '%s'", err.msg, want1, want2);
}

/* Heights and distances beyond 1e7 m are refused at their line; a release
 * 1 mm under the ground is refused whatever the profile's extent. */
static void test_bounds_and_release(void **state)
{
    (void)state;
    expect_refused("profile: {points: [[0, 10], [20, 0], [3.4e38, 0]], material: rock}\n"
                   "materials: {rock: {R_n: 0.3, R_t: 0.8}}\nblock: {shape: point, mass: 1}\nrelease: {x: 2, y: 12}\n",
                   "far.yaml:1:", "profile.points[2] = [3.4e+38, 0]");
    expect_refused("materials: {rock: {R_n: 0.3, R_t: 0.8}}\n"
                   "profile: {points: [[-1e308, 0], [0, 0], [1e308, 0]], material: rock}\n"
                   "block: {shape: point, mass: 1}\nrelease: {x: 2, y: -1000}\n",
                   "far.yaml:2:", "1e+07 m");
    expect_refused("profile: {points: [[0, 10], [20, 0], [9e6, 0]], material: rock}\n"
                   "materials: {rock: {R_n: 0.3, R_t: 0.8}}\nblock: {shape: point, mass: 1}\n"
                   "release: {x: 2, y: 8.999}\n",
                   "far.yaml:4:", "under the ground");
}

/* 4000 profiles generated as the fuzzer does (tests/traj_gen.h: slopes,
 * steps, pits, notches, every analytic law, point block or sphere, release on
 * the ground or above): every file loads and every trajectory keeps the
 * invariants. */
static void test_generated_profiles(void **state)
{
    (void)state;
    for (uint64_t i = 0; i < 4000; i++) {
        uint8_t bytes[48];
        for (size_t j = 0; j < sizeof bytes; j++)
            bytes[j] = (uint8_t)(rf_traj_uniform(31, i, j) * 256);
        char yaml[8192];
        size_t len = traj_gen_yaml(bytes, sizeof bytes, yaml, sizeof yaml);
        rf_error err;
        int st = traj_gen_run(yaml, len, i, &err);
        if (st != 0)
            fail_msg("case %llu %s: %s\n%s", (unsigned long long)i, st < 0 ? "does not load" : "fails", err.msg, yaml);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_step_point_block),
        cmocka_unit_test(test_pit),
        cmocka_unit_test(test_step_rolling_sphere),
        cmocka_unit_test(test_notch),
        cmocka_unit_test(test_sliding_sphere_spin),
        cmocka_unit_test(test_far_vertex_changes_nothing),
        cmocka_unit_test(test_bounds_and_release),
        cmocka_unit_test(test_generated_profiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
