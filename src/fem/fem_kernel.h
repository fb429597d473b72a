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

#include "rockfuzz/material.h"
#include "rockfuzz/status.h"

typedef struct fem_kernel fem_kernel;

/* What a dissipative kernel reports of its committed state. */
typedef struct {
    double plastic_work;         /* plastic dissipation of the block so far [J] */
    double plastic_strain_max;   /* largest equivalent plastic strain of an integration point [-] */
    long element_max;            /* the element of that point (global number; -1 if none yielded) */
} fem_kernel_report;

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
    /* Optional (NULL: nothing dissipates): the dissipation account of the
       committed state, for fem_kernel_report_get (which has zeroed r). */
    void (*report)(const fem_kernel *k, fem_kernel_report *r);
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
    /* 1 for a dissipative law: state[0] is the equivalent plastic strain and
       state[nstate - 1] the plastic work per unit volume of the last
       increment [J/m^3]; the kernel then integrates the dissipation. */
    int dissipative;
    /* Optional (NULL): elastic energy density of a stress [J/m^3], for the
       energy account's check (fem_kernel_elastic_energy). */
    double (*energy)(const void *params, const double *sig);
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
/* The axisymmetric one from a packed copy of K (quad4_kernel.h: 36 of the 64
 * entries, the same products to the last bit, 44 % less memory traffic): K
 * (count matrices) is packed into pk (quad4_packed_size(count) doubles, the
 * caller's, kept); returns -1 if a K_e is not exactly symmetric (k untouched). */
int fem_kernel_linear_axi_packed(fem_kernel *k, long first, long count, const double *K, double *pk);

/* A rigid body's block: no internal force (fem_kernel_rigid.c). */
void fem_kernel_rigid(fem_kernel *k, long first, long count, int ndofe);
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
/* The same with the mean-dilatation B-bar (Hughes 1980; Nagtegaal, Parks &
 * Rice 1974) when bbar != 0: the volumetric strain of every point is replaced
 * by its volume average over the element, so that isochoric (plastic or
 * near-incompressible) flow does not lock the fully integrated quad; the
 * force is the transpose, sum_q w_q Bbar_q^T sigma_q (the element stays
 * symmetric, its stiffness below the fully integrated one: the time step
 * bound of the full stiffness stays valid). */
rf_status fem_kernel_points_axi_ex(fem_kernel *k, long first, long count, const double *r, const double *z,
                                   const int *conn, const fem_point_law *law, int bbar, rf_error *err);
/* The same with two laws of the same state size: element first + i uses
 * law2 where use_law2[i] != 0 (count flags, copied), else law: a layered
 * body in one block. */
rf_status fem_kernel_points_axi_two(fem_kernel *k, long first, long count, const double *r, const double *z,
                                    const int *conn, const fem_point_law *law, const fem_point_law *law2,
                                    const unsigned char *use_law2, int bbar, rf_error *err);
/* Turn an integration-point kernel just made (above) into the updated
 * Lagrangian form (large deformation, docs/validation-plastic.md section 6e):
 * at every step the strain increment is B(x_mid) (u_{n+1} - u_n) on the
 * mid-step geometry x_mid = X + (u_n + u_{n+1}) / 2, the committed Cauchy
 * stress is rotated by the Hughes-Winget rotation of the increment's spin
 * 1/2 (d du_z/dr - d du_r/dz) (rf_material_rotate) before the law's update,
 * and the force is sum_q w_q B_q^T sigma_q with B, 1/r and w = 2 pi r det J
 * (and the B-bar average, if chosen) of the current geometry X + u_{n+1}.
 * Both are exact for a rigid rotation of any size (no strain, the stress
 * turned with the body).  r, z, conn: the reference mesh (copied). */
rf_status fem_kernel_points_axi_large(fem_kernel *k, const double *r, const double *z, const int *conn,
                                      rf_error *err);
/* sig = sig_n + D deps for an isotropic material (lam, mu = the Lame constants). */
typedef struct {
    double lam, mu;
} fem_lame;
fem_point_law fem_point_law_linear(const fem_lame *lame);
/* The linear elastic stress update of both point kernels: normal components
   0..2, shear components 3..nc-1 (engineering shear strains). */
