/* test_trajectory_mc.c - Monte Carlo ensembles: the same bits at 1, 2 and 3
 * threads (every sample draws from its own counter-based stream, so any split
 * of the samples over threads or MPI ranks gives the same ensemble), the
 * sample p95 converging at the rate sqrt(p (1 - p) / N) / f(q) of a sample
 * quantile, Latin hypercube strata, and the normal quantile. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_traj_util.h"
#include "test_util.h"

static void load(const char *yaml, rf_traj_spec *s)
{
    rf_error err;
    if (rf_traj_load_buffer("mc.yaml", yaml, strlen(yaml), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

static void test_same_bits_any_threads(void **state)
{
    (void)state;
    rf_traj_spec s;
    load("profile: {points: [[0, 60], [20, 45], [30, 44], [45, 20], [50, 19], [70, 5], [80, 6], [120, 0]], material: m}\n"
         "materials: {m: {R_n: {uniform: [0.2, 0.6]}, R_t: {normal: [0.8, 0.1], min: 0.5, max: 1}, friction_angle: 30,\n"
         "                roughness: 10}}\n"
         "block: {shape: sphere, radius: 0.4, density: 2700}\n"
         "release: {x: 1, y: 62, vx: {uniform: [0, 5]}, vy: 0}\n"
         "bounce: {law: rigid_sphere}\n"
         "collectors: [{name: a, x: 40}, {name: b, x: 100}]\n"
         "samples: 701\nseed: 42\n", &s);
    rf_traj_ensemble e[3];
    rf_error err;
    for (int t = 0; t < 3; t++)
        assert_int_equal(rf_traj_run(&s, t + 1, &e[t], &err), RF_OK);
    assert_ensemble_invariants(&s, &e[0]);
    for (int t = 1; t < 3; t++) {
        assert_memory_equal(e[0].state, e[t].state, s.samples);
        assert_memory_equal(e[0].runout_x, e[t].runout_x, s.samples * sizeof(double));
        assert_memory_equal(e[0].rebound_height, e[t].rebound_height, s.samples * sizeof(double));
        for (size_t i = 0; i < s.samples * 2; i++) {
            assert_int_equal(e[0].crossings[i].reached, e[t].crossings[i].reached);
            assert_memory_equal(&e[0].crossings[i].total_energy, &e[t].crossings[i].total_energy, sizeof(double));
            assert_memory_equal(&e[0].crossings[i].height_lowest, &e[t].crossings[i].height_lowest, sizeof(double));
        }
    }
    /* something random did happen */
    assert_true(e[0].rebound_height[0] != e[0].rebound_height[1]);
    for (int t = 0; t < 3; t++)
        rf_traj_ensemble_free(&e[t]);
    rf_traj_spec_free(&s);
}

/* Vertical drop from h ~ U[a, b] onto flat ground: rebound height R_n^2 h
 * exactly, whose p95 is R_n^2 (a + 0.95 (b - a)); the sample quantile's
 * standard error is sqrt(0.95 * 0.05 / N) R_n^2 (b - a). */
static double p95_rmse(size_t N, int lhs, double *se)
{
    const double Rn = 0.5, a = 2, b = 12, exact = Rn * Rn * (a + 0.95 * (b - a));
    double sum = 0;
    const int seeds = 100;
    for (int k = 0; k < seeds; k++) {
        char yaml[1024];
        snprintf(yaml, sizeof yaml,
                 "profile: {points: [[-1, 0], [1, 0]], material: m}\n"
                 "materials: {m: {R_n: %g, R_t: 1, friction_angle: 30}}\n"
                 "block: {shape: point, mass: 1}\n"
                 "release: {x: 0, y: {uniform: [%g, %g]}}\n"
                 "bounce: {contact_speed: 1}\n"
                 "samples: %zu\nseed: %d\nrecord: 0\nsampling: %s\n", Rn, a, b, N, 1000 + k, lhs ? "lhs" : "random");
        rf_traj_spec s;
        load(yaml, &s);
        rf_traj_ensemble e;
        rf_error err;
        assert_int_equal(rf_traj_run(&s, 1, &e, &err), RF_OK);
        double q = rf_traj_percentiles_of(e.rebound_height, N).p95;
        sum += (q - exact) * (q - exact);
        rf_traj_ensemble_free(&e);
        rf_traj_spec_free(&s);
    }
    *se = sqrt(0.95 * 0.05 / (double)N) * Rn * Rn * (b - a);
    return sqrt(sum / seeds);
}

static void test_p95_convergence_rate(void **state)
{
    (void)state;
    double se[3], r[3];
    size_t N[3] = {250, 1000, 4000};
    for (int i = 0; i < 3; i++) {
        r[i] = p95_rmse(N[i], 0, &se[i]);
        print_message("N = %5zu: RMSE of p95 %.4g, theory %.4g\n", N[i], r[i], se[i]);
        /* 100 seeds: the RMSE estimate itself scatters by ~ 1/sqrt(200) = 7 % */
        assert_true(r[i] > 0.6 * se[i] && r[i] < 1.5 * se[i]);
    }
    double slope = log(r[2] / r[0]) / log((double)N[2] / (double)N[0]);
    print_message("observed rate N^%.3f (expected -0.5)\n", slope);
    assert_true(slope > -0.65 && slope < -0.35);
}

/* With sampling: lhs each of the N equal strata of U[a, b] holds exactly one drop height. */
static void test_lhs_strata(void **state)
{
    (void)state;
    const size_t N = 97;
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[-1, 0], [1, 0]], material: m}\n"
             "materials: {m: {R_n: 1, R_t: 1, friction_angle: 30}}\n"
             "block: {shape: point, mass: 1}\n"
             "release: {x: 0, y: {uniform: [2, 12]}}\n"
             "stop: {max_steps: 3}\n"
             "samples: %zu\nseed: 5\nsampling: lhs\n", N);
    rf_traj_spec s;
    load(yaml, &s);
    rf_traj_ensemble e;
    rf_error err;
    assert_int_equal(rf_traj_run(&s, 2, &e, &err), RF_OK);
    assert_ensemble_invariants(&s, &e);
    int *count = calloc(N, sizeof *count);
    for (size_t i = 0; i < N; i++) {
        double h = e.rebound_height[i]; /* R_n = 1: rebound to the release height */
        size_t k = (size_t)((h - 2) / 10 * (double)N);
        assert_true(k < N);
        count[k]++;
    }
    for (size_t k = 0; k < N; k++)
        assert_int_equal(count[k], 1);
    free(count);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

static void test_normal_quantile(void **state)
{
    (void)state;
    assert_close(rf_traj_normal_quantile(0.975), 1.959963984540054, 1e-14);
    assert_close(rf_traj_normal_quantile(0.5 + 0.3413447460685429), 1.0, 1e-13);
    assert_close(rf_traj_normal_quantile(1e-10), -6.361340902404056, 1e-13);
    assert_true(rf_traj_normal_quantile(0.5) == 0);
    double u = rf_traj_uniform(1, 2, 3);
    assert_true(u > 0 && u < 1 && u == rf_traj_uniform(1, 2, 3) && u != rf_traj_uniform(1, 2, 4));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_bits_any_threads),
        cmocka_unit_test(test_p95_convergence_rate),
        cmocka_unit_test(test_lhs_strata),
        cmocka_unit_test(test_normal_quantile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
