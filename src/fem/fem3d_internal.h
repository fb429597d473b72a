/* fem3d_internal.h - data shared by the parts of the 3D impact solver: the
 * mesh (fem3d_mesh.c), the hexahedron routines (fem3d_element.c), the
 * contact with friction (fem3d_contact.c), the internal force
 * (fem3d_force.c) and the stages of the run (fem3d_run.h: fem3d_prepare.c,
 * fem3d_assemble.c, fem3d_step.c, fem3d_extract.c, fem3d_solver.c). */
#ifndef ROCKFUZZ_FEM3D_INTERNAL_H
#define ROCKFUZZ_FEM3D_INTERNAL_H

#include <stddef.h>

#include "fem_tuning.h"
#include "rockfuzz/status.h"

#include "core/util.h"
#include "fem_kernel.h"

enum { F3_BOULDER = 0, F3_SLOPE = 1 };
/* Master nodes per contact pair: the 4 x 4 grid nodes of the C1 (Catmull-Rom) master face
 * around the quad under the slave (fem3d_contact.c). */
enum { F3_NM = 16 };

/* Node flags */
enum { F3_SYM = 1, F3_OUTER = 2, F3_SURFACE = 4 };

/* Structured fine box at the contact point of one body: uniform cubes of size
 * h, x in [-nxm h, nxp h], y in [-ny h, ny h] (or [0, ny h] for the half
 * model), z in [-nz h, 0] in the body's half-space coordinates. */
typedef struct {
    int nxm, nxp, ny, nz;
    double h;
} f3_box;

typedef struct {
    long n_nodes, n_elems;
    double *x;             /* 3 per node [m] */
    unsigned char *flags;  /* F3_SYM / F3_OUTER / F3_SURFACE */
    int *conn;             /* 8 per element, positive Jacobian */
    long boulder_nodes, boulder_elems; /* nodes/elements [0, boulder_*) are the boulder */
    /* contact faces: the fine boxes' top faces as node grids, index
       [i * nyt + j] for i along x and j along y */
    int nxt_b, nyt_b, nxt_s, nyt_s;
    int *top_b, *top_s;
    double x0_s, y0_s, h_s; /* slope top grid: node (i, j) at (x0 + i h, y0 + j h, 0) */
    /* outer surface quads of the slope (dashpots) */
    long n_outer_quads;
    int *outer_quads;      /* 4 per quad */
    int extruded;          /* the slope is the extruded mesh of fem3d_layer.c (a cylinder, not a hemisphere) */
} f3_mesh;

typedef struct {
    f3_box boulder, slope;
    int full;              /* full model (else y >= 0) */
    double radius;         /* boulder sphere radius before the affine map [m] */
    double scale_xy, scale_z; /* affine spheroid map x,y *= scale_xy, z *= scale_z about the pole */
    double boulder_inner;  /* radius of the boulder's half-space image / radius */
    double domain;         /* slope hemisphere radius [m] */
    double layer_aspect;   /* radial/tangential size ratio of the layers */
    int extruded;          /* slope as the extruded mesh with horizontal node planes (fem3d_layer.c) */
    double layer_depth;    /* > 0: a node plane at z = -layer_depth (extruded mesh) [m] */
} f3_mesh_spec;

/* Mass redistribution at the slope's contact face (fem3d_mass.c): each slope element with
 * a face on the contact face (face[node] != 0) whose Gershgorin bound lam_upper[e] is below
 * kappa lam_max keeps alpha = max(FEM_MASS_KEPT_MIN (fem_core.h), lam_upper[e] / (kappa lam_max)) of its face
 * nodes' masses elm and gives the rest to the node below each; lam_upper[e] becomes
 * lam_upper[e] / alpha.  Returns the number of elements changed. */
long f3_surface_mass_shift(const f3_mesh *mesh, const unsigned char *face, double *elm, double *lam_upper,
                           double lam_max, double kappa);

