/* test_fem_contact_friction.c - Coulomb friction of the axisymmetric contact
 * (src/fem/fem_contact_friction.c) on hand-built pairs, one step against
 * closed forms and conservation laws: a sticking pair ends without relative
 * tangential velocity and conserves the radial momentum; a sliding pair
 * carries exactly mu times the normal force, against the slip, and
 * dissipates; a rigid boulder on an inclined segment sticks or slips and
 * takes the vertical impulse of both forces, the vertical momentum of boulder
 * and soil conserved. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem/fem_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { NN = 3, NDOF = 2 * NN };

/* One pair: slave node 0 over the segment of nodes 1 and 2 at xi; storage on the caller's stack. */
typedef struct {
    fem_contact C;
    contact_pair pair[1];
    double gpred[1], lambda[1], A[1], rhs[1], du[NDOF], gvo[1];
    int active[1], cand[1];
} one_pair;

static void one_pair_init(one_pair *P, double xi, const double n[2], int large, double mu)
{
    memset(P, 0, sizeof *P);
    contact_pair *p = P->pair;
    p->xi = xi, p->n[0] = n[0], p->n[1] = n[1], p->r = 0.1;
    const int z[3] = {1, 3, 5}, r[3] = {0, 2, 4};
    for (int k = 0; k < 3; k++)
        p->dof[k] = z[k], p->rdof[k] = r[k], p->dof[3 + k] = r[k];
    const double w[3] = {1, -(1 - xi), -xi};
    for (int k = 0; k < 3; k++)
        p->c[k] = w[k] * n[1], p->c[3 + k] = w[k] * n[0];
    fem_contact *C = &P->C;
    C->npairs = 1, C->pair = P->pair, C->gpred = P->gpred, C->lambda = P->lambda, C->active = P->active;
    C->cand = P->cand, C->A = P->A, C->rhs = P->rhs, C->du = P->du, C->gvo = P->gvo;
    C->tol = 1e-15, C->band = 1, C->nq = large ? 6 : 3, C->block_rounds = FEM_CONTACT_BLOCK_ROUNDS;
    rf_error err = {0};
    assert_int_equal(fem_contact_friction_setup(C, NDOF, mu, &err), RF_OK);
}

static void one_pair_free(one_pair *P)
{
    free(P->C.lam_t), free(P->C.vt_old);
}

