/* fem3d_force.c - the internal force of the 3D model through the material
 * kernels (fem_kernel.h: element-vector or nodal-field kernels), with the
 * boulder's elastic part taken in its co-rotational frame (a rigid rotation
 * costs no strain energy), the deterministic node-ordered assembly, and the
 * sums of the energy account (the boulder's strain energy among them).  One
 * parallel region per call; every sum over nodes in fixed chunks, so the bits
 * do not depend on the thread count (docs/fem-speed.md, "Threads"). */
#include "fem3d_internal.h"
#include "fem3d_prof.h"

#include <math.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* Sums over nodes run in F3_CHUNKS fixed chunks of a node range, each summed in node order,
   then the chunk sums in chunk order: the same bits for any thread count, and the threads share
   the chunks.  A chunk's partial sums take PART doubles (two cache lines: no false sharing). */
enum { CHUNKS = F3_CHUNKS, PART = 16 };

static long chunk_begin(long n, int k)
{
    return f3_chunk_begin(n, k);
}

/* The boulder's frame: CM c, rotation R about y and the atan2 arguments p, q. */
typedef struct {
    double R[9], c[3], p, q;
} boulder_frame;

/* Chunk k of the frame sums over the boulder nodes: sum m x (3), sum m (x - c0)_a (X - c0)_b
   for a, b in {x, z} (4) and sum m (X - c0)_b (2), x = X + u. */
static void frame_partials(const f3_system *S, const double *u, double (*part)[PART])
{
    const double *X = S->mesh->x, *c0 = S->c0;
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
    for (int k = 0; k < CHUNKS; k++) {
        double s[9] = {0};
        for (long i = chunk_begin(S->nbn, k); i < chunk_begin(S->nbn, k + 1); i++) {
            const double m = S->mass[3 * i];
            double x[3], d[3], D[3];
            for (int q = 0; q < 3; q++) {
                x[q] = X[3 * i + q] + u[3 * i + q];
                s[q] += m * x[q];
                d[q] = x[q] - c0[q], D[q] = X[3 * i + q] - c0[q];
            }
            s[3] += m * d[0] * D[0], s[4] += m * d[0] * D[2], s[5] += m * d[2] * D[0], s[6] += m * d[2] * D[2];
            s[7] += m * D[0], s[8] += m * D[2];
        }
        memcpy(part[k], s, sizeof s);
    }
}

/* Boulder CM c and rotation angle theta about y (the axis normal to the plane of motion; the
   motion is planar by symmetry): theta = atan2(A_xz - A_zx, A_xx + A_zz) with
   A = sum m (x - c)(X - c0)^T = sum m (x - c0)(X - c0)^T - (c - c0) sum m (X - c0)^T, the
   rotation that best fits the displaced nodes.  Every thread combines the same partials in the
   same order (the same bits in each). */
static void frame_combine(const f3_system *S, double (*part)[PART], boulder_frame *F)
{
    double s[9] = {0};
    for (int k = 0; k < CHUNKS; k++)
        for (int j = 0; j < 9; j++)
            s[j] += part[k][j];
    const double *c0 = S->c0;
    double *c = F->c;
    for (int q = 0; q < 3; q++)
        c[q] = s[q] / S->Mb;
    if (!S->full)
        c[1] = 0;
    const double Axx = s[3] - (c[0] - c0[0]) * s[7], Axz = s[4] - (c[0] - c0[0]) * s[8];
    const double Azx = s[5] - (c[2] - c0[2]) * s[7], Azz = s[6] - (c[2] - c0[2]) * s[8];
    F->p = Axz - Azx, F->q = Axx + Azz;
    const double th = atan2(F->p, F->q), ct = cos(th), st = sin(th);
    const double R[9] = {ct, 0, st, 0, 1, 0, -st, 0, ct};
    memcpy(F->R, R, sizeof R);
}

