/* test_tm.c - the Transformation Method against the test vectors of
 * tm_spec.md s.6 (independent prototype, exact analytic values for the
 * monotone ones), interval arithmetic, evaluation-count formulas and a
 * dense-grid optimum for non-monotone models. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include <cmocka.h>

#include "rockfuzz/analysis.h"
#include "rockfuzz/fuzzy.h"
#include "rockfuzz/tm.h"
#include "test_util.h"
#include "tm/tm_internal.h"

#define RTOL 1e-12

static rf_tm_result run(const rf_fuzzy *in, size_t n, rf_model *model, rf_tm_scheme scheme, size_t m, int lr)
{
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = scheme;
    opt.levels = m;
    opt.left_right = lr;
    rf_tm_result res;
    rf_error err = {0};
    rf_status st = rf_tm_run(in, n, model, &opt, &res, &err);
    if (st)
        fail_msg("rf_tm_run: %s", err.msg);
    return res;
}

static void check_cuts(const rf_tm_result *r, size_t k, const double *lo, const double *hi)
{
    size_t m = r->levels;
    for (size_t j = 0; j <= m; j++) {
        assert_close(r->lo[k * (m + 1) + j], lo[j], RTOL);
        assert_close(r->hi[k * (m + 1) + j], hi[j], RTOL);
    }
}

/* ---- A: product, monotone (s.6.1) */
static void f_product(const double *x, double *y) { y[0] = x[0] * x[1]; }

static void test_vector_A(void **state)
{
    (void)state;
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 2, 1, 1, NULL);
    rf_fuzzy_tfn(&in[1], 3, 1, 2, NULL);
    const double lo[] = {2, 2.8125, 3.75, 4.8125, 6}, hi[] = {15, 12.375, 10, 7.875, 6};
    for (int s = 0; s < 3; s++) {
        rf_model model = test_model(2, 1, f_product);
        rf_tm_result r = run(in, 2, &model, (rf_tm_scheme)s, 4, 0);
        check_cuts(&r, 0, lo, hi);
        if (s == RF_TM_GENERAL)
            assert_int_equal(r.requested, 55);
        if (s == RF_TM_REDUCED) {
            assert_int_equal(r.requested, 17);
            assert_int_equal(r.distinct, 17);
            assert_int_equal(test_model_calls(&model), 17);
        }
        /* bound-producing inputs: level 0 min at (1, 2), max at (3, 5) */
        assert_close(r.x_lo[0], 1, RTOL);
        assert_close(r.x_lo[1], 2, RTOL);
        assert_close(r.x_hi[0], 3, RTOL);
        assert_close(r.x_hi[1], 5, RTOL);
        rf_tm_result_free(&r);
        rf_model_free(&model);
    }
    /* reduced-form gains and Hanss measures */
    rf_model model = test_model(2, 1, f_product);
    rf_tm_result r = run(in, 2, &model, RF_TM_REDUCED, 4, 1);
    rf_analysis an;
    assert_int_equal(rf_analysis_compute(&r, &an, NULL), RF_OK);
    const double eta1[] = {3.5, 3.375, 3.25, 3.125};
    for (int j = 0; j < 4; j++) {
        assert_close(an.gain[0 * 4 + j], eta1[j], RTOL);
        assert_close(an.gain[1 * 4 + j], 2, RTOL);
    }
    assert_close(an.mean_gain[0], 3.2083333333333333, 1e-12);
    assert_close(an.mean_gain[1], 2, RTOL);
    assert_close(an.kappa[0], 2.7083333333333333, 1e-12);
    assert_close(an.kappa[1], 2.5, RTOL);
    assert_close(an.rho[0], 0.52, RTOL);
    assert_close(an.rho[1], 0.48, RTOL);
    /* s.5.4 [P] values of the prototype (6 digits given) */
    assert_close(an.kappa_left[0], 0.269097, 2e-6);
    assert_close(an.kappa_left[1], 0.166667, 2e-6);
    assert_close(an.kappa_right[0], 0.269097, 2e-6);
    assert_close(an.kappa_right[1], 0.333333, 2e-6);
    assert_close(an.rho_left[0], 0.259197, 2e-6);
    assert_close(an.rho_left[1], 0.160535, 2e-6);
    assert_close(an.rho_right[0], 0.259197, 2e-6);
    assert_close(an.rho_right[1], 0.321070, 2e-6);
    assert_close(an.degree_of_uncertainty[0], 1.057292, 2e-6);
    assert_close(an.interaction[0], 1.057292 - 1.038194, 1e-4);
    /* three-point grid: m (3^n - 1) + 1 = 33 distinct points, of which the
     * 17 corners/peak are shared with the reduced grid except the level
     * corners that coincide: count what only the LR grid needed */
    assert_int_equal(r.distinct, 17 + r.lr_evaluations);
    rf_analysis_free(&an);
    rf_tm_result_free(&r);
    rf_model_free(&model);
}

/* ---- B: non-monotone 1-D (s.6.2) */
static void f_shifted_square(const double *x, double *y) { y[0] = (x[0] - 0.33) * (x[0] - 0.33); }

