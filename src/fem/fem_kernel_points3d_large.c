/* fem_kernel_points3d_large.c - the updated-Lagrangian (large deformation)
 * form of the hexahedron's integration-point kernel (fem_kernel.h,
 * fem_kernel_points_hex_large), on the same SIMD blocks and helpers as the
 * small-strain form (fem_kernel_points3d.h).  Per block and step, from the
 * committed displacements u_n and the new ones u_{n+1}:
 *
 *   1. shape-function gradients and det J of the mid-step geometry
 *      X + (u_n + u_{n+1}) / 2; the strain increment (B-bar of that geometry
 *      if chosen) and the spin 1/2 curl(u_{n+1} - u_n) at every point;
 *   2. the committed Cauchy stress turned by the Hughes-Winget rotation of
 *      that spin (rf_material_rotate), then the law's update;
 *   3. gradients and det J of the current geometry X + u_{n+1}: the force
 *      sum_q w_q B_q^T sigma_q (B-bar as in the small-strain form).
 *
 * For a rigid motion of any size the mid-step increment has no strain and
 * the Cayley rotation of its spin is exactly the rotation of the increment
 * (Hughes & Winget 1980), so a stress turns with the body.  commit() keeps
 * u_{n+1} and the current weights, over which the plastic dissipation is
 * integrated.  The geometry is recomputed in SIMD (J, its inverse, the
 * gradients) twice per step: the gradients of the small-strain form are
 * stored once. */
#include "fem_kernel_points3d.h"

#include <math.h>
#include <stdlib.h>

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=fast")
#elif defined(__clang__)
#pragma clang fp contract(fast)
#endif

#define NQ P3_NQ
#define NC P3_NC
#define PW P3_W
typedef p3_vec pvec;

/* dN_a/dxi_i at Gauss point q: the node and point order of fem3d_element.c
   (point q at (XI[q], ETA[q], ZETA[q]) / sqrt 3). */
static void natural_gradients(double dl[NQ][8][3])
{
    static const double XI[8] = {-1, 1, 1, -1, -1, 1, 1, -1};
    static const double ETA[8] = {-1, -1, 1, 1, -1, -1, 1, 1};
    static const double ZETA[8] = {-1, -1, -1, -1, 1, 1, 1, 1};
    const double g = 1 / sqrt(3.0);
    for (int q = 0; q < NQ; q++)
        for (int a = 0; a < 8; a++) {
            const double xi = XI[q] * g, eta = ETA[q] * g, zeta = ZETA[q] * g;
            dl[q][a][0] = 0.125 * XI[a] * (1 + ETA[a] * eta) * (1 + ZETA[a] * zeta);
            dl[q][a][1] = 0.125 * ETA[a] * (1 + XI[a] * xi) * (1 + ZETA[a] * zeta);
            dl[q][a][2] = 0.125 * ZETA[a] * (1 + XI[a] * xi) * (1 + ETA[a] * eta);
        }
}

/* Gradients G [8 points][8 nodes][3][W] and det J wb [8 points][W] of the
   block's geometry x (as f3_hex_gradients, lane by lane in the vector). */
P3_CLONES
static void block_geometry(const double dl[NQ][8][3], const pvec x[24], double *G, double *wb)
{
    for (int q = 0; q < NQ; q++) {
        pvec J[9] = {{0}}; /* J[3 i + j] = d x_j / d xi_i */
        for (int a = 0; a < 8; a++)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    J[3 * i + j] += dl[q][a][i] * x[3 * a + j];
        const pvec c0 = J[4] * J[8] - J[5] * J[7], c1 = J[5] * J[6] - J[3] * J[8], c2 = J[3] * J[7] - J[4] * J[6];
        const pvec det = J[0] * c0 + J[1] * c1 + J[2] * c2, r = 1 / det;
        const pvec inv[9] = {c0 * r, (J[2] * J[7] - J[1] * J[8]) * r, (J[1] * J[5] - J[2] * J[4]) * r,
                             c1 * r, (J[0] * J[8] - J[2] * J[6]) * r, (J[2] * J[3] - J[0] * J[5]) * r,
                             c2 * r, (J[1] * J[6] - J[0] * J[7]) * r, (J[0] * J[4] - J[1] * J[3]) * r};
        memcpy(wb + q * PW, &det, sizeof det);
        for (int a = 0; a < 8; a++)
            for (int j = 0; j < 3; j++) {
                const pvec g = inv[3 * j] * dl[q][a][0] + inv[3 * j + 1] * dl[q][a][1] + inv[3 * j + 2] * dl[q][a][2];
                memcpy(G + ((q * 8 + a) * 3 + j) * PW, &g, sizeof g);
            }
    }
}

