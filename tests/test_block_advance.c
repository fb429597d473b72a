/* test_block_advance.c - adaptive steps of a rigid block (rf_block_advance,
 * block_contact.c): a long free flight follows the exact parabola and keeps
 * the space angular momentum to round-off and the energy of an asymmetric
 * top within the rotor's bounded oscillation; over a bumpy bilinear DEM
 * (with its exact bound above a plane) no long flight step ends with a
 * vertex in the ground, the first contact comes within 2 h of the
 * fixed-step run's, far fewer steps are taken, and the energy never grows
 * in a contact step; a sphere dropped on a plane rebounds to e^2 H as with
 * fixed steps; without a ground bound every step is a contact step. */
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
#define NODES 61
#define CELL 1.0

static double dem[NODES * NODES];

static int dem_ground(void *ctx, double x, double y, double *z, double n[3])
{
    (void)ctx;
    double u = x / CELL, v = y / CELL;
    if (!(u >= 0 && v >= 0 && u <= NODES - 1 && v <= NODES - 1))
        return 0;
    int i = u >= NODES - 1 ? NODES - 2 : (int)u, j = v >= NODES - 1 ? NODES - 2 : (int)v;
    double fu = u - i, fv = v - j, *c = dem + j * NODES + i;
    *z = (1 - fv) * ((1 - fu) * c[0] + fu * c[1]) + fv * ((1 - fu) * c[NODES] + fu * c[NODES + 1]);
    double dx = ((1 - fv) * (c[1] - c[0]) + fv * (c[NODES + 1] - c[NODES])) / CELL;
    double dy = ((1 - fu) * (c[NODES] - c[0]) + fu * (c[NODES + 1] - c[1])) / CELL, l = sqrt(1 + dx * dx + dy * dy);
    n[0] = -dx / l, n[1] = -dy / l, n[2] = 1 / l;
    return 1;
}

/* Exact: bilinear minus a plane peaks at x in {x0, x1, grid lines} times y likewise. */
static int dem_bound(void *ctx, double x0, double y0, double x1, double y1, const double p[3], double *dz)
{
    (void)ctx;
    double top = (NODES - 1) * CELL, xs[NODES + 2], ys[NODES + 2], z, n[3], m = -INFINITY;
    x0 = fmax(x0, 0), y0 = fmax(y0, 0), x1 = fmin(x1, top), y1 = fmin(y1, top);
    if (!(x0 <= x1 && y0 <= y1))
        return 0;
    int nx = 0, ny = 0;
    xs[nx++] = x0, ys[ny++] = y0;
    for (double g = (floor(x0 / CELL) + 1) * CELL; g < x1; g += CELL)
        xs[nx++] = g;
    for (double g = (floor(y0 / CELL) + 1) * CELL; g < y1; g += CELL)
        ys[ny++] = g;
    xs[nx++] = x1, ys[ny++] = y1;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++)
            if (dem_ground(NULL, xs[i], ys[j], &z, n))
                m = fmax(m, z - p[0] - p[1] * xs[i] - p[2] * ys[j]);
    *dz = m;
    return 1;
}

/* A 30 deg slope falling to +x with bumps of 0.3 m. */
static void make_dem(void)
{
    for (int j = 0; j < NODES; j++)
        for (int i = 0; i < NODES; i++)
            dem[j * NODES + i] = -tan(30 * 3.14159265358979323846 / 180) * i * CELL + 0.3 * sin(i / 2.3) * cos(j / 3.1);
}

static double lowest_gap(const rf_block_shape *s, const rf_block_state *st)
{
    double worst = INFINITY;
    for (size_t i = 0; i < s->n_vertices; i++) {
        double p[3], z, n[3];
        rf_block_to_space(st->q, s->vertices + 3 * i, p);
        if (dem_ground(NULL, st->x[0] + p[0], st->x[1] + p[1], &z, n))
            worst = fmin(worst, st->x[2] + p[2] - z);
    }
    return worst;
}

static void test_long_flight(void **state)
{
    (void)state;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_box(1, 2, 3, 2650, &s, &err), RF_OK);
    rf_block_world w = {.e_n = 0.3, .mu = 0.5, .g = G, .h = 1e-3, .tol = 1e-10, .max_iter = 500};
    rf_block_state st = {{0, 0, 0}, {1, 0, 0, 0}, {3, -1, 20}, {0.2, 3.0, 0.4}}, st0 = st;
    double L0[3], L[3], t = 0, e0 = rf_block_energy(&s, &st, G), worst = 0;
    rf_block_angular_momentum(&s, &st, L0);
    int n = 0;
    while (t < 4 - 1e-12) {
        double h = rf_block_advance(&s, &w, &st, 0.064, NULL);
        assert_true(h == 0.064 || n == 0 || t + h > 4 - 0.064);
        t += h, n++;
        worst = fmax(worst, fabs(rf_block_energy(&s, &st, G) - e0));
    }
    assert_true(n <= 4 / 0.064 + 6);
    for (int i = 0; i < 3; i++) {
        double want = st0.x[i] + st0.v[i] * t - (i == 2 ? 0.5 * G * t * t : 0);
        if (fabs(st.x[i] - want) > 1e-9)
            fail_msg("axis %d: %.15g, want %.15g", i, st.x[i], want);
    }
    rf_block_angular_momentum(&s, &st, L);
    for (int i = 0; i < 3; i++)
        assert_true(fabs(L[i] - L0[i]) < 1e-12 * sqrt(L0[0] * L0[0] + L0[1] * L0[1] + L0[2] * L0[2]));
    /* the rotor's bounded O(theta^2) oscillation at sub-steps of 0.05 rad: measured 7.5e-6 of the rotational energy */
    double rot = rf_block_kinetic_energy(&s, &st0, NULL) - 0.5 * s.mass * 410;
    printf("long flight: %d steps over %.3f s, energy error at most %.3g of the rotational energy\n", n, t,
           worst / rot);
    assert_true(worst < 1e-4 * rot);
    rf_block_shape_free(&s);
}

