/* test_fuzzy.c - fuzzy numbers: cuts of every shape against hand-computed
 * values (tm_spec.md s.1), membership consistency, and rejection of invalid
 * shapes with messages that name the value. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "rockfuzz/fuzzy.h"
#include "test_util.h"

static void test_triangular(void **state)
{
    (void)state;
    rf_fuzzy f;
    assert_int_equal(rf_fuzzy_tfn(&f, 2, 1, 3, NULL), RF_OK);
    double lo, hi;
    rf_fuzzy_cut(&f, 0.25, &lo, &hi);
    assert_close(lo, 1.25, 1e-15);
    assert_close(hi, 4.25, 1e-15);
    rf_fuzzy_cut(&f, 1, &lo, &hi);
    assert_true(lo == 2 && hi == 2);
    assert_close(rf_fuzzy_membership(&f, 3.5), 0.5, 1e-15);
    assert_close(rf_fuzzy_nominal(&f), 2, 0);
}

static void test_gaussian_spec_example(void **state)
{
    (void)state; /* tm_spec s.1.4: gfn(10, 1, 2), c = 3, m = 4 */
    rf_fuzzy f;
    rf_fuzzy_gaussian(&f, 10, 1, 2, 3, NULL);
    double lo[5], hi[5];
    assert_int_equal(rf_fuzzy_decompose(&f, 4, lo, hi, NULL), RF_OK);
    const double elo[] = {7, 8.334891, 8.822590, 9.241472, 10};
    const double ehi[] = {16, 13.330218, 12.354820, 11.517055, 10};
    for (int j = 0; j < 5; j++) {
        assert_close(lo[j], elo[j], 1e-6);
        assert_close(hi[j], ehi[j], 1e-6);
    }
}

static void test_trapezoid_interval_crisp(void **state)
{
    (void)state;
    rf_fuzzy f;
    double lo, hi;
    rf_fuzzy_trapezoid(&f, 0.05, 0.45, 0.55, 0.95, NULL);
    rf_fuzzy_cut(&f, 0.5, &lo, &hi);
    assert_close(lo, 0.25, 1e-15);
    assert_close(hi, 0.75, 1e-15);
    assert_close(rf_fuzzy_nominal(&f), 0.5, 1e-15);
    assert_close(rf_fuzzy_membership(&f, 0.85), 0.25, 1e-12);
    rf_fuzzy_interval(&f, 1, 2, NULL);
    rf_fuzzy_cut(&f, 0.3, &lo, &hi);
    assert_true(lo == 1 && hi == 2);
    rf_fuzzy_crisp(&f, 1.5, NULL);
    rf_fuzzy_cut(&f, 0, &lo, &hi);
    assert_true(lo == 1.5 && hi == 1.5);
}

static void test_points(void **state)
{
    (void)state; /* s.1.5: the same cuts as the equivalent trapezoid */
    rf_fuzzy p, t;
    assert_int_equal(rf_fuzzy_points(&p, 5, (double[]){0, 1, 2, 3, 5}, (double[]){0, 0.5, 1, 1, 0}, NULL), RF_OK);
    rf_fuzzy_trapezoid(&t, 0, 2, 3, 5, NULL);
    for (int j = 0; j <= 8; j++) {
        double mu = j / 8.0, a, b, c, d;
        rf_fuzzy_cut(&p, mu, &a, &b);
        rf_fuzzy_cut(&t, mu, &c, &d);
        assert_close(a, c, 1e-14);
        assert_close(b, d, 1e-14);
        assert_close(rf_fuzzy_membership(&p, c), mu, 1e-12);
    }
    rf_fuzzy_free(&p);
    /* a flat piece on the rising branch: smallest x with membership >= mu */
    rf_fuzzy_points(&p, 5, (double[]){0, 1, 2, 3, 4}, (double[]){0, 0.5, 0.5, 1, 0}, NULL);
    double a, b;
    rf_fuzzy_cut(&p, 0.5, &a, &b);
    assert_close(a, 1, 1e-15);
    assert_close(b, 3.5, 1e-15);
    rf_fuzzy_free(&p);
}

static void test_cuts_form(void **state)
{
    (void)state;
    rf_fuzzy f;
    assert_int_equal(rf_fuzzy_cuts(&f, 3, (double[]){0, 0.5, 1}, (double[]){1, 1.5, 2}, (double[]){3, 2.5, 2}, NULL),
                     RF_OK);
    double lo, hi;
    rf_fuzzy_cut(&f, 0.25, &lo, &hi);
    assert_close(lo, 1.25, 1e-15);
    assert_close(hi, 2.75, 1e-15);
    assert_close(rf_fuzzy_membership(&f, 1.25), 0.25, 1e-12);
    rf_fuzzy g;
    rf_fuzzy_copy(&g, &f, NULL);
    rf_fuzzy_free(&f);
    rf_fuzzy_cut(&g, 1, &lo, &hi);
    assert_true(lo == 2 && hi == 2);
    rf_fuzzy_free(&g);
}

static void expect_error(rf_status st, const rf_error *err, const char *needle)
{
    assert_int_equal(st, RF_EINVAL);
    if (!strstr(err->msg, needle))
        fail_msg("message '%s' lacks '%s'", err->msg, needle);
}

