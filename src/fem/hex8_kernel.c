/* hex8_kernel.c - internal-force kernels for blocks of 8-node hexahedra
 * (hex8_kernel.h): one shared stiffness for congruent elements, and a
 * matrix-free kernel that forms strains and stresses at the 2x2x2 Gauss
 * points from J^-1 and det J, stored or recomputed from the coordinates.
 *
 * Why: today's loop streams a stored single-precision K_e, 2.7 KB per
 * element-step with its other arrays, and runs at the machine's bandwidth
 * floor (docs/fem-speed.md).  The matrix-free kernel moves 1.1 KB (J
 * stored) or 0.5 KB (J recomputed) for 2-3 times the instructions, and it
 * is the form a plastic material needs anyway (stress at the points).
 *
 * How: HEX8_W elements per block, one per vector lane (GCC/clang vector
 * extension, target clones up to AVX-512); the displacement goes to its 8
 * trilinear modes once per element, so a point's gradient costs 27
 * multiply-adds, and the force is gathered in the same modes (sum
 * factorisation).  Vectors cross function calls by pointer only: a vector
 * passed by value from a clone to a plain function changes the ABI.
 *
 * Both kernels give, up to round-off, f3_hex_matrices's K_e times u_e:
 * f_a = sum_q det J_q B_a(q)^T sig(q), sig = lam tr(eps) I + 2 mu eps. */
#include "hex8_kernel.h"

/* -std=c17 turns off the fusing of a * b + c into one FMA instruction; these loops are mostly
   multiply-adds, so fuse them here (the result changes by round-off only, the same in every
   thread). */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=fast")
#elif defined(__clang__)
#pragma clang fp contract(fast)
#endif

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

static rf_status bmat_alloc(hex8_bmat *B, long n, int store, rf_error *err)
{
    memset(B, 0, sizeof *B);
    B->n = n;
    B->nblk = (n + HEX8_W - 1) / HEX8_W;
    const size_t lanes = (size_t)B->nblk * HEX8_W;
    B->elem = malloc(lanes * sizeof *B->elem);
    B->conn = malloc(lanes * 8 * sizeof *B->conn);
    if (store) {
        B->jinv = malloc(lanes * 72 * sizeof *B->jinv);
        B->wdet = malloc(lanes * 8 * sizeof *B->wdet);
    }
    B->lam = malloc(lanes * sizeof *B->lam);
    B->mu = malloc(lanes * sizeof *B->mu);
    if (n > 0 && (!B->elem || !B->conn || (store && (!B->jinv || !B->wdet)) || !B->lam || !B->mu)) {
        hex8_bmat_free(B);
        return rf_fail(err, RF_ENOMEM, "hex8 kernel: out of memory for %ld elements", n);
    }
    return RF_OK;
}

rf_status hex8_bmat_init(hex8_bmat *B, const double *x, const int *conn, const int *elem, long n, const double *lam,
                         const double *mu, int store_jacobians, rf_error *err)
{
    rf_status st = bmat_alloc(B, n, store_jacobians, err);
    if (st != RF_OK)
        return st;
    B->x = store_jacobians ? NULL : x;
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
            if (!store_jacobians)
                continue;
            B->wdet[(b * 8 + q) * HEX8_W + l] = s < n ? det : 0;
            for (int r = 0; r < 9; r++)
                B->jinv[((b * 8 + q) * 9 + r) * HEX8_W + l] = inv[r];
        }
    }
    return RF_OK;
}

/* One vector of HEX8_W doubles, one lane per element of a block (GCC/clang vector extension:
   lowered to one AVX-512, two AVX2 or four SSE2 registers by the clone that runs). */
#if defined(__GNUC__) || defined(__clang__)
typedef double hvec __attribute__((vector_size(HEX8_W * sizeof(double))));
#else
#error "hex8_kernel.c needs the GCC/clang vector extension"
#endif

static inline void vget(hvec *v, const double *p)
{
    memcpy(v, p, sizeof *v);
}

