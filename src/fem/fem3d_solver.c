/* fem3d_solver.c - rf_fem3d_impact: set-up, the central-difference time
 * loop, contact with friction (fem3d_contact.c), energy bookkeeping and the
 * rigid-body outputs of an oblique impact.
 *
 * Time integration (lumped mass M, stiffness K, forces f):
 *   v_{n+1/2} = v_{n-1/2} + dt M^-1 (f_n - K u_n + G^T lambda_n),  u_{n+1} = u_n + dt v_{n+1/2}.
 * Energy: with K symmetric, E_n = 1/2 v_{n+1/2}' M v_{n+1/2} + 1/2 u_n' K u_{n+1}
 * changes only by the work f_n' (u_{n+1} - u_{n-1}) / 2 of the forces applied at
 * step n.  The tangential contact work is the frictional dissipation and
 * enters the closure; the normal contact work (ideally 0) and round-off are
 * the closure error.
 * Determinism: every element writes its own 24 forces; every node then sums
 * its elements in element order; sums over nodes run serially.  The result
 * is the same bit for bit for any thread count. */
#include "rockfuzz/fem3d.h"
#include "fem3d_internal.h"
#include "fem_contact_window.h"
#include "core/util.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void rf_fem3d_options_default(rf_fem3d_options *o3)
{
    memset(o3, 0, sizeof *o3);
    o3->full_model = 0;
    o3->core_factor = 1.3;
    o3->elongation = 1.0;
    o3->layer_aspect = 1.6;
    o3->boulder_inner = 4.0;
}

void rf_fem3d_report_free(rf_fem3d_report *rep)
{
    if (!rep)
        return;
    free(rep->friction_series);
    rep->friction_series = NULL;
    rep->n = 0;
}

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* What the 3D model can do beyond the ranges every impact model shares
 * (rf_impact_input_validate) and the option rules (rf_fem_options_validate). */
static rf_status check_input(const rf_impact_input *in, const rf_fem_options *o, const rf_fem3d_options *o3,
                             rf_error *err)
{
#define BAD(cond, ...)                                                                                             \
    do {                                                                                                           \
        if (cond)                                                                                                  \
            return rf_fail(err, RF_EINVAL, __VA_ARGS__);                                                           \
    } while (0)
    BAD(!in, "fem3d: NULL input");
    if (rf_impact_input_validate(in, err) != RF_OK)
        return rf_error_prefix(err, "fem3d");
    rf_status st = rf_fem_options_validate(o, 1, err);
    if (st != RF_OK)
        return st;
    BAD(!(in->slope_angle <= 80 * RF_PI / 180), "fem3d: slope_angle must be in [0, 80] degrees, got %g rad",
        in->slope_angle);
    BAD(!(in->friction <= 5), "fem3d: friction must be in [0, 5], got %g", in->friction);
    BAD(in->horizontal_axis > 0 && in->slope_angle != 0,
        "fem3d: a spheroid on an inclined slope is not supported (its contact point is not a pole); got "
        "horizontal_axis = %g m, slope_angle = %g rad",
        in->horizontal_axis, in->slope_angle);
    if (in->horizontal_axis > 0) {
        double c = in->horizontal_axis, d = rf_impact_vertical_semi_axis(in);
        BAD(c / d > 3 || d / c > 3, "fem3d: spheroid aspect c/d = %g outside [1/3, 3] is not supported", c / d);
    }
    BAD(!(o3->core_factor >= 1 && o3->core_factor <= 4), "fem3d: core_factor must be in [1, 4], got %g",
        o3->core_factor);
    BAD(!(o3->elongation >= 0 && o3->elongation <= 4), "fem3d: elongation must be in [0, 4], got %g", o3->elongation);
    BAD(!(o3->layer_aspect >= 0.5 && o3->layer_aspect <= 4), "fem3d: layer_aspect must be in [0.5, 4], got %g",
        o3->layer_aspect);
    BAD(!(o3->boulder_inner >= 2.5 && o3->boulder_inner <= 20), "fem3d: boulder_inner must be in [2.5, 20], got %g",
        o3->boulder_inner);
    return RF_OK;
#undef BAD
}

/* Growable time series. */
#define NCOL 13
typedef struct {
    size_t n, cap;
    double *col[NCOL];
} series;

static int series_push(series *s, const double v[NCOL])
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 1024;
        for (int k = 0; k < NCOL; k++) {
            double *p = realloc(s->col[k], cap * sizeof *p);
            if (!p)
                return -1;
            s->col[k] = p;
        }
        s->cap = cap;
    }
    for (int k = 0; k < NCOL; k++)
        s->col[k][s->n] = v[k];
    s->n++;
    return 0;
}

typedef struct {
    long nn, ne, ndof, nbn;
    const f3_mesh *mesh;
    float *K;       /* 576 per element (single precision: the kernel is memory-bound; exactly symmetric) */
    double *fe;     /* 24 per element */
    long *inc_ptr;  /* node -> (element * 8 + local) list, in element order */
    long *inc;
    const double *mass; /* per dof */
    double Mb, c0[3]; /* boulder mass (model) and reference CM */
    int full;
    double R[9], c[3]; /* boulder rotation and CM of the last internal_force call */
    double p, q;       /* atan2 arguments of the rotation angle */
    double *fel;       /* boulder element forces in the boulder frame, 3 per node */
    int threads;
} f3_system;

