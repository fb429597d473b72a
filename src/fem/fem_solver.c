/* fem_solver.c - rf_fem_impact: set-up, the central-difference time loop,
 * forward-increment Lagrange-multiplier contact, energy bookkeeping and the
 * extraction of the impact outputs.
 *
 * Time integration (lumped mass M, stiffness K, external forces f):
 *   v_{n+1/2} = v_{n-1/2} + dt M^-1 (f_n - K u_n + G^T lambda_n),  u_{n+1} = u_n + dt v_{n+1/2}.
 * Contact (Carpenter, Taylor & Katona 1991, IJNME 32:103): the multipliers
 * lambda_n >= 0 are the forces at step n that make the predicted gaps at
 * n+1 exactly non-negative (a small linear complementarity problem over the
 * pairs near contact, solved by an active set with dense Cholesky); they add
 * no compliance and do not restrict dt.  Pairs are node-to-segment with
 * small sliding: each boulder surface node keeps the slope segment and the
 * local coordinate found in the reference configuration; the normal is the
 * slope's undeformed normal (vertical), frictionless.
 * Energy: with K symmetric, E_n = 1/2 v_{n+1/2}' M v_{n+1/2} + 1/2 u_n' K u_{n+1}
 * changes only by the work f' (u_{n+1} - u_{n-1}) / 2 of the forces f
 * applied at step n (contact, dashpots), so the closure error measures the
 * contact scheme (its small inelastic node collisions) and round-off only. */
#include "rockfuzz/fem.h"
#include "fem_contact_window.h"
#include "fem_internal.h"

#include <float.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

void rf_fem_history_free(rf_fem_history *h)
{
    if (!h)
        return;
    free(h->t);
    free(h->contact_force), free(h->compression), free(h->contact_radius);
    free(h->kinetic_boulder), free(h->strain_boulder), free(h->kinetic_slope), free(h->strain_slope);
    free(h->contact_work), free(h->absorbed), free(h->closure), free(h->boulder_velocity);
    h->t = h->contact_force = h->compression = h->contact_radius = NULL;
    h->kinetic_boulder = h->strain_boulder = h->kinetic_slope = h->strain_slope = NULL;
    h->contact_work = h->absorbed = h->closure = h->boulder_velocity = NULL;
    h->n = 0;
}

/* One contact pair: boulder node s over slope segment (m1, m2) at coordinate xi. */
typedef struct {
    int dof[3];    /* z dofs: slave, master 1, master 2 */
    double c[3];   /* gap gradient: 1, -(1 - xi), -xi */
    int rdof[3];   /* r dofs, for the slip diagnostic */
    double g0;     /* reference gap */
    double r;      /* reference radius of the slave */
} contact_pair;

typedef struct {
    long ndof, ne, nb_dof;
    const fem_mesh *mesh;
    double *K;        /* 64 per element */
    double *invm;     /* 1/m per dof, 0 on constrained dofs */
    double *mass;     /* nodal mass per dof */
    int threads;
    double *fbuf;     /* per-thread force buffers (threads - 1) */
} fem_system;

static void force_kernel(const fem_system *S, const double *u, double *f, long e0, long e1)
{
    const int *conn = S->mesh->conn;
    for (long e = e0; e < e1; e++) {
        const int *c = conn + 4 * e;
        const double *k = S->K + 64 * e;
        double ue[8];
        for (int a = 0; a < 4; a++) {
            ue[2 * a] = u[2 * c[a]];
            ue[2 * a + 1] = u[2 * c[a] + 1];
        }
        double fe[8];
        for (int a = 0; a < 8; a++) {
            const double *ka = k + 8 * a;
            fe[a] = ka[0] * ue[0] + ka[1] * ue[1] + ka[2] * ue[2] + ka[3] * ue[3] + ka[4] * ue[4] +
                    ka[5] * ue[5] + ka[6] * ue[6] + ka[7] * ue[7];
        }
        for (int a = 0; a < 4; a++) {
            f[2 * c[a]] += fe[2 * a];
            f[2 * c[a] + 1] += fe[2 * a + 1];
        }
    }
}

/* f = K u */
static void internal_force(const fem_system *S, const double *u, double *f)
{
#ifdef _OPENMP
    if (S->threads > 1) {
#pragma omp parallel num_threads(S->threads)
        {
            int tid = omp_get_thread_num(), T = omp_get_num_threads();
            double *ft = tid == 0 ? f : S->fbuf + (size_t)(tid - 1) * S->ndof;
            memset(ft, 0, (size_t)S->ndof * sizeof *ft);
            force_kernel(S, u, ft, S->ne * tid / T, S->ne * (tid + 1) / T);
#pragma omp barrier
            long d0 = S->ndof * tid / T, d1 = S->ndof * (tid + 1) / T;
            for (int t = 1; t < T; t++) {
                const double *src = S->fbuf + (size_t)(t - 1) * S->ndof;
                for (long d = d0; d < d1; d++)
                    f[d] += src[d];
            }
        }
        return;
    }
#endif
    memset(f, 0, (size_t)S->ndof * sizeof *f);
    force_kernel(S, u, f, 0, S->ne);
}

