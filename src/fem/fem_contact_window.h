/* fem_contact_window.h - contact duration from a force history (both solvers). */
#ifndef ROCKFUZZ_FEM_CONTACT_WINDOW_H
#define ROCKFUZZ_FEM_CONTACT_WINDOW_H

/* force[k] at t = k dt, k < nsteps.  *t_first = 0 and *t_last = -1 when the
 * force never exceeds the threshold. */
void rf_fem_contact_window_(const double *force, long nsteps, double dt, double threshold, double *t_first,
                            double *t_last);

#endif