static void test_invalid(void **state)
{
    (void)state;
    rf_fuzzy f;
    rf_error err;
    expect_error(rf_fuzzy_tfn(&f, 1, -0.5, 1, &err), &err, "-0.5");
    expect_error(rf_fuzzy_tfn(&f, NAN, 1, 1, &err), &err, "finite");
    expect_error(rf_fuzzy_trapezoid(&f, 1, 3, 2, 4, &err), &err, "x1 <= x2 <= x3 <= x4");
    expect_error(rf_fuzzy_interval(&f, 2, 1, &err), &err, "[2, 1]");
    expect_error(rf_fuzzy_gaussian(&f, 0, 1, 1, 0, &err), &err, "cutoff = 0");
    expect_error(rf_fuzzy_points(&f, 3, (double[]){0, 1, 2}, (double[]){0, 0.5, 0}, &err), &err, "membership 1");
    expect_error(rf_fuzzy_points(&f, 4, (double[]){0, 1, 2, 3}, (double[]){0.5, 0.2, 1, 0}, &err), &err,
                 "would not nest");
    expect_error(rf_fuzzy_points(&f, 3, (double[]){0, 2, 1}, (double[]){0, 1, 0}, &err), &err, "decrease");
    /* cuts that do not nest */
    expect_error(rf_fuzzy_cuts(&f, 3, (double[]){0, 0.5, 1}, (double[]){1, 0.5, 2}, (double[]){3, 2.5, 2}, &err), &err,
                 "must nest");
    expect_error(rf_fuzzy_cuts(&f, 2, (double[]){0.1, 1}, (double[]){1, 2}, (double[]){3, 2}, &err), &err,
                 "start at 0");
    double lo[3] = {0, 1, 0.5}, hi[3] = {3, 2, 2.5};
    expect_error(rf_cuts_check_nested(2, lo, hi, &err), &err, "not inside");
    expect_error(rf_fuzzy_decompose(&f, 0, lo, hi, &err), &err, "levels = 0");
}

/* Supports whose ends, widths or midpoints overflow, and spreads too small
 * for doubles to resolve, are refused with the field named (issue 12). */
static void expect_refused(rf_status st, const rf_error *err, const char *field)
{
    assert_int_equal(st, RF_EINVAL);
    if (!strstr(err->msg, field))
        fail_msg("message '%s' does not name '%s'", err->msg, field);
}

static void test_overflowing_supports(void **state)
{
    (void)state;
    rf_fuzzy f;
    rf_error err = {0};
    expect_refused(rf_fuzzy_tfn(&f, 1e308, 1e307, 1e308, &err), &err, "peak");
    expect_refused(rf_fuzzy_tfn(&f, 1e307, 1e307, 1.79e308, &err), &err, "peak + right deviation = inf");
    expect_refused(rf_fuzzy_tfn(&f, -1e307, 1.7e308, 1, &err), &err, "peak - left deviation");
    expect_refused(rf_fuzzy_interval(&f, -1e308, 1e308, &err), &err, "lower bound = -1e+308");
    expect_refused(rf_fuzzy_trapezoid(&f, 0, 1, 2, 1e308, &err), &err, "x4 = 1e+308");
    expect_refused(rf_fuzzy_gaussian(&f, 1e307, 1e306, 2e307, 3, &err), &err, "peak + cutoff * right sigma");
    expect_refused(rf_fuzzy_crisp(&f, -1.5e308, &err), &err, "value");
    /* the largest accepted magnitude still gives finite widths and midpoints */
    assert_int_equal(rf_fuzzy_interval(&f, -4e307, 4e307, &err), RF_OK);
    double lo[11], hi[11];
    assert_int_equal(rf_fuzzy_decompose(&f, 10, lo, hi, &err), RF_OK);
    assert_true(isfinite(hi[0] - lo[0]) && isfinite(0.5 * (lo[0] + hi[0])));
    /* a spread that vanishes next to the peak would make the input silently crisp */
    expect_refused(rf_fuzzy_tfn(&f, 1e16, 1e-5, 1e-5, &err), &err, "left deviation = 1e-05 vanishes");
    expect_refused(rf_fuzzy_gaussian(&f, 1e20, 1, 1e-3, 3, &err), &err, "left sigma");
    /* representable but too narrow for 10 levels: 8 wide where doubles are 2 apart */
    assert_int_equal(rf_fuzzy_trapezoid(&f, 1e16, 1e16 + 2, 1e16 + 4, 1e16 + 8, &err), RF_OK);
    expect_refused(rf_fuzzy_decompose(&f, 10, lo, hi, &err), &err, "too narrow for doubles");
    /* a narrow support at a small magnitude is fine */
    assert_int_equal(rf_fuzzy_tfn(&f, 1e-300, 1e-310, 1e-310, &err), RF_OK);
    assert_int_equal(rf_fuzzy_decompose(&f, 10, lo, hi, &err), RF_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_triangular), cmocka_unit_test(test_gaussian_spec_example),
        cmocka_unit_test(test_trapezoid_interval_crisp), cmocka_unit_test(test_points),
        cmocka_unit_test(test_cuts_form), cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_overflowing_supports),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
