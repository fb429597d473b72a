/* fem_axi_run.h - the state of one axisymmetric impact run and the stages
 * its files share (docs/fem-internals.md).  The run is split by idea:
 *   fem_axi_setup.c     check, automatic settings, Hertz reference, sizing and meshing, release
 *   fem_axi_force.c     the internal force (element kernels, node-ordered gather) and the commit
 *   fem_axi_assemble.c  arrays, element matrices, masses and time step, kernels, dashpots,
 *                       contact pairs, gravity's geostatic state and body load
 *   fem_axi_step.c      one time step (dashpots, predictor, contact, ALE rezone), its stability
 *   fem_axi_account.c   the energy account of a step and the outputs of the final state
 *   fem_solver.c        the driver's table of stages (fem_driver.h) and the public entries
 * A file calls only the files above it in this list (tools/check_layers.py:
 * no call circles between object files). */
#ifndef ROCKFUZZ_FEM_AXI_RUN_H
#define ROCKFUZZ_FEM_AXI_RUN_H

#include "fem_ale.h"
#include "fem_core.h"
#include "fem_internal.h"
#include "fem_kernel.h"
#include "rockfuzz/fem.h"

/* Buffers of the axisymmetric solver in the workspace pool. */
enum { P_K, P_FE, P_INC_PTR, P_INC, P_INVM, P_MASS, P_U, P_V, P_F, P_FEXT, P_DASH, P_OUTER, P_ELM, P_FIXED, P_VTK,
       P_EMAT, P_USE2, P_DTE, P_PACK0, P_PACK1, P_FGRAV, P_MSHIFT, P_ALE };

/* What the run was asked and what follows from it (axi_prepare). */
typedef struct {
    const rf_impact_input *in;
    rf_fem_options o;     /* the options with their automatic values resolved */
    rf_fem_tuning t;      /* o.tuning's values, or the defaults */
    rf_hertz_reference H; /* with a layer: the finer contact radius, the longer duration */
    double V, L;          /* impact speed [m/s], domain radius [m] */
    int threads, fixed_outer;
    int layer;            /* a layer of thickness in->layer_thickness over the slope */
    int rigid;            /* a rigid boulder: no internal force, one vertical velocity */
    int large;            /* updated Lagrangian kernels and contact on the current surfaces */
    int work_account;     /* energy from the internal work (a plastic body, large deformation) */
    int no_contact;       /* fem_axi_slope_at_rest: the slope alone (no contact step) */
} axi_settings;

/* The bodies: boulder, slope (bedrock), layer. */
typedef struct {
    fem_material mat[3];
    rf_wave_speeds w[3];
    rf_material matl[3];  /* constitutive law of each body (plastic[b] != 0: not elastic) */
    int plastic[3];
    fem_lame lame[2];     /* parameters of the point laws */
    fem_kernel kernel[2]; /* boulder and slope blocks */
    unsigned char *emat;  /* material of each element: 0 boulder, 1 slope, 2 layer */
} axi_bodies;

/* The mesh's sizes and the assembled system (pool buffers). */
typedef struct {
    double h, hb;         /* element size at the contact in the slope, in the boulder [m] */
    double fine_r;        /* the slope's uniform fine zone reaches r = fine_r [m] */
    int have_mesh;
    long nn, ndof, ne, nbd; /* nodes, dofs, elements, boulder dofs (the first ones) */
    double *K, *fe;       /* element stiffness matrices (64 each), element forces (8 each) */
    double *invm, *mass;  /* per dof: lumped mass and its inverse (0 on a fixed dof) */
    double *u, *v, *f, *fext; /* displacement u_n, velocity v_{n-1/2}, internal force, dashpot force */
    double *dash;         /* per outer node: dashpot coefficients, normal (even) and tangential (odd) */
    long *inc_ptr, *inc;  /* node -> (element * 4 + local node), in element order */
    int *outer;           /* the outer (dashpot) nodes */
    long nouter;
    double *mshift;       /* per node: mass added by the contact face's redistribution [kg] (or NULL) */
    long shifted_elems;   /* contact-face elements whose masses were redistributed */
    double mesh_mass_b;   /* the boulder mesh's own mass before scaling to the spheroid's [kg] */
    double Mb;            /* the boulder's mass [kg] */
} axi_system;

/* The time step and its stability. */
typedef struct {
    double dt, dt_bound, dt_edge; /* step, its eigenvalue bound, the edge transit bound [s] */
    double *dte;          /* large deformation: each element's step bound 2/sqrt(lambda_e) per unit of
                             its size L_e = area / longest diagonal (0: not checked) */
    long unstable;        /* large deformation: an element whose current step bound fell below dt (-1: none) */
} axi_timestep;

/* The energy account's running sums. */
typedef struct {
    double ke0;           /* initial kinetic energy [J] */
    double W_abs;         /* work absorbed by the dashpots [J] */
    double W_int[2];      /* internal work of each body so far [J] */
    double pen_max;       /* deepest position of the boulder's lowest point below z = 0 [m] */
} axi_account;

/* Gravity (docs/validation-plastic.md "Gravity"): g > 0 gives the body load fgrav
 * (the boulder's lumped weight, the slope's geostatic internal force at u = 0),
 * its work W_grav, the elastic energy E0 of the geostatic stress and the
 * count of points whose geostatic state the law does not admit. */
typedef struct {
    double g, *fgrav, W_grav, E0;
    long geo_outside;
} axi_gravity_load;

/* ALE rezoning of the slope (fem_ale.h; large deformation, option ale). */
typedef struct {
    int on;
    fem_ale state;
    fem_ale_account acc;
    double *delta;
} axi_ale;

/* The state of one axisymmetric run. */
typedef struct {
    axi_settings set;
    axi_bodies body;
    fem_mesh mesh;
    axi_system sys;
    axi_timestep ts;
    axi_account acc;
    axi_gravity_load grav;
    fem_contact C;
    axi_ale ale;
    fem_pool *pool;
} axi_run;

/* fem_axi_setup.c: check, resolve the automatic settings, take the Hertz reference;
 * size and build the mesh; free what the run holds outside the pool. */
rf_status axi_prepare(axi_run *S, const rf_impact_input *in, const rf_fem_options *opt, rf_error *err);
rf_status axi_mesh(axi_run *S, rf_error *err);
void axi_free(axi_run *S);

/* fem_axi_force.c: f = f_int(u); the kernels' acceptance of the state they last saw. */
void axi_internal_force(const axi_run *S, const double *u, double *f);
void axi_commit(axi_run *S);

/* fem_axi_assemble.c: the system, its time step and the initial state. */
rf_status axi_assemble(axi_run *S, rf_error *err);

/* fem_axi_step.c: one step (total contact force *Fc, contact radius *rad); the first
 * element whose step bound fell below dt in large deformation (-1: none). */
rf_status axi_step(axi_run *S, double *Fc, double *rad, rf_error *err);
long axi_step_violation(const axi_run *S);

/* fem_axi_account.c: a step's energies, history row, compression and closure error;
 * the outputs and diagnostics of the final state. */
void axi_energy(const axi_run *S, double t, double Fc, double rad, double row[13], double *comp, double *closure);
void axi_extract(axi_run *S, const fem_run *R, long nsteps, rf_impact_output *out, rf_fem_history *hist);

#endif