static inline void fem_lame_update(const fem_lame *p, const double *deps, const double *sig_n, double *sig, int nc)
{
    const double tr = deps[0] + deps[1] + deps[2];
    for (int i = 0; i < 3; i++)
        sig[i] = sig_n[i] + p->lam * tr + 2 * p->mu * deps[i];
    for (int i = 3; i < nc; i++)
        sig[i] = sig_n[i] + p->mu * deps[i];
}
/* The material library's return maps (rockfuzz/material.h) as a point law of
 * the axisymmetric quad: rr, zz, tt, rz (engineering shear) map onto xx, yy,
 * zz, xy with zero yz, zx; state = {eps_p_eq, eps_p_vol, compaction,
 * dissipation of the increment}.  m must outlive the kernel. */
fem_point_law fem_point_law_material(const rf_material *m);
/* The dissipation account of a kernel's committed state (its ops->report):
 * zeros for any kernel that is not an integration-point kernel with a
 * dissipative law, axisymmetric or hexahedral. */
void fem_kernel_report_get(const fem_kernel *k, fem_kernel_report *r);
/* The committed state of element e (global number) of an integration-point
 * kernel: mean stress components over its points (rr, zz, tt, rz) and the
 * largest equivalent plastic strain (0 for a law without one).  Returns 0,
 * leaving the outputs alone, for other kernels or elements outside the block. */
int fem_kernel_cell_state(const fem_kernel *k, long e, double sig[4], double *plastic_strain);
/* Elastic energy of the committed stresses, sum_q w_q psi(sigma_q) [J], of an
 * integration-point kernel whose law gives psi; -1 otherwise. */
double fem_kernel_elastic_energy(const fem_kernel *k);

/* Integration-point kernel of the 8-node hexahedron (fem_kernel_points3d.c):
 * 2x2x2 Gauss, the x-gradients of the shape functions and det J stored per
 * point (1.6 kB per element), the committed strain, stress and law state per
 * point; `law` (ncomp = 6) at every point each step, law2 (same shape) for
 * the elements with use_law2[i] != 0 (NULL: law everywhere); mean-dilatation
 * B-bar when bbar != 0 (as fem_kernel_points_axi_ex).  x: node coordinates,
 * conn: 8 nodes per element (global numbering; copied).  Provides
 * forces_field() only: work units are blocks of HEX8_W elements, one per vector lane (the kinematics in SIMD, the laws lane by
 * lane); any split of the units gives the same bits.
 * With the linear law and bbar = 0 it reproduces the matrix-free elastic
 * kernel to round-off (test_fem3d_plastic).  In the 3D solver the boulder's
 * field is co-rotated first: a plastic boulder's committed stresses live in
 * its co-rotated frame. */
rf_status fem_kernel_points_hex(fem_kernel *k, long first, long count, const double *x, const int *conn,
                                const fem_point_law *law, const fem_point_law *law2, const unsigned char *use_law2,
                                int bbar, rf_error *err);
/* fem_kernel_cell_state (6 components xx yy zz xy yz zx) and
 * fem_kernel_elastic_energy for the hexahedron kernel above (0 and -1 for
 * other kernels); its dissipation account is fem_kernel_report_get's. */
int fem_kernel_points_hex_cell(const fem_kernel *k, long e, double sig[6], double *plastic_strain);
double fem_kernel_points_hex_energy(const fem_kernel *k);
/* Turn a hexahedron point kernel just made (above) into the updated
 * Lagrangian form (large deformation, fem_kernel_points3d_large.c): the strain
 * increment and the spin from the gradients of the mid-step geometry
 * X + (u_n + u_{n+1}) / 2, the committed stress turned by the Hughes-Winget
 * rotation of that spin before the law's update, the force (and B-bar, if
 * chosen) with the gradients and det J of the current geometry X + u_{n+1},
 * the plastic dissipation over the current volumes.  Exact for a rigid
 * motion of any size.  x: the reference node coordinates (read here only). */
rf_status fem_kernel_points_hex_large(fem_kernel *k, const double *x, rf_error *err);
/* sig = sig_n + D deps in 3D (xx yy zz xy yz zx, engineering shear strains),
 * with its elastic energy density. */
fem_point_law fem_point_law_linear3d(const fem_lame *lame);
/* The material library's return maps as a 3D point law (ncomp = 6, the
 * Voigt order of rockfuzz/material.h); state as fem_point_law_material. */
fem_point_law fem_point_law_material3d(const rf_material *m);

/* The points of an integration-point kernel as the shared helpers below see
 * them (fem_points_state.c): np points, nq per element, nc stress
 * components, the law (law2 where use2[element] != 0), the weights and the
 * committed and trial strain, stress and state arrays. */
