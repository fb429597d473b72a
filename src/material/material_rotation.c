/* material_rotation.c - objective stress update for large deformation: the
 * incremental rotation of Hughes & Winget (1980), "Finite rotation effects in
 * numerical integration of rate constitutive equations arising in
 * large-deformation analysis", IJNME 15:1862-1867.
 *
 * sig <- Q sig Q^T with Q = (I - W/2)^-1 (I + W/2), the Cayley transform of
 * the spin increment W = skew(w) (W v = w x v).  Q is exactly orthogonal for
 * any step, so the rotation never changes the invariants the yield functions
 * use; it turns by 2 atan(|w|/2), which is |w| to second order. */
#include "rockfuzz/material.h"

/* Voigt (xx, yy, zz, xy, yz, zx) <-> full symmetric 3x3. */
static void to_matrix(const double v[6], double a[3][3])
{
    a[0][0] = v[0], a[1][1] = v[1], a[2][2] = v[2];
    a[0][1] = a[1][0] = v[3];
    a[1][2] = a[2][1] = v[4];
    a[2][0] = a[0][2] = v[5];
}

/* Q = I + 2/(1 + |w|^2/4) (W/2 + W^2/4). */
static void cayley(const double w[3], double q[3][3])
{
    double W[3][3] = {{0, -w[2], w[1]}, {w[2], 0, -w[0]}, {-w[1], w[0], 0}};
    double f = 2.0 / (1.0 + 0.25 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double w2 = W[i][0] * W[0][j] + W[i][1] * W[1][j] + W[i][2] * W[2][j];
            q[i][j] = (i == j ? 1.0 : 0.0) + f * (0.5 * W[i][j] + 0.25 * w2);
        }
}

void rf_material_rotate(double sig[6], const double spin[3])
{
    if (spin[0] == 0.0 && spin[1] == 0.0 && spin[2] == 0.0)
        return;
    double q[3][3], s[3][3], qs[3][3], r[3][3];
    cayley(spin, q);
    to_matrix(sig, s);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            qs[i][j] = q[i][0] * s[0][j] + q[i][1] * s[1][j] + q[i][2] * s[2][j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[i][j] = qs[i][0] * q[j][0] + qs[i][1] * q[j][1] + qs[i][2] * q[j][2];
    sig[0] = r[0][0], sig[1] = r[1][1], sig[2] = r[2][2];
    sig[3] = 0.5 * (r[0][1] + r[1][0]);
    sig[4] = 0.5 * (r[1][2] + r[2][1]);
    sig[5] = 0.5 * (r[2][0] + r[0][2]);
}
