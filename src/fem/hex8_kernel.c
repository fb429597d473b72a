/* hex8_kernel.c - internal-force kernels for blocks of 8-node hexahedra
 * (hex8_kernel.h): one shared stiffness for congruent elements, and a
 * matrix-free kernel that forms strains and stresses at the 2x2x2 Gauss
 * points from stored J^-1 and det J.
 *
 * Why: today's loop streams a stored single-precision K_e, 2.3 KB per
 * element-step (docs/fem-speed.md).  A shared K_e is read from L1; the
 * matrix-free kernel reads 80 doubles per element and does about three
 * times the flops of K_e u_e, in lanes of HEX8_W elements that the compiler
 * vectorises, and it is the form a plastic material needs anyway (stress
 * at integration points).
 *
 * Both give, up to round-off, what f3_hex_matrices's K_e times u_e gives:
 * f_a = sum_q det J_q B_a(q)^T sig(q), sig = lam tr(eps) I + 2 mu eps. */
#include "hex8_kernel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Node a's reference coordinates (fem3d_element.c's numbering). */
static const double XI[8] = {-1, 1, 1, -1, -1, 1, 1, -1};
static const double ETA[8] = {-1, -1, 1, 1, -1, -1, 1, 1};
static const double ZETA[8] = {-1, -1, -1, -1, 1, 1, 1, 1};

/* As the solver's element_force: a wider-vector clone on x86-64, chosen once per process. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define HEX8_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define HEX8_CLONES
#endif

HEX8_CLONES
void hex8_shared_force(const double K[576], const int *conn, const int *elem, long n, const double *u, double *fe)
{
    for (long k = 0; k < n; k++) {
        const int *cn = conn + 8 * (long)elem[k];
        double acc[24] = {0};
        for (int a = 0; a < 8; a++)
            for (int c = 0; c < 3; c++) {
                const double *kj = K + 24 * (3 * a + c); /* row = column by symmetry: contiguous axpy */
                const double uj = u[3 * (long)cn[a] + c];
                for (int i = 0; i < 24; i++)
                    acc[i] += kj[i] * uj;
            }
        memcpy(fe + 24 * (long)elem[k], acc, sizeof acc);
    }
}

long hex8_find_congruent(const double *x, const int *conn, const int *cand, long ncand, const double xref[24],
                         double tol, int *out)
{
    long m = 0;
    for (long k = 0; k < ncand; k++) {
        const int *cn = conn + 8 * (long)cand[k];
        const double *x0 = x + 3 * (long)cn[0];
        int same = 1;
        for (int a = 1; a < 8 && same; a++)
            for (int d = 0; d < 3; d++)
                if (fabs((x[3 * (long)cn[a] + d] - x0[d]) - (xref[3 * a + d] - xref[d])) > tol)
                    same = 0;
        if (same)
            out[m++] = cand[k];
    }
    return m;
}

/* d N_a / d xi_i at Gauss point q, points ordered as the nodes (xi = XI[q] / sqrt 3 ...). */
static void gauss_derivatives(double dl[8][8][3])
{
    const double g = 1 / sqrt(3.0);
    for (int q = 0; q < 8; q++) {
        const double xi = XI[q] * g, eta = ETA[q] * g, zeta = ZETA[q] * g;
        for (int a = 0; a < 8; a++) {
            dl[q][a][0] = 0.125 * XI[a] * (1 + ETA[a] * eta) * (1 + ZETA[a] * zeta);
            dl[q][a][1] = 0.125 * ETA[a] * (1 + XI[a] * xi) * (1 + ZETA[a] * zeta);
            dl[q][a][2] = 0.125 * ZETA[a] * (1 + XI[a] * xi) * (1 + ETA[a] * eta);
        }
    }
}

/* J^-1 (inv[j][i] = d xi_i / d x_j) and det J at Gauss point q. */
static double jacobian_inverse(const double x[24], const double dl[8][3], double inv[9])
{
    double J[3][3] = {{0}}; /* J[i][j] = d x_j / d xi_i */
    for (int a = 0; a < 8; a++)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                J[i][j] += dl[a][i] * x[3 * a + j];
    const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                       J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                       J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    inv[0] = (J[1][1] * J[2][2] - J[1][2] * J[2][1]) / det;
    inv[1] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) / det;
    inv[2] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) / det;
    inv[3] = (J[1][2] * J[2][0] - J[1][0] * J[2][2]) / det;
    inv[4] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) / det;
    inv[5] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) / det;
    inv[6] = (J[1][0] * J[2][1] - J[1][1] * J[2][0]) / det;
    inv[7] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) / det;
    inv[8] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / det;
    return det;
}

