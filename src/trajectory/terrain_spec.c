/* terrain_spec.c - the terrain part of a trajectory spec (free, copy, hash)
 * and the prepared world.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

#include <stdlib.h>
#include <string.h>

void rf_terrain_def_free(rf_terrain_def *d) { (void)d; }
rf_status rf_terrain_def_copy(const rf_terrain_def *src, rf_terrain_def *dst, rf_error *err)
{
    (void)src, (void)dst;
    return rf_fail(err, RF_EINVAL, "terrain: copy not written yet");
}
uint64_t rf_terrain_def_hash(const rf_terrain_def *d, uint64_t h)
{
    (void)d;
    return h;
}
rf_status rf_terrain_world_create(const rf_traj_spec *spec, rf_terrain_world **w, rf_error *err)
{
    (void)spec;
    *w = NULL;
    return rf_fail(err, RF_EINVAL, "terrain: world not written yet");
}
void rf_terrain_world_free(rf_terrain_world *w) { (void)w; }
const rf_terrain *rf_terrain_world_surface(const rf_terrain_world *w) { return w ? w->dem : NULL; }
