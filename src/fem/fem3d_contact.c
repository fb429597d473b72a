/* fem3d_contact.c - forward-increment Lagrange-multiplier contact with
 * Coulomb friction (Carpenter, Taylor & Katona 1991, IJNME 32:103; friction
 * as in impact_refs.md 5.4, Lagrange version).
 *
 * After the contact-free predictor u*, the multipliers lambda (normal
 * lambda_n >= 0, tangential lambda_t) act at step n so that
 *   gap(u_{n+1}) >= 0, lambda_n >= 0, lambda_n gap = 0, and
 *   either the relative tangential displacement of the step is zero (stick)
 *   or |lambda_t| = f lambda_n opposing it (slip),
 * with u_{n+1} = u* + dt^2 M^-1 G^T lambda.  The pairs couple only through
 * shared master nodes; the system is solved by projected Gauss-Seidel in
 * slave order: the normal update is a projection on lambda_n >= 0, the
 * tangential one computes the multiplier that stops the slip of the step and
 * caps it so that |F_t| <= f |F_n| (return map).  No penalty, no tangential
 * spring: the constraints hold to the solver tolerance (1e-9 h).
 * Rows: the normal n = (-S_x, -S_y, 1), the gap's gradient, and the face's
 * tangents t_x = (1, 0, S_x), t_y = (0, 1, S_y), orthogonal to n.  With
 * tangential rows along x and y (as before) friction pushed into a crater's
 * wall and the cap f lambda_n was not Coulomb's on a sloped face (effective f
 * f / (1 + S^2 -+ f S): 1.33 or 0.57 for f = 1, S = 0.5); the stick
 * kinematics is the same (n, t_x, t_y span space), the forces are not
 * (docs/validation-plastic.md 9f).
 * Pairing: the master material point currently under the slave (current
 * tangential positions of both surfaces, found by Newton on the C1 face below)
 * picks the 4 x 4 stencil of the slope's uniform fine-box face.  Unlike the axisymmetric solver the
 * pairing is not frozen at the reference configuration: the boulder slides
 * v_t t_c ~ 3 cm, a quarter of the contact radius, which a fixed pairing
 * would turn into a wrong gap (the master's indentation is measured at the
 * wrong place).
 * Master face: C1, the Catmull-Rom (cubic Hermite with central-difference
 * slopes) surface of the 4 x 4 grid nodes around the quad under the slave,
 * for the gap, the relative tangential displacement and the slope S alike;
 * S = dz/dx against the current tangential position (J^-T dz/dX), which is
 * what the gap's derivative carries where the soil's face is stretched
 * (docs/validation-plastic.md 9e).
 * With the bilinear quad (C0) S was the quad's secant slope, constant across
 * the quad in x: a slave at the fraction xi of the quad saw the slope of its
 * middle, off by (1/2 - xi) h u_z'', and the slaves of the near-matching
 * meshes share xi, so a sliding boulder met a coherent spurious tangential
 * force (frictionless 45 deg: R_t 1 +- 1.5e-3 and R_n +- 1.6e-3 at
 * a/h = 3-5; docs/fem-speed.md section 5).  The Catmull-Rom slope is
 * continuous and exact to O(h^2), and the normal row is still the gradient
 * of the gap that is constrained.
 * A rigid boulder (rigid_invm > 0, fem3d_rigid.c): its nodes have no inverse
 * mass; each multiplier's force and torque go to the rigid dofs (CM x, z and
 * the rotation about y), so every pair couples with every other through the
 * body.  Gauss-Seidel never factors the matrix: the dependent rows that made
 * the axisymmetric direct solve singular (validation-plastic.md 10c) only make
 * the multipliers non-unique, not the impulses.
 * Sphere mode (C->sphere, a rigid sphere with rf_fem_options.sphere_contact_3d):
 * the roles are turned round.  The slaves are the slope's fine-box face nodes
 * and the master is the boulder's exact sphere: gap |x - c| - r0, rows the
 * unit normal out of the sphere and two unit tangents (t1 in the x-z plane,
 * t2 = n x t1), each impulse on its node alone and back on the rigid body.
 * The faceted contact's Catmull-Rom stencil, whose negative weights pushed
 * the outer soil nodes of a pair into the boulder where the next slaves
 * captured them, is gone (docs/validation-plastic.md 9g). */
