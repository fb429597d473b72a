/* fem_kernel_points3d.c - the integration-point material kernel of the 3D
 * model's 8-node hexahedron (fem_kernel.h): at each of the 2x2x2 Gauss
 * points the strain from the stored shape-function gradients, optionally the
 * mean-dilatation B-bar, the point law's stress update from the strain
 * increment, and the internal force sum_q w_q Bbar_q^T sigma_q; commit()
 * accepts the trial values and integrates a dissipative law's plastic work.
 * Point laws with ncomp = 6: linear elasticity (the reference: with it and
 * without B-bar this kernel reproduces the matrix-free elastic kernel) and
 * the material library's return maps (rockfuzz/material.h: xx yy zz xy yz
 * zx, engineering shear strains, tensor stresses).
 *
 * B-bar without a B-bar matrix: with p_q = tr(sigma_q) / 3 and pbar its
 * w-weighted element mean, sum_q w_q Bbar_q^T sigma_q =
 * sum_q w_q B_q^T (sigma_q - p_q I + pbar I) (the volumetric rows of Bbar
 * are the element mean of those of B), so the force is the usual gradient
 * product with the pressure replaced by its element mean.
 *
 * Layout: per element 192 gradients and 8 weights (1.6 kB), per point 6
 * committed strains and stresses, their trial copies and the law's state;
 * one scalar element at a time (not yet in SIMD blocks like hex8_kernel.c). */
#include "fem3d_internal.h"
#include "fem_kernel.h"

#include <stdlib.h>
#include <string.h>

#define NQ 8 /* Gauss points per element */
#define NC 6 /* strain components: xx yy zz xy yz zx */
#define P3_UNIT 8 /* elements per work unit of forces_field */

typedef struct {
    fem_point_law law, law2;
    unsigned char *use2;  /* per element: law2 (NULL: law everywhere) */
    const int *conn;      /* 8 nodes per element (global numbering), the caller's */
    double *G;            /* per element [8 points][8 nodes][3]: dN/dx */
    double *w;            /* per element [8]: det J */
    int bbar;
    double *eps, *sig, *var;       /* committed, per point */
    double *eps_t, *sig_t, *var_t; /* trial of the last forces() */
    double plastic_work, plastic_strain_max;
    long point_max;
} p3_data;

/* Strains at the points (engineering shear), with the volume-averaged dilatation if bbar. */
static void element_strains(const double *G, const double *w, const double ue[24], int bbar, double eps[NQ][NC])
{
    double W = 0, th = 0;
    for (int q = 0; q < NQ; q++) {
        double H[3][3] = {{0}}; /* H[c][j] = d u_c / d x_j */
        for (int a = 0; a < 8; a++) {
            const double *g = G + 3 * (8 * q + a);
            for (int c = 0; c < 3; c++)
                for (int j = 0; j < 3; j++)
                    H[c][j] += ue[3 * a + c] * g[j];
        }
        eps[q][0] = H[0][0], eps[q][1] = H[1][1], eps[q][2] = H[2][2];
        eps[q][3] = H[0][1] + H[1][0], eps[q][4] = H[1][2] + H[2][1], eps[q][5] = H[2][0] + H[0][2];
        W += w[q], th += w[q] * (H[0][0] + H[1][1] + H[2][2]);
    }
    if (!bbar)
        return;
    for (int q = 0; q < NQ; q++) {
        const double c = (th / W - (eps[q][0] + eps[q][1] + eps[q][2])) / 3;
        eps[q][0] += c, eps[q][1] += c, eps[q][2] += c;
    }
}

