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
 * Layout: blocks of HEX8_W elements, one per vector lane, as hex8_kernel.c
 * (structure of arrays): per element 192 gradients and 8 weights (1.6 kB),
 * the strains and forces as vector multiply-adds over the lanes (GCC/clang
 * vector extension, target clones up to AVX-512), the point laws lane by
 * lane (a return map branches); per point 6 committed strains and stresses,
 * their trial copies and the law's state.  Vectors cross function calls by
 * pointer only. */
#include "fem3d_internal.h"
/* The multiply-adds of the kinematics fused into FMA, as in hex8_kernel.c (round-off only). */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=fast")
#elif defined(__clang__)
#pragma clang fp contract(fast)
#endif

#include "fem_kernel_points3d.h"

#include <stdlib.h>
#include <string.h>

#define NQ P3_NQ
#define NC P3_NC
#define PW P3_W
typedef p3_vec pvec;

P3_CLONES
void p3_block_strains(const double *G, const double *wb, const pvec ue[24], int bbar, pvec eps[NQ][NC],
                      pvec spin[NQ][3])
{
    pvec W = {0}, th = {0};
    for (int q = 0; q < NQ; q++) {
        pvec H[9] = {{0}}, w; /* H[3c + j] = d u_c / d x_j */
        for (int a = 0; a < 8; a++) {
            pvec g[3];
            for (int j = 0; j < 3; j++)
                p3_vget(&g[j], G + ((q * 8 + a) * 3 + j) * PW);
            for (int c = 0; c < 3; c++)
                for (int j = 0; j < 3; j++)
                    H[3 * c + j] += ue[3 * a + c] * g[j];
        }
        eps[q][0] = H[0], eps[q][1] = H[4], eps[q][2] = H[8];
        eps[q][3] = H[1] + H[3], eps[q][4] = H[5] + H[7], eps[q][5] = H[6] + H[2];
        if (spin) /* W v = spin x v with W = (H - H^T) / 2 */
            spin[q][0] = 0.5 * (H[7] - H[5]), spin[q][1] = 0.5 * (H[2] - H[6]), spin[q][2] = 0.5 * (H[3] - H[1]);
        p3_vget(&w, wb + q * PW);
        W += w, th += w * (H[0] + H[4] + H[8]);
    }
    if (!bbar)
        return;
    const pvec m = th / W;
    for (int q = 0; q < NQ; q++) {
        const pvec c = (m - (eps[q][0] + eps[q][1] + eps[q][2])) / 3;
        eps[q][0] += c, eps[q][1] += c, eps[q][2] += c;
    }
}

P3_CLONES
void p3_block_force(const double *G, const double *wb, const pvec sig[NQ][NC], int bbar, pvec F[24])
{
    pvec W = {0}, pbar = {0};
    for (int q = 0; q < NQ; q++) {
        pvec w;
        p3_vget(&w, wb + q * PW);
        W += w, pbar += w * (sig[q][0] + sig[q][1] + sig[q][2]) / 3;
    }
    pbar /= W;
    for (int r = 0; r < 24; r++)
        F[r] = (pvec){0};
    for (int q = 0; q < NQ; q++) {
        const pvec *s = sig[q], dp = bbar ? pbar - (s[0] + s[1] + s[2]) / 3 : (pvec){0};
        pvec w;
        p3_vget(&w, wb + q * PW);
        const pvec S[9] = {w * (s[0] + dp), w * s[3], w * s[5], w * s[3], w * (s[1] + dp),
                           w * s[4], w * s[5], w * s[4], w * (s[2] + dp)};
        for (int a = 0; a < 8; a++) {
            pvec g[3];
            for (int j = 0; j < 3; j++)
                p3_vget(&g[j], G + ((q * 8 + a) * 3 + j) * PW);
            for (int c = 0; c < 3; c++)
                F[3 * a + c] += S[3 * c] * g[0] + S[3 * c + 1] * g[1] + S[3 * c + 2] * g[2];
        }
    }
}

/* One point's law call: small strain from the total strain et, or (spin) from
   the increment de with the committed stress turned first. */
static void point_law(const p3_data *d, const fem_point_law *L, size_t p, const double *e, const double *spin,
                      double *st)
{
    const size_t ns = (size_t)L->nstate;
    double deps[NC], s0[NC], *et = d->eps_t + NC * p;
    const double *sn = d->sig + NC * p;
    for (int i = 0; i < NC; i++) {
        deps[i] = spin ? e[i] : e[i] - d->eps[NC * p + i];
        et[i] = spin ? d->eps[NC * p + i] + e[i] : e[i];
    }
    if (spin) {
        memcpy(s0, sn, sizeof s0);
        rf_material_rotate(s0, spin);
        sn = s0;
    }
    L->update(L->params, deps, sn, d->var + ns * p, st, d->var_t + ns * p);
}

