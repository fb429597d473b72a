/* fem_points_state.c - what the integration-point kernels (the axisymmetric
 * quad, fem_kernel_points.c, and the hexahedron, fem_kernel_points3d.c) do
 * alike with the state of their points once a step is accepted: trial
 * values become committed and a dissipative law's plastic work is
 * integrated; and what the solvers read of it: the element means for the VTK
 * frames and the elastic energy of the committed stresses; and the
 * geostatic pre-stress under gravity. */
#include "fem_kernel.h"

#include <math.h>
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

double fem_geostatic_k0(const rf_material_params *p)
{
    if (p->model == RF_MATERIAL_DRUCKER_PRAGER)
        return 1 - sin(p->friction_angle);
    return p->poisson / (1 - p->poisson);
}

double fem_geostatic_vertical(const fem_geostatic *g, double depth)
{
    const double d = fmax(depth, 0), t = g->thickness;
    return -g->g * (g->rho_layer * fmin(d, t) + g->rho_base * fmax(d - t, 0));
}

/* A cap through the mean stress p (compression > 0): its compaction. */
static double cap_consolidation(const rf_material *m, double p)
{
    if (!m || !m->cap || !(p > m->cap_pressure) || !(m->cap_hardening > 0))
        return 0;
    return (p - m->cap_pressure) / m->cap_hardening;
}

long fem_points_geostatic(const fem_points_view *v, const double *depth, const fem_geostatic *g)
{
    const size_t ns = (size_t)v->law->nstate, nc = (size_t)v->nc;
    long outside = 0;
    for (size_t p = 0; p < v->np; p++) {
        const int two = v->use2 && v->use2[p / (size_t)v->nq];
        const double sv0 = fem_geostatic_vertical(g, depth[p]);
        const double sv = g->incline != 0 ? cos(g->incline) * sv0 : sv0, sh = g->k0[two] * sv;
        double *s = v->sig + nc * p, *st = (double *)v->sig_t + nc * p;
        for (size_t i = 0; i < nc; i++)
            s[i] = 0;
        if (nc == 4) /* rr zz tt rz: z vertical */
            s[0] = sh, s[1] = sv, s[2] = sh;
        else /* xx yy zz xy yz zx: z the (slope) normal */
            s[0] = sh, s[1] = sh, s[2] = sv, s[5] = g->incline != 0 ? -sin(g->incline) * sv0 : 0;
        memcpy(st, s, nc * sizeof *s);
        const rf_material *m = g->mat[two];
        if (!m)
            continue;
        rf_material_state ms = {0, 0, cap_consolidation(m, -(sv + 2 * sh) / 3)};
        if (ns >= 3)
            v->var[ns * p + 2] = ((double *)v->var_t)[ns * p + 2] = ms.compaction;
        const double s6[6] = {s[0], s[1], s[2], s[3], nc == 6 ? s[4] : 0, nc == 6 ? s[5] : 0};
        outside += !rf_material_admissible(m, s6, &ms, 1e-9);
    }
    return outside;
}
