/* fem_element.c - the 4-node axisymmetric quad: stiffness with full 2x2
 * Gauss integration (strains e_rr, e_zz, e_tt = u_r/r, g_rz; volume element
 * 2 pi r dA), area-weighted lumped mass, the element eigenvalue bound that
 * sets the explicit time step, and the centre stress for output. */
#include "fem_internal.h"

#include <math.h>
#include <string.h>

static const double XI[4] = {-1, 1, 1, -1}, ETA[4] = {-1, -1, 1, 1};

static void dmatrix(const fem_material *mat, double D[4][4])
{
    double lam = mat->E * mat->nu / ((1 + mat->nu) * (1 - 2 * mat->nu));
    double mu = mat->E / (2 * (1 + mat->nu));
    memset(D, 0, 16 * sizeof(double));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            D[i][j] = lam + (i == j ? 2 * mu : 0);
    D[3][3] = mu;
}

/* B (4 x 8) at (xi, eta); returns det J and r at the point. */
static double bmatrix(const double r[4], const double z[4], double xi, double eta, double B[4][8],
                      double N[4], double *rp)
{
    double dNx[4], dNe[4];
    for (int a = 0; a < 4; a++) {
        N[a] = 0.25 * (1 + XI[a] * xi) * (1 + ETA[a] * eta);
        dNx[a] = 0.25 * XI[a] * (1 + ETA[a] * eta);
        dNe[a] = 0.25 * ETA[a] * (1 + XI[a] * xi);
    }
    double j11 = 0, j12 = 0, j21 = 0, j22 = 0, rr = 0;
    for (int a = 0; a < 4; a++) {
        j11 += dNx[a] * r[a], j12 += dNx[a] * z[a];
        j21 += dNe[a] * r[a], j22 += dNe[a] * z[a];
        rr += N[a] * r[a];
    }
    double det = j11 * j22 - j12 * j21;
    memset(B, 0, 32 * sizeof(double));
    for (int a = 0; a < 4; a++) {
        double dr = (j22 * dNx[a] - j12 * dNe[a]) / det;
        double dz = (-j21 * dNx[a] + j11 * dNe[a]) / det;
        B[0][2 * a] = dr;
        B[1][2 * a + 1] = dz;
        B[2][2 * a] = N[a] / rr;
        B[3][2 * a] = dz;
        B[3][2 * a + 1] = dr;
    }
    *rp = rr;
    return det;
}

void fem_element_points(const double r[4], const double z[4], double B[4][32], double w[4])
{
    double g = 1 / sqrt(3.0), N[4];
    for (int q = 0; q < 4; q++) {
        double rp, det = bmatrix(r, z, XI[q] * g, ETA[q] * g, (double(*)[8])B[q], N, &rp);
        w[q] = 2 * RF_PI * rp * det;
    }
}

void fem_element_matrices(const double r[4], const double z[4], const fem_material *mat, double K[64],
                          double m[4], double *mass, double *area)
{
    double D[4][4], B[4][8], N[4], DB[4][8];
    dmatrix(mat, D);
    memset(K, 0, 64 * sizeof(double));
    double g = 1 / sqrt(3.0), M = 0, A = 0, an[4] = {0, 0, 0, 0};
    for (int q = 0; q < 4; q++) {
        double rp, det = bmatrix(r, z, XI[q] * g, ETA[q] * g, B, N, &rp);
        double wv = 2 * RF_PI * rp * det;
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 8; j++)
                DB[i][j] = D[i][0] * B[0][j] + D[i][1] * B[1][j] + D[i][2] * B[2][j] + D[i][3] * B[3][j];
        for (int a = 0; a < 8; a++)
            for (int b = 0; b < 8; b++)
                K[8 * a + b] += wv * (B[0][a] * DB[0][b] + B[1][a] * DB[1][b] + B[2][a] * DB[2][b] +
                                      B[3][a] * DB[3][b]);
        M += mat->rho * wv;
        A += det;
        for (int a = 0; a < 4; a++)
            an[a] += N[a] * det;
    }
    /* exact symmetry */
    for (int a = 0; a < 8; a++)
        for (int b = a + 1; b < 8; b++) {
            double s = 0.5 * (K[8 * a + b] + K[8 * b + a]);
            K[8 * a + b] = K[8 * b + a] = s;
        }
    for (int a = 0; a < 4; a++)
        m[a] = M * an[a] / A;
    *mass = M;
    *area = A;
}

/* Cyclic Jacobi on a symmetric n x n matrix (n <= 8); returns the largest eigenvalue. */
static double jacobi_max(double *A, int n)
{
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = 0, diag = 0;
        for (int i = 0; i < n; i++) {
            diag += A[i * n + i] * A[i * n + i];
            for (int j = i + 1; j < n; j++)
                off += A[i * n + j] * A[i * n + j];
        }
        if (off <= 1e-22 * diag)
            break;
        for (int p = 0; p < n; p++)
            for (int q = p + 1; q < n; q++) {
                double apq = A[p * n + q];
                if (fabs(apq) < 1e-300)
                    continue;
                double th = (A[q * n + q] - A[p * n + p]) / (2 * apq);
                double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < n; k++) {
                    double akp = A[k * n + p], akq = A[k * n + q];
                    A[k * n + p] = c * akp - s * akq;
                    A[k * n + q] = s * akp + c * akq;
                }
                for (int k = 0; k < n; k++) {
                    double apk = A[p * n + k], aqk = A[q * n + k];
                    A[p * n + k] = c * apk - s * aqk;
                    A[q * n + k] = s * apk + c * aqk;
                }
            }
    }
    double mx = 0;
    for (int i = 0; i < n; i++)
        if (A[i * n + i] > mx)
            mx = A[i * n + i];
    return mx;
}

double fem_element_lambda_max(const double K[64], const double m[4], const int free_dof[8])
{
    int idx[8], n = 0;
    for (int a = 0; a < 8; a++)
        if (free_dof[a])
            idx[n++] = a;
    if (n == 0)
        return 0;
    double A[64];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            A[i * n + j] = K[8 * idx[i] + idx[j]] / sqrt(m[idx[i] / 2] * m[idx[j] / 2]);
    return jacobi_max(A, n);
}

void fem_element_stress(const double r[4], const double z[4], const fem_material *mat, const double u[8],
                        double s[4])
{
    double D[4][4], B[4][8], N[4], rp, eps[4] = {0, 0, 0, 0};
    dmatrix(mat, D);
    bmatrix(r, z, 0, 0, B, N, &rp);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 8; j++)
            eps[i] += B[i][j] * u[j];
    for (int i = 0; i < 4; i++)
        s[i] = D[i][0] * eps[0] + D[i][1] * eps[1] + D[i][2] * eps[2] + D[i][3] * eps[3];
}
