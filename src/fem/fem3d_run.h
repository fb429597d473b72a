/* fem3d_run.h - the state of one 3D impact run (solid_run) and the stages
 * its files share.  The run is grouped by what owns each member: the
 * settings (what was asked and what follows before the mesh), the bodies
 * (materials, laws, kernels chosen), the grid (mesh and its sizes), the
 * system (assembled arrays and the state u, v), the time step, the absorbing
 * boundary, the contact and its account over the run, the rigid boulder and
 * gravity.
 *
 * The files are layers (tools/check_layers.py: no call circle), each calling
 * only those above it in this list:
 *   fem3d_prepare.c   check, automatic settings, Hertz reference, sizing and mesh
 *   fem3d_assemble.c  arrays, topology, elements, masses, time step, kernels,
 *                     dashpots, contact set-up, initial state; release
 *   fem3d_step.c      one step (dashpots, internal force, predictor, contact,
 *                     account) and the energies of the history row
 *   fem3d_extract.c   rigid-body state, separation, VTK frame, outputs,
 *                     history and report of the final state
 *   fem3d_solver.c    the driver's stage table and the public entries
 *   fem3d_gravity_run.c  fem3d_gravity_free_run (the gravity test hook)
 * Internal header. */
#ifndef ROCKFUZZ_FEM3D_RUN_H
#define ROCKFUZZ_FEM3D_RUN_H

#include "rockfuzz/fem3d.h"
#include "rockfuzz/impact.h"
#include "rockfuzz/material.h"

#include "fem3d_gravity.h"
#include "fem3d_internal.h"
#include "fem3d_large.h"
#include "fem3d_spec.h"
#include "fem_core.h"
#include "fem_kernel.h"
#include "fem_tuning.h"

/* Buffers of the 3D solver in the workspace pool. */
enum { Q_K, Q_FE, Q_FEL, Q_INC_PTR, Q_INC, Q_U, Q_V, Q_F, Q_FEXT, Q_MASS, Q_INVM, Q_DASH, Q_ELM, Q_LAMX, Q_FIXED,
       Q_OUTER, Q_UB, Q_VTK, Q_EMAT, Q_USE2, Q_DASHL, Q_DNRM, Q_LAMU, Q_ULE, Q_FGRAV, Q_MSHIFT };

/* What the run was asked, and what follows from it before the mesh. */
typedef struct {
    const rf_impact_input *in;
    rf_impact_input ground; /* *in with the ground's inclination (f3_ground_angle) as its slope angle: gravity's */
    rf_fem_options o;
    rf_fem_tuning t;      /* o.tuning's values, or the defaults */
    rf_fem3d_options o3;
    rf_hertz_reference H;
    double V, Vn, Vt;     /* impact speed and its normal and tangential components [m/s] */
    double L;             /* slope domain radius [m] */
    double a_box;         /* contact radius the fine boxes cover (the larger of slope and layer) [m] */
    f3_layer_contact lc;  /* the layer's contact estimate (fem3d_spec.h); lc.thick: it alone sizes the mesh */
    int threads;
    int fixed_outer;      /* the outer surface fixed (else absorbing dashpots) */
    int no_contact;       /* fem3d_gravity_free_run: no contact step */
} solid_settings;

/* The three bodies (0 boulder, 1 slope: the bedrock under a layer, 2 layer)
 * and the laws and kernels chosen for them. */
typedef struct {
    f3_material mat[3];
    rf_wave_speeds w[3];
    rf_material matl[3];  /* constitutive law of each (plastic[b] != 0: not elastic) */
    fem_lame lame[3];     /* parameters of the linear point laws (kernel = points) */
    int plastic[3];
    int work_account;     /* energies from the internal work (a plastic body, large deformation, gravity) */
    int large;            /* large deformation (rf_fem_large_deformation); work_account then too */
    int ul[2];            /* body b on the updated-Lagrangian kernel: large and (on, or the body plastic) */
    int layer, rigid;     /* a layer over the slope (fem3d_layer.c); a rigid boulder (fem3d_rigid.c) */
} solid_bodies;

/* The mesh and its sizes. */
typedef struct {
    f3_mesh_spec ms;
    f3_mesh mesh;
    int have_mesh;
    double h, hb;         /* slope and boulder element size at the contact [m] */
    double sym_factor;    /* full body / model: 2 for the half model */
    long nn, ne, ndof, nbn; /* nodes, elements, dofs, boulder nodes (the first nbn) */
    unsigned char *emat;  /* material of each element: 0 boulder, 1 slope, 2 layer */
    long crater_node;     /* the slope's surface node at the first-contact point */
} solid_grid;

