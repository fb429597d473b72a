/* roots.c - the first root of a quadratic in time, which every event of a
 * trajectory comes from (a contact stretch's end, an edge of the envelopes):
 * the motion between events is uniformly accelerated. */
#include "trajectory/traj_internal.h"

#include <math.h>

double traj_first_root(double c2, double c1, double c0, double tmax)
{
    double r[2] = {INFINITY, INFINITY};
    if (c2 == 0) {
        if (c1 != 0)
            r[0] = -c0 / c1;
    } else {
        double disc = c1 * c1 - 4 * c2 * c0;
        if (disc >= 0) {
            double q = -0.5 * (c1 + copysign(sqrt(disc), c1)); /* no cancellation (Numerical Recipes 5.6) */
            r[0] = q / c2;
            r[1] = q != 0 ? c0 / q : r[0];
        }
    }
    double best = INFINITY;
    for (int i = 0; i < 2; i++)
        if (r[i] >= 0 && r[i] <= tmax && r[i] < best)
            best = r[i];
    return best;
}
