/* test_fem_contact_surface.c - the smooth master surface of the
 * large-deformation axisymmetric contact (src/fem/fem_contact_surface.c)
 * against independent references: the gap's gradient against central
 * differences of the gap itself (re-projected at every perturbed state),
 * the continuity of the normal and of the gap across a node (the property
 * whose absence made the updated-Lagrangian contact do work, issue 29),
 * and nodes on a circle: the curve follows the circle to far better than
 * the chords' sagitta, with the radial tangent on the axis. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem/fem_contact_surface.h"

/* A kinked segment (chord 1 mm, kinks of a few degrees both ways). */
static fem_surf_segment kinked(int has_prev, int has_next)
{
    fem_surf_segment S = {.p = {{0.0, 0.0}, {1e-3, 0.05e-3}, {2e-3, 0.02e-3}, {3.1e-3, 0.09e-3}},
                          .has_prev = has_prev, .has_next = has_next};
    return S;
}

static double gap_at(const fem_surf_segment *S, const double xs[2])
{
    fem_surf_gap G;
    fem_surf_project(S, xs, &G);
    return G.g;
}

/* Every entry of the gradient against (g(x + h) - g(x - h)) / 2h. */
static void check_gradient(int has_prev, int has_next, const double xs[2])
{
    fem_surf_segment S = kinked(has_prev, has_next);
    fem_surf_gap G;
    assert_int_equal(fem_surf_project(&S, xs, &G), 0);
    const double h = 1e-9; /* m: 1e-6 of the chord */
    double scale = 1, err = 0;
    for (int a = 0; a < 2; a++) { /* the slave: n */
        double xp[2] = {xs[0], xs[1]}, xm[2] = {xs[0], xs[1]};
        xp[a] += h, xm[a] -= h;
        const double fd = (gap_at(&S, xp) - gap_at(&S, xm)) / (2 * h);
        err = fmax(err, fabs(fd - G.n[a]));
    }
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 2; a++) {
            fem_surf_segment P = S, M = S;
            P.p[k][a] += h, M.p[k][a] -= h;
            const double fd = (gap_at(&P, xs) - gap_at(&M, xs)) / (2 * h);
            const int absent = (k == 0 && !has_prev) || (k == 3 && !has_next);
            if (absent) /* the gap does not depend on an absent node */
                assert_true(fabs(fd) < 1e-12);
            else
                err = fmax(err, fabs(fd - G.dg[k][a]));
            scale = fmax(scale, fabs(G.dg[k][a]));
        }
    printf("prev %d next %d: gradient error %.2e (entries up to %.3f)\n", has_prev, has_next, err, scale);
    assert_true(err < 1e-6 * scale);
}

static void test_gradient(void **state)
{
    (void)state;
    const double xs[4][2] = {{1.3e-3, 0.06e-3}, {1.7e-3, 0.01e-3}, {1.05e-3, 0.05e-3}, {1.5e-3, 0.2e-3}};
    for (int c = 0; c < 4; c++) {
        check_gradient(1, 1, xs[c]);
        check_gradient(0, 1, xs[c]);
        check_gradient(1, 0, xs[c]);
    }
}

/* Five nodes, two segments sharing node 2: the same normal and the same gap
 * on both sides of the node; the straight segments' normals differ there by
 * the kink angle. */
static void test_continuous_at_node(void **state)
{
    (void)state;
    const double p[6][2] = {{0, 0},           {1e-3, 0.05e-3}, {2e-3, 0.02e-3},
                            {3.1e-3, 0.09e-3}, {4e-3, 0.2e-3},  {5e-3, 0.25e-3}};
    fem_surf_segment A = {.has_prev = 1, .has_next = 1}, B = A;
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 2; a++)
            A.p[k][a] = p[k][a], B.p[k][a] = p[k + 1][a];
    double xa[2], ta[2], xb[2], tb[2];
    fem_surf_point(&A, 1, xa, ta), fem_surf_point(&B, 0, xb, tb);
    assert_true(hypot(xa[0] - p[2][0], xa[1] - p[2][1]) < 1e-18);
    assert_true(hypot(xb[0] - p[2][0], xb[1] - p[2][1]) < 1e-18);
    assert_true(fabs(ta[0] * tb[1] - ta[1] * tb[0]) < 1e-14); /* one tangent direction */
    const double kink = atan2(p[3][1] - p[2][1], p[3][0] - p[2][0]) - atan2(p[2][1] - p[1][1], p[2][0] - p[1][0]);
    assert_true(fabs(kink) > 0.05);
    /* a slave just above the node, a little before and after it */
    for (int side = -1; side <= 1; side += 2) {
        const double xs[2] = {p[2][0] + side * 1e-9, p[2][1] + 1e-7};
        fem_surf_gap Ga, Gb;
        fem_surf_project(&A, xs, &Ga), fem_surf_project(&B, xs, &Gb);
        /* one of the two finds the point beyond its end (clamped to the node): both gaps agree */
        assert_true(fabs(Ga.g - Gb.g) < 1e-12);
        assert_true(fabs(Ga.g - 1e-7) < 1e-9);
        assert_true(fabs(Ga.n[0] - Gb.n[0]) < 1e-6 && fabs(Ga.n[1] - Gb.n[1]) < 1e-6);
    }
}

/* Nodes on a circle of radius R (the boulder's print), the first on the
 * axis: points on the circle have gaps below 1e-3 of the chords' sagitta
 * h^2 / 8R, and points at R - delta the gap delta. */
static void test_circle(void **state)
{
    (void)state;
    const double R = 0.5, dth = 0.02; /* chord h = R dth = 1 cm */
    const int n = 12;
    double p[12][2];
    for (int i = 0; i < n; i++)
        p[i][0] = R * sin(i * dth), p[i][1] = R - R * cos(i * dth);
    const double sagitta = R * dth * R * dth / (8 * R);
    double emax = 0;
    for (int j = 0; j + 1 < n; j++) {
        fem_surf_segment S = {.has_prev = j > 0, .has_next = j + 2 < n};
        for (int k = 0; k < 4; k++) {
            const int i = j - 1 + k < 0 ? 0 : j - 1 + k >= n ? n - 1 : j - 1 + k;
            S.p[k][0] = p[i][0], S.p[k][1] = p[i][1];
        }
        for (int q = 1; q < 10; q++) {
            const double th = (j + q / 10.0) * dth, delta = 1e-5;
            const double on[2] = {R * sin(th), R - R * cos(th)};
            const double in[2] = {(R - delta) * sin(th), R - (R - delta) * cos(th)};
            fem_surf_gap G;
            assert_int_equal(fem_surf_project(&S, on, &G), 0);
            const double gon = G.g;
            fem_surf_project(&S, in, &G);
            emax = fmax(emax, fmax(fabs(gon), fabs(G.g - gon - delta)));
            assert_true(fabs(G.g - gon - delta) < 1e-3 * delta);
            if (j + 2 < n) /* the one-sided tangent at the surface's end is not the circle's */
                assert_true(fabs(gon) < 1e-3 * sagitta);
        }
    }
    printf("circle: largest gap error %.2e m, chord sagitta %.2e m\n", emax, sagitta);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gradient),
        cmocka_unit_test(test_continuous_at_node),
        cmocka_unit_test(test_circle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