static void test_vector_B(void **state)
{
    (void)state;
    rf_fuzzy in;
    rf_fuzzy_tfn(&in, 0, 1, 1, NULL);
    const double lo[] = {0.0064, 0.0064, 0.0064, 0.0064, 0.1089}, hi[] = {1.7689, 1.1664, 0.6889, 0.3364, 0.1089};
    rf_model model = test_model(1, 1, f_shifted_square);
    rf_tm_result r = run(&in, 1, &model, RF_TM_GENERAL, 4, 0);
    check_cuts(&r, 0, lo, hi);
    assert_int_equal(r.requested, 15);
    assert_int_equal(r.monotonicity[0], RF_MONO_NONMONOTONIC);
    rf_tm_result_free(&r);
    rf_model_free(&model);
    model = test_model(1, 1, f_shifted_square);
    r = run(&in, 1, &model, RF_TM_REDUCED, 4, 0);
    check_cuts(&r, 0, lo, hi);
    assert_int_equal(r.requested, 9);
    assert_int_equal(r.monotonicity[0], RF_MONO_AUTO); /* not checked without the three-point grid */
    rf_tm_result_free(&r);
    rf_model_free(&model);
    /* with the three-point grid the reduced form's diagnostic fires */
    model = test_model(1, 1, f_shifted_square);
    r = run(&in, 1, &model, RF_TM_REDUCED, 4, 1);
    assert_int_equal(r.monotonicity[0], RF_MONO_NONMONOTONIC);
    rf_tm_result_free(&r);
    rf_model_free(&model);
}

/* ---- C: non-monotone in one of two parameters (s.6.3) + extended form */
static void f_square_plus(const double *x, double *y) { y[0] = x[0] * x[0] + x[1]; }

static void test_vector_C(void **state)
{
    (void)state;
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 0, 1, 1, NULL);
    rf_fuzzy_tfn(&in[1], 1, 0.5, 0.5, NULL);
    const double glo[] = {0.5, 0.6875, 0.75, 0.9375, 1}, ghi[] = {2.5, 1.9375, 1.5, 1.1875, 1};
    rf_model model = test_model(2, 1, f_square_plus);
    rf_tm_result g = run(in, 2, &model, RF_TM_GENERAL, 4, 0);
    check_cuts(&g, 0, glo, ghi);
    size_t general_distinct = g.distinct;
    rf_tm_result_free(&g);
    rf_model_free(&model);

    const double rlo[] = {0.9375, 0.9375, 0.9375, 0.9375, 1};
    model = test_model(2, 1, f_square_plus);
    rf_tm_result r = run(in, 2, &model, RF_TM_REDUCED, 4, 0);
    check_cuts(&r, 0, rlo, ghi);
    rf_tm_result_free(&r);
    rf_model_free(&model);

    model = test_model(2, 1, f_square_plus);
    rf_tm_result e = run(in, 2, &model, RF_TM_EXTENDED, 4, 0);
    check_cuts(&e, 0, glo, ghi);
    assert_int_equal(e.input_class[0], RF_MONO_NONMONOTONIC);
    assert_int_equal(e.input_class[1], RF_MONO_MONOTONIC);
    /* main grid of the extended form is smaller than the general one */
    size_t main_ext = e.distinct - e.probe_evaluations;
    assert_true(e.requested - 0 > 0);
    assert_true(main_ext < general_distinct);
    size_t main_requested = 0;
    for (size_t j = 0; j <= 4; j++)
        main_requested += e.data->main[j].count;
    assert_true(main_requested < rf_tm_count_general(2, 4));
    assert_int_equal(main_requested, 5 * 2 + 4 * 2 + 3 * 2 + 2 * 2 + 1);
    rf_tm_result_free(&e);
    rf_model_free(&model);

    /* forced classes skip the probe */
    rf_monotonicity force[2] = {RF_MONO_NONMONOTONIC, RF_MONO_MONOTONIC};
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = RF_TM_EXTENDED;
    opt.left_right = 0;
    opt.force_class = force;
    model = test_model(2, 1, f_square_plus);
    rf_error err;
    assert_int_equal(rf_tm_run(in, 2, &model, &opt, &e, &err), RF_OK);
    check_cuts(&e, 0, glo, ghi);
    assert_int_equal(e.probe_evaluations, 0);
    assert_int_equal(e.requested, 29);
    rf_tm_result_free(&e);
    rf_model_free(&model);
}

/* ---- L: linear model, analysis identities (s.6.4) */
static void f_linear(const double *x, double *y) { y[0] = 2 * x[0] - 3 * x[1]; }

