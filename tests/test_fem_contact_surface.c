/* test_fem_contact_surface.c - the smooth master surface of the
 * large-deformation axisymmetric contact (src/fem/fem_contact_surface.c)
 * against independent references: the gap's gradient against central
 * differences of the gap itself (re-projected at every perturbed state),
 * the continuity of the point, the normal and the gap from one segment to
 * the next (the property whose absence made the updated-Lagrangian contact
 * do work, issue 29), the radial tangent on the axis, the masters' weights
 * never negative and summing to one, the consistent (hat-function) share of
 * a uniform pressure for the axis node, and nodes on a circle: the curve
 * follows it within the B-spline's known offset. */
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

/* Segment j of a surface of n nodes p (the first on the axis), as the
 * contact makes it (fem_contact.c surface_segment). */
static fem_surf_segment segment_of(const double (*p)[2], int n, int j)
{
    fem_surf_segment S = {.has_prev = j > 0, .has_next = j + 2 < n};
    for (int k = 0; k < 4; k++) {
        const int i = j - 1 + k < 0 ? 0 : j - 1 + k >= n ? n - 1 : j - 1 + k;
        S.p[k][0] = p[i][0], S.p[k][1] = p[i][1];
    }
    return S;
}

/* Six kinked nodes, the first on the axis: where segment j ends segment
 * j + 1 begins, with the same tangent, and a slave just above the joint
 * has the same gap and normal on both (the straight segments' normals
 * differ at the nodes by the kink angle); on the axis the tangent is radial. */
static void test_continuous_at_joints(void **state)
{
    (void)state;
    const double p[6][2] = {{0, 0}, {1e-3, 0.05e-3}, {2e-3, 0.02e-3}, {3.1e-3, 0.09e-3}, {4e-3, 0.2e-3}, {5e-3, 0.25e-3}};
    const double kink = atan2(p[3][1] - p[2][1], p[3][0] - p[2][0]) - atan2(p[2][1] - p[1][1], p[2][0] - p[1][0]);
    assert_true(fabs(kink) > 0.05);
    for (int j = 0; j + 2 < 6; j++) {
        fem_surf_segment A = segment_of(p, 6, j), B = segment_of(p, 6, j + 1);
        double xa[2], ta[2], xb[2], tb[2];
        fem_surf_point(&A, 1, xa, ta), fem_surf_point(&B, 0, xb, tb);
        assert_true(hypot(xa[0] - xb[0], xa[1] - xb[1]) < 1e-18);
        assert_true(fabs(ta[0] * tb[1] - ta[1] * tb[0]) < 1e-14); /* one tangent direction */
        /* within 1e-8 m of the joint (the normal turns by the arc's curvature,
           kink / (2 FILLET h) ~ 100 / m here, times the distance) */
        for (int side = -1; side <= 1; side += 2) {
            const double xs[2] = {xa[0] + side * 1e-9, xa[1] + 1e-8};
            fem_surf_gap Ga, Gb;
            fem_surf_project(&A, xs, &Ga), fem_surf_project(&B, xs, &Gb);
            /* one of the two finds the point beyond its end (clamped to the joint): both gaps agree */
            assert_true(fabs(Ga.g - Gb.g) < 1e-13);
            const double gj = -ta[1] * (xs[0] - xa[0]) + ta[0] * (xs[1] - xa[1]); /* along the joint's normal */
            assert_true(fabs(Ga.g - gj) < 1e-13);
            assert_true(fabs(Ga.n[0] - Gb.n[0]) < 1e-6 && fabs(Ga.n[1] - Gb.n[1]) < 1e-6);
        }
    }
    fem_surf_segment S = segment_of(p, 6, 0);
    double x[2], t[2];
    fem_surf_point(&S, 0, x, t);
    assert_true(fabs(x[0]) < 1e-18 && fabs(t[1]) < 1e-14); /* on the axis, radial */
}

/* The masters' weights W = -dg / n (per coordinate) at many points of every
 * segment of a kinked surface: never negative (a slave pushes every master
 * node away from itself, never pulls one: the Hermite curve's H11 < 0 pulled
 * the free surface node beyond the loaded segment, docs 6f), and summing to
 * one (a rigid translation of slave and masters leaves the gap), except the
 * radial weights of segment 0, whose mirrored node does not move with a
 * radial translation (nor does the axis). */
static void test_weights_nonnegative(void **state)
{
    (void)state;
    const double p[7][2] = {{0, 0},           {1e-3, 0.05e-3}, {2e-3, 0.02e-3}, {3.1e-3, 0.09e-3},
                            {4e-3, 0.2e-3},    {5e-3, 0.25e-3}, {6e-3, 0.22e-3}};
    double wmin = 1;
    for (int j = 0; j + 1 < 7; j++) {
        fem_surf_segment S = segment_of(p, 7, j);
        for (int q = 0; q <= 20; q++) {
            double x[2], t[2];
            fem_surf_point(&S, q / 20.0, x, t);
            const double xs[2] = {x[0] - 1e-6 * t[1], x[1] + 1e-6 * t[0]};
            fem_surf_gap G;
            fem_surf_project(&S, xs, &G);
            for (int a = 0; a < 2; a++) {
                if (fabs(G.n[a]) < 1e-3)
                    continue;
                double sum = 0;
                for (int m = 0; m < 4; m++) {
                    const double w = -G.dg[m][a] / G.n[a];
                    wmin = fmin(wmin, w), sum += w;
                }
                if (a == 1 || j > 0)
                    assert_true(fabs(sum - 1) < 1e-12);
            }
        }
    }
    printf("smallest master weight %.3e\n", wmin);
    assert_true(wmin > -1e-12);
}