/* Sum factorisation of the trilinear field: u = sum_k m_k s_k(xi, eta, zeta) with the monomials
   s = 1, xi, eta, zeta, xi eta, eta zeta, xi zeta, xi eta zeta and m_k = 1/8 sum_a s_k(node a) u_a.
   Its derivatives at a point need 27 multiply-adds instead of 72, and the force (the transpose)
   is gathered in the same 8 modes and expanded to the nodes once per element.  Node order as
   XI/ETA/ZETA: 0 (-,-,-) 1 (+,-,-) 2 (+,+,-) 3 (-,+,-), 4-7 the same at zeta = +1. */

/* m[3k + c] = 1/8 sum_a s_k(a) ue[3a + c], k = 1..7 (the constant mode carries no strain): three
   butterfly stages (xi, eta, zeta pairs of nodes), 23 additions instead of 56 multiply-adds. */
static inline void to_modes(const hvec ue[24], hvec m[24])
{
    for (int c = 0; c < 3; c++) {
        const hvec *u0 = &ue[c];
#define U(a) u0[3 * (a)]
        const hvec s01 = U(1) + U(0), d01 = U(1) - U(0), s32 = U(2) + U(3), d32 = U(2) - U(3);
        const hvec s45 = U(5) + U(4), d45 = U(5) - U(4), s76 = U(6) + U(7), d76 = U(6) - U(7);
#undef U
        const hvec ssb = s32 + s01, sdb = s32 - s01, sst = s76 + s45, sdt = s76 - s45;
        const hvec dsb = d32 + d01, ddb = d32 - d01, dst = d76 + d45, ddt = d76 - d45;
        m[3 + c] = 0.125 * (dst + dsb), m[6 + c] = 0.125 * (sdt + sdb), m[9 + c] = 0.125 * (sst - ssb);
        m[12 + c] = 0.125 * (ddt + ddb), m[15 + c] = 0.125 * (sdt - sdb), m[18 + c] = 0.125 * (dst - dsb);
        m[21 + c] = 0.125 * (ddt - ddb);
    }
}

/* fe[3a + c] = 1/8 sum_k s_k(a) F[3k + c]: the transposed butterflies (F_0 = 0). */
static inline void from_modes(const hvec F[24], hvec fa[24])
{
    for (int c = 0; c < 3; c++) {
        const hvec F1 = F[3 + c], F2 = F[6 + c], F3 = F[9 + c], F4 = F[12 + c], F5 = F[15 + c], F6 = F[18 + c],
                   F7 = F[21 + c];
        const hvec sst = F3, ssb = -F3, sdt = F2 + F5, sdb = F2 - F5;
        const hvec dst = F1 + F6, dsb = F1 - F6, ddt = F4 + F7, ddb = F4 - F7;
        const hvec s32 = ssb + sdb, s01 = ssb - sdb, s76 = sst + sdt, s45 = sst - sdt;
        const hvec d32 = dsb + ddb, d01 = dsb - ddb, d76 = dst + ddt, d45 = dst - ddt;
        fa[3 + c] = 0.125 * (s01 + d01), fa[c] = 0.125 * (s01 - d01);
        fa[6 + c] = 0.125 * (s32 + d32), fa[9 + c] = 0.125 * (s32 - d32);
        fa[15 + c] = 0.125 * (s45 + d45), fa[12 + c] = 0.125 * (s45 - d45);
        fa[18 + c] = 0.125 * (s76 + d76), fa[21 + c] = 0.125 * (s76 - d76);
    }
}

/* H[3c + j] = d u_c / d x_j at reference point p = (xi, eta, zeta), (J^-1)[j][i] = ji[3j + i]. */
static inline void point_gradient(const hvec m[24], const double p[3], const hvec ji[9], hvec H[9])
{
    const double x = p[0], y = p[1], z = p[2];
    for (int c = 0; c < 3; c++) {
        const hvec G0 = m[3 + c] + y * m[12 + c] + z * m[18 + c] + (y * z) * m[21 + c];
        const hvec G1 = m[6 + c] + x * m[12 + c] + z * m[15 + c] + (x * z) * m[21 + c];
        const hvec G2 = m[9 + c] + y * m[15 + c] + x * m[18 + c] + (x * y) * m[21 + c];
        for (int j = 0; j < 3; j++)
            H[3 * c + j] = G0 * ji[3 * j] + G1 * ji[3 * j + 1] + G2 * ji[3 * j + 2];
    }
}

