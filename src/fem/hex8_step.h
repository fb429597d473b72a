/* hex8_step.h - the smallest element stable step 2/sqrt(max lambda(M_e^-1
 * K_e)) of a mesh without an eigen-solve per element: a rigorous Gershgorin
 * bound orders the elements and the exact bound is computed only for those
 * that can still set the minimum (docs/fem-speed.md: 187 of 24 256 at the
 * default 3D a/h = 6).  Internal header. */
#ifndef ROCKFUZZ_HEX8_STEP_H
#define ROCKFUZZ_HEX8_STEP_H

/* Element e's stiffness (24 x 24, row-major, symmetric), lumped nodal masses
 * and free dofs, as f3_hex_lambda_max takes them. */
typedef void (*hex8_element_fn)(void *ctx, long e, double K[576], double m[8], unsigned char free_dof[24]);

/* Returns min over e of 2/sqrt(f3_hex_lambda_max(K_e, m_e, free_e)), the
 * same value as the brute-force minimum, or -1 when out of memory.
 * dt_lower (optional, ne entries): a rigorous lower bound of each element's
 * step (Gershgorin), safe for assigning subcycling levels.  n_exact
 * (optional): how many eigen-solves were needed.  fn is called about
 * ne + n_exact times, from one thread. */
double hex8_min_stable_step(long ne, hex8_element_fn fn, void *ctx, double *dt_lower, long *n_exact);

#endif
