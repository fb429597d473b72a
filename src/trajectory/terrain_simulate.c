/* terrain_simulate.c - one 3D trajectory: flights, impacts, contact.
 * (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

terrain_piece_outcome terrain_emit(terrain_run *r, const terrain_piece *pc, double *tau_cut, double *scale)
{
    if (r->hazard)
        terrain_hazard_piece(r->hazard, r->dem, r->mass, pc);
    return terrain_barrier_piece(r, pc, tau_cut, scale);
}

void terrain_event(terrain_run *r, rf_traj_event_kind kind, int flying)
{
    (void)r, (void)kind, (void)flying;
}

rf_status rf_terrain_simulate(const rf_terrain_world *w, const rf_traj_spec *values, uint64_t seed, uint64_t sample,
                              const double start[3], rf_terrain_result *res, rf_error *err)
{
    (void)w, (void)values, (void)seed, (void)sample, (void)start, (void)res;
    return rf_fail(err, RF_EINVAL, "terrain trajectories are not written yet");
}
