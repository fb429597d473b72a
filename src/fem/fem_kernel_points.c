/* fem_kernel_points.c - the integration-point material kernel of the
 * axisymmetric quad (fem_kernel.h): strain at each Gauss point from B ue,
 * the point law's stress update from the strain increment, internal force
 * sum_q w_q B_q^T sigma_q; trial values become committed in commit(), which
 * also integrates a dissipative law's plastic work (sum_q w_q D_q).  Optional
 * mean-dilatation B-bar.  And two point laws: linear elasticity (the
 * reference: with it this kernel reproduces the precomputed stiffness) and
 * the material library's return maps (rockfuzz/material.h).
 *
 * The elements run in SIMD blocks of AXB_W consecutive elements, one per
 * vector lane (fem_points_block.c: geometry, strains, spins, forces), the
 * laws lane by lane (a return map branches).  Small strain keeps each
 * block's gradients, N/r, weights and B-bar correction; the updated
 * Lagrangian form computes them twice per step (mid-step and current
 * geometry).  The per-point state stays in point order (p = 4 le + q). */
#include "fem_internal.h"
#include "fem_kernel.h"
#include "fem_points_block.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NQ 4 /* Gauss points per element */
#define NC 4 /* strain components */

typedef struct {
    fem_point_law law, law2;
    unsigned char *use2;      /* per element: law2 (NULL: law everywhere) */
    long nblk;                /* blocks of AXB_W elements, the last one padded */
    double *G, *C, *wb;       /* per block: AXB_G, AXB_C, AXB_Q (fem_points_block.h) */
    double *w;      /* 4 per element */
    double *eps, *sig, *var;          /* committed, per point */
    double *eps_t, *sig_t, *var_t;    /* trial of the last forces() */
    double plastic_work, plastic_strain_max; /* committed (dissipative laws) */
    long point_max;                          /* the point of plastic_strain_max (-1: none) */
    /* updated Lagrangian (fem_kernel_points_axi_large): reference node
       coordinates r0 z0 r1 z1 ... and committed / trial displacements, 8 per
       element (nblk AXB_W elements, the padding a unit square); w then holds
       the committed current weights, w_t the trial ones */
    double *X, *ue_c, *ue_t, *w_t;
    int bbar;
} points_data;

/* The laws of block b's elements [lo, hi) (local numbers), lane by lane.
 * sn NULL (small strain): eps are total strains, the committed stresses the
 * points'.  Else eps are the increments and sn [4 points][4][AXB_W] the
 * committed stresses turned by the increment's spin.  sig: the trial
 * stresses (0 in other lanes).  The laws' inputs are all stored first: a law
 * reads them with 16-byte loads, which stall on 8-byte stores still in the
 * store buffer (measured: the small-strain runs were 5-15 % slower). */
static void block_laws(points_data *d, long b, long lo, long hi, const double *eps, const double *sn, double *sig)
{
    double in[AXB_W][NQ][2][NC]; /* per lane and point: deps, committed stress (UL) */
    for (long le = lo; le < hi; le++)
        for (int q = 0; q < NQ; q++) {
            const long l = le - b * AXB_W, p = NQ * le + q;
            for (int i = 0; i < NC; i++) {
                const double s = eps[(q * NC + i) * AXB_W + l];
                if (sn)
                    in[l][q][0][i] = s, d->eps_t[NC * p + i] = d->eps[NC * p + i] + s,
                    in[l][q][1][i] = sn[(q * NC + i) * AXB_W + l];
                else
                    d->eps_t[NC * p + i] = s, in[l][q][0][i] = s - d->eps[NC * p + i];
            }
        }
    memset(sig, 0, AXB_S * sizeof *sig);
    for (long le = lo; le < hi; le++) {
        const long l = le - b * AXB_W;
        const fem_point_law *L = d->use2 && d->use2[le] ? &d->law2 : &d->law;
        const int ns = L->nstate;
        for (int q = 0; q < NQ; q++) {
            const long p = NQ * le + q;
            double *st = d->sig_t + NC * p;
            L->update(L->params, in[l][q][0], sn ? in[l][q][1] : d->sig + NC * p, d->var + (size_t)ns * p, st,
                      d->var_t + (size_t)ns * p);
            for (int i = 0; i < NC; i++)
                sig[(q * NC + i) * AXB_W + l] = st[i];
        }
    }
}

/* Element vectors (8 each, elements [lo, hi) of block b from v) into lanes
 * (zeros elsewhere), and back. */
