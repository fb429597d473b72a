/* test_tm_values.c - extra outputs of a finished TM run (rf_tm_point_inputs,
 * rf_tm_retransform_values, rf_analysis_compute_values) against a second
 * method: the run itself.  Every scalar output of real runs (general,
 * reduced and extended forms, m = 1..4, with and without the left/right
 * grids, monotonic and non-monotonic models) is recomputed at every distinct
 * point from the inputs the point list gives, fed back, and must give the
 * run's cuts and every analysis number to the bit (memcmp). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "rockfuzz/analysis.h"
#include "rockfuzz/fuzzy.h"
#include "rockfuzz/tm.h"
#include "test_util.h"

#define NOUT 4

/* monotonic product, non-monotonic sine and saddle, a flat (crisp) output */
static void f_mix(const double *x, double *y)
{
    y[0] = x[0] * x[1] + x[2];
    y[1] = sin(3.0 * x[0]) * cos(2.0 * x[1]) + x[2] * x[2];
    y[2] = (x[0] - 2.1) * (x[0] - 2.1) - (x[1] - 2.9) * (x[2] - 0.4);
    y[3] = 2.5;
}

static void make_inputs(rf_fuzzy *in)
{
    assert_int_equal(rf_fuzzy_tfn(&in[0], 2, 1, 1, NULL), RF_OK);
    assert_int_equal(rf_fuzzy_tfn(&in[1], 3, 0.5, 2, NULL), RF_OK);
    assert_int_equal(rf_fuzzy_trapezoid(&in[2], -0.5, 0.2, 0.5, 1.5, NULL), RF_OK);
}

static int same_bits(const void *a, const void *b, size_t bytes) { return memcmp(a, b, bytes) == 0; }

/* Output k's slice of every per-output array of the two analyses. */
static void check_analysis(const rf_analysis *an, size_t k, const rf_analysis *av, size_t n, size_t m)
{
    size_t nk = n, at = k * n;
    assert_true(same_bits(an->gain + at * m, av->gain, nk * m * sizeof(double)));
    const double *const full[] = {an->mean_gain, an->std_gain, an->kappa, an->rho,
                                  an->kappa_left, an->kappa_right, an->rho_left, an->rho_right};
    const double *const one[] = {av->mean_gain, av->std_gain, av->kappa, av->rho,
                                 av->kappa_left, av->kappa_right, av->rho_left, av->rho_right};
    for (size_t a = 0; a < 8; a++)
        if (!same_bits(full[a] + at, one[a], nk * sizeof(double)))
            fail_msg("analysis array %zu of output %zu differs", a, k);
    assert_true(same_bits(an->reason_hanss + at, av->reason_hanss, nk * sizeof(rf_na_reason)));
    assert_true(same_bits(an->reason_std + at, av->reason_std, nk * sizeof(rf_na_reason)));
    assert_true(same_bits(an->reason_lr + at, av->reason_lr, nk * sizeof(rf_na_reason)));
    assert_true(same_bits(an->degree_of_uncertainty + k, av->degree_of_uncertainty, sizeof(double)));
    assert_true(same_bits(an->interaction + k, av->interaction, sizeof(double)));
    assert_true(same_bits(an->reason_nu + k, av->reason_nu, sizeof(rf_na_reason)));
}

/* Every output of one run fed back, one column at a time and all at once. */
static void check_run(rf_tm_scheme scheme, size_t m, int lr)
{
    rf_fuzzy in[3];
    make_inputs(in);
    rf_model model = test_model(3, NOUT, f_mix);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = scheme;
    opt.levels = m;
    opt.left_right = lr;
    rf_tm_result res;
    rf_error err = {0};
    if (rf_tm_run(in, 3, &model, &opt, &res, &err))
        fail_msg("rf_tm_run: %s", err.msg);
    rf_analysis an;
    assert_int_equal(rf_analysis_compute(&res, &an, &err), RF_OK);
    size_t np = rf_tm_point_count(&res), m1 = m + 1;
    assert_int_equal(np, res.distinct);
    assert_int_equal(test_model_calls(&model), np); /* every distinct point evaluated once */
    double *y = malloc(NOUT * np * sizeof(double)), *lo = malloc(NOUT * m1 * sizeof(double));
    double *hi = malloc(NOUT * m1 * sizeof(double)), x[3], out[NOUT];
    for (size_t id = 0; id < np; id++) { /* the second method: the model again, at the listed inputs */
        assert_int_equal(rf_tm_point_inputs(&res, id, x, &err), RF_OK);
        f_mix(x, out);
        for (size_t k = 0; k < NOUT; k++)
            y[k * np + id] = out[k];
    }
    assert_int_equal(rf_tm_point_inputs(&res, np, x, &err), RF_EINVAL);
    for (size_t k = 0; k < NOUT; k++) {
        rf_analysis av;
        assert_int_equal(rf_tm_retransform_values(&res, 1, y + k * np, lo, hi, &err), RF_OK);
        assert_true(same_bits(lo, res.lo + k * m1, m1 * sizeof(double)));
        assert_true(same_bits(hi, res.hi + k * m1, m1 * sizeof(double)));
        memset(lo, 0, m1 * sizeof(double));
        assert_int_equal(rf_analysis_compute_values(&res, 1, y + k * np, lo, NULL, &av, &err), RF_OK);
        assert_true(same_bits(lo, res.lo + k * m1, m1 * sizeof(double)));
        assert_int_equal(av.n_outputs, 1);
        check_analysis(&an, k, &av, 3, m);
        rf_analysis_free(&av);
    }
    rf_analysis all; /* all columns in one call: the same numbers */
    assert_int_equal(rf_analysis_compute_values(&res, NOUT, y, lo, hi, &all, &err), RF_OK);
    assert_true(same_bits(lo, res.lo, NOUT * m1 * sizeof(double)));
    assert_true(same_bits(hi, res.hi, NOUT * m1 * sizeof(double)));
    for (size_t k = 0; k < NOUT; k++) {
        rf_analysis one = all;
        one.gain += k * 3 * m;
        one.mean_gain += k * 3, one.std_gain += k * 3, one.kappa += k * 3, one.rho += k * 3;
        one.kappa_left += k * 3, one.kappa_right += k * 3, one.rho_left += k * 3, one.rho_right += k * 3;
        one.reason_hanss += k * 3, one.reason_std += k * 3, one.reason_lr += k * 3;
        one.degree_of_uncertainty += k, one.interaction += k, one.reason_nu += k;
        check_analysis(&an, k, &one, 3, m);
    }
    rf_analysis_free(&all);
    free(y);
    free(lo);
    free(hi);
    rf_analysis_free(&an);
    rf_tm_result_free(&res);
    rf_model_free(&model);
    for (size_t i = 0; i < 3; i++)
        rf_fuzzy_free(&in[i]);
}