static void test_vector_L(void **state)
{
    (void)state;
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 1, 0.5, 0.5, NULL);
    rf_fuzzy_tfn(&in[1], 2, 0.2, 0.4, NULL);
    const double lo[] = {-6.2, -5.65, -5.1, -4.55, -4}, hi[] = {-2.4, -2.8, -3.2, -3.6, -4};
    for (int s = 0; s < 3; s++) {
        rf_model model = test_model(2, 1, f_linear);
        rf_tm_result r = run(in, 2, &model, (rf_tm_scheme)s, 4, 1);
        check_cuts(&r, 0, lo, hi);
        rf_analysis an;
        assert_int_equal(rf_analysis_compute(&r, &an, NULL), RF_OK);
        for (int j = 0; j < 4; j++) {
            assert_close(an.gain[j], 2, 1e-12);
            assert_close(an.gain[4 + j], -3, 1e-12);
        }
        assert_close(an.rho[0], 2.0 / 3.8, 1e-12);
        assert_close(an.rho[1], 1.8 / 3.8, 1e-12);
        assert_close(an.kappa_left[0], 0.125, 1e-12);
        assert_close(an.kappa_left[1], 0.15, 1e-12);
        assert_close(an.kappa_right[0], 0.125, 1e-12);
        assert_close(an.kappa_right[1], 0.075, 1e-12);
        assert_close(an.degree_of_uncertainty[0], 0.475, 1e-12);
        assert_true(fabs(an.interaction[0]) < 1e-12); /* additive: nu = sum kappa */
        assert_close(an.rho_left[1], 0.315789473684210, 1e-12);
        assert_close(an.rho_right[1], 0.157894736842105, 1e-12);
        rf_analysis_free(&an);
        rf_tm_result_free(&r);
        rf_model_free(&model);
    }
}

/* ---- SG++ published test, trapezoids and flat cores (s.6.5) */
static void f_sgpp(const double *x, double *y) { y[0] = 6.4 * x[0] * x[1]; }

static void test_sgpp_trapezoids(void **state)
{
    (void)state;
    rf_fuzzy in[2];
    rf_fuzzy_trapezoid(&in[0], 0.375, 0.625, 0.75, 0.875, NULL);
    rf_fuzzy_trapezoid(&in[1], 0.05, 0.45, 0.55, 0.95, NULL);
    const double lo[] = {0.12, 0.42, 0.8, 1.26, 1.8}, hi[] = {5.32, 4.59, 3.9, 3.25, 2.64};
    for (int s = 0; s < 3; s++) {
        rf_model model = test_model(2, 1, f_sgpp);
        rf_tm_result r = run(in, 2, &model, (rf_tm_scheme)s, 4, 0);
        check_cuts(&r, 0, lo, hi);
        if (s == RF_TM_REDUCED)
            assert_int_equal(r.requested, 5 * 4); /* (m + 1) 2^n with flat cores */
        rf_tm_result_free(&r);
        rf_model_free(&model);
    }
}

/* ---- dependency: x - x and x / x (s.6.6) */
static void f_dependency(const double *x, double *y)
{
    y[0] = x[0] - x[0];
    y[1] = x[0] / x[0];
}

static void test_dependency(void **state)
{
    (void)state;
    rf_fuzzy in;
    rf_fuzzy_tfn(&in, 1, 0.5, 0.5, NULL);
    rf_model model = test_model(1, 2, f_dependency);
    rf_tm_result r = run(&in, 1, &model, RF_TM_REDUCED, 4, 1);
    for (size_t j = 0; j <= 4; j++) {
        assert_true(r.lo[j] == 0 && r.hi[j] == 0);
        assert_true(r.lo[5 + j] == 1 && r.hi[5 + j] == 1);
    }
    rf_analysis an;
    rf_analysis_compute(&r, &an, NULL);
    /* nominal output 0: normalised measures are n/a, not 0 */
    assert_true(isnan(an.degree_of_uncertainty[0]));
    assert_int_equal(an.reason_nu[0], RF_NA_ZERO_NOMINAL);
    assert_true(isnan(an.rho[0]));
    assert_int_equal(an.reason_hanss[0], RF_NA_ALL_ZERO);
    rf_analysis_free(&an);
    rf_tm_result_free(&r);
    rf_model_free(&model);
}

/* ---- evaluation counts (s.6.7) */
static void test_counts(void **state)
{
    (void)state;
    assert_int_equal(rf_tm_count_general(2, 4), 55);
    assert_int_equal(rf_tm_count_general(3, 10), 4356);
    assert_int_equal(rf_tm_count_general(4, 10), 39974);
    assert_int_equal(rf_tm_count_general(6, 10), 3749966);
    assert_int_equal(rf_tm_count_reduced(2, 4), 17);
    assert_int_equal(rf_tm_count_reduced(6, 10), 641);
    const struct {
        size_t n, m, distinct;
    } t[] = {{2, 4, 41}, {2, 10, 221}, {3, 10, 2331}, {4, 10, 24641}};
    for (size_t c = 0; c < 4; c++) {
        rf_fuzzy in[4];
        for (size_t i = 0; i < t[c].n; i++)
            rf_fuzzy_tfn(&in[i], (double)i + 1, 0.5, 0.5, NULL);
        rf_tm_options opt;
        rf_tm_options_default(&opt);
        opt.scheme = RF_TM_GENERAL;
        opt.levels = t[c].m;
        opt.left_right = 0;
        size_t rq, ds;
        assert_int_equal(rf_tm_count(in, t[c].n, &opt, &rq, &ds, NULL), RF_OK);
        assert_int_equal(rq, rf_tm_count_general(t[c].n, t[c].m));
        assert_int_equal(ds, t[c].distinct);
        /* three-point grids: 3^n points at levels 0..m-1, the nominal at m */
        opt.scheme = RF_TM_REDUCED;
        opt.left_right = 1;
        assert_int_equal(rf_tm_count(in, t[c].n, &opt, &rq, &ds, NULL), RF_OK);
        size_t p3 = 1;
        for (size_t i = 0; i < t[c].n; i++)
            p3 *= 3;
        assert_int_equal(rq, t[c].m * p3 + 1 + rf_tm_count_reduced(t[c].n, t[c].m));
        /* asymmetric inputs: essentially no reuse (tfn(0,1,2), n = 2, m = 4: 55) */
    }
    rf_fuzzy as[2];
    rf_fuzzy_tfn(&as[0], 0, 1, 2, NULL);
    rf_fuzzy_tfn(&as[1], 0, 1, 2, NULL);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = RF_TM_GENERAL;
    opt.left_right = 0;
    size_t rq, ds;
    rf_tm_count(as, 2, &opt, &rq, &ds, NULL);
    assert_int_equal(ds, 55);
}