#include "fem3d_internal.h"

#include <math.h>
#include <string.h>

/* Catmull-Rom weights of the nodes -1, 0, 1, 2 at t in [0, 1] between nodes 0 and 1, and their
   derivatives d/dt. */
static void cr_w(double t, double w[4], double dw[4])
{
    w[0] = (-t * t * t + 2 * t * t - t) / 2, w[1] = (3 * t * t * t - 5 * t * t + 2) / 2;
    w[2] = (-3 * t * t * t + 4 * t * t + t) / 2, w[3] = (t * t * t - t * t) / 2;
    dw[0] = (-3 * t * t + 4 * t - 1) / 2, dw[1] = (9 * t * t - 10 * t) / 2;
    dw[2] = (-9 * t * t + 8 * t + 1) / 2, dw[3] = (3 * t * t - 2 * t) / 2;
}

/* The C1 master face at (xi, eta) in quad (i, j): nodes m and weights N of the 4 x 4 stencil
   (mirrored across the half model's symmetry plane y = 0, where the face is even in y; clamped
   at the grid's other edges, where a repeated node's weight is merged into its first copy),
   the slope S of the deformed face against the current tangential position (dz/dx =
   J^-T dz/dX, J = d(x, y)/d(X, Y): the face is stretched where the soil flows out of a crater),
   the tangential displacement ut there and J (row-major). */
static void catmull_rom(const f3_mesh *mesh, const double *u, int i, int j, double xi, double eta, int *m,
                        double *N, double S[2], double ut[2], double J[4])
{
    const int nx = mesh->nxt_s, ny = mesh->nyt_s, mirror = fabs(mesh->y0_s) <= 1e-9 * mesh->h_s;
    double wx[4], dwx[4], wy[4], dwy[4];
    cr_w(xi, wx, dwx), cr_w(eta, wy, dwy);
    double G[3][2] = {{1, 0}, {0, 1}, {0, 0}}; /* d(x, y, z) / d(X, Y) of the deformed face */
    ut[0] = ut[1] = 0;
    int q = 0;
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++, q++) {
            int ii = i - 1 + a, jj = j - 1 + b;
            if (jj < 0 && mirror) /* the half model's symmetry plane: the face is even in y */
                jj = -jj;
            ii = ii < 0 ? 0 : ii > nx - 1 ? nx - 1 : ii;
            jj = jj < 0 ? 0 : jj > ny - 1 ? ny - 1 : jj;
            m[q] = mesh->top_s[ii * ny + jj];
            N[q] = wx[a] * wy[b];
            const double dX = dwx[a] * wy[b] / mesh->h_s, dY = wx[a] * dwy[b] / mesh->h_s, *um = u + 3 * m[q];
            for (int d = 0; d < 3; d++)
                G[d][0] += dX * um[d], G[d][1] += dY * um[d];
            ut[0] += N[q] * um[0], ut[1] += N[q] * um[1];
        }
    const double det = G[0][0] * G[1][1] - G[0][1] * G[1][0];
    if (det > 0) {
        S[0] = (G[1][1] * G[2][0] - G[1][0] * G[2][1]) / det;
        S[1] = (-G[0][1] * G[2][0] + G[0][0] * G[2][1]) / det;
    } else { /* a folded face (no height field over x, y there): its material slope, finite */
        S[0] = G[2][0], S[1] = G[2][1];
    }
    J[0] = G[0][0], J[1] = G[0][1], J[2] = G[1][0], J[3] = G[1][1];
    for (int a = 0; a < F3_NM; a++)
        for (int b = a + 1; b < F3_NM; b++)
            if (N[b] != 0 && m[b] == m[a])
                N[a] += N[b], N[b] = 0;
}

