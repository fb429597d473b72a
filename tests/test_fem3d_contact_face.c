/* test_fem3d_contact_face.c - the 3D contact's master face where the soil is
 * stretched along it (src/fem/fem3d_contact.c, docs/validation-plastic.md
 * section 9e).  Under a rigid boulder sinking into soil the face flows out of
 * the crater: the master material point under a slave is then no longer near
 * the slave's own (X, Y), and the slope that the normal row carries must be
 * dz/dx against the current position, not dz/dX against the material one.
 * The references are exact: the Catmull-Rom face reproduces an affine
 * displacement field, so the located point, the slope and the gap have closed
 * forms, and the normal row G v must be the derivative of that gap (a finite
 * difference of the located gap along a random velocity field).  With the
 * material slope, the normal contact did work on a frictionless sliding pair:
 * +1.7 % of the kinetic energy in the S5 soil at a/h 2.  And the mass
 * redistribution at the contact face (fem3d_mass.c) on one element: mass
 * conserved, the element's eigenvalue bound raised to kappa lambda_max.  And
 * Coulomb friction on a sloped face: |F_t| = f F_n for the forces split by the
 * face's geometry (section 9f). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fem/fem3d_internal.h"

enum { NX = 9, NY = 8, NN = NX * NY + 1 };

typedef struct {
    f3_mesh mesh;
    f3_contact C;
    double x[3 * NN];
    int top[NX * NY];
    int slave, mnode[F3_NM];
    double N[F3_NM], S[2], s0[3], gvo[3], Xm[2];
    unsigned char outside;
} face_case;

/* A top grid of NX x NY nodes at spacing h, the slave node last; the contact set on it. */
static void face_setup(face_case *f, double h)
{
    memset(f, 0, sizeof *f);
    for (int i = 0; i < NX; i++)
        for (int j = 0; j < NY; j++) {
            const int n = i * NY + j;
            f->top[n] = n;
            f->x[3 * n] = -4 * h + i * h, f->x[3 * n + 1] = -3 * h + j * h, f->x[3 * n + 2] = 0;
        }
    f->mesh.n_nodes = NN, f->mesh.x = f->x, f->mesh.top_s = f->top;
    f->mesh.nxt_s = NX, f->mesh.nyt_s = NY, f->mesh.x0_s = -4 * h, f->mesh.y0_s = -3 * h, f->mesh.h_s = h;
    f->slave = NN - 1;
    f->C.nslave = 1, f->C.slave = &f->slave, f->C.mnode = f->mnode, f->C.N = f->N, f->C.S = f->S;
    f->C.s0 = f->s0, f->C.gvo = f->gvo, f->C.outside = &f->outside, f->C.Xm = f->Xm;
}

/* Start the next location from the slave's reference (X, Y), as the solver does before the first. */
static void face_restart(face_case *f)
{
    f->Xm[0] = f->x[3 * f->slave], f->Xm[1] = f->x[3 * f->slave + 1];
}

/* The affine field u = (ex X + g Y, ey Y, a X + b Y) on the grid, the slave at (xs, ys, zs). */
static void affine(const face_case *f, double *u, const double p[5], const double xs[3])
{
    for (int n = 0; n < NN - 1; n++) {
        const double X = f->x[3 * n], Y = f->x[3 * n + 1];
        u[3 * n] = p[0] * X + p[2] * Y, u[3 * n + 1] = p[1] * Y, u[3 * n + 2] = p[3] * X + p[4] * Y;
    }
    for (int d = 0; d < 3; d++)
        u[3 * (NN - 1) + d] = xs[d] - f->x[3 * (NN - 1) + d];
}

/* The gap of the located pair: the slave's z less the face's at the master point. */
static double located_gap(face_case *f, const double *u, const double *v)
{
    face_restart(f);
    f3_contact_locate(&f->C, &f->mesh, u, v, 1, 1);
    double g = f->x[3 * f->slave + 2] + u[3 * f->slave + 2];
    for (int a = 0; a < F3_NM; a++)
        g -= f->N[a] * (f->x[3 * f->mnode[a] + 2] + u[3 * f->mnode[a] + 2]);
    return g;
}

