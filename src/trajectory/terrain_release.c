/* terrain_release.c - release features: the map point at given uniforms.
 * (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

rf_status terrain_release_prepare(const rf_traj_spec *s, terrain_release_set **set, rf_error *err)
{
    (void)s;
    *set = NULL;
    return rf_fail(err, RF_EINVAL, "terrain release areas are not written yet");
}
void terrain_release_free(terrain_release_set *set) { (void)set; }
void terrain_release_point(const terrain_release_set *set, double u1, double u2, double u3, double *x, double *y)
{
    (void)set, (void)u1, (void)u2, (void)u3;
    *x = *y = NAN;
}