static void test_bit_identical(void **state)
{
    (void)state;
    for (int s = 0; s < 3; s++)
        for (size_t m = 1; m <= 4; m++)
            for (int lr = 0; lr <= 1; lr++)
                check_run((rf_tm_scheme)s, m, lr);
}

/* The non-monotonic output really is: its general-form cut is wider than the
 * reduced form's corners give (so the test above covered both cases). */
static void test_general_differs_from_reduced(void **state)
{
    (void)state;
    rf_fuzzy in[3];
    make_inputs(in);
    rf_tm_result r[2];
    for (int s = 0; s < 2; s++) {
        rf_model model = test_model(3, NOUT, f_mix);
        rf_tm_options opt;
        rf_tm_options_default(&opt);
        opt.scheme = s ? RF_TM_REDUCED : RF_TM_GENERAL;
        opt.levels = 3;
        assert_int_equal(rf_tm_run(in, 3, &model, &opt, &r[s], NULL), RF_OK);
        rf_model_free(&model);
    }
    assert_true(r[0].lo[1 * 4] < r[1].lo[1 * 4] - 1e-3); /* output 1, level 0 */
    for (int s = 0; s < 2; s++)
        rf_tm_result_free(&r[s]);
    for (size_t i = 0; i < 3; i++)
        rf_fuzzy_free(&in[i]);
}

/* NaN values: left out of the bounds; a column NaN everywhere is undefined. */
static void test_nan_columns(void **state)
{
    (void)state;
    rf_fuzzy in[3]; /* single peaks, no left/right grid: every point is on a main grid */
    make_inputs(in);
    rf_fuzzy_free(&in[2]);
    assert_int_equal(rf_fuzzy_tfn(&in[2], 0.3, 0.8, 1.2, NULL), RF_OK);
    rf_model model = test_model(3, NOUT, f_mix);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = RF_TM_GENERAL;
    opt.levels = 2;
    opt.left_right = 0;
    rf_tm_result res;
    assert_int_equal(rf_tm_run(in, 3, &model, &opt, &res, NULL), RF_OK);
    size_t np = rf_tm_point_count(&res);
    double *y = malloc(2 * np * sizeof(double)), x[3], lo[6], hi[6];
    double bmin = INFINITY, bmax = -INFINITY; /* brute force over every point with x0 >= 2 */
    for (size_t id = 0; id < np; id++) {
        rf_tm_point_inputs(&res, id, x, NULL);
        double v = x[0] + 10 * x[1] + 100 * x[2];
        y[id] = x[0] >= 2 ? v : NAN;
        y[np + id] = NAN;
        if (x[0] >= 2) {
            bmin = fmin(bmin, v);
            bmax = fmax(bmax, v);
        }
    }
    assert_int_equal(rf_tm_retransform_values(&res, 2, y, lo, hi, NULL), RF_OK);
    assert_close(lo[0], bmin, 1e-15);
    assert_close(hi[0], bmax, 1e-15);
    for (size_t j = 0; j < 3; j++)
        assert_true(isnan(lo[3 + j]) && isnan(hi[3 + j]));
    assert_int_equal(rf_tm_retransform_values(&res, 0, y, lo, hi, NULL), RF_EINVAL);
    free(y);
    rf_tm_result_free(&res);
    rf_model_free(&model);
    for (size_t i = 0; i < 3; i++)
        rf_fuzzy_free(&in[i]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bit_identical),
        cmocka_unit_test(test_general_differs_from_reduced),
        cmocka_unit_test(test_nan_columns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
