/* fem_kernel_points.c - the integration-point material kernel of the
 * axisymmetric quad (fem_kernel.h): strain at each Gauss point from B ue,
 * the point law's stress update from the strain increment, internal force
 * sum_q w_q B_q^T sigma_q; trial values become committed in commit(), which
 * also integrates a dissipative law's plastic work (sum_q w_q D_q).  Optional
 * mean-dilatation B-bar.  And two point laws: linear elasticity (the
 * reference: with it this kernel reproduces the precomputed stiffness) and
 * the material library's return maps (rockfuzz/material.h). */
#include "fem_internal.h"
#include "fem_kernel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NQ 4 /* Gauss points per element */
#define NC 4 /* strain components */

typedef struct {
    fem_point_law law, law2;
    unsigned char *use2;      /* per element: law2 (NULL: law everywhere) */
    double *B;      /* 4 x 32 per element */
    double *w;      /* 4 per element */
    double *eps, *sig, *var;          /* committed, per point */
    double *eps_t, *sig_t, *var_t;    /* trial of the last forces() */
    double plastic_work, plastic_strain_max; /* committed (dissipative laws) */
    long point_max;                          /* the point of plastic_strain_max (-1: none) */
    /* updated Lagrangian (fem_kernel_points_axi_large): reference node
       coordinates r0 z0 r1 z1 ... and committed / trial displacements, 8 per
       element; w then holds the committed current weights, w_t the trial ones */
    double *X, *ue_c, *ue_t, *w_t;
    int bbar;
} points_data;

static void mean_dilatation(double B[NQ][32], const double w[NQ]);

static void points_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    points_data *d = k->data;
    const int ns = d->law.nstate;
    for (long e = e0; e < e1; e++, ue += 8, fe += 8) {
        const long le = e - k->first;
        const fem_point_law *L = d->use2 && d->use2[le] ? &d->law2 : &d->law;
        double y[8] = {0};
        for (int q = 0; q < NQ; q++) {
            const long p = NQ * le + q;
            const double *B = d->B + 32 * p;
            double *eps = d->eps_t + NC * p, *sig = d->sig_t + NC * p, deps[NC];
            for (int i = 0; i < NC; i++) {
                double s = 0;
                for (int j = 0; j < 8; j++)
                    s += B[8 * i + j] * ue[j];
                eps[i] = s;
                deps[i] = s - d->eps[NC * p + i];
            }
            L->update(L->params, deps, d->sig + NC * p, d->var + (size_t)ns * p, sig, d->var_t + (size_t)ns * p);
            for (int j = 0; j < 8; j++)
                y[j] += d->w[p] * (B[j] * sig[0] + B[8 + j] * sig[1] + B[16 + j] * sig[2] + B[24 + j] * sig[3]);
        }
        memcpy(fe, y, sizeof y);
    }
}

/* Spin of the increment at each point, 1/2 (d du_z/dr - d du_r/dz), from the
 * plain B (before B-bar): row 0 holds dN/dr at the r dofs, row 1 dN/dz at the z dofs. */
static void point_spins(double B[NQ][32], const double du[8], double spin[NQ])
{
    for (int q = 0; q < NQ; q++) {
        double s = 0;
        for (int a = 0; a < 4; a++)
            s += B[q][2 * a] * du[2 * a + 1] - B[q][8 + 2 * a + 1] * du[2 * a];
        spin[q] = 0.5 * s;
    }
}

/* Updated Lagrangian element: the strain increment B(x_mid) du on the
 * mid-step geometry (exactly zero for a rigid rotation of any size), the
 * committed stress turned by the Hughes-Winget rotation of the increment's
 * spin (exact for that rotation), the return map, and the force
 * sum_q w_q(x) B_q(x)^T sigma_q on the current geometry x = X + u. */
