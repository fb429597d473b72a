/* impact_internal.h - helpers shared by the analytic impact models:
 * rigid_kinematics.c (the rebound law) uses impact_input.c only; hertz.c uses
 * both (no circle). */
#ifndef ROCKFUZZ_IMPACT_INTERNAL_H
#define ROCKFUZZ_IMPACT_INTERNAL_H

#include "rockfuzz/impact.h"

#include "core/util.h"

/* (rigid_kinematics.c) Rebound kinematics: given the normal COR e_n, fill
 * v_*_before/after, omega_after, R_n, R_t, R_ke with the rigid-body Coulomb
 * law of impact_refs.md sec. 4.1.  Rejects a spheroid on an inclined slope
 * (its contact point leaves the pole; not modelled analytically). */
rf_status rf_impact_kinematics_(const rf_impact_input *in, double e_n, rf_impact_output *out,
                                rf_error *err);

/* The public rf_impact_output_clear (impact_input.c), under its older internal name. */
#define rf_impact_output_clear_ rf_impact_output_clear

#endif