/* The top grid's quad (i, j) and local (xi, eta) of the material point (Xm, Ym), clamped to the
   grid; returns 1 if it was outside (the symmetry plane's side y < 0 of a half model is not). */
static int grid_cell(const f3_mesh *mesh, double Xm, double Ym, int *i, int *j, double *xi, double *eta)
{
    const double fx = (Xm - mesh->x0_s) / mesh->h_s, fy = (Ym - mesh->y0_s) / mesh->h_s;
    const int nx = mesh->nxt_s, ny = mesh->nyt_s;
    int out = 0;
    *i = (int)floor(fx), *j = (int)floor(fy);
    if (*i < 0)
        *i = 0, out = 1;
    if (*i > nx - 2)
        *i = nx - 2, out = 1;
    if (*j < 0)
        *j = 0, out = fy < -1e-9;
    if (*j > ny - 2)
        *j = ny - 2, out = 1;
    *xi = fx - *i, *eta = fy - *j;
    *xi = *xi < 0 ? 0 : *xi > 1 ? 1 : *xi;
    *eta = *eta < 0 ? 0 : *eta > 1 ? 1 : *eta;
    return out;
}

/* The face's residual r = (X, Y) - X_m - u_t(X_m) at the material point P = X_m, with its
   stencil, weights, slope and J into m, N, S, J; returns 1 if P is outside the grid. */
static int face_residual(const f3_mesh *mesh, const double *u, double X, double Y, const double P[2], int *m,
                         double *N, double *S, double r[2], double J[4])
{
    int i, j;
    double xi, eta, ut[2];
    const int out = grid_cell(mesh, P[0], P[1], &i, &j, &xi, &eta);
    catmull_rom(mesh, u, i, j, xi, eta, m, N, S, ut, J);
    r[0] = X - P[0] - ut[0], r[1] = Y - P[1] - ut[1];
    return out;
}

/* The master material point currently under the slave at (X, Y): X_m + u_t(X_m) = (X, Y) on the
   C1 face, by Newton from P (the slave's previous master point, or its own position if that was off
   the grid; on return the new one), its stencil, weights and slope into m, N, S.  Where the soil is
   stretched unevenly along the face (a crater's wall: one quad 3.3 times its length between two
   compressed ones) x(X) is S-shaped, and plain Newton from the slave's own (X, Y) cycled between the
   quads and stopped 7 mm off (docs/validation-plastic.md 9e): each step is halved until |r| falls
   (backtracking; a step off the grid too), which converges wherever the face is a height field over
   (x, y).  Where it is folded (det J <= 0 on the way) the point is not unique: the previous one is
   kept, so that the gap stays continuous.  Returns 0; 1 if the point lies outside the grid; 2 if it
   was not found to 1e-9 h (the previous point kept). */
