/* test_store_tm.c - rf_tm_options.tolerate_failures: by default a failed
 * evaluation stops the run (message with the parameter vector); when
 * tolerated, the failed point (or a NaN output) is left out of the min/max of
 * every cut and counted (the reduced grid is the 2^n corners of each cut), through the serial evaluator and the threaded runner. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "rockfuzz/runner.h"
#include "rockfuzz/tm.h"
#include "test_util.h"

static int nan_mode; /* 0: the bad point fails, 1: it returns NaN */

/* y = 2 x0 + x1; the point x0 == 1 (left end of the support of x0) is bad. */
static rf_status lin_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    (void)ctx;
    if (x[0] == 1.0) {
        if (nan_mode) {
            y[0] = NAN;
            return RF_OK;
        }
        return rf_fail(err, RF_EMODEL, "mesh inverted");
    }
    y[0] = 2 * x[0] + x[1];
    return RF_OK;
}

static rf_model lin_model(void)
{
    rf_model m;
    memset(&m, 0, sizeof m);
    const char *names[1] = {"y"};
    rf_model_init_outputs(&m, 1, names, NULL, NULL);
    m.n_inputs = 2;
    m.eval = lin_eval;
    m.threads_per_eval = 1;
    return m;
}

static void run_case(int tolerate, int threaded, int nan)
{
    nan_mode = nan;
    rf_model m = lin_model();
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 2, 1, 1, NULL);
    rf_fuzzy_tfn(&in[1], 3, 1, 2, NULL);
    rf_runner r;
    rf_runner_init(&r);
    r.jobs = 2;
    r.tolerate_failures = tolerate;
    rf_evaluator ev = rf_runner_evaluator(&r);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = RF_TM_REDUCED;
    opt.levels = 2;
    opt.left_right = 0;
    opt.tolerate_failures = tolerate;
    if (threaded)
        opt.evaluator = &ev;
    rf_tm_result res;
    rf_error err;
    memset(&err, 0, sizeof err);
    rf_status st = rf_tm_run(in, 2, &m, &opt, &res, &err);
    if (!tolerate) {
        assert_int_not_equal(st, RF_OK);
        assert_non_null(strstr(err.msg, nan ? "NaN at parameters (1, 2)" : "at parameters (1, 2)"));
    } else {
        assert_int_equal(st, RF_OK);
        /* the reduced grid of level 0 holds the corners (1,2), (1,5), (3,2), (3,5): two are bad */
        assert_int_equal(res.failed_points, 2);
        assert_int_equal(res.nan_points[0], 2);
        /* level 0 without y(1,2) = 4: the lower bound comes from level 1, y(1.5,2.5) = 5.5 */
        assert_close(res.lo[0], 5.5, 1e-15);
        assert_close(res.hi[0], 2 * 3.0 + 5.0, 1e-15);
        assert_close(res.lo[1], 5.5, 1e-15);
        assert_close(res.lo[2], 7.0, 1e-15); /* nominal level untouched */
        assert_int_equal(res.output_undefined[0], 0);
        rf_tm_result_free(&res);
    }
    rf_fuzzy_free(&in[0]);
    rf_fuzzy_free(&in[1]);
    rf_model_free(&m);
}

static void test_failure_stops_by_default(void **state)
{
    (void)state;
    run_case(0, 0, 0);
    run_case(0, 1, 0);
    run_case(0, 0, 1);
}

static void test_tolerated_failure_left_out(void **state)
{
    (void)state;
    run_case(1, 0, 0);
    run_case(1, 1, 0);
    run_case(1, 1, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_failure_stops_by_default),
        cmocka_unit_test(test_tolerated_failure_left_out),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