/* fe = sum_q w_q B_q^T s_q, s_q = sigma_q with the pressure replaced by its element mean if bbar. */
static void element_force(const double *G, const double *w, const double sig[NQ][NC], int bbar, double fe[24])
{
    double W = 0, pbar = 0;
    for (int q = 0; q < NQ; q++)
        W += w[q], pbar += w[q] * (sig[q][0] + sig[q][1] + sig[q][2]) / 3;
    pbar /= W;
    memset(fe, 0, 24 * sizeof *fe);
    for (int q = 0; q < NQ; q++) {
        const double *s = sig[q], dp = bbar ? pbar - (s[0] + s[1] + s[2]) / 3 : 0;
        const double S[3][3] = {{w[q] * (s[0] + dp), w[q] * s[3], w[q] * s[5]},
                                {w[q] * s[3], w[q] * (s[1] + dp), w[q] * s[4]},
                                {w[q] * s[5], w[q] * s[4], w[q] * (s[2] + dp)}};
        for (int a = 0; a < 8; a++) {
            const double *g = G + 3 * (8 * q + a);
            for (int c = 0; c < 3; c++)
                fe[3 * a + c] += S[c][0] * g[0] + S[c][1] * g[1] + S[c][2] * g[2];
        }
    }
}

/* One element (local number le): strains, point updates (trial state), forces. */
static void p3_element(const fem_kernel *k, long le, const double ue[24], double fe[24])
{
    p3_data *d = k->data;
    const fem_point_law *L = d->use2 && d->use2[le] ? &d->law2 : &d->law;
    const size_t ns = (size_t)d->law.nstate, p0 = (size_t)NQ * (size_t)le;
    const double *G = d->G + 192 * le, *w = d->w + NQ * le;
    double eps[NQ][NC], sig[NQ][NC];
    element_strains(G, w, ue, d->bbar, eps);
    for (int q = 0; q < NQ; q++) {
        const size_t p = p0 + (size_t)q;
        double deps[NC];
        for (int i = 0; i < NC; i++)
            deps[i] = eps[q][i] - d->eps[NC * p + i];
        L->update(L->params, deps, d->sig + NC * p, d->var + ns * p, sig[q], d->var_t + ns * p);
        memcpy(d->eps_t + NC * p, eps[q], sizeof eps[q]);
        memcpy(d->sig_t + NC * p, sig[q], sizeof sig[q]);
    }
    element_force(G, w, (const double(*)[NC])sig, d->bbar, fe);
}

static void p3_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    for (long e = e0; e < e1; e++, ue += 24, fe += 24)
        p3_element(k, e - k->first, ue, fe);
}

/* Work units of P3_UNIT elements straight from the nodal field; element e's forces at fe + 24 e. */
static void p3_field(const fem_kernel *k, long w0, long w1, const double *u, double *fe)
{
    const p3_data *d = k->data;
    for (long w = w0; w < w1; w++)
        for (long le = w * P3_UNIT; le < (w + 1) * P3_UNIT && le < k->count; le++) {
            const long e = k->first + le;
            const int *cn = d->conn + 8 * e;
            double ue[24];
            for (int a = 0; a < 8; a++)
                for (int c = 0; c < 3; c++)
                    ue[3 * a + c] = u[3 * (long)cn[a] + c];
            p3_element(k, le, ue, fe + 24 * e);
        }
}

static void p3_commit(fem_kernel *k)
{
    p3_data *d = k->data;
    const size_t np = (size_t)NQ * (size_t)k->count, ns = (size_t)d->law.nstate;
    memcpy(d->eps, d->eps_t, np * NC * sizeof(double));
    memcpy(d->sig, d->sig_t, np * NC * sizeof(double));
    if (ns)
        memcpy(d->var, d->var_t, np * ns * sizeof(double));
    if (!d->law.dissipative)
        return;
    double W = 0, emax = d->plastic_strain_max;
    long pmax = d->point_max;
    for (size_t p = 0; p < np; p++) {
        const double *v = d->var + ns * p;
        W += d->w[p] * v[ns - 1];
        if (v[0] > emax)
            emax = v[0], pmax = (long)p;
    }
    d->plastic_work += W, d->plastic_strain_max = emax, d->point_max = pmax;
}

