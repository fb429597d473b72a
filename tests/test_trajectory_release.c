/* test_trajectory_release.c - release kinds (issue 27 point 5): a release by
 * speed and angle is the same bits as the vx, vy it stands for; points drawn
 * along a line or in a zone are uniform by length (Kolmogorov-Smirnov
 * against the exact distribution, fixed seed; with Latin hypercube sampling
 * exactly one point per stratum); a zone puts every block on the ground, in
 * contact with its segment; bad lines and zones are refused at their line. */
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
#include "test_traj_util.h"

static void load(const char *yaml, rf_traj_spec *s)
{
    rf_error err;
    if (rf_traj_load_buffer("r.yaml", yaml, strlen(yaml), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

static void run(rf_traj_spec *s, rf_traj_ensemble *e)
{
    rf_error err;
    if (rf_traj_run(s, 2, e, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_ensemble_invariants(s, e);
}

/* A cliff, a 3:4 talus and a floor, a sphere with random restitution and roughness. */
static const char *speed_file =
    "profile: {points: [[0, 40], [10, 40], [10, 20], [50, -10], [120, -10]], material: m}\n"
    "materials: {m: {R_n: {uniform: [0.2, 0.5]}, R_t: 0.8, friction_angle: 35, roughness: 6,\n"
    "                rolling_resistance: 0.1}}\n"
    "block: {shape: sphere, radius: 0.5, density: 2600}\n"
    "release: {x: 8, y: 41, %s}\n"
    "bounce: {law: rigid_sphere}\n"
    "collectors: [{name: c, x: 60}]\n"
    "samples: 300\nseed: 9\n";

static void test_speed_angle_equals_vx_vy(void **state)
{
    (void)state;
    const double speed[] = {6, 3.5, 0, 12}, angle[] = {35, -20, 50, 120};
    for (int k = 0; k < 4; k++) {
        char rel[200], yaml[1024];
        rf_traj_spec a, b;
        snprintf(rel, sizeof rel, "speed: %.17g, angle: %.17g", speed[k], angle[k]);
        snprintf(yaml, sizeof yaml, speed_file, rel);
        load(yaml, &a);
        double th = angle[k] * (RF_PI / 180); /* the given angle in radians, as the reader converts it */
        snprintf(rel, sizeof rel, "vx: %.17g, vy: %.17g", speed[k] * cos(th), speed[k] * sin(th));
        snprintf(yaml, sizeof yaml, speed_file, rel);
        load(yaml, &b);
        rf_traj_ensemble ea, eb;
        run(&a, &ea);
        run(&b, &eb);
        assert_memory_equal(ea.runout_x, eb.runout_x, a.samples * sizeof *ea.runout_x);
        assert_memory_equal(ea.rebound_height, eb.rebound_height, a.samples * sizeof *ea.runout_x);
        assert_memory_equal(ea.crossings, eb.crossings, a.samples * sizeof *ea.crossings);
        assert_memory_equal(ea.state, eb.state, a.samples);
        double t;
        assert_true(ea.recorded[0].n_events > 1 && (t = ea.recorded[0].events[0].vx, t == speed[k] * cos(th)));
        rf_traj_ensemble_free(&ea), rf_traj_ensemble_free(&eb);
        rf_traj_spec_free(&a), rf_traj_spec_free(&b);
    }
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Kolmogorov-Smirnov distance of the sample v[0..n) (sorted here) from the CDF F. */
static double ks_distance(double *v, size_t n, double (*F)(double))
{
    qsort(v, n, sizeof *v, cmp);
    double d = 0;
    for (size_t i = 0; i < n; i++) {
        double f = F(v[i]);
        d = fmax(d, fmax(fabs(f - (double)i / (double)n), fabs((double)(i + 1) / (double)n - f)));
    }
    return d;
}

/* The release line: (2, 45) -> (8, 53) (length 10) -> (28, 53) (length 20). */
static double line_cdf(double s) { return s / 30; }

static double line_arc(double x, double y)
{
    return y < 53 - 1e-9 ? hypot(x - 2, y - 45) : 10 + (x - 8);
}

static const char *line_file =
    "profile: {points: [[0, 40], [10, 40], [10, 20], [50, -10], [120, -10]], material: m}\n"
    "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 35}}\n"
    "block: {shape: point, mass: 100}\n"
    "release: {line: [[2, 45], [8, 53], [28, 53]], vx: 1}\n"
    "samples: 4000\nrecord: 4000\nseed: 5\nsampling: %s\n";

static void test_line_uniform_by_length(void **state)
{
    (void)state;
    const size_t N = 4000;
    double *s = malloc(N * sizeof *s);
    for (int lhs = 0; lhs < 2; lhs++) {
        char yaml[1024];
        snprintf(yaml, sizeof yaml, line_file, lhs ? "lhs" : "random");
        rf_traj_spec spec;
        load(yaml, &spec);
        assert_int_equal(spec.release_kind, RF_TRAJ_RELEASE_LINE);
        assert_true(spec.x0 == 13 && spec.y0 == 53); /* the nominal release: the middle by length (15 of 30 m) */
        rf_traj_ensemble e;
        run(&spec, &e);
        assert_int_equal(e.n_recorded, N);
        for (size_t i = 0; i < N; i++) {
            const rf_traj_event *ev = &e.recorded[i].events[0];
            assert_int_equal(ev->kind, RF_EV_RELEASE);
            double x = ev->x, y = ev->y;
            int on_first = x <= 8 && fabs((y - 45) * 6 - (x - 2) * 8) <= 1e-9 * 100;
            int on_second = x >= 8 && x <= 28 && y == 53;
            if (!on_first && !on_second)
                fail_msg("release %zu at (%.17g, %.17g) is not on the line", i, x, y);
            s[i] = line_arc(x, y);
        }
        if (lhs) { /* exactly one point per stratum of length 30 / N */
            unsigned char *seen = calloc(N, 1);
            for (size_t i = 0; i < N; i++) {
                size_t k = (size_t)floor(s[i] / 30 * (double)N + 1e-9);
                assert_true(k < N && !seen[k]);
                seen[k] = 1;
            }
            free(seen);
        }
        double d = ks_distance(s, N, line_cdf);
        /* critical value at alpha = 0.001: 1.949 / sqrt(N) = 0.0308; LHS is far closer than that */
        if (!(d < (lhs ? 1.0 / (double)N + 1e-9 : 1.949 / sqrt((double)N))))
            fail_msg("KS distance %g (lhs %d)", d, lhs);
        rf_traj_ensemble_free(&e);
        rf_traj_spec_free(&spec);
    }
    free(s);
}

/* The zone x in [4, 20] covers the end of the ledge (4 <= x < 10, flat, length
 * 6) and the top of the 3:4 talus (10 <= x <= 20: length 12.5); the vertical
 * step at x = 10 holds no ground.  Arc length along the ground in the zone: */
static double zone_arc(double x) { return x <= 10 ? x - 4 : 6 + (x - 10) * 1.25; }
static double zone_cdf(double s) { return s / 18.5; }

static void check_zone(const char *zone, const char *sampling)
{
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[0, 40], [10, 40], [10, 20], [50, -10], [120, -10]], material: m}\n"
             "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 20}}\n"
             "block: {shape: point, mass: 100}\n"
             "release: {zone: %s}\n"
             "samples: 3000\nrecord: 3000\nseed: 11\nsampling: %s\n", zone, sampling);
    rf_traj_spec spec;
    load(yaml, &spec);
    rf_traj_ensemble e;
    run(&spec, &e);
    const size_t N = 3000;
    double *s = malloc(N * sizeof *s);
    for (size_t i = 0; i < N; i++) {
        const rf_traj_event *ev = &e.recorded[i].events[0];
        double x = ev->x, y = ev->y, ground = x < 10 ? 40 : 20 - (x - 10) * 0.75;
        if (!(x >= 4 && x <= 20 + 1e-12) || fabs(y - ground) > 1e-9 * (1 + fabs(x) + fabs(y)))
            fail_msg("zone %s: release %zu at (%.17g, %.17g), ground %.17g", zone, i, x, y, ground);
        assert_false(ev->flying); /* on the ground: in contact with its segment */
        s[i] = zone_arc(x);
    }
    double d = ks_distance(s, N, zone_cdf);
    if (!(d < 1.949 / sqrt((double)N)))
        fail_msg("zone %s: KS distance %g", zone, d);
    free(s);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&spec);
}

static void test_zone_on_the_ground_uniform(void **state)
{
    (void)state;
    check_zone("{x: [4, 20]}", "random");
    check_zone("{x: [4, 20]}", "lhs");
    check_zone("{polygon: [[4, 50], [4, 0], [20, 0], [20, 50]]}", "random");
    /* a slanted edge through the ground at (20, 12.5): y = 12.5 + 9.5 (x - 20) */
    check_zone("{polygon: [[4, 60], [25, 60], [13.421052631578947, -50], [4, -50]]}",
               "random");
}

static void expect_refused(const char *release, const char *want1, const char *want2)
{
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[0, 40], [10, 40], [10, 20], [50, -10], [120, -10]], material: m}\n"
             "materials: {m: {R_n: 0.3, R_t: 0.8}}\nblock: {shape: point, mass: 1}\n"
             "release: %s\n", release);
    rf_traj_spec s;
    rf_error err;
    assert_int_not_equal(rf_traj_load_buffer("r.yaml", yaml, strlen(yaml), &s, &err), RF_OK);
    if (!strstr(err.msg, want1) || !strstr(err.msg, want2))
        fail_msg("message '%s' lacks '%s' or '%s'", err.msg, want1, want2);
}