/* J^-1 (ji[3j + i] = d xi_i / d x_j) and det J at p from the modes mx of the node coordinates:
   J[i][j] = d x_j / d xi_i is point_gradient's G with x in place of u. */
static inline void point_jacobian(const hvec mx[24], const double p[3], hvec ji[9], hvec *det)
{
    const double x = p[0], y = p[1], z = p[2];
    hvec J[9];
    for (int j = 0; j < 3; j++) {
        J[j] = mx[3 + j] + y * mx[12 + j] + z * mx[18 + j] + (y * z) * mx[21 + j];
        J[3 + j] = mx[6 + j] + x * mx[12 + j] + z * mx[15 + j] + (x * z) * mx[21 + j];
        J[6 + j] = mx[9 + j] + y * mx[15 + j] + x * mx[18 + j] + (x * y) * mx[21 + j];
    }
    const hvec c0 = J[4] * J[8] - J[5] * J[7], c1 = J[5] * J[6] - J[3] * J[8], c2 = J[3] * J[7] - J[4] * J[6];
    *det = J[0] * c0 + J[1] * c1 + J[2] * c2;
    const hvec r = 1 / *det;
    ji[0] = c0 * r, ji[1] = (J[2] * J[7] - J[1] * J[8]) * r, ji[2] = (J[1] * J[5] - J[2] * J[4]) * r;
    ji[3] = c1 * r, ji[4] = (J[0] * J[8] - J[2] * J[6]) * r, ji[5] = (J[2] * J[3] - J[0] * J[5]) * r;
    ji[6] = c2 * r, ji[7] = (J[1] * J[6] - J[0] * J[7]) * r, ji[8] = (J[0] * J[4] - J[1] * J[3]) * r;
}

/* det J times isotropic linear elastic stress: S = wd (lam tr(eps) I + 2 mu eps), eps = sym(H). */
static inline void point_elastic(const hvec H[9], const hvec *wl, const hvec *wm, hvec S[9])
{
    const hvec wlam = *wl, wmu = *wm, tr = wlam * (H[0] + H[4] + H[8]), m2 = 2 * wmu;
    S[0] = tr + m2 * H[0], S[4] = tr + m2 * H[4], S[8] = tr + m2 * H[8];
    S[1] = S[3] = wmu * (H[1] + H[3]);
    S[2] = S[6] = wmu * (H[2] + H[6]);
    S[5] = S[7] = wmu * (H[5] + H[7]);
}

/* The caller's routine, lane by lane (it may branch, e.g. a return map), times det J; padding
   lanes get 0. */
static void point_callback(const hex8_bmat *B, long b, int q, const hex8_stress *st, const hvec H[9],
                           const hvec *wd, hvec S[9])
{
    double h[9][HEX8_W], s[9][HEX8_W], w[HEX8_W];
    memcpy(h, H, sizeof h);
    memcpy(w, wd, sizeof w);
    for (int l = 0; l < HEX8_W; l++) {
        const long k = b * HEX8_W + l;
        double sig[6] = {0};
        if (B->elem[k] >= 0) {
            const double eps[6] = {h[0][l], h[4][l], h[8][l], 0.5 * (h[5][l] + h[7][l]), 0.5 * (h[2][l] + h[6][l]),
                                   0.5 * (h[1][l] + h[3][l])};
            st->fn(st->ctx, 8 * k + q, eps, sig);
        }
        for (int r = 0; r < 6; r++)
            sig[r] *= w[l];
        s[0][l] = sig[0], s[4][l] = sig[1], s[8][l] = sig[2];
        s[5][l] = s[7][l] = sig[3], s[2][l] = s[6][l] = sig[4], s[1][l] = s[3][l] = sig[5];
    }
    memcpy(S, s, sizeof s);
}

