/* fem_contact_window.h - the total contact force history of a run and the
 * contact duration measured from it (both solvers). */
#ifndef ROCKFUZZ_FEM_CONTACT_WINDOW_H
#define ROCKFUZZ_FEM_CONTACT_WINDOW_H

/* Store value as force[n], doubling the array (capacity *cap) when full;
 * returns -1 when out of memory (the array is left as it was). */
int rf_fem_force_record_(double **force, long *cap, long n, double value);

/* force[k] at t = k dt, k < nsteps.  *t_first = 0 and *t_last = -1 when the
 * force never exceeds the threshold. */
void rf_fem_contact_window_(const double *force, long nsteps, double dt, double threshold, double *t_first,
                            double *t_last);

#endif