/* A face stretched 60 % along x and sheared, tilted: located point, slope and gap exact. */
static void test_stretched_face_closed_form(void **state)
{
    (void)state;
    face_case f;
    const double h = 0.1, p[5] = {0.6, -0.2, 0.15, 0.3, -0.25}, xs[3] = {0.031, 0.047, 0.02};
    face_setup(&f, h);
    double u[3 * NN], v[3 * NN] = {0};
    affine(&f, u, p, xs);
    const double g = located_gap(&f, u, v);
    /* x = (1 + ex) X + g Y, y = (1 + ey) Y  =>  the material point and z = a X + b Y there */
    const double Ym = xs[1] / (1 + p[1]), Xm = (xs[0] - p[2] * Ym) / (1 + p[0]);
    const double z = p[3] * Xm + p[4] * Ym;
    const double dzdx = p[3] / (1 + p[0]), dzdy = p[4] / (1 + p[1]) - p[3] * p[2] / ((1 + p[0]) * (1 + p[1]));
    assert_int_equal(f.outside, 0);
    assert_true(fabs(g - (xs[2] - z)) < 1e-13);
    assert_true(fabs(f.S[0] - dzdx) < 1e-12);
    assert_true(fabs(f.S[1] - dzdy) < 1e-12);
    /* the material slope dz/dX = a would be 60 % off: the check is not vacuous */
    assert_true(fabs(f.S[0] - p[3]) > 0.1);
}

/* On a curved, stretched face (quadratic in X, Y) the normal row is the gap's derivative. */
static void test_normal_row_is_gap_derivative(void **state)
{
    (void)state;
    face_case f;
    const double h = 0.1, p[5] = {0.5, 0.3, -0.1, 0.2, 0.1}, xs[3] = {-0.012, 0.061, 0.03};
    face_setup(&f, h);
    double u[3 * NN], v[3 * NN], up[3 * NN], um[3 * NN];
    affine(&f, u, p, xs);
    unsigned long long seed = 12345;
    for (int n = 0; n < NN - 1; n++) { /* a crater-like bowl on top of the affine field */
        const double X = f.x[3 * n], Y = f.x[3 * n + 1];
        u[3 * n + 2] += 1.5 * (X * X + Y * Y);
    }
    for (int d = 0; d < 3 * NN; d++) {
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        v[d] = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
    }
    const double eps = 1e-6;
    for (int d = 0; d < 3 * NN; d++)
        up[d] = u[d] + eps * v[d], um[d] = u[d] - eps * v[d];
    const double dg = (located_gap(&f, up, v) - located_gap(&f, um, v)) / (2 * eps);
    located_gap(&f, u, v);
    double gv[3];
    f3_contact_gv(&f.C, 0, v, gv);
    assert_true(fabs(gv[0] - dg) < 1e-6 * (1 + fabs(dg)));
}

/* The half model's symmetry plane y = 0 (the grid starts on it): the face is even in y, so its slope
   across the plane is 0 there; the Catmull-Rom stencil mirrors the row y = -h onto y = +h (a clamped
   stencil gave (u(h) - u(0)) / 2h). */
static void test_symmetry_plane_slope(void **state)
{
    (void)state;
    face_case f;
    const double h = 0.1;
    face_setup(&f, h);
    for (int n = 0; n < NN - 1; n++)
        f.x[3 * n + 1] += 3 * h; /* rows y = 0 .. 7h */
    f.mesh.y0_s = 0;
    double u[3 * NN] = {0}, v[3 * NN] = {0};
    for (int n = 0; n < NN - 1; n++) {
        const double X = f.x[3 * n], Y = f.x[3 * n + 1];
        u[3 * n + 2] = -0.3 * (X * X + Y * Y);
    }
    f.x[3 * (NN - 1)] = 0.037, f.x[3 * (NN - 1) + 1] = 0, f.x[3 * (NN - 1) + 2] = 0.01;
    located_gap(&f, u, v);
    assert_int_equal(f.outside, 0);
    assert_true(fabs(f.S[1]) < 1e-15);
    assert_true(fabs(f.S[0] - (-0.6 * 0.037)) < 1e-3); /* dz/dx of the bowl, to the face's O(h^2) */
}

/* A crater's wall along the plane of motion, as measured where a ploughing boulder's pair went
   wrong (docs/validation-plastic.md 9e): one quad stretched to 3.3 times its length between
   compressed neighbours, so x(X) along the face is S-shaped, and the slave 0.17 m from its master
   material point.  Plain Newton from the slave's own (X, Y) cycled between the quads and stopped
   7 mm off after its 8 iterations (on this grid it leaves the grid); the located point must put the face under the slave (the
   Catmull-Rom weights interpolate the node positions, so sum N x_m is the face point's x), from a
   cold start and from a warm one on the far side. */
