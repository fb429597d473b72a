/* fem_points_block.c - the axisymmetric point kernel's kinematics on SIMD
 * blocks of AXB_W elements (fem_points_block.h).  GCC vector extensions, one
 * element per lane; the entry points are cloned for AVX2 and AVX-512 and
 * their helpers inlined into each clone.  The arithmetic is the scalar
 * code's, operation for operation (ISO C mode: no contraction into FMA), so
 * the lanes give the bits of the scalar kernel. */
#include "fem_points_block.h"

#include "fem_internal.h"

#include <math.h>
#include <string.h>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define AXB_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define AXB_CLONES
#endif
#define AXB_INLINE static inline __attribute__((always_inline))
/* The helpers pass vectors by value but are always inlined: no ABI between clones to warn about. */
#pragma GCC diagnostic ignored "-Wpsabi"

typedef double avec __attribute__((vector_size(AXB_W * sizeof(double))));

static const double XI[4] = {-1, 1, 1, -1}, ETA[4] = {-1, -1, 1, 1};

AXB_INLINE avec vld(const double *p)
{
    avec v;
    memcpy(&v, p, sizeof v);
    return v;
}

AXB_INLINE void vst(double *p, avec v)
{
    memcpy(p, &v, sizeof v);
}

/* The plain B of point q (rows rr zz tt rz, dofs r0 z0 ..), with zeros where
 * fem_element.c's bmatrix has them. */
AXB_INLINE void plain_rows(const double *G, int q, avec B[4][8])
{
    const avec zero = {0};
    for (int a = 0; a < 4; a++) {
        const avec dr = vld(G + ((q * 3 + 0) * 4 + a) * AXB_W), dz = vld(G + ((q * 3 + 1) * 4 + a) * AXB_W);
        const avec nr = vld(G + ((q * 3 + 2) * 4 + a) * AXB_W);
        B[0][2 * a] = dr, B[0][2 * a + 1] = zero;
        B[1][2 * a] = zero, B[1][2 * a + 1] = dz;
        B[2][2 * a] = nr, B[2][2 * a + 1] = zero;
        B[3][2 * a] = dz, B[3][2 * a + 1] = dr;
    }
}

/* B + C of point q: the B-bar rows of the scalar kernel's mean_dilatation. */
AXB_INLINE void bbar_rows(const double *G, const double *C, int q, avec B[4][8])
{
    plain_rows(G, q, B);
    for (int j = 0; j < 8; j++) {
        const avec c = vld(C + (q * 8 + j) * AXB_W);
        B[0][j] += c, B[1][j] += c, B[2][j] += c;
    }
}

/* fem_element.c's bmatrix at Gauss point q for every lane: G of q, returns w_q. */
AXB_INLINE avec point_geometry(const avec r[4], const avec z[4], int q, double *G)
{
    const double g = 1 / sqrt(3.0), xi = XI[q] * g, eta = ETA[q] * g;
    double N[4], dNx[4], dNe[4];
    for (int a = 0; a < 4; a++) {
        N[a] = 0.25 * (1 + XI[a] * xi) * (1 + ETA[a] * eta);
        dNx[a] = 0.25 * XI[a] * (1 + ETA[a] * eta);
        dNe[a] = 0.25 * ETA[a] * (1 + XI[a] * xi);
    }
    avec j11 = {0}, j12 = {0}, j21 = {0}, j22 = {0}, rr = {0};
    for (int a = 0; a < 4; a++) {
        j11 += dNx[a] * r[a], j12 += dNx[a] * z[a];
        j21 += dNe[a] * r[a], j22 += dNe[a] * z[a];
        rr += N[a] * r[a];
    }
    const avec det = j11 * j22 - j12 * j21;
    for (int a = 0; a < 4; a++) {
        vst(G + ((q * 3 + 0) * 4 + a) * AXB_W, (j22 * dNx[a] - j12 * dNe[a]) / det);
        vst(G + ((q * 3 + 1) * 4 + a) * AXB_W, (-j21 * dNx[a] + j11 * dNe[a]) / det);
        vst(G + ((q * 3 + 2) * 4 + a) * AXB_W, N[a] / rr);
    }
    return 2 * RF_PI * rr * det;
}

