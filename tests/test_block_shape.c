/* test_block_shape.c - block shapes and their mass properties (issue 30;
 * block_shape.c, block_hull.c, block_mass.c) against closed forms (box,
 * ellipsoid, cube), invariance under rigid motion, a second method
 * (inscribed polyhedra converging to the ellipsoid at second order), the
 * hull's topology (Euler) and containment, and brute-force support
 * points. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/block.h"

#define PI 3.14159265358979323846
#define RHO 2650.0

static void assert_rel(double got, double want, double tol, const char *what)
{
    double err = fabs(got - want) / fmax(fabs(want), 1e-300);
    if (!(err <= tol))
        fail_msg("%s: got %.17g, want %.17g (relative error %.3g > %.3g)", what, got, want, err, tol);
}

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / 16777216.0;
}

static void test_box_closed_form(void **state)
{
    (void)state;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_box(1, 2, 3, RHO, &s, &err), RF_OK);
    double m = RHO * 6;
    assert_int_equal(s.n_vertices, 8);
    assert_int_equal(s.n_faces, 12);
    assert_rel(s.volume, 6, 1e-13, "box volume");
    assert_rel(s.mass, m, 1e-13, "box mass");
    /* ascending: about z (1 + 4), y (1 + 9), x (4 + 9), times m/12 */
    assert_rel(s.inertia[0], m * 5 / 12, 1e-12, "box I1");
    assert_rel(s.inertia[1], m * 10 / 12, 1e-12, "box I2");
    assert_rel(s.inertia[2], m * 13 / 12, 1e-12, "box I3");
    assert_rel(s.bound_radius, sqrt(14) / 2, 1e-13, "box bounding radius");
    for (int i = 0; i < 3; i++)
        assert_true(fabs(s.centre[i]) < 1e-14);
    /* body x is the given z (the longest edge has the smallest moment) */
    assert_rel(fabs(s.axes[2 * 3 + 0]), 1, 1e-14, "axis 1 along z");
    rf_block_shape_free(&s);
}

/* The unit cube's corners, with face centres, edge midpoints, repeated
 * corners and interior points that the hull must drop. */
static void test_cube_cloud(void **state)
{
    (void)state;
    double p[3 * 200];
    size_t n = 0;
    unsigned seed = 7;
    double L = 0.7, o[3] = {3, -2, 10};
    for (int k = 0; k < 27; k++) /* the 3x3x3 grid: corners, edge midpoints, face centres, centre */
        for (int c = 0; c < 3; c++)
            p[3 * k + c] = o[c] + L * 0.5 * ((k / (c == 0 ? 1 : c == 1 ? 3 : 9)) % 3);
    n = 27;
    for (; n < 60; n++)
        for (int c = 0; c < 3; c++)
            p[3 * n + c] = o[c] + L * urand(&seed);
    memcpy(p + 3 * n, p, 3 * sizeof *p); /* a repeated corner */
    n++;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_polyhedron(n, p, RHO, &s, &err), RF_OK);
    assert_int_equal(s.n_vertices, 8);
    double V = L * L * L, m = RHO * V;
    assert_rel(s.volume, V, 1e-12, "cube volume");
    for (int i = 0; i < 3; i++) {
        assert_rel(s.inertia[i], m * L * L / 6, 1e-12, "cube moment");
        assert_rel(s.centre[i], o[i] + L / 2, 1e-12, "cube centre");
    }
    rf_block_shape_free(&s);
}

/* Ellipsoid: closed forms, and the hulls of points on its surface (a
 * latitude-longitude grid) converge to them at second order in the grid
 * spacing: the error falls about 4x when the grid is refined 2x. */
static double ellipsoid_hull_error(int nlat, const rf_block_shape *e, const double abc[3])
{
    int nlon = 2 * nlat;
    size_t n = (size_t)(nlat - 1) * nlon + 2;
    double *p = malloc(3 * n * sizeof *p);
    size_t k = 0;
    for (int i = 1; i < nlat; i++)
        for (int j = 0; j < nlon; j++) {
            double th = PI * i / nlat, ph = 2 * PI * j / nlon;
            p[3 * k] = abc[0] * sin(th) * cos(ph), p[3 * k + 1] = abc[1] * sin(th) * sin(ph);
            p[3 * k + 2] = abc[2] * cos(th);
            k++;
        }
    double poles[6] = {0, 0, abc[2], 0, 0, -abc[2]};
    memcpy(p + 3 * k, poles, sizeof poles);
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_polyhedron(n, p, RHO, &s, &err), RF_OK);
    free(p);
    double worst = fabs(s.volume - e->volume) / e->volume;
    for (int i = 0; i < 3; i++)
        worst = fmax(worst, fabs(s.inertia[i] - e->inertia[i]) / e->inertia[i]);
    rf_block_shape_free(&s);
    return worst;
}

