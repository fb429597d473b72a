/* test_trajectory_study.c - the trajectory model in a `rockfuzz run` study.
 * Hybrid closed form: a point dropped from h ~ U[a, b] onto flat ground
 * rebounds to R_n^2 h, so with a fuzzy R_n the p95 rebound height at the cut
 * [r_lo, r_hi] is [r_lo^2, r_hi^2] (a + 0.95 (b - a)); the TM over the Monte
 * Carlo must match it within 3 standard errors of the sample quantile,
 * sqrt(0.95 * 0.05 / N) R_n^2 (b - a).  Also: the general form is the
 * default, bindings are checked, common random numbers make the model a
 * deterministic function of its inputs, and a fuzzy exceedance probability
 * (runout, energy at a collector) matches its closed form. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/study.h"
#include "rockfuzz/tm.h"
#include "rockfuzz/trajectory.h"
#include "test_util.h"

static const char *drop_yaml =
    "name: drop\n"
    "profile: {points: [[-1, 0], [1, 0]], material: ground}\n"
    "materials: {ground: {R_n: 0.5, R_t: 0.8, friction_angle: 30}}\n"
    "block: {shape: point, mass: 100}\n"
    "release: {x: 0, y: {uniform: [2, 12]}}\n"
    "bounce: {contact_speed: 1}\n"
    "samples: 4000\nseed: 11\n";

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static rf_status load_study(const char *study_text, rf_study *s, rf_error *err)
{
    write_file("traj_drop.yaml", drop_yaml);
    write_file("traj_study.yaml", study_text);
    return rf_study_load("traj_study.yaml", s, err);
}

static size_t output_index(const rf_model *m, const char *name)
{
    for (size_t k = 0; k < m->n_outputs; k++)
        if (!strcmp(m->output_names[k], name))
            return k;
    fail_msg("no output %s", name);
    return 0;
}

static void test_hybrid_closed_form(void **state)
{
    (void)state;
    rf_study s;
    rf_error err;
    if (load_study("levels: 4\n"
                   "parameters: {Rn: {tfn: [0.5, 0.2, 0.2]}}\n"
                   "model: {trajectory: {file: traj_drop.yaml, bind: {Rn: materials.ground.R_n}}}\n",
                   &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s.model_kind, RF_STUDY_MODEL_TRAJECTORY);
    assert_int_equal(s.scheme, RF_TM_GENERAL);
    rf_tm_options opt;
    rf_study_tm_options(&s, &opt);
    rf_tm_result r;
    assert_int_equal(rf_tm_run(s.inputs, s.n_params, &s.model, &opt, &r, &err), RF_OK);
    size_t k = output_index(&s.model, "rebound_height_p95"), m = r.levels;
    const double N = 4000, q95 = 2 + 0.95 * 10;
    for (size_t j = 0; j <= m; j++) {
        double rlo = r.in_lo[j], rhi = r.in_hi[j];
        double lo = r.lo[k * (m + 1) + j], hi = r.hi[k * (m + 1) + j];
        double se_lo = sqrt(0.95 * 0.05 / N) * rlo * rlo * 10, se_hi = sqrt(0.95 * 0.05 / N) * rhi * rhi * 10;
        print_message("mu = %zu/%zu: p95 [%.5f, %.5f], closed form [%.5f, %.5f] +- 3 se [%.4f, %.4f]\n", j, m, lo, hi,
                      rlo * rlo * q95, rhi * rhi * q95, 3 * se_lo, 3 * se_hi);
        assert_true(fabs(lo - rlo * rlo * q95) <= 3 * se_lo);
        assert_true(fabs(hi - rhi * rhi * q95) <= 3 * se_hi);
    }
    /* common random numbers: the bounds are exactly R_n^2 times one sample quantile */
    double q = r.hi[k * (m + 1) + m] / (r.in_hi[m] * r.in_hi[m]);
    assert_close(r.lo[k * (m + 1)] / (r.in_lo[0] * r.in_lo[0]), q, 1e-9);
    rf_tm_result_free(&r);
    rf_study_free(&s);
}

/* A fuzzy exceedance probability, closed form: a point released on flat
 * ground at v0 ~ U[5, 15] m/s slides to x = v0^2 / (2 g tan phi), so
 * P(runout_x > X) = (15 - sqrt(2 g tan phi X)) / 10; at a collector at xc its
 * energy is m (v0^2 - 2 g tan phi xc) / 2, so P(E > Es) = (15 - sqrt(2 Es / m +
 * 2 g tan phi xc)) / 10.  Both fall with phi: the cut [phi_lo, phi_hi] gives
 * [P(phi_hi), P(phi_lo)], within 3 standard errors sqrt(P (1 - P) / N). */
static const char *slide_yaml =
    "name: slide\n"
    "profile: {points: [[-1, 0], [300, 0]], material: ground}\n"
    "materials: {ground: {R_n: 0.3, R_t: 0.8, friction_angle: 30}}\n"
    "block: {shape: point, mass: 1000}\n"
    "release: {x: 0, y: 0, vx: {uniform: [5, 15]}, vy: 0}\n"
    "collectors: [{name: c, x: 4, energy_thresholds: [30000]}]\n"
    "outputs: {runout_thresholds: [8]}\n"
    "samples: 2000\nseed: 5\n";

static double p_exceed(double v_star) { return (15 - v_star) / 10; }

