/* fem_kernel_hex8.c - the matrix-free linear-elastic kernel of the 3D
 * model's hexahedra (fem_kernel.h) on top of hex8_kernel.c: one hex8_bmat
 * per block, its SIMD blocks of HEX8_W elements as the work units that the
 * time loop shares among threads (docs/fem-speed.md). */
#include "fem_kernel.h"
#include "hex8_kernel.h"

#include <stdlib.h>

static void matfree_field(const fem_kernel *k, long w0, long w1, const double *u, double *fe)
{
    hex8_bmat_force(k->data, w0, w1, u, NULL, fe);
}

static void matfree_destroy(fem_kernel *k)
{
    if (k->data)
        hex8_bmat_free(k->data);
    free(k->data);
    k->data = NULL;
}

static const fem_kernel_ops matfree_ops = {"linear elastic (hexahedron, matrix-free)", NULL, NULL, NULL,
                                           matfree_destroy, matfree_field, NULL};

rf_status fem_kernel_hex8_matfree(fem_kernel *k, long first, long count, const double *x, const int *conn, double lam,
                                  double mu, int store_jacobians, rf_error *err)
{
    k->ops = NULL, k->data = NULL;
    hex8_bmat *B = calloc(1, sizeof *B);
    int *ids = malloc((size_t)(count > 0 ? count : 1) * sizeof *ids);
    double *lm = malloc((size_t)(count > 0 ? count : 1) * 2 * sizeof *lm);
    rf_status st = RF_OK;
    if (!B || !ids || !lm)
        st = rf_fail(err, RF_ENOMEM, "fem kernel: out of memory for %ld hexahedra", count);
    if (st == RF_OK) {
        for (long e = 0; e < count; e++)
            ids[e] = (int)(first + e), lm[e] = lam, lm[count + e] = mu;
        st = hex8_bmat_init(B, x, conn, ids, count, lm, lm + count, store_jacobians, err);
    }
    free(ids), free(lm);
    if (st != RF_OK) {
        free(B);
        return st;
    }
    k->ops = &matfree_ops;
    k->first = first, k->count = count, k->ndofe = 24, k->units = B->nblk, k->data = B;
    return RF_OK;
}