static void test_ellipsoid(void **state)
{
    (void)state;
    rf_block_shape e, sp;
    rf_error err;
    double abc[3] = {0.5, 1.5, 1.0};
    assert_int_equal(rf_block_ellipsoid(abc[0], abc[1], abc[2], RHO, &e, &err), RF_OK);
    double V = 4.0 / 3.0 * PI * 0.75, m = RHO * V;
    assert_rel(e.volume, V, 1e-14, "ellipsoid volume");
    /* longest semi-axis (b = 1.5) on body x: I1 = m (1 + 0.25)/5 */
    assert_rel(e.semi[0], 1.5, 0, "body x semi-axis");
    assert_rel(e.inertia[0], m * (1.0 + 0.25) / 5, 1e-14, "ellipsoid I1");
    assert_rel(e.inertia[1], m * (2.25 + 0.25) / 5, 1e-14, "ellipsoid I2");
    assert_rel(e.inertia[2], m * (2.25 + 1.0) / 5, 1e-14, "ellipsoid I3");
    assert_int_equal(rf_block_sphere(0.8, RHO, &sp, &err), RF_OK);
    rf_block_shape e2;
    assert_int_equal(rf_block_ellipsoid(0.8, 0.8, 0.8, RHO, &e2, &err), RF_OK);
    assert_rel(e2.inertia[1], sp.inertia[1], 1e-14, "ellipsoid(a,a,a) = sphere");
    double e16 = ellipsoid_hull_error(16, &e, abc), e32 = ellipsoid_hull_error(32, &e, abc);
    double e64 = ellipsoid_hull_error(64, &e, abc);
    print_message("ellipsoid hulls: relative error %.3e %.3e %.3e (grid 16, 32, 64)\n", e16, e32, e64);
    assert_true(e64 < 2e-3);
    assert_true(e16 / e32 > 3.5 && e16 / e32 < 4.5);
    assert_true(e32 / e64 > 3.5 && e32 / e64 < 4.5);
}

