/* test_block_flight.c - free flight of a rigid block (block_body.c): the
 * space angular momentum kept to round-off over 1e5 steps, the centre on
 * the closed-form parabola, the energy of an asymmetric top kept to second
 * order (the error falls 4x when dt halves, without drift), the
 * intermediate-axis instability (a spin near the middle axis flips, near
 * the others it does not), and a symmetric top against its closed-form
 * precession (second-order convergence of the orientation). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rockfuzz/block.h"

#define G 9.81

static rf_block_shape box123(void)
{
    rf_block_shape s;
    rf_error err;
    if (rf_block_box(1, 2, 3, 2650, &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    return s; /* I = m (5, 10, 13) / 12 */
}

static void test_momentum_and_parabola(void **state)
{
    (void)state;
    rf_block_shape s = box123();
    rf_block_state st = {{0, 0, 100}, {1, 0, 0, 0}, {3, -1, 12}, {1.3, 0.4, -2.1}};
    double L0[3], L[3], h = 1e-3, worst = 0;
    rf_block_angular_momentum(&s, &st, L0);
    double l0 = sqrt(L0[0] * L0[0] + L0[1] * L0[1] + L0[2] * L0[2]);
    for (int k = 1; k <= 100000; k++) {
        rf_block_flight_step(&s, &st, G, h);
        if (k % 100)
            continue;
        rf_block_angular_momentum(&s, &st, L);
        for (int i = 0; i < 3; i++)
            worst = fmax(worst, fabs(L[i] - L0[i]) / l0);
    }
    print_message("angular momentum over 1e5 steps: largest relative change %.3e\n", worst);
    assert_true(worst < 1e-12);
    /* each step is exact; 1e5 sums gather at most 1e5 roundings of the largest value */
    double t = 1e5 * h, ulps = 1e5 * 2.3e-16;
    assert_true(fabs(st.x[0] - 3 * t) < ulps * 300);
    assert_true(fabs(st.x[2] - (100 + 12 * t - 0.5 * G * t * t)) < ulps * 5e4);
    assert_true(fabs(st.v[2] - (12 - G * t)) < ulps * 1e3);
    double qn = st.q[0] * st.q[0] + st.q[1] * st.q[1] + st.q[2] * st.q[2] + st.q[3] * st.q[3];
    assert_true(fabs(qn - 1) < 1e-15);
    rf_block_shape_free(&s);
}

/* The largest relative energy error over T = 20 s. */
static double energy_error(const rf_block_shape *s, double h, double *final)
{
    rf_block_state st = {{0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0}, {0.9, 2.0, -0.7}};
    double e0 = rf_block_kinetic_energy(s, &st, NULL), worst = 0;
    long n = lround(20.0 / h);
    for (long k = 0; k < n; k++) {
        rf_block_rotor_step(s->inertia, st.q, st.w, h);
        worst = fmax(worst, fabs(rf_block_kinetic_energy(s, &st, NULL) - e0) / e0);
    }
    *final = fabs(rf_block_kinetic_energy(s, &st, NULL) - e0) / e0;
    return worst;
}

static void test_energy_order(void **state)
{
    (void)state;
    rf_block_shape s = box123();
    double f1, f2, f3;
    double e1 = energy_error(&s, 4e-3, &f1), e2 = energy_error(&s, 2e-3, &f2), e3 = energy_error(&s, 1e-3, &f3);
    print_message("energy error (largest over 20 s): %.3e %.3e %.3e at dt 4, 2, 1 ms; ratios %.3f %.3f\n", e1, e2,
                  e3, e1 / e2, e2 / e3);
    assert_true(e1 / e2 > 3.8 && e1 / e2 < 4.2);
    assert_true(e2 / e3 > 3.8 && e2 / e3 < 4.2);
    assert_true(e3 < 1e-4);
    /* no drift: the error at the end is within the largest (bounded oscillation) */
    assert_true(f3 <= e3);
    rf_block_shape_free(&s);
}

/* Spin about body axis `axis` with a perturbation eps on the others: the
 * first time w[axis] changes sign (INFINITY if never within T). */