/* ---- general-form points (s.2.1 examples) */
static void f_first(const double *x, double *y) { y[0] = x[0]; }

static void expect_level(const rf_tm_result *r, size_t j, const double *v, size_t k)
{
    const rf_grid *g = &r->data->main[j];
    assert_int_equal(g->radix[0], k);
    for (size_t l = 0; l < k; l++)
        assert_close(r->data->values[0][g->vidx[0][l]], v[l], 1e-12);
}

static void test_general_points(void **state)
{
    (void)state;
    rf_fuzzy in;
    rf_fuzzy_tfn(&in, 0, 1, 1, NULL);
    rf_model model = test_model(1, 1, f_first);
    rf_tm_result r = run(&in, 1, &model, RF_TM_GENERAL, 4, 0);
    expect_level(&r, 0, (double[]){-1, -0.5, 0, 0.5, 1}, 5);
    expect_level(&r, 1, (double[]){-0.75, -0.25, 0.25, 0.75}, 4);
    expect_level(&r, 2, (double[]){-0.5, 0, 0.5}, 3);
    expect_level(&r, 3, (double[]){-0.25, 0.25}, 2);
    expect_level(&r, 4, (double[]){0}, 1);
    rf_tm_result_free(&r);
    rf_model_free(&model);
    rf_fuzzy_tfn(&in, 0, 1, 2, NULL);
    model = test_model(1, 1, f_first);
    r = run(&in, 1, &model, RF_TM_GENERAL, 4, 0);
    expect_level(&r, 0, (double[]){-1, -0.46875, 0.1875, 1.03125, 2}, 5);
    expect_level(&r, 2, (double[]){-0.5, 0.125, 1}, 3);
    rf_tm_result_free(&r);
    rf_model_free(&model);
}

/* ---- interval arithmetic on a monotone function is exact (reduced form) */
static void f_monotone3(const double *x, double *y)
{
    y[0] = x[0] * x[0] * x[1] / x[2] + exp(x[1]); /* increasing in x0>0, x1; decreasing in x2>0 */
    y[1] = -y[0];
}

static void test_interval_arithmetic(void **state)
{
    (void)state;
    rf_fuzzy in[3];
    rf_fuzzy_tfn(&in[0], 2, 0.5, 1, NULL);
    rf_fuzzy_gaussian(&in[1], 1, 0.1, 0.2, 3, NULL);
    rf_fuzzy_points(&in[2], 4, (double[]){1, 2, 3, 5}, (double[]){0, 1, 1, 0}, NULL);
    size_t m = 6;
    rf_model model = test_model(3, 2, f_monotone3);
    rf_tm_result r = run(in, 3, &model, RF_TM_REDUCED, m, 1);
    for (size_t j = 0; j <= m; j++) {
        double mu = (double)j / (double)m, a[3], b[3];
        for (int i = 0; i < 3; i++)
            rf_fuzzy_cut(&in[i], mu, &a[i], &b[i]);
        double lo = a[0] * a[0] * a[1] / b[2] + exp(a[1]);
        double hi = b[0] * b[0] * b[1] / a[2] + exp(b[1]);
        assert_close(r.lo[j], lo, 1e-13);
        assert_close(r.hi[j], hi, 1e-13);
        assert_close(r.lo[(m + 1) + j], -hi, 1e-13);
        assert_close(r.hi[(m + 1) + j], -lo, 1e-13);
        for (int i = 0; i < 3; i++)
            assert_int_equal(r.monotonicity[i], RF_MONO_MONOTONIC);
    }
    rf_tm_result_free(&r);
    rf_model_free(&model);
    rf_fuzzy_free(&in[2]);
}

/* ---- non-monotone: never over-estimates a dense-grid optimum; converges */
static void f_wavy(const double *x, double *y) { y[0] = sin(3 * x[0]) * cos(2 * x[1]) + 0.3 * x[0] * x[1]; }

