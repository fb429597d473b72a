/* terrain_mc_glue.c - STAND-IN until the simulator (terrain_simulate.c)
 * provides terrain_simulate_hazard (terrain_internal.h): the trajectory
 * without its pieces reaching the rasters (only the deposit at its end).
 * Delete this file when terrain_simulate.c defines the function. */
#include "trajectory/terrain_internal.h"

rf_status terrain_simulate_hazard(const rf_terrain_world *w, const rf_traj_spec *values, uint64_t seed,
                                  uint64_t sample, const double start[3], struct rf_terrain_hazard *hazard,
                                  rf_terrain_result *res, rf_error *err)
{
    if (hazard)
        terrain_hazard_begin(hazard);
    rf_status st = rf_terrain_simulate(w, values, seed, sample, start, res, err);
    if (hazard && st == RF_OK)
        terrain_hazard_end(hazard, res->state == RF_TRAJ_STOPPED, res->end);
    return st;
}
