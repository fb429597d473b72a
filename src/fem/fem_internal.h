/* fem_internal.h - data shared by the parts of the axisymmetric impact solver:
 * the mesh (fem_mesh.c), the element routines (fem_element.c), the contact
 * (fem_contact.c), VTK output (fem_vtk.c) and the stages of the run
 * (fem_solver.c and the fem_axi_*.c files, over the run state of fem_axi_run.h). */
#ifndef ROCKFUZZ_FEM_INTERNAL_H
#define ROCKFUZZ_FEM_INTERNAL_H

#include <stddef.h>

#include "fem_tuning.h"
#include "rockfuzz/fem.h"
#include "rockfuzz/status.h"

#include "core/util.h"

#ifndef M_SQRT2
#define M_SQRT2 1.41421356237309504880
#endif

enum { FEM_BOULDER = 0, FEM_SLOPE = 1 };

/* Node flags */
enum { FEM_AXIS = 1, FEM_OUTER = 2, FEM_SURFACE = 4 };

typedef struct {
    long n_nodes, n_elems;
    double *r, *z;        /* node coordinates [m] */
    unsigned char *flags; /* FEM_AXIS / FEM_OUTER / FEM_SURFACE */
    int *conn;            /* 4 per element, counter-clockwise in (r, z) */
    unsigned char *ebody; /* FEM_BOULDER / FEM_SLOPE per element */
    /* Nodes [0, boulder_nodes) and elements [0, boulder_elems) are the boulder. */
    long boulder_nodes, boulder_elems;
    /* Surface nodes ordered by increasing r from the first-contact point. */
    long n_bsurf, n_ssurf;
    int *bsurf, *ssurf;
} fem_mesh;

/* Parameters of the structured graded quarter-disc mesher of one body. */
typedef struct {
    double h;       /* element size in the fine core [m] */
    int n;          /* core divisions (core is n x n squares of size h) */
    double grading; /* size growth per element outside the core */
    double h_far;   /* largest element size [m] */
    double extent;  /* slope: hemisphere radius; boulder: horizontal semi-axis c */
    double height;  /* boulder: vertical semi-axis d (unused for the slope) */
} fem_body_spec;

rf_status fem_mesh_build(const fem_body_spec *boulder, const fem_body_spec *slope, fem_mesh *mesh,
                         long max_elements, rf_error *err);
void fem_mesh_free(fem_mesh *mesh);

/* Isotropic elastic material. */
typedef struct {
    double rho, E, nu;
} fem_material;

/* Element stiffness (8x8, row-major, dof order r0 z0 r1 z1 ...), lumped
 * nodal masses (area-weighted share of the 2*pi*r element mass) and area. */
void fem_element_matrices(const double r[4], const double z[4], const fem_material *mat,
                          double K[64], double m[4], double *mass, double *area);
/* B matrices (4 x 8 row-major, strains e_rr e_zz e_tt g_rz) and volume
 * weights 2 pi r det(J) at the 2x2 Gauss points, for integration-point kernels. */
void fem_element_points(const double r[4], const double z[4], double B[4][32], double w[4]);
/* Largest eigenvalue of M_e^-1 K_e over the unconstrained dofs (free[i] != 0). */
double fem_element_lambda_max(const double K[64], const double m[4], const int free_dof[8]);
/* Stress at the element centre: sigma_rr, sigma_zz, sigma_tt, sigma_rz. */
void fem_element_stress(const double r[4], const double z[4], const fem_material *mat,
                        const double u[8], double s[4]);

/* VTK output of one frame; appends the frame to the .pvd index text.
 * kernel (may be NULL): the material kernel of each body; an
 * integration-point kernel supplies its committed stress and plastic strain
 * (of the previous step), else the stress is the elastic one from u. */
struct fem_kernel;
rf_status fem_vtk_frame(const char *dir, int frame, double t, const fem_mesh *mesh,
                        const double *u, const double *v, const fem_material mat[2],
                        const struct fem_kernel *kernel, rf_error *err);
