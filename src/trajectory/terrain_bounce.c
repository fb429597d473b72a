/* terrain_bounce.c - the bounce laws in 3D.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

int terrain_bounce(terrain_run *r, size_t ci, size_t cj, double v[3], double omega[3])
{
    (void)r, (void)ci, (void)cj, (void)v, (void)omega;
    return 1;
}