rf_status f3_mesh_build(const f3_mesh_spec *spec, f3_mesh *mesh, long max_elements, rf_error *err);
void f3_mesh_free(f3_mesh *mesh);
/* The extruded slope (fem3d_layer.c): its node, element and outer-quad
 * counts, and the fill of nodes [n0, ...) and elements [e0, ...) of m (also
 * top_s, nxt_s, nyt_s and the outer quads). */
void f3_slab_counts(const f3_mesh_spec *spec, long *nodes, long *elems, long *outer_quads);
rf_status f3_slab_fill(const f3_mesh_spec *spec, f3_mesh *m, long n0, long e0, rf_error *err);

/* Weight the boulder's element-node masses elm (8 per boulder element) so
 * that their sum is M, their centre of mass is (X0, ., Z0) and their moment
 * of inertia about the y axis through it is Iyy (fem3d_mass.c).  Returns 0
 * (elm unchanged) if no positive weighting was found. */
int f3_boulder_mass_moments(const f3_mesh *mesh, double *elm, double M, double X0, double Z0, double Iyy);

typedef struct {
    double rho, E, nu;
} f3_material;

/* Element stiffness (24 x 24, row-major, dofs x0 y0 z0 x1 ...), lumped nodal
 * masses (row sums of the consistent mass) and volume; 2x2x2 Gauss. */
void f3_hex_matrices(const double x[24], const f3_material *mat, double K[576], double m[8], double *volume);
/* dN_a/dx_j at the 8 Gauss points (dN[q][a][j], points ordered as the nodes,
 * xi = XI[q] / sqrt 3 ...) and their weights det J (Gauss weights are 1). */
void f3_hex_gradients(const double x[24], double dN[8][8][3], double w[8]);
/* Jacobian determinant at the element centre (orientation check). */
double f3_hex_center_jacobian(const double x[24]);
void f3_hex_orient(const double *x, int *c); /* fem3d_element.c: positive Jacobian */
/* Largest eigenvalue of M_e^-1 K_e over the free dofs (Householder + Sturm
 * bisection: exact for a 24 x 24 matrix up to round-off). */
double f3_hex_lambda_max(const double K[576], const double m[8], const unsigned char free_dof[24]);

/* The settings and statistics of a contact solve (projected Gauss-Seidel). */
typedef struct {
    double friction;     /* Coulomb coefficient */
    double tol;          /* converged when no multiplier changes by more than tol [m, as increments] */
    double band;         /* pairs with a predicted gap below band [m] are candidates of the solve */
    int max_sweeps;
    int sweeps;          /* statistics of the last solve */
    double residual;
} f3_contact_solver;

/* Contact of the boulder's fine-box face nodes (slaves) on the slope's
 * fine-box face (a uniform grid of master quads in the plane z = 0): each
 * step, every slave is paired with the master point under its current
 * tangential position; the master face is the C1 Catmull-Rom surface of the
 * 4 x 4 grid nodes around that point (F3_NM weights), the normal row carries
 * its deformed slope, and the forward-increment multipliers are found by
 * projected Gauss-Seidel in slave order (deterministic). */