/* Dense Cholesky solve of A x = b (n x n, A overwritten).  Returns 0 on success. */
static int cholesky_solve(double *A, double *b, int n)
{
    for (int j = 0; j < n; j++) {
        double d = A[j * n + j];
        for (int k = 0; k < j; k++)
            d -= A[j * n + k] * A[j * n + k];
        if (!(d > 0))
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

typedef struct {
    long npairs;
    contact_pair *pair;
    double *gpred;   /* predicted gap per pair */
    double *lambda;  /* multiplier per pair [N] */
    int *active, *cand;
    double *A, *rhs;
    double *du;      /* ndof scratch, kept zero between calls */
    double tol;      /* gap tolerance [m] */
    double band;     /* pairs with predicted gap below this are candidates [m] */
} contact_state;

static double pair_aij(const contact_pair *a, const contact_pair *b, const double *invm)
{
    double s = 0;
    for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++)
            if (a->dof[p] == b->dof[q])
                s += a->c[p] * b->c[q] * invm[a->dof[p]];
    return s;
}

/* Solve the contact LCP for the predicted displacements u; writes lambda. */
static rf_status contact_solve(contact_state *C, const double *u, const double *invm, double dt, rf_error *err)
{
    int nc = 0, na = 0;
    for (long i = 0; i < C->npairs; i++) {
        const contact_pair *p = C->pair + i;
        double g = p->g0 + p->c[0] * u[p->dof[0]] + p->c[1] * u[p->dof[1]] + p->c[2] * u[p->dof[2]];
        C->gpred[i] = g;
        C->lambda[i] = 0;
        if (g < C->band) {
            C->cand[nc++] = (int)i;
            if (g < 0)
                C->active[na++] = (int)i;
        }
    }
    double dt2 = dt * dt;
    for (int iter = 0; iter < 200 && na > 0; iter++) {
        for (int a = 0; a < na; a++) {
            const contact_pair *pa = C->pair + C->active[a];
            for (int b = 0; b <= a; b++) {
                double v = dt2 * pair_aij(pa, C->pair + C->active[b], invm);
                C->A[a * na + b] = C->A[b * na + a] = v;
            }
            C->rhs[a] = -C->gpred[C->active[a]];
        }
        if (cholesky_solve(C->A, C->rhs, na) != 0)
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
        for (int a = 0; a < na; a++) {
            const contact_pair *p = C->pair + C->active[a];
            C->lambda[C->active[a]] = C->rhs[a];
            for (int q = 0; q < 3; q++)
                C->du[p->dof[q]] += dt2 * invm[p->dof[q]] * p->c[q] * C->rhs[a];
        }
        int added = 0;
        for (int k = 0; k < nc; k++) {
            int i = C->cand[k];
            if (C->lambda[i] > 0)
                continue;
            const contact_pair *p = C->pair + i;
            double g = C->gpred[i] + p->c[0] * C->du[p->dof[0]] + p->c[1] * C->du[p->dof[1]] +
                       p->c[2] * C->du[p->dof[2]];
            if (g < -C->tol) {
                int in = 0;
                for (int a = 0; a < na; a++)
                    in |= C->active[a] == i;
                if (!in)
                    C->active[na++] = i, added = 1;
            }
        }
        for (int k = 0; k < nc; k++) { /* clean scratch */
            const contact_pair *p = C->pair + C->cand[k];
            for (int q = 0; q < 3; q++)
                C->du[p->dof[q]] = 0;
        }
        if (!added)
            return RF_OK;
        for (int k = 0; k < nc; k++)
            C->lambda[C->cand[k]] = 0;
    }
    if (na > 0)
        return rf_fail(err, RF_EINTERNAL, "fem contact: active set did not settle");
    return RF_OK;
}

/* What the axisymmetric model can do beyond the ranges every impact model
 * shares (rf_impact_input_validate) and the option rules (rf_fem_options_validate). */
static rf_status check_input(const rf_impact_input *in, const rf_fem_options *o, rf_error *err)
{
    if (!in || !o)
        return rf_fail(err, RF_EINVAL, "fem: NULL input or options");
    if (!(in->slope_angle == 0))
        return rf_fail(err, RF_EINVAL,
                       "fem: the axisymmetric FE model handles only normal impact (slope_angle = 0); got slope_angle = %g rad",
                       in->slope_angle);
    if (rf_impact_input_validate(in, err) != RF_OK)
        return rf_error_prefix(err, "fem");
    rf_status st = rf_fem_options_validate(o, 0, err);
    if (st != RF_OK)
        return st;
    double c = in->horizontal_axis, d = rf_impact_vertical_semi_axis(in);
    if (c > 0 && (c / d > 3 * (1 + 1e-9) || d / c > 3 * (1 + 1e-9)))
        return rf_fail(err, RF_EINVAL, "fem: spheroid aspect c/d = %g outside [1/3, 3] is not supported by the mesher",
                       c / d);
    return RF_OK;
}

/* Growable time series. */
typedef struct {
    size_t n, cap;
    double *col[12];
} series;

static int series_push(series *s, const double v[12])
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 1024;
        for (int k = 0; k < 12; k++) {
            double *p = realloc(s->col[k], cap * sizeof *p);
            if (!p)
                return -1;
            s->col[k] = p;
        }
        s->cap = cap;
    }
    for (int k = 0; k < 12; k++)
        s->col[k][s->n] = v[k];
    s->n++;
    return 0;
}

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

