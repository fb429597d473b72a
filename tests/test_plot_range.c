/* test_plot_range.c - axes PLplot can draw (plot/figure.h,
 * rf_plot_axis_range): a fuzzy output whose alpha-0 cut is [40, 40 + 7e-15]
 * (runout at the profile's end, differing in the last bits) made PLplot's
 * tick search loop for ever and a study never ended (SIGTERM unanswered).
 * The widened range holds the data and is at least 1e-3 of its magnitude
 * wide; tests/cli_plot_crisp.sh runs the study that hung. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "plot/figure.h"

static void check(double lo, double hi)
{
    double a = lo, b = hi;
    rf_plot_axis_range(&a, &b);
    assert_true(isfinite(a) && isfinite(b));
    if (isfinite(lo) && isfinite(hi) && hi >= lo)
        assert_true(a <= lo && b >= hi); /* the data stay inside */
    const double mag = fmax(fabs(a), fabs(b));
    assert_true(b - a >= (mag > 0 ? 0.999e-3 * mag : 1));
}

static void test_ranges(void **state)
{
    (void)state;
    check(40, 40 + 7e-15);
    check(40, 40);
    check(0, 0);
    check(-1e300, -1e300);
    check(1e-300, 2e-300);
    check(0, 1);
    check(NAN, 1);
    check(0, INFINITY);
    check(3, 2);
    double a = 10, b = 20; /* a wide range is left alone */
    rf_plot_axis_range(&a, &b);
    assert_true(a == 10 && b == 20);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ranges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
