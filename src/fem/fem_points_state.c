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

/* A point's geostatic stress s (nc components) at the vertical stress sv0
 * with the in-plane ratio k, and as its material m sees it: s6 and the
 * state ms (the cap normally consolidated through the mean stress). */
static void geostatic_point(const fem_geostatic *g, size_t nc, double sv0, double k, const rf_material *m, double *s,
                            double s6[6], rf_material_state *ms)
{
    const double sv = g->incline != 0 ? cos(g->incline) * sv0 : sv0, sh = k * sv;
    for (size_t i = 0; i < nc; i++)
        s[i] = 0;
    if (nc == 4) /* rr zz tt rz: z vertical */
        s[0] = sh, s[1] = sv, s[2] = sh;
    else /* xx yy zz xy yz zx: z the (slope) normal */
        s[0] = sh, s[1] = sh, s[2] = sv, s[5] = g->incline != 0 ? -sin(g->incline) * sv0 : 0;
    *ms = (rf_material_state){0, 0, cap_consolidation(m, -(sv + 2 * sh) / 3)};
    const double t[6] = {s[0], s[1], s[2], s[3], nc == 6 ? s[4] : 0, nc == 6 ? s[5] : 0};
    memcpy(s6, t, sizeof t);
}

#define GEO_TOL 1e-9 /* admissible: every yield function <= GEO_TOL * its scale */

static int geostatic_inside(const fem_geostatic *g, size_t nc, double sv0, double k, const rf_material *m)
{
    double s[6], s6[6];
    rf_material_state ms;
    geostatic_point(g, nc, sv0, k, m, s, s6, &ms);
    return rf_material_admissible(m, s6, &ms, GEO_TOL);
}

static double geostatic_yield(const fem_geostatic *g, size_t nc, double sv0, double k, const rf_material *m)
{
    double s[6], s6[6];
    rf_material_state ms;
    geostatic_point(g, nc, sv0, k, m, s, s6, &ms);
    return rf_material_yield(m, s6, &ms);
}

/* The in-plane ratio K of a point whose K0 state is outside its yield
 * surface (docs/validation-plastic.md section 11b): the smallest K in
 * [K0, 1] whose yield function is <= 0 (bisection: it falls with K there),
 * else the same in [1, K*], K* the K minimising the yield function in
 * [1, Kp] (golden section: it is convex in K; Kp = (2 - K0) / K0,
 * Rankine's passive coefficient for Jaky's K0).  Strictly <= 0, not within
 * a tolerance: a point just outside would yield at the first step.  *inside
 * 0 when no K is admissible (then K*: the least violation). */
static double geostatic_ratio(const fem_geostatic *g, size_t nc, double sv0, double k0, const rf_material *m,
                              int *inside)
{
    double lo = k0, hi = fmax(k0, 1);
    if (geostatic_yield(g, nc, sv0, hi, m) > 0) {
        const double r = 0.5 * (sqrt(5.0) - 1);
        double a = hi, b = fmax(hi, (2 - k0) / k0);
        for (int it = 0; it < 200 && b - a > 1e-12 * b; it++) {
            const double c = b - r * (b - a), d = a + r * (b - a);
            if (geostatic_yield(g, nc, sv0, c, m) <= geostatic_yield(g, nc, sv0, d, m))
                b = d;
            else
                a = c;
        }
        lo = hi, hi = 0.5 * (a + b);
        if (geostatic_yield(g, nc, sv0, hi, m) > 0)
            return *inside = geostatic_inside(g, nc, sv0, hi, m), hi;
    }
    for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; it++) {
        const double mid = 0.5 * (lo + hi);
        *(geostatic_yield(g, nc, sv0, mid, m) <= 0 ? &hi : &lo) = mid;
    }
    *inside = 1;
    return hi;
}

long fem_points_geostatic(const fem_points_view *v, const double *depth, const fem_geostatic *g)
{
    const size_t ns = (size_t)v->law->nstate, nc = (size_t)v->nc;
    long outside = 0;
    for (size_t p = 0; p < v->np; p++) {
        const int two = v->use2 && v->use2[p / (size_t)v->nq];
        const rf_material *m = g->mat[two];
        const double sv0 = fem_geostatic_vertical(g, depth[p]);
        double *s = v->sig + nc * p, *st = (double *)v->sig_t + nc * p, s6[6], k = g->k0[two];
        rf_material_state ms;
        int inside = 1;
        if (m && !geostatic_inside(g, nc, sv0, k, m))
            k = geostatic_ratio(g, nc, sv0, k, m, &inside);
        geostatic_point(g, nc, sv0, k, m, s, s6, &ms);
        memcpy(st, s, nc * sizeof *s);
        if (m && ns >= 3)
            v->var[ns * p + 2] = ((double *)v->var_t)[ns * p + 2] = ms.compaction;
        outside += !inside;
    }
    return outside;
}