typedef struct {
    long nslave;
    int *slave;          /* boulder node ids */
    double *lam;         /* 3 per slave: normal, tangential x, y [N]; the next step's start */
    int *mnode;          /* F3_NM master node ids per slave (this step; a repeated id has weight 0) */
    double *N;           /* F3_NM Catmull-Rom weights per slave */
    double *S;           /* 2 per slave: slope d u_z / d(x, y) of the deformed master face */
    double *gap;         /* predicted normal gap [m] */
    double *ds;          /* 3 per slave: predicted relative displacement increment of the step [m] */
    double *s0;          /* 3 per slave: relative displacement at step n [m] */
    double *A;           /* 3 per slave: diagonal of dt^2 G M^-1 G^T */
    double *gvo;         /* 3 per slave: G v_{n-1/2} (normal, t_x, t_y rows) */
    double *Xm;          /* 2 per slave: its master material point (X, Y) at the last pairing, where the
                            next one starts (set to the slave's reference position before the first) */
    unsigned char *outside; /* 1: slave beyond the master grid (clamped); 2: its master point not found */
    int *cand;
    long ncand;
    double *du;          /* 3 per node scratch, zero between calls */
    /* A rigid boulder (rigid_invm > 0; its nodes' invm are 0): every slave moves with
       its CM (x, z) and rotation about y; the corrections of a solve accumulate in
       rigid_du (the solver applies and zeroes them, f3_rigid_correct). */
    double rigid_invm, rigid_invi; /* 1 / M, 1 / I_yy (model) */
    double rigid_c[2];   /* its CM (x, z) in the predicted state [m]; set before f3_contact_predict */
    double rigid_du[3];  /* CM displacement (x, z) [m] and rotation [rad] of the corrections */
    double *rr;          /* 2 per slave: (x, z) from the CM in the predicted state [m] */
    /* Sphere mode (rf_fem_options.sphere_contact_3d, a rigid spherical boulder): the slaves are the
       slope's face nodes (top_s order) and the master is the boulder's exact sphere of radius
       `radius` about rigid_c; no master nodes.  s0 holds the slave's u at step n and gvo its
       v_{n-1/2} (vectors, not row products); the rows are orthonormal (wr). */
    int sphere;
    double radius;
    double body_d[3];    /* the rigid predictor's step: CM (x, z) [m] and rotation [rad] */
    double body_vo[3];   /* the body's (V_x, V_z, omega) at n-1/2 */
    double body_v[3];    /* ... and at n+1/2 after the correction (set before the account) */
    double *wr;          /* 9 per slave: unit normal (out of the sphere) and tangents t1, t2 */
    f3_contact_solver solve;
} f3_contact;

/* Pair every slave with the master quad under its position x + u (u at step
 * n) if repair (else keep the pairing); store the relative displacement at n and
 * G v_{n-1/2}.  Inside a parallel region its threads share the slaves, with
 * no barrier at the end (synchronise before u or v change). */
void f3_contact_locate(f3_contact *C, const f3_mesh *mesh, const double *u, const double *v, int threads,
                       int repair);
/* Relative vector of pair k: slave minus master point, of any per-dof field. */
void f3_contact_rel(const f3_contact *C, long k, const double *v, double r[3]);
/* G v of pair k: its rows n = (-S_x, -S_y, 1), t_x = (1, 0, S_x), t_y = (0, 1, S_y) on the
   relative vector (or any per-dof field). */
void f3_contact_gv(const f3_contact *C, long k, const double *v, double g[3]);
/* G v_{n-1/2} of pair k (its rows at the account on the stored old velocities). */
void f3_contact_gvo(const f3_contact *C, long k, double g[3]);
/* Gap of pair k after the correction (u at n+1; in sphere mode rigid_c the corrected centre) [m]. */
double f3_contact_gap_now(const f3_contact *C, const f3_mesh *mesh, long k, const double *u);
/* Normal and tangential force magnitudes of pair k's multipliers [N]. */
void f3_contact_forces(const f3_contact *C, long k, double *Fn, double *Ft);
/* Predicted gaps and slip increments from the predicted displacements. */
void f3_contact_predict(f3_contact *C, const f3_mesh *mesh, const double *u, const double *invm, double dt,
                        int threads);
/* Multipliers for the predicted state; adds the corrections to u and v. */
rf_status f3_contact_solve(f3_contact *C, const double *invm, double dt, double *u, double *v, rf_error *err);

/* A rigid boulder (fem3d_rigid.c): planar rigid motion, CM translation
 * (x, z) and rotation theta about y (v = V + omega x r, omega = (0, w, 0)). */
typedef struct {
    int on;
    double M, I;      /* model mass [kg] and I_yy about the CM [kg m^2] */
    double c0[3];     /* reference CM [m] */
    double X[2], th;  /* CM displacement (x, z) [m] and rotation [rad] at step n */
    double V[2], w;   /* CM velocity (x, z) [m/s] and angular velocity [rad/s] at n - 1/2 */
} f3_rigid;