rf_status rf_fem_impact(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                        rf_fem_history *hist, rf_error *err)
{
    double wall0 = wall_now();
    if (hist)
        memset(hist, 0, sizeof *hist);
    rf_fem_options o;
    if (opt)
        o = *opt;
    else
        rf_fem_options_default(&o);
    if (!out)
        return rf_fail(err, RF_EINVAL, "fem: NULL output");
    rf_status st = check_input(in, &o, err);
    if (st != RF_OK)
        return st;
    o.refinement = rf_fem_refinement(&o, 0);
    o.domain_factor = rf_fem_domain_factor(&o, in);

    rf_hertz_reference H;
    rf_impact_hertz_reference(in, &H);
    const double V = in->velocity, L = o.domain_factor * in->radius;
    fem_material mat[2] = {{in->boulder_density, in->boulder_E, in->boulder_poisson},
                           {in->slope_density, in->slope_E, in->slope_poisson}};
    double cp[2], cs[2];
    for (int b = 0; b < 2; b++) {
        double lam = mat[b].E * mat[b].nu / ((1 + mat[b].nu) * (1 - 2 * mat[b].nu));
        double mu = mat[b].E / (2 * (1 + mat[b].nu));
        cp[b] = sqrt((lam + 2 * mu) / mat[b].rho);
        cs[b] = sqrt(mu / mat[b].rho);
    }
    /* mesh sizing from the Hertz contact radius */
    double h = H.contact_radius / o.refinement, hb = h * o.boulder_mesh_ratio;
    /* the uniform fine zone must stay well inside the boulder: shrink it at
       very high speed (a/R > 0.24 with the default 2.5 a) down to 1.5 a */
    double core = fmin(o.core_factor, 0.55 * fmin(H.c, H.d) / H.contact_radius);
    if (core < 1.5)
        return rf_fail(err, RF_EINVAL,
                       "fem: the Hertz contact radius a = %.4g m is too large for the boulder (c = %g m, d = %g m): "
                       "a fine zone of 1.5 a must fit in 0.55 min(c, d); Hertz-based meshing needs a << min(c, d)",
                       H.contact_radius, H.c, H.d);
    fem_body_spec bs = {0}, ss = {0};
    ss.h = h;
    ss.n = 3 * (int)ceil(core * o.refinement / 3 - 1e-9);
    while (ss.n > 3 && ss.n * h > 0.6 * fmin(H.c, H.d))
        ss.n -= 3;
    ss.grading = o.grading;
    double cr = cs[1] * (0.87 + 1.12 * mat[1].nu) / (1 + mat[1].nu); /* Rayleigh speed (Viktorov) */
    ss.h_far = fmax(h, fmin(cr * H.duration / 12, L / 8));
    ss.extent = L;
    bs.h = hb;
    bs.n = 3 * (int)ceil(core * o.refinement / o.boulder_mesh_ratio / 3 - 1e-9);
    while (bs.n > 3 && bs.n * hb > 0.6 * fmin(H.c, H.d))
        bs.n -= 3;
    bs.grading = o.grading;
    bs.h_far = fmax(hb, fmin(H.c, H.d) / 10);
    bs.extent = H.c;
    bs.height = H.d;
    if (bs.n * bs.h > 0.7 * fmin(H.c, H.d))
        return rf_fail(err, RF_EINVAL,
                       "fem: the Hertz contact radius %.4g m is too large for the boulder (c = %g m, d = %g m): the "
                       "fine zone does not fit; lower the impact speed or raise refinement",
                       H.contact_radius, H.c, H.d);
    if (ss.n * ss.h * 4 > L)
        return rf_fail(err, RF_EINVAL, "fem: domain radius %g m is too small for the fine zone (%g m)", L,
                       ss.n * ss.h);

    fem_mesh mesh;
    st = fem_mesh_build(&bs, &ss, &mesh, o.max_elements, err);
    if (st != RF_OK)
        return st;

    fem_system S = {0};
    contact_state C = {0};
    series ser = {0};
    double *u = NULL, *v = NULL, *f = NULL, *fext = NULL, *dash = NULL, *Fstep = NULL, *gvo = NULL;
    int *outer = NULL;
    double *vtk_times = NULL;
    long nouter = 0;
    const long nn = mesh.n_nodes, ndof = 2 * nn, ne = mesh.n_elems, nbd = 2 * mesh.boulder_nodes;
    int nthreads = o.threads > 0 ? o.threads : 1;
#ifndef _OPENMP
    nthreads = 1;
#endif
    S.ndof = ndof, S.ne = ne, S.nb_dof = nbd, S.mesh = &mesh, S.threads = nthreads;
    S.K = malloc((size_t)ne * 64 * sizeof *S.K);
    S.invm = calloc((size_t)ndof, sizeof *S.invm);
    S.mass = calloc((size_t)ndof, sizeof *S.mass);
    if (nthreads > 1)
        S.fbuf = malloc((size_t)(nthreads - 1) * ndof * sizeof *S.fbuf);
    u = calloc((size_t)ndof, sizeof *u);
    v = calloc((size_t)ndof, sizeof *v);
    f = calloc((size_t)ndof, sizeof *f);
    fext = calloc((size_t)ndof, sizeof *fext);
    dash = calloc((size_t)ndof, sizeof *dash);
    outer = malloc((size_t)nn * sizeof *outer);
    double *elm = malloc((size_t)ne * 4 * sizeof *elm);
    if (!S.K || !S.invm || !S.mass || (nthreads > 1 && !S.fbuf) || !u || !v || !f || !fext || !dash || !outer ||
        !elm) {
        free(elm);
        st = rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld elements", ne);
        goto done;
    }

    /* constrained dofs: u_r = 0 on the axis; the outer surface if fixed */
    const int fixed_outer = o.boundary == RF_FEM_BOUNDARY_FIXED;
    unsigned char *fixed = calloc((size_t)ndof, 1);
    if (!fixed) {
        free(elm);
        st = rf_fail(err, RF_ENOMEM, "fem: out of memory");
        goto done;
    }
    for (long i = 0; i < nn; i++) {
        if (mesh.flags[i] & FEM_AXIS)
            fixed[2 * i] = 1;
        if (i >= mesh.boulder_nodes && (mesh.flags[i] & FEM_OUTER) && fixed_outer)
            fixed[2 * i] = fixed[2 * i + 1] = 1;
    }
    /* element matrices, lumped masses, time-step bound */
    double lam_max = 0, dt_edge = DBL_MAX, mesh_mass_b = 0;
    for (long e = 0; e < ne; e++) {
        const int *c = mesh.conn + 4 * e;
        double r[4], z[4], mass, area;
        for (int a = 0; a < 4; a++)
            r[a] = mesh.r[c[a]], z[a] = mesh.z[c[a]];
        int b = mesh.ebody[e];
        fem_element_matrices(r, z, &mat[b], S.K + 64 * e, elm + 4 * e, &mass, &area);
        if (!(area > 0)) {
            free(elm), free(fixed);
            st = rf_fail(err, RF_EINTERNAL, "fem mesh: element %ld has non-positive area", e);
            goto done;
        }
        if (b == FEM_BOULDER)
            mesh_mass_b += mass;
        for (int a = 0; a < 4; a++) {
            double ed = hypot(r[(a + 1) % 4] - r[a], z[(a + 1) % 4] - z[a]);
            if (ed > 1e-12 * h && ed / cp[b] < dt_edge)
                dt_edge = ed / cp[b];
        }
    }
    /* the boulder mesh is a polygon inside the spheroid: scale its density so
       that the rigid-body mass is exact (stiffness untouched) */
    const double mscale = H.mass / mesh_mass_b;
    for (long e = 0; e < mesh.boulder_elems; e++)
        for (int a = 0; a < 4; a++)
            elm[4 * e + a] *= mscale;
    for (long e = 0; e < ne; e++) {
        const int *c = mesh.conn + 4 * e;
        int freed[8];
        for (int a = 0; a < 4; a++) {
            S.mass[2 * c[a]] += elm[4 * e + a];
            S.mass[2 * c[a] + 1] += elm[4 * e + a];
            freed[2 * a] = !fixed[2 * c[a]];
            freed[2 * a + 1] = !fixed[2 * c[a] + 1];
        }
        /* degenerate (collapsed) quads repeat a node: merge its masses for the bound */
        double me[4];
        for (int a = 0; a < 4; a++) {
            me[a] = 0;
            for (int b = 0; b < 4; b++)
                if (c[b] == c[a])
                    me[a] += elm[4 * e + b];
        }
        double lm = fem_element_lambda_max(S.K + 64 * e, me, freed);
        if (lm > lam_max)
            lam_max = lm;
    }
    free(elm);
    for (long d = 0; d < ndof; d++)
        S.invm[d] = fixed[d] ? 0 : 1 / S.mass[d];
    free(fixed);
    const double dt_bound = 2 / sqrt(lam_max), dt = o.dt_safety * dt_bound;

    /* dashpots on the outer surface (Lysmer & Kuhlemeyer 1969) */
    if (!fixed_outer) {
        double *trib = dash; /* reuse as tributary area per node (even entries) */
        for (long e = mesh.boulder_elems; e < ne; e++) {
            const int *c = mesh.conn + 4 * e;
            for (int a = 0; a < 4; a++) {
                int p = c[a], q = c[(a + 1) % 4];
                if (p != q && (mesh.flags[p] & FEM_OUTER) && (mesh.flags[q] & FEM_OUTER)) {
                    double l = hypot(mesh.r[q] - mesh.r[p], mesh.z[q] - mesh.z[p]);
                    trib[2 * p] += 2 * M_PI * l * (mesh.r[p] / 3 + mesh.r[q] / 6);
                    trib[2 * q] += 2 * M_PI * l * (mesh.r[p] / 6 + mesh.r[q] / 3);
                }
            }
        }
        for (long i = mesh.boulder_nodes; i < nn; i++)
            if (mesh.flags[i] & FEM_OUTER)
                outer[nouter++] = (int)i;
    }

    /* contact pairs */
    C.pair = malloc((size_t)mesh.n_bsurf * sizeof *C.pair);
    C.gpred = calloc((size_t)mesh.n_bsurf + 1, sizeof *C.gpred);
    C.lambda = calloc((size_t)mesh.n_bsurf + 1, sizeof *C.lambda);
    C.active = malloc(((size_t)mesh.n_bsurf + 1) * sizeof *C.active);
    C.cand = malloc(((size_t)mesh.n_bsurf + 1) * sizeof *C.cand);
    C.du = calloc((size_t)ndof, sizeof *C.du);
    if (!C.pair || !C.gpred || !C.lambda || !C.active || !C.cand || !C.du) {
        st = rf_fail(err, RF_ENOMEM, "fem: out of memory");
        goto done;
    }
    for (long k = 0; k < mesh.n_bsurf; k++) {
        int s = mesh.bsurf[k];
        double rs = mesh.r[s];
        if (mesh.z[s] > 0.5 * H.d || rs >= mesh.r[mesh.ssurf[mesh.n_ssurf - 1]])
            continue;
        long j = 0;
        while (j + 2 < mesh.n_ssurf && mesh.r[mesh.ssurf[j + 1]] <= rs)
            j++;
        int m1 = mesh.ssurf[j], m2 = mesh.ssurf[j + 1];
        double xi = (rs - mesh.r[m1]) / (mesh.r[m2] - mesh.r[m1]);
        contact_pair *p = C.pair + C.npairs++;
        p->dof[0] = 2 * s + 1, p->dof[1] = 2 * m1 + 1, p->dof[2] = 2 * m2 + 1;
        p->rdof[0] = 2 * s, p->rdof[1] = 2 * m1, p->rdof[2] = 2 * m2;
        p->c[0] = 1, p->c[1] = -(1 - xi), p->c[2] = -xi;
        p->g0 = mesh.z[s] - ((1 - xi) * mesh.z[m1] + xi * mesh.z[m2]);
        p->r = rs;
    }
    C.A = malloc((size_t)C.npairs * C.npairs * sizeof *C.A + sizeof(double));
    C.rhs = malloc(((size_t)C.npairs + 1) * sizeof *C.rhs);
    gvo = malloc(((size_t)C.npairs + 1) * sizeof *gvo);
    if (!C.A || !C.rhs || !gvo) {
        st = rf_fail(err, RF_ENOMEM, "fem: out of memory");
        goto done;
    }
    C.tol = 1e-9 * h;
    C.band = 0.5 * fmin(h, hb) + 2 * V * dt;

    /* initial state: boulder translating down at V */
    for (long i = 0; i < mesh.boulder_nodes; i++)
        v[2 * i + 1] = -V;
    double Mb = 0, Ms = 0;
    for (long i = 0; i < nn; i++)
        *(i < mesh.boulder_nodes ? &Mb : &Ms) += S.mass[2 * i + 1];
    const double ke0 = 0.5 * Mb * V * V;

    const double t_min = o.end_time > 0 ? o.end_time : 1.3 * H.duration;
    const double t_max = o.end_time > 0 ? o.end_time : 3.0 * H.duration;
    long steps_est = (long)ceil(t_min / dt);
    int stride = o.history_stride > 0 ? o.history_stride : (int)(steps_est / 5000 + 1);
    int vtk_every = (int)(steps_est / (o.vtk_frames > 0 ? o.vtk_frames : 60) + 1), vtk_n = 0;
    long fcap = steps_est + 16;
    Fstep = malloc((size_t)fcap * sizeof *Fstep);
    if (!Fstep) {
        st = rf_fail(err, RF_ENOMEM, "fem: out of memory");
        goto done;
    }
    if (o.vtk_dir) {
        vtk_times = malloc((size_t)(o.vtk_frames + 8) * 4 * sizeof *vtk_times);
        if (!vtk_times) {
            st = rf_fail(err, RF_ENOMEM, "fem: out of memory");
            goto done;
        }
    }

    double W_contact = 0, W_abs = 0, closure_max = 0, comp_max = 0, F_max = 0, a_at_Fmax = 0;
    double pen_max = 0, slip_max = 0, t_last_contact = 0, rad = 0;
    int episodes = 0, in_contact = 0;
    long n = 0;
    for (;; n++) {
        double t = n * dt;
        if (o.vtk_dir && n % vtk_every == 0 && vtk_n < 4 * (o.vtk_frames + 8)) {
            st = fem_vtk_frame(o.vtk_dir, vtk_n, t, &mesh, u, v, mat, err);
            if (st != RF_OK)
                goto done;
            vtk_times[vtk_n++] = t;
        }
        internal_force(&S, u, f);
        /* dashpot forces from v_{n-1/2} */
        for (long k = 0; k < nouter; k++) {
            int i = outer[k];
            double nr = mesh.r[i] / L, nz = mesh.z[i] / L, len = hypot(nr, nz);
            nr /= len, nz /= len;
            double vr = v[2 * i], vz = v[2 * i + 1], vn = vr * nr + vz * nz;
            double A = dash[2 * i], rho = mat[1].rho;
            double fr = -A * rho * (cp[1] * vn * nr + cs[1] * (vr - vn * nr));
            double fz = -A * rho * (cp[1] * vn * nz + cs[1] * (vz - vn * nz));
            fext[2 * i] = fr, fext[2 * i + 1] = fz;
        }
        /* predictor; G v_{n-1/2} is kept for the contact work */
        for (long i = 0; i < C.npairs; i++) {
            const contact_pair *p = C.pair + i;
            gvo[i] = p->c[0] * v[p->dof[0]] + p->c[1] * v[p->dof[1]] + p->c[2] * v[p->dof[2]];
        }
        double W_abs_inc = 0;
        for (long k = 0; k < nouter; k++) { /* half of the dashpot work uses v_{n-1/2} */
            int i = outer[k];
            W_abs_inc -= 0.5 * dt * (fext[2 * i] * v[2 * i] + fext[2 * i + 1] * v[2 * i + 1]);
        }
        for (long d = 0; d < ndof; d++) {
            v[d] += dt * S.invm[d] * (fext[d] - f[d]);
            u[d] += dt * v[d];
        }
        for (long k = 0; k < nouter; k++) {
            int i = outer[k];
            W_abs_inc -= 0.5 * dt * (fext[2 * i] * v[2 * i] + fext[2 * i + 1] * v[2 * i + 1]);
        }
        /* contact: multipliers that close the predicted gaps exactly */
        st = contact_solve(&C, u, S.invm, dt, err);
        if (st != RF_OK)
            goto done;
        double Fc = 0;
        for (long i = 0; i < C.npairs; i++) {
            if (C.lambda[i] <= 0)
                continue;
            const contact_pair *p = C.pair + i;
            for (int q = 0; q < 3; q++) {
                double dv = dt * S.invm[p->dof[q]] * p->c[q] * C.lambda[i];
                v[p->dof[q]] += dv;
                u[p->dof[q]] += dt * dv;
            }
            Fc += C.lambda[i];
        }
        /* contact work lambda' G (v_{n+1/2} + v_{n-1/2}) dt / 2 */
        for (long i = 0; i < C.npairs; i++) {
            if (C.lambda[i] <= 0)
                continue;
            const contact_pair *p = C.pair + i;
            double gvn = 0;
            for (int q = 0; q < 3; q++)
                gvn += p->c[q] * v[p->dof[q]];
            W_contact += C.lambda[i] * (gvn + gvo[i]) * dt / 2;
        }
        W_abs += W_abs_inc;
        if (rf_fem_force_record_(&Fstep, &fcap, n, Fc)) {
            st = rf_fail(err, RF_ENOMEM, "fem: out of memory");
            goto done;
        }
        /* penetration, slip, contact radius (gaps at n+1) */
        long kout = -1;
        for (long i = 0; i < C.npairs; i++) {
            const contact_pair *p = C.pair + i;
            double g = p->g0 + p->c[0] * u[p->dof[0]] + p->c[1] * u[p->dof[1]] + p->c[2] * u[p->dof[2]];
            if (-g > pen_max)
                pen_max = -g;
            C.gpred[i] = g;
            if (C.lambda[i] > 0) {
                double slip = fabs(u[p->rdof[0]] + p->c[1] * u[p->rdof[1]] + p->c[2] * u[p->rdof[2]]);
                if (slip > slip_max)
                    slip_max = slip;
                if (kout < 0 || p->r > C.pair[kout].r)
                    kout = i;
            }
        }
        rad = 0;
        if (kout >= 0) {
            rad = C.pair[kout].r;
            /* gap ~ (r - a)^(3/2) outside a Hertz contact: extrapolate g^(2/3) of the next two pairs */
            long k1 = -1, k2 = -1;
            for (long i = 0; i < C.npairs; i++) {
                double ri = C.pair[i].r;
                if (ri <= rad)
                    continue;
                if (k1 < 0 || ri < C.pair[k1].r)
                    k2 = k1, k1 = i;
                else if (k2 < 0 || ri < C.pair[k2].r)
                    k2 = i;
            }
            if (k1 >= 0 && k2 >= 0 && C.pair[k2].r < C.pair[k1].r) {
                long t2 = k1;
                k1 = k2, k2 = t2;
            }
            if (k1 >= 0 && k2 >= 0) {
                double g1 = pow(fmax(C.gpred[k1], 0), 2.0 / 3), g2 = pow(fmax(C.gpred[k2], 0), 2.0 / 3);
                double r1 = C.pair[k1].r, r2 = C.pair[k2].r;
                if (g2 > g1) {
                    double a = r1 - g1 * (r2 - r1) / (g2 - g1);
                    rad = fmin(fmax(a, rad), r1);
                }
            }
        }
        if (Fc > 0) {
            if (!in_contact)
                episodes++;
            in_contact = 1;
            t_last_contact = t;
        } else
            in_contact = 0;
        if (Fc > F_max)
            F_max = Fc, a_at_Fmax = rad;
        /* energies at t_{n+1/2}: KE with v_{n+1/2}, strain 1/2 u_n' K u_{n+1} */
        double ke[2] = {0, 0}, se[2] = {0, 0}, pz = 0, uz = 0;
        for (long d = 0; d < nbd; d++) {
            ke[0] += S.mass[d] * v[d] * v[d];
            se[0] += f[d] * u[d];
        }
        for (long d = 1; d < nbd; d += 2) {
            pz += S.mass[d] * v[d];
            uz += S.mass[d] * u[d];
        }
        for (long d = nbd; d < ndof; d++) {
            ke[1] += S.mass[d] * v[d] * v[d];
            se[1] += f[d] * u[d];
        }
        ke[0] *= 0.5, ke[1] *= 0.5, se[0] *= 0.5, se[1] *= 0.5;
        double comp = -uz / Mb;
        if (comp > comp_max)
            comp_max = comp;
        double closure = ke[0] + ke[1] + se[0] + se[1] + W_abs - ke0;
        if (!isfinite(closure) || fabs(closure) > 10 * ke0) {
            st = rf_fail(err, RF_EMODEL,
                         "fem: the solution diverged at t = %.4g s (energy %.3g x KE0); time step %.3g s is unstable",
                         t, closure / ke0, dt);
            goto done;
        }
        if (fabs(closure) > closure_max)
            closure_max = fabs(closure);
        if (hist && n % stride == 0) {
            double row[12] = {t, Fc, comp, rad, ke[0], se[0], ke[1], se[1], W_contact, W_abs, closure, pz / Mb};
            if (series_push(&ser, row) != 0) {
                st = rf_fail(err, RF_ENOMEM, "fem: out of memory");
                goto done;
            }
        }
        double tn = (n + 1) * dt;
        if (tn >= t_max)
            break;
        if (o.end_time > 0) {
            if (tn >= o.end_time)
                break;
        } else if (tn >= t_min && !in_contact && tn - t_last_contact > 0.1 * H.duration)
            break;
    }
    long nsteps = n + 1;

    /* outputs.  Contact duration: first to last nonzero multiplier (exact
       zeros off contact; the threshold only guards round-off), the end
       extrapolated linearly to zero within the last step. */
    double t0, t1;
    rf_fem_contact_window_(Fstep, nsteps, dt, o.duration_threshold * F_max, &t0, &t1);
    double pz = 0, ekb = 0, seb = 0, eks = 0, ses = 0;
    for (long d = 1; d < nbd; d += 2)
        pz += S.mass[d] * v[d];
    for (long d = 0; d < nbd; d++)
        ekb += 0.5 * S.mass[d] * v[d] * v[d];
    for (long d = nbd; d < ndof; d++)
        eks += 0.5 * S.mass[d] * v[d] * v[d];
    {   /* strain energy of the final state, 1/2 u' K u */
        internal_force(&S, u, f);
        for (long d = 0; d < nbd; d++)
            seb += 0.5 * f[d] * u[d];
        for (long d = nbd; d < ndof; d++)
            ses += 0.5 * f[d] * u[d];
    }
    double v_after = pz / Mb;
    memset(out, 0, sizeof *out);
    out->contact_force_max = F_max;
    out->compression_max = comp_max;
    out->contact_duration = t1 - t0;
    out->contact_radius = a_at_Fmax;
    out->v_n_before = -V;
    out->v_t_before = 0;
    out->v_n_after = v_after;
    out->v_t_after = 0;
    out->omega_after = 0;
    out->R_n = -v_after / -V;
    out->R_t = NAN;
    out->R_ke = (v_after * v_after) / (V * V);
    out->energy_error = closure_max / ke0;
    out->nodes = (double)nn;
    out->elements = (double)ne;
    out->steps = (double)nsteps;

    if (o.vtk_dir) {
        st = fem_vtk_index(o.vtk_dir, vtk_n, vtk_times, err);
        if (st != RF_OK)
            goto done;
    }
    if (hist) {
        hist->n = ser.n;
        double **dst[12] = {&hist->t, &hist->contact_force, &hist->compression, &hist->contact_radius,
                            &hist->kinetic_boulder, &hist->strain_boulder, &hist->kinetic_slope,
                            &hist->strain_slope, &hist->contact_work, &hist->absorbed, &hist->closure,
                            &hist->boulder_velocity};
        for (int k = 0; k < 12; k++)
            *dst[k] = ser.col[k], ser.col[k] = NULL;
        hist->dt = dt;
        hist->dt_bound = dt_bound;
        hist->dt_edge = dt_edge;
        hist->h_contact = h;
        hist->hertz_radius = H.contact_radius;
        hist->hertz_duration = H.duration;
        hist->boulder_mass = H.mass;
        hist->boulder_mesh_mass = mesh_mass_b;
        hist->penetration_max = pen_max;
        hist->slip_max = slip_max;
        hist->reflection_time = 2 * L / cp[1];
        hist->vibration_energy = ekb + seb - 0.5 * Mb * v_after * v_after;
        hist->slope_energy = eks + ses;
        hist->ke0 = ke0;
        hist->boulder_nodes = mesh.boulder_nodes;
        hist->boulder_elements = mesh.boulder_elems;
        hist->slope_nodes = nn - mesh.boulder_nodes;
        hist->slope_elements = ne - mesh.boulder_elems;
        size_t wl = 0;
        hist->warning[0] = 0;
        if (fixed_outer && 2 * L / cp[1] < H.duration)
            wl += (size_t)snprintf(hist->warning + wl, sizeof hist->warning - wl,
                                   "P waves reflected by the fixed boundary return after 2L/c_p = %.3g ms, before the "
                                   "Hertz contact ends (%.3g ms): R_n includes reflected energy; use absorbing "
                                   "boundaries or domain_factor >= %.0f. ",
                                   2e3 * L / cp[1], 1e3 * H.duration, ceil(cp[1] * H.duration / 2 / in->radius));
        if (episodes > 1 && wl < sizeof hist->warning)
            wl += (size_t)snprintf(hist->warning + wl, sizeof hist->warning - wl,
                                   "Contact closed %d times (re-contact after separation). ", episodes);
        if (o.end_time > 0 && in_contact && wl < sizeof hist->warning)
            snprintf(hist->warning + wl, sizeof hist->warning - wl,
                     "Still in contact at end_time: rebound velocity is not final. ");
    }
    out->wall_seconds = wall_now() - wall0;

done:
    for (int k = 0; k < 12; k++)
        free(ser.col[k]);
    free(C.pair), free(C.gpred), free(C.lambda), free(C.active), free(C.cand), free(C.A), free(C.rhs), free(C.du);
    free(S.K), free(S.invm), free(S.mass), free(S.fbuf);
    free(u), free(v), free(f), free(fext), free(dash), free(outer), free(Fstep), free(vtk_times), free(gvo);
    fem_mesh_free(&mesh);
    if (st != RF_OK && hist)
        rf_fem_history_free(hist);
    return st;
}