static double flip_time(const rf_block_shape *s, int axis, double omega, double eps, double T, double *min_ratio)
{
    rf_block_state st = {{0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0}, {eps, eps, eps}};
    st.w[axis] = omega;
    double h = 1e-3;
    *min_ratio = 1;
    for (long k = 1; k * h <= T; k++) {
        rf_block_rotor_step(s->inertia, st.q, st.w, h);
        *min_ratio = fmin(*min_ratio, st.w[axis] / omega);
        if (st.w[axis] < 0)
            return k * h;
    }
    return INFINITY;
}

static void test_tennis_racket(void **state)
{
    (void)state;
    rf_block_shape s = box123();
    const double *I = s.inertia, omega = 2.0, eps = 1e-3;
    /* linearised growth rate about the middle axis */
    double lambda = omega * sqrt((I[1] - I[0]) * (I[2] - I[1]) / (I[0] * I[2]));
    double t_grow = log(omega / eps) / lambda, r1, r2, r3;
    double t1 = flip_time(&s, 0, omega, eps, 20 * t_grow, &r1);
    double t2 = flip_time(&s, 1, omega, eps, 20 * t_grow, &r2);
    double t3 = flip_time(&s, 2, omega, eps, 20 * t_grow, &r3);
    print_message("spin about axis 1, 2, 3: first flip at %g, %g, %g s (e-folding estimate %.3f s); smallest w/w0 "
                  "%.6f %.6f %.6f\n", t1, t2, t3, t_grow, r1, r2, r3);
    assert_true(isinf(t1) && isinf(t3));
    assert_true(r1 > 0.999 && r3 > 0.999);
    assert_true(t2 > 0.5 * t_grow && t2 < 3 * t_grow);
    rf_block_shape_free(&s);
}

/* Symmetric top I1 = I2 (an ellipsoid a = b): in the body, w3 is constant
 * and (w1, w2) turns at Omega = (I3 - I1) w3 / I1; in space the
 * body turns about L at |L| / I1 (then by -Omega t about its own axis).
 * The orientation's error at t = 2 s falls 4x when dt halves. */
static double symmetric_top_error(const rf_block_shape *s, double h)
{
    rf_block_state st = {{0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0}, {0.8, 0.0, 3.0}};
    long n = lround(2.0 / h);
    for (long k = 0; k < n; k++)
        rf_block_rotor_step(s->inertia, st.q, st.w, h);
    double t = n * h, I1 = s->inertia[0], I3 = s->inertia[2];
    double Om = (I3 - I1) * 3.0 / I1;
    double w1 = 0.8 * cos(Om * t), w2 = 0.8 * sin(Om * t);
    double err = hypot(st.w[0] - w1, st.w[1] - w2);
    /* the body's symmetry axis in space: e3(t) = rot(L^, |L| t / I1) e3(0) */
    double L[3] = {I1 * 0.8, 0, I3 * 3.0}, l = sqrt(L[0] * L[0] + L[2] * L[2]), u[3] = {L[0] / l, 0, L[2] / l};
    double ang = l / I1 * t, e0[3] = {0, 0, 1}, ud = u[2], c = cos(ang), sn = sin(ang), uxe[3] = {0, -u[0], 0};
    double e3[3], got[3], b[3] = {0, 0, 1};
    for (int i = 0; i < 3; i++)
        e3[i] = e0[i] * c + uxe[i] * sn + u[i] * ud * (1 - c);
    rf_block_to_space(st.q, b, got);
    for (int i = 0; i < 3; i++)
        err = fmax(err, fabs(got[i] - e3[i]));
    return err;
}

static void test_symmetric_top(void **state)
{
    (void)state;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_ellipsoid(1.0, 1.0, 0.5, 2650, &s, &err), RF_OK);
    assert_true(fabs(s.inertia[0] - s.inertia[1]) < 1e-12 * s.inertia[0]);
    double e1 = symmetric_top_error(&s, 2e-3), e2 = symmetric_top_error(&s, 1e-3), e3 = symmetric_top_error(&s, 5e-4);
    print_message("symmetric top, error at 2 s: %.3e %.3e %.3e (dt 2, 1, 0.5 ms)\n", e1, e2, e3);
    assert_true(e1 / e2 > 3.7 && e1 / e2 < 4.3);
    assert_true(e2 / e3 > 3.7 && e2 / e3 < 4.3);
    assert_true(e3 < 1e-4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_momentum_and_parabola),
        cmocka_unit_test(test_energy_order),
        cmocka_unit_test(test_tennis_racket),
        cmocka_unit_test(test_symmetric_top),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