static int locate_master(const f3_mesh *mesh, const double *u, double X, double Y, double P[2], int *m, double *N,
                         double *S)
{
    const double tol = 1e-12 * mesh->h_s;
    double r[2], J[4];
    int out = face_residual(mesh, u, X, Y, P, m, N, S, r, J);
    if (out) /* the last point was off the grid: start again under the slave */
        P[0] = X, P[1] = Y, out = face_residual(mesh, u, X, Y, P, m, N, S, r, J);
    const double P0[2] = {P[0], P[1]};
    double rn = hypot(r[0], r[1]);
    int current = 1; /* m, N, S and J are those of P */
    for (int it = 0; it < 60 && !out && rn > tol; it++) {
        const double det = J[0] * J[3] - J[1] * J[2];
        if (!(det > 0))
            break;
        const double d[2] = {(J[3] * r[0] - J[1] * r[1]) / det, (-J[2] * r[0] + J[0] * r[1]) / det};
        int accepted = 0;
        for (double a = 1; a >= 0x1p-30 && !accepted; a *= 0.5) {
            const double T[2] = {P[0] + a * d[0], P[1] + a * d[1]};
            double rt[2];
            const int o = face_residual(mesh, u, X, Y, T, m, N, S, rt, J);
            const double rtn = hypot(rt[0], rt[1]);
            current = 0;
            if (rtn < (1 - 0.5 * a) * rn)
                P[0] = T[0], P[1] = T[1], r[0] = rt[0], r[1] = rt[1], rn = rtn, out = o, accepted = current = 1;
        }
        if (!accepted)
            break;
    }
    if (out) /* beyond the grid (the accepted point's clamped stencil) */
        return 1;
    const int found = rn <= 1e-9 * mesh->h_s;
    if (!found)
        P[0] = P0[0], P[1] = P0[1];
    if (!found || !current)
        face_residual(mesh, u, X, Y, P, m, N, S, r, J);
    return found ? 0 : 2;
}

void f3_contact_locate(f3_contact *C, const f3_mesh *mesh, const double *u, const double *v, int threads, int repair)
{
    (void)threads;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait /* orphaned: shared by the caller's parallel region, if any */
#endif
    for (long k = 0; k < C->nslave; k++) {
        int s = C->slave[k];
        if (C->sphere) { /* the slave's own u_n and v_{n-1/2}: the master is the rigid body */
            for (int d = 0; d < 3; d++)
                C->s0[3 * k + d] = u[3 * s + d], C->gvo[3 * k + d] = v[3 * s + d];
            continue;
        }
        int *m = C->mnode + F3_NM * k;
        double *N = C->N + F3_NM * k, *P = C->Xm + 2 * k;
        const double X = mesh->x[3 * s] + u[3 * s], Y = mesh->x[3 * s + 1] + u[3 * s + 1];
        if (repair)
            C->outside[k] = (unsigned char)locate_master(mesh, u, X, Y, P, m, N, C->S + 2 * k);
        f3_contact_rel(C, k, u, C->s0 + 3 * k);
        f3_contact_gv(C, k, v, C->gvo + 3 * k);
    }
}

/* Relative vector of pair k (slave minus the master point's interpolation) of the nodal field v. */
void f3_contact_rel(const f3_contact *C, long k, const double *v, double r[3])
{
    const int s = C->slave[k];
    const int *m = C->mnode + F3_NM * k;
    const double *N = C->N + F3_NM * k;
    for (int d = 0; d < 3; d++) {
        r[d] = v[3 * s + d];
        for (int a = 0; a < F3_NM; a++)
            r[d] -= N[a] * v[3 * m[a] + d];
    }
}

/* The rows of pair k: the face's normal n = (-S_x, -S_y, 1) (the gradient of the gap) and its
   tangents t_x = (1, 0, S_x), t_y = (0, 1, S_y), both orthogonal to n. */
static inline void row_w(const f3_contact *C, long k, int c, double w[3])
{
    if (C->sphere) {
        const double *W = C->wr + 9 * k + 3 * c;
        w[0] = W[0], w[1] = W[1], w[2] = W[2];
        return;
    }
    const double Sx = C->S[2 * k], Sy = C->S[2 * k + 1];
    if (c == 0)
        w[0] = -Sx, w[1] = -Sy, w[2] = 1;
    else if (c == 1)
        w[0] = 1, w[1] = 0, w[2] = Sx;
    else
        w[0] = 0, w[1] = 1, w[2] = Sy;
}

/* Row c of pair k applied to a relative vector r. */
static inline double row_dot(const f3_contact *C, long k, int c, const double r[3])
{
    double w[3];
    row_w(C, k, c, w);
    return w[0] * r[0] + w[1] * r[1] + w[2] * r[2];
}

