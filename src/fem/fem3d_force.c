/* fem3d_force.c - the internal force of the 3D model through the material
 * kernels (fem_kernel.h: element-vector or nodal-field kernels), with the
 * boulder's elastic part taken in its co-rotational frame (a rigid rotation
 * costs no strain energy), the deterministic node-ordered assembly, and the boulder's strain energy. */
#include "fem3d_internal.h"

#include <math.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* Boulder CM c and rotation angle theta about y (the axis normal to the plane of motion; the
   motion is planar by symmetry): theta = atan2(A_xz - A_zx, A_xx + A_zz) with
   A = sum m (x - c)(X - c0)^T, the rotation that best fits the displaced nodes. */
static void boulder_frame(f3_system *S, const double *u)
{
    const double *X = S->mesh->x;
    double c[3] = {0, 0, 0}, A[9] = {0};
    for (long i = 0; i < S->nbn; i++)
        for (int q = 0; q < 3; q++)
            c[q] += S->mass[3 * i] * (X[3 * i + q] + u[3 * i + q]);
    for (int q = 0; q < 3; q++)
        c[q] /= S->Mb;
    if (!S->full)
        c[1] = 0;
    for (long i = 0; i < S->nbn; i++) {
        double m = S->mass[3 * i];
        for (int a = 0; a < 3; a += 2)
            for (int b = 0; b < 3; b += 2)
                A[3 * a + b] += m * (X[3 * i + a] + u[3 * i + a] - c[a]) * (X[3 * i + b] - S->c0[b]);
    }
    S->p = A[2] - A[6], S->q = A[0] + A[8];
    double th = atan2(S->p, S->q), ct = cos(th), st = sin(th);
    const double R[9] = {ct, 0, st, 0, 1, 0, -st, 0, ct};
    memcpy(S->R, R, sizeof R);
    memcpy(S->c, c, sizeof c);
}

/* Element forces by kernels on element vectors (forces()): u_el formed per element-node. */
static void element_vector_forces(f3_system *S, const double *u)
{
    const int *conn = S->mesh->conn;
    const double *X = S->mesh->x, *R = S->R, *c = S->c, *c0 = S->c0;
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
    for (long e = 0; e < S->ne; e++) {
        const int *cn = conn + 8 * e;
        double uel[24];
        if (e < S->mesh->boulder_elems) { /* elastic part in the boulder's frame */
            for (int a = 0; a < 8; a++) {
                const long i = cn[a];
                const double r[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1],
                                     X[3 * i + 2] + u[3 * i + 2] - c[2]};
                for (int q = 0; q < 3; q++)
                    uel[3 * a + q] = R[q] * r[0] + R[3 + q] * r[1] + R[6 + q] * r[2] - (X[3 * i + q] - c0[q]);
            }
        } else {
            for (int a = 0; a < 8; a++) {
                uel[3 * a] = u[3 * cn[a]];
                uel[3 * a + 1] = u[3 * cn[a] + 1];
                uel[3 * a + 2] = u[3 * cn[a] + 2];
            }
        }
        const fem_kernel *k = &S->kernel[e >= S->mesh->boulder_elems];
        k->ops->forces(k, e, e + 1, uel, S->fe + 24 * e); /* one element per call: 576 multiply-adds each */
    }
}

/* Element forces by kernels on the nodal field (forces_field()): the boulder's field in its
   frame once per node, u_b = R^T (x - c) - (X - c0), then the work units of both bodies as one
   list split evenly over the threads (each element from one unit: the same bits for any split). */
static void field_forces(f3_system *S, const double *u)
{
    const double *X = S->mesh->x, *R = S->R, *c = S->c, *c0 = S->c0;
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
    for (long i = 0; i < S->nbn; i++) {
        const double r[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1],
                             X[3 * i + 2] + u[3 * i + 2] - c[2]};
        for (int q = 0; q < 3; q++)
            S->ub[3 * i + q] = R[q] * r[0] + R[3 + q] * r[1] + R[6 + q] * r[2] - (X[3 * i + q] - c0[q]);
    }
    const fem_kernel *kb = &S->kernel[F3_BOULDER], *ks = &S->kernel[F3_SLOPE];
    const long nb = kb->units, nw = nb + ks->units;
    long tid = 0, T = 1;
#ifdef _OPENMP
    tid = omp_get_thread_num(), T = omp_get_num_threads();
#endif
    const long w0 = nw * tid / T, w1 = nw * (tid + 1) / T;
    if (w0 < nb)
        kb->ops->forces_field(kb, w0, w1 < nb ? w1 : nb, S->ub, S->fe);
    if (w1 > nb)
        ks->ops->forces_field(ks, w0 > nb ? w0 - nb : 0, w1 - nb, u, S->fe);