static void test_never_overestimates(void **state)
{
    (void)state;
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 0.2, 1.3, 1.1, NULL);
    rf_fuzzy_tfn(&in[1], -0.4, 0.9, 1.6, NULL);
    size_t ms[] = {4, 16};
    double gap_prev = INFINITY;
    for (size_t c = 0; c < 2; c++) {
        size_t m = ms[c];
        for (int s = 0; s < 3; s++) {
            rf_model model = test_model(2, 1, f_wavy);
            rf_tm_result r = run(in, 2, &model, (rf_tm_scheme)s, m, 0);
            double gap = 0;
            for (size_t j = 0; j <= m; j++) {
                double mu = (double)j / (double)m, a0, b0, a1, b1, lo = INFINITY, hi = -INFINITY;
                rf_fuzzy_cut(&in[0], mu, &a0, &b0);
                rf_fuzzy_cut(&in[1], mu, &a1, &b1);
                const int N = 400;
                for (int p = 0; p <= N; p++)
                    for (int q = 0; q <= N; q++) {
                        double x[2] = {a0 + (b0 - a0) * p / N, a1 + (b1 - a1) * q / N}, y;
                        f_wavy(x, &y);
                        lo = fmin(lo, y);
                        hi = fmax(hi, y);
                    }
                /* the dense grid itself under-estimates a little: allow its own resolution */
                assert_true(r.lo[j] >= lo - 1e-4);
                assert_true(r.hi[j] <= hi + 1e-4);
                if (j > 0) { /* nested */
                    assert_true(r.lo[j] >= r.lo[j - 1]);
                    assert_true(r.hi[j] <= r.hi[j - 1]);
                }
                gap = fmax(gap, fmax(r.lo[j] - lo, hi - r.hi[j]));
            }
            if (s == RF_TM_GENERAL) {
                assert_true(gap < gap_prev); /* the general form converges as m grows */
                gap_prev = gap;
            }
            rf_tm_result_free(&r);
            rf_model_free(&model);
        }
    }
    assert_true(gap_prev < 0.02);
}

/* ---- cap and failing model */
static rf_status eval_fail_high(void *ctx, const double *x, double *y, rf_error *err)
{
    (void)ctx;
    if (x[0] > 2.5)
        return rf_fail(err, RF_EMODEL, "solver diverged");
    y[0] = x[0];
    return RF_OK;
}

static void test_cap_and_failure(void **state)
{
    (void)state;
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 2, 1, 1, NULL);
    rf_fuzzy_tfn(&in[1], 3, 1, 2, NULL);
    rf_model model = test_model(2, 1, f_product);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = RF_TM_GENERAL;
    opt.left_right = 0;
    opt.max_evaluations = 10;
    rf_tm_result r;
    rf_error err = {0};
    assert_int_equal(rf_tm_run(in, 2, &model, &opt, &r, &err), RF_ECAP);
    assert_non_null(strstr(err.msg, "max_evaluations = 10"));
    assert_int_equal(test_model_calls(&model), 0); /* nothing evaluated past the cap */
    rf_model_free(&model);

    rf_model bad = test_model(2, 1, f_product);
    bad.eval = eval_fail_high;
    opt.max_evaluations = 0;
    assert_int_equal(rf_tm_run(in, 2, &bad, &opt, &r, &err), RF_EMODEL);
    assert_non_null(strstr(err.msg, "solver diverged"));
    assert_non_null(strstr(err.msg, "(3, "));
    rf_model_free(&bad);
}

/* ---- grids beyond the cap are refused before anything is built (issue 12) */
static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static long peak_rss_kib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;
}

/* rf_tm_count and rf_tm_run must both refuse, with the message naming
 * `grid` and `advice`, without evaluating anything. */
static void expect_refused_fast(rf_fuzzy *in, size_t n, const rf_tm_options *opt, const char *grid,
                                const char *advice)
{
    rf_model model = test_model(n, 1, f_first);
    rf_error err = {0};
    size_t rq = 0, ds = 0;
    double t0 = seconds();
    assert_int_equal(rf_tm_count(in, n, opt, &rq, &ds, &err), RF_ECAP);
    if (!strstr(err.msg, grid) || !strstr(err.msg, advice))
        fail_msg("rf_tm_count: '%s' should name '%s' and say '%s'", err.msg, grid, advice);
    rf_tm_result r;
    assert_int_equal(rf_tm_run(in, n, &model, opt, &r, &err), RF_ECAP);
    if (!strstr(err.msg, grid) || !strstr(err.msg, advice))
        fail_msg("rf_tm_run: '%s' should name '%s' and say '%s'", err.msg, grid, advice);
    assert_int_equal(test_model_calls(&model), 0);
    assert_true(seconds() - t0 < 1.0); /* analytic: no grid is enumerated */
    rf_model_free(&model);
}