/* Boulder CM c and rotation angle theta about y (the axis normal to the plane of motion; the
   motion is planar by symmetry): theta = atan2(A_xz - A_zx, A_xx + A_zz) with
   A = sum m (x - c)(X - c0)^T, the rotation that best fits the displaced nodes. */
static void boulder_frame(f3_system *S, const double *u)
{
    const double *X = S->mesh->x;
    double c[3] = {0, 0, 0}, A[9] = {0};
    for (long i = 0; i < S->nbn; i++)
        for (int q = 0; q < 3; q++)
            c[q] += S->mass[3 * i] * (X[3 * i + q] + u[3 * i + q]);
    for (int q = 0; q < 3; q++)
        c[q] /= S->Mb;
    if (!S->full)
        c[1] = 0;
    for (long i = 0; i < S->nbn; i++) {
        double m = S->mass[3 * i];
        for (int a = 0; a < 3; a += 2)
            for (int b = 0; b < 3; b += 2)
                A[3 * a + b] += m * (X[3 * i + a] + u[3 * i + a] - c[a]) * (X[3 * i + b] - S->c0[b]);
    }
    S->p = A[2] - A[6], S->q = A[0] + A[8];
    double th = atan2(S->p, S->q), ct = cos(th), st = sin(th);
    const double R[9] = {ct, 0, st, 0, 1, 0, -st, 0, ct};
    memcpy(S->R, R, sizeof R);
    memcpy(S->c, c, sizeof c);
}

/* fe = K_e u_e.  K is stored in single precision (7 digits, far below the discretisation error;
   it halves the memory traffic that bounds this loop) and is symmetric: fe = sum_j K[j][.] u_j runs over contiguous rows as a
   vectorisable axpy.  On x86-64 a wider-vector clone is picked once per process (the same one for
   every thread, so the thread count never changes a result). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("default", "arch=x86-64-v3")))
#endif
static void element_force(const float *restrict k, const double *restrict uel, double *restrict fe)
{
    double acc[24] = {0};
    for (int j = 0; j < 24; j++) {
        const float *kj = k + 24 * j;
        const double uj = uel[j];
        for (int i = 0; i < 24; i++)
            acc[i] += (double)kj[i] * uj;
    }
    memcpy(fe, acc, sizeof acc);
}

/* f = K u for the slope; for the boulder f = dE/dx with E = 1/2 u_el' K u_el,
   u_el = R^T (x - c) - (X - c0): R K u_el plus the term through theta(x), which makes the force
   the exact gradient (co-rotational: a finite rigid rotation of the boulder costs no strain
   energy, whereas with linear small strain a spinning sphere inflates by r theta^2 / 2 and
   pushes on the slope).  Element forces, then a node-ordered gather (no races, the same sums for
   any thread count); the one torque sum runs serially. */
static void internal_force(f3_system *S, const double *u, double *f)
{
    const int *conn = S->mesh->conn;
    const double *X = S->mesh->x;
    const long ne = S->ne, nn = S->nn, nbn = S->nbn;
    boulder_frame(S, u);
    const double *R = S->R, *c = S->c, *c0 = S->c0;
#ifdef _OPENMP
#pragma omp parallel num_threads(S->threads)
#endif
    {
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
        for (long e = 0; e < ne; e++) {
            const int *cn = conn + 8 * e;
            double uel[24];
            if (e < S->mesh->boulder_elems) { /* elastic part in the boulder's frame */
                for (int a = 0; a < 8; a++) {
                    const long i = cn[a];
                    const double r[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1],
                                         X[3 * i + 2] + u[3 * i + 2] - c[2]};
                    for (int q = 0; q < 3; q++)
                        uel[3 * a + q] = R[q] * r[0] + R[3 + q] * r[1] + R[6 + q] * r[2] - (X[3 * i + q] - c0[q]);
                }
            } else {
                for (int a = 0; a < 8; a++) {
                    uel[3 * a] = u[3 * cn[a]];
                    uel[3 * a + 1] = u[3 * cn[a] + 1];
                    uel[3 * a + 2] = u[3 * cn[a] + 2];
                }
            }
            element_force(S->K + 576 * e, uel, S->fe + 24 * e);
        }
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
        for (long n = 0; n < nn; n++) {
            double fx = 0, fy = 0, fz = 0;
            for (long p = S->inc_ptr[n]; p < S->inc_ptr[n + 1]; p++) {
                const double *fp = S->fe + 24 * (S->inc[p] >> 3) + 3 * (S->inc[p] & 7);
                fx += fp[0], fy += fp[1], fz += fp[2];
            }
            if (n < nbn) {
                S->fel[3 * n] = fx, S->fel[3 * n + 1] = fy, S->fel[3 * n + 2] = fz;
                f[3 * n] = R[0] * fx + R[1] * fy + R[2] * fz;
                f[3 * n + 1] = R[3] * fx + R[4] * fy + R[5] * fz;
                f[3 * n + 2] = R[6] * fx + R[7] * fy + R[8] * fz;
            } else
                f[3 * n] = fx, f[3 * n + 1] = fy, f[3 * n + 2] = fz;
        }
    }
    /* dE/dtheta = -(sum r x f_el)_y, r = X - c0 + u_el; dtheta/dx_i from atan2(p, q) */
    double T = 0;
    for (long i = 0; i < nbn; i++) {
        const double *fe = S->fel + 3 * i;
        /* r = R^T (x - c) = X - c0 + u_el */
        const double d[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1],
                             X[3 * i + 2] + u[3 * i + 2] - c[2]};
        const double rx = R[0] * d[0] + R[3] * d[1] + R[6] * d[2], rz = R[2] * d[0] + R[5] * d[1] + R[8] * d[2];
        T += rz * fe[0] - rx * fe[2];
    }
    const double dEdth = -T, pq = S->p * S->p + S->q * S->q;
    for (long i = 0; i < nbn; i++) {
        double m = S->mass[3 * i], dx = X[3 * i] - c0[0], dz = X[3 * i + 2] - c0[2];
        f[3 * i] += dEdth * m * (S->q * dz - S->p * dx) / pq;
        f[3 * i + 2] += dEdth * m * (-S->q * dx - S->p * dz) / pq;
    }
}