static void random_rotation(unsigned *seed, double r[9])
{
    double q[4], n = 0;
    for (int i = 0; i < 4; i++)
        q[i] = urand(seed) - 0.5, n += q[i] * q[i];
    for (int i = 0; i < 4; i++)
        q[i] /= sqrt(n);
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double m[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
    memcpy(r, m, sizeof m);
}

/* A random rock (points on a distorted sphere plus interior points): the
 * same volume, principal moments and (moved) centre after a random rotation
 * and translation; the hull is simplicial: F = 2 V - 4, E = 3 F / 2; every
 * point is inside it. */
static void test_rigid_motion_invariance(void **state)
{
    (void)state;
    enum { N = 300 };
    double p[3 * N], p2[3 * N], r[9], t[3] = {120.5, -33.25, 1800.0};
    unsigned seed = 42;
    for (int i = 0; i < N; i++) {
        double u = 2 * urand(&seed) - 1, ph = 2 * PI * urand(&seed), rad = i < 250 ? 1 : 0.5 * urand(&seed);
        double s = sqrt(1 - u * u);
        p[3 * i] = 1.6 * rad * s * cos(ph), p[3 * i + 1] = 1.1 * rad * s * sin(ph), p[3 * i + 2] = 0.7 * rad * u;
    }
    random_rotation(&seed, r);
    for (int i = 0; i < N; i++)
        for (int c = 0; c < 3; c++)
            p2[3 * i + c] = t[c] + r[3 * c] * p[3 * i] + r[3 * c + 1] * p[3 * i + 1] + r[3 * c + 2] * p[3 * i + 2];
    rf_block_shape a, b;
    rf_error err;
    assert_int_equal(rf_block_polyhedron(N, p, RHO, &a, &err), RF_OK);
    assert_int_equal(rf_block_polyhedron(N, p2, RHO, &b, &err), RF_OK);
    assert_int_equal(a.n_vertices, 250);
    assert_int_equal(a.n_faces, 2 * a.n_vertices - 4);
    assert_int_equal(b.n_vertices, a.n_vertices);
    assert_rel(b.volume, a.volume, 1e-12, "volume after motion");
    for (int i = 0; i < 3; i++) {
        assert_rel(b.inertia[i], a.inertia[i], 1e-12, "principal moment after motion");
        double c = t[i] + r[3 * i] * a.centre[0] + r[3 * i + 1] * a.centre[1] + r[3 * i + 2] * a.centre[2];
        assert_true(fabs(b.centre[i] - c) < 1e-12 * 1800);
    }
    assert_true(a.inertia[0] < a.inertia[1] && a.inertia[1] < a.inertia[2]);
    /* every body-frame point inside every face plane */
    for (size_t f = 0; f < a.n_faces; f++) {
        const double *v0 = a.vertices + 3 * a.faces[3 * f], *v1 = a.vertices + 3 * a.faces[3 * f + 1];
        const double *v2 = a.vertices + 3 * a.faces[3 * f + 2];
        double e1[3], e2[3], n[3];
        for (int c = 0; c < 3; c++)
            e1[c] = v1[c] - v0[c], e2[c] = v2[c] - v0[c];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        for (size_t i = 0; i < a.n_vertices; i++) {
            const double *q = a.vertices + 3 * i;
            double d = n[0] * (q[0] - v0[0]) + n[1] * (q[1] - v0[1]) + n[2] * (q[2] - v0[2]);
            assert_true(d <= 1e-12);
        }
    }
    rf_block_shape_free(&a);
    rf_block_shape_free(&b);
}

/* Scaling keeps shape: mass ~ V, moments ~ V^(5/3); equal to the hull of the
 * scaled points.  Stretching at constant volume: an ellipsoid keeps abc, a
 * box becomes the box of the stretched edges. */
static void test_scaling(void **state)
{
    (void)state;
    rf_block_shape c, d, e, box, box2;
    rf_error err;
    assert_int_equal(rf_block_eota_cube(2.0, RHO, &c, &err), RF_OK);
    assert_rel(c.volume, 2.0, 1e-14, "EOTA cube volume");
    assert_rel(c.inertia[0], c.inertia[2], 1e-12, "EOTA cube is isotropic");
    assert_int_equal(rf_block_copy(&c, &d, &err), RF_OK);
    assert_int_equal(rf_block_scale_to_volume(&d, 16.0, &err), RF_OK);
    assert_rel(d.mass, 8 * c.mass, 1e-14, "mass x8");
    assert_rel(d.inertia[1], 32 * c.inertia[1], 1e-13, "moment x2^5");
    double *p = malloc(3 * d.n_vertices * sizeof *p);
    memcpy(p, d.vertices, 3 * d.n_vertices * sizeof *p);
    assert_int_equal(rf_block_polyhedron(d.n_vertices, p, RHO, &e, &err), RF_OK);
    assert_rel(e.volume, 16.0, 1e-12, "hull of the scaled points: volume");
    assert_rel(e.inertia[2], d.inertia[2], 1e-12, "hull of the scaled points: moment");
    free(p);
    rf_block_shape ell;
    assert_int_equal(rf_block_ellipsoid(1, 1, 1, RHO, &ell, &err), RF_OK);
    assert_int_equal(rf_block_stretch(&ell, 2, 1, 0.5, ell.volume, &err), RF_OK);
    assert_rel(ell.semi[0] * ell.semi[1] * ell.semi[2], 1, 1e-14, "stretched ellipsoid: abc kept");
    assert_rel(ell.semi[0] / ell.semi[2], 4, 1e-14, "stretched ellipsoid: ratio");
    assert_int_equal(rf_block_box(1, 1, 1, RHO, &box, &err), RF_OK);
    assert_int_equal(rf_block_stretch(&box, 3, 1, 1.0 / 3, 0, &err), RF_OK);
    assert_int_equal(rf_block_box(3, 1, 1.0 / 3, RHO, &box2, &err), RF_OK);
    for (int i = 0; i < 3; i++)
        assert_rel(box.inertia[i], box2.inertia[i], 1e-12, "stretched box = box of stretched edges");
    rf_block_shape w;
    assert_int_equal(rf_block_eota_wheel(2.0, RHO, &w, &err), RF_OK);
    assert_rel(w.volume, 2.0, 1e-14, "EOTA wheel volume");
    assert_rel(w.inertia[0], w.inertia[1], 1e-12, "wheel: I1 = I2");
    assert_true(w.inertia[2] > 1.5 * w.inertia[1]);
    rf_block_shape_free(&c), rf_block_shape_free(&d), rf_block_shape_free(&e);
    rf_block_shape_free(&box), rf_block_shape_free(&box2), rf_block_shape_free(&w);
}

/* Support points: a polyhedron's is the brute-force maximum; an ellipsoid's
 * lies on its surface with its normal along d. */
static void test_support(void **state)
{
    (void)state;
    rf_block_shape w, e;
    rf_error err;
    assert_int_equal(rf_block_eota_wheel(1.0, RHO, &w, &err), RF_OK);
    assert_int_equal(rf_block_ellipsoid(1.2, 0.7, 0.4, RHO, &e, &err), RF_OK);
    unsigned seed = 3;
    for (int k = 0; k < 100; k++) {
        double d[3] = {urand(&seed) - 0.5, urand(&seed) - 0.5, urand(&seed) - 0.5}, p[3];
        double h = rf_block_support(&w, d, p), best = -INFINITY;
        for (size_t i = 0; i < w.n_vertices; i++) {
            const double *v = w.vertices + 3 * i;
            best = fmax(best, d[0] * v[0] + d[1] * v[1] + d[2] * v[2]);
        }
        assert_rel(h, best, 0, "polyhedron support");
        rf_block_support(&e, d, p);
        double on = 0, g[3], gn = 0, dn = 0, dot = 0;
        for (int i = 0; i < 3; i++) {
            on += p[i] * p[i] / (e.semi[i] * e.semi[i]);
            g[i] = p[i] / (e.semi[i] * e.semi[i]);
            gn += g[i] * g[i], dn += d[i] * d[i], dot += g[i] * d[i];
        }
        assert_rel(on, 1, 1e-14, "ellipsoid support on the surface");
        assert_rel(dot / sqrt(gn * dn), 1, 1e-14, "ellipsoid normal along d");
    }
    /* the lowest point of a box resting on a face, turned 30 deg about y */
    rf_block_shape b;
    assert_int_equal(rf_block_box(2, 1, 1, RHO, &b, &err), RF_OK);
    rf_block_state st = {{0, 0, 5}, {1, 0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    rf_block_quat_from_matrix(b.axes, st.q); /* as given: edges along x, y, z */
    double up[3] = {0, 0, 1}, p[3];
    assert_rel(rf_block_lowest_point(&b, &st, up, p), 4.5, 1e-14, "lowest point of the box");
    double c = cos(PI / 6), s = sin(PI / 6), ry[9] = {c, 0, s, 0, 1, 0, -s, 0, c}, m[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m[3 * i + j] = ry[3 * i] * b.axes[j] + ry[3 * i + 1] * b.axes[3 + j] + ry[3 * i + 2] * b.axes[6 + j];
    rf_block_quat_from_matrix(m, st.q);
    assert_rel(rf_block_lowest_point(&b, &st, up, p), 5 - (1.0 * s + 0.5 * c), 1e-14, "lowest point, turned");
    rf_block_shape_free(&w), rf_block_shape_free(&b);
}

static void test_bad_input(void **state)
{
    (void)state;
    rf_block_shape s;
    rf_error err;
    double flat[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1e-14};
    assert_int_equal(rf_block_polyhedron(4, flat, RHO, &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "coplanar"));
    assert_int_equal(rf_block_box(1, -2, 1, RHO, &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "ly"));
    assert_non_null(strstr(err.msg, "-2"));
    assert_int_equal(rf_block_sphere(1, 0, &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "density"));
    double nan_pts[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, NAN};
    assert_int_equal(rf_block_polyhedron(4, nan_pts, RHO, &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "point 3"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box_closed_form), cmocka_unit_test(test_cube_cloud),
        cmocka_unit_test(test_ellipsoid),       cmocka_unit_test(test_rigid_motion_invariance),
        cmocka_unit_test(test_scaling),         cmocka_unit_test(test_support),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
