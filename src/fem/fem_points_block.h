/* fem_points_block.h - the kinematics of the axisymmetric integration-point
 * kernel (fem_kernel_points.c) on SIMD blocks of AXB_W quads, one element
 * per vector lane (the layout of the hexahedron kernels, hex8_kernel.h):
 * the 2x2 Gauss geometry (shape-function gradients, N/r, weights
 * w = 2 pi r det J, the mean-dilatation correction), the point strains B u,
 * the spins and the force sum_q w_q B_q^T sigma_q.  Each is the scalar
 * code's arithmetic (fem_element.c's bmatrix, the kernel's former dense
 * 4 x 8 B) in the same order, so the results are the same bits.
 *
 * Arrays are in lane layout, element l of the block at [..][l]:
 *   r, z [4 nodes][W]; u, du, F [8 dofs r0 z0 r1 z1 ..][W];
 *   G [4 points][3: dN/dr, dN/dz, N/r][4 nodes][W];
 *   C [4 points][8 dofs][W]: the B-bar correction added to the rr, zz, tt
 *     rows (all zero without B-bar);
 *   w [4 points][W]; eps, sig [4 points][4: rr zz tt rz][W]; spin [4 points][W].
 * Internal header. */
#ifndef ROCKFUZZ_FEM_POINTS_BLOCK_H
#define ROCKFUZZ_FEM_POINTS_BLOCK_H

enum { AXB_W = 8 };  /* elements per block: one AVX-512 register of doubles */
enum { AXB_G = 48 * AXB_W, AXB_C = 32 * AXB_W, AXB_Q = 4 * AXB_W, AXB_S = 16 * AXB_W, AXB_U = 8 * AXB_W };

/* G, C (B-bar if bbar, else zeros) and w of a block's elements from their node coordinates. */
void axb_geometry(const double *r, const double *z, int bbar, double *G, double *C, double *w);
/* eps = (B + C) u at the four points (engineering shear). */
void axb_strains(const double *G, const double *C, const double *u, double *eps);
/* spin = 1/2 (d du_z/dr - d du_r/dz) at the four points (the plain B, without C). */
void axb_spins(const double *G, const double *du, double *spin);
/* F = sum_q w_q (B_q + C_q)^T sig_q. */
void axb_force(const double *G, const double *C, const double *w, const double *sig, double *F);

/* sig (in: committed, out: turned) by the Hughes-Winget rotation of the spin
 * about the hoop axis, as rf_material_rotate(sig, (0, 0, spin)) (the same bits). */
void axb_rotate(const double *spin, double *sig);

#endif