rf_status fem_vtk_index(const char *dir, int frames, const double *times, rf_error *err);

/* The binary .vtu writer of both models (fem_vtk.c): arrays of count values
 * of size bytes each (ncomp per tuple), written raw into one appended block. */
typedef struct {
    const char *name, *type; /* VTK type name: Float64, Int32, UInt8 */
    int ncomp;
    const void *data;
    size_t count, size;
} fem_vtk_array;
typedef struct {
    long n_points, n_cells;
    fem_vtk_array points, cells[3]; /* connectivity, offsets, types */
    fem_vtk_array point_data[4], cell_data[8];
    int n_point_data, n_cell_data;
    void *owned[8]; /* buffers freed by fem_vtk_grid_free */
} fem_vtk_grid;
rf_status fem_vtk_write(const char *path, double t, const fem_vtk_grid *g, rf_error *err);
/* g->cells for n elements of k nodes each (conn: k per element), VTK cell type vtk_type;
 * the offsets and types go to g->owned[0..1]. */
rf_status fem_vtk_cells(fem_vtk_grid *g, const int *conn, long n, int k, unsigned char vtk_type, rf_error *err);
void fem_vtk_grid_free(fem_vtk_grid *g);

/* Semi-implicit dashpot (fem_axi_step.c): the velocity v_{n+1/2} of a node
 * of lumped mass m and velocity v = v_{n-1/2} along one direction, under
 * the other forces g and a dashpot -C v_{n+1/2}:
 * (m + dt C) v_{n+1/2} = m v + dt g.  Stable for any dt C / m. */
static inline double fem_dashpot_velocity(double m, double C, double v, double g, double dt)
{
    return (m * v + dt * g) / (m + dt * C);
}

/* One contact pair: boulder node s over slope segment (m1, m2) at coordinate xi.
 * Small strain: the vertical gap, z dofs only (nq = 3).  Large deformation:
 * the gap along the normal of the smooth surface (fem_contact_surface.h),
 * dofs z then r of s, m1, m2, then z and r of the neighbours m0, m3 (nq = 10),
 * the pair linearised anew at every step: gap at the predicted state, gradient at the step's start. */
typedef struct {
    int dof[10];   /* z dofs: slave, master 1, master 2; then (large deformation) their r dofs, then m0, m3 */
    double c[10];  /* gap gradient: small strain 1, -(1 - xi), -xi; large: fem_contact.c pair_gradient */
    int rdof[3];   /* r dofs, for the slip diagnostic */
    double g0;     /* gap at u = 0 of the linear form g0 + c . u */
    double r;      /* radius of the slave: reference (small strain) or current */
    double xi;     /* position on the segment */
    long seg;      /* large deformation: the segment, ssurf[seg] to ssurf[seg + 1] */
    double n[2];   /* the gap's unit normal (r, z): (0, 1) in small strain */
} contact_pair;

typedef struct {
    long npairs;
    contact_pair *pair;
    double *gpred;   /* predicted gap per pair */
    double *lambda;  /* multiplier per pair [N] */
    int *active, *cand;
    double *A, *rhs;
    double *du;      /* ndof scratch, kept zero between calls */
    double *gvo;     /* G v_{n-1/2} per pair */
    double tol;      /* gap tolerance [m] */
    double band;     /* pairs with predicted gap below this are candidates [m] */
    double work;     /* work of the contact forces so far [J] */
    double pen_max;  /* largest penetration [m] */
    double slip_max; /* largest radial slip of a closed pair [m] */
    /* A rigid boulder (rigid_invm = 1 / its mass > 0): every slave moves with
       the boulder, whose z dofs 1, 3, ..., rigid_dofs - 1 get the correction. */
    double rigid_invm;
    long rigid_dofs;
    /* Large deformation (fem_contact_large): pairs on the current surfaces. */
    int nq;               /* gradient entries per pair: 3, or 6 with large deformation */
    const fem_mesh *mesh; /* reference coordinates and surfaces (large deformation) */
    double *vold;         /* v_{n-1/2} kept by fem_contact_begin (large deformation) */
    int block_rounds;     /* block active-set rounds before single pivoting (FEM_CONTACT_BLOCK_ROUNDS) */
    /* Coulomb friction (fem_contact_friction.c; friction > 0 after fem_contact_friction_setup) */
    double friction;      /* coefficient, static = kinetic */
    double *lam_t;        /* tangential multiplier per pair [N], |lam_t| <= friction lambda */
    double *vt_old;       /* v_{n-1/2}, kept by fem_contact_begin for the friction work */
    double W_fric;        /* work dissipated by friction so far [J] (>= 0) */
    long pair_steps, stick_steps; /* closed pair-steps, and those that stuck */
    int sweeps_max;       /* largest number of Gauss-Seidel sweeps of one step */
    double stick_residual_max; /* largest slip per step left on a sticking pair [m] */
    long ndof;            /* size of vt_old */
} fem_contact;

