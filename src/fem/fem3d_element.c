/* fem3d_element.c - the 8-node hexahedron: stiffness with full 2x2x2 Gauss
 * integration (isotropic linear elasticity, small strain), row-sum lumped
 * mass, and the element eigenvalue bound 2/sqrt(max lambda(M_e^-1 K_e)) that
 * sets the explicit time step (Householder tridiagonalisation + Sturm
 * bisection: exact up to round-off, unlike an edge-length estimate), and the
 * node order that gives a positive Jacobian. */
#include "fem3d_internal.h"

#include <math.h>
#include <string.h>

static const double XI[8] = {-1, 1, 1, -1, -1, 1, 1, -1};
static const double ETA[8] = {-1, -1, 1, 1, -1, -1, 1, 1};
static const double ZETA[8] = {-1, -1, -1, -1, 1, 1, 1, 1};

/* Shape functions and their x-derivatives at (xi, eta, zeta); returns det J. */
static double shape(const double x[24], double xi, double eta, double zeta, double N[8], double dN[8][3])
{
    double dl[8][3], J[3][3] = {{0}};
    for (int a = 0; a < 8; a++) {
        N[a] = 0.125 * (1 + XI[a] * xi) * (1 + ETA[a] * eta) * (1 + ZETA[a] * zeta);
        dl[a][0] = 0.125 * XI[a] * (1 + ETA[a] * eta) * (1 + ZETA[a] * zeta);
        dl[a][1] = 0.125 * ETA[a] * (1 + XI[a] * xi) * (1 + ZETA[a] * zeta);
        dl[a][2] = 0.125 * ZETA[a] * (1 + XI[a] * xi) * (1 + ETA[a] * eta);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                J[i][j] += dl[a][i] * x[3 * a + j]; /* J[i][j] = d x_j / d xi_i */
    }
    double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                 J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                 J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    double inv[3][3];
    inv[0][0] = (J[1][1] * J[2][2] - J[1][2] * J[2][1]) / det;
    inv[0][1] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) / det;
    inv[0][2] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) / det;
    inv[1][0] = (J[1][2] * J[2][0] - J[1][0] * J[2][2]) / det;
    inv[1][1] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) / det;
    inv[1][2] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) / det;
    inv[2][0] = (J[1][0] * J[2][1] - J[1][1] * J[2][0]) / det;
    inv[2][1] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) / det;
    inv[2][2] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / det;
    /* d N / d x_j = sum_i inv[j][i] dN/dxi_i  (inv = J^-1, x-derivatives) */
    for (int a = 0; a < 8; a++)
        for (int j = 0; j < 3; j++)
            dN[a][j] = inv[j][0] * dl[a][0] + inv[j][1] * dl[a][1] + inv[j][2] * dl[a][2];
    return det;
}

double f3_hex_center_jacobian(const double x[24])
{
    double N[8], dN[8][3];
    return shape(x, 0, 0, 0, N, dN);
}

/* Swaps the hexahedron's two faces when its centre Jacobian is negative. */
void f3_hex_orient(const double *x, int *c)
{
    double xe[24];
    for (int a = 0; a < 8; a++)
        for (int d = 0; d < 3; d++)
            xe[3 * a + d] = x[3 * c[a] + d];
    if (f3_hex_center_jacobian(xe) < 0)
        for (int a = 0; a < 4; a++) {
            int t = c[a];
            c[a] = c[a + 4], c[a + 4] = t;
        }
}

void f3_hex_gradients(const double x[24], double dN[8][8][3], double w[8])
{
    const double g = 1 / sqrt(3.0);
    for (int q = 0; q < 8; q++) {
        double N[8];
        w[q] = shape(x, XI[q] * g, ETA[q] * g, ZETA[q] * g, N, dN[q]);
    }
}

