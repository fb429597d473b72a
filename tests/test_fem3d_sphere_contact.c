/* test_fem3d_sphere_contact.c - the 3D contact in sphere mode
 * (rf_fem_options.sphere_contact_3d, src/fem/fem3d_contact.c,
 * docs/validation-plastic.md section 9g): a slope node against a rigid
 * sphere (mass M, I_yy about its centre) on one step of the forward-increment
 * contact.  The references are conservation laws and closed forms, not the
 * code's own rows: after the solve the node lies on the sphere, the linear
 * momentum of node and body and their angular momentum about the body's
 * centre are unchanged by the contact impulse, a frictionless impulse gives
 * the body no spin, a sliding pair's force satisfies |F_t| = f F_n against
 * the slip, and a sticking pair leaves no relative tangential displacement of
 * the node and the sphere's material point under it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "fem/fem3d_internal.h"

enum { NN = 1 };
#define DEG_RAD (3.14159265358979323846 / 180)

typedef struct {
    f3_mesh mesh;
    f3_contact C;
    double x[3], u[3], v[3], invm[3], du[3];
    double lam[3], gap[1], ds[3], s0[3], A[3], gvo[3], rr[2], wr[9];
    int slave, cand[1];
    unsigned char outside;
} sphere_case;

static const double R = 0.5, m = 3.0, M = 400.0, I = 0.4 * 400.0 * 0.25, dt = 1e-5;

/* The node at angle beta from the sphere's lowest point (in x-z), a gap g0 off the sphere centred at
   c = (0.1, R - 0.02) at rest; friction f. */
static void sphere_setup(sphere_case *s, double beta, double g0, double f)
{
    memset(s, 0, sizeof *s);
    const double c[2] = {0.1, R - 0.02};
    s->x[0] = c[0] + (R + g0) * sin(beta), s->x[2] = c[1] - (R + g0) * cos(beta);
    for (int d = 0; d < 3; d++)
        s->invm[d] = 1 / m;
    s->mesh.n_nodes = NN, s->mesh.x = s->x;
    f3_contact *C = &s->C;
    C->nslave = 1, C->slave = &s->slave, C->lam = s->lam, C->gap = s->gap, C->ds = s->ds, C->s0 = s->s0;
    C->A = s->A, C->gvo = s->gvo, C->cand = s->cand, C->du = s->du, C->rr = s->rr, C->wr = s->wr;
    C->outside = &s->outside;
    C->sphere = 1, C->radius = R, C->rigid_invm = 1 / M, C->rigid_invi = 1 / I;
    C->rigid_c[0] = c[0], C->rigid_c[1] = c[1];
    C->solve.friction = f, C->solve.tol = 1e-16, C->solve.band = 0.01, C->solve.max_sweeps = 200;
}

/* One contact step: the predictor moves the node by mv; returns the node's correction in dn and the
   unit normal n and tangent t (in x-z) of the sphere at the predicted node, from the geometry. */
static void sphere_step(sphere_case *s, const double mv[3], double dn[3], double n[3], double t[3])
{
    f3_contact_locate(&s->C, &s->mesh, s->u, s->v, 1, 1);
    for (int d = 0; d < 3; d++)
        s->u[d] += mv[d], s->v[d] += mv[d] / dt;
    double pred[3];
    memcpy(pred, s->u, sizeof pred);
    f3_contact_predict(&s->C, &s->mesh, s->u, s->invm, dt, 1);
    rf_error err = {0};
    assert_int_equal(f3_contact_solve(&s->C, s->invm, dt, s->u, s->v, &err), RF_OK);
    for (int d = 0; d < 3; d++)
        dn[d] = s->u[d] - pred[d];
    const double d[3] = {s->x[0] + pred[0] - s->C.rigid_c[0], s->x[1] + pred[1], s->x[2] + pred[2] - s->C.rigid_c[1]};
    const double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int q = 0; q < 3; q++)
        n[q] = d[q] / r;
    const double l = hypot(n[0], n[2]);
    t[0] = -n[2] / l, t[1] = 0, t[2] = n[0] / l;
}

/* Distance of the node from the corrected sphere centre, less R. */
static double final_gap(const sphere_case *s)
{
    const double *b = s->C.rigid_du;
    const double dx = s->x[0] + s->u[0] - s->C.rigid_c[0] - b[0], dy = s->x[1] + s->u[1];
    const double dz = s->x[2] + s->u[2] - s->C.rigid_c[1] - b[1];
    return sqrt(dx * dx + dy * dy + dz * dz) - R;
}

/* Linear momentum (x, z) and angular momentum about the centre (y) of the contact's impulses:
   m dn / dt for the node (arm r from the centre), M db / dt and I dtheta / dt for the body. */
static void impulse_balance(const sphere_case *s, const double dn[3], double P[2], double *L)
{
    const double *b = s->C.rigid_du, rx = s->x[0] + s->u[0] - dn[0] - s->C.rigid_c[0];
    const double rz = s->x[2] + s->u[2] - dn[2] - s->C.rigid_c[1];
    P[0] = (m * dn[0] + M * b[0]) / dt, P[1] = (m * dn[2] + M * b[1]) / dt;
    *L = (I * b[2] + m * (rz * dn[0] - rx * dn[2])) / dt; /* (r x p)_y = r_z p_x - r_x p_z */
}

/* Frictionless capture on a flank (beta 35 deg): the node ends on the sphere, momentum is conserved,
   and the normal through the centre gives the body no spin. */
