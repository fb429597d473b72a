/* quad4_kernel.h - internal-force kernel for blocks of 4-node axisymmetric
 * quadrilaterals with a precomputed 8 x 8 stiffness, array in, array out,
 * for the axisymmetric solver to call (docs/fem-speed.md).
 *
 * The axisymmetric element stiffness depends on the radial positions but
 * not on a shift along z: in the uniform core every element of one column
 * (and in the graded part every element repeated along z) has the same K_e.
 * So elements point to a stiffness through an index, kidx[e], into a table
 * of distinct matrices: with kidx[e] = e this is today's per-element store;
 * with quad4_group_by_shape the table shrinks to one K per shape and stays
 * in cache.  Internal header. */
#ifndef ROCKFUZZ_QUAD4_KERNEL_H
#define ROCKFUZZ_QUAD4_KERNEL_H

/* f[dofs of e] += K_{kidx[e]} u_e for e in [e0, e1), in element order (the
 * solver's scatter: one f per thread, summed in thread order afterwards).
 * Kg: 64 per matrix, row-major and symmetric, dofs r0 z0 r1 z1 ...; conn: 4
 * nodes per element; u, f: 2 per node.  kidx NULL means kidx[e] = e. */
void quad4_force(const double *Kg, const int *kidx, const int *conn, long e0, long e1, const double *u, double *f);

/* fe[8 (e - e0) ..] = K_e ue[8 (e - e0) ..] for e in [e0, e1) (K_e at Kg + 64 e):
 * element vectors in and out, the same arithmetic as quad4_force (the
 * multi-thread path of the solver: element forces, then a node gather). */
void quad4_force_elements(const double *Kg, long e0, long e1, const double *ue, double *fe);

/* The packed table: K_e is exactly symmetric, so only its 36 entries K[i][j],
 * i <= j, are stored, for 8 consecutive elements at a time with the element
 * in the vector lane: entry t of element e at pk[288 (e / 8) + 8 t + e % 8].
 * 288 instead of 512 doubles per 8 elements: the default a/h = 10 table is
 * 1.2 MB instead of 2.1 MB and fits the 2 MB L2 (docs/fem-speed.md, section 5).
 * Each product is the same chain of operations as quad4_product, so the same
 * bits as quad4_force. */
long quad4_packed_size(long ne); /* doubles of the packed table of ne elements */
/* 1 when the packed table pays for ne elements: the process runs the
 * AVX-512 clone (x86-64-v4; the AVX2 clone's 8 x 8 transposes take 3.5x the
 * per-element product's instructions, callgrind) and the per-element table
 * (512 B each) would fill more than 3/4 of the L2 cache (sysconf; 2 MB if
 * unknown).  Below, the per-element product is faster: its gather and scatter
 * take fewer instructions and its table is read from L2 either way (measured
 * in docs/fem-speed.md, section 5).  Either choice gives the same bits. */
int quad4_packed_pays(long ne);
/* Packs ne matrices (Kg, 64 each) into pk; -1 (pk partly written) if one is
 * not exactly symmetric. */
int quad4_pack(const double *Kg, long ne, double *pk);
/* quad4_force (kidx NULL) from the packed table; element e uses entry e of pk. */
void quad4_force_packed(const double *pk, const int *conn, long e0, long e1, const double *u, double *f);
/* quad4_force_elements from the packed table. */
void quad4_force_packed_elements(const double *pk, long e0, long e1, const double *ue, double *fe);

/* Groups elements whose node radii agree within tol [m] and whose node z,
 * relative to node 0, agree within tol (same shape, shifted along z; node
 * order must match too).  Writes kidx[e] (group of e, in an order fixed by
 * the shapes) and rep[g] (the lowest element id of group g); returns the
 * number of groups, or -1 when out of memory.  Shapes that straddle a
 * rounding boundary of tol may land in separate groups (less sharing, never
 * a wrong K). */
long quad4_group_by_shape(const double *r, const double *z, const int *conn, long ne, double tol, int *kidx,
                          int *rep);

#endif
