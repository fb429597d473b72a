/* fem_axi_force.c - the axisymmetric run's internal force f_int(u): each
 * element's forces through its body's material kernel, then each node's sum of
 * its elements' forces in element order, so that any thread count gives the
 * same bits; and the kernels' commit of the state they last saw. */
#include "fem_axi_run.h"

#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* Element forces of elements [e0, e1) through the block's kernel, in
 * chunks: into S->sys.fe (f == NULL), or added to f node by node in element
 * order (one thread: the same sums as the node-ordered gather, without the
 * extra pass). */
static void block_forces(const axi_run *S, const fem_kernel *k, const double *u, long e0, long e1, double *f)
{
    const int *conn = S->mesh.conn;
    double ue[FEM_KERNEL_CHUNK * 8], fe[FEM_KERNEL_CHUNK * 8];
    for (long c0 = e0; c0 < e1; c0 += FEM_KERNEL_CHUNK) {
        long c1 = c0 + FEM_KERNEL_CHUNK < e1 ? c0 + FEM_KERNEL_CHUNK : e1;
        for (long e = c0; e < c1; e++) {
            const int *c = conn + 4 * e;
            double *x = ue + 8 * (e - c0);
            for (int a = 0; a < 4; a++)
                x[2 * a] = u[2 * c[a]], x[2 * a + 1] = u[2 * c[a] + 1];
        }
        if (!f) {
            k->ops->forces(k, c0, c1, ue, S->sys.fe + 8 * c0);
            continue;
        }
        k->ops->forces(k, c0, c1, ue, fe);
        for (long e = c0; e < c1; e++) {
            const int *c = conn + 4 * e;
            const double *y = fe + 8 * (e - c0);
            for (int a = 0; a < 4; a++)
                f[2 * c[a]] += y[2 * a], f[2 * c[a] + 1] += y[2 * a + 1];
        }
    }
}

/* Node n's force: its elements' forces summed in element order. */
static inline void gather_node(const axi_run *S, long n, double *f)
{
    double fr = 0, fz = 0;
    for (long p = S->sys.inc_ptr[n]; p < S->sys.inc_ptr[n + 1]; p++) {
        const double *fp = S->sys.fe + 8 * (S->sys.inc[p] >> 2) + 2 * (S->sys.inc[p] & 3);
        fr += fp[0], fz += fp[1];
    }
    f[2 * n] = fr, f[2 * n + 1] = fz;
}

/* f = f_int(u): element forces by the material kernels, then a node-ordered
 * gather (the same sums for any thread count). */
void axi_internal_force(const axi_run *S, const double *u, double *f)
{
    if (S->set.threads <= 1) { /* no parallel region, direct assembly */
        memset(f, 0, (size_t)S->sys.ndof * sizeof *f);
        for (int b = 0; b < 2; b++) {
            const fem_kernel *k = &S->body.kernel[b];
            if (k->ops->assemble)
                k->ops->assemble(k, k->first, k->first + k->count, S->mesh.conn, u, f);
            else
                block_forces(S, k, u, k->first, k->first + k->count, f);
        }
        return;
    }
#ifdef _OPENMP
#pragma omp parallel num_threads(S->set.threads)
    {
        int tid = omp_get_thread_num(), T = omp_get_num_threads();
        for (int b = 0; b < 2; b++) {
            const fem_kernel *k = &S->body.kernel[b];
            long n = k->count, a0 = k->first + n * tid / T, a1 = k->first + n * (tid + 1) / T;
            block_forces(S, k, u, a0, a1, NULL);
        }
#pragma omp barrier
#pragma omp for schedule(static)
        for (long n = 0; n < S->sys.nn; n++)
            gather_node(S, n, f);
    }
#endif
}

/* The state at the last internal force is accepted (the kernels' committed stresses). */
void axi_commit(axi_run *S)
{
    for (int b = 0; b < 2; b++)
        if (S->body.kernel[b].ops->commit)
            S->body.kernel[b].ops->commit(&S->body.kernel[b]);
}
