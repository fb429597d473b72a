/* fem3d_mass.c - the lumped masses: the rigid-body moments of the boulder's,
 * and the mass redistribution at the slope's contact face.
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
#include "fem_core.h"

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

/* Mass redistribution at the slope's contact face (Khenous, Laborde & Renard
 * 2008, Eur. J. Mech. A/Solids 27:918; Doyen, Ern & Piperno 2011, SIAM J.
 * Sci. Comput. 33:223).  The forward-increment contact captures a surface node
 * perfectly inelastically: it loses the relative kinetic energy of its mass,
 * an O(h) loss (docs/validation-plastic.md 9e).  The method takes the mass
 * off the contact nodes onto the interior ones, which makes the semi-discrete
 * contact energy-conserving and converges like the mesh (the mass moved is
 * that of a surface layer of one element, moved by one element).  An explicit
 * scheme cannot take all of it (a massless node has no stable step), so here
 * each contact-face element of the slope keeps the fraction alpha of its
 * surface nodes' masses and gives the rest to the node below each (its edge
 * neighbour off the face), with alpha = max(FEM_MASS_KEPT_MIN, lambda_e /
 * (kappa lambda_max)): its element eigenvalue then stays below lambda_e / alpha
 * <= kappa lambda_max (M' >= alpha M), so the step, set by lambda_max, is
 * unchanged, and kappa < 1 leaves the updated-Lagrangian step check room for
 * the element to be compressed.  Elements at or above kappa lambda_max (an
 * elastic granite face, whose elements set the step) are left alone.  The
 * solver calls it for soil only, and in 3D only on request
 * (rf_fem_options.surface_mass_3d: on meshes whose elements are about as deep
 * as the crater it misplaces the ploughed mass).  lam_upper: each element's
 * Gershgorin bound, raised to the redistributed element's bound.  face: per
 * node, 1 on the contact face. */
long f3_surface_mass_shift(const f3_mesh *mesh, const unsigned char *face, double *elm, double *lam_upper,
                           double lam_max, double kappa)
{
    static const int ed[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    long n = 0;
    for (long e = mesh->boulder_elems; e < mesh->n_elems; e++) {
        const int *cn = mesh->conn + 8 * e;
        int top[8], nt = 0, below[8];
        for (int a = 0; a < 8; a++)
            nt += top[a] = face[cn[a]] != 0;
        const double alpha = fem_mass_kept(lam_upper[e], kappa, lam_max);
        if (nt != 4 || !(alpha > 0) || alpha >= 1)
            continue;
        for (int a = 0; a < 8; a++)
            below[a] = -1;
        for (int k = 0; k < 12; k++) {
            const int p = ed[k][0], q = ed[k][1];
            if (top[p] != top[q])
                below[top[p] ? p : q] = top[p] ? q : p;
        }
        for (int a = 0; a < 8; a++)
            if (top[a]) {
                elm[8 * e + below[a]] += (1 - alpha) * elm[8 * e + a];
                elm[8 * e + a] *= alpha;
            }
        lam_upper[e] /= alpha;
        n++;
    }
    return n;
}