/* Under a uniform pressure p on a flat surface of nodes r_k = k h, node k
 * takes F_k = 2 pi p int W_k(r) r dr.  The consistent share, the one of the
 * linear elements' hat functions and of the lumped masses, is h^2 / 6 on
 * the axis and k h^2 elsewhere (2 pi p left out).  The curve departs from
 * the chords only within f = FILLET (1/4) of the nodes, and by hand from its
 * weights: the axis node takes h^2 (1/6 + f^2/6 - f^3/24) (+5.9 %), x_1
 * h^2 (1 + f^3/24), the others exactly k h^2.  (The uniform cubic B-spline
 * mirrored at the axis gave the axis node 7/30: 1.4 times its share, so it
 * was accelerated 1.4 times as fast as the surface around it and ran ahead
 * of the boulder's tip into the soil, docs 6f.) */
static void test_axis_share(void **state)
{
    (void)state;
    enum { n = 9, nq = 4000 };
    const double h = 1e-3;
    double p[n][2], F[n] = {0};
    for (int k = 0; k < n; k++)
        p[k][0] = k * h, p[k][1] = 0;
    for (int j = 0; j + 2 < n; j++) { /* the last segment's extrapolated end left out */
        fem_surf_segment S = segment_of(p, n, j);
        for (int q = 0; q < nq; q++) {
            const double r = (j + (q + 0.5) / nq) * h; /* the curve's r is linear in xi here */
            const double xs[2] = {r, 1e-9};
            fem_surf_gap G;
            assert_int_equal(fem_surf_project(&S, xs, &G), 0);
            assert_true(fabs(G.xi - (q + 0.5) / nq) < 1e-9);
            for (int m = 0; m < 4; m++) {
                const int k = j - 1 + m;
                if (k >= 0 && k < n)
                    F[k] += -G.dg[m][1] * r * h / nq;
            }
        }
    }
    const double f = 0.25;
    const double want[5] = {1.0 / 6 + f * f / 6 - f * f * f / 24, 1 + f * f * f / 24, 2, 3, 4};
    for (int k = 0; k < 5; k++) {
        printf("node %d: share %.6f h^2 (hat %.6f)\n", k, F[k] / (h * h), k ? (double)k : 1.0 / 6);
        assert_true(fabs(F[k] / (h * h) - want[k]) < 1e-6 * (k + 1));
    }
}

/* Nodes on a circle of radius R (the boulder's print), the first on the
 * axis.  The curve is the chord on the middle half of each segment and an
 * arc inside the polygon near the nodes, so points on the circle lie at
 * most the chord's sagitta h^2 / 8R below it (mid-chord), and never above
 * it; at a node the arc is FILLET / 4 (1/16) of the second difference,
 * h^2 / 16R, inside.  A point moved inward by delta has the gap larger by
 * delta. */
static void test_circle(void **state)
{
    (void)state;
    const double R = 0.5, dth = 0.02; /* chord h = R dth = 1 cm */
    enum { n = 12 };
    double p[n][2];
    for (int i = 0; i < n; i++)
        p[i][0] = R * sin(i * dth), p[i][1] = R - R * cos(i * dth);
    const double sag = R * dth * dth / 8;
    double emax = 0;
    for (int j = 0; j + 2 < n; j++) {
        fem_surf_segment S = segment_of(p, n, j);
        for (int q = 0; q < 10; q++) {
            const double th = (j + q / 10.0) * dth, delta = 1e-5;
            const double on[2] = {R * sin(th), R - R * cos(th)};
            const double in[2] = {(R - delta) * sin(th), R - (R - delta) * cos(th)};
            fem_surf_gap G;
            if (q > 0)
                assert_int_equal(fem_surf_project(&S, on, &G), 0);
            fem_surf_project(&S, on, &G);
            const double gon = G.g;
            fem_surf_project(&S, in, &G);
            assert_true(fabs(G.g - gon - delta) < 1e-3 * delta);
            assert_true(gon <= 1e-3 * sag && gon > -sag * 1.001);
            if (q == 0) /* on a node */
                assert_true(fabs(gon + sag / 2) < 1e-2 * sag);
            emax = fmax(emax, -gon);
        }
    }
    printf("circle: largest gap of points on it %.3e m, chord sagitta %.3e m\n", emax, sag);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gradient),
        cmocka_unit_test(test_continuous_at_joints),
        cmocka_unit_test(test_weights_nonnegative),
        cmocka_unit_test(test_axis_share),
        cmocka_unit_test(test_circle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