static void test_cap_before_allocating(void **state)
{
    (void)state;
    long rss0 = peak_rss_kib();
    rf_fuzzy in[16];
    for (size_t i = 0; i < 16; i++)
        rf_fuzzy_tfn(&in[i], 1.0 + (double)i, 0.1, 0.2, NULL);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.max_evaluations = 100000;
    /* general form, 8 inputs, m = 10: 11^8 = 214 358 881 points at mu = 0
     * (this allocated 23.8 GB before the cap message) */
    opt.scheme = RF_TM_GENERAL;
    opt.levels = 10;
    opt.left_right = 0;
    expect_refused_fast(in, 8, &opt, "general-form grid at mu = 0 has 214358881 points", "scheme: reduced");
    /* reduced form, 14 inputs with left/right: 3^14 = 4 782 969 on the
     * three-point grid (2^14 corners alone would fit): it is named, and the
     * advice is to turn the left/right influence off, not the reduced form */
    opt.scheme = RF_TM_REDUCED;
    opt.left_right = 1;
    expect_refused_fast(in, 14, &opt, "three-point grid of the left/right influence at mu = 0 has 4782969 points",
                        "options.left_right: false");
    /* without a cap a grid beyond what point ids can index is still refused */
    opt.max_evaluations = 0;
    opt.left_right = 0;
    opt.scheme = RF_TM_GENERAL;
    expect_refused_fast(in, 12, &opt, "general-form grid at mu = 0 has", "this build can index");
    /* memory bounded by the cap, not by the grid: a few MiB at most */
    long grown = peak_rss_kib() - rss0;
    if (grown > 64 * 1024)
        fail_msg("peak RSS grew by %ld KiB while refusing", grown);

    /* no single grid exceeds the cap, their distinct union does: counted
     * exactly without storing points, refused with the sizes */
    opt.scheme = RF_TM_REDUCED;
    opt.left_right = 1;
    opt.levels = 10;
    opt.max_evaluations = 2000; /* 3^6 = 729 per level, 11 levels, 2^6 corners */
    rf_error err = {0};
    size_t rq, ds;
    assert_int_equal(rf_tm_count(in, 6, &opt, &rq, &ds, &err), RF_ECAP);
    assert_non_null(strstr(err.msg, "distinct model evaluations"));
    assert_non_null(strstr(err.msg, "options.left_right: false"));
    opt.max_evaluations = 0;
    assert_int_equal(rf_tm_count(in, 6, &opt, &rq, &ds, &err), RF_OK);
    assert_true(ds > 2000 && rq >= ds);
    opt.max_evaluations = ds; /* exactly at the cap: runs */
    rf_model model = test_model(6, 1, f_first);
    rf_tm_result r;
    assert_int_equal(rf_tm_run(in, 6, &model, &opt, &r, &err), RF_OK);
    assert_int_equal(r.distinct, ds);
    assert_int_equal(test_model_calls(&model), ds);
    rf_tm_result_free(&r);
    rf_model_free(&model);
}

/* ---- inputs of every shape give nested outputs; crisp inputs are n/a */
static void f_sum(const double *x, double *y)
{
    y[0] = 0;
    for (int i = 0; i < 6; i++)
        y[0] += (i + 1) * x[i];
}

static void test_shapes_and_crisp(void **state)
{
    (void)state;
    rf_fuzzy in[6];
    rf_fuzzy_tfn(&in[0], 2, 1, 1, NULL);
    rf_fuzzy_trapezoid(&in[1], 0.05, 0.45, 0.55, 0.95, NULL);
    rf_fuzzy_interval(&in[2], 1, 2, NULL);
    rf_fuzzy_gaussian(&in[3], 10, 1, 2, 3, NULL);
    rf_fuzzy_crisp(&in[4], 1.5, NULL);
    rf_fuzzy_points(&in[5], 3, (double[]){0, 1, 3}, (double[]){0, 1, 0}, NULL);
    size_t m = 4;
    rf_model model = test_model(6, 1, f_sum);
    rf_tm_result r = run(in, 6, &model, RF_TM_REDUCED, m, 1);
    /* linear: exact cuts are the weighted sums of the input cuts */
    for (size_t j = 0; j <= m; j++) {
        double lo = 0, hi = 0;
        for (int i = 0; i < 6; i++) {
            double a, b;
            rf_fuzzy_cut(&in[i], (double)j / (double)m, &a, &b);
            lo += (i + 1) * a;
            hi += (i + 1) * b;
        }
        assert_close(r.lo[j], lo, 1e-12);
        assert_close(r.hi[j], hi, 1e-12);
    }
    rf_analysis an;
    rf_analysis_compute(&r, &an, NULL);
    assert_true(isnan(an.rho[4]));
    assert_int_equal(an.reason_hanss[4], RF_NA_CRISP);
    assert_int_equal(an.reason_lr[4], RF_NA_CRISP);
    double sum = 0, sumlr = 0;
    for (int i = 0; i < 6; i++) {
        if (i == 4)
            continue;
        sum += an.rho[i];
        sumlr += an.rho_left[i] + an.rho_right[i];
    }
    assert_close(sum, 1, 1e-12);
    assert_close(sumlr, 1, 1e-12);
    /* linear model, triangular-like: rho_i = |c_i| W_i-weighted: interval has
     * constant width 1, so it is compared by kappa = |c| * w-average: */
    assert_close(an.kappa[2], 3 * 1.0, 1e-12);
    assert_true(fabs(an.interaction[0]) < 1e-12);
    rf_analysis_free(&an);
    rf_tm_result_free(&r);
    rf_model_free(&model);
    rf_fuzzy_free(&in[5]);
}

/* ---- NaN outputs: undefined everywhere is reported, partly NaN is an error */
static void f_nan(const double *x, double *y)
{
    y[0] = x[0];
    y[1] = NAN;                      /* e.g. R_t of a normal impact */
    y[2] = x[0] > 2.9 ? NAN : x[0];  /* breaks down at one corner */
}

static void f_nan_first_two(const double *x, double *y)
{
    double z[3];
    f_nan(x, z);
    y[0] = z[0];
    y[1] = z[1];
}

