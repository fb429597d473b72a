/* fem_kernel_linear.c - the linear-elastic material kernels (fem_kernel.h):
 * fe = K_e ue with the element stiffness precomputed at set-up, for the
 * axisymmetric quad (double; the product in quad4_kernel.c) and the
 * hexahedron (float, symmetric). */
#include "fem_kernel.h"
#include "quad4_kernel.h"

#include <stdlib.h>
#include <string.h>

/* On x86-64 a wider-vector clone of the hot loops is picked once per process
 * (the same one for every thread, so the thread count never changes a
 * result; C17 mode does not contract a*b+c into FMA, so the clones give the
 * same bits as the default code). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define RF_VECTOR_CLONES __attribute__((target_clones("default", "arch=x86-64-v3")))
#else
#define RF_VECTOR_CLONES
#endif

/* The axisymmetric quad's K_e u_e as 8 vector column updates (quad4_kernel.c: 108 instead of
 * 245 instructions per element-step, docs/fem-speed.md); both paths share one product. */
static void axi_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    const double *K = k->data;
    quad4_force_elements(K, e0 - k->first, e1 - k->first, ue, fe);
}

/* The fused gather-multiply-scatter (conn: 4 nodes per element, 2 dofs per
 * node), element order. */
static void axi_assemble(const fem_kernel *k, long e0, long e1, const int *conn, const double *u, double *f)
{
    quad4_force(k->data, NULL, conn + 4 * k->first, e0 - k->first, e1 - k->first, u, f);
}

/* The same products from the packed table (quad4_pack: 36 entries per element, 8 elements per
 * vector; the same bits). */
static void axi_packed_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    quad4_force_packed_elements(k->data, e0 - k->first, e1 - k->first, ue, fe);
}

static void axi_packed_assemble(const fem_kernel *k, long e0, long e1, const int *conn, const double *u, double *f)
{
    quad4_force_packed(k->data, conn + 4 * k->first, e0 - k->first, e1 - k->first, u, f);
}

RF_VECTOR_CLONES
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

static const fem_kernel_ops axi_owned = {"linear elastic (axisymmetric quad)", axi_forces, axi_assemble, NULL,
                                         owned_destroy, NULL, NULL};
static const fem_kernel_ops axi_pooled = {"linear elastic (axisymmetric quad)", axi_forces, axi_assemble, NULL,
                                          pooled_destroy, NULL, NULL};
static const fem_kernel_ops axi_packed = {"linear elastic (axisymmetric quad)", axi_packed_forces,
                                          axi_packed_assemble, NULL, pooled_destroy, NULL, NULL};
static const fem_kernel_ops hex_owned = {"linear elastic (hexahedron)", hex_forces, NULL, NULL, owned_destroy, NULL, NULL};
static const fem_kernel_ops hex_pooled = {"linear elastic (hexahedron)", hex_forces, NULL, NULL, pooled_destroy, NULL, NULL};

void fem_kernel_linear_axi(fem_kernel *k, long first, long count, double *K, int pooled)
{
    k->ops = pooled ? &axi_pooled : &axi_owned;
    k->first = first, k->count = count, k->ndofe = 8, k->units = 0, k->data = K;
}

int fem_kernel_linear_axi_packed(fem_kernel *k, long first, long count, const double *K, double *pk)
{
    if (quad4_pack(K, count, pk) != 0)
        return -1;
    k->ops = &axi_packed;
    k->first = first, k->count = count, k->ndofe = 8, k->units = 0, k->data = pk;
    return 0;
}

void fem_kernel_linear_hex(fem_kernel *k, long first, long count, float *K, int pooled)
{
    k->ops = pooled ? &hex_pooled : &hex_owned;
    k->first = first, k->count = count, k->ndofe = 24, k->units = 0, k->data = K;
}
