/* test_trajectory_study.c - the trajectory model in a `rockfuzz run` study.
 * Hybrid closed form: a point dropped from h ~ U[a, b] onto flat ground
 * rebounds to R_n^2 h, so with a fuzzy R_n the p95 rebound height at the cut
 * [r_lo, r_hi] is [r_lo^2, r_hi^2] (a + 0.95 (b - a)); the TM over the Monte
 * Carlo must match it within 3 standard errors of the sample quantile,
 * sqrt(0.95 * 0.05 / N) R_n^2 (b - a).  Also: the general form is the
 * default, bindings are checked, and common random numbers make the model a
 * deterministic function of its inputs. */
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

static void test_binding_errors(void **state)
{
    (void)state;
    rf_study s;
    rf_error err;
    assert_int_not_equal(load_study("parameters: {Rn: {tfn: [0.5, 0.2, 0.2]}}\n"
                                    "model: {trajectory: {file: traj_drop.yaml, bind: {Rn: materials.ground.Q}}}\n",
                                    &s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "traj_study.yaml:2: model.trajectory.bind.Rn = materials.ground.Q"));
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
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