static void test_frictionless_capture(void **state)
{
    (void)state;
    sphere_case s;
    const double beta = 35 * DEG_RAD;
    sphere_setup(&s, beta, 1e-4, 0);
    const double mv[3] = {-2e-3 * sin(beta) + 1e-3 * cos(beta), 0, 2e-3 * cos(beta) + 1e-3 * sin(beta)};
    double dn[3], n[3], t[3], P[2], L;
    sphere_step(&s, mv, dn, n, t);
    impulse_balance(&s, dn, P, &L);
    const double Fn = m * sqrt(dn[0] * dn[0] + dn[2] * dn[2]) / (dt * dt);
    assert_true(Fn > 0);
    assert_true(fabs(final_gap(&s)) < 1e-12);
    assert_true(fabs(P[0]) < 1e-9 * m * Fn * dt && fabs(P[1]) < 1e-9 * m * Fn * dt);
    assert_true(fabs(s.C.rigid_du[2]) < 1e-15 && fabs(L) < 1e-9 * Fn * dt * R);
    /* the correction is along the normal at the predicted point: its tangential motion is kept */
    assert_true(fabs(dn[0] * t[0] + dn[2] * t[2]) < 1e-12 * fabs(dn[0] * n[0] + dn[2] * n[2]));
    assert_true(dn[0] * n[0] + dn[2] * n[2] > 0);
}

/* Sliding on a flank (f 0.3, a large slip along the sphere): |F_t| = f F_n against the slip, the node
   on the sphere to the step's second order, linear and angular momentum conserved (the friction
   spins the body). */
static void test_sliding_coulomb(void **state)
{
    (void)state;
    sphere_case s;
    const double beta = -20 * DEG_RAD, f = 0.3;
    sphere_setup(&s, beta, 0, f);
    const double n0[3] = {sin(beta), 0, -cos(beta)}, t0[3] = {cos(beta), 0, sin(beta)};
    double mv[3], dn[3], n[3], t[3], P[2], L;
    for (int d = 0; d < 3; d++)
        mv[d] = 4e-3 * t0[d] - 5e-4 * n0[d];
    sphere_step(&s, mv, dn, n, t);
    impulse_balance(&s, dn, P, &L);
    double Fn = 0, Ft = 0;
    for (int d = 0; d < 3; d++)
        Fn += m * dn[d] / (dt * dt) * n[d], Ft += m * dn[d] / (dt * dt) * t[d];
    const double scale = m * fabs(Fn) * dt;
    assert_true(Fn > 0 && Ft < 0);           /* pushes out, against the slip */
    assert_true(fabs(-Ft / Fn - f) < 1e-9);  /* Coulomb, at the predicted point */
    /* on the sphere to second order: a correction dn along the tangent lifts the node by dn^2 / 2R */
    const double dn2 = dn[0] * dn[0] + dn[1] * dn[1] + dn[2] * dn[2];
    assert_true(fabs(final_gap(&s)) < dn2 / R);
    assert_true(fabs(P[0]) < 1e-9 * scale && fabs(P[1]) < 1e-9 * scale);
    assert_true(fabs(L) < 1e-9 * scale * R);
    assert_true(s.C.rigid_du[2] != 0);
}

/* Sticking (f 1, a small slip, the body moving in the step): the node's step, less the step of the
   sphere's material point under it, has no tangential part after the solve. */
static void test_stick_follows_body(void **state)
{
    (void)state;
    sphere_case s;
    const double beta = 10 * DEG_RAD;
    sphere_setup(&s, beta, 0, 1.0);
    s.C.body_d[0] = 2e-4, s.C.body_d[1] = -1e-4, s.C.body_d[2] = 3e-4; /* the rigid predictor's step */
    s.C.rigid_c[0] += s.C.body_d[0], s.C.rigid_c[1] += s.C.body_d[1];
    const double n0[3] = {sin(beta), 0, -cos(beta)}, t0[3] = {cos(beta), 0, sin(beta)};
    double mv[3], dn[3], n[3], t[3];
    for (int d = 0; d < 3; d++) /* into the sphere, along it and across the plane of motion */
        mv[d] = 1e-4 * t0[d] - 2e-4 * n0[d] + (d == 1 ? 1e-4 : 0);
    sphere_step(&s, mv, dn, n, t);
    /* the body's total step: predictor + correction; its material point at the node's arm */
    const double bx = s.C.body_d[0] + s.C.rigid_du[0], bz = s.C.body_d[1] + s.C.rigid_du[1];
    const double th = s.C.body_d[2] + s.C.rigid_du[2], rx = s.C.rr[0], rz = s.C.rr[1];
    const double bp[3] = {bx + th * rz, 0, bz - th * rx};
    double rel[3], wt[3] = {0, 0, 0};
    for (int d = 0; d < 3; d++)
        rel[d] = s.u[d] - bp[d];
    for (int c = 1; c < 3; c++)
        for (int d = 0; d < 3; d++)
            wt[c] += s.C.wr[3 * c + d] * rel[d];
    assert_true(s.lam[0] > 0);
    assert_true(fabs(wt[1]) < 1e-12 && fabs(wt[2]) < 1e-12);
    assert_true(hypot(s.lam[1], s.lam[2]) < s.lam[0]); /* inside the cone */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frictionless_capture),
        cmocka_unit_test(test_sliding_coulomb),
        cmocka_unit_test(test_stick_follows_body),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