static void test_nan_outputs(void **state)
{
    (void)state;
    rf_fuzzy in;
    rf_fuzzy_tfn(&in, 2, 1, 1, NULL);
    rf_model model = test_model(1, 3, f_nan);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    rf_tm_result r;
    rf_error err;
    assert_int_equal(rf_tm_run(&in, 1, &model, &opt, &r, &err), RF_EMODEL);
    assert_non_null(strstr(err.msg, "output 'y2' is NaN at parameters (3)"));
    rf_model_free(&model);
    model = test_model(1, 2, f_nan_first_two);
    assert_int_equal(rf_tm_run(&in, 1, &model, &opt, &r, &err), RF_OK);
    assert_int_equal(r.output_undefined[0], 0);
    assert_int_equal(r.output_undefined[1], 1);
    assert_true(isnan(r.lo[5]) && isnan(r.hi[9]));
    assert_close(r.lo[0], 1, 0);
    rf_analysis an;
    assert_int_equal(rf_analysis_compute(&r, &an, NULL), RF_OK);
    assert_int_equal(an.reason_hanss[1], RF_NA_UNDEFINED);
    assert_true(isnan(an.rho[1]));
    assert_close(an.rho[0], 1, 1e-15);
    rf_analysis_free(&an);
    rf_tm_result_free(&r);
    rf_model_free(&model);
}

/* ---- rounding noise is not influence: an output constant on every level
 * box but level 0 (rolling R_t = 5/7 unless friction is 0) */
static void f_rolling(const double *x, double *y)
{
    y[0] = (x[0] < 0.05 ? 1.0 : 5.0 / 7.0) * (1 + 1e-15 * x[1]);
}

static void test_noise_is_not_influence(void **state)
{
    (void)state;
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 0.6, 0.6, 0.4, NULL); /* friction, support [0, 1] */
    rf_fuzzy_tfn(&in[1], 1, 0.05, 0.05, NULL);  /* radius: no physical effect */
    rf_model model = test_model(2, 1, f_rolling);
    rf_tm_result r = run(in, 2, &model, RF_TM_REDUCED, 4, 1);
    rf_analysis an;
    assert_int_equal(rf_analysis_compute(&r, &an, NULL), RF_OK);
    /* Hanss's measures weight levels 1..m-1 only, where the output is constant */
    assert_true(isnan(an.rho[0]) && isnan(an.rho[1]));
    assert_int_equal(an.reason_hanss[1], RF_NA_ALL_ZERO);
    /* the left/right measures include level 0: friction takes it all */
    assert_close(an.rho_right[0], 1, 1e-12);
    assert_true(an.rho_left[1] == 0 && an.rho_right[1] == 0);
    rf_analysis_free(&an);
    rf_tm_result_free(&r);
    rf_model_free(&model);
}

/* ---- bounds and gains bit for bit against plain sequential scans (the
 * retransformation and the analysis run several running extrema and line
 * sums side by side; their results must not depend on it).  The model has
 * ties, -0 and +0, and NaN points (tolerated) among values that differ. */
static void f_ties(const double *x, double *y)
{
    y[0] = floor(2 * x[1]) + (x[0] > 1.5 ? -0.0 : 0.0); /* plateaus, both zeros */
    y[1] = x[0] * x[1] - sin(3 * x[2]);
    y[2] = x[0] > 2.2 && x[2] < 3 ? NAN : x[1] - x[2];   /* fails at some points */
    y[3] = x[2] > 2.9 ? 0.0 : -0.0;
}

static int same_bits(double a, double b) { return (isnan(a) && isnan(b)) || !memcmp(&a, &b, sizeof a); }

static double *scratch_for(const struct rf_tm_data *d)
{
    size_t maxc = 1;
    for (size_t j = 0; j <= d->m; j++)
        maxc = d->main[j].count > maxc ? d->main[j].count : maxc;
    return malloc(maxc * sizeof(double));
}

/* Retransformation as one strict scan per level grid, level m down to 0. */
static void check_bounds_sequential(const rf_tm_result *r)
{
    const struct rf_tm_data *d = r->data;
    size_t m = r->levels, n = r->n_inputs;
    double *z = scratch_for(d);
    for (size_t k = 0; k < r->n_outputs; k++) {
        double zmin = INFINITY, zmax = -INFINITY;
        size_t amin = 0, amax = 0;
        for (size_t jj = m + 1; jj-- > 0;) {
            const rf_grid *g = &d->main[jj];
            const double *zk = rf_tm_outputs(d, g, k, z);
            for (size_t p = 0; p < g->count; p++) {
                if (zk[p] < zmin)
                    zmin = zk[p], amin = g->ids[p];
                if (zk[p] > zmax)
                    zmax = zk[p], amax = g->ids[p];
            }
            size_t at = k * (m + 1) + jj;
            assert_true(same_bits(r->lo[at], zmin > zmax ? NAN : zmin));
            assert_true(same_bits(r->hi[at], zmin > zmax ? NAN : zmax));
            for (size_t i = 0; zmin <= zmax && i < n; i++) {
                assert_true(same_bits(r->x_lo[at * n + i], d->values[i][rf_tm_tuple(d, amin, i)]));
                assert_true(same_bits(r->x_hi[at * n + i], d->values[i][rf_tm_tuple(d, amax, i)]));
            }
        }
    }
    free(z);
}