/* F (modes) += the point's contribution: P[c][i] = sum_j S[c][j] (J^-1)[j][i] is d(energy)/d(G[c][i]). */
static inline void point_force(const hvec S[9], const double p[3], const hvec ji[9], hvec F[24])
{
    const double x = p[0], y = p[1], z = p[2];
    for (int c = 0; c < 3; c++) {
        const hvec P0 = S[3 * c] * ji[0] + S[3 * c + 1] * ji[3] + S[3 * c + 2] * ji[6];
        const hvec P1 = S[3 * c] * ji[1] + S[3 * c + 1] * ji[4] + S[3 * c + 2] * ji[7];
        const hvec P2 = S[3 * c] * ji[2] + S[3 * c + 1] * ji[5] + S[3 * c + 2] * ji[8];
        F[3 + c] += P0, F[6 + c] += P1, F[9 + c] += P2;
        F[12 + c] += y * P0 + x * P1;
        F[15 + c] += z * P1 + y * P2;
        F[18 + c] += z * P0 + x * P2;
        F[21 + c] += (y * z) * P0 + (x * z) * P1 + (x * y) * P2;
    }
}

static void gather_block(const hex8_bmat *B, long b, const double *u, hvec ue[24])
{
    double ul[24][HEX8_W];
    const int *cn = B->conn + b * 8 * HEX8_W;
    for (int a = 0; a < 8; a++)
        for (int l = 0; l < HEX8_W; l++) {
            const double *un = u + 3 * (long)cn[a * HEX8_W + l];
            ul[3 * a][l] = un[0], ul[3 * a + 1][l] = un[1], ul[3 * a + 2][l] = un[2];
        }
    memcpy(ue, ul, sizeof ul);
}

static void scatter_block(const hex8_bmat *B, long b, const hvec fa[24], double *fe)
{
    double fl[24][HEX8_W];
    memcpy(fl, fa, sizeof fl);
    for (int l = 0; l < HEX8_W; l++) {
        const int e = B->elem[b * HEX8_W + l];
        if (e >= 0)
            for (int r = 0; r < 24; r++)
                fe[24 * (long)e + r] = fl[r][l];
    }
}

HEX8_CLONES
static void bmat_block(const hex8_bmat *B, long b, const double *u, const hex8_stress *st, const double pts[8][3],
                       double *fe)
{
    hvec ue[24], m[24], mx[24], F[24] = {0}, fa[24], lam, mu;
    gather_block(B, b, u, ue);
    to_modes(ue, m);
    if (!B->jinv) {
        gather_block(B, b, B->x, ue);
        to_modes(ue, mx);
    }
    vget(&lam, B->lam + b * HEX8_W), vget(&mu, B->mu + b * HEX8_W);
    for (int q = 0; q < 8; q++) {
        hvec ji[9], H[9], S[9], wd;
        if (B->jinv) {
            for (int r = 0; r < 9; r++)
                vget(&ji[r], B->jinv + ((b * 8 + q) * 9 + r) * HEX8_W);
            vget(&wd, B->wdet + (b * 8 + q) * HEX8_W);
        } else
            point_jacobian(mx, pts[q], ji, &wd);
        point_gradient(m, pts[q], ji, H);
        const hvec wlam = wd * lam, wmu = wd * mu;
        if (!st || !st->fn)
            point_elastic(H, &wlam, &wmu, S);
        else
            point_callback(B, b, q, st, H, &wd, S);
        point_force(S, pts[q], ji, F);
    }
    from_modes(F, fa);
    scatter_block(B, b, fa, fe);
}

void hex8_bmat_force(const hex8_bmat *B, long b0, long b1, const double *u, const hex8_stress *stress, double *fe)
{
    const double g = 1 / sqrt(3.0);
    double pts[8][3];
    for (int q = 0; q < 8; q++)
        pts[q][0] = g * XI[q], pts[q][1] = g * ETA[q], pts[q][2] = g * ZETA[q];
    for (long b = b0; b < b1; b++)
        bmat_block(B, b, u, stress, (const double(*)[3])pts, fe);
}