static void step(one_pair *P, const double *invm, double dt, double *u, double *v)
{
    double Fc;
    rf_error err = {0};
    fem_contact_begin(&P->C, v);
    if (fem_contact_step(&P->C, invm, dt, u, v, &Fc, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

/* Small strain (vertical gap, radial tangent), an elastic boulder node sliding
 * radially at V over two slope nodes at rest, pressed in by delta. */
static void sliding_node(double mu, double *lam_n, double *lam_t, double *s0, double *s1, double *a, double *wf,
                         double *p_r0, double *p_r1)
{
    const double xi = 0.3, ms = 2, m1 = 3, m2 = 5, dt = 1e-4, delta = 1e-6, V = 1e-3;
    const double n[2] = {0, 1}, mass[NN] = {ms, m1, m2};
    double invm[NDOF], u[NDOF] = {0}, v[NDOF] = {0};
    for (int d = 0; d < NDOF; d++)
        invm[d] = 1 / mass[d / 2];
    u[1] = -delta, v[1] = -delta / dt, v[0] = V;
    one_pair P;
    one_pair_init(&P, xi, n, 0, mu);
    *s0 = v[0] - (1 - xi) * v[2] - xi * v[4];
    *p_r0 = ms * v[0] + m1 * v[2] + m2 * v[4];
    step(&P, invm, dt, u, v);
    assert_true(fabs(u[1] - (1 - xi) * u[3] - xi * u[5]) < 1e-12 * delta); /* the gap closed */
    *s1 = v[0] - (1 - xi) * v[2] - xi * v[4];
    *p_r1 = ms * v[0] + m1 * v[2] + m2 * v[4];
    *lam_n = P.C.lambda[0], *lam_t = P.C.lam_t[0], *wf = P.C.W_fric;
    *a = 1 / ms + (1 - xi) * (1 - xi) / m1 + xi * xi / m2;
    one_pair_free(&P);
}

static void test_stick(void **state)
{
    (void)state;
    double ln, lt, s0, s1, a, wf, p0, p1;
    sliding_node(10, &ln, &lt, &s0, &s1, &a, &wf, &p0, &p1);
    const double dt = 1e-4;
    printf("stick: lambda_n %.6g N, lambda_t %.6g N (closed form %.6g), slip rate %.3g -> %.3g m/s, radial momentum "
           "%.12g -> %.12g\n", ln, lt, -s0 / (dt * a), s0, s1, p0, p1);
    assert_true(ln > 0 && fabs(lt) < 10 * ln);
    assert_true(fabs(s1) < 1e-12 * fabs(s0));
    assert_true(fabs(lt + s0 / (dt * a)) < 1e-12 * fabs(lt));
    assert_true(fabs(p1 - p0) < 1e-12 * fabs(p0));
    assert_true(wf > 0); /* stopping the slip dissipates: lam_t s_old dt / 2 */
}

static void test_slip(void **state)
{
    (void)state;
    const double mu = 0.05, dt = 1e-4;
    double ln, lt, s0, s1, a, wf, p0, p1;
    sliding_node(mu, &ln, &lt, &s0, &s1, &a, &wf, &p0, &p1);
    printf("slip: lambda_t / lambda_n %.15g, slip rate %.6g -> %.6g m/s (closed form %.6g), friction work %.6g J\n",
           lt / ln, s0, s1, s0 - dt * a * mu * ln, wf);
    assert_true(fabs(lt + mu * ln) < 1e-14 * mu * ln); /* at the bound, against the slip (s0 > 0) */
    assert_true(s1 > 0 && fabs(s1 - (s0 - dt * a * mu * ln)) < 1e-12 * s0);
    assert_true(fabs(p1 - p0) < 1e-12 * fabs(p0));
    assert_true(fabs(wf - mu * ln * (s0 + s1) * dt / 2) < 1e-12 * wf);
}

/* A rigid boulder (one node, mass Mb) moving down at V onto an inclined
 * segment (n = (-sin theta, cos theta)) of two free soil nodes at rest,
 * large-deformation rows: the friction row's vertical component acts on the
 * boulder.  With enough friction the relative tangential velocity ends at
 * zero (stick); with less the force is mu lambda_n against the slip.  Either
 * way the contact conserves the vertical momentum of boulder and soil. */
static void rigid_on_wall(double mu, double theta, int stick)
{
    const double Mb = 4, m = 3, dt = 1e-4, V = 1e-3, delta = 1e-6, xi = 0.4;
    const double n[2] = {-sin(theta), cos(theta)}, tz = -n[0], tr = n[1];
    double invm[NDOF] = {1 / Mb, 1 / Mb, 1 / m, 1 / m, 1 / m, 1 / m}, u[NDOF] = {0}, v[NDOF] = {0};
    v[1] = -V, u[1] = -delta / n[1];
    one_pair P;
    one_pair_init(&P, xi, n, 1, mu);
    P.C.rigid_invm = 1 / Mb, P.C.rigid_dofs = 2;
    const double s0 = tz * v[1], pz0 = Mb * v[1];
    step(&P, invm, dt, u, v);
    const double ln = P.C.lambda[0], lt = P.C.lam_t[0];
    const double s1 = tz * v[1] - (1 - xi) * (tz * v[3] + tr * v[2]) - xi * (tz * v[5] + tr * v[4]);
    const double pz1 = Mb * v[1] + m * (v[3] + v[5]);
    printf("rigid boulder on a segment at %.1f deg, mu %g: slip rate %.6g -> %.3g m/s, lambda_t / lambda_n %.6g, "
           "vertical momentum %.12g -> %.12g\n", theta * 180 / M_PI, mu, s0, s1, lt / ln, pz0, pz1);
    assert_true(ln > 0);
    assert_true(fabs(pz1 - pz0) < 1e-12 * fabs(pz0));
    assert_true(fabs(Mb * (v[1] + V) - dt * (n[1] * ln + tz * lt)) < 1e-12 * Mb * V);
    if (stick) {
        assert_true(fabs(s1) < 1e-12 * fabs(s0));
        assert_true(fabs(lt) < mu * ln);
    } else {
        assert_true(lt * s1 < 0 && P.C.W_fric > 0); /* the force opposes the slip that is left, and dissipates */
        assert_true(fabs(fabs(lt) - mu * ln) < 1e-14 * mu * ln);
    }
    one_pair_free(&P);
}

static void test_rigid_on_wall(void **state)
{
    (void)state;
    rigid_on_wall(2.0, M_PI / 4, 1);
    rigid_on_wall(0.02, M_PI / 4, 0);
    rigid_on_wall(1.0, M_PI / 8, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stick),
        cmocka_unit_test(test_slip),
        cmocka_unit_test(test_rigid_on_wall),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
