/* fem_kernel_linear.c - the linear-elastic material kernels (fem_kernel.h):
 * fe = K_e ue with the element stiffness precomputed at set-up, for the
 * axisymmetric quad (double) and the hexahedron (float, symmetric). */
#include "fem_kernel.h"

#include <stdlib.h>
#include <string.h>

static void axi_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    const double *K = k->data;
    for (long e = e0; e < e1; e++, ue += 8, fe += 8) {
        const double *ke = K + 64 * (e - k->first);
        for (int a = 0; a < 8; a++) {
            const double *ka = ke + 8 * a;
            fe[a] = ka[0] * ue[0] + ka[1] * ue[1] + ka[2] * ue[2] + ka[3] * ue[3] + ka[4] * ue[4] + ka[5] * ue[5] +
                    ka[6] * ue[6] + ka[7] * ue[7];
        }
    }
}

/* fe = K_e u_e with K symmetric: fe = sum_j K[j][.] u_j runs over contiguous
 * rows as a vectorisable axpy.  On x86-64 a wider-vector clone is picked once
 * per process (the same one for every thread, so the thread count never
 * changes a result). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("default", "arch=x86-64-v3")))
#endif
static void hex_element_force(const float *restrict k, const double *restrict uel, double *restrict fe)
{
    double acc[24] = {0};
    for (int j = 0; j < 24; j++) {
        const float *kj = k + 24 * j;
        const double uj = uel[j];
        for (int i = 0; i < 24; i++)
            acc[i] += (double)kj[i] * uj;
    }
    memcpy(fe, acc, sizeof acc);
}

static void hex_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    const float *K = k->data;
    for (long e = e0; e < e1; e++, ue += 24, fe += 24)
        hex_element_force(K + 576 * (e - k->first), ue, fe);
}

static void owned_destroy(fem_kernel *k)
{
    free(k->data);
    k->data = NULL;
}

static void pooled_destroy(fem_kernel *k)
{
    k->data = NULL;
}

static const fem_kernel_ops axi_owned = {"linear elastic (axisymmetric quad)", axi_forces, NULL, owned_destroy};
static const fem_kernel_ops axi_pooled = {"linear elastic (axisymmetric quad)", axi_forces, NULL, pooled_destroy};
static const fem_kernel_ops hex_owned = {"linear elastic (hexahedron)", hex_forces, NULL, owned_destroy};
static const fem_kernel_ops hex_pooled = {"linear elastic (hexahedron)", hex_forces, NULL, pooled_destroy};

void fem_kernel_linear_axi(fem_kernel *k, long first, long count, double *K, int pooled)
{
    k->ops = pooled ? &axi_pooled : &axi_owned;
    k->first = first, k->count = count, k->ndofe = 8, k->data = K;
}

void fem_kernel_linear_hex(fem_kernel *k, long first, long count, float *K, int pooled)
{
    k->ops = pooled ? &hex_pooled : &hex_owned;
    k->first = first, k->count = count, k->ndofe = 24, k->data = K;
}
