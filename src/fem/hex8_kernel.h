/* hex8_kernel.h - fast internal-force kernels for blocks of 8-node
 * hexahedra (small strain, full 2x2x2 Gauss), array in, array out, for the
 * explicit solvers to call from their own loops (docs/fem-speed.md).
 *
 * Every kernel reads a nodal displacement field u (3 doubles per node) and
 * writes the 24 element forces f_e = dE/du_e of each listed element e at
 * fe + 24 e, the layout of fem3d_assemble.c's element-force array, so that the
 * node-ordered gather that follows stays as it is.  Each element's forces
 * are computed by one call from that element's data alone, in a fixed order:
 * any split of the element list over threads gives the same bits.
 *
 * - hex8_shared_force: elements congruent up to translation (the uniform
 *   cubes of the slope's fine box) share one stiffness K_e, which stays in
 *   L1; only displacements stream.
 * - hex8_bmat_*: any element shape, matrix-free.  J^-1 and det J at the 8
 *   Gauss points are stored (80 doubles per element instead of 576 floats)
 *   or recomputed each call from the node coordinates (nothing stored:
 *   fewer bytes, more flops).  Strains and stresses are formed at the
 *   points, in blocks of HEX8_W elements laid out as structure of arrays
 *   (one element per vector lane).  The stress at a point comes from
 *   isotropic linear elasticity or from a caller's point-wise routine
 *   sig = f(eps, state), so that plastic materials share the kernel.
 * Internal header. */
#ifndef ROCKFUZZ_HEX8_KERNEL_H
#define ROCKFUZZ_HEX8_KERNEL_H

#include "rockfuzz/status.h"

enum { HEX8_W = 8 }; /* elements per block: one AVX-512 register of doubles */

/* fe[24 e ..] = K u_e for e = elem[0 .. n-1]; K is 24 x 24 row-major and
 * symmetric, dofs x0 y0 z0 x1 ... (fem3d_element.c's convention). */
void hex8_shared_force(const double K[576], const int *conn, const int *elem, long n, const double *u, double *fe);

/* Writes to out[] the candidates whose node positions, relative to their
 * node 0, equal those of xref (24 coordinates) within tol [m]; returns how
 * many.  The caller then computes the one K_e from xref. */
long hex8_find_congruent(const double *x, const int *conn, const int *cand, long ncand, const double xref[24],
                         double tol, int *out);

/* Point-wise stress routine: eps and sig in Voigt order xx yy zz yz xz xy,
 * tensor (not engineering) shear strains.  point = 8 k + q for the k-th
 * listed element and Gauss point q, so that ctx can index a state array
 * (plastic strain, hardening, the stress of the last step).  The kernel
 * passes the strain of the displacement field it is given: give it the
 * step's displacement increment to get the strain increment. */
typedef void (*hex8_stress_fn)(void *ctx, long point, const double eps[6], double sig[6]);
typedef struct {
    hex8_stress_fn fn; /* NULL: isotropic linear elasticity with the stored Lame constants */
    void *ctx;
} hex8_stress;

typedef struct {
    long n;       /* listed elements */
    long nblk;    /* blocks of HEX8_W lanes, the last one padded */
    int *elem;    /* element id per lane, -1 for padding [nblk W] */
    int *conn;    /* per block [8 nodes][W] node ids */
    double *jinv; /* per block [8 points][9][W]: (J^-1)[j][i] = d xi_i / d x_j; NULL: recomputed */
    double *wdet; /* per block [8 points][W]: det J (Gauss weights are 1); NULL with jinv */
    const double *x; /* node coordinates (3 per node) when jinv is NULL; the caller keeps them */
    double *lam;  /* per block [W]: Lame constants [Pa] */
    double *mu;
} hex8_bmat;

/* Geometry of the listed elements (x: 3 per node, conn: 8 per element) and
 * their Lame constants lam[k], mu[k] (k = list index).  store_jacobians: keep
 * J^-1 and det J (640 B per element), else keep a pointer to x and recompute
 * them in every call.  RF_EINVAL for a non-positive Jacobian at a Gauss
 * point, RF_ENOMEM. */
rf_status hex8_bmat_init(hex8_bmat *B, const double *x, const int *conn, const int *elem, long n, const double *lam,
                         const double *mu, int store_jacobians, rf_error *err);
void hex8_bmat_free(hex8_bmat *B);
/* Element forces of blocks [b0, b1). */
void hex8_bmat_force(const hex8_bmat *B, long b0, long b1, const double *u, const hex8_stress *stress, double *fe);

#endif