static void p3_destroy(fem_kernel *k)
{
    p3_data *d = k->data;
    if (d) {
        free(d->G), free(d->w), free(d->eps), free(d->sig), free(d->var), free(d->eps_t), free(d->sig_t);
        free(d->var_t), free(d->use2);
    }
    free(d);
    k->data = NULL;
}

static const fem_kernel_ops p3_ops = {"integration points (hexahedron)", p3_forces, NULL, p3_commit, p3_destroy,
                                      p3_field};

static rf_status p3_check(const fem_point_law *law, const fem_point_law *law2, const unsigned char *use2,
                          rf_error *err)
{
    if (use2 && (!law2 || law2->nstate != law->nstate || law2->ncomp != law->ncomp ||
                 law2->dissipative != law->dissipative))
        return rf_fail(err, RF_EINVAL, "fem3d: the two point laws of a block must have the same shape");
    if (law->ncomp != NC)
        return rf_fail(err, RF_EINVAL, "fem3d: the point law '%s' has %d strain components; the hexahedron needs %d",
                       law->name, law->ncomp, NC);
    if (law->dissipative && law->nstate < 2)
        return rf_fail(err, RF_EINVAL, "fem3d: the dissipative point law '%s' needs >= 2 state variables",
                       law->name);
    return RF_OK;
}

static rf_status p3_alloc(p3_data *d, long count, size_t ns, const unsigned char *use2, rf_error *err)
{
    const size_t np = (size_t)NQ * (size_t)count, ne = (size_t)(count > 0 ? count : 1);
    if (use2 && !(d->use2 = malloc(ne)))
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    if (use2)
        memcpy(d->use2, use2, (size_t)count);
    d->G = malloc(ne * 192 * sizeof *d->G), d->w = malloc(ne * NQ * sizeof *d->w);
    d->eps = calloc(np * NC + 1, sizeof *d->eps), d->sig = calloc(np * NC + 1, sizeof *d->sig);
    d->eps_t = calloc(np * NC + 1, sizeof *d->eps_t), d->sig_t = calloc(np * NC + 1, sizeof *d->sig_t);
    d->var = calloc(np * ns + 1, sizeof *d->var), d->var_t = calloc(np * ns + 1, sizeof *d->var_t);
    if (!d->G || !d->w || !d->eps || !d->sig || !d->eps_t || !d->sig_t || !d->var || !d->var_t)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld integration points", (long)np);
    return RF_OK;
}

rf_status fem_kernel_points_hex(fem_kernel *k, long first, long count, const double *x, const int *conn,
                                const fem_point_law *law, const fem_point_law *law2, const unsigned char *use_law2,
                                int bbar, rf_error *err)
{
    k->ops = NULL, k->data = NULL;
    rf_status st = p3_check(law, law2, use_law2, err);
    if (st != RF_OK)
        return st;
    p3_data *d = calloc(1, sizeof *d);
    if (!d)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    k->ops = &p3_ops, k->first = first, k->count = count, k->ndofe = 24, k->data = d;
    k->units = (count + P3_UNIT - 1) / P3_UNIT;
    d->law = *law, d->law2 = use_law2 ? *law2 : *law, d->conn = conn, d->bbar = bbar, d->point_max = -1;
    if ((st = p3_alloc(d, count, (size_t)law->nstate, use_law2, err)) != RF_OK)
        return st;
    for (long le = 0; le < count; le++) {
        const int *cn = conn + 8 * (first + le);
        double xe[24];
        for (int a = 0; a < 8; a++)
            for (int c = 0; c < 3; c++)
                xe[3 * a + c] = x[3 * (long)cn[a] + c];
        f3_hex_gradients(xe, (double(*)[8][3])(d->G + 192 * le), d->w + NQ * le);
        for (int q = 0; q < NQ; q++)
            if (!(d->w[NQ * le + q] > 0))
                return rf_fail(err, RF_EINVAL, "fem3d: element %ld has det J = %g at Gauss point %d", first + le,
                               d->w[NQ * le + q], q);
    }
    return RF_OK;
}

