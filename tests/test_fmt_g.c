/* test_fmt_g.c - rf_fmt_g (core/fmt.h) writes what printf's "%.*g" writes,
 * byte for byte, for every precision 1..17: random bit patterns (every
 * exponent, subnormals), random mantissas over 10^-20..10^20, decimal
 * fractions (where rounding ties and near-ties live), the values of a
 * trajectory file's rows, and the edge cases (zeros, the extremes, exact
 * halves, 10^P - 1/2 carries, the switch between styles f and e).  The
 * reference is glibc's snprintf, an independent correctly rounded method. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/fmt.h"

static uint64_t rng = 88172645463325252ull;
static uint64_t next(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return rng;
}

static size_t mismatches;

static void check(double v)
{
    char mine[RF_FMT_G_MAX], ref[64];
    for (int p = 1; p <= 17; p++) {
        size_t n = rf_fmt_g(mine, v, p);
        snprintf(ref, sizeof ref, "%.*g", p, v);
        if (strcmp(mine, ref) || n != strlen(ref)) {
            if (mismatches++ < 10)
                print_message("precision %d, %.17g: rf_fmt_g '%s', printf '%s'\n", p, v, mine, ref);
        }
    }
}

static void test_random(void **state)
{
    (void)state;
    mismatches = 0;
    for (long i = 0; i < 200000; i++) {
        uint64_t r = next();
        double v;
        memcpy(&v, &r, sizeof v);
        if (isfinite(v))
            check(v);
        check(ldexp((double)(next() >> 11), -53) * pow(10, (int)(next() % 41) - 20) * (r & 1 ? -1 : 1));
        check((double)((int64_t)(next() % 2000001) - 1000000) / pow(10, (int)(next() % 12)));
        check(600.0 - (double)i * 1.2345e-4); /* trajectory rows */
    }
    assert_int_equal(mismatches, 0);
}

static void test_edges(void **state)
{
    (void)state;
    mismatches = 0;
    const double v[] = {0.0, -0.0, 5e-324, 1e-320, 2.2250738585072014e-308, 1.7976931348623157e308, 0.5, 1.5, 2.5,
                        0.125, 1e21, 1e22, 1e23, 123456789, 999999999.5, 9.9999999995, 0.0001, 0.00001, 0.000099999,
                        99999.95, 1e16, 9007199254740993.0, 0.1, 0.2, 0.3, 1.0 / 3, 2.0 / 3, 1e-5, 1e-4, 1e9,
                        -1e-300, 6.02214076e23, 1.602176634e-19};
    for (size_t k = 0; k < sizeof v / sizeof *v; k++)
        check(v[k]);
    for (int e = -30; e <= 30; e++)
        for (int p = 1; p <= 17; p++) { /* 10^e - half a unit of the last digit: the carry to 10^(e+1) */
            double t = pow(10, e);
            check(t), check(t - 0.5 * pow(10, e - p)), check(t * (1 - 1e-17));
        }
    char buf[RF_FMT_G_MAX];
    rf_fmt_g(buf, INFINITY, 9);
    assert_string_equal(buf, "inf");
    rf_fmt_g(buf, -NAN, 9);
    assert_string_equal(buf, "-nan");
    assert_int_equal(mismatches, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random),
        cmocka_unit_test(test_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