static void test_uneven_stretch_located(void **state)
{
    (void)state;
    face_case f;
    const double h = 0.1094, xs[3] = {0.2473, 0.0512, -0.0818};
    /* x of the node columns i = 0..8 (X = (i - 4) h): the measured -0.028, 0.061, 0.375, 0.476 at i = 4..7 */
    const double xcol[NX] = {-0.36, -0.25, -0.15, -0.08, -0.028, 0.061, 0.375, 0.476, 0.57};
    face_setup(&f, h);
    double u[3 * NN] = {0}, v[3 * NN] = {0};
    for (int n = 0; n < NN - 1; n++) {
        const double X = f.x[3 * n];
        u[3 * n] = xcol[n / NY] - X, u[3 * n + 2] = -0.05 - 0.1 * X * X;
    }
    for (int d = 0; d < 3; d++)
        u[3 * (NN - 1) + d] = xs[d] - f.x[3 * (NN - 1) + d];
    for (int start = 0; start < 2; start++) {
        face_restart(&f);
        if (start) /* warm start from a point beyond the root, in the next quad but one */
            f.Xm[0] = 3.5 * h, f.Xm[1] = -2 * h;
        f3_contact_locate(&f.C, &f.mesh, u, v, 1, 1);
        double x = 0, y = 0;
        for (int a = 0; a < F3_NM; a++)
            x += f.N[a] * (f.x[3 * f.mnode[a]] + u[3 * f.mnode[a]]), y += f.N[a] * f.x[3 * f.mnode[a] + 1];
        assert_int_equal(f.outside, 0);
        assert_true(fabs(x - xs[0]) < 1e-12 && fabs(y - xs[1]) < 1e-12);
        assert_true(fabs(f.Xm[0] - xs[0]) > 0.07); /* the master point is far from the slave's X */
    }
}

/* A folded face (column 5 pushed past column 6: x(X) turns back, det J < 0 between them): the
   point under a slave is not unique there, so the location keeps the slave's previous master
   point (flag 2) and the stencil there, and the gap stays continuous. */
static void test_folded_face_keeps_point(void **state)
{
    (void)state;
    face_case f;
    const double h = 0.1, xs[3] = {0.16, 0.05, 0.02};
    const double xcol[NX] = {-0.4, -0.3, -0.2, -0.1, 0.0, 0.25, 0.12, 0.3, 0.4};
    face_setup(&f, h);
    double u[3 * NN] = {0}, v[3 * NN] = {0};
    for (int n = 0; n < NN - 1; n++)
        u[3 * n] = xcol[n / NY] - f.x[3 * n];
    for (int d = 0; d < 3; d++)
        u[3 * (NN - 1) + d] = xs[d] - f.x[3 * (NN - 1) + d];
    const double P0[2] = {0.15, 0.05}; /* inside the fold: x(X) decreases there */
    f.Xm[0] = P0[0], f.Xm[1] = P0[1];
    f3_contact_locate(&f.C, &f.mesh, u, v, 1, 1);
    assert_int_equal(f.outside, 2);
    assert_true(f.Xm[0] == P0[0] && f.Xm[1] == P0[1]);
    double X = 0, Y = 0; /* the weights are the Catmull-Rom ones at P0 (they reproduce X and Y) */
    for (int a = 0; a < F3_NM; a++)
        X += f.N[a] * f.x[3 * f.mnode[a]], Y += f.N[a] * f.x[3 * f.mnode[a] + 1];
    assert_true(fabs(X - P0[0]) < 1e-12 && fabs(Y - P0[1]) < 1e-12);
}

/* The mass redistribution of one unit-cube element (top face = nodes 4-7 on the contact face):
   kappa lambda_max = 5 lambda_e keeps alpha = 0.2 of the face nodes' mass, gives the rest to the
   node below each (a <-> a + 4 along the vertical edges), conserves the mass and bounds the
   element's eigenvalue by kappa lambda_max; an element already above kappa lambda_max, or a slope
   element without a whole face on it, is left alone. */
