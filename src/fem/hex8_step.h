/* hex8_step.h - the largest element eigenvalue max_e lambda_max(M_e^-1 K_e)
 * of a hexahedral mesh, hence its stable step, without an eigen-solve per
 * element: a rigorous Gershgorin bound orders the elements and the exact
 * value is computed only for those that can still set the maximum
 * (docs/fem-speed.md: 187 of 24 256 at the default 3D a/h = 6).  Used by the
 * 3D solver's set-up and by bench_hex8.  Internal header. */
#ifndef ROCKFUZZ_HEX8_STEP_H
#define ROCKFUZZ_HEX8_STEP_H

/* Element e's stiffness (24 x 24, row-major, symmetric), lumped nodal masses
 * and free dofs, as f3_hex_lambda_max takes them. */
typedef void (*hex8_element_fn)(void *ctx, long e, double K[576], double m[8], unsigned char free_dof[24]);

/* Gershgorin's bound max over free rows of sum_j |K_ij| / sqrt(m_i m_j) >=
 * lambda_max(M^-1 K) (the symmetric form M^-1/2 K M^-1/2); 0 without a free dof. */
double hex8_gershgorin_bound(const double K[576], const double m[8], const unsigned char free_dof[24]);

/* max over e of f3_hex_lambda_max(K_e, m_e, free_e), bit for bit the
 * brute-force maximum (every element is solved when memory for the ordering
 * is missing).  lam_upper (optional, ne entries): each element's Gershgorin
 * bound.  n_exact (optional): how many eigen-solves were needed.  fn is
 * called about ne + n_exact times, from one thread. */
double hex8_max_eigenvalue(long ne, hex8_element_fn fn, void *ctx, double *lam_upper, long *n_exact);

/* min over e of 2/sqrt(lambda_max_e) (DBL_MAX when no element has one).
 * dt_lower (optional, ne entries): a rigorous lower bound of each element's
 * step, 2/sqrt of its Gershgorin bound, safe for assigning subcycling
 * levels. */
double hex8_min_stable_step(long ne, hex8_element_fn fn, void *ctx, double *dt_lower, long *n_exact);

#endif