/* Strain energy of the boulder, 1/2 f_el(n)' u_el(n+1) with u_el(n+1) in the frame of step n
   (the shadow energy 1/2 u_n' K u_{n+1} of the linear case when the rotation is constant). */
static double boulder_strain(const f3_system *S, const double *u)
{
    const double *X = S->mesh->x, *R = S->R, *c0 = S->c0;
    double c[3] = {0, 0, 0};
    for (long i = 0; i < S->nbn; i++)
        for (int q = 0; q < 3; q++)
            c[q] += S->mass[3 * i] * (X[3 * i + q] + u[3 * i + q]);
    for (int q = 0; q < 3; q++)
        c[q] /= S->Mb;
    if (!S->full)
        c[1] = 0;
    double e = 0;
    for (long i = 0; i < S->nbn; i++) {
        double r[3] = {X[3 * i] + u[3 * i] - c[0], X[3 * i + 1] + u[3 * i + 1] - c[1], X[3 * i + 2] + u[3 * i + 2] - c[2]};
        for (int a = 0; a < 3; a++)
            e += S->fel[3 * i + a] * (R[a] * r[0] + R[3 + a] * r[1] + R[6 + a] * r[2] - (X[3 * i + a] - c0[a]));
    }
    return 0.5 * e;
}

static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

rf_status rf_fem3d_impact(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                          rf_fem_history *hist, rf_error *err)
{
    return rf_fem3d_impact_ex(in, opt, NULL, out, hist, NULL, err);
}

rf_status rf_fem3d_impact_ex(const rf_impact_input *in, const rf_fem_options *opt, const rf_fem3d_options *o3p,
                             rf_impact_output *out, rf_fem_history *hist, rf_fem3d_report *rep, rf_error *err)
{
    const double wall0 = wall_now();
    rf_fem_options o;
    rf_fem3d_options o3;
    if (opt)
        o = *opt;
    else
        rf_fem_options_default(&o);
    if (o3p)
        o3 = *o3p;
    else
        rf_fem3d_options_default(&o3);
    if (!out)
        return rf_fail(err, RF_EINVAL, "fem3d: NULL output");
    rf_status st = check_input(in, &o, &o3, err);
    if (st != RF_OK)
        return st;
    if (hist)
        memset(hist, 0, sizeof *hist);
    if (rep)
        memset(rep, 0, sizeof *rep);

    o.refinement = rf_fem_refinement(&o, 1);
    o.domain_factor = rf_fem_domain_factor(&o, in);
    /* geometry and Hertz reference with the normal velocity component */
    rf_hertz_reference H;
    rf_impact_hertz_reference(in, &H);
    const double V = in->velocity, Vn = H.normal_velocity, Vt = H.tangential_velocity;
    const double c = H.c, d = H.d, mass = H.mass, a_h = H.contact_radius, t_h = H.duration;
    const double L = o.domain_factor * in->radius;
    const f3_material mat[2] = {{in->boulder_density, in->boulder_E, in->boulder_poisson},
                                {in->slope_density, in->slope_E, in->slope_poisson}};
    double cp[2], cs[2];
    for (int b = 0; b < 2; b++) {
        double lam = mat[b].E * mat[b].nu / ((1 + mat[b].nu) * (1 - 2 * mat[b].nu));
        double mu = mat[b].E / (2 * (1 + mat[b].nu));
        cp[b] = sqrt((lam + 2 * mu) / mat[b].rho);
        cs[b] = sqrt(mu / mat[b].rho);
    }

    /* fine boxes: uniform cubes over core_factor * a, elongated down-slope by the patch travel */
    const double h = a_h / o.refinement, hb = h * o.boulder_mesh_ratio, travel = o3.elongation * Vt * t_h;
    f3_mesh_spec ms;
    memset(&ms, 0, sizeof ms);
    ms.full = o3.full_model != 0;
    int n_s = (int)ceil(o3.core_factor * a_h / h - 1e-9), n_b = (int)ceil(o3.core_factor * a_h / hb - 1e-9);
    ms.slope = (f3_box){n_s, n_s + (int)ceil(travel / h - 1e-9), n_s, n_s, h};
    /* the boulder's half-space image is scaled by c (x, y) and d (z) afterwards */
    const double sxy = c / in->radius, sz = d / in->radius;
    double hb0 = hb / sxy;
    ms.boulder = (f3_box){n_b, n_b + (int)ceil(travel / hb - 1e-9), n_b, n_b, hb0};
    ms.radius = in->radius;
    ms.scale_xy = sxy, ms.scale_z = sz;
    ms.boulder_inner = o3.boulder_inner;
    ms.domain = L;
    ms.layer_aspect = o3.layer_aspect;
    double box_b = (ms.boulder.nxp + ms.boulder.nxm) * hb0;
    if (box_b > 0.6 * in->radius)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: the fine zone (%.3g m) does not fit the boulder (r0 = %g m): the Hertz contact radius "
                       "%.3g m is too large; lower core_factor or the impact speed",
                       box_b, in->radius, a_h);
    if ((ms.slope.nxm + ms.slope.nxp) * h * 4 > L)
        return rf_fail(err, RF_EINVAL, "fem3d: domain radius %g m is too small for the fine zone", L);

    f3_mesh mesh;
    st = f3_mesh_build(&ms, &mesh, o.max_elements, err);
    if (st != RF_OK)
        return st;

    const long nn = mesh.n_nodes, ne = mesh.n_elems, ndof = 3 * nn, nbn = mesh.boulder_nodes;
    int nthreads = o.threads > 0 ? o.threads : 1;