void f3_hex_matrices(const double x[24], const f3_material *mat, double K[576], double m[8], double *volume)
{
    const double lam = mat->E * mat->nu / ((1 + mat->nu) * (1 - 2 * mat->nu));
    const double mu = mat->E / (2 * (1 + mat->nu));
    const double g = 1 / sqrt(3.0);
    memset(K, 0, 576 * sizeof(double));
    double vol = 0;
    for (int a = 0; a < 8; a++)
        m[a] = 0;
    for (int q = 0; q < 8; q++) {
        double N[8], dN[8][3];
        double det = shape(x, XI[q] * g, ETA[q] * g, ZETA[q] * g, N, dN);
        vol += det;
        for (int a = 0; a < 8; a++) {
            m[a] += mat->rho * N[a] * det;
            for (int b = 0; b < 8; b++) {
                double dot = dN[a][0] * dN[b][0] + dN[a][1] * dN[b][1] + dN[a][2] * dN[b][2];
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++)
                        K[24 * (3 * a + i) + 3 * b + j] +=
                            det * (lam * dN[a][i] * dN[b][j] + mu * dN[a][j] * dN[b][i] + (i == j ? mu * dot : 0));
            }
        }
    }
    for (int r = 0; r < 24; r++) /* exact symmetry: the energy identity of the time loop needs it */
        for (int c = r + 1; c < 24; c++) {
            double s = 0.5 * (K[24 * r + c] + K[24 * c + r]);
            K[24 * r + c] = K[24 * c + r] = s;
        }
    *volume = vol;
}

/* Number of eigenvalues of the symmetric tridiagonal (d, e) below s (Sturm). */
static int sturm_below(const double *d, const double *e, int n, double s)
{
    int cnt = 0;
    double q = 1;
    for (int i = 0; i < n; i++) {
        double e2 = i > 0 ? e[i - 1] * e[i - 1] : 0;
        q = d[i] - s - (i > 0 ? e2 / q : 0);
        if (q == 0)
            q = -1e-300;
        if (q < 0)
            cnt++;
    }
    return cnt;
}

double f3_hex_lambda_max(const double K[576], const double m[8], const unsigned char free_dof[24])
{
    int idx[24], n = 0;
    for (int a = 0; a < 24; a++)
        if (free_dof[a])
            idx[n++] = a;
    if (n == 0)
        return 0;
    double A[576];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            A[i * n + j] = K[24 * idx[i] + idx[j]] / sqrt(m[idx[i] / 3] * m[idx[j] / 3]);
    /* Householder reduction to tridiagonal form */
    for (int k = 0; k + 2 < n; k++) {
        double v[24], p[24], q[24], nx = 0;
        for (int i = k + 1; i < n; i++)
            v[i] = A[i * n + k], nx += v[i] * v[i];
        nx = sqrt(nx);
        if (nx == 0)
            continue;
        double alpha = v[k + 1] > 0 ? -nx : nx;
        v[k + 1] -= alpha;
        double vv = 0;
        for (int i = k + 1; i < n; i++)
            vv += v[i] * v[i];
        if (vv == 0)
            continue;
        double w = 2 / vv, vp = 0;
        for (int i = k + 1; i < n; i++) {
            double s = 0;
            for (int j = k + 1; j < n; j++)
                s += A[i * n + j] * v[j];
            p[i] = w * s;
            vp += v[i] * p[i];
        }
        double kk = 0.5 * w * vp;
        for (int i = k + 1; i < n; i++)
            q[i] = p[i] - kk * v[i];
        for (int i = k + 1; i < n; i++)
            for (int j = k + 1; j < n; j++)
                A[i * n + j] -= v[i] * q[j] + q[i] * v[j];
        A[(k + 1) * n + k] = A[k * n + k + 1] = alpha;
        for (int i = k + 2; i < n; i++)
            A[i * n + k] = A[k * n + i] = 0;
    }
    double d[24], e[24];
    for (int i = 0; i < n; i++) {
        d[i] = A[i * n + i];
        e[i] = i + 1 < n ? A[(i + 1) * n + i] : 0;
    }
    double lo = 0, hi = 0;
    for (int i = 0; i < n; i++) {
        double r = fabs(i > 0 ? e[i - 1] : 0) + fabs(e[i]);
        if (d[i] + r > hi)
            hi = d[i] + r;
        if (d[i] - r < lo)
            lo = d[i] - r;
    }
    for (int it = 0; it < 200 && hi - lo > 1e-15 * fabs(hi); it++) {
        double mid = 0.5 * (lo + hi);
        if (sturm_below(d, e, n, mid) == n)
            hi = mid; /* all eigenvalues below mid */
        else
            lo = mid;
    }
    return hi;
}