static void test_surface_mass_shift(void **state)
{
    (void)state;
    f3_mesh m = {0};
    double x[8 * 3];
    int conn[3 * 8];
    unsigned char face[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (int a = 0; a < 8; a++)
        x[3 * a] = (a == 1 || a == 2 || a == 5 || a == 6), x[3 * a + 1] = (a == 2 || a == 3 || a == 6 || a == 7),
                  x[3 * a + 2] = a >= 4 ? 0 : -1;
    for (int e = 0; e < 3; e++)
        for (int a = 0; a < 8; a++)
            conn[8 * e + a] = a;
    m.n_nodes = 8, m.x = x, m.conn = conn, m.n_elems = 3, m.boulder_elems = 1; /* element 0: the boulder */
    double elm[24], lam[3] = {1, 1, 6};
    for (int k = 0; k < 24; k++)
        elm[k] = 1 + 0.1 * (k % 8);
    const double lam_max = 100, kappa = 0.05, before = elm[8 + 4] + elm[8 + 0];
    assert_int_equal(f3_surface_mass_shift(&m, face, elm, lam, lam_max, kappa), 1); /* element 2: 6 >= kappa lam_max = 5 */
    for (int a = 0; a < 8; a++)
        assert_true(elm[a] == 1 + 0.1 * a && elm[16 + a] == 1 + 0.1 * a); /* boulder and element 2 untouched */
    for (int a = 4; a < 8; a++) {
        assert_true(fabs(elm[8 + a] - 0.2 * (1 + 0.1 * a)) < 1e-15);
        assert_true(fabs(elm[8 + a - 4] - (1 + 0.1 * (a - 4) + 0.8 * (1 + 0.1 * a))) < 1e-15);
    }
    assert_true(fabs(elm[8 + 4] + elm[8 + 0] - before) < 1e-15);
    assert_true(fabs(lam[1] - kappa * lam_max) < 1e-12 && lam[0] == 1 && lam[2] == 6);
}

/* Coulomb friction on a sloped face z = a X (a = 0.5, the wall of a crater), a slave sliding down
   along it into a 1 mm penetration, masters fixed: after the solve the slave's contact force F
   (m du / dt^2), split along the face's unit normal by geometry, is at the cap |F_t| = f F_n and
   opposes the slip, and the gap is closed.  With friction rows along x (the old form) F_t / F_n
   would be f / (1 + a^2 +- f a) = 0.94 or 0.48 for f = 0.8. */
static void test_friction_on_sloped_face(void **state)
{
    (void)state;
    face_case f;
    const double h = 0.1, a = 0.5, fr = 0.8, dt = 1e-5, m = 2.0;
    const double p[5] = {0, 0, 0, a, 0}, xs[3] = {0.02, 0.03, a * 0.02};
    face_setup(&f, h);
    double u[3 * NN], v[3 * NN] = {0}, invm[3 * NN] = {0}, du[3 * NN] = {0};
    double lam[3] = {0}, gap[1], ds[3], A[3], rr[2];
    int cand[1];
    affine(&f, u, p, xs);
    for (int d = 0; d < 3; d++)
        invm[3 * f.slave + d] = 1 / m;
    f.C.lam = lam, f.C.gap = gap, f.C.ds = ds, f.C.A = A, f.C.cand = cand, f.C.du = du, f.C.rr = rr;
    f.C.solve.friction = fr, f.C.solve.tol = 1e-15, f.C.solve.band = h, f.C.solve.max_sweeps = 100;
    face_restart(&f);
    f3_contact_locate(&f.C, &f.mesh, u, v, 1, 1);
    /* the predictor: down the slope (-x along the face, a little across it) and 1 mm into it */
    const double mv[3] = {-0.004, 0.001, -a * 0.004 - 0.001};
    for (int d = 0; d < 3; d++)
        u[3 * f.slave + d] += mv[d];
    double pred[3];
    memcpy(pred, u + 3 * f.slave, sizeof pred);
    f3_contact_predict(&f.C, &f.mesh, u, invm, dt, 1);
    rf_error err = {0};
    assert_int_equal(f3_contact_solve(&f.C, invm, dt, u, v, &err), RF_OK);
    double F[3], n[3] = {-a, 0, 1}, Fn = 0;
    const double nn = sqrt(1 + a * a);
    for (int d = 0; d < 3; d++)
        F[d] = m * (u[3 * f.slave + d] - pred[d]) / (dt * dt), n[d] /= nn, Fn += F[d] * n[d];
    double Ft[3], slip[3], sn = 0, ft = 0, dot = 0, sl = 0;
    for (int d = 0; d < 3; d++)
        sn += mv[d] * n[d];
    for (int d = 0; d < 3; d++)
        Ft[d] = F[d] - Fn * n[d], slip[d] = mv[d] - sn * n[d], ft += Ft[d] * Ft[d], sl += slip[d] * slip[d],
        dot += Ft[d] * slip[d];
    ft = sqrt(ft), sl = sqrt(sl);
    const double z = f.x[3 * f.slave + 2] + u[3 * f.slave + 2], X = f.x[3 * f.slave] + u[3 * f.slave];
    assert_true(Fn > 0);
    assert_true(fabs(z - a * X) < 1e-12);            /* on the face again */
    assert_true(fabs(ft / Fn - fr) < 1e-9);           /* Coulomb's cap on the forces */
    assert_true(dot < -0.999 * ft * sl);              /* against the slip (here along it exactly) */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stretched_face_closed_form),
        cmocka_unit_test(test_normal_row_is_gap_derivative),
        cmocka_unit_test(test_symmetry_plane_slope),
        cmocka_unit_test(test_uneven_stretch_located),
        cmocka_unit_test(test_folded_face_keeps_point),
        cmocka_unit_test(test_surface_mass_shift),
        cmocka_unit_test(test_friction_on_sloped_face),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
