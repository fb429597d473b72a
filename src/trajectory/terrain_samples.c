/* terrain_samples.c - the per-sample part of a terrain ensemble
 * (rf_traj_ensemble.terrain): freeing it.  Its own file so that
 * rf_traj_ensemble_free (montecarlo.c) can free a terrain run without
 * montecarlo.c and terrain_montecarlo.c calling each other. */
#include "trajectory/terrain_internal.h"

#include <stdlib.h>

void terrain_samples_free(rf_terrain_samples *t)
{
    if (!t)
        return;
    for (size_t i = 0; t->recorded && i < t->n_recorded; i++) {
        free(t->recorded[i].crossings);
        free(t->recorded[i].impacts);
        free(t->recorded[i].events);
    }
    free(t->recorded);
    free(t->start);
    free(t->end);
    free(t->runout);
    free(t->reach_angle);
    terrain_hazard_free(t->hazard);
    free(t);
}
