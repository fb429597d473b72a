/* test_duration.c - the one duration formatter (core/util.h,
 * rf_format_duration) that the progress line of `rockfuzz impact`, `rockfuzz
 * status` and the runner's progress line print: the texts at the boundaries of
 * seconds, minutes and hours in each style, truncation (not rounding) of the
 * larger units, the unknown cases and a short buffer. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "core/util.h"

static void expect(double s, int style, const char *want, int known)
{
    char buf[64];
    memset(buf, 'x', sizeof buf);
    const int got = rf_format_duration(s, style, buf, sizeof buf);
    if (strcmp(buf, want) != 0 || got != known)
        fail_msg("%.17g s, style %d: '%s' (%d), want '%s' (%d)", s, style, buf, got, want, known);
}

/* The words style with one decimal (`rockfuzz status`). */
static void test_words(void **state)
{
    (void)state;
    expect(0.0, 0, "0.0 s", 1);
    expect(12.34, 0, "12.3 s", 1);
    expect(59.9, 0, "59.9 s", 1);
    expect(60.0, 0, "1 min 00 s", 1);
    expect(61.9, 0, "1 min 01 s", 1);      /* seconds truncated */
    expect(3599.9, 0, "59 min 59 s", 1);
    expect(3600.0, 0, "1 h 00 min", 1);
    expect(3600.0 + 59 * 60 + 59, 0, "1 h 59 min", 1); /* minutes truncated */
    expect(25 * 3600.0 + 61, 0, "25 h 01 min", 1);
    expect(1e8, 0, "27777 h 46 min", 1);   /* the largest known duration */
}

/* Whole seconds (the FE progress line) and the compact style (the runner's line). */
static void test_whole_and_compact(void **state)
{
    (void)state;
    expect(12.4, RF_DURATION_WHOLE, "12 s", 1);
    expect(0.4, RF_DURATION_WHOLE, "0 s", 1);
    expect(75.0, RF_DURATION_WHOLE, "1 min 15 s", 1);
    expect(12.34, RF_DURATION_COMPACT, "12.3s", 1);
    expect(60.0, RF_DURATION_COMPACT, "1m00s", 1);
    expect(3599.0, RF_DURATION_COMPACT, "59m59s", 1);
    expect(7322.0, RF_DURATION_COMPACT, "2h02m", 1);
    expect(7.6, RF_DURATION_COMPACT | RF_DURATION_WHOLE, "8s", 1);
}

/* Not known: negative, NaN, beyond 1e8 s; and a buffer too short is cut, not overrun. */
static void test_unknown_and_short_buffer(void **state)
{
    (void)state;
    expect(-1.0, 0, "?", 0);
    expect(NAN, RF_DURATION_COMPACT, "?", 0);
    expect(nextafter(1e8, 2e8), 0, "?", 0);
    expect(INFINITY, RF_DURATION_WHOLE, "?", 0);
    char buf[8] = "zzzzzzz";
    assert_int_equal(rf_format_duration(3661.0, 0, buf, 5), 1);
    assert_string_equal(buf, "1 h ");
    assert_int_equal(buf[6], 'z');
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_words),
        cmocka_unit_test(test_whole_and_compact),
        cmocka_unit_test(test_unknown_and_short_buffer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
