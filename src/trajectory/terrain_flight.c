/* terrain_flight.c - exact first impact of a parabola with the bilinear
 * surface, cell by cell.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

int terrain_first_impact(const rf_terrain *t, const double p[3], const double v[3], double g, double tmax,
                         double *tau, size_t *ci, size_t *cj)
{
    (void)t, (void)p, (void)v, (void)g, (void)tmax, (void)ci, (void)cj;
    *tau = INFINITY;
    return 0;
}
