/* fem3d.h - 3D explicit finite-element model of a boulder (sphere, or
 * spheroid on a horizontal slope) falling vertically onto an inclined slope
 * with Coulomb friction (study S4).  Bodies elastic by default; the slope may
 * be von_mises or drucker_prager, the boulder von_mises (integration-point
 * kernel with B-bar, docs/validation-plastic.md section 9) or rigid (planar
 * rigid motion, exact mass and I_yy, fem3d_rigid.c); a layer of
 * layer_thickness over the slope with its own density, E, nu and law, on a
 * mesh with a node plane at its bottom (fem3d_layer.c).
 *
 * Same design as the axisymmetric solver (fem.h), in the slope's frame
 * (x down-slope, z the outward slope normal, y normal to the plane of
 * motion): the slope is a hemisphere of radius domain_factor * r0 whose flat
 * face is the slope, its curved surface fixed or absorbing; the boulder
 * approaches with v_n = -V cos(alpha), v_t = V sin(alpha), no spin; gravity
 * (rf_impact_gravity) along the fall, g (sin alpha, 0, -cos alpha): the
 * boulder's weight, the slope's inclined geostatic state, a layer that cannot
 * stand on the slope refused (docs/validation-plastic.md section 11b).  8-node hexahedra, full 2x2x2 integration (elastic: matrix-free
 * linear kernel; plastic: return maps at the points with B-bar; small
 * strain, the boulder co-rotational), lumped mass, central differences at the
 * element eigenvalue bound, no damping.  Contact: forward-increment Lagrange
 * multipliers (Carpenter, Taylor & Katona 1991) node-to-segment, boulder
 * nodes on the slope's undeformed face, with Coulomb friction as a
 * tangential multiplier that stops the relative slip of the step, capped at
 * f times the normal multiplier (return map): stick and slip without a
 * tangential spring.  Half model (symmetry plane y = 0) by default.
 * Results do not depend on the thread count (fixed-order assembly).
 * See docs/validation-3d.md for the measured accuracy.
 *
 * Units: SI.  Thread safety: as rf_fem_impact. */
#ifndef ROCKFUZZ_FEM3D_H
#define ROCKFUZZ_FEM3D_H

#include <stdint.h>

#include "rockfuzz/fem.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The 3D model's own numerical settings (fine box, mesh grading, half or
 * full model): src/fem/fem_tuning.h, for the tests and benchmarks only. */
typedef struct rf_fem3d_options rf_fem3d_options;

/* Diagnostics beyond rf_fem_history (energies in J, full body). */
typedef struct {
    double friction_work;      /* energy dissipated by Coulomb friction [J] */
    double normal_work;        /* work of the normal contact multipliers (ideally 0) [J] */
    double slip_max;           /* largest slip increment of a contact pair in one step [m] */
    double contact_point_velocity; /* v_t' - omega' r after the impact [m/s] (0 = rolling) */
    double inertia_lumped;     /* boulder I about y from the lumped masses [kg m^2] */
    double inertia_exact;      /* analytic I about y [kg m^2] */
    double v_y_after;          /* out-of-plane CM velocity after (0 by symmetry) [m/s] */
    double stick_fraction;     /* share of contact pair-steps that stuck (0 without friction) */
    int pgs_sweeps_max;        /* most Gauss-Seidel sweeps needed by the contact in one step */
    double pgs_residual_max;   /* largest contact residual left (gap or slip) [m] */
    long unlocated_pair_steps; /* closed pair-steps whose master point was not found to 1e-9 h (0 expected) */
    uint64_t state_hash;       /* FNV-1a over the bytes of the final u and v arrays */
    double *friction_series;   /* friction work at the rf_fem_history sample times [J] */
    size_t n;                  /* samples in friction_series */
} rf_fem3d_report;

void rf_fem3d_report_free(rf_fem3d_report *rep);

/* Run one impact with default 3D settings (half model). */
rf_status rf_fem3d_impact(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                          rf_fem_history *hist, rf_error *err);

/* The same with explicit 3D settings (o3 may be NULL: the defaults) and diagnostics (rep
 * may be NULL; release with rf_fem3d_report_free).  hist->contact_work holds
 * the normal contact work; hist->closure = KE + strain + absorbed + friction
 * work - KE0; hist->boulder_velocity is the CM velocity along the slope
 * normal.  Returns RF_EINVAL for bad inputs, a spheroid on an inclined slope,
 * or a mesh beyond the element cap (RF_ECAP). */
rf_status rf_fem3d_impact_ex(const rf_impact_input *in, const rf_fem_options *opt, const rf_fem3d_options *o3,
                             rf_impact_output *out, rf_fem_history *hist, rf_fem3d_report *rep, rf_error *err);
/* The same in a caller's workspace (see rf_fem_workspace in fem.h). */
rf_status rf_fem3d_impact_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                             const rf_fem3d_options *o3, rf_impact_output *out, rf_fem_history *hist,
                             rf_fem3d_report *rep, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
