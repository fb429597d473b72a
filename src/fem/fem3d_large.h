/* fem3d_large.h - what large deformation adds to the 3D solver besides its
 * kernel (fem_kernel_points3d_large.c): the per-step check that no element
 * was compressed below the stability bound of the explicit step
 * (fem3d_large.c).  Internal header. */
#ifndef ROCKFUZZ_FEM3D_LARGE_H
#define ROCKFUZZ_FEM3D_LARGE_H

#include "fem3d_internal.h"
#include "hex8_step.h"

/* Each element's step bound 2 / sqrt(lambda_max(M_e^-1 K_e)) of the reference
 * geometry, per unit of its size (f3_element_size), scaled by its current
 * size every step, as the axisymmetric solver does.  Exact bounds are found
 * only for the elements whose rigorous lower bound (Gershgorin's) can fall
 * below the step: once each, then kept. */
typedef struct {
    long ne;
    const f3_mesh *mesh;
    hex8_element_fn fn; /* the reference K_e, m_e and free dofs */
    void *ctx;
    double *lower;      /* per element: Gershgorin's bound / reference size (0: not checked) */
    double *exact;      /* per element: the exact bound / reference size (0: not computed yet) */
    long n_exact;       /* exact bounds computed so far */
} f3_step_check;

/* The smallest altitude of the parallelepiped spanned by the element's
 * natural-coordinate tangents at its centre (mesh x + u; u may be NULL),
 * det J / max |x_,i x x_,j|: a cube of side h gives h / 2, a cube compressed
 * to lambda h along an axis lambda h / 2; 0 for an inverted element. */
double f3_element_size(const f3_mesh *mesh, long e, const double *u);

/* Elements [e0, ne) with check[e] != 0 (NULL: all) are watched; lam_upper[e]
 * Gershgorin's bound of each (hex8_max_eigenvalue's). */
rf_status f3_step_check_init(f3_step_check *c, const f3_mesh *mesh, long ne, const unsigned char *check,
                             const double *lam_upper, hex8_element_fn fn, void *ctx, rf_error *err);
void f3_step_check_free(f3_step_check *c);
/* The first element whose bound at the current geometry (mesh x + u) is
 * below dt, -1 if none. */
long f3_step_violation(f3_step_check *c, double dt, const double *u);

#endif
