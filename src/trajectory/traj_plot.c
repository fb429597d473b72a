/* traj_plot.c - placeholder (plots land in step 5). */
#include "trajectory/traj_internal.h"

rf_status rf_traj_write_plots(const char *dir, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                              const rf_traj_stats *st, rf_error *err)
{
    (void)dir, (void)spec, (void)ens, (void)st, (void)err;
    return RF_OK;
}