static void large_field(const fem_kernel *k, long b0, long b1, const double *u, double *fe)
{
    p3_data *d = k->data;
    double dl[NQ][8][3];
    natural_gradients(dl);
    for (long b = b0; b < b1; b++) {
        double ul[24][PW], fl[24][PW], G[NQ * 24 * PW], wb[NQ * PW];
        p3_block_gather(d, b, u, ul);
        pvec un[24], uc[24], X[24], x[24], du[24], deps[NQ][NC], spin[NQ][3], sig[NQ][NC], F[24];
        memcpy(un, ul, sizeof un);
        memcpy(uc, d->uc + (size_t)b * 24 * PW, sizeof uc);
        memcpy(X, d->X + (size_t)b * 24 * PW, sizeof X);
        for (int r = 0; r < 24; r++)
            du[r] = un[r] - uc[r], x[r] = X[r] + 0.5 * (un[r] + uc[r]);
        block_geometry((const double(*)[8][3])dl, x, G, wb);
        p3_block_strains(G, wb, du, d->bbar, deps, spin);
        p3_block_laws(d, b, (const pvec(*)[NC])deps, (const pvec(*)[3])spin, sig);
        for (int r = 0; r < 24; r++)
            x[r] = X[r] + un[r];
        block_geometry((const double(*)[8][3])dl, x, G, wb);
        p3_block_force(G, wb, (const pvec(*)[NC])sig, d->bbar, F);
        memcpy(fl, F, sizeof fl);
        p3_block_scatter(d, b, k->first, (const double(*)[PW])fl, fe);
        memcpy(d->ut + (size_t)b * 24 * PW, ul, sizeof ul);
        for (int l = 0; l < PW; l++) {
            const long le = d->lane[b * PW + l];
            for (int q = 0; q < NQ && le >= 0; q++)
                d->w_t[NQ * le + q] = wb[q * PW + l];
        }
    }
}

/* The trial geometry becomes the committed one, then the points' state. */
static void large_commit(fem_kernel *k)
{
    p3_data *d = k->data;
    memcpy(d->uc, d->ut, (size_t)d->nblk * 24 * PW * sizeof *d->uc);
    memcpy(d->w, d->w_t, (size_t)NQ * (size_t)k->count * sizeof *d->w);
    p3_accept(k);
}

static const fem_kernel_ops p3_large_ops = {"integration points (hexahedron, SIMD blocks, updated Lagrangian)",
                                            NULL, NULL, large_commit, p3_destroy, large_field, p3_report};

rf_status fem_kernel_points_hex_large(fem_kernel *k, const double *x, rf_error *err)
{
    if (!p3_is(k) || k->ops == &p3_large_ops)
        return rf_fail(err, RF_EINVAL, "fem3d: updated Lagrangian needs a small-strain hexahedron point kernel");
    p3_data *d = k->data;
    const size_t nd = (size_t)(d->nblk > 0 ? d->nblk : 1) * 24 * PW, np = (size_t)NQ * (size_t)k->count;
    d->X = malloc(nd * sizeof *d->X), d->uc = calloc(nd, sizeof *d->uc), d->ut = calloc(nd, sizeof *d->ut);
    d->w_t = malloc((np + 1) * sizeof *d->w_t);
    if (!d->X || !d->uc || !d->ut || !d->w_t)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", k->count);
    for (long b = 0; b < d->nblk; b++)
        p3_block_gather(d, b, x, (double(*)[PW])(d->X + (size_t)b * 24 * PW));
    memcpy(d->w_t, d->w, np * sizeof *d->w);
    k->ops = &p3_large_ops;
    return RF_OK;
}