static void test_refused(void **state)
{
    (void)state;
    expect_refused("{line: [[2, 45], [20, 5]]}", "r.yaml:4:", "release.line[1] = [20, 5]: under the ground");
    expect_refused("{line: [[2, 45], [130, 5]]}", "r.yaml:4:", "outside the profile's x-range");
    expect_refused("{line: [[5, 41], [30, 10]]}", "r.yaml:4:",
                   "passes under the ground at profile.points[1] = [10, 40]");
    expect_refused("{line: [[2, 45]]}", "r.yaml:4:", "release.line");
    expect_refused("{zone: {x: [200, 300]}}", "r.yaml:4:", "release.zone: holds no ground");
    expect_refused("{zone: {x: [20, 5]}}", "r.yaml:4:", "x0 < x1");
    expect_refused("{zone: {polygon: [[0, 0], [1, 1]]}}", "r.yaml:4:", "release.zone.polygon");
    expect_refused("{zone: {x: [4, 20]}, x: 5}", "r.yaml:4:", "not both");
    expect_refused("{x: 5, y: 41, vx: 1, speed: 2}", "r.yaml:4:", "vx, vy or speed, angle: not both");
    expect_refused("{x: 5, y: 41, angle: 10}", "r.yaml:4:", "speed [m/s] is required");
    expect_refused("{x: 5, y: 41, speed: -1}", "r.yaml:4:", "release.speed = -1: must be >= 0");
    expect_refused("{x: 5, y: 41, speed: 1, angle: 270}", "r.yaml:4:", "release.angle = 270");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_speed_angle_equals_vx_vy),
        cmocka_unit_test(test_line_uniform_by_length),
        cmocka_unit_test(test_zone_on_the_ground_uniform),
        cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
