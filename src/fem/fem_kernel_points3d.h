/* fem_kernel_points3d.h - what the hexahedron's integration-point kernel
 * (fem_kernel_points3d.c, small strain) shares with its updated-Lagrangian
 * form (fem_kernel_points3d_large.c): the block layout, the kernel's data and
 * the SIMD block helpers (kinematics, laws lane by lane, force).  Internal
 * header. */
#ifndef ROCKFUZZ_FEM_KERNEL_POINTS3D_H
#define ROCKFUZZ_FEM_KERNEL_POINTS3D_H

#include "fem_kernel.h"
#include "hex8_kernel.h"

#include <string.h>

#define P3_NQ 8 /* Gauss points per element */
#define P3_NC 6 /* strain components: xx yy zz xy yz zx */
enum { P3_W = HEX8_W }; /* elements per block (one vector lane each) = per work unit of forces_field */

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define P3_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define P3_CLONES
#endif

typedef double p3_vec __attribute__((vector_size(P3_W * sizeof(double))));

typedef struct {
    fem_point_law law, law2;
    unsigned char *use2;  /* per element: law2 (NULL: law everywhere) */
    long nblk;
    int *conn;            /* per block [8 nodes][W] node ids */
    long *lane;           /* per block [W]: local element number, -1 for padding */
    double *G;            /* per block [8 points][8 nodes][3][W]: dN/dx (0 in padding) */
    double *wb;           /* per block [8 points][W]: det J (1 in padding) */
    double *w;            /* per point (8 le + q): det J (updated Lagrangian: of the committed geometry) */
    int bbar;
    double *eps, *sig, *var;       /* committed, per point */
    double *eps_t, *sig_t, *var_t; /* trial of the last forces() */
    double plastic_work, plastic_strain_max;
    long point_max;
    /* updated Lagrangian (fem_kernel_points_hex_large), per block [24 dofs][W]:
       reference node coordinates, committed and trial displacements; w_t (per
       point) the weights of the trial (current) geometry */
    double *X, *uc, *ut, *w_t;
} p3_data;

static inline void p3_vget(p3_vec *v, const double *p)
{
    memcpy(v, p, sizeof *v);
}

/* Strains of the block's points from the displacements ue (engineering
 * shear), the dilatation replaced by its element mean if bbar; spin (NULL: not
 * wanted) the rotation vector 1/2 curl ue at each point. */
void p3_block_strains(const double *G, const double *wb, const p3_vec ue[24], int bbar, p3_vec eps[P3_NQ][P3_NC],
                      p3_vec spin[P3_NQ][3]);
/* F = sum_q w_q B_q^T s_q, s_q = sigma_q with the pressure replaced by its element mean if bbar. */
void p3_block_force(const double *G, const double *wb, const p3_vec sig[P3_NQ][P3_NC], int bbar, p3_vec F[24]);
/* The point laws, lane by lane: trial stress and state of block b.  spin
 * NULL: eps are total strains (small strain).  Else eps are the strain
 * increments and the committed stress is first turned by the Hughes-Winget
 * rotation of spin (rf_material_rotate). */
void p3_block_laws(const p3_data *d, long b, const p3_vec eps[P3_NQ][P3_NC], const p3_vec spin[P3_NQ][3],
                   p3_vec sig[P3_NQ][P3_NC]);
/* Block b's nodal values of the field u (3 per node) as [24][W]. */
void p3_block_gather(const p3_data *d, long b, const double *u, double ul[24][P3_W]);
/* Element forces of block b's lanes to fe + 24 (first + le). */
void p3_block_scatter(const p3_data *d, long b, long first, const double fl[24][P3_W], double *fe);

/* The kernel's points as fem_points_state.c sees them; commit (accept the
 * trial state), destroy and report, shared by both forms. */
fem_points_view p3_view(const fem_kernel *k);
void p3_accept(fem_kernel *k);
void p3_destroy(fem_kernel *k);
void p3_report(const fem_kernel *k, fem_kernel_report *r);
/* 1 if k is a hexahedron point kernel of either form. */
int p3_is(const fem_kernel *k);

#endif