void p3_block_laws(const p3_data *d, long b, const pvec eps[NQ][NC], const pvec spin[NQ][3], pvec sig[NQ][NC])
{
    double e[NQ][NC][PW], s[NQ][NC][PW], w[NQ][3][PW];
    memcpy(e, eps, sizeof e);
    if (spin)
        memcpy(w, spin, sizeof w);
    memset(s, 0, sizeof s);
    for (int l = 0; l < PW; l++) {
        const long le = d->lane[b * PW + l];
        if (le < 0)
            continue;
        const fem_point_law *L = d->use2 && d->use2[le] ? &d->law2 : &d->law;
        for (int q = 0; q < NQ; q++) {
            const size_t p = (size_t)NQ * (size_t)le + (size_t)q;
            double el[NC], wl[3], *st = d->sig_t + NC * p;
            for (int i = 0; i < NC; i++)
                el[i] = e[q][i][l];
            for (int i = 0; i < 3; i++)
                wl[i] = spin ? w[q][i][l] : 0;
            point_law(d, L, p, el, spin ? wl : NULL, st);
            for (int i = 0; i < NC; i++)
                s[q][i][l] = st[i];
        }
    }
    memcpy(sig, s, sizeof s);
}

void p3_block_gather(const p3_data *d, long b, const double *u, double ul[24][PW])
{
    for (int a = 0; a < 8; a++)
        for (int l = 0; l < PW; l++) {
            const double *un = u + 3 * (long)d->conn[(b * 8 + a) * PW + l];
            ul[3 * a][l] = un[0], ul[3 * a + 1][l] = un[1], ul[3 * a + 2][l] = un[2];
        }
}

void p3_block_scatter(const p3_data *d, long b, long first, const double fl[24][PW], double *fe)
{
    for (int l = 0; l < PW; l++) {
        const long le = d->lane[b * PW + l];
        if (le >= 0)
            for (int r = 0; r < 24; r++)
                fe[24 * (first + le) + r] = fl[r][l];
    }
}

/* Work units = blocks of PW elements, straight from the nodal field; element e's forces at fe + 24 e. */
static void p3_field(const fem_kernel *k, long b0, long b1, const double *u, double *fe)
{
    const p3_data *d = k->data;
    for (long b = b0; b < b1; b++) {
        double ul[24][PW], fl[24][PW];
        p3_block_gather(d, b, u, ul);
        pvec ue[24], eps[NQ][NC], sig[NQ][NC], F[24];
        memcpy(ue, ul, sizeof ul);
        const double *G = d->G + (size_t)b * NQ * 24 * PW, *wb = d->wb + (size_t)b * NQ * PW;
        p3_block_strains(G, wb, ue, d->bbar, eps, NULL);
        p3_block_laws(d, b, (const pvec(*)[NC])eps, NULL, sig);
        p3_block_force(G, wb, (const pvec(*)[NC])sig, d->bbar, F);
        memcpy(fl, F, sizeof fl);
        p3_block_scatter(d, b, k->first, (const double(*)[PW])fl, fe);
    }
}

fem_points_view p3_view(const fem_kernel *k)
{
    p3_data *d = k->data;
    return (fem_points_view){(size_t)NQ * (size_t)k->count, NQ, NC, &d->law, &d->law2, d->use2, d->w,
                             d->eps, d->sig, d->var, d->eps_t, d->sig_t, d->var_t};
}

void p3_accept(fem_kernel *k)
{
    p3_data *d = k->data;
    const fem_points_view v = p3_view(k);
    fem_points_accept(&v, &d->plastic_work, &d->plastic_strain_max, &d->point_max);
}

void p3_destroy(fem_kernel *k)
{
    p3_data *d = k->data;
    if (d) {
        free(d->conn), free(d->lane), free(d->G), free(d->wb), free(d->w), free(d->eps), free(d->sig);
        free(d->var), free(d->eps_t), free(d->sig_t), free(d->var_t), free(d->use2);
        free(d->X), free(d->uc), free(d->ut), free(d->w_t);
    }
    free(d);
    k->data = NULL;
}

void p3_report(const fem_kernel *k, fem_kernel_report *r)
{
    const p3_data *d = k->data;
    r->plastic_work = d->plastic_work, r->plastic_strain_max = d->plastic_strain_max;
    r->element_max = d->point_max < 0 ? -1 : k->first + d->point_max / NQ;
}

static const fem_kernel_ops p3_ops = {"integration points (hexahedron, SIMD blocks)", NULL, NULL, p3_accept,
                                      p3_destroy, p3_field, p3_report};