void hex8_bmat_free(hex8_bmat *B)
{
    free(B->elem), free(B->conn), free(B->jinv), free(B->wdet), free(B->lam), free(B->mu);
    memset(B, 0, sizeof *B);
}

static rf_status bmat_alloc(hex8_bmat *B, long n, rf_error *err)
{
    memset(B, 0, sizeof *B);
    B->n = n;
    B->nblk = (n + HEX8_W - 1) / HEX8_W;
    const size_t lanes = (size_t)B->nblk * HEX8_W;
    B->elem = malloc(lanes * sizeof *B->elem);
    B->conn = malloc(lanes * 8 * sizeof *B->conn);
    B->jinv = malloc(lanes * 72 * sizeof *B->jinv);
    B->wdet = malloc(lanes * 8 * sizeof *B->wdet);
    B->lam = malloc(lanes * sizeof *B->lam);
    B->mu = malloc(lanes * sizeof *B->mu);
    if (n > 0 && (!B->elem || !B->conn || !B->jinv || !B->wdet || !B->lam || !B->mu)) {
        hex8_bmat_free(B);
        return rf_fail(err, RF_ENOMEM, "hex8 kernel: out of memory for %ld elements", n);
    }
    return RF_OK;
}

rf_status hex8_bmat_init(hex8_bmat *B, const double *x, const int *conn, const int *elem, long n, const double *lam,
                         const double *mu, rf_error *err)
{
    rf_status st = bmat_alloc(B, n, err);
    if (st != RF_OK)
        return st;
    double dl[8][8][3];
    gauss_derivatives(dl);
    for (long s = 0; s < B->nblk * HEX8_W; s++) {
        const long b = s / HEX8_W, l = s % HEX8_W, k = s < n ? s : 0; /* padding repeats element 0, weight 0 */
        const int *cn = conn + 8 * (long)elem[k];
        double xe[24];
        for (int a = 0; a < 8; a++) {
            B->conn[(b * 8 + a) * HEX8_W + l] = cn[a];
            for (int d = 0; d < 3; d++)
                xe[3 * a + d] = x[3 * (long)cn[a] + d];
        }
        B->elem[s] = s < n ? elem[s] : -1;
        B->lam[s] = lam[k], B->mu[s] = mu[k];
        for (int q = 0; q < 8; q++) {
            double inv[9];
            const double det = jacobian_inverse(xe, dl[q], inv);
            if (!(det > 0)) {
                hex8_bmat_free(B);
                return rf_fail(err, RF_EINVAL, "hex8 kernel: element %d has det J = %g at Gauss point %d",
                               elem[k], det, q);
            }
            B->wdet[(b * 8 + q) * HEX8_W + l] = s < n ? det : 0;
            for (int r = 0; r < 9; r++)
                B->jinv[((b * 8 + q) * 9 + r) * HEX8_W + l] = inv[r];
        }
    }
    return RF_OK;
}

typedef double lanes[HEX8_W];

/* H[3c + j] = d u_c / d x_j at point q of the block's lanes. */
static inline void point_gradient(const lanes ue[24], const double dl[8][3], const double *ji, lanes H[9])
{
    lanes G[9]; /* G[3c + i] = d u_c / d xi_i */
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < 3; i++) {
            for (int l = 0; l < HEX8_W; l++)
                G[3 * c + i][l] = 0;
            for (int a = 0; a < 8; a++)
                for (int l = 0; l < HEX8_W; l++)
                    G[3 * c + i][l] += dl[a][i] * ue[3 * a + c][l];
        }
    for (int c = 0; c < 3; c++)
        for (int j = 0; j < 3; j++)
            for (int l = 0; l < HEX8_W; l++)
                H[3 * c + j][l] = G[3 * c][l] * ji[(3 * j) * HEX8_W + l] + G[3 * c + 1][l] * ji[(3 * j + 1) * HEX8_W + l] +
                                  G[3 * c + 2][l] * ji[(3 * j + 2) * HEX8_W + l];
}