static void lanes_in(const double *v, long b, long lo, long hi, double *u)
{
    memset(u, 0, AXB_U * sizeof *u);
    for (long le = lo; le < hi; le++, v += 8)
        for (int j = 0; j < 8; j++)
            u[j * AXB_W + le - b * AXB_W] = v[j];
}

static void lanes_out(const double *F, long b, long lo, long hi, double *v)
{
    for (long le = lo; le < hi; le++, v += 8)
        for (int j = 0; j < 8; j++)
            v[j] = F[j * AXB_W + le - b * AXB_W];
}

static void points_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    points_data *d = k->data;
    const long l0 = e0 - k->first, l1 = e1 - k->first;
    for (long b = l0 / AXB_W; b * AXB_W < l1; b++) {
        const long lo = l0 > b * AXB_W ? l0 : b * AXB_W, hi = l1 < (b + 1) * AXB_W ? l1 : (b + 1) * AXB_W;
        const double *G = d->G + AXB_G * b, *C = d->C + AXB_C * b;
        double u[AXB_U], eps[AXB_S], sig[AXB_S], F[AXB_U];
        lanes_in(ue + 8 * (lo - l0), b, lo, hi, u);
        axb_strains(G, C, u, eps);
        block_laws(d, b, lo, hi, eps, NULL, sig);
        axb_force(G, C, d->wb + AXB_Q * b, sig, F);
        lanes_out(F, b, lo, hi, fe + 8 * (lo - l0));
    }
}

/* Updated Lagrangian block: the strain increment B(x_mid) du on the
 * mid-step geometry (exactly zero for a rigid rotation of any size), the
 * committed stress turned by the Hughes-Winget rotation of the increment's
 * spin (exact for that rotation), the return map, and the force
 * sum_q w_q(x) B_q(x)^T sigma_q on the current geometry x = X + u.  Lanes
 * outside [lo, hi) keep their committed displacement (no increment). */
static void large_block(points_data *d, long b, long lo, long hi, const double *ue, double *F)
{
    double rm[4 * AXB_W], zm[4 * AXB_W], rc[4 * AXB_W], zc[4 * AXB_W], du[AXB_U];
    for (int l = 0; l < AXB_W; l++) {
        const long le = b * AXB_W + l;
        const double *X = d->X + 8 * le, *uc = d->ue_c + 8 * le;
        const double *u = le >= lo && le < hi ? ue + 8 * (le - lo) : uc;
        for (int a = 0; a < 4; a++) {
            const int i = a * AXB_W + l;
            rm[i] = X[2 * a] + 0.5 * (u[2 * a] + uc[2 * a]);
            zm[i] = X[2 * a + 1] + 0.5 * (u[2 * a + 1] + uc[2 * a + 1]);
            rc[i] = X[2 * a] + u[2 * a], zc[i] = X[2 * a + 1] + u[2 * a + 1];
            du[2 * a * AXB_W + l] = u[2 * a] - uc[2 * a], du[(2 * a + 1) * AXB_W + l] = u[2 * a + 1] - uc[2 * a + 1];
        }
    }
    double Gm[AXB_G], Cm[AXB_C], wm[AXB_Q], Gc[AXB_G], Cc[AXB_C], wc[AXB_Q], spin[AXB_Q], eps[AXB_S], sig[AXB_S];
    axb_geometry(rm, zm, d->bbar, Gm, Cm, wm);
    axb_spins(Gm, du, spin);
    axb_geometry(rc, zc, d->bbar, Gc, Cc, wc);
    for (long le = lo; le < hi; le++) {
        memcpy(d->ue_t + 8 * le, ue + 8 * (le - lo), 8 * sizeof *ue);
        for (int q = 0; q < NQ; q++)
            d->w_t[NQ * le + q] = wc[q * AXB_W + le - b * AXB_W];
    }
    double sn[AXB_S] = {0}; /* the committed stresses, turned */
    for (long le = lo; le < hi; le++)
        for (int i = 0; i < NQ * NC; i++)
            sn[i * AXB_W + le - b * AXB_W] = d->sig[NC * NQ * le + i];
    axb_rotate(spin, sn);
    axb_strains(Gm, Cm, du, eps);
    block_laws(d, b, lo, hi, eps, sn, sig);
    axb_force(Gc, Cc, wc, sig, F);
}

