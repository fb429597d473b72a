/* fem_points_state.c - what the integration-point kernels (the axisymmetric
 * quad, fem_kernel_points.c, and the hexahedron, fem_kernel_points3d.c) do
 * alike with the state of their points once a step is accepted: trial
 * values become committed and a dissipative law's plastic work is
 * integrated; and what the solvers read of it: the element means for the VTK
 * frames and the elastic energy of the committed stresses. */
#include "fem_kernel.h"

#include <string.h>

void fem_points_accept(const fem_points_view *v, double *work, double *strain_max, long *point_max)
{
    const size_t ns = (size_t)v->law->nstate;
    memcpy(v->eps, v->eps_t, v->np * (size_t)v->nc * sizeof(double));
    memcpy(v->sig, v->sig_t, v->np * (size_t)v->nc * sizeof(double));
    if (ns)
        memcpy(v->var, v->var_t, v->np * ns * sizeof(double));
    if (!v->law->dissipative)
        return;
    double W = 0, emax = *strain_max;
    long pmax = *point_max;
    for (size_t p = 0; p < v->np; p++) {
        const double *s = v->var + ns * p;
        W += v->w[p] * s[ns - 1];
        if (s[0] > emax)
            emax = s[0], pmax = (long)p;
    }
    *work += W, *strain_max = emax, *point_max = pmax;
}

void fem_points_cell(const fem_points_view *v, long le, double *sig, double *plastic_strain)
{
    const size_t p0 = (size_t)v->nq * (size_t)le, ns = (size_t)v->law->nstate;
    double emax = 0;
    for (int i = 0; i < v->nc; i++)
        sig[i] = 0;
    for (size_t p = p0; p < p0 + (size_t)v->nq; p++) {
        for (int i = 0; i < v->nc; i++)
            sig[i] += v->sig[(size_t)v->nc * p + (size_t)i] / v->nq;
        if (v->law->dissipative && v->var[ns * p] > emax)
            emax = v->var[ns * p];
    }
    *plastic_strain = emax;
}

double fem_points_energy(const fem_points_view *v)
{
    if (!v->law->energy || (v->use2 && !v->law2->energy))
        return -1;
    double E = 0;
    for (size_t p = 0; p < v->np; p++) {
        const fem_point_law *L = v->use2 && v->use2[p / (size_t)v->nq] ? v->law2 : v->law;
        E += v->w[p] * L->energy(L->params, v->sig + (size_t)v->nc * p);
    }
    return E;
}