#ifdef _OPENMP
#pragma omp barrier
#endif
}

/* f = f_int(u) through the material kernels (fem_kernel.h): for the slope
   the element displacements are u; for the boulder f = dE/dx with E = 1/2 u_el' K u_el,
   u_el = R^T (x - c) - (X - c0): R K u_el plus the term through theta(x), which makes the force
   the exact gradient (co-rotational: a finite rigid rotation of the boulder costs no strain
   energy, whereas with linear small strain a spinning sphere inflates by r theta^2 / 2 and
   pushes on the slope).  Element forces, then a node-ordered gather (no races, the same sums for
   any thread count); the one torque sum runs serially. */
void f3_internal_force(f3_system *S, const double *u, double *f)
{
    const double *X = S->mesh->x;
    const long nn = S->nn, nbn = S->nbn;
    boulder_frame(S, u);
    const double *R = S->R, *c = S->c, *c0 = S->c0;
    const int field = S->kernel[F3_BOULDER].ops->forces_field && S->kernel[F3_SLOPE].ops->forces_field;
#ifdef _OPENMP
#pragma omp parallel num_threads(S->threads) if (S->threads > 1)
#endif
    {
        if (field)
            field_forces(S, u);
        else
            element_vector_forces(S, u);
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
        for (long n = 0; n < nn; n++) {
            double fx = 0, fy = 0, fz = 0;
            for (long p = S->inc_ptr[n]; p < S->inc_ptr[n + 1]; p++) {
                const double *fp = S->fe + 24 * (S->inc[p] >> 3) + 3 * (S->inc[p] & 7);
                fx += fp[0], fy += fp[1], fz += fp[2];
            }
            if (n < nbn) {
                S->fel[3 * n] = fx, S->fel[3 * n + 1] = fy, S->fel[3 * n + 2] = fz;
                f[3 * n] = R[0] * fx + R[1] * fy + R[2] * fz;
                f[3 * n + 1] = R[3] * fx + R[4] * fy + R[5] * fz;
                f[3 * n + 2] = R[6] * fx + R[7] * fy + R[8] * fz;
            } else
                f[3 * n] = fx, f[3 * n + 1] = fy, f[3 * n + 2] = fz;
        }
    }
    /* dE/dtheta = -(sum r x f_el)_y, r = X - c0 + u_el; dtheta/dx_i from atan2(p, q) */
    double T = 0;
    for (long i = 0; i < nbn; i++) {
        const double *fe = S->fel + 3 * i;
        /* r = R^T (x - c) = X - c0 + u_el */
        const double d[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1],
                             X[3 * i + 2] + u[3 * i + 2] - c[2]};
        const double rx = R[0] * d[0] + R[3] * d[1] + R[6] * d[2], rz = R[2] * d[0] + R[5] * d[1] + R[8] * d[2];
        T += rz * fe[0] - rx * fe[2];
    }
    const double dEdth = -T, pq = S->p * S->p + S->q * S->q;
    for (long i = 0; i < nbn; i++) {
        double m = S->mass[3 * i], dx = X[3 * i] - c0[0], dz = X[3 * i + 2] - c0[2];
        f[3 * i] += dEdth * m * (S->q * dz - S->p * dx) / pq;
        f[3 * i + 2] += dEdth * m * (-S->q * dx - S->p * dz) / pq;
    }
}

/* Strain energy of the boulder, 1/2 f_el(n)' u_el(n+1) with u_el(n+1) in the frame of step n
   (the shadow energy 1/2 u_n' K u_{n+1} of the linear case when the rotation is constant). */
double f3_boulder_strain(const f3_system *S, const double *u)
{
    const double *X = S->mesh->x, *R = S->R, *c0 = S->c0;
    double c[3] = {0, 0, 0};
    for (long i = 0; i < S->nbn; i++)
        for (int q = 0; q < 3; q++)
            c[q] += S->mass[3 * i] * (X[3 * i + q] + u[3 * i + q]);
    for (int q = 0; q < 3; q++)
        c[q] /= S->Mb;
    if (!S->full)
        c[1] = 0;
    double e = 0;
    for (long i = 0; i < S->nbn; i++) {
        double r[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1], X[3 * i + 2] + u[3 * i + 2] - c[2]};
        for (int a = 0; a < 3; a++)
            e += S->fel[3 * i + a] * (R[a] * r[0] + R[3 + a] * r[1] + R[6 + a] * r[2] - (X[3 * i + a] - c0[a]));
    }
    return 0.5 * e;
}