/* Gain factors from one sequential sum per line family (s.5.1). */
static void check_gains_sequential(const rf_tm_result *r, const rf_analysis *an)
{
    const struct rf_tm_data *d = r->data;
    size_t m = r->levels, n = r->n_inputs;
    double *z = scratch_for(d);
    for (size_t k = 0; k < r->n_outputs; k++) {
        double zbar = r->nominal[k], lo0 = r->lo[k * (m + 1)], hi0 = r->hi[k * (m + 1)];
        double noise = 1e-12 * fmax(fabs(zbar), fmax(fabs(lo0), fabs(hi0)));
        for (size_t j = 0; j < m; j++) {
            const rf_grid *g = &d->main[j];
            const double *zk = rf_tm_outputs(d, g, k, z);
            for (size_t i = 0; i < n; i++) {
                size_t rdx = g->radix[i], s = g->stride[i], last = rdx - 1;
                double sum = 0, w = r->in_hi[i * (m + 1) + j] - r->in_lo[i * (m + 1) + j], eta = NAN;
                for (size_t outer = 0; outer < g->count; outer += rdx * s)
                    for (size_t inner = 0; inner < s; inner++)
                        sum += zk[outer + last * s + inner] - zk[outer + inner];
                double dz = last >= 1 ? sum / (double)(g->count / rdx) : NAN;
                if (!isnan(dz) && w > 0 && !r->output_undefined[k])
                    eta = (fabs(dz) <= noise ? 0.0 : dz) / w;
                assert_true(same_bits(an->gain[(k * n + i) * m + j], eta));
            }
        }
    }
    free(z);
}

static void test_lanes_match_sequential(void **state)
{
    (void)state;
    rf_fuzzy in[3];
    rf_fuzzy_tfn(&in[0], 2, 1, 0.5, NULL);
    rf_fuzzy_tfn(&in[1], 1, 0.6, 0.9, NULL);
    rf_fuzzy_trapezoid(&in[2], 2, 2.4, 2.7, 3.2, NULL); /* a flat core */
    const rf_tm_scheme schemes[] = {RF_TM_REDUCED, RF_TM_GENERAL, RF_TM_EXTENDED};
    for (size_t c = 0; c < 3; c++) {
        rf_model model = test_model(3, 4, f_ties);
        rf_tm_options opt;
        rf_tm_options_default(&opt);
        opt.scheme = schemes[c];
        opt.levels = 5 + c;
        opt.tolerate_failures = 1;
        rf_tm_result r;
        rf_error err;
        assert_int_equal(rf_tm_run(in, 3, &model, &opt, &r, &err), RF_OK);
        assert_true(r.nan_points[2] > 0);
        check_bounds_sequential(&r);
        rf_analysis an;
        assert_int_equal(rf_analysis_compute(&r, &an, NULL), RF_OK);
        check_gains_sequential(&r, &an);
        rf_analysis_free(&an);
        rf_tm_result_free(&r);
        rf_model_free(&model);
    }
}

/* ---- every evaluated point is the point its tuple names: outputs echo the
 * inputs, so output i of point id must be the value its tuple indexes (rows
 * written at once, rows with repeated points, buffer flushes in between) */
static size_t echo_n; /* inputs = outputs of f_echo (serial test only) */
static void f_echo(const double *x, double *y) { memcpy(y, x, echo_n * sizeof(double)); }

static void test_points_match_tuples(void **state)
{
    (void)state;
    rf_fuzzy in[8];
    for (size_t i = 0; i < 8; i++)
        rf_fuzzy_tfn(&in[i], 1 + (double)i, 0.3, 0.2 + 0.1 * (double)i, NULL);
    const struct {
        rf_tm_scheme scheme;
        size_t n, m;
        int lr;
    } cases[] = {{RF_TM_REDUCED, 8, 7, 0}, {RF_TM_REDUCED, 8, 5, 1}, {RF_TM_GENERAL, 3, 6, 1}, {RF_TM_EXTENDED, 4, 4, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        size_t n = echo_n = cases[c].n;
        rf_model model = test_model(n, n, f_echo);
        rf_tm_result r = run(in, n, &model, cases[c].scheme, cases[c].m, cases[c].lr);
        const struct rf_tm_data *d = r.data;
        assert_int_equal(d->npoints, r.distinct);
        assert_int_equal(test_model_calls(&model), r.distinct);
        for (size_t id = 0; id < d->npoints; id++)
            for (size_t i = 0; i < n; i++)
                assert_true(rf_tm_y(d, id, i) == d->values[i][rf_tm_tuple(d, id, i)]);
        rf_tm_result_free(&r);
        rf_model_free(&model);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vector_A),        cmocka_unit_test(test_vector_B),
        cmocka_unit_test(test_vector_C),        cmocka_unit_test(test_vector_L),
        cmocka_unit_test(test_sgpp_trapezoids), cmocka_unit_test(test_dependency),
        cmocka_unit_test(test_counts),          cmocka_unit_test(test_general_points),
        cmocka_unit_test(test_interval_arithmetic), cmocka_unit_test(test_never_overestimates),
        cmocka_unit_test(test_cap_and_failure), cmocka_unit_test(test_cap_before_allocating),
        cmocka_unit_test(test_shapes_and_crisp),
        cmocka_unit_test(test_nan_outputs),      cmocka_unit_test(test_noise_is_not_influence),
        cmocka_unit_test(test_lanes_match_sequential), cmocka_unit_test(test_points_match_tuples),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
