/* fem3d_mass.c - the rigid-body moments of the boulder's lumped masses.
 *
 * The faceted boulder mesh lies inside the spheroid, and its element-node
 * masses put the centre of mass and the moment of inertia a little off the
 * spheroid's: I_yy +1 % at a/h = 3 (docs/validation-mdr.md section 5), and the
 * centre of mass 1e-3 r down-slope at a/h = 3 (5.8e-4 r at 4, 2.6e-4 r at 6),
 * because the fine box is elongated down-slope and the mesh is therefore not
 * symmetric in x.  That offset e is not harmless: the frictional spin omega
 * moves the contact point along the normal at omega e relative to the centre
 * of mass, which lowered R_n of the 10 m/s, 45 degree, f = 0.6 impact by
 * about 2.1 e / r (docs/fem-speed.md section 5).
 *
 * The element-node masses m are weighted by
 *     1 + c1 + c2 (x - X0) + c3 (z - Z0) + c4 w,   w = (x - X0)^2 + (z - Z0)^2,
 * with (c1..c4) from the 4 x 4 Gram system, so that the mass, both in-plane
 * coordinates of the centre of mass (X0, Z0) and the moment of inertia about
 * the y axis through it (the axis of the in-plane rotation) are the
 * spheroid's.  y needs no correction: the mesh is symmetric about y = 0 (full
 * model) or cut by it (half model). */
#include "fem3d_internal.h"

#include <math.h>

/* Solve the n x n system A c = b in place (Gaussian elimination, partial pivoting); 0 if singular. */
static int solve_small(int n, double A[4][4], double b[4], double c[4])
{
    for (int k = 0; k < n; k++) {
        int p = k;
        for (int i = k + 1; i < n; i++)
            if (fabs(A[i][k]) > fabs(A[p][k]))
                p = i;
        if (!(fabs(A[p][k]) > 0))
            return 0;
        for (int j = 0; j < n; j++) {
            double t = A[k][j];
            A[k][j] = A[p][j], A[p][j] = t;
        }
        double t = b[k];
        b[k] = b[p], b[p] = t;
        for (int i = k + 1; i < n; i++) {
            double l = A[i][k] / A[k][k];
            for (int j = k; j < n; j++)
                A[i][j] -= l * A[k][j];
            b[i] -= l * b[k];
        }
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (int j = i + 1; j < n; j++)
            s -= A[i][j] * c[j];
        c[i] = s / A[i][i];
    }
    return 1;
}

static void basis(const double *x, double X0, double Z0, double psi[4])
{
    const double dx = x[0] - X0, dz = x[2] - Z0;
    psi[0] = 1, psi[1] = dx, psi[2] = dz, psi[3] = dx * dx + dz * dz;
}

int f3_boulder_mass_moments(const f3_mesh *mesh, double *elm, double M, double X0, double Z0, double Iyy)
{
    const long n8 = 8 * mesh->boulder_elems;
    double A[4][4] = {{0}}, b[4] = {0}, c[4] = {0};
    for (long k = 0; k < n8; k++) {
        double psi[4];
        basis(mesh->x + 3 * (long)mesh->conn[k], X0, Z0, psi);
        for (int i = 0; i < 4; i++) {
            b[i] -= elm[k] * psi[i];
            for (int j = 0; j < 4; j++)
                A[i][j] += elm[k] * psi[i] * psi[j];
        }
    }
    b[0] += M, b[3] += Iyy; /* targets less the present moments: M, 0, 0, I */
    if (!solve_small(4, A, b, c))
        return 0;
    for (long k = 0; k < n8; k++) {
        double psi[4];
        basis(mesh->x + 3 * (long)mesh->conn[k], X0, Z0, psi);
        const double wgt = 1 + c[0] + c[1] * psi[1] + c[2] * psi[2] + c[3] * psi[3];
        if (!(wgt > 0))
            return 0;
    }
    for (long k = 0; k < n8; k++) {
        double psi[4];
        basis(mesh->x + 3 * (long)mesh->conn[k], X0, Z0, psi);
        elm[k] *= 1 + c[0] + c[1] * psi[1] + c[2] * psi[2] + c[3] * psi[3];
    }
    return 1;
}