/* Element forces by kernels on element vectors (forces()): u_el formed per element-node. */
static void element_vector_forces(f3_system *S, const double *u, const boulder_frame *F)
{
    const int *conn = S->mesh->conn;
    const double *X = S->mesh->x, *R = F->R, *c = F->c, *c0 = S->c0;
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
static void field_forces(f3_system *S, const double *u, const boulder_frame *F)
{
    const double *X = S->mesh->x, *R = F->R, *c = F->c, *c0 = S->c0;
    F3P_MARK(m);
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
    for (long i = 0; i < S->nbn; i++) {
        const double r[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1],
                             X[3 * i + 2] + u[3 * i + 2] - c[2]};
        for (int q = 0; q < 3; q++)
            S->ub[3 * i + q] = R[q] * r[0] + R[3 + q] * r[1] + R[6 + q] * r[2] - (X[3 * i + q] - c0[q]);
    }
    F3P_LAP(F3P_UB, m);
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
    F3P_LAP(F3P_KERNEL, m);
#ifdef _OPENMP
#pragma omp barrier
#endif
    F3P_LAP(F3P_KWAIT, m);
}

/* Node n's element forces, summed in element order. */
static inline void node_force(const f3_system *S, long n, double g[3])
{
    double fx = 0, fy = 0, fz = 0;
    for (long p = S->inc_ptr[n]; p < S->inc_ptr[n + 1]; p++) {
        const double *fp = S->fe + 24 * (S->inc[p] >> 3) + 3 * (S->inc[p] & 7);
        fx += fp[0], fy += fp[1], fz += fp[2];
    }
    g[0] = fx, g[1] = fy, g[2] = fz;
}

/* The node-ordered gather into f: a boulder node's sum is its force in the frame (fel) turned
   back by R, and chunk k of the boulder nodes sums the torque (sum r x f_el)_y, r = R^T (x - c)
   = X - c0 + u_el, into part[k][9]. */
static void gather(f3_system *S, const double *u, double *f, const boulder_frame *F, double (*part)[PART])
{
    const double *X = S->mesh->x, *R = F->R, *c = F->c;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < CHUNKS; k++) {
        double T = 0;
        for (long n = chunk_begin(S->nbn, k); n < chunk_begin(S->nbn, k + 1); n++) {
            double g[3];
            node_force(S, n, g);
            S->fel[3 * n] = g[0], S->fel[3 * n + 1] = g[1], S->fel[3 * n + 2] = g[2];
            f[3 * n] = R[0] * g[0] + R[1] * g[1] + R[2] * g[2];
            f[3 * n + 1] = R[3] * g[0] + R[4] * g[1] + R[5] * g[2];
            f[3 * n + 2] = R[6] * g[0] + R[7] * g[1] + R[8] * g[2];
            const double d[3] = {X[3 * n] + u[3 * n] - c[0], X[3 * n + 1] + u[3 * n + 1] - c[1],
                                 X[3 * n + 2] + u[3 * n + 2] - c[2]};
            const double rx = R[0] * d[0] + R[3] * d[1] + R[6] * d[2], rz = R[2] * d[0] + R[5] * d[1] + R[8] * d[2];
            T += rz * g[0] - rx * g[2];
        }
        part[k][9] = T;
    }
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
    for (long n = S->nbn; n < S->nn; n++)
        node_force(S, n, f + 3 * n);
}

/* The term through theta(x): dE/dtheta = -(sum r x f_el)_y, dtheta/dx_i from atan2(p, q).  After
   the gather's barrier; every thread sums the torque chunks in the same order.  The loop's form
   (static over the F3_CHUNKS chunks of [0, nbn), nowait) is part of f3_force_hooks's contract. */