/* Both forms of the kernel (small strain here, updated Lagrangian in
   fem_kernel_points3d_large.c) free their data with p3_destroy. */
int p3_is(const fem_kernel *k)
{
    return k->ops && k->ops->destroy == p3_destroy && k->data;
}

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
    d->nblk = (count + PW - 1) / PW;
    const size_t lanes = (size_t)(d->nblk > 0 ? d->nblk : 1) * PW;
    d->conn = malloc(lanes * 8 * sizeof *d->conn), d->lane = malloc(lanes * sizeof *d->lane);
    d->G = calloc(lanes * NQ * 24, sizeof *d->G), d->wb = malloc(lanes * NQ * sizeof *d->wb);
    d->w = malloc(ne * NQ * sizeof *d->w);
    d->eps = calloc(np * NC + 1, sizeof *d->eps), d->sig = calloc(np * NC + 1, sizeof *d->sig);
    d->eps_t = calloc(np * NC + 1, sizeof *d->eps_t), d->sig_t = calloc(np * NC + 1, sizeof *d->sig_t);
    d->var = calloc(np * ns + 1, sizeof *d->var), d->var_t = calloc(np * ns + 1, sizeof *d->var_t);
    if (!d->conn || !d->lane || !d->G || !d->wb || !d->w || !d->eps || !d->sig || !d->eps_t || !d->sig_t ||
        !d->var || !d->var_t)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld integration points", (long)np);
    return RF_OK;
}

/* Lane s (block s / PW, lane s % PW): the element's nodes, gradients and weights; padding repeats
   element 0's nodes with zero gradients and unit weights (zero strain, no law call). */
static rf_status p3_lane(p3_data *d, long s, long first, long count, const double *x, const int *conn,
                         rf_error *err)
{
    const long b = s / PW, l = s % PW, le = s < count ? s : -1;
    const int *cn = conn + 8 * (first + (le < 0 ? 0 : le));
    d->lane[s] = le;
    for (int a = 0; a < 8; a++)
        d->conn[(b * 8 + a) * PW + l] = cn[a];
    for (int q = 0; q < NQ; q++)
        d->wb[(b * NQ + q) * PW + l] = 1;
    if (le < 0)
        return RF_OK;
    double xe[24], dN[8][8][3], *w = d->w + NQ * le;
    for (int a = 0; a < 8; a++)
        for (int c = 0; c < 3; c++)
            xe[3 * a + c] = x[3 * (long)cn[a] + c];
    f3_hex_gradients(xe, dN, w);
    for (int q = 0; q < NQ; q++) {
        if (!(w[q] > 0))
            return rf_fail(err, RF_EINVAL, "fem3d: element %ld has det J = %g at Gauss point %d", first + le, w[q], q);
        d->wb[(b * NQ + q) * PW + l] = w[q];
        for (int a = 0; a < 8; a++)
            for (int j = 0; j < 3; j++)
                d->G[(((b * NQ + q) * 8 + a) * 3 + j) * PW + l] = dN[q][a][j];
    }
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
    d->law = *law, d->law2 = use_law2 ? *law2 : *law, d->bbar = bbar, d->point_max = -1;
    if ((st = p3_alloc(d, count, (size_t)law->nstate, use_law2, err)) != RF_OK)
        return st;
    k->units = d->nblk;
    for (long s = 0; s < d->nblk * PW; s++)
        if ((st = p3_lane(d, s, first, count, x, conn, err)) != RF_OK)
            return st;
    return RF_OK;
}

int fem_kernel_points_hex_cell(const fem_kernel *k, long e, double sig[6], double *plastic_strain)
{
    if (!p3_is(k) || e < k->first || e >= k->first + k->count)
        return 0;
    const fem_points_view v = p3_view(k);
    fem_points_cell(&v, e - k->first, sig, plastic_strain);
    return 1;
}

long fem_kernel_points_hex_geostatic(fem_kernel *k, const double *depth, const fem_geostatic *g)
{
    if (!p3_is(k) || !k->data) /* either kinematics: the updated-Lagrangian kernel shares the points */
        return -1;
    const fem_points_view v = p3_view(k);
    return fem_points_geostatic(&v, depth, g);
}

double fem_kernel_points_hex_energy(const fem_kernel *k)
{
    if (!p3_is(k))
        return -1;
    const fem_points_view v = p3_view(k);
    return fem_points_energy(&v);
}

static void linear3d_update(const void *params, const double *deps, const double *sig_n, const double *state_n,
                            double *sig, double *state)
{
    (void)state_n, (void)state;
    fem_lame_update(params, deps, sig_n, sig, 6);
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