void fem_kernel_points_hex_report(const fem_kernel *k, fem_kernel_report *r)
{
    r->plastic_work = r->plastic_strain_max = 0, r->element_max = -1;
    if (k->ops != &p3_ops || !k->data)
        return;
    const p3_data *d = k->data;
    r->plastic_work = d->plastic_work, r->plastic_strain_max = d->plastic_strain_max;
    r->element_max = d->point_max < 0 ? -1 : k->first + d->point_max / NQ;
}

int fem_kernel_points_hex_cell(const fem_kernel *k, long e, double sig[6], double *plastic_strain)
{
    if (k->ops != &p3_ops || !k->data || e < k->first || e >= k->first + k->count)
        return 0;
    const p3_data *d = k->data;
    const size_t p0 = (size_t)NQ * (size_t)(e - k->first), ns = (size_t)d->law.nstate;
    double emax = 0;
    for (int i = 0; i < NC; i++)
        sig[i] = 0;
    for (size_t p = p0; p < p0 + NQ; p++) {
        for (int i = 0; i < NC; i++)
            sig[i] += d->sig[NC * p + i] / NQ;
        if (d->law.dissipative && d->var[ns * p] > emax)
            emax = d->var[ns * p];
    }
    *plastic_strain = emax;
    return 1;
}

double fem_kernel_points_hex_energy(const fem_kernel *k)
{
    if (k->ops != &p3_ops || !k->data)
        return -1;
    const p3_data *d = k->data;
    if (!d->law.energy || !d->law2.energy)
        return -1;
    double E = 0;
    for (size_t p = 0; p < (size_t)NQ * (size_t)k->count; p++) {
        const fem_point_law *L = d->use2 && d->use2[p / NQ] ? &d->law2 : &d->law;
        E += d->w[p] * L->energy(L->params, d->sig + NC * p);
    }
    return E;
}

static void linear3d_update(const void *params, const double *deps, const double *sig_n, const double *state_n,
                            double *sig, double *state)
{
    (void)state_n, (void)state;
    const fem_lame *p = params;
    const double tr = deps[0] + deps[1] + deps[2];
    for (int i = 0; i < 3; i++)
        sig[i] = sig_n[i] + p->lam * tr + 2 * p->mu * deps[i];
    for (int i = 3; i < 6; i++)
        sig[i] = sig_n[i] + p->mu * deps[i];
}

static double linear3d_energy(const void *params, const double *sig)
{
    const fem_lame *p = params; /* 1/2 sig : C^-1 : sig with K = lam + 2 mu / 3 */
    const double tr = sig[0] + sig[1] + sig[2], K = p->lam + 2 * p->mu / 3;
    double ss = 0;
    for (int i = 0; i < 3; i++)
        ss += (sig[i] - tr / 3) * (sig[i] - tr / 3);
    ss += 2 * (sig[3] * sig[3] + sig[4] * sig[4] + sig[5] * sig[5]);
    return tr * tr / (18 * K) + ss / (4 * p->mu);
}

fem_point_law fem_point_law_linear3d(const fem_lame *lame)
{
    fem_point_law law = {"linear elastic (3D)", NC, 0, linear3d_update, lame, 0, linear3d_energy};
    return law;
}

static void material3d_update(const void *params, const double *deps, const double *sig_n, const double *state_n,
                              double *sig, double *state)
{
    rf_material_state st = {state_n[0], state_n[1], state_n[2]};
    double D;
    memcpy(sig, sig_n, NC * sizeof *sig);
    rf_material_update(params, deps, sig, &st, &D);
    state[0] = st.plastic_strain_eq, state[1] = st.plastic_volumetric, state[2] = st.compaction, state[3] = D;
}

static double material3d_energy(const void *params, const double *sig)
{
    return rf_material_elastic_energy(params, sig);
}

fem_point_law fem_point_law_material3d(const rf_material *m)
{
    fem_point_law law = {rf_material_model_name(m->model), NC, 4, material3d_update, m, 1, material3d_energy};
    return law;
}
