/* terrain_report.c - maps and report.html of a terrain run.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

rf_status terrain_write_maps(const char *dir, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                             const rf_traj_stats *st, const rf_terrain *dem, const terrain_band *bands, size_t n,
                             rf_error *err)
{
    (void)spec, (void)ens, (void)st, (void)dem, (void)bands, (void)n;
    return rf_fail(err, RF_EINVAL, "%s: terrain maps are not written yet", dir);
}