/* Sphere mode: the rigid body's field d = (CM x, CM z, rotation about y) at pair k's arm. */
static inline void body_point(const f3_contact *C, long k, const double d[3], double b[3])
{
    const double rx = C->rr[2 * k], rz = C->rr[2 * k + 1];
    b[0] = d[0] + d[2] * rz, b[1] = 0, b[2] = d[1] - d[2] * rx;
}

/* Sphere mode: the slave's field a minus the body's field d at its arm, on the three rows. */
static inline void sphere_rows(const f3_contact *C, long k, const double a[3], const double d[3], double g[3])
{
    double b[3], r[3];
    body_point(C, k, d, b);
    for (int q = 0; q < 3; q++)
        r[q] = a[q] - b[q];
    for (int c = 0; c < 3; c++)
        g[c] = row_dot(C, k, c, r);
}

void f3_contact_gv(const f3_contact *C, long k, const double *v, double g[3])
{
    if (C->sphere) {
        sphere_rows(C, k, v + 3 * C->slave[k], C->body_v, g);
        return;
    }
    double r[3];
    f3_contact_rel(C, k, v, r);
    for (int c = 0; c < 3; c++)
        g[c] = row_dot(C, k, c, r);
}

void f3_contact_gvo(const f3_contact *C, long k, double g[3])
{
    if (C->sphere) {
        sphere_rows(C, k, C->gvo + 3 * k, C->body_vo, g);
        return;
    }
    for (int c = 0; c < 3; c++)
        g[c] = C->gvo[3 * k + c];
}

/* Sphere mode: slave node s's position x + u from the sphere's centre (rigid_c, on y = 0) into d;
   returns |d| - r0, its gap. */
static double sphere_offset(const f3_contact *C, const f3_mesh *mesh, const double *u, int s, double d[3])
{
    d[0] = mesh->x[3 * s] + u[3 * s] - C->rigid_c[0], d[1] = mesh->x[3 * s + 1] + u[3 * s + 1];
    d[2] = mesh->x[3 * s + 2] + u[3 * s + 2] - C->rigid_c[1];
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - C->radius;
}

double f3_contact_gap_now(const f3_contact *C, const f3_mesh *mesh, long k, const double *u)
{
    const int s = C->slave[k];
    if (C->sphere) {
        double d[3];
        return sphere_offset(C, mesh, u, s, d);
    }
    double g = mesh->x[3 * s + 2] + u[3 * s + 2];
    for (int a = 0; a < F3_NM; a++)
        g -= C->N[F3_NM * k + a] * u[3 * C->mnode[F3_NM * k + a] + 2];
    return g;
}

/* |n| of a face of slope S, and |l_x t_x + l_y t_y| of the tangential multipliers l on it. */
static inline double normal_norm(const double S[2])
{
    return sqrt(1 + S[0] * S[0] + S[1] * S[1]);
}

static inline double tangential_norm(const double S[2], double lx, double ly)
{
    return sqrt(lx * lx * (1 + S[0] * S[0]) + ly * ly * (1 + S[1] * S[1]) + 2 * lx * ly * S[0] * S[1]);
}

/* The same for pair k (sphere mode: orthonormal rows). */
static inline double pair_normal_norm(const f3_contact *C, long k)
{
    return C->sphere ? 1 : normal_norm(C->S + 2 * k);
}

static inline double pair_tangential_norm(const f3_contact *C, long k, double lx, double ly)
{
    return C->sphere ? hypot(lx, ly) : tangential_norm(C->S + 2 * k, lx, ly);
}

void f3_contact_forces(const f3_contact *C, long k, double *Fn, double *Ft)
{
    const double *lam = C->lam + 3 * k;
    *Fn = lam[0] * pair_normal_norm(C, k);
    *Ft = pair_tangential_norm(C, k, lam[1], lam[2]);
}

