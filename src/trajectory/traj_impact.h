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

/* traj_impact_cache.c: rows of (v_n, theta, R_n, R_t, spin) for this setup
 * appended to *memo from the file (returns how many); and appended to it. */
size_t traj_impact_cache_load(const char *path, const traj_impact_setup *s, double **memo, size_t *n, size_t *cap);
void traj_impact_cache_append(const char *path, const traj_impact_setup *s, const double *rows, size_t count);

#endif