/* Symmetric stress sig[3c + j] of the gradient H: elastic in lanes, or the caller's routine per lane. */
static inline void point_stress(const hex8_bmat *B, long b, int q, const hex8_stress *st, lanes H[9], lanes S[9])
{
    const double *lam = B->lam + b * HEX8_W, *mu = B->mu + b * HEX8_W;
    if (!st || !st->fn) {
        for (int l = 0; l < HEX8_W; l++) {
            const double tr = lam[l] * (H[0][l] + H[4][l] + H[8][l]), m2 = 2 * mu[l];
            S[0][l] = tr + m2 * H[0][l], S[4][l] = tr + m2 * H[4][l], S[8][l] = tr + m2 * H[8][l];
            S[1][l] = S[3][l] = mu[l] * (H[1][l] + H[3][l]);
            S[2][l] = S[6][l] = mu[l] * (H[2][l] + H[6][l]);
            S[5][l] = S[7][l] = mu[l] * (H[5][l] + H[7][l]);
        }
        return;
    }
    for (int l = 0; l < HEX8_W; l++) {
        const long s = b * HEX8_W + l;
        if (B->elem[s] < 0) {
            for (int r = 0; r < 9; r++)
                S[r][l] = 0;
            continue;
        }
        const double eps[6] = {H[0][l], H[4][l], H[8][l], 0.5 * (H[5][l] + H[7][l]), 0.5 * (H[2][l] + H[6][l]),
                               0.5 * (H[1][l] + H[3][l])};
        double sig[6];
        st->fn(st->ctx, 8 * s + q, eps, sig);
        S[0][l] = sig[0], S[4][l] = sig[1], S[8][l] = sig[2];
        S[5][l] = S[7][l] = sig[3], S[2][l] = S[6][l] = sig[4], S[1][l] = S[3][l] = sig[5];
    }
}

/* fa[3a + c] += sum_i dl[a][i] det sum_j sig[c][j] (J^-1)[j][i]. */
static inline void point_force(const lanes S[9], const double dl[8][3], const double *ji, const double *wd,
                               lanes fa[24])
{
    lanes P[9];
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < 3; i++)
            for (int l = 0; l < HEX8_W; l++)
                P[3 * c + i][l] = wd[l] * (S[3 * c][l] * ji[i * HEX8_W + l] + S[3 * c + 1][l] * ji[(3 + i) * HEX8_W + l] +
                                           S[3 * c + 2][l] * ji[(6 + i) * HEX8_W + l]);
    for (int a = 0; a < 8; a++)
        for (int c = 0; c < 3; c++)
            for (int l = 0; l < HEX8_W; l++)
                fa[3 * a + c][l] += dl[a][0] * P[3 * c][l] + dl[a][1] * P[3 * c + 1][l] + dl[a][2] * P[3 * c + 2][l];
}

HEX8_CLONES
static void bmat_block(const hex8_bmat *B, long b, const double *u, const hex8_stress *st, const double dl[8][8][3],
                       double *fe)
{
    lanes ue[24], fa[24], H[9], S[9];
    const int *cn = B->conn + b * 8 * HEX8_W;
    for (int a = 0; a < 8; a++)
        for (int c = 0; c < 3; c++)
            for (int l = 0; l < HEX8_W; l++) {
                ue[3 * a + c][l] = u[3 * (long)cn[a * HEX8_W + l] + c];
                fa[3 * a + c][l] = 0;
            }
    for (int q = 0; q < 8; q++) {
        const double *ji = B->jinv + (b * 8 + q) * 9 * HEX8_W, *wd = B->wdet + (b * 8 + q) * HEX8_W;
        point_gradient(ue, dl[q], ji, H);
        point_stress(B, b, q, st, H, S);
        point_force(S, dl[q], ji, wd, fa);
    }
    for (int l = 0; l < HEX8_W; l++) {
        const int e = B->elem[b * HEX8_W + l];
        if (e >= 0)
            for (int r = 0; r < 24; r++)
                fe[24 * (long)e + r] = fa[r][l];
    }
}

void hex8_bmat_force(const hex8_bmat *B, long b0, long b1, const double *u, const hex8_stress *stress, double *fe)
{
    double dl[8][8][3];
    gauss_derivatives(dl);
    for (long b = b0; b < b1; b++)
        bmat_block(B, b, u, stress, dl, fe);
}