static void large_element(points_data *d, const fem_point_law *L, long le, const double *ue, double *y)
{
    const int ns = L->nstate;
    const double *X = d->X + 8 * le, *uc = d->ue_c + 8 * le;
    double xm[8], du[8], xc[8], Bm[NQ][32], wm[NQ], Bc[NQ][32], spin[NQ];
    for (int j = 0; j < 8; j++)
        du[j] = ue[j] - uc[j], xm[j] = X[j] + 0.5 * (ue[j] + uc[j]), xc[j] = X[j] + ue[j];
    const double rm[4] = {xm[0], xm[2], xm[4], xm[6]}, zm[4] = {xm[1], xm[3], xm[5], xm[7]};
    const double rc[4] = {xc[0], xc[2], xc[4], xc[6]}, zc[4] = {xc[1], xc[3], xc[5], xc[7]};
    fem_element_points(rm, zm, Bm, wm);
    point_spins(Bm, du, spin);
    fem_element_points(rc, zc, Bc, d->w_t + NQ * le);
    if (d->bbar)
        mean_dilatation(Bm, wm), mean_dilatation(Bc, d->w_t + NQ * le);
    memcpy(d->ue_t + 8 * le, ue, 8 * sizeof *ue);
    for (int q = 0; q < NQ; q++) {
        const long p = NQ * le + q;
        const double *B = Bm[q], *w = d->w_t + NQ * le;
        double deps[NC], s6[6] = {d->sig[NC * p], d->sig[NC * p + 1], d->sig[NC * p + 2], d->sig[NC * p + 3], 0, 0};
        for (int i = 0; i < NC; i++) {
            double s = 0;
            for (int j = 0; j < 8; j++)
                s += B[8 * i + j] * du[j];
            deps[i] = s;
            d->eps_t[NC * p + i] = d->eps[NC * p + i] + s;
        }
        rf_material_rotate(s6, (const double[3]){0, 0, spin[q]});
        double *sig = d->sig_t + NC * p;
        L->update(L->params, deps, s6, d->var + (size_t)ns * p, sig, d->var_t + (size_t)ns * p);
        for (int j = 0; j < 8; j++)
            y[j] += w[q] * (Bc[q][j] * sig[0] + Bc[q][8 + j] * sig[1] + Bc[q][16 + j] * sig[2] + Bc[q][24 + j] * sig[3]);
    }
}

static void points_forces_large(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    points_data *d = k->data;
    for (long e = e0; e < e1; e++, ue += 8, fe += 8) {
        const long le = e - k->first;
        double y[8] = {0};
        large_element(d, d->use2 && d->use2[le] ? &d->law2 : &d->law, le, ue, y);
        memcpy(fe, y, sizeof y);
    }
}

/* The kernel's points as fem_points_state.c sees them. */
static fem_points_view points_view(const fem_kernel *k)
{
    points_data *d = k->data;
    return (fem_points_view){(size_t)NQ * (size_t)k->count, NQ, NC, &d->law, &d->law2, d->use2, d->w,
                             d->eps, d->sig, d->var, d->eps_t, d->sig_t, d->var_t};
}

static void points_commit(fem_kernel *k)
{
    points_data *d = k->data;
    const size_t np = (size_t)NQ * (size_t)k->count;
    if (d->X) /* the current geometry of the accepted state */
        memcpy(d->ue_c, d->ue_t, (size_t)k->count * 8 * sizeof(double)), memcpy(d->w, d->w_t, np * sizeof(double));
    const fem_points_view v = points_view(k);
    fem_points_accept(&v, &d->plastic_work, &d->plastic_strain_max, &d->point_max);
}

static void points_destroy(fem_kernel *k)
{
    points_data *d = k->data;
    if (d) {
        free(d->B), free(d->w), free(d->eps), free(d->sig), free(d->var), free(d->eps_t), free(d->sig_t);
        free(d->var_t), free(d->use2), free(d->X), free(d->ue_c), free(d->ue_t), free(d->w_t);
    }
    free(d);
    k->data = NULL;
}

static void points_report(const fem_kernel *k, fem_kernel_report *r)
{
    const points_data *d = k->data;
    r->plastic_work = d->plastic_work, r->plastic_strain_max = d->plastic_strain_max;
    r->element_max = d->point_max < 0 ? -1 : k->first + d->point_max / NQ;
}

static const fem_kernel_ops points_ops = {"integration points (axisymmetric quad)", points_forces, NULL,
                                          points_commit, points_destroy, NULL, points_report};
static const fem_kernel_ops points_large_ops = {"integration points (axisymmetric quad, updated Lagrangian)",
                                                points_forces_large, NULL, points_commit, points_destroy, NULL,
                                                points_report};

static int is_points(const fem_kernel *k)
{
    return k->ops == &points_ops || k->ops == &points_large_ops;
}