/* The assembled system and the state. */
typedef struct {
    f3_system S;
    float *K;
    double *u, *v, *f, *fext, *mass, *invm, *elm, *lamx;
    unsigned char *fixed;
    double *mshift;       /* per node: mass added by the contact face's redistribution [kg, model] (or NULL) */
    long shifted_elems;   /* contact-face elements whose masses were redistributed */
    double mesh_mass_b;   /* the boulder mesh's mass before the density correction [kg, model] */
    double Mb, ke0;       /* boulder mass [kg] and initial kinetic energy [J] (model) */
    int mass_moments_ok;
} solid_system;

/* The time step and, in large deformation, its check. */
typedef struct {
    double dt, dt_bound, dt_edge;
    double *lamu;         /* large: each element's Gershgorin bound of lambda_max (reference geometry) */
    unsigned char *ul_elem; /* large: per element, on the UL kernel (the step check watches those) */
    f3_step_check check;  /* large: the elements' step bounds at their current size */
    long unstable;        /* large: an element whose current step bound fell below dt (-1: none) */
} solid_timestep;

/* The absorbing boundary (dashpots on the outer surface). */
typedef struct {
    int *outer;           /* outer slope nodes */
    long nouter;
    double *dash, *dashl; /* tributary areas of the slope's and the layer's faces [m^2] */
    double *dnrm;         /* outer normals (extruded mesh) */
    double dash_ratio;    /* largest dt C / m of an explicit dashpot (stable below 2) */
} solid_boundary;

/* The account of the run: works and contact statistics. */
typedef struct {
    double W_n, W_fric, W_abs; /* normal contact, friction and dashpot work [J] (model) */
    double W_int[2];      /* internal work of each body so far [J] (model, not full body) */
    double pen_max, slip_max, pgs_res_max;
    double depth_max;     /* deepest position of the boulder's lowest point below z = 0 [m] */
    long stick_steps, pair_steps;
    long unlocated_steps; /* pair-steps in contact whose master point was not found to tolerance */
    int pgs_sweeps_max, outside_contact;
    double sep_v[3], sep_w; /* with gravity: CM velocity (x, y, z) and spin when the contact last opened */
} solid_account;

/* The state of one 3D run. */
typedef struct {
    solid_settings set;
    solid_bodies body;
    solid_grid grid;
    solid_system sys;
    solid_timestep step;
    solid_boundary bound;
    f3_contact C;
    solid_account acc;
    f3_rigid B;
    f3_gravity grav;      /* gravity (fem3d_gravity.c); grav.g = 0: none */
    fem_pool *pool;
} solid_run;

/* fem3d_prepare.c: check, resolve the automatic settings, Hertz reference
 * (opt, o3 NULL: the defaults); sizing and meshing. */
rf_status f3_run_prepare(solid_run *R, const rf_impact_input *in, const rf_fem_options *opt,
                        const rf_fem3d_options *o3, rf_error *err);
rf_status f3_run_mesh(solid_run *R, rf_error *err);

/* fem3d_assemble.c: assembly and initial state; release of what a run owns
 * beyond the pool. */
rf_status f3_run_assemble(solid_run *R, rf_error *err);
void f3_run_release(solid_run *R);

/* fem3d_step.c: one step (dashpots, internal force, pairing, predictor,
 * contact, account); the energies at t_{n+1/2} and the history row;
 * the plastic dissipation of body b so far [J] (model). */
rf_status f3_run_step(solid_run *R, double *Fc, double *rad, rf_error *err);
void f3_run_energy(solid_run *R, double t, double Fc, double rad, double row[13], double *comp, double *closure);
double f3_run_plastic_work(const solid_run *R, int b);

/* fem3d_extract.c: the VTK frame of u_n; the state at separation (gravity);
 * outputs, history and report of the final state. */
rf_status f3_run_vtk(solid_run *R, int frame, double t, rf_error *err);
void f3_run_separation(solid_run *R);
void f3_run_extract(solid_run *R, fem_run *run, long nsteps, rf_impact_output *out, rf_fem_history *hist,
                   rf_fem3d_report *rep);

#endif
