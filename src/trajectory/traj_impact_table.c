/* traj_impact_table.c - placeholder (filled in step 6). */
#include "trajectory/traj_internal.h"

rf_status traj_impact_table_build(const rf_traj_spec *spec, traj_impact_table **table, rf_error *err)
{
    (void)spec;
    *table = NULL;
    return rf_fail(err, RF_EINVAL, "bounce.law = impact_model: not available yet");
}

void traj_impact_table_free(traj_impact_table *t) { (void)t; }

void traj_impact_table_eval(const traj_impact_table *t, double vn, double theta, double *R_n, double *R_t,
                            double *spin_ratio)
{
    (void)t, (void)vn, (void)theta;
    *R_n = *R_t = 1, *spin_ratio = 0;
}