static void points_forces_large(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    points_data *d = k->data;
    const long l0 = e0 - k->first, l1 = e1 - k->first;
    for (long b = l0 / AXB_W; b * AXB_W < l1; b++) {
        const long lo = l0 > b * AXB_W ? l0 : b * AXB_W, hi = l1 < (b + 1) * AXB_W ? l1 : (b + 1) * AXB_W;
        double F[AXB_U];
        large_block(d, b, lo, hi, ue + 8 * (lo - l0), F);
        lanes_out(F, b, lo, hi, fe + 8 * (lo - l0));
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
        free(d->G), free(d->C), free(d->wb), free(d->w), free(d->eps), free(d->sig), free(d->var), free(d->eps_t);
        free(d->sig_t);
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

/* Node a of local element le (block padding beyond count: a unit square at r = 1..2 m). */
static void element_node(const double *r, const double *z, const int *conn, long first, long count, long le, int a,
                         double *re, double *ze)
{
    static const double PR[4] = {1, 2, 2, 1}, PZ[4] = {0, 0, 1, 1};
    if (le >= count) {
        *re = PR[a], *ze = PZ[a];
        return;
    }
    const int n = conn[4 * (first + le) + a];
    *re = r[n], *ze = z[n];
}

rf_status fem_kernel_points_axi_large(fem_kernel *k, const double *r, const double *z, const int *conn, rf_error *err)
{
    if (!is_points(k) || !k->data)
        return rf_fail(err, RF_EINVAL, "fem: updated Lagrangian needs an integration-point kernel");
    points_data *d = k->data;
    const size_t ne = (size_t)k->count, np = NQ * ne;
    const size_t nl = (size_t)d->nblk * AXB_W; /* elements with the padding */
    d->X = malloc((nl + 1) * 8 * sizeof *d->X), d->ue_c = calloc(nl + 1, 8 * sizeof *d->ue_c);
    d->ue_t = calloc(nl + 1, 8 * sizeof *d->ue_t), d->w_t = malloc((np + 1) * sizeof *d->w_t);
    if (!d->X || !d->ue_c || !d->ue_t || !d->w_t)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld elements", k->count);
    for (size_t e = 0; e < nl; e++)
        for (int a = 0; a < 4; a++) {
            double re, ze;
            element_node(r, z, conn, k->first, k->count, (long)e, a, &re, &ze);
            d->X[8 * e + 2 * a] = re, d->X[8 * e + 2 * a + 1] = ze;
        }
    memcpy(d->w_t, d->w, np * sizeof *d->w);
    k->ops = &points_large_ops;
    return RF_OK;
}

int fem_kernel_points_axi_ale(fem_kernel *k, fem_points_view *v, double **ue_c)
{
    if (k->ops != &points_large_ops || !k->data)
        return 0;
    *v = points_view(k);
    *ue_c = ((points_data *)k->data)->ue_c;
    return 1;
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
    d->nblk = (count + AXB_W - 1) / AXB_W;
    d->G = malloc(((size_t)d->nblk * AXB_G + 1) * sizeof *d->G);
    d->C = malloc(((size_t)d->nblk * AXB_C + 1) * sizeof *d->C);
    d->wb = malloc(((size_t)d->nblk * AXB_Q + 1) * sizeof *d->wb), d->w = malloc((np + 1) * sizeof *d->w);
    d->eps = calloc(np * NC, sizeof *d->eps), d->sig = calloc(np * NC, sizeof *d->sig);
    d->eps_t = calloc(np * NC, sizeof *d->eps_t), d->sig_t = calloc(np * NC, sizeof *d->sig_t);
    d->var = calloc(np * ns, sizeof *d->var), d->var_t = calloc(np * ns, sizeof *d->var_t);
    if (!d->G || !d->C || !d->wb || !d->w || !d->eps || !d->sig || !d->eps_t || !d->sig_t || !d->var || !d->var_t)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld integration points", (long)np);
    for (long b = 0; b < d->nblk; b++) {
        double rl[4 * AXB_W], zl[4 * AXB_W], *wb = d->wb + AXB_Q * b;
        for (int l = 0; l < AXB_W; l++)
            for (int a = 0; a < 4; a++)
                element_node(r, z, conn, first, count, b * AXB_W + l, a, &rl[a * AXB_W + l], &zl[a * AXB_W + l]);
        axb_geometry(rl, zl, bbar, d->G + AXB_G * b, d->C + AXB_C * b, wb);
        for (long le = b * AXB_W; le < count && le < (b + 1) * AXB_W; le++)
            for (int q = 0; q < NQ; q++)
                d->w[NQ * le + q] = wb[q * AXB_W + le - b * AXB_W];
    }
    return RF_OK;
}

static void linear_update(const void *params, const double *deps, const double *sig_n, const double *state_n,
                          double *sig, double *state)
{
    (void)state_n, (void)state;
    fem_lame_update(params, deps, sig_n, sig, 4);
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