typedef struct {
    size_t np;
    int nq, nc;
    const fem_point_law *law, *law2;
    const unsigned char *use2;
    const double *w;
    double *eps, *sig, *var;
    const double *eps_t, *sig_t, *var_t;
} fem_points_view;
/* For an ALE remap (fem_ale.c): the committed points of an updated
 * Lagrangian kernel made by fem_kernel_points_axi_large (v) and its committed
 * element displacements (*ue_c, 8 per element of the block, writable: the
 * remap moves the committed geometry with the mesh).  0 for another kernel. */
int fem_kernel_points_axi_ale(fem_kernel *k, fem_points_view *v, double **ue_c);
/* Trial state becomes committed; a dissipative law's plastic work of the
 * increment, sum_p w_p var_p[nstate - 1], is added to *work and the largest
 * equivalent plastic strain var_p[0] (and its point) tracked. */
void fem_points_accept(const fem_points_view *v, double *work, double *strain_max, long *point_max);
/* Mean committed stress over the points of local element le and their
 * largest equivalent plastic strain (0 for a law without one). */
void fem_points_cell(const fem_points_view *v, long le, double *sig, double *plastic_strain);
/* Elastic energy of the committed stresses, sum_p w_p psi(sigma_p) [J]; -1
 * if a law has no energy density. */
double fem_points_energy(const fem_points_view *v);

/* The geostatic state of a body under gravity (docs/validation-plastic.md
 * "Gravity"): at depth d below the surface z = 0 the vertical stress is
 * sigma_v = -g (rho_layer min(d, t) + rho_base max(d - t, 0)) (t: the layer
 * thickness, 0 for none), the horizontal ones K0 sigma_v, no shear; K0 of
 * the point's law (k0[0] for law, k0[1] for law2).  mat[i] (NULL for a
 * linear law): the law's material, whose compaction cap (if any) is put
 * through the geostatic mean stress (normally consolidated under its own
 * weight: eps_c = (p - X0) / H_c when p > X0).
 * An infinite slope inclined at `incline` (3D model, slope frame: x
 * down-slope, z the outward normal, d measured along -z): sigma_zz =
 * cos(incline) sigma_v, sigma_zx = -sin(incline) sigma_v (>= 0, from
 * equilibrium), sigma_xx = sigma_yy = K0 sigma_zz (incline 0: the level
 * state above, bit for bit). */
typedef struct {
    double g;                  /* [m/s^2] */
    double thickness;          /* [m] */
    double rho_layer, rho_base; /* [kg/m^3] */
    double k0[2];
    const rf_material *mat[2];
    double incline;            /* [rad] slope angle (6-component points only) */
} fem_geostatic;
/* K0 of a material: Jaky's 1 - sin(phi) for Drucker-Prager (normally
 * consolidated soil), nu / (1 - nu) (uniaxial strain) for elastic and von Mises. */
double fem_geostatic_k0(const rf_material_params *p);
/* Vertical geostatic stress at depth d [Pa] (<= 0). */
double fem_geostatic_vertical(const fem_geostatic *g, double depth);
/* Committed and trial stresses (and a cap's compaction) of every point set to
 * the geostatic state at its depth depth[p].  The in-plane stresses are
 * statically indeterminate: where K0 puts a point outside its yield surface
 * the smallest ratio K > K0 that puts it on or inside is taken instead (in
 * [K0, 1], else up to the K minimising the yield function; bisection on the
 * material's yield function); returns the number of points for which no
 * such K exists (the state the law does not admit). */
long fem_points_geostatic(const fem_points_view *v, const double *depth, const fem_geostatic *g);
/* The same for the axisymmetric integration-point kernel (the point depths
 * -z at its 2x2 Gauss points, the reference mesh r, z, conn); -1 for another kernel. */
long fem_kernel_points_axi_geostatic(fem_kernel *k, const double *r, const double *z, const int *conn,
                                     const fem_geostatic *g);
/* The same for the hexahedron kernel (fem_kernel_points_hex) with the
 * depths of its points given (depth[8 e + q], e local, q in the order of
 * f3_hex_gradients); -1 for another kernel. */
long fem_kernel_points_hex_geostatic(fem_kernel *k, const double *depth, const fem_geostatic *g);

static inline void fem_kernel_release(fem_kernel *k)
{
    if (k->ops && k->ops->destroy)
        k->ops->destroy(k);
    k->ops = 0;
}

#endif