AXB_CLONES
void axb_geometry(const double *r, const double *z, int bbar, double *G, double *C, double *w)
{
    avec rv[4], zv[4], wq[4], bsum[8] = {{0}}, W = {0}, B[4][8];
    for (int a = 0; a < 4; a++)
        rv[a] = vld(r + a * AXB_W), zv[a] = vld(z + a * AXB_W);
    for (int q = 0; q < 4; q++)
        vst(w + q * AXB_W, wq[q] = point_geometry(rv, zv, q, G));
    memset(C, 0, AXB_C * sizeof *C);
    if (!bbar)
        return;
    for (int q = 0; q < 4; q++) {
        plain_rows(G, q, B);
        W += wq[q];
        for (int j = 0; j < 8; j++)
            bsum[j] += wq[q] * (B[0][j] + B[1][j] + B[2][j]);
    }
    for (int q = 0; q < 4; q++) {
        plain_rows(G, q, B);
        for (int j = 0; j < 8; j++)
            vst(C + (q * 8 + j) * AXB_W, (bsum[j] / W - (B[0][j] + B[1][j] + B[2][j])) / 3);
    }
}

AXB_CLONES
void axb_strains(const double *G, const double *C, const double *u, double *eps)
{
    avec uv[8], B[4][8];
    for (int j = 0; j < 8; j++)
        uv[j] = vld(u + j * AXB_W);
    for (int q = 0; q < 4; q++) {
        bbar_rows(G, C, q, B);
        for (int i = 0; i < 4; i++) {
            avec s = {0};
            for (int j = 0; j < 8; j++)
                s += B[i][j] * uv[j];
            vst(eps + (q * 4 + i) * AXB_W, s);
        }
    }
}

AXB_CLONES
void axb_spins(const double *G, const double *du, double *spin)
{
    avec B[4][8];
    for (int q = 0; q < 4; q++) {
        plain_rows(G, q, B);
        avec s = {0};
        for (int a = 0; a < 4; a++)
            s += B[0][2 * a] * vld(du + (2 * a + 1) * AXB_W) - B[1][2 * a + 1] * vld(du + 2 * a * AXB_W);
        vst(spin + q * AXB_W, 0.5 * s);
    }
}

AXB_CLONES
void axb_force(const double *G, const double *C, const double *w, const double *sig, double *F)
{
    avec y[8] = {{0}}, B[4][8];
    for (int q = 0; q < 4; q++) {
        bbar_rows(G, C, q, B);
        const avec wq = vld(w + q * AXB_W), s0 = vld(sig + (q * 4) * AXB_W), s1 = vld(sig + (q * 4 + 1) * AXB_W);
        const avec s2 = vld(sig + (q * 4 + 2) * AXB_W), s3 = vld(sig + (q * 4 + 3) * AXB_W);
        for (int j = 0; j < 8; j++)
            y[j] += wq * (B[0][j] * s0 + B[1][j] * s1 + B[2][j] * s2 + B[3][j] * s3);
    }
    for (int j = 0; j < 8; j++)
        vst(F + j * AXB_W, y[j]);
}

/* rf_material_rotate (material_rotation.c) for a spin (0, 0, s) about the
 * hoop axis and an axisymmetric stress (no yz, zx), operation for operation
 * with the terms that are exactly zero left out: the Cayley factor f, Q's
 * in-plane entries, Q sigma and (Q sigma) Q^T; tt is untouched (Q_tt = 1).
 * The same bits (but for the sign of a zero component); s = 0 leaves sigma. */
AXB_CLONES
void axb_rotate(const double *spin, double *sig)
{
    for (int q = 0; q < 4; q++) {
        const avec s = vld(spin + q * AXB_W), f = 2.0 / (1.0 + 0.25 * (s * s));
        const avec q00 = 1.0 + f * (0.25 * -(s * s)), q01 = f * (0.5 * -s), q10 = f * (0.5 * s), q11 = q00;
        double *p = sig + q * 4 * AXB_W;
        const avec a = vld(p), b = vld(p + AXB_W), d = vld(p + 3 * AXB_W);
        const avec s00 = q00 * a + q01 * d, s01 = q00 * d + q01 * b, s10 = q10 * a + q11 * d, s11 = q10 * d + q11 * b;
        vst(p, s00 * q00 + s01 * q01);
        vst(p + AXB_W, s10 * q10 + s11 * q11);
        vst(p + 3 * AXB_W, 0.5 * ((s00 * q10 + s01 * q11) + (s10 * q00 + s11 * q01)));
    }
}