#ifndef _OPENMP
    nthreads = 1;
#endif
    f3_system S = {0};
    f3_contact C = {0};
    series ser = {0};
    double *u = NULL, *v = NULL, *f = NULL, *fext = NULL, *mass_d = NULL, *invm = NULL, *dash = NULL;
    double *elm = NULL, *lamx = NULL, *Fstep = NULL;
    unsigned char *fixed = NULL;
    int *outer = NULL;
    long nouter = 0;
    S.nn = nn, S.ne = ne, S.ndof = ndof, S.nbn = nbn, S.mesh = &mesh, S.threads = nthreads, S.full = ms.full;
    S.fel = malloc((size_t)3 * nbn * sizeof *S.fel);
    S.K = malloc((size_t)ne * 576 * sizeof *S.K);
    S.fe = malloc((size_t)ne * 24 * sizeof *S.fe);
    S.inc_ptr = calloc((size_t)nn + 1, sizeof *S.inc_ptr);
    S.inc = malloc((size_t)ne * 8 * sizeof *S.inc);
    u = calloc((size_t)ndof, sizeof *u);
    v = calloc((size_t)ndof, sizeof *v);
    f = calloc((size_t)ndof, sizeof *f);
    fext = calloc((size_t)ndof, sizeof *fext);
    mass_d = calloc((size_t)ndof, sizeof *mass_d);
    invm = calloc((size_t)ndof, sizeof *invm);
    dash = calloc((size_t)nn, sizeof *dash);
    elm = malloc((size_t)ne * 8 * sizeof *elm);
    lamx = malloc((size_t)ne * sizeof *lamx);
    fixed = calloc((size_t)ndof, 1);
    outer = malloc((size_t)nn * sizeof *outer);
    if (!S.K || !S.fe || !S.fel || !S.inc_ptr || !S.inc || !u || !v || !f || !fext || !mass_d || !invm || !dash || !elm ||
        !lamx || !fixed || !outer) {
        st = rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", ne);
        goto done;
    }
    /* incidence lists in element order */
    for (long e = 0; e < ne; e++)
        for (int a = 0; a < 8; a++)
            S.inc_ptr[mesh.conn[8 * e + a] + 1]++;
    for (long n = 0; n < nn; n++)
        S.inc_ptr[n + 1] += S.inc_ptr[n];
    {
        long *fill = malloc((size_t)nn * sizeof *fill);
        if (!fill) {
            st = rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
            goto done;
        }
        memcpy(fill, S.inc_ptr, (size_t)nn * sizeof *fill);
        for (long e = 0; e < ne; e++)
            for (int a = 0; a < 8; a++)
                S.inc[fill[mesh.conn[8 * e + a]]++] = e * 8 + a;
        free(fill);
    }
    /* constraints: symmetry plane u_y = 0; fixed outer surface */
    const int fixed_outer = o.boundary == RF_FEM_BOUNDARY_FIXED;
    for (long i = 0; i < nn; i++) {
        if (mesh.flags[i] & F3_SYM)
            fixed[3 * i + 1] = 1;
        if (i >= nbn && (mesh.flags[i] & F3_OUTER)) {
            outer[nouter++] = (int)i;
            if (fixed_outer)
                fixed[3 * i] = fixed[3 * i + 1] = fixed[3 * i + 2] = 1;
        }
    }
    /* element matrices (independent per element) */
    int bad_elem = 0;
    double *vols = lamx; /* reuse: volume first, eigenvalue bound later */
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(nthreads) reduction(| : bad_elem)
#endif
    for (long e = 0; e < ne; e++) {
        double xe[24];
        const int *cn = mesh.conn + 8 * e;
        for (int a = 0; a < 8; a++)
            for (int q = 0; q < 3; q++)
                xe[3 * a + q] = mesh.x[3 * cn[a] + q];
        int b = e < mesh.boulder_elems ? F3_BOULDER : F3_SLOPE;
        double Kd[576];
        f3_hex_matrices(xe, &mat[b], Kd, elm + 8 * e, &vols[e]);
        for (int q = 0; q < 576; q++)
            S.K[576 * e + q] = (float)Kd[q];
        for (int a = 0; a < 8; a++)
            if (!(elm[8 * e + a] > 0))
                bad_elem |= 1;
    }
    if (bad_elem) {
        st = rf_fail(err, RF_EINTERNAL, "fem3d mesh: an element has a non-positive nodal mass (distorted hexahedron)");
        goto done;
    }
    /* the boulder mesh is a polyhedron inside the spheroid: scale its density so that the rigid-body
       mass is exact (stiffness untouched) */
    double mesh_mass_b = 0;
    for (long e = 0; e < mesh.boulder_elems; e++)
        for (int a = 0; a < 8; a++)
            mesh_mass_b += elm[8 * e + a];
    const double sym_factor = ms.full ? 1.0 : 2.0;
    const double mscale = mass / sym_factor / mesh_mass_b;
    for (long e = 0; e < mesh.boulder_elems * 8; e++)
        elm[e] *= mscale;
    for (long n = 0; n < nn; n++) {
        double m = 0;
        for (long p = S.inc_ptr[n]; p < S.inc_ptr[n + 1]; p++)
            m += elm[S.inc[p]];
        mass_d[3 * n] = mass_d[3 * n + 1] = mass_d[3 * n + 2] = m;
    }
    for (long dd = 0; dd < ndof; dd++)
        invm[dd] = fixed[dd] ? 0 : 1 / mass_d[dd];
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(nthreads)
#endif
    for (long e = 0; e < ne; e++) {
        unsigned char fr[24];
        const int *cn = mesh.conn + 8 * e;
        for (int a = 0; a < 8; a++)
            for (int q = 0; q < 3; q++)
                fr[3 * a + q] = !fixed[3 * cn[a] + q];
        double Kd[576];
        for (int q = 0; q < 576; q++)
            Kd[q] = S.K[576 * e + q];
        lamx[e] = f3_hex_lambda_max(Kd, elm + 8 * e, fr);
    }
    double lam_max = 0, dt_edge = DBL_MAX;
    for (long e = 0; e < ne; e++) {
        if (lamx[e] > lam_max)
            lam_max = lamx[e];
        const int *cn = mesh.conn + 8 * e;
        static const int ed[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                      {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
        int b = e < mesh.boulder_elems ? 0 : 1;
        for (int k = 0; k < 12; k++) {
            const double *p = mesh.x + 3 * cn[ed[k][0]], *q = mesh.x + 3 * cn[ed[k][1]];
            double l = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
            if (l / cp[b] < dt_edge)
                dt_edge = l / cp[b];
        }
    }
    const double dt_bound = 2 / sqrt(lam_max), dt = o.dt_safety * dt_bound;

    /* dashpots on the outer surface (Lysmer & Kuhlemeyer 1969): tributary areas */
    if (!fixed_outer)
        for (long q = 0; q < mesh.n_outer_quads; q++) {
            const int *qn = mesh.outer_quads + 4 * q;
            const double *p0 = mesh.x + 3 * qn[0], *p1 = mesh.x + 3 * qn[1], *p2 = mesh.x + 3 * qn[2],
                         *p3 = mesh.x + 3 * qn[3];
            double d1[3], d2[3], cr[3];
            for (int a = 0; a < 3; a++)
                d1[a] = p2[a] - p0[a], d2[a] = p3[a] - p1[a];
            cr[0] = d1[1] * d2[2] - d1[2] * d2[1];
            cr[1] = d1[2] * d2[0] - d1[0] * d2[2];
            cr[2] = d1[0] * d2[1] - d1[1] * d2[0];
            double area = 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
            for (int a = 0; a < 4; a++)
                dash[qn[a]] += 0.25 * area;
        }

    /* contact: slaves are the boulder's fine-box face nodes */
    C.nslave = (long)mesh.nxt_b * mesh.nyt_b;
    C.slave = malloc((size_t)C.nslave * sizeof *C.slave);
    C.lam = calloc((size_t)C.nslave * 3, sizeof *C.lam);
    C.mnode = malloc((size_t)C.nslave * 4 * sizeof *C.mnode);
    C.N = malloc((size_t)C.nslave * 4 * sizeof *C.N);
    C.S = calloc((size_t)C.nslave * 2, sizeof *C.S);
    C.gap = malloc((size_t)C.nslave * sizeof *C.gap);
    C.ds = malloc((size_t)C.nslave * 2 * sizeof *C.ds);
    C.s0 = malloc((size_t)C.nslave * 2 * sizeof *C.s0);
    C.A = malloc((size_t)C.nslave * 3 * sizeof *C.A);
    C.gvo = malloc((size_t)C.nslave * 3 * sizeof *C.gvo);
    C.outside = calloc((size_t)C.nslave, 1);
    C.cand = malloc((size_t)C.nslave * sizeof *C.cand);
    C.du = calloc((size_t)ndof, sizeof *C.du);
    if (!C.slave || !C.lam || !C.mnode || !C.N || !C.S || !C.gap || !C.ds || !C.s0 || !C.A || !C.gvo || !C.outside ||
        !C.cand || !C.du) {
        st = rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
        goto done;
    }
    memcpy(C.slave, mesh.top_b, (size_t)C.nslave * sizeof *C.slave);
    C.friction = in->friction;
    C.tol = 1e-9 * h;
    C.band = 0.5 * fmin(h, hb) + 2 * V * dt;
    C.max_sweeps = 2000;

    /* initial state: boulder translating at (V sin alpha, 0, -V cos alpha) in the slope frame */
    for (long i = 0; i < nbn; i++)
        v[3 * i] = Vt, v[3 * i + 2] = -Vn;
    double Mb = 0;
    for (long i = 0; i < nbn; i++)
        Mb += mass_d[3 * i];
    const double ke0 = 0.5 * Mb * V * V; /* of the model (half of the boulder in the half model) */
    S.mass = mass_d, S.Mb = Mb;
    for (long i = 0; i < nbn; i++)
        for (int q = 0; q < 3; q++)
            S.c0[q] += mass_d[3 * i] * mesh.x[3 * i + q] / Mb;
    if (!ms.full)
        S.c0[1] = 0;

    const double t_min = o.end_time > 0 ? o.end_time : 1.3 * t_h;
    const double t_max = o.end_time > 0 ? o.end_time : 3.0 * t_h;
    long steps_est = (long)ceil(t_min / dt);
    int stride = o.history_stride > 0 ? o.history_stride : (int)(steps_est / 5000 + 1);
    long fcap = steps_est + 16;
    Fstep = malloc((size_t)fcap * sizeof *Fstep);
    if (!Fstep) {
        st = rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
        goto done;
    }

    double W_n = 0, W_fric = 0, W_abs = 0, closure_max = 0, comp_max = 0, F_max = 0, a_at_Fmax = 0;
    double pen_max = 0, slip_max = 0, pgs_res_max = 0, t_last_contact = 0;
    long stick_steps = 0, pair_steps = 0;
    int episodes = 0, in_contact = 0, pgs_sweeps_max = 0, outside_contact = 0;
    long n = 0;
    for (;; n++) {
        const double t = n * dt;
        internal_force(&S, u, f);
        /* dashpot forces from v_{n-1/2}: normal rho c_p v_n, shear rho c_s v_s, radial normal */
        double W_abs_inc = 0;
        if (!fixed_outer)
            for (long k = 0; k < nouter; k++) {
                int i = outer[k];
                const double *x = mesh.x + 3 * i;
                double rr = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
                double nv[3] = {x[0] / rr, x[1] / rr, x[2] / rr};
                double vn = v[3 * i] * nv[0] + v[3 * i + 1] * nv[1] + v[3 * i + 2] * nv[2];
                for (int q = 0; q < 3; q++)
                    fext[3 * i + q] =
                        -dash[i] * mat[1].rho * (cp[1] * vn * nv[q] + cs[1] * (v[3 * i + q] - vn * nv[q]));
                for (int q = 0; q < 3; q++)
                    if (fixed[3 * i + q])
                        fext[3 * i + q] = 0;
                for (int q = 0; q < 3; q++)
                    W_abs_inc -= 0.5 * dt * fext[3 * i + q] * v[3 * i + q];
            }
        /* pairing at step n, G v_{n-1/2} for the contact work */
        f3_contact_locate(&C, &mesh, u, v, nthreads, 1);
        /* predictor */
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(nthreads)
#endif
        for (long dd = 0; dd < ndof; dd++) {
            v[dd] += dt * invm[dd] * (fext[dd] - f[dd]);
            u[dd] += dt * v[dd];
        }
        if (!fixed_outer)
            for (long k = 0; k < nouter; k++) {
                int i = outer[k];
                for (int q = 0; q < 3; q++)
                    W_abs_inc -= 0.5 * dt * fext[3 * i + q] * v[3 * i + q];
            }
        /* contact multipliers for the predicted state */
        f3_contact_predict(&C, &mesh, u, invm, dt, nthreads);
        st = f3_contact_solve(&C, invm, dt, u, v, err);
        if (st != RF_OK)
            goto done;
        if (C.sweeps > pgs_sweeps_max)
            pgs_sweeps_max = C.sweeps;
        if (C.residual > pgs_res_max)
            pgs_res_max = C.residual;
        /* contact force, work, radius (force-weighted second moment: <rho^2> = 0.4 a^2 for Hertz) */
        double Fc = 0, sx = 0, sy = 0, sxx = 0;
        for (long q = 0; q < C.ncand; q++) {
            long k = C.cand[q];
            const double *lam = C.lam + 3 * k;
            if (lam[0] <= 0)
                continue;
            int s = C.slave[k];
            double gvn[3];
            f3_contact_gv(&C, k, v, gvn);
            W_n += lam[0] * dt * (gvn[0] + C.gvo[3 * k]) / 2;
            W_fric -= (lam[1] * (gvn[1] + C.gvo[3 * k + 1]) + lam[2] * (gvn[2] + C.gvo[3 * k + 2])) * dt / 2;
            double slip = hypot(gvn[1], gvn[2]) * dt;
            if (slip > slip_max)
                slip_max = slip;
            pair_steps++;
            if (hypot(lam[1], lam[2]) < (1 - 1e-9) * C.friction * lam[0])
                stick_steps++;
            if (C.outside[k])
                outside_contact = 1;
            double X = mesh.x[3 * s] + u[3 * s], Y = mesh.x[3 * s + 1] + u[3 * s + 1];
            Fc += lam[0];
            sx += lam[0] * X;
            sy += lam[0] * Y;
            sxx += lam[0] * (X * X + Y * Y);
        }
        double rad = 0;
        if (Fc > 0) {
            double mx = sx / Fc, my = ms.full ? sy / Fc : 0;
            double var = sxx / Fc - mx * mx - my * my;
            rad = sqrt(fmax(0, 2.5 * var));
        }
        for (long q = 0; q < C.ncand; q++) { /* penetration after the correction */
            long k = C.cand[q];
            int s = C.slave[k];
            double g = mesh.x[3 * s + 2] + u[3 * s + 2];
            for (int a = 0; a < 4; a++)
                g -= C.N[4 * k + a] * u[3 * C.mnode[4 * k + a] + 2];
            if (-g > pen_max)
                pen_max = -g;
        }
        W_abs += W_abs_inc;
        if (rf_fem_force_record_(&Fstep, &fcap, n, Fc)) {
            st = rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
            goto done;
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
        for (long dd = 0; dd < 3 * nbn; dd++)
            ke[0] += mass_d[dd] * v[dd] * v[dd];
        se[0] = 2 * boulder_strain(&S, u);
        for (long dd = 2; dd < 3 * nbn; dd += 3) {
            pz += mass_d[dd] * v[dd];
            uz += mass_d[dd] * u[dd];
        }
        for (long dd = 3 * nbn; dd < ndof; dd++) {
            ke[1] += mass_d[dd] * v[dd] * v[dd];
            se[1] += f[dd] * u[dd];
        }
        ke[0] *= 0.5, ke[1] *= 0.5, se[0] *= 0.5, se[1] *= 0.5;
        const double comp = -uz / Mb;
        if (comp > comp_max)
            comp_max = comp;
        const double closure = ke[0] + ke[1] + se[0] + se[1] + W_abs + W_fric - ke0;
        if (!isfinite(closure) || fabs(closure) > 10 * ke0) {
            st = rf_fail(err, RF_EMODEL,
                         "fem3d: the solution diverged at t = %.4g s (energy %.3g x KE0); time step %.3g s is unstable",
                         t, closure / ke0, dt);
            goto done;
        }
        if (fabs(closure) > closure_max)
            closure_max = fabs(closure);
        if ((hist || rep) && n % stride == 0) {
            double sf = sym_factor;
            double row[NCOL] = {t,         Fc * sf,     comp,       rad,        ke[0] * sf, se[0] * sf, ke[1] * sf,
                                se[1] * sf, W_n * sf,   W_abs * sf, closure * sf, pz / Mb,   W_fric * sf};
            if (series_push(&ser, row) != 0) {
                st = rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
                goto done;
            }
        }
        const double tn = (n + 1) * dt;
        if (tn >= t_max)
            break;
        if (o.end_time > 0) {
            if (tn >= o.end_time)
                break;
        } else if (tn >= t_min && !in_contact && tn - t_last_contact > 0.1 * t_h)
            break;
    }
    const long nsteps = n + 1;

    /* contact duration: first to last nonzero multiplier, ends interpolated as in fem_solver.c */
    double t0, t1;
    rf_fem_contact_window_(Fstep, nsteps, dt, o.duration_threshold * F_max, &t0, &t1);

    /* rigid-body state of the boulder: CM velocity, angular momentum about the CM with the lumped
       inertia tensor (current positions) */
    double P[3] = {0, 0, 0}, X[3] = {0, 0, 0};
    for (long i = 0; i < nbn; i++)
        for (int q = 0; q < 3; q++) {
            P[q] += mass_d[3 * i] * v[3 * i + q];
            X[q] += mass_d[3 * i] * (mesh.x[3 * i + q] + u[3 * i + q]);
        }
    for (int q = 0; q < 3; q++)
        P[q] /= Mb, X[q] /= Mb;
    double Lm[3] = {0, 0, 0}, I[3][3] = {{0}};
    for (long i = 0; i < nbn; i++) {
        double m = mass_d[3 * i], r[3], w[3];
        for (int q = 0; q < 3; q++)
            r[q] = mesh.x[3 * i + q] + u[3 * i + q] - X[q], w[q] = v[3 * i + q];
        Lm[0] += m * (r[1] * w[2] - r[2] * w[1]);
        Lm[1] += m * (r[2] * w[0] - r[0] * w[2]);
        Lm[2] += m * (r[0] * w[1] - r[1] * w[0]);
        double rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                I[a][b] += m * ((a == b ? rr : 0) - r[a] * r[b]);
    }
    double omega[3] = {0, 0, 0};
    if (ms.full) { /* solve I omega = H (Cramer) */
        double det = I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[2][1]) - I[0][1] * (I[1][0] * I[2][2] - I[1][2] * I[2][0]) +
                     I[0][2] * (I[1][0] * I[2][1] - I[1][1] * I[2][0]);
        for (int col = 0; col < 3; col++) {
            double M3[3][3];
            memcpy(M3, I, sizeof M3);
            for (int a = 0; a < 3; a++)
                M3[a][col] = Lm[a];
            omega[col] = (M3[0][0] * (M3[1][1] * M3[2][2] - M3[1][2] * M3[2][1]) -
                          M3[0][1] * (M3[1][0] * M3[2][2] - M3[1][2] * M3[2][0]) +
                          M3[0][2] * (M3[1][0] * M3[2][1] - M3[1][1] * M3[2][0])) /
                         det;
        }
    } else { /* mirror symmetry: only the y component survives in the full body */
        omega[1] = Lm[1] / I[1][1];
        P[1] = 0;
    }
    const double Iyy = I[1][1];
    const double vn_after = P[2], vt_after = P[0], w_after = omega[1];
    const double K_after = 0.5 * Mb * (vn_after * vn_after + vt_after * vt_after) + 0.5 * Iyy * w_after * w_after;
    memset(out, 0, sizeof *out);
    out->contact_force_max = F_max * sym_factor;
    out->compression_max = comp_max;
    out->contact_duration = t1 - t0;
    out->contact_radius = a_at_Fmax;
    out->v_n_before = -Vn;
    out->v_t_before = Vt;
    out->v_n_after = vn_after;
    out->v_t_after = vt_after;
    out->omega_after = w_after;
    out->R_n = vn_after / Vn;
    out->R_t = Vt > 0 ? vt_after / Vt : NAN;
    out->R_ke = K_after / ke0;
    out->energy_error = closure_max / ke0;
    out->nodes = (double)nn;
    out->elements = (double)ne;
    out->steps = (double)nsteps;

    if (hist || rep) {
        internal_force(&S, u, f);
    }
    if (hist) {
        double seb = 0, ses = 0, eks = 0, ekb = 0;
        for (long dd = 0; dd < 3 * nbn; dd++)
            ekb += 0.5 * mass_d[dd] * v[dd] * v[dd];
        seb = boulder_strain(&S, u);
        for (long dd = 3 * nbn; dd < ndof; dd++)
            ses += 0.5 * f[dd] * u[dd], eks += 0.5 * mass_d[dd] * v[dd] * v[dd];
        hist->n = ser.n;
        double **dst[12] = {&hist->t,           &hist->contact_force,  &hist->compression, &hist->contact_radius,
                            &hist->kinetic_boulder, &hist->strain_boulder, &hist->kinetic_slope, &hist->strain_slope,
                            &hist->contact_work, &hist->absorbed,      &hist->closure,     &hist->boulder_velocity};
        for (int k = 0; k < 12; k++)
            *dst[k] = ser.col[k], ser.col[k] = NULL;
        hist->dt = dt;
        hist->dt_bound = dt_bound;
        hist->dt_edge = dt_edge;
        hist->h_contact = h;
        hist->hertz_radius = a_h;
        hist->hertz_duration = t_h;
        hist->boulder_mass = mass;
        hist->boulder_mesh_mass = mesh_mass_b * sym_factor;
        hist->penetration_max = pen_max;
        hist->slip_max = slip_max;
        hist->reflection_time = 2 * L / cp[1];
        hist->vibration_energy = (ekb + seb - K_after) * sym_factor;
        hist->slope_energy = (eks + ses) * sym_factor;
        hist->ke0 = ke0 * sym_factor;
        hist->boulder_nodes = mesh.boulder_nodes;
        hist->boulder_elements = mesh.boulder_elems;
        hist->slope_nodes = nn - mesh.boulder_nodes;
        hist->slope_elements = ne - mesh.boulder_elems;
        size_t wl = 0;
        hist->warning[0] = 0;
        if (fixed_outer && 2 * L / cp[1] < t_h)
            wl += (size_t)snprintf(hist->warning + wl, sizeof hist->warning - wl,
                                   "P waves reflected by the fixed boundary return after 2L/c_p = %.3g ms, before the "
                                   "Hertz contact ends (%.3g ms): R_n includes reflected energy; use absorbing "
                                   "boundaries or domain_factor >= %.0f. ",
                                   2e3 * L / cp[1], 1e3 * t_h, ceil(cp[1] * t_h / 2 / in->radius));
        if (episodes > 1 && wl < sizeof hist->warning)
            wl += (size_t)snprintf(hist->warning + wl, sizeof hist->warning - wl,
                                   "Contact closed %d times (re-contact after separation). ", episodes);
        if (outside_contact && wl < sizeof hist->warning)
            wl += (size_t)snprintf(hist->warning + wl, sizeof hist->warning - wl,
                                   "Contact reached the edge of the fine zone: raise core_factor. ");
        if (o.end_time > 0 && in_contact && wl < sizeof hist->warning)
            snprintf(hist->warning + wl, sizeof hist->warning - wl,
                     "Still in contact at end_time: rebound velocity is not final. ");
    }
    if (rep) {
        rep->friction_work = W_fric * sym_factor;
        rep->normal_work = W_n * sym_factor;
        rep->slip_max = slip_max;
        rep->contact_point_velocity = vt_after - w_after * d;
        rep->inertia_lumped = Iyy * sym_factor;
        rep->inertia_exact = mass * (c * c + d * d) / 5;
        rep->v_y_after = P[1];
        rep->stick_fraction = pair_steps ? (double)stick_steps / (double)pair_steps : 0;
        rep->pgs_sweeps_max = pgs_sweeps_max;
        rep->pgs_residual_max = pgs_res_max;
        uint64_t hh = 1469598103934665603ULL;
        hh = fnv1a(hh, u, (size_t)ndof * sizeof *u);
        hh = fnv1a(hh, v, (size_t)ndof * sizeof *v);
        rep->state_hash = hh;
        rep->n = ser.n;
        rep->friction_series = ser.col[12];
        ser.col[12] = NULL;
    }
    out->wall_seconds = wall_now() - wall0;

done:
    for (int k = 0; k < NCOL; k++)
        free(ser.col[k]);
    free(C.slave), free(C.lam), free(C.mnode), free(C.N), free(C.S), free(C.gap), free(C.ds), free(C.s0), free(C.A);
    free(C.gvo), free(C.outside), free(C.cand), free(C.du);
    free(S.K), free(S.fe), free(S.fel), free(S.inc_ptr), free(S.inc);
    free(u), free(v), free(f), free(fext), free(mass_d), free(invm), free(dash), free(elm), free(lamx);
    free(fixed), free(outer), free(Fstep);
    f3_mesh_free(&mesh);
    if (st != RF_OK && hist)
        rf_fem_history_free(hist);
    if (st != RF_OK && rep)
        rf_fem3d_report_free(rep);
    return st;
}