/* Sphere mode: unit normal n out of the sphere at the slave's direction d from the centre, and
   tangents t1 in the (x, z) plane (down the slope where n is the slope's normal), t2 = n x t1. */
static void sphere_basis(const double d[3], double w[9])
{
    const double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double *n = w, *t1 = w + 3, *t2 = w + 6;
    for (int q = 0; q < 3; q++)
        n[q] = r > 0 ? d[q] / r : q == 2 ? -1 : 0;
    double l = hypot(n[0], n[2]);
    if (l > 1e-6)
        t1[0] = -n[2] / l, t1[1] = 0, t1[2] = n[0] / l;
    else /* n along y: t1 = x */
        t1[0] = 1, t1[1] = 0, t1[2] = 0;
    t2[0] = n[1] * t1[2] - n[2] * t1[1], t2[1] = n[2] * t1[0] - n[0] * t1[2], t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

/* Sphere mode, pair k: gap, rows, arm, the slip of the predictor's step relative to the body's
   material point, and the diagonal of dt^2 G M^-1 G^T (the slave node and the rigid body). */
static void sphere_predict_pair(f3_contact *C, const f3_mesh *mesh, const double *u, const double *invm, double dt2,
                                long k)
{
    const int s = C->slave[k];
    double d[3];
    C->gap[k] = sphere_offset(C, mesh, u, s, d);
    if (C->gap[k] >= C->solve.band) /* not a candidate of this step's solve: nothing else is read */
        return;
    double *w = C->wr + 9 * k;
    sphere_basis(d, w);
    C->rr[2 * k] = d[0], C->rr[2 * k + 1] = d[2];
    double b[3];
    body_point(C, k, C->body_d, b);
    for (int q = 0; q < 3; q++)
        C->ds[3 * k + q] = u[3 * s + q] - C->s0[3 * k + q] - b[q];
    for (int c = 0; c < 3; c++) {
        const double *wc = w + 3 * c, tn = d[2] * wc[0] - d[0] * wc[2];
        double a = C->rigid_invm * (wc[0] * wc[0] + wc[2] * wc[2]) + C->rigid_invi * tn * tn;
        for (int q = 0; q < 3; q++)
            a += wc[q] * wc[q] * invm[3 * s + q];
        C->A[3 * k + c] = dt2 * a;
    }
}

void f3_contact_predict(f3_contact *C, const f3_mesh *mesh, const double *u, const double *invm, double dt,
                        int threads)
{
    (void)threads;
    const double dt2 = dt * dt;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads) if (C->nslave > 4096)
#endif
    for (long k = 0; k < C->nslave; k++) {
        if (C->sphere) {
            sphere_predict_pair(C, mesh, u, invm, dt2, k);
            continue;
        }
        int s = C->slave[k];
        const int *m = C->mnode + F3_NM * k;
        const double *N = C->N + F3_NM * k;
        double g = mesh->x[3 * s + 2] + u[3 * s + 2]; /* the master face is z = 0 in the reference */
        for (int a = 0; a < F3_NM; a++)
            g -= N[a] * (mesh->x[3 * m[a] + 2] + u[3 * m[a] + 2]);
        double r[3];
        f3_contact_rel(C, k, u, r);
        for (int d = 0; d < 3; d++)
            C->ds[3 * k + d] = r[d] - C->s0[3 * k + d];
        /* the master point moved with the slip of the step: first order in the face slope */
        C->gap[k] = g - C->S[2 * k] * C->ds[3 * k] - C->S[2 * k + 1] * C->ds[3 * k + 1];
        /* diagonal of dt^2 G M^-1 G^T: (normal, t_x, t_y) */
        double an = 0, ax = 0, ay = 0, wn[3], wx[3], wy[3];
        row_w(C, k, 0, wn), row_w(C, k, 1, wx), row_w(C, k, 2, wy);
        for (int q = -1; q < F3_NM; q++) {
            const double *im = invm + 3 * (q < 0 ? s : m[q]), n2 = q < 0 ? 1 : N[q] * N[q];
            for (int d = 0; d < 3; d++)
                an += n2 * wn[d] * wn[d] * im[d], ax += n2 * wx[d] * wx[d] * im[d], ay += n2 * wy[d] * wy[d] * im[d];
        }
        if (C->rigid_invm > 0) { /* the slave's response is the rigid body's: |w_xz|^2 / M + (r x w)_y^2 / I */
            const double rx = mesh->x[3 * s] + u[3 * s] - C->rigid_c[0], rz = mesh->x[3 * s + 2] + u[3 * s + 2] - C->rigid_c[1];
            C->rr[2 * k] = rx, C->rr[2 * k + 1] = rz;
            const double *w3[3] = {wn, wx, wy};
            double *a3[3] = {&an, &ax, &ay};
            for (int c = 0; c < 3; c++) {
                const double *w = w3[c], tn = rz * w[0] - rx * w[2];
                *a3[c] += C->rigid_invm * (w[0] * w[0] + w[2] * w[2]) + C->rigid_invi * tn * tn;
            }
        }
        C->A[3 * k] = dt2 * an, C->A[3 * k + 1] = dt2 * ax, C->A[3 * k + 2] = dt2 * ay;
    }
}