/* The rigid boulder's kernel: no internal force (zeroes its elements' fe once). */
void f3_rigid_kernel(fem_kernel *k, long first, long count, double *fe);
/* Boulder nodes [0, nbn) placed from the rigid state: u (of X0) and v. */
void f3_rigid_place(const f3_rigid *B, const f3_mesh *mesh, long nbn, double *u, double *v);
/* Predictor X += dt V, theta += dt w; the contact's correction du = (dX, dZ,
 * dtheta) applied to position and velocity (du / dt), du zeroed. */
void f3_rigid_predict(f3_rigid *B, double dt);
void f3_rigid_correct(f3_rigid *B, double du[3], double dt);
/* Kinetic energy 1/2 M V^2 + 1/2 I w^2 [J]. */
double f3_rigid_energy(const f3_rigid *B);

/* The internal-force system of the 3D model (fem3d_force.c). */
typedef struct {
    long nn, ne, ndof, nbn;
    const f3_mesh *mesh;
    fem_kernel kernel[2]; /* boulder and slope blocks */
    double *fe;     /* 24 per element */
    long *inc_ptr;  /* node -> (element * 8 + local) list, in element order */
    long *inc;
    const double *mass; /* per dof */
    double Mb, c0[3]; /* boulder mass (model) and reference CM */
    int full;
    double R[9], c[3]; /* boulder rotation and CM of the last internal_force call */
    double p, q;       /* atan2 arguments of the rotation angle */
    double *fel;       /* boulder element forces in the boulder frame, 3 per node */
    double *ub;        /* boulder displacements in its frame, 3 per node (matrix-free kernels) */
    int threads;
} f3_system;

/* f = f_int(u) (element forces by the kernels, node-ordered gather; the
 * boulder co-rotational); keeps the boulder frame of u for f3_boulder_strain. */
void f3_internal_force(f3_system *S, const double *u, double *f);
/* Loops and sums over n nodes run in F3_CHUNKS fixed chunks, chunk k being nodes
 * [f3_chunk_begin(n, k), f3_chunk_begin(n, k + 1)). */
enum { F3_CHUNKS = 64 };
static inline long f3_chunk_begin(long n, int k)
{
    return n * k / F3_CHUNKS;
}
/* The same with work run by every thread of its parallel region (ctx shared): first at the
 * start (it must not change u; orphaned `omp for nowait` loops are the way to share it), last
 * at the end, with no barrier before it: f is complete at the slope's nodes, and at the
 * boulder's nodes of chunk k (of nbn) once `#pragma omp for schedule(static)` over k in
 * [0, F3_CHUNKS) reaches it (that loop form gives each thread the chunks whose last term it
 * added itself). */
typedef struct {
    void (*first)(void *ctx), (*last)(void *ctx);
    void *ctx;
} f3_force_hooks;
void f3_internal_force_hooked(f3_system *S, const double *u, double *f, const f3_force_hooks *hooks);
/* Strain energy of the boulder, 1/2 f_el(n)' u_el(n+1) in the frame of the last f3_internal_force. */
double f3_boulder_strain(const f3_system *S, const double *u);
/* The sums of the energy account, each in a fixed order (the same bits for any thread count):
 * per body sum m v^2 (boulder dofs first), the boulder's sum m v_z and m u_z, the slope's
 * sum f . u, and f3_boulder_strain (the only one computed when v or f is NULL). */
typedef struct {
    double mv2[2], boulder_pz, boulder_uz, slope_fu, boulder_strain;
} f3_state_sums;
void f3_state_sums_compute(const f3_system *S, const double *u, const double *v, const double *f,
                           f3_state_sums *out);

/* One VTK frame (fem3d_vtk.c): dir/fem_NNNN.vtu of the mesh with u, v, the
 * cell stresses and plastic strains of the kernels (elastic kernels: from u,
 * the boulder's from S->ub, its co-rotated field of the last
 * f3_internal_force); the .pvd index is fem_vtk_index (fem_internal.h). */
rf_status f3_vtk_frame(const char *dir, int frame, double t, const f3_system *S, const double *u, const double *v,
                       const f3_material mat[2], rf_error *err);

#endif
