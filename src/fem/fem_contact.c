/* fem_contact.c - contact of the axisymmetric solver: node-to-segment pairs
 * (boulder surface nodes on slope surface segments; small strain: small
 * sliding, vertical gaps in the reference configuration; large deformation:
 * each slave's closest point found again on the current surface at every
 * step, the gap along its normal, the surface the slope's surface polygon
 * with its corners rounded, C1: fem_contact_surface.c), forward-increment Lagrange multipliers
 * (Carpenter, Taylor & Katona 1991, IJNME 32:103): the multipliers lambda_n
 * >= 0 are the forces at step n that make the predicted gaps at n+1 exactly
 * non-negative, a small linear complementarity problem over the pairs near
 * contact solved by an active set with dense Cholesky.  They add no
 * compliance and do not restrict dt.  Coulomb friction, when asked, in
 * fem_contact_friction.c. */
#include "fem_contact_surface.h"
#include "fem_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Dense Cholesky solve of A x = b (n x n, A overwritten).  Returns 0 on
 * success, -1 when a pivot falls to round-off (below 1e-12 of its diagonal
 * entry): a row dependent on the ones before it. */
static int cholesky_solve(double *A, double *b, int n)
{
    for (int j = 0; j < n; j++) {
        double d = A[j * n + j];
        const double djj = d;
        for (int k = 0; k < j; k++)
            d -= A[j * n + k] * A[j * n + k];
        if (!(d > 1e-12 * djj))
            return -1;
        d = sqrt(d);
        A[j * n + j] = d;
        for (int i = j + 1; i < n; i++) {
            double s = A[i * n + j];
            for (int k = 0; k < j; k++)
                s -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = s / d;
        }
    }
    for (int i = 0; i < n; i++) {
        double s = b[i];
        for (int k = 0; k < i; k++)
            s -= A[i * n + k] * b[k];
        b[i] = s / A[i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (int k = i + 1; k < n; k++)
            s -= A[k * n + i] * b[k];
        b[i] = s / A[i * n + i];
    }
    return 0;
}

/* (G M^-1 G^T)_ab; with a rigid boulder every two slaves are coupled
 * through its mass (slave dofs are the boulder's, masters the slope's). */
static double pair_aij(const contact_pair *a, const contact_pair *b, const double *invm, double rigid_invm, int nq)
{
    double s = rigid_invm > 0 ? a->c[0] * b->c[0] * rigid_invm : 0;
    for (int p = rigid_invm > 0; p < nq; p++)
        for (int q = rigid_invm > 0; q < nq; q++)
            if (a->dof[p] == b->dof[q])
                s += a->c[p] * b->c[q] * invm[a->dof[p]];
    return s;
}

/* The linear gap g0 + c . u of a pair. */
static double pair_gap(const contact_pair *p, const double *u, int nq)
{
    double g = p->g0;
    for (int q = 0; q < nq; q++)
        g += p->c[q] * u[p->dof[q]];
    return g;
}

/* The active pairs' matrix dt^2 G M^-1 G^T + shift I and right-hand side -g_pred. */
static void active_matrix(fem_contact *C, const double *invm, double dt2, int na, double shift)
{
    for (int a = 0; a < na; a++) {
        const contact_pair *pa = C->pair + C->active[a];
        for (int b = 0; b <= a; b++) {
            double v = dt2 * pair_aij(pa, C->pair + C->active[b], invm, C->rigid_invm, C->nq);
            C->A[a * na + b] = C->A[b * na + a] = v;
        }
        C->A[a * na + a] += shift;
        C->rhs[a] = -C->gpred[C->active[a]];
    }
}

/* The multipliers of the active pairs: (G M^-1 G^T dt^2) lambda = -g_pred,
 * solution in C->rhs.  The matrix is only semi-definite when rows depend on
 * each other: with a rigid boulder every row sums to zero over the boulder
 * and its masters, so the rank is at most the number of slope master nodes
 * in contact (two segments carrying two boulder nodes each: 4 rows, rank 3).
 * The multipliers are then not unique, but the corrections G^T lambda (the
 * impulses, the gaps) are: the solve is repeated with the matrix shifted by
 * 1e-9 of its largest diagonal entry (Tikhonov: the least-norm multipliers
 * as the shift goes to zero; the gaps close to 1e-9 of their size).
 * Returns 0, or -1 if even that fails. */
static int active_solve(fem_contact *C, const double *invm, double dt2, int na)
{
    active_matrix(C, invm, dt2, na, 0);
    if (cholesky_solve(C->A, C->rhs, na) == 0)
        return 0;
    active_matrix(C, invm, dt2, na, 0);
    double dmax = 0;
    for (int a = 0; a < na; a++)
        dmax = fmax(dmax, C->A[a * na + a]);
    active_matrix(C, invm, dt2, na, 1e-9 * dmax);
    return cholesky_solve(C->A, C->rhs, na);
}

/* lambda of the active pairs from C->rhs and their displacement corrections
 * in the scratch C->du (a rigid boulder's on every candidate slave). */
static void active_corrections(fem_contact *C, const double *invm, double dt2, int na, int nc)
{
    double du_rigid = 0; /* of a rigid boulder (every slave) */
    const int q0 = C->rigid_invm > 0;
    for (int a = 0; a < na; a++) {
        const contact_pair *p = C->pair + C->active[a];
        C->lambda[C->active[a]] = C->rhs[a];
        du_rigid += dt2 * C->rigid_invm * p->c[0] * C->rhs[a];
        for (int q = q0; q < C->nq; q++)
            C->du[p->dof[q]] += dt2 * invm[p->dof[q]] * p->c[q] * C->rhs[a];
    }
    if (q0)
        for (int k = 0; k < nc; k++)
            C->du[C->pair[C->cand[k]].dof[0]] = du_rigid;
}

/* The gap of pair i after the corrections in C->du. */
static double corrected_gap(const fem_contact *C, int i)
{
    const contact_pair *p = C->pair + i;
    double g = C->gpred[i];
    for (int q = 0; q < C->nq; q++)
        g += p->c[q] * C->du[p->dof[q]];
    return g;
}

static int is_active(const fem_contact *C, int na, int i)
{
    int in = 0;
    for (int a = 0; a < na; a++)
        in |= C->active[a] == i;
    return in;
}

/* Zero the scratch C->du and the candidates' multipliers. */
static void clean_scratch(fem_contact *C, int nc)
{
    for (int k = 0; k < nc; k++) {
        const contact_pair *p = C->pair + C->cand[k];
        for (int q = 0; q < C->nq; q++)
            C->du[p->dof[q]] = 0;
    }
}

/* Fallback when the block active-set method below cycles (seen with a rigid
 * boulder pressing a squeezed soil layer, many nearly dependent pairs):
 * Murty's (1974) least-index principal pivoting, which changes one pair per
 * iteration, the violated one of least number (a negative multiplier, or an
 * inactive pair that would penetrate) and terminates for a positive-definite
 * matrix. */
static rf_status contact_solve_single(fem_contact *C, const double *invm, double dt2, int nc, int na, rf_error *err)
{
    for (long iter = 0; iter < 100 + 20L * nc * nc; iter++) {
        for (int k = 0; k < nc; k++)
            C->lambda[C->cand[k]] = 0;
        if (na > 0 && active_solve(C, invm, dt2, na) != 0)
            return rf_fail(err, RF_EINTERNAL, "fem contact: singular contact matrix (%d pairs)", na);
        active_corrections(C, invm, dt2, na, nc);
        int j = -1;
        for (int k = 0; k < nc; k++) {
            const int i = C->cand[k];
            const int bad = is_active(C, na, i) ? C->lambda[i] < 0 : corrected_gap(C, i) < -C->tol;
            if (bad && (j < 0 || i < j))
                j = i;
        }
        clean_scratch(C, nc);
        if (j < 0)
            return RF_OK;
        if (is_active(C, na, j)) { /* drop it */
            int k = 0;
            for (int a = 0; a < na; a++)
                if (C->active[a] != j)
                    C->active[k++] = C->active[a];
            na = k;
        } else {
            C->active[na++] = j;
        }
    }
    return rf_fail(err, RF_EINTERNAL, "fem contact: active set did not settle (%d candidate pairs)", nc);
}

/* Solve the contact LCP for the predicted displacements u; writes lambda.
 * Block active set: drop every pair in tension, add every penetrating one;
 * after C->block_rounds rounds without settling, the single-pivot
 * fallback above. */
static rf_status contact_solve(fem_contact *C, const double *u, const double *invm, double dt, rf_error *err)
{
    int nc = 0, na = 0;
    for (long i = 0; i < C->npairs; i++) {
        const contact_pair *p = C->pair + i;
        double g = pair_gap(p, u, C->nq);
        C->gpred[i] = g;
        C->lambda[i] = 0;
        if (g < C->band) {
            C->cand[nc++] = (int)i;
            if (g < 0)
                C->active[na++] = (int)i;
        }
    }
    double dt2 = dt * dt;
    for (int iter = 0; iter < C->block_rounds && na > 0; iter++) {
        if (active_solve(C, invm, dt2, na) != 0)
            return rf_fail(err, RF_EINTERNAL, "fem contact: singular contact matrix (%d pairs)", na);
        int neg = 0;
        for (int a = 0; a < na; a++)
            if (C->rhs[a] < 0)
                neg = 1;
        if (neg) { /* drop pairs in tension */
            int k = 0;
            for (int a = 0; a < na; a++)
                if (C->rhs[a] >= 0)
                    C->active[k++] = C->active[a];
            na = k;
            continue;
        }
        /* displacement corrections, then check the inactive candidates */
        active_corrections(C, invm, dt2, na, nc);
        int added = 0;
        for (int k = 0; k < nc; k++) {
            int i = C->cand[k];
            if (C->lambda[i] > 0)
                continue;
            if (corrected_gap(C, i) < -C->tol && !is_active(C, na, i))
                C->active[na++] = i, added = 1;
        }
        clean_scratch(C, nc);
        if (!added)
            return RF_OK;
        for (int k = 0; k < nc; k++)
            C->lambda[C->cand[k]] = 0;
    }
    if (na > 0)
        return contact_solve_single(C, invm, dt2, nc, na, err);
    return RF_OK;
}

void fem_contact_free(fem_contact *C)
{
    free(C->pair), free(C->gpred), free(C->lambda), free(C->active), free(C->cand), free(C->A), free(C->rhs);
    free(C->du), free(C->gvo), free(C->vold), free(C->lam_t), free(C->vt_old);
    *C = (fem_contact){0};
}

/* Pair every boulder surface node of the lower half (below its equator,
 * height d above the lowest point: the whole list mesh->bsurf) with the
 * slope segment under it.  Penetrations up to about r0 (sand, section 8 of
 * docs/validation-plastic.md) need the steep sides: a set ending at d/2 let
 * the soil pass the sides of a block sunk deeper than that.  The upper half
 * is not paired: with the vertical pairing its nodes would face the soil
 * under the lower half, and soil folding over the top of the block cannot
 * be represented by a slope surface that stays a graph z(r). */
rf_status fem_contact_setup(fem_contact *C, const fem_mesh *mesh, long ndof, double d, rf_error *err)
{
    *C = (fem_contact){0};
    C->nq = 3, C->block_rounds = FEM_CONTACT_BLOCK_ROUNDS;
    const size_t nb = (size_t)mesh->n_bsurf + 1;
    C->pair = malloc(nb * sizeof *C->pair);
    C->gpred = calloc(nb, sizeof *C->gpred);
    C->lambda = calloc(nb, sizeof *C->lambda);
    C->active = malloc(nb * sizeof *C->active);
    C->cand = malloc(nb * sizeof *C->cand);
    C->du = calloc((size_t)ndof, sizeof *C->du);
    if (!C->pair || !C->gpred || !C->lambda || !C->active || !C->cand || !C->du)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    for (long k = 0; k < mesh->n_bsurf; k++) {
        int s = mesh->bsurf[k];
        double rs = mesh->r[s];
        if (mesh->z[s] > d || rs >= mesh->r[mesh->ssurf[mesh->n_ssurf - 1]])
            continue;
        long j = 0;
        while (j + 2 < mesh->n_ssurf && mesh->r[mesh->ssurf[j + 1]] <= rs)
            j++;
        int m1 = mesh->ssurf[j], m2 = mesh->ssurf[j + 1];
        double xi = (rs - mesh->r[m1]) / (mesh->r[m2] - mesh->r[m1]);
        contact_pair *p = C->pair + C->npairs++;
        p->dof[0] = 2 * s + 1, p->dof[1] = 2 * m1 + 1, p->dof[2] = 2 * m2 + 1;
        p->rdof[0] = 2 * s, p->rdof[1] = 2 * m1, p->rdof[2] = 2 * m2;
        p->c[0] = 1, p->c[1] = -(1 - xi), p->c[2] = -xi;
        p->g0 = mesh->z[s] - ((1 - xi) * mesh->z[m1] + xi * mesh->z[m2]);
        p->r = rs, p->xi = xi, p->seg = j, p->n[0] = 0, p->n[1] = 1;
    }
    C->A = malloc((size_t)C->npairs * C->npairs * sizeof *C->A + sizeof(double));
    C->rhs = malloc(((size_t)C->npairs + 1) * sizeof *C->rhs);
    C->gvo = malloc(((size_t)C->npairs + 1) * sizeof *C->gvo);
    if (!C->A || !C->rhs || !C->gvo)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    return RF_OK;
}

/* G v_{n-1/2} of every pair, kept for the contact work. */
void fem_contact_begin(fem_contact *C, const double *v)
{
    if (C->vt_old)
        memcpy(C->vt_old, v, (size_t)C->ndof * sizeof *v);
    if (C->vold) { /* the pairs change after the predictor: keep v itself */
        memcpy(C->vold, v, (size_t)(2 * C->mesh->n_nodes) * sizeof *v);
        return;
    }
    for (long i = 0; i < C->npairs; i++) {
        const contact_pair *p = C->pair + i;
        C->gvo[i] = p->c[0] * v[p->dof[0]] + p->c[1] * v[p->dof[1]] + p->c[2] * v[p->dof[2]];
    }
}

/* The corrections of u and v by the multipliers C->lambda; returns their
 * vertical force on the boulder. */
static double apply_normal(fem_contact *C, const double *invm, double dt, double *u, double *v)
{
    double F = 0, dv_rigid = 0;
    const int q0 = C->rigid_invm > 0;
    for (long i = 0; i < C->npairs; i++) {
        if (C->lambda[i] <= 0)
            continue;
        const contact_pair *p = C->pair + i;
        dv_rigid += dt * C->rigid_invm * p->c[0] * C->lambda[i];
        for (int q = q0; q < C->nq; q++) {
            double dv = dt * invm[p->dof[q]] * p->c[q] * C->lambda[i];
            v[p->dof[q]] += dv;
            u[p->dof[q]] += dt * dv;
        }
        F += C->lambda[i] * p->c[0]; /* the vertical force on the boulder (c[0] = 1 in small strain) */
    }
    if (q0 && dv_rigid != 0) /* the whole boulder moves */
        for (long d = 1; d < C->rigid_dofs; d += 2)
            v[d] += dv_rigid, u[d] += dt * dv_rigid;
    return F;
}

static void pairs_at_midpoint(fem_contact *C, const double *u, const double *v, double dt);

/* Multipliers for the predicted u, their corrections of u and v, the
 * contact work lambda' G (v_{n+1/2} + v_{n-1/2}) dt / 2; returns the total
 * vertical contact force on the boulder in *Fc. */
rf_status fem_contact_step(fem_contact *C, const double *invm, double dt, double *u, double *v, double *Fc,
                           rf_error *err)
{
    if (C->mesh) /* large deformation: after fem_contact_update */
        pairs_at_midpoint(C, u, v, dt);
    rf_status st = contact_solve(C, u, invm, dt, err);
    if (st != RF_OK)
        return st;
    double F = apply_normal(C, invm, dt, u, v);
    if (C->friction > 0) /* the tangential multipliers, on the normal ones (fem_contact_friction.c) */
        F += fem_contact_friction(C, invm, dt, u, v);
    for (long i = 0; i < C->npairs; i++) {
        if (C->lambda[i] <= 0)
            continue;
        const contact_pair *p = C->pair + i;
        double gvn = 0;
        for (int q = 0; q < C->nq; q++)
            gvn += p->c[q] * v[p->dof[q]];
        C->work += C->lambda[i] * (gvn + C->gvo[i]) * dt / 2;
    }
    *Fc = F;
    return RF_OK;
}

/* Radius of the contact from the outermost closed pair kout and the gaps of
 * the next two pairs: gap ~ (r - a)^(3/2) outside a Hertz contact, so
 * g^(2/3) is extrapolated linearly to zero. */
static double contact_radius(const fem_contact *C, long kout)
{
    double rad = C->pair[kout].r;
    long k1 = -1, k2 = -1;
    for (long i = 0; i < C->npairs; i++) {
        double ri = C->pair[i].r;
        if (ri <= rad)
            continue;
        if (k1 < 0 || ri < C->pair[k1].r)
            k2 = k1, k1 = i;
        else if (k2 < 0 || ri < C->pair[k2].r)
            k2 = i;
    }
    if (k1 >= 0 && k2 >= 0 && C->pair[k2].r < C->pair[k1].r) {
        long t2 = k1;
        k1 = k2, k2 = t2;
    }
    if (k1 >= 0 && k2 >= 0) {
        double g1 = pow(fmax(C->gpred[k1], 0), 2.0 / 3), g2 = pow(fmax(C->gpred[k2], 0), 2.0 / 3);
        double r1 = C->pair[k1].r, r2 = C->pair[k2].r;
        if (g2 > g1) {
            double a = r1 - g1 * (r2 - r1) / (g2 - g1);
            rad = fmin(fmax(a, rad), r1);
        }
    }
    return rad;
}

/* Gaps at n+1: largest penetration and radial slip so far, contact radius. */
double fem_contact_measure(fem_contact *C, const double *u)
{
    long kout = -1;
    for (long i = 0; i < C->npairs; i++) {
        const contact_pair *p = C->pair + i;
        double g = pair_gap(p, u, C->nq);
        if (-g > C->pen_max)
            C->pen_max = -g;
        C->gpred[i] = g;
        if (C->lambda[i] > 0) {
            double slip = C->nq == 3 ? fabs(u[p->rdof[0]] + p->c[1] * u[p->rdof[1]] + p->c[2] * u[p->rdof[2]])
                                     : fabs(u[p->rdof[0]] - (1 - p->xi) * u[p->rdof[1]] - p->xi * u[p->rdof[2]]);
            if (slip > C->slip_max)
                C->slip_max = slip;
            if (kout < 0 || p->r > C->pair[kout].r)
                kout = i;
        }
    }
    return kout >= 0 ? contact_radius(C, kout) : 0;
}

rf_status fem_contact_large(fem_contact *C, const fem_mesh *mesh, long ndof, rf_error *err)
{
    C->nq = 10, C->mesh = mesh;
    if (!(C->vold = calloc((size_t)ndof + 1, sizeof *C->vold)))
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    return RF_OK;
}

/* Current position of node n. */
static void node_x(const fem_mesh *m, const double *u, int n, double x[2])
{
    x[0] = m->r[n] + u[2 * n], x[1] = m->z[n] + u[2 * n + 1];
}

/* Segment j of the current slope surface with its neighbours (fem_contact_surface.h). */
static void surface_segment(const fem_mesh *m, const double *u, long j, fem_surf_segment *S)
{
    S->has_prev = j > 0, S->has_next = j + 2 < m->n_ssurf;
    for (int k = 0; k < 4; k++) {
        const long i = j - 1 + k;
        node_x(m, u, m->ssurf[i < 0 ? 0 : i >= m->n_ssurf ? m->n_ssurf - 1 : i], S->p[k]);
    }
}

/* The slave's closest point on the smooth current surface, from the pair's
 * last segment on: moves to the neighbouring segment while the point lies
 * beyond the segment's ends (the curve is C1, so the walk cannot turn back
 * and forth at a node; bounded anyway). */
static long surface_gap(const fem_mesh *m, const double *u, long j, const double x[2], fem_surf_segment *S,
                        fem_surf_gap *G)
{
    const long last = m->n_ssurf - 2;
    for (long walk = 0; walk <= m->n_ssurf; walk++) {
        surface_segment(m, u, j, S);
        const int side = fem_surf_project(S, x, G);
        if ((side < 0 && j == 0) || (side > 0 && j == last) || side == 0)
            break;
        j += side;
    }
    return j;
}

/* The pair's gradient c and dofs from the gap G of segment S (nodes of
 * segment p->seg) for slave s: n on the slave, -(dx(xi)/dx_k)' n on the
 * masters m0..m3 (the segment's nodes and the neighbours that shape its
 * rounded corners; xi and n drop out at a closest point); absent neighbours
 * (axis, end of the surface) get zero entries. */
static void pair_gradient(fem_contact *C, contact_pair *p, int s, const fem_surf_segment *S, const fem_surf_gap *G)
{
    const fem_mesh *m = C->mesh;
    const long j = p->seg, nsurf = m->n_ssurf;
    const int mk[4] = {m->ssurf[j > 0 ? j - 1 : j], m->ssurf[j], m->ssurf[j + 1],
                       m->ssurf[j + 2 < nsurf ? j + 2 : j + 1]};
    const int rigid = C->rigid_invm > 0;
    const int dof[10] = {2 * s + 1, 2 * mk[1] + 1, 2 * mk[2] + 1, 2 * s, 2 * mk[1], 2 * mk[2],
                         2 * mk[0] + 1, 2 * mk[3] + 1, 2 * mk[0], 2 * mk[3]};
    const double c[10] = {G->n[1], G->dg[1][1], G->dg[2][1], rigid ? 0 : G->n[0], G->dg[1][0], G->dg[2][0],
                          S->has_prev ? G->dg[0][1] : 0, S->has_next ? G->dg[3][1] : 0,
                          S->has_prev ? G->dg[0][0] : 0, S->has_next ? G->dg[3][0] : 0};
    for (int q = 0; q < 10; q++)
        p->dof[q] = dof[q], p->c[q] = c[q];
    p->rdof[0] = 2 * s, p->rdof[1] = 2 * mk[1], p->rdof[2] = 2 * mk[2];
    p->xi = G->xi, p->n[0] = G->n[0], p->n[1] = G->n[1];
}

/* Pair p for the predicted slave position x_s: its closest point x(xi) on
 * the smooth surface (the slope's surface polygon with its corners rounded
 * by quadratic arcs, normal continuous along it: fem_contact_surface.c) and the gap
 * g = n . (x_s - x(xi)) along the normal there, kept in p->g0 until
 * pair_midpoint makes the linear form. */
static void pair_relinearise(fem_contact *C, contact_pair *p, const double *u)
{
    const fem_mesh *m = C->mesh;
    const int s = (p->dof[0] - 1) / 2;
    double x[2];
    node_x(m, u, s, x);
    fem_surf_segment S;
    fem_surf_gap G;
    p->seg = surface_gap(m, u, p->seg, x, &S, &G);
    pair_gradient(C, p, s, &S, &G);
    p->g0 = G.g, p->r = x[0];
}

/* The linear form g0 + c . u of pair p for the step from u_n = u - dt v to
 * the predicted u: the gap at the predicted u (pair_relinearise), the
 * gradient at u_n, on the same segment's curve (extended past its ends if
 * the slave was beyond them).  The gradient at the start of the step, the
 * midpoint of u_{n-1} and u_{n+1}, makes the impulse's work
 * lambda c . (u_{n+1} - u_{n-1}) / 2 the gap's change to third order in the
 * step (a closed pair's force does no work, up to round-off and O(dt^3)); the
 * gradient at the predicted end, which the contact used before, is off by
 * the gap's curvature times the step, and its work lambda dt^2 v' H v has
 * the sign of that curvature: it fed the relative motion of closed pairs
 * energy in proportion to its own (issue 29 item 1, exponential growth). */
static void pair_midpoint(fem_contact *C, contact_pair *p, const double *u, const double *v, double dt)
{
    const fem_mesh *m = C->mesh;
    const int s = p->rdof[0] / 2;
    double un[2 * 5];
    int nodes[5] = {s, m->ssurf[p->seg > 0 ? p->seg - 1 : p->seg], m->ssurf[p->seg], m->ssurf[p->seg + 1],
                    m->ssurf[p->seg + 2 < m->n_ssurf ? p->seg + 2 : p->seg + 1]};
    for (int k = 0; k < 5; k++)
        for (int a = 0; a < 2; a++) {
            const int d = 2 * nodes[k] + a;
            un[2 * k + a] = (a ? m->z[nodes[k]] : m->r[nodes[k]]) + u[d] - dt * v[d];
        }
    fem_surf_segment S = {.has_prev = p->seg > 0, .has_next = p->seg + 2 < m->n_ssurf};
    for (int k = 0; k < 4; k++)
        S.p[k][0] = un[2 * (k + 1)], S.p[k][1] = un[2 * (k + 1) + 1];
    fem_surf_gap G;
    fem_surf_project_extended(&S, un, &G);
    const double g = p->g0;
    pair_gradient(C, p, s, &S, &G);
    p->g0 = g;
    for (int q = 0; q < C->nq; q++)
        p->g0 -= p->c[q] * u[p->dof[q]];
}

/* After the predictor (large deformation): every pair's closest point and gap
 * at the predicted u; fem_contact_step adds the gradient at the step's start
 * (pairs_at_midpoint) and G v_{n-1/2} with it for the contact work. */
void fem_contact_update(fem_contact *C, const double *u)
{
    for (long i = 0; i < C->npairs; i++)
        pair_relinearise(C, C->pair + i, u);
}

/* Large deformation, at the start of the step's contact: each pair's linear
 * form (pair_midpoint) and G v_{n-1/2} with its gradient, for the work. */
static void pairs_at_midpoint(fem_contact *C, const double *u, const double *v, double dt)
{
    for (long i = 0; i < C->npairs; i++) {
        contact_pair *p = C->pair + i;
        pair_midpoint(C, p, u, v, dt);
        double gv = 0;
        for (int q = 0; q < C->nq; q++)
            gv += p->c[q] * C->vold[p->dof[q]];
        C->gvo[i] = gv;
    }
}
