/* traj_impact.h - the bounce law `impact_model`: the adapter to rockfuzz's
 * impact models (traj_impact_adapter.c) and the adaptive table of R_n, R_t
 * and spin over (normal speed, incidence) (traj_impact_table.c). */
#ifndef ROCKFUZZ_TRAJ_IMPACT_H
#define ROCKFUZZ_TRAJ_IMPACT_H

#include "rockfuzz/trajectory.h"

#include <stdatomic.h>

typedef struct {
    int solver;           /* rf_impact_solver */
    double radius, density, friction;
    double refinement;    /* FE a/h, 0 = default */
    const atomic_int *stop; /* non-zero: an FE impact stops between two steps (RF_EINTERRUPTED); may be NULL */
} traj_impact_setup;

/* The k-th impact solver's name (rockfuzz impact --solver), NULL past the last:
 * the names bounce.impact.solver takes. */
const char *traj_impact_solver_name(size_t k);
rf_status traj_impact_setup_init(traj_impact_setup *s, const rf_traj_spec *spec, rf_error *err);
/* One impact: normal speed vn [m/s] > 0, incidence theta [rad] from the normal. */
rf_status traj_impact_coefficients(const traj_impact_setup *s, double vn, double theta, double *R_n, double *R_t,
                                   double *spin, rf_error *err);

/* traj_impact_cache.c: rows of (v_n, theta, R_n, R_t, spin) for this setup
 * appended to *memo from the file, each checked (finite, v_n > 0, theta in
 * [0, pi/2), R_n in [0, 1], |R_t| <= 1, no energy gained beyond 1 %), an
 * identical repeat kept once, a conflicting one refused with both lines; and
 * new rows appended to the file. */
rf_status traj_impact_cache_load(const char *path, const traj_impact_setup *s, double **memo, size_t *n,
                                 size_t *cap, rf_error *err);
void traj_impact_cache_append(const char *path, const traj_impact_setup *s, const double *rows, size_t count);

#endif