static void torque_term(const f3_system *S, double *f, const boulder_frame *F, double (*part)[PART])
{
    const double *X = S->mesh->x, *c0 = S->c0;
    double T = 0;
    for (int k = 0; k < CHUNKS; k++)
        T += part[k][9];
    const double dEdth = -T, pq = F->p * F->p + F->q * F->q;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < CHUNKS; k++)
        for (long i = chunk_begin(S->nbn, k); i < chunk_begin(S->nbn, k + 1); i++) {
            double m = S->mass[3 * i], dx = X[3 * i] - c0[0], dz = X[3 * i + 2] - c0[2];
            f[3 * i] += dEdth * m * (F->q * dz - F->p * dx) / pq;
            f[3 * i + 2] += dEdth * m * (-F->q * dx - F->p * dz) / pq;
        }
}

/* f = f_int(u) through the material kernels (fem_kernel.h): for the slope
   the element displacements are u; for the boulder f = dE/dx with E = 1/2 u_el' K u_el,
   u_el = R^T (x - c) - (X - c0): R K u_el plus the term through theta(x), which makes the force
   the exact gradient (co-rotational: a finite rigid rotation of the boulder costs no strain
   energy, whereas with linear small strain a spinning sphere inflates by r theta^2 / 2 and
   pushes on the slope).  One parallel region: frame sums, element forces, node-ordered gather
   with the torque sums, torque term; every sum in a fixed order (no races, the same bits for
   any thread count).  The hooks share the region (fewer thread meetings per step). */
void f3_internal_force(f3_system *S, const double *u, double *f)
{
    f3_internal_force_hooked(S, u, f, NULL);
}

void f3_internal_force_hooked(f3_system *S, const double *u, double *f, const f3_force_hooks *hooks)
{
    const int field = S->kernel[F3_BOULDER].ops->forces_field && S->kernel[F3_SLOPE].ops->forces_field;
    _Alignas(64) double part[CHUNKS][PART];
    boulder_frame F0;
    F3P_MARK(m0);
#ifdef _OPENMP
#pragma omp parallel num_threads(S->threads) if (S->threads > 1)
#endif
    {
#ifdef _OPENMP
        if (omp_get_thread_num() == 0)
#endif
            F3P_LAP(F3P_FORK, m0);
        if (hooks && hooks->first)
            hooks->first(hooks->ctx);
        F3P_MARK(m);
        boulder_frame F;
        frame_partials(S, u, part);
        frame_combine(S, part, &F);
        F3P_LAP(F3P_FRAME, m);
        if (field)
            field_forces(S, u, &F);
        else
            element_vector_forces(S, u, &F);
        F3P_MARK(mg);
        gather(S, u, f, &F, part);
        F3P_LAP(F3P_GATHER, mg);
        torque_term(S, f, &F, part);
        F3P_LAP(F3P_TORQUE, mg);
        if (hooks && hooks->last) /* (no barrier: see f3_force_hooks) */
            hooks->last(hooks->ctx);
#ifdef _OPENMP
        if (omp_get_thread_num() == 0)
#endif
        {
            F0 = F;
            F3P_SET(m0, f3p_now());
        }
    }
    F3P_LAP(F3P_JOIN, m0);
    memcpy(S->R, F0.R, sizeof F0.R);
    memcpy(S->c, F0.c, sizeof F0.c);
    S->p = F0.p, S->q = F0.q;
}

/* Chunk k of the boulder's strain sums, x = X + u, r = R^T (x - c0) - (X - c0) in the frame R
   of the last f3_internal_force: sum m x into part[k][0..2], sum f_el into [3..5] and
   sum f_el . r into [10].  With c the CM, f_el . (R^T (x - c) - (X - c0)) summed over the nodes
   is sum f_el . r - (sum f_el) . R^T (c - c0): one pass, no wait for c. */
