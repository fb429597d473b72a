/* fem_contact_window.c - the recorded contact force history and the contact
 * duration measured from it, shared by the axisymmetric and the 3D solver so
 * that both measure it the same way: first to last step whose total contact force exceeds the
 * threshold (multipliers are exactly zero off contact; the threshold only
 * guards round-off), both ends interpolated linearly to the threshold within
 * the neighbouring step. */
#include "fem_contact_window.h"

#include <math.h>
#include <stdlib.h>

int rf_fem_force_record_(double **force, long *cap, long n, double value)
{
    if (n >= *cap) {
        long grown = 2 * *cap > n ? 2 * *cap : n + 1;
        double *p = realloc(*force, (size_t)grown * sizeof *p);
        if (!p)
            return -1;
        *force = p;
        *cap = grown;
    }
    (*force)[n] = value;
    return 0;
}

void rf_fem_contact_window_(const double *force, long nsteps, double dt, double threshold, double *t_first,
                            double *t_last)
{
    double t0 = -1, t1 = -1;
    for (long k = 0; k < nsteps; k++)
        if (force[k] > threshold) {
            if (t0 < 0) {
                t0 = (double)k * dt;
                if (k > 0)
                    t0 -= dt * fmin(1, (force[k] - threshold) / (force[k] - force[k - 1]));
            }
            t1 = (double)k * dt;
            if (k + 1 < nsteps && k > 0 && force[k - 1] > force[k])
                t1 += dt * fmin(1, (force[k] - threshold) / (force[k - 1] - force[k]));
        }
    *t_first = t0 < 0 ? 0 : t0;
    *t_last = t1;
}