/* A rigid boulder's part of spread(): the force F of the multiplier increment on the rigid dofs. */
static inline void spread_rigid(f3_contact *C, long k, const double F[3], double dt2)
{
    const double rx = C->rr[2 * k], rz = C->rr[2 * k + 1];
    C->rigid_du[0] += dt2 * C->rigid_invm * F[0];
    C->rigid_du[1] += dt2 * C->rigid_invm * F[2];
    C->rigid_du[2] += dt2 * C->rigid_invi * (rz * F[0] - rx * F[2]);
}

/* Add dt^2 M^-1 G_c^T delta of pair k (component c: 0 normal, 1 x, 2 y) to du.  The normal row
   is the gradient of the gap including the slope S of the deformed master face, so that the
   normal multipliers do no work when the boulder slides over an indented face. */
static inline void spread(f3_contact *C, long k, int c, double delta, const double *invm, double dt2)
{
    const int s = C->slave[k];
    const int *m = C->mnode + F3_NM * k;
    const double *N = C->N + F3_NM * k;
    double w[3];
    row_w(C, k, c, w);
    if (C->sphere) { /* the slave is pushed along w, the body back */
        const double F[3] = {-w[0] * delta, -w[1] * delta, -w[2] * delta};
        spread_rigid(C, k, F, dt2);
        for (int d = 0; d < 3; d++)
            C->du[3 * s + d] += dt2 * invm[3 * s + d] * w[d] * delta;
        return;
    }
    if (C->rigid_invm > 0) {
        const double F[3] = {w[0] * delta, w[1] * delta, w[2] * delta};
        spread_rigid(C, k, F, dt2);
    }
    for (int d = 0; d < 3; d++) {
        if (w[d] == 0)
            continue;
        C->du[3 * s + d] += dt2 * invm[3 * s + d] * w[d] * delta;
        for (int a = 0; a < F3_NM; a++)
            C->du[3 * m[a] + d] -= dt2 * invm[3 * m[a] + d] * N[a] * w[d] * delta;
    }
}

static inline double gdu(const f3_contact *C, long k, int c)
{
    if (C->sphere) {
        double g[3];
        sphere_rows(C, k, C->du + 3 * C->slave[k], C->rigid_du, g);
        return g[c];
    }
    double r[3];
    f3_contact_rel(C, k, C->du, r);
    if (C->rigid_invm > 0) { /* the slave's displacement is the rigid body's */
        const double *d = C->rigid_du, rx = C->rr[2 * k], rz = C->rr[2 * k + 1];
        r[0] += d[0] + d[2] * rz, r[2] += d[1] - d[2] * rx;
    }
    return row_dot(C, k, c, r);
}