static void test_fuzzy_exceedance_closed_form(void **state)
{
    (void)state;
    rf_study s;
    rf_error err;
    write_file("traj_slide.yaml", slide_yaml);
    write_file("traj_slide_study.yaml", "levels: 3\nparameters: {phi: {tfn: [30, 5, 5]}}\n"
                                        "model: {trajectory: {file: traj_slide.yaml, "
                                        "bind: {phi: materials.ground.friction_angle}}}\n");
    if (rf_study_load("traj_slide_study.yaml", &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    rf_tm_options opt;
    rf_study_tm_options(&s, &opt);
    rf_tm_result r;
    assert_int_equal(rf_tm_run(s.inputs, s.n_params, &s.model, &opt, &r, &err), RF_OK);
    size_t kx = output_index(&s.model, "p_runout_x_above_8m"), ke = output_index(&s.model, "c_p_total_energy_above_30000J");
    size_t m = r.levels;
    const double g = 9.81, DEG = 3.14159265358979323846 / 180, N = 2000;
    for (size_t j = 0; j <= m; j++) {
        double t_lo = tan(r.in_lo[j] * DEG), t_hi = tan(r.in_hi[j] * DEG);
        double px[2] = {p_exceed(sqrt(2 * g * t_hi * 8)), p_exceed(sqrt(2 * g * t_lo * 8))};
        double pe[2] = {p_exceed(sqrt(60 + 2 * g * t_hi * 4)), p_exceed(sqrt(60 + 2 * g * t_lo * 4))};
        double got_x[2] = {r.lo[kx * (m + 1) + j], r.hi[kx * (m + 1) + j]};
        double got_e[2] = {r.lo[ke * (m + 1) + j], r.hi[ke * (m + 1) + j]};
        for (int b = 0; b < 2; b++) {
            print_message("mu = %zu/%zu: P(runout > 8 m) %.4f (closed form %.4f), P(E > 30 kJ) %.4f (%.4f)\n", j, m,
                          got_x[b], px[b], got_e[b], pe[b]);
            assert_true(fabs(got_x[b] - px[b]) <= 3 * sqrt(px[b] * (1 - px[b]) / N));
            assert_true(fabs(got_e[b] - pe[b]) <= 3 * sqrt(pe[b] * (1 - pe[b]) / N));
        }
    }
    assert_true(r.hi[kx * (m + 1)] - r.lo[kx * (m + 1)] > 0.1); /* really fuzzy */
    rf_tm_result_free(&r);
    rf_study_free(&s);
}

static void test_binding_errors(void **state)
{
    (void)state;
    rf_study s;
    rf_error err;
    assert_int_not_equal(load_study("parameters: {Rn: {tfn: [0.5, 0.2, 0.2]}}\n"
                                    "model: {trajectory: {file: traj_drop.yaml, bind: {Rn: materials.ground.Q}}}\n",
                                    &s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "traj_study.yaml:2: model.trajectory.bind.Rn = materials.ground.Q"));
    /* a typo: the nearest bindable path (from the input tables) and the list */
    assert_int_not_equal(load_study("parameters: {Rn: {tfn: [0.5, 0.2, 0.2]}}\n"
                                    "model: {trajectory: {file: traj_drop.yaml, bind: {Rn: materials.ground.Rn}}}\n",
                                    &s, &err), RF_OK);
    if (!strstr(err.msg, "traj_study.yaml:2: model.trajectory.bind.Rn = materials.ground.Rn") ||
        !strstr(err.msg, "did you mean 'materials.ground.R_n'?") ||
        !strstr(err.msg, "materials.ground.friction_angle [deg]"))
        fail_msg("%s", err.msg);
    assert_int_not_equal(load_study("parameters: {Rn: {tfn: [0.9, 0.2, 0.2]}}\n"
                                    "model: {trajectory: {file: traj_drop.yaml, bind: {Rn: materials.ground.R_n}}}\n",
                                    &s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "traj_study.yaml:1: parameters.Rn: the value 1.1"));
    assert_int_not_equal(load_study("parameters: {h: {tfn: [5, 1, 1]}}\n"
                                    "model: {trajectory: {file: traj_drop.yaml, bind: {h: release.y}}}\n",
                                    &s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "random in the trajectory file"));
    assert_int_not_equal(load_study("parameters: {h: {tfn: [5, 1, 1]}}\n"
                                    "model: {trajectory: {file: traj_drop.yaml}}\n", &s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "parameters.h: not bound"));
    /* a distribution parameter whose support sends random draws under the ground */
    assert_int_not_equal(load_study("parameters: {h: {tfn: [1, 2, 2]}}\n"
                                    "model: {trajectory: {file: traj_drop.yaml, bind: {h: release.y.lo}}}\n",
                                    &s, &err), RF_OK);
    if (!strstr(err.msg, "traj_study.yaml:1: parameters.h: the value -1") || !strstr(err.msg, "reaches -1"))
        fail_msg("%s", err.msg);
    /* a distribution parameter can be fuzzy, and an explicit scheme is kept */
    if (load_study("scheme: reduced\nparameters: {h: {tfn: [12, 1, 1]}}\n"
                   "model: {trajectory: {file: traj_drop.yaml, samples: 10, bind: {h: release.y.hi}}}\n",
                   &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s.scheme, RF_TM_REDUCED);
    double x = 12, y1[64], y2[64];
    assert_true(s.model.n_outputs <= 64);
    assert_int_equal(rf_model_eval(&s.model, &x, y1, &err), RF_OK);
    assert_int_equal(rf_model_eval(&s.model, &x, y2, &err), RF_OK);
    assert_memory_equal(y1, y2, s.model.n_outputs * sizeof(double));
    rf_study_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hybrid_closed_form),
        cmocka_unit_test(test_binding_errors),
        cmocka_unit_test(test_fuzzy_exceedance_closed_form),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