/* The same throw onto the DEM with fixed steps and with rf_block_advance. */
static void test_dem_no_tunnelling(void **state)
{
    (void)state;
    make_dem();
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_eota_cube(1.0, 2650, &s, &err), RF_OK);
    rf_block_world w = {.e_n = 0.3, .mu = 0.6, .g = G, .h = 1e-3, .tol = 1e-10, .max_iter = 1000,
                        .ground = dem_ground, .ground_bound = dem_bound};
    rf_block_state st0 = {{5, 30, 3}, {0.9, 0.3, -0.2, 0.25}, {4, 0.5, 2}, {1, -2, 3}};
    double qn = sqrt(0.81 + 0.09 + 0.04 + 0.0625);
    for (int i = 0; i < 4; i++)
        st0.q[i] /= qn;
    rf_block_state a = st0, f = st0;
    double t_first_fixed = -1, t = 0;
    for (int k = 0; k < 20000 && t_first_fixed < 0; k++) {
        rf_block_step_info info;
        rf_block_step(&s, &w, &f, &info);
        t += w.h;
        if (info.n_contacts)
            t_first_fixed = t;
    }
    assert_true(t_first_fixed > 0.1);
    double t_first = -1, e = rf_block_energy(&s, &a, G);
    int steps = 0, long_steps = 0;
    t = 0;
    while (t < 3) {
        rf_block_step_info info;
        double h = rf_block_advance(&s, &w, &a, 0.064, &info);
        t += h, steps++;
        if (h > w.h) {
            long_steps++;
            double gap = lowest_gap(&s, &a);
            if (!(gap > 0))
                fail_msg("a long step (%.3f s) ended at t = %.4f s with a vertex %.3g m in the ground", h, t, gap);
        }
        if (info.n_contacts && t_first < 0)
            t_first = t;
        double e2 = rf_block_energy(&s, &a, G);
        if (info.n_contacts)
            assert_true(e2 - e < 1e-9 * fabs(e));
        e = e2;
    }
    printf("DEM: first contact at %.4f s (fixed steps %.4f s); %d steps over 3 s, %d long\n", t_first, t_first_fixed,
           steps, long_steps);
    assert_true(fabs(t_first - t_first_fixed) <= 2 * w.h + 1e-12);
    assert_true(long_steps > 0 && steps < 3000 / 2);
    rf_block_shape_free(&s);
}

static void test_sphere_rebound(void **state)
{
    (void)state;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_sphere(0.5, 2650, &s, &err), RF_OK);
    rf_block_plane floor = {{0, 0, 0}, {0, 0, 1}};
    rf_block_world w = {.e_n = 0.6, .mu = 0.5, .g = G, .h = 1e-4, .tol = 1e-12, .max_iter = 500, .n_planes = 1,
                        .planes = &floor};
    rf_block_state st = {{0, 0, 2.5}, {1, 0, 0, 0}, {0}, {0}};
    double apex = 0, t = 0;
    int hit = 0, steps = 0;
    while (t < 1.5) {
        rf_block_step_info info;
        t += rf_block_advance(&s, &w, &st, 0.064, &info), steps++;
        hit |= info.n_contacts > 0;
        if (hit && !info.n_contacts && st.v[2] > 0) /* the parabola's top, exactly */
            apex = fmax(apex, st.x[2] + st.v[2] * st.v[2] / (2 * G) - 0.5);
    }
    double v = sqrt(2 * G * 2.0);
    printf("sphere: apex %.5f m after the bounce (e^2 H = %.5f), %d steps\n", apex, 0.36 * 2.0, steps);
    assert_true(fabs(apex - 0.36 * 2.0) < 2 * v * w.h);
    assert_true(steps < 1.5 / w.h / 5);
    rf_block_shape_free(&s);
}

static void test_without_bound(void **state)
{
    (void)state;
    make_dem();
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_eota_cube(1.0, 2650, &s, &err), RF_OK);
    rf_block_world w = {.e_n = 0.3, .mu = 0.6, .g = G, .h = 1e-3, .tol = 1e-10, .max_iter = 1000,
                        .ground = dem_ground};
    rf_block_state st = {{5, 30, 10}, {1, 0, 0, 0}, {0}, {0}};
    for (int k = 0; k < 10; k++)
        assert_true(rf_block_advance(&s, &w, &st, 0.064, NULL) == w.h);
    rf_block_shape_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_long_flight),
        cmocka_unit_test(test_dem_no_tunnelling),
        cmocka_unit_test(test_sphere_rebound),
        cmocka_unit_test(test_without_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
