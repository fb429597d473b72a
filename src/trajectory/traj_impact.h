/* traj_impact.h - the bounce law `impact_model`: the adapter to rockfuzz's
 * impact models (traj_impact_adapter.c) and the adaptive table of R_n, R_t
 * and spin over (normal speed, incidence) (traj_impact_table.c). */
#ifndef ROCKFUZZ_TRAJ_IMPACT_H
#define ROCKFUZZ_TRAJ_IMPACT_H

#include "rockfuzz/trajectory.h"

typedef struct {
    int solver;           /* rf_impact_solver */
    double radius, density, friction;
    double refinement;    /* FE a/h, 0 = default */
} traj_impact_setup;

rf_status traj_impact_setup_init(traj_impact_setup *s, const rf_traj_spec *spec, rf_error *err);
/* One impact: normal speed vn [m/s] > 0, incidence theta [rad] from the normal. */
rf_status traj_impact_coefficients(const traj_impact_setup *s, double vn, double theta, double *R_n, double *R_t,
                                   double *spin, rf_error *err);

#endif
