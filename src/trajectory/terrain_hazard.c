/* terrain_hazard.c - hazard raster accumulators.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

#include <stdlib.h>

rf_terrain_hazard *terrain_hazard_create(const rf_traj_spec *s, const rf_terrain *dem)
{
    (void)s, (void)dem;
    return NULL;
}
void terrain_hazard_begin(rf_terrain_hazard *h) { (void)h; }
void terrain_hazard_piece(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc)
{
    (void)h, (void)dem, (void)mass, (void)pc;
}
void terrain_hazard_end(rf_terrain_hazard *h, int stopped, const double end[3]) { (void)h, (void)stopped, (void)end; }
void terrain_hazard_merge(rf_terrain_hazard *into, const rf_terrain_hazard *from) { (void)into, (void)from; }
void terrain_hazard_free(rf_terrain_hazard *h) { (void)h; }
void terrain_hazard_grid(const rf_terrain_hazard *h, size_t *nx, size_t *ny, double *x0, double *y0, double *cell)
{
    (void)h;
    *nx = *ny = 0, *x0 = *y0 = *cell = 0;
}
rf_status terrain_hazard_bands(const rf_terrain_hazard *h, const rf_traj_spec *s, size_t samples, terrain_band **bands,
                               size_t *n, rf_error *err)
{
    (void)h, (void)s, (void)samples;
    *bands = NULL, *n = 0;
    return rf_fail(err, RF_EINVAL, "hazard rasters are not written yet");
}
void terrain_bands_free(terrain_band *b, size_t n)
{
    for (size_t k = 0; b && k < n; k++)
        free(b[k].data);
    free(b);
}