rf_status fem_kernel_points_axi_large(fem_kernel *k, const double *r, const double *z, const int *conn, rf_error *err)
{
    if (!is_points(k) || !k->data)
        return rf_fail(err, RF_EINVAL, "fem: updated Lagrangian needs an integration-point kernel");
    points_data *d = k->data;
    const size_t ne = (size_t)k->count, np = NQ * ne;
    d->X = malloc((ne + 1) * 8 * sizeof *d->X), d->ue_c = calloc(ne + 1, 8 * sizeof *d->ue_c);
    d->ue_t = calloc(ne + 1, 8 * sizeof *d->ue_t), d->w_t = malloc((np + 1) * sizeof *d->w_t);
    if (!d->X || !d->ue_c || !d->ue_t || !d->w_t)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld elements", k->count);
    for (size_t e = 0; e < ne; e++)
        for (int a = 0; a < 4; a++) {
            const int n = conn[4 * (k->first + (long)e) + a];
            d->X[8 * e + 2 * a] = r[n], d->X[8 * e + 2 * a + 1] = z[n];
        }
    memcpy(d->w_t, d->w, np * sizeof *d->w);
    k->ops = &points_large_ops;
    return RF_OK;
}

int fem_kernel_cell_state(const fem_kernel *k, long e, double sig[4], double *plastic_strain)
{
    if (!is_points(k) || !k->data || e < k->first || e >= k->first + k->count)
        return 0;
    const fem_points_view v = points_view(k);
    fem_points_cell(&v, e - k->first, sig, plastic_strain);
    return 1;
}

double fem_kernel_elastic_energy(const fem_kernel *k)
{
    if (!is_points(k) || !k->data)
        return -1;
    const fem_points_view v = points_view(k);
    return fem_points_energy(&v);
}

void fem_kernel_report_get(const fem_kernel *k, fem_kernel_report *r)
{
    r->plastic_work = r->plastic_strain_max = 0, r->element_max = -1;
    if (k->ops && k->ops->report && k->data)
        k->ops->report(k, r);
}

/* Mean dilatation: B_q rows rr, zz, tt get (bbar - b_q) / 3 with b_q the
 * volumetric row (sum of the three normal rows) and bbar its w-weighted mean. */
static void mean_dilatation(double B[NQ][32], const double w[NQ])
{
    double bbar[8] = {0}, W = 0;
    for (int q = 0; q < NQ; q++) {
        W += w[q];
        for (int j = 0; j < 8; j++)
            bbar[j] += w[q] * (B[q][j] + B[q][8 + j] + B[q][16 + j]);
    }
    for (int q = 0; q < NQ; q++)
        for (int j = 0; j < 8; j++) {
            const double c = (bbar[j] / W - (B[q][j] + B[q][8 + j] + B[q][16 + j])) / 3;
            B[q][j] += c, B[q][8 + j] += c, B[q][16 + j] += c;
        }
}

rf_status fem_kernel_points_axi(fem_kernel *k, long first, long count, const double *r, const double *z,
                                const int *conn, const fem_point_law *law, rf_error *err)
{
    return fem_kernel_points_axi_ex(k, first, count, r, z, conn, law, 0, err);
}

rf_status fem_kernel_points_axi_ex(fem_kernel *k, long first, long count, const double *r, const double *z,
                                   const int *conn, const fem_point_law *law, int bbar, rf_error *err)
{
    return fem_kernel_points_axi_two(k, first, count, r, z, conn, law, NULL, NULL, bbar, err);
}

