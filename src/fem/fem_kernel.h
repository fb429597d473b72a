/* fem_kernel.h - the material interface of the FE core.  The internal force
 * of a block of elements (one body, one material, one element type) comes
 * from a kernel; the time loop only gathers element displacements, calls the
 * kernel of each block and assembles the element forces, so a new material
 * (elasto-plastic rock or soil, a faster or a rigid formulation) is a new
 * kernel chosen per body, and the loop does not change.
 *
 * Contract of a kernel:
 *   forces(k, e0, e1, ue, fe): for the elements e0 <= e < e1 of the block
 *     (global element numbers), ue holds (e1 - e0) element displacement
 *     vectors of ndofe values each (in the element's frame: the 3D solver
 *     removes the boulder's rigid rotation first), fe receives as many
 *     internal-force vectors.  Called from several threads on disjoint
 *     ranges; it may write per-element or per-integration-point trial state
 *     of its own elements only.
 *   commit(k): the step is accepted: trial state becomes the committed state
 *     (NULL for a stateless kernel such as linear elasticity).
 *   destroy(k): release data.
 *
 * The linear-elastic kernels precompute each element's stiffness (fe = K_e
 * ue: the fastest form for elasticity).  A J2 or Drucker-Prager-with-cap
 * kernel (plasticity_refs.md) keeps, per integration point, the committed
 * strain, stress and internal variables and the B matrix or its factors; its
 * forces() computes the strain increment at each point from ue, calls the
 * point-wise return map (src/material) for the trial stress and state, and
 * integrates B^T sigma det(J) w (with B-bar or one-point integration plus
 * hourglass control where plastic flow is isochoric); commit() accepts the
 * trial values.  The energy account then uses the kernel's internal work
 * instead of 1/2 u'K u (a stage to add with the first dissipative kernel). */
#ifndef ROCKFUZZ_FEM_KERNEL_H
#define ROCKFUZZ_FEM_KERNEL_H

#include "rockfuzz/status.h"

typedef struct fem_kernel fem_kernel;

typedef struct {
    const char *name;
    void (*forces)(const fem_kernel *k, long e0, long e1, const double *ue, double *fe);
    /* Optional fused path (NULL if absent) for one thread and elements whose
       displacements are plain u: gather, forces and f += scatter per element,
       in element order (the same sums as forces() + the node-ordered gather). */
    void (*assemble)(const fem_kernel *k, long e0, long e1, const int *conn, const double *u, double *f);
    void (*commit)(fem_kernel *k);
    void (*destroy)(fem_kernel *k);
    /* (Last, so that positional initialisers of older kernels stay valid.)
       Optional matrix-free path (NULL if absent): the forces of the work units
       [w0, w1) of the block (k->units of them; a unit is a fixed group of
       elements, e.g. one SIMD block of hexahedra) straight from the nodal
       field u (the solver passes the boulder's field in its own frame),
       element e's forces written at fe + ndofe e (global numbering).  Each
       element's forces come from one unit alone: any split of the units over
       threads gives the same bits.  A kernel with this path may leave
       forces() NULL; the time loop then calls this one. */
    void (*forces_field)(const fem_kernel *k, long w0, long w1, const double *u, double *fe);
} fem_kernel_ops;

struct fem_kernel {
    const fem_kernel_ops *ops;
    long first, count; /* the block: elements [first, first + count) */
    int ndofe;         /* dofs per element: 8 (axisymmetric quad), 24 (hexahedron) */
    long units;        /* work units of forces_field (0 without it) */
    void *data;        /* the kernel's own data */
};

/* A point-wise constitutive law, the unit an integration-point kernel calls:
 * from the strain increment deps and the committed stress sig_n and internal
 * variables state_n of one point, the trial stress sig and variables state
 * (ncomp = 4 for axisymmetry: rr, zz, tt, rz with engineering shear; 6 in
 * 3D).  A J2 or Drucker-Prager-with-cap return map (src/material) has this
 * shape; linear elasticity is sig = sig_n + D deps (fem_point_law_linear). */
typedef struct {
    const char *name;
    int ncomp, nstate;
    void (*update)(const void *params, const double *deps, const double *sig_n, const double *state_n, double *sig,
                   double *state);
    const void *params;
} fem_point_law;

/* Elements per call of forces() in the time loops (bounded stack buffers). */
#define FEM_KERNEL_CHUNK 32

/* Linear elasticity with a precomputed stiffness per element:
 *   axisymmetric quads, K in double (64 per element, row-major);
 *   hexahedra, K in float (576 per element, symmetric: single precision
 *   halves the memory traffic that bounds this loop, 7 digits are far below
 *   the discretisation error).
 * The kernel takes ownership of K (freed by destroy unless pooled != 0). */
void fem_kernel_linear_axi(fem_kernel *k, long first, long count, double *K, int pooled);
void fem_kernel_linear_hex(fem_kernel *k, long first, long count, float *K, int pooled);

/* Linear elasticity of hexahedra, matrix-free (hex8_kernel.h): strains and
 * stresses at the 2x2x2 Gauss points from J^-1 and det J, in SIMD blocks of
 * HEX8_W elements; J stored (store_jacobians != 0, 640 B per element) or
 * recomputed from x each step (x and conn must outlive the kernel).  Full
 * double precision (the stored-K kernel above keeps K in float).  lam, mu:
 * the block's Lame constants.  Only forces_field is provided. */
rf_status fem_kernel_hex8_matfree(fem_kernel *k, long first, long count, const double *x, const int *conn, double lam,
                                  double mu, int store_jacobians, rf_error *err);

/* Integration-point kernel of the axisymmetric quad (2x2 Gauss): keeps B and
 * the weight at every point, the committed strain, stress and internal
 * variables, and calls `law` at every point of every element each step; the
 * template for elasto-plastic kernels.  r, z: node coordinates, conn: 4
 * nodes per element (global numbering; the block's elements are
 * [first, first + count)).  With the linear law it reproduces the
 * precomputed-stiffness kernel to round-off (test_fem). */
rf_status fem_kernel_points_axi(fem_kernel *k, long first, long count, const double *r, const double *z,
                                const int *conn, const fem_point_law *law, rf_error *err);
/* sig = sig_n + D deps for an isotropic material (lam, mu = the Lame constants). */
typedef struct {
    double lam, mu;
} fem_lame;
fem_point_law fem_point_law_linear(const fem_lame *lame);

static inline void fem_kernel_release(fem_kernel *k)
{
    if (k->ops && k->ops->destroy)
        k->ops->destroy(k);
    k->ops = 0;
}

#endif