rf_status f3_contact_solve(f3_contact *C, const double *invm, double dt, double *u, double *v, rf_error *err)
{
    (void)err;
    const double dt2 = dt * dt, f = C->solve.friction;
    C->ncand = 0;
    for (long k = 0; k < C->nslave; k++) {
        if (C->gap[k] < C->solve.band) {
            C->cand[C->ncand++] = (int)k;
        } else {
            C->lam[3 * k] = C->lam[3 * k + 1] = C->lam[3 * k + 2] = 0;
        }
    }
    C->solve.sweeps = 0;
    C->solve.residual = 0;
    if (C->ncand == 0)
        return RF_OK;
    /* warm start from the previous step's multipliers */
    for (long q = 0; q < C->ncand; q++) {
        long k = C->cand[q];
        for (int c = 0; c < 3; c++)
            if (C->lam[3 * k + c] != 0)
                spread(C, k, c, C->lam[3 * k + c], invm, dt2);
    }
    double change = 0;
    int sweep;
    for (sweep = 0; sweep < C->solve.max_sweeps; sweep++) {
        change = 0;
        for (long q = 0; q < C->ncand; q++) {
            long k = C->cand[q];
            double *lam = C->lam + 3 * k;
            const double *A = C->A + 3 * k;
            /* normal: projection on lambda_n >= 0 */
            double g = C->gap[k] + gdu(C, k, 0);
            double ln = lam[0] - g / A[0];
            if (ln < 0)
                ln = 0;
            double dn = ln - lam[0];
            if (dn != 0) {
                spread(C, k, 0, dn, invm, dt2);
                lam[0] = ln;
                if (fabs(dn) * A[0] > change)
                    change = fabs(dn) * A[0];
            }
            /* tangential: stop the slip of the step, cap at f lambda_n */
            double lt[2];
            for (int c = 1; c < 3; c++) {
                if (A[c] > 0) {
                    double s = row_dot(C, k, c, C->ds + 3 * k) + gdu(C, k, c); /* slip of the step */
                    lt[c - 1] = lam[c] - s / A[c];
                } else
                    lt[c - 1] = 0;
            }
            /* Coulomb on the forces: |lt_x t_x + lt_y t_y| <= f ln |n| */
            const double cap = f * ln * pair_normal_norm(C, k), mag = pair_tangential_norm(C, k, lt[0], lt[1]);
            if (mag > cap) {
                double sc = mag > 0 ? cap / mag : 0;
                lt[0] *= sc, lt[1] *= sc;
            }
            for (int c = 1; c < 3; c++) {
                double dl = lt[c - 1] - lam[c];
                if (dl != 0) {
                    spread(C, k, c, dl, invm, dt2);
                    lam[c] = lt[c - 1];
                    if (fabs(dl) * A[c] > change)
                        change = fabs(dl) * A[c];
                }
            }
        }
        if (change <= C->solve.tol)
            break;
    }
    C->solve.sweeps = sweep + 1;
    C->solve.residual = change;
    /* apply the corrections, clear the scratch */
    for (long q = 0; q < C->ncand; q++) {
        long k = C->cand[q];
        int nodes[F3_NM + 1];
        const int nn = C->sphere ? 1 : F3_NM + 1;
        nodes[0] = C->slave[k];
        for (int a = 0; a + 1 < nn; a++)
            nodes[a + 1] = C->mnode[F3_NM * k + a];
        for (int a = 0; a < nn; a++)
            for (int d = 0; d < 3; d++) {
                double x = C->du[3 * nodes[a] + d];
                if (x != 0) {
                    u[3 * nodes[a] + d] += x;
                    v[3 * nodes[a] + d] += x / dt;
                    C->du[3 * nodes[a] + d] = 0;
                }
            }
    }
    return RF_OK;
}
