/* fem3d_gravity.h - gravity in the 3D model (fem3d_gravity.c): the
 * direction in the slope frame, the infinite slope's stability check, the
 * inclined geostatic state of the slope and the body load, gravity's power. */
#ifndef ROCKFUZZ_FEM3D_GRAVITY_H
#define ROCKFUZZ_FEM3D_GRAVITY_H

#include "rockfuzz/fem3d.h"
#include "rockfuzz/impact.h"
#include "rockfuzz/material.h"

#include "fem3d_internal.h"

typedef struct {
    double g;       /* [m/s^2]; 0: no gravity (fgrav NULL) */
    double dir[3];  /* unit direction in the slope frame: (sin theta, 0, -cos theta) */
    double *fgrav;  /* body load per dof [N]: the boulder's lumped weight, the slope's geostatic force at u = 0 */
    double W;       /* its work so far [J] (model) */
    double E0;      /* elastic energy of the slope's geostatic stress [J] (model) */
    long outside;   /* integration points whose K0 state the law does not admit */
} f3_gravity;

/* Gravity's direction (sin theta, 0, -cos theta) for the slope angle theta:
 * the boulder falls vertically, x down-slope, z the outward slope normal. */
void f3_gravity_direction(double theta, double dir[3]);

/* The infinite slope (Mohr-Coulomb on the slope-parallel plane: FS = (c +
 * sigma_n tan phi) / tau; von Mises: FS = Y / (sqrt 3 tau)) of an
 * elasto-plastic layer at its base and of an elasto-plastic slope at the
 * model's depth depth_max [m]; RF_EINVAL naming the angle, the strength and
 * FS when FS < 1 (the body cannot stand on this slope). *fs: the smallest FS
 * (INFINITY without a plastic body or on a level slope). */
rf_status f3_gravity_stability(const rf_impact_input *in, double g, double depth_max, double *fs, rf_error *err);

/* The ground's inclination [rad] under an impact at in->slope_angle (rf_fem_ground):
 * the slope angle itself, or with RF_FEM_GROUND_STABLE and gravity g > 0 the
 * steepest angle up to it at which the factor of safety above is at least
 * RF_FEM_GROUND_SAFETY (bisection: it falls monotonically with the angle). */
double f3_ground_angle(const rf_impact_input *in, rf_fem_ground mode, double g, double depth_max);

/* The geostatic state and the body load, after assembly (u = 0): fgrav (ndof
 * values, zeroed by the caller) gets the slope's internal force of the
 * inclined geostatic stress set at its kernel's points (an integration-point
 * kernel; a linear elastic matrix-free slope needs none: its response to
 * gravity superposes and cancels) and the boulder's weight m_a g dir at its
 * nodes.  matl, plastic: slope (1) and layer (2) laws, as the solver has them. */
rf_status f3_gravity_setup(f3_gravity *G, f3_system *S, const rf_impact_input *in, const rf_material matl[3],
                           const int plastic[3], const double *u_zero, double *fgrav, rf_error *err);

/* fgrav' v, the boulder's part as M g . V of a rigid boulder (B on). */
double f3_gravity_power(const f3_gravity *G, const f3_rigid *B, const double *v, long nbn, long ndof);

/* Test hook (tests/test_fem3d_gravity.c, fem3d_gravity_run.c): the run's own
 * assembly and `steps` steps without the contact: the slope alone under
 * gravity, the boulder in free flight through it.  chk zero-initialised
 * by the caller (ctx and cell set, or cell NULL). */
typedef struct {
    void *ctx;                 /* for cell */
    void (*cell)(void *ctx, double depth, int layer, const double sig[6]); /* every slope cell at the end:
                                  centre depth [m], in the layer, mean point stress (xx yy zz xy yz zx) [Pa] */
    double slope_u_max, slope_v_max; /* largest |u| [m] and |v| [m/s] of a slope dof */
    double cm_u[3], cm_v[3];   /* the boulder's CM displacement [m] and velocity [m/s] (v at t_n - dt/2) */
    double spread_u;           /* largest |u_a - u_CM| of a boulder node (elastic: its deformation) [m] */
    double dt, closure, gravity_work; /* [s]; energy closure and gravity's work [J] (model) */
    double ground_angle;       /* the ground's inclination gravity and the geostatic state took [rad] */
    long outside, box_nodes;   /* geostatic points outside the yield surface; nodes in load_err */
    double load_err;           /* largest |fgrav - m_a g dir| / (m_a g) over the slope's nodes inside
                                  the fine box's rectangular elements (off the outer and symmetry
                                  surfaces; the top surface in: traction-free) */
} f3_gravity_check;
rf_status fem3d_gravity_free_run(const rf_impact_input *in, const rf_fem_options *opt, const rf_fem3d_options *o3,
                                 long steps, f3_gravity_check *chk, rf_error *err);

#endif
