/* dem.c - placeholder: the DEM cut (step 5). */
#include "trajectory/traj_yaml_internal.h"

rf_status ty_dem_profile(ty_ctx *c, struct fy_node *n)
{
    return sp_fail(&c->sp, n, "profile.dem", "DEM profiles are not available in this build");
}
