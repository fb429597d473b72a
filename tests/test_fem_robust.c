/* test_fem_robust.c - the solver robustness for soils
 * (docs/validation-plastic.md section 9): the automatic end of a run against
 * closed-form boulder motions (a contact longer than the old 3 Hertz
 * durations runs to its end; a stalled one fails at the bound, with no
 * rebound velocity reported). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem/fem_core.h"
#include "rockfuzz/fem.h"

/* A boulder of speed V (v = -V at t = 0) decelerated by a constant force
 * of a (per unit mass) up to t_slow, then by a_late; once at rest an elastic
 * unloading pushes it to +v_out over t_un, then the contact opens.  The run
 * account is fed with this motion until fem_run_stop or a failure; returns
 * the status, *t_end the time after the last step. */
typedef struct {
    double V, a, t_slow, a_late, v_out, t_un;
} motion;

static rf_status feed(const motion *m, const rf_fem_options *o, double t_h, double dt, double *t_end, rf_error *err)
{
    fem_run R;
    rf_status st = fem_run_begin(&R, "fem", o, dt, t_h, 0, 12, err);
    assert_int_equal(st, RF_OK);
    double v = -m->V, t_rest = -1;
    for (long n = 0;; n++) {
        const double t = (double)n * dt;
        double a = t < m->t_slow ? m->a : m->a_late, Fc = a;
        if (v >= 0 && t_rest < 0)
            t_rest = t;
        if (t_rest >= 0) { /* unloading, then free flight */
            a = t < t_rest + m->t_un ? m->v_out / m->t_un : 0;
            Fc = a;
        }
        v += a * dt;
        double row[12] = {0};
        row[11] = v;
        *t_end = (double)(n + 1) * dt;
        if ((st = fem_run_account(&R, n, Fc, 0, 0, 0, 1, row, err)) != RF_OK || fem_run_stop(&R, n))
            break;
    }
    fem_run_free(&R);
    return st;
}

/* A rigid-plastic approach of 5 Hertz durations (constant force: the
 * boulder stops at V / a = 5 t_h), an elastic unloading of 0.3 t_h: the run
 * must end 0.1 t_h after the contact opens, at 5.4 t_h, not at the old fixed
 * 3 t_h with the boulder still moving in.  An elastic-like contact of 1 t_h
 * keeps the old end (1.3 t_h); a given end_time is kept. */
static void test_stop_after_long_contact(void **state)
{
    (void)state;
    const double t_h = 1e-3, dt = 1e-6;
    rf_fem_options o;
    rf_fem_options_default(&o);
    rf_error err = {0};
    double t_end;
    const motion plastic = {10, 10 / (5 * t_h), 1, 0, 1, 0.3 * t_h};
    assert_int_equal(feed(&plastic, &o, t_h, dt, &t_end, &err), RF_OK);
    printf("long contact: the run ends at %.4f t_h (contact open at 5.3 t_h)\n", t_end / t_h);
    assert_true(fabs(t_end - 5.4 * t_h) < 3 * dt);
    const motion elastic = {10, 10 / (0.5 * t_h), 1, 0, 10, 0.5 * t_h};
    assert_int_equal(feed(&elastic, &o, t_h, dt, &t_end, &err), RF_OK);
    assert_true(fabs(t_end - 1.3 * t_h) < 3 * dt);
    o.end_time = 2 * t_h;
    assert_int_equal(feed(&plastic, &o, t_h, dt, &t_end, &err), RF_OK);
    assert_true(fabs(t_end - 2 * t_h) < 3 * dt);
}

/* The contact stalls after 3 t_h with 60 % of the momentum reversed (the
 * force drops to a trickle): the bound is 4 x 3 t_h / 0.6 = 20 t_h, where
 * the run fails with a message instead of a rebound velocity. */
static void test_stalled_contact_fails(void **state)
{
    (void)state;
    const double t_h = 1e-3, dt = 1e-6;
    rf_fem_options o;
    rf_fem_options_default(&o);
    rf_error err = {0};
    double t_end;
    const motion stalled = {10, 10 / (5 * t_h), 3 * t_h, 1e-9, 1, 0.3 * t_h};
    assert_int_equal(feed(&stalled, &o, t_h, dt, &t_end, &err), RF_EMODEL);
    printf("stalled contact: %s\n", err.msg);
    assert_true(fabs(t_end - 20 * t_h) < 3 * dt);
    assert_non_null(strstr(err.msg, "has not ended"));
    assert_non_null(strstr(err.msg, "end_time"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stop_after_long_contact),
        cmocka_unit_test(test_stalled_contact_fails),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
