/* material_j2.c - von Mises (J2) plasticity with linear isotropic hardening:
 * the radial return of Wilkins (1964), in the form of Simo & Hughes (1998)
 * "Computational Inelasticity" ch. 3 and de Souza Neto, Peric & Owen (2008)
 * ch. 7.  Closed form for linear hardening, exact for
 * radial (proportional) strain paths; the mean stress stays elastic. */
#include "material/material_internal.h"

#include <math.h>

void mat_return_von_mises(const rf_material *m, double eps_p_eq, const double s_tr[6], double p_tr,
                          mat_return *r)
{
    double q_tr = sqrt(1.5 * mat_ddot(s_tr, s_tr));
    double sigma_y = m->yield + m->hardening * eps_p_eq;
    double gamma = 0.0, scale = 1.0;
    if (q_tr > sigma_y) {
        gamma = (q_tr - sigma_y) / (3.0 * m->G + m->hardening);
        scale = 1.0 - 3.0 * m->G * gamma / q_tr;
    }
    for (int i = 0; i < 6; i++)
        r->s[i] = scale * s_tr[i];
    r->p = p_tr;
    r->gamma_j2 = gamma;
    r->compaction = 0.0;
}