/* Rounds of the block active-set method before the contact solver falls back
 * to single pivoting (fem_contact.block_rounds: 0 with the option
 * contact_single_pivot, whose test checks that both give the one solution of
 * the complementarity problem). */
#define FEM_CONTACT_BLOCK_ROUNDS 200
/* Pairs of the boulder surface nodes below its equator, height d (fem_contact.c). */
rf_status fem_contact_setup(fem_contact *C, const fem_mesh *mesh, long ndof, double d, rf_error *err);
/* Switch the pairs to large deformation: after the predictor,
 * fem_contact_update finds each slave's closest point on the current slope
 * surface and its gap there; fem_contact_step takes the gap's gradient at the
 * step's start (mesh must outlive C). */
rf_status fem_contact_large(fem_contact *C, const fem_mesh *mesh, long ndof, rf_error *err);
void fem_contact_update(fem_contact *C, const double *u);
/* Before the predictor: keep G v_{n-1/2}. */
void fem_contact_begin(fem_contact *C, const double *v);
/* After the predictor: multipliers, corrections of u and v, contact work, total force. */
rf_status fem_contact_step(fem_contact *C, const double *invm, double dt, double *u, double *v, double *Fc,
                           rf_error *err);
/* Gaps at n+1: penetration and slip maxima; returns the contact radius [m]. */
double fem_contact_measure(fem_contact *C, const double *u);
/* Coulomb friction on the pairs (fem_contact_friction.c): set up for ndof
 * dofs with coefficient mu > 0; after the normal corrections of a step, the
 * tangential multipliers by projected Gauss-Seidel and their corrections of
 * u and v, the friction work; returns their vertical force on the boulder. */
rf_status fem_contact_friction_setup(fem_contact *C, long ndof, double mu, rf_error *err);
double fem_contact_friction(fem_contact *C, const double *invm, double dt, double *u, double *v);
void fem_contact_free(fem_contact *C);

/* Test hook (tests/test_fem_gravity.c): the slope of an impact alone under
 * gravity for `steps` steps of the solver's own assembly and time step,
 * without the contact (the boulder falls freely, out of the picture): the
 * largest slope node speed and displacement, and the mean stress of the
 * deepest layer element (of the deepest element without a layer) with its
 * centre depth, to compare with the closed form. */
typedef struct {
    double v_max, u_max, dt;
    double depth, sig[4];     /* centre depth [m] and mean point stress (rr zz tt rz) [Pa] */
    double zn[4];             /* its node heights [m] */
    int layer_elem;           /* 1: that element is in the layer */
    double plastic_strain_max;
    long elements, outside;
    /* the slope's body load against its lumped weight -m_a g: the range of
       the ratio at the interior nodes (off the surface, axis and outer
       boundary), and the sums over all free slope dofs */
    double load_ratio_min, load_ratio_max, load_sum, weight_sum;
} fem_rest_check;
rf_status fem_axi_slope_at_rest(const rf_impact_input *in, const rf_fem_options *opt, long steps,
                                fem_rest_check *chk, rf_error *err);

#endif