rf_status fem_kernel_points_axi_two(fem_kernel *k, long first, long count, const double *r, const double *z,
                                    const int *conn, const fem_point_law *law, const fem_point_law *law2,
                                    const unsigned char *use_law2, int bbar, rf_error *err)
{
    if (use_law2 && (!law2 || law2->nstate != law->nstate || law2->ncomp != law->ncomp ||
                     law2->dissipative != law->dissipative))
        return rf_fail(err, RF_EINVAL, "fem: the two point laws of a block must have the same shape");
    if (law->ncomp != NC)
        return rf_fail(err, RF_EINVAL, "fem: the point law '%s' has %d strain components; the axisymmetric quad "
                       "needs %d", law->name, law->ncomp, NC);
    if (law->dissipative && law->nstate < 2)
        return rf_fail(err, RF_EINVAL, "fem: the dissipative point law '%s' needs >= 2 state variables",
                       law->name);
    points_data *d = calloc(1, sizeof *d);
    const size_t np = (size_t)NQ * (size_t)count, ns = (size_t)(law->nstate > 0 ? law->nstate : 1);
    k->ops = &points_ops, k->first = first, k->count = count, k->ndofe = 8, k->data = d;
    if (!d)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    d->law = *law;
    d->point_max = -1, d->bbar = bbar;
    if (use_law2) {
        d->law2 = *law2;
        if (!(d->use2 = malloc((size_t)count > 0 ? (size_t)count : 1)))
            return rf_fail(err, RF_ENOMEM, "fem: out of memory");
        memcpy(d->use2, use_law2, (size_t)count);
    }
    d->B = malloc(np * 32 * sizeof *d->B), d->w = malloc(np * sizeof *d->w);
    d->eps = calloc(np * NC, sizeof *d->eps), d->sig = calloc(np * NC, sizeof *d->sig);
    d->eps_t = calloc(np * NC, sizeof *d->eps_t), d->sig_t = calloc(np * NC, sizeof *d->sig_t);
    d->var = calloc(np * ns, sizeof *d->var), d->var_t = calloc(np * ns, sizeof *d->var_t);
    if (!d->B || !d->w || !d->eps || !d->sig || !d->eps_t || !d->sig_t || !d->var || !d->var_t)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld integration points", (long)np);
    for (long e = 0; e < count; e++) {
        const int *c = conn + 4 * (first + e);
        double re[4], ze[4];
        for (int a = 0; a < 4; a++)
            re[a] = r[c[a]], ze[a] = z[c[a]];
        fem_element_points(re, ze, (double(*)[32])(d->B + 128 * e), d->w + NQ * e);
        if (bbar)
            mean_dilatation((double(*)[32])(d->B + 128 * e), d->w + NQ * e);
    }
    return RF_OK;
}

static void linear_update(const void *params, const double *deps, const double *sig_n, const double *state_n,
                          double *sig, double *state)
{
    (void)state_n, (void)state;
    const fem_lame *p = params;
    const double tr = deps[0] + deps[1] + deps[2];
    for (int i = 0; i < 3; i++)
        sig[i] = sig_n[i] + p->lam * tr + 2 * p->mu * deps[i];
    sig[3] = sig_n[3] + p->mu * deps[3];
}

fem_point_law fem_point_law_linear(const fem_lame *lame)
{
    fem_point_law law = {"linear elastic", NC, 0, linear_update, lame, 0, NULL};
    return law;
}

static void material_update(const void *params, const double *deps, const double *sig_n, const double *state_n,
                            double *sig, double *state)
{
    const double d6[6] = {deps[0], deps[1], deps[2], deps[3], 0, 0};
    double s6[6] = {sig_n[0], sig_n[1], sig_n[2], sig_n[3], 0, 0}, D;
    rf_material_state st = {state_n[0], state_n[1], state_n[2]};
    rf_material_update(params, d6, s6, &st, &D);
    memcpy(sig, s6, NC * sizeof *sig);
    state[0] = st.plastic_strain_eq, state[1] = st.plastic_volumetric, state[2] = st.compaction, state[3] = D;
}

static double material_energy(const void *params, const double *sig)
{
    const double s6[6] = {sig[0], sig[1], sig[2], sig[3], 0, 0};
    return rf_material_elastic_energy(params, s6);
}

fem_point_law fem_point_law_material(const rf_material *m)
{
    fem_point_law law = {rf_material_model_name(m->model), NC, 4, material_update, m, 1, material_energy};
    return law;
}

long fem_kernel_points_axi_geostatic(fem_kernel *k, const double *r, const double *z, const int *conn,
                                     const fem_geostatic *g)
{
    if (!is_points(k) || !k->data)
        return -1;
    (void)r;
    /* the Gauss points in the order of fem_element_points (fem_element.c) */
    static const double XI[4] = {-1, 1, 1, -1}, ETA[4] = {-1, -1, 1, 1};
    const double gp = 1 / sqrt(3.0);
    const size_t np = (size_t)NQ * (size_t)k->count;
    double *depth = malloc((np + 1) * sizeof *depth);
    if (!depth)
        return -1;
    for (long e = 0; e < k->count; e++) {
        const int *c = conn + 4 * (k->first + e);
        for (int q = 0; q < NQ; q++) {
            double zq = 0;
            for (int a = 0; a < 4; a++)
                zq += 0.25 * (1 + XI[a] * XI[q] * gp) * (1 + ETA[a] * ETA[q] * gp) * z[c[a]];
            depth[NQ * e + q] = -zq;
        }
    }
    const fem_points_view v = points_view(k);
    const long outside = fem_points_geostatic(&v, depth, g);
    free(depth);
    return outside;
}