static void strain_partials(const f3_system *S, const double *u, double (*part)[PART])
{
    const double *X = S->mesh->x, *R = S->R, *c0 = S->c0;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < CHUNKS; k++) {
        double s[6] = {0, 0, 0, 0, 0, 0}, e = 0;
        for (long i = chunk_begin(S->nbn, k); i < chunk_begin(S->nbn, k + 1); i++) {
            double d[3];
            for (int q = 0; q < 3; q++) {
                const double x = X[3 * i + q] + u[3 * i + q];
                s[q] += S->mass[3 * i] * x;
                s[3 + q] += S->fel[3 * i + q];
                d[q] = x - c0[q];
            }
            for (int a = 0; a < 3; a++)
                e += S->fel[3 * i + a] * (R[a] * d[0] + R[3 + a] * d[1] + R[6 + a] * d[2] - (X[3 * i + a] - c0[a]));
        }
        memcpy(part[k], s, sizeof s);
        part[k][10] = e;
    }
}

/* The boulder's strain energy 1/2 f_el . (R^T (x - c) - (X - c0)) from the chunks of strain_partials. */
static double strain_combine(const f3_system *S, double (*part)[PART])
{
    double s[6] = {0, 0, 0, 0, 0, 0}, e = 0, c[3];
    for (int k = 0; k < CHUNKS; k++) {
        for (int j = 0; j < 6; j++)
            s[j] += part[k][j];
        e += part[k][10];
    }
    for (int q = 0; q < 3; q++)
        c[q] = s[q] / S->Mb - S->c0[q];
    if (!S->full)
        c[1] = 0;
    const double *R = S->R;
    for (int a = 0; a < 3; a++)
        e -= s[3 + a] * (R[a] * c[0] + R[3 + a] * c[1] + R[6 + a] * c[2]);
    return 0.5 * e;
}

/* Chunk k of the energy sums: boulder chunks (k < CHUNKS) sum m v^2, m v_z and m u_z into
   part[k][11..13], slope chunks sum m v^2 and f . u into part[k - CHUNKS][14..15]. */
static void state_partials(const f3_system *S, const double *u, const double *v, const double *f,
                           double (*part)[PART])
{
    const double *m = S->mass;
    const long nb = S->nbn, ns = S->nn - nb;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < 2 * CHUNKS; k++) {
        double s[3] = {0, 0, 0};
        if (k < CHUNKS) {
            const long d0 = 3 * chunk_begin(nb, k), d1 = 3 * chunk_begin(nb, k + 1);
            for (long dd = d0; dd < d1; dd++)
                s[0] += m[dd] * v[dd] * v[dd];
            for (long dd = d0 + 2; dd < d1; dd += 3)
                s[1] += m[dd] * v[dd], s[2] += m[dd] * u[dd];
            part[k][11] = s[0], part[k][12] = s[1], part[k][13] = s[2];
        } else {
            const long d0 = 3 * (nb + chunk_begin(ns, k - CHUNKS)), d1 = 3 * (nb + chunk_begin(ns, k - CHUNKS + 1));
            for (long dd = d0; dd < d1; dd++)
                s[0] += m[dd] * v[dd] * v[dd], s[1] += f[dd] * u[dd];
            part[k - CHUNKS][14] = s[0], part[k - CHUNKS][15] = s[1];
        }
    }
}

double f3_boulder_strain(const f3_system *S, const double *u)
{
    f3_state_sums s;
    f3_state_sums_compute(S, u, NULL, NULL, &s);
    return s.boulder_strain;
}

void f3_state_sums_compute(const f3_system *S, const double *u, const double *v, const double *f, f3_state_sums *out)
{
    _Alignas(64) double part[CHUNKS][PART];
#ifdef _OPENMP
#pragma omp parallel num_threads(S->threads) if (S->threads > 1)
#endif
    {
        strain_partials(S, u, part);
        if (v && f)
            state_partials(S, u, v, f, part);
    }
    memset(out, 0, sizeof *out);
    out->boulder_strain = strain_combine(S, part);
    for (int k = 0; k < CHUNKS && v && f; k++) {
        out->mv2[0] += part[k][11], out->boulder_pz += part[k][12], out->boulder_uz += part[k][13];
        out->mv2[1] += part[k][14], out->slope_fu += part[k][15];
    }
}
