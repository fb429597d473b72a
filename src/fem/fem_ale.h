/* fem_ale.h - ALE rezoning of the axisymmetric updated-Lagrangian slope
 * (docs/validation-plastic.md section 8): the operator split of Benson (1992,
 * "Computational methods in Lagrangian and Eulerian hydrocodes", CMAME
 * 99:235), a Lagrangian step and then, where the mesh has become distorted,
 *
 *   smoothing  the slope's interior nodes relax toward the affine fit of their
 *              neighbours' displacements from the reference mesh (any affine
 *              motion of the reference mesh, rigid ones included, is left as
 *              it is; only the distortion is smoothed), in a zone around the
 *              elements whose stable size fell; the contact surface, the outer
 *              boundary and the layer/bedrock interface stay Lagrangian, axis
 *              nodes move along the axis;
 *   remap      the committed point state (stress, strain, internal
 *              variables) by first-order donor-cell advection with the
 *              exact axisymmetric volumes swept by the element faces
 *              (conservative, exact for a uniform field), the nodal
 *              velocities by interpolation in the old mesh with the z
 *              momentum restored (radial momentum is not conserved in
 *              axisymmetry).
 *
 * The nodal masses stay those of the Lagrangian mesh (the density is not
 * advected): a relocated node carries its mass along.  The energy the remap
 * changes (kinetic, elastic of the remapped stresses, potential of the moved
 * masses) is returned as a separate account, never hidden. */
#ifndef ROCKFUZZ_FEM_ALE_H
#define ROCKFUZZ_FEM_ALE_H

#include "fem_internal.h"
#include "fem_kernel.h"

typedef struct {
    double trigger; /* rezone when a slope element's size ratio (current / reference L_e) falls below */
    double zone;    /* smooth around the elements whose ratio is below this (>= trigger) */
    int sweeps;     /* Gauss-Seidel relaxation sweeps per rezone (0: no node moves) */
} fem_ale_params;

/* What the rezones did, summed over the run. */
typedef struct {
    long rezones;                      /* rezones that moved nodes */
    long nodes_moved;                  /* node relocations, summed */
    double kinetic, elastic, potential; /* energy the remaps added [J] */
    double ratio_min;                  /* smallest size ratio seen before a rezone */
    double move_max;                   /* largest relocation of a node [m] */
} fem_ale_account;

typedef struct {
    fem_ale_params p;
    long nn, e0, e1;       /* nodes; the smoothed block of elements [e0, e1) */
    unsigned char *move;   /* per node: 0 stays, 1 moves in r and z, 2 along the axis only */
    long *nb_ptr, *nb;     /* edge neighbours of each node within the block */
    long *ne_ptr, *ne;     /* elements of the block around each node */
    long *face;            /* 4 per block element: the element across local edge a (-1: none) */
    double *size0;         /* reference size of each block element */
    unsigned char *zone_e; /* scratch per block element */
    unsigned char *zone_n; /* scratch per node */
    long *slot;            /* block element -> row of the means (-1) */
    double *mean, *swept, *vol0, *w1, *hmin, *vnew; /* scratch */
    long nmean;
} fem_ale;

/* The block [e0, e1) (the slope) of mesh; emat (may be NULL): the material
 * of each element (nodes between two materials stay); invm: a node dof with
 * invm 0 is fixed and does not move. */
rf_status fem_ale_setup(fem_ale *A, const fem_mesh *mesh, long e0, long e1, const unsigned char *emat,
                        const double *invm, const fem_ale_params *p, rf_error *err);
void fem_ale_free(fem_ale *A);

/* Element size L = area / longest diagonal at X + u (u may be NULL: the reference); 0 if inverted. */
double fem_ale_element_size(const fem_mesh *mesh, long e, const double *u);
/* Smallest size ratio (current / reference) of the block's elements at X + u. */
double fem_ale_ratio_min(const fem_ale *A, const fem_mesh *mesh, const double *u);

/* The mesh motion delta (2 per node, zeroed here) for the elements below
 * the zone ratio and two rings around them; returns the nodes moved. */
long fem_ale_smooth(fem_ale *A, const fem_mesh *mesh, const double *u, double *delta);
/* Remap the committed state of the updated-Lagrangian point kernel k (the
 * block's kernel) from X + u to X + u + delta, and move its committed
 * geometry; *elastic: the change of the elastic energy of the committed
 * stresses (0 if the law has none). */
rf_status fem_ale_remap_points(fem_ale *A, const fem_mesh *mesh, const double *u, const double *delta, fem_kernel *k,
                               double *elastic, rf_error *err);
/* Velocities of the moved nodes interpolated in the mesh X + u at their new
 * positions, the z momentum of the moved nodes restored; returns the change
 * of kinetic energy [J]. */
double fem_ale_remap_velocity(fem_ale *A, const fem_mesh *mesh, const double *u, const double *delta,
                              const double *mass, const double *invm, double *v);

/* One rezone if the block's smallest size ratio fell below the trigger:
 * smooth, remap the state of k and the velocities, u += delta; fgrav (may
 * be NULL): the gravity load, for the potential energy of the moved masses.
 * Returns the nodes moved (0: nothing changed, to the bit), < 0 on error. */
long fem_ale_rezone(fem_ale *A, const fem_mesh *mesh, double *u, double *v, const double *mass,
                    const double *invm, const double *fgrav, fem_kernel *k, double *delta, fem_ale_account *acc,
                    rf_error *err);

#endif
