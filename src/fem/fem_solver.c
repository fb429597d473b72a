/* fem_solver.c - rf_fem_impact: the axisymmetric impact run, as the stages of
 * fem_core.h applied to this geometry: check, sizing and meshing
 * (fem_mesh.c), assembly of masses, constraints, dashpots and the material
 * kernels (fem_kernel.h), the time step, the time loop (internal force ->
 * dashpots -> predictor -> contact (fem_contact.c) -> energy account -> stop
 * test), and the output extraction.
 *
 * Time integration (lumped mass M, internal force f_int, external forces f):
 *   v_{n+1/2} = v_{n-1/2} + dt M^-1 (f_n - f_int(u_n) + G^T lambda_n),  u_{n+1} = u_n + dt v_{n+1/2}.
 * Energy: with K symmetric, E_n = 1/2 v_{n+1/2}' M v_{n+1/2} + 1/2 u_n' K u_{n+1}
 * changes only by the work f' (u_{n+1} - u_{n-1}) / 2 of the forces f
 * applied at step n (contact, dashpots), so the closure error measures the
 * contact scheme (its small inelastic node collisions) and round-off only.
 * With a plastic body the strain energy is replaced by the internal work
 * W_n = sum_k f_int(u_k)' (u_{k+1} - u_{k-1}) / 2, accumulated per step as
 * dt/2 f_int(u_n)' (v_{n-1/2} + v_{n+1/2}); for a linear material it equals
 * 1/2 u_n' K u_{n+1} exactly (the sum telescopes), so the closure means the
 * same; the plastic dissipation (integrated by the kernels from the return
 * maps) is the part of W that is not stored elastically.
 * Determinism: each element writes its own forces, each node sums its
 * elements in element order: the same bits for any thread count. */
#include "rockfuzz/fem.h"
#include "fem_ale.h"
#include "fem_core.h"
#include "fem_driver.h"
#include "fem_internal.h"
#include "fem_kernel.h"
#include "quad4_kernel.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

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

/* Buffers of the axisymmetric solver in the workspace pool. */
enum { P_K, P_FE, P_INC_PTR, P_INC, P_INVM, P_MASS, P_U, P_V, P_F, P_FEXT, P_DASH, P_OUTER, P_ELM, P_FIXED, P_VTK,
       P_EMAT, P_USE2, P_DTE, P_PACK0, P_PACK1, P_FGRAV, P_MSHIFT, P_ALE };

/* The state of one axisymmetric run. */
typedef struct {
    const rf_impact_input *in;
    rf_fem_options o;
    rf_fem_tuning t;      /* o.tuning's values, or the defaults */
    rf_hertz_reference H;
    fem_material mat[3];  /* boulder, slope (bedrock), layer */
    rf_wave_speeds w[3];
    unsigned char *emat;  /* material of each element: 0 boulder, 1 slope, 2 layer */
    int layer;            /* a layer of thickness in->layer_thickness over the slope */
    double V, L, h, hb;
    double fine_r;        /* the slope's uniform fine zone reaches r = fine_r [m] */
    fem_mesh mesh;
    int have_mesh;
    long nn, ndof, ne, nbd;
    int threads, fixed_outer;
    fem_kernel kernel[2]; /* boulder and slope blocks */
    fem_lame lame[2];     /* parameters of the point laws */
    rf_material matl[3];  /* constitutive law of each body (plastic[b] != 0: not elastic) */
    int plastic[3], work_account; /* work_account: energy from the internal work (a plastic body) */
    int rigid;            /* a rigid boulder: no internal force, one vertical velocity */
    int large;            /* updated Lagrangian kernels and contact on the current surfaces */
    double *dte;          /* large deformation: each element's step bound 2/sqrt(lambda_e) per unit of
                             its size L_e = area / longest diagonal (0: not checked) */
    long unstable;        /* large deformation: an element whose current step bound fell below dt (-1: none) */
    double W_int[2];      /* internal work of each body so far [J] */
    double pen_max;       /* deepest position of the boulder's lowest point below z = 0 [m] */
    double *K, *fe, *invm, *mass, *u, *v, *f, *fext, *dash;
    long *inc_ptr, *inc;
    int *outer;
    long nouter;
    double dt, dt_bound, dt_edge, mesh_mass_b, Mb, ke0, W_abs;
    double *mshift;       /* per node: mass added by the contact face's redistribution [kg] (or NULL) */
    long shifted_elems;   /* contact-face elements whose masses were redistributed */
    /* gravity (docs/validation-plastic.md "Gravity"): g > 0 gives the body load fgrav
       (the boulder's lumped weight, the slope's geostatic internal force at u = 0),
       its work W_grav, the elastic energy E0 of the geostatic stress and the
       count of points whose geostatic state the law does not admit */
    double g, *fgrav, W_grav, E0;
    long geo_outside;
    int no_contact;       /* fem_axi_slope_at_rest: the slope alone (no contact step) */
    fem_contact C;
    /* ALE rezoning of the slope (fem_ale.h; large deformation, option ale) */
    int ale_on;
    fem_ale ale;
    fem_ale_account ale_acc;
    double *ale_delta;
    fem_pool *pool;
} axi_run;

/* Sizing and meshing: the fine zone from the Hertz contact radius, graded
 * elements out to the domain radius. */
static rf_status axi_mesh(axi_run *S, rf_error *err)
{
    const rf_fem_options *o = &S->o;
    const rf_hertz_reference *H = &S->H;
    S->h = H->contact_radius / o->refinement, S->hb = S->h * S->t.boulder_mesh_ratio;
    const double h = S->h, hb = S->hb;
    /* the uniform fine zone must stay well inside the boulder: shrink it at
       very high speed (a/R > 0.24 with the default 2.5 a) down to 1.5 a */
    double core = fmin(S->t.fine_zone_factor, 0.55 * fmin(H->c, H->d) / H->contact_radius);
    if (core < 1.5)
        return rf_fail(err, RF_EINVAL,
                       "fem: the Hertz contact radius a = %.4g m is too large for the boulder (c = %g m, d = %g m): "
                       "a fine zone of 1.5 a must fit in 0.55 min(c, d); Hertz-based meshing needs a << min(c, d)",
                       H->contact_radius, H->c, H->d);
    fem_body_spec bs = {0}, ss = {0};
    ss.h = h;
    ss.n = 3 * (int)ceil(core * o->refinement / 3 - 1e-9);
    while (ss.n > 3 && ss.n * h > 0.6 * fmin(H->c, H->d))
        ss.n -= 3;
    ss.grading = S->t.grading;
    const double c_r = S->layer ? fmin(S->w[1].rayleigh, S->w[2].rayleigh) : S->w[1].rayleigh;
    ss.h_far = fmax(h, fmin(c_r * H->duration / 12, S->L / 8));
    ss.extent = S->L;
    bs.h = hb;
    bs.n = 3 * (int)ceil(core * o->refinement / S->t.boulder_mesh_ratio / 3 - 1e-9);
    while (bs.n > 3 && bs.n * hb > 0.6 * fmin(H->c, H->d))
        bs.n -= 3;
    bs.grading = S->t.grading;
    bs.h_far = fmax(hb, fmin(H->c, H->d) / 10);
    bs.extent = H->c;
    bs.height = H->d;
    if (bs.n * bs.h > 0.7 * fmin(H->c, H->d))
        return rf_fail(err, RF_EINVAL,
                       "fem: the Hertz contact radius %.4g m is too large for the boulder (c = %g m, d = %g m): the "
                       "fine zone does not fit; lower the impact speed or raise refinement",
                       H->contact_radius, H->c, H->d);
    if (ss.n * ss.h * 4 > S->L)
        return rf_fail(err, RF_EINVAL, "fem: domain radius %g m is too small for the fine zone (%g m)", S->L,
                       ss.n * ss.h);
    S->fine_r = ss.n * ss.h;
    rf_status st = fem_mesh_build(&bs, &ss, &S->mesh, S->t.max_elements, err);
    S->have_mesh = st == RF_OK;
    return st;
}

/* The run's arrays, from the workspace pool (zeroed where the run expects it). */
static rf_status axi_alloc(axi_run *S, rf_error *err)
{
    fem_pool *P = S->pool;
    const size_t nd = (size_t)S->ndof, ne = (size_t)S->ne, nn = (size_t)S->nn;
    S->K = fem_pool_get(P, P_K, ne * 64 * sizeof(double), 0);
    S->fe = fem_pool_get(P, P_FE, ne * 8 * sizeof(double), 0);
    S->inc_ptr = fem_pool_get(P, P_INC_PTR, (nn + 1) * sizeof(long), 1);
    S->inc = fem_pool_get(P, P_INC, ne * 4 * sizeof(long), 0);
    S->invm = fem_pool_get(P, P_INVM, nd * sizeof(double), 1);
    S->mass = fem_pool_get(P, P_MASS, nd * sizeof(double), 1);
    S->u = fem_pool_get(P, P_U, nd * sizeof(double), 1);
    S->v = fem_pool_get(P, P_V, nd * sizeof(double), 1);
    S->f = fem_pool_get(P, P_F, nd * sizeof(double), 1);
    S->fext = fem_pool_get(P, P_FEXT, nd * sizeof(double), 1);
    S->dash = fem_pool_get(P, P_DASH, nd * sizeof(double), 1);
    S->outer = fem_pool_get(P, P_OUTER, nn * sizeof(int), 0);
    if (!S->K || !S->fe || !S->inc_ptr || !S->inc || !S->invm || !S->mass || !S->u || !S->v || !S->f || !S->fext ||
        !S->dash || !S->outer)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld elements", S->ne);
    return RF_OK;
}

/* Node -> (element * 4 + local node) lists in element order: the assembly
 * then sums each node's element forces in the same order for any thread count. */
static void axi_incidence(axi_run *S)
{
    const int *conn = S->mesh.conn;
    for (long e = 0; e < S->ne; e++)
        for (int a = 0; a < 4; a++)
            S->inc_ptr[conn[4 * e + a] + 1]++;
    for (long n = 0; n < S->nn; n++)
        S->inc_ptr[n + 1] += S->inc_ptr[n];
    for (long e = 0; e < S->ne; e++) /* fill in element order, then restore the pointers */
        for (int a = 0; a < 4; a++)
            S->inc[S->inc_ptr[conn[4 * e + a]]++] = e * 4 + a;
    for (long n = S->nn; n > 0; n--)
        S->inc_ptr[n] = S->inc_ptr[n - 1];
    S->inc_ptr[0] = 0;
}

/* Element matrices and lumped masses; returns the time-step eigenvalue bound
 * inputs.  The boulder mesh is a polygon inside the spheroid: its density is
 * scaled so that the rigid-body mass is exact (stiffness untouched). */
static rf_status axi_elements(axi_run *S, double *elm, rf_error *err)
{
    const fem_mesh *mesh = &S->mesh;
    S->dt_edge = DBL_MAX, S->mesh_mass_b = 0;
    for (long e = 0; e < S->ne; e++) {
        const int *c = mesh->conn + 4 * e;
        double r[4], z[4], mass, area;
        for (int a = 0; a < 4; a++)
            r[a] = mesh->r[c[a]], z[a] = mesh->z[c[a]];
        const int b = mesh->ebody[e], mb = S->emat[e];
        fem_element_matrices(r, z, &S->mat[mb], S->K + 64 * e, elm + 4 * e, &mass, &area);
        if (!(area > 0))
            return rf_fail(err, RF_EINTERNAL, "fem mesh: element %ld has non-positive area", e);
        if (b == FEM_BOULDER)
            S->mesh_mass_b += mass;
        for (int a = 0; a < 4; a++) {
            double ed = hypot(r[(a + 1) % 4] - r[a], z[(a + 1) % 4] - z[a]);
            if (ed > 1e-12 * S->h && ed / S->w[mb].p < S->dt_edge)
                S->dt_edge = ed / S->w[mb].p;
        }
    }
    const double mscale = S->H.mass / S->mesh_mass_b;
    for (long e = 0; e < mesh->boulder_elems; e++)
        for (int a = 0; a < 4; a++)
            elm[4 * e + a] *= mscale;
    return RF_OK;
}

/* Large deformation: the central-difference step must stay below every
 * element's bound as the elements are compressed; the bound is scaled with
 * the element's current size.  Returns the first element that violates it, -1 if none. */
static long axi_step_violation(const axi_run *S)
{
    for (long e = 0; e < S->ne; e++)
        if (S->dte[e] > 0 && S->dt > S->dte[e] * fem_ale_element_size(&S->mesh, e, S->u))
            return e;
    return -1;
}

/* Element e's largest eigenvalue of M_e^-1 K_e (a collapsed quad's repeated node with its masses merged). */
static double axi_element_lambda(const axi_run *S, const double *elm, const unsigned char *fixed, long e)
{
    const int *c = S->mesh.conn + 4 * e;
    int freed[8];
    double me[4];
    for (int a = 0; a < 4; a++) {
        freed[2 * a] = !fixed[2 * c[a]];
        freed[2 * a + 1] = !fixed[2 * c[a] + 1];
        me[a] = 0;
        for (int b = 0; b < 4; b++)
            if (c[b] == c[a])
                me[a] += elm[4 * e + b];
    }
    return fem_element_lambda_max(S->K + 64 * e, me, freed);
}

/* The mass redistribution at the slope's contact face (docs/validation-plastic.md 9e; the 3D form
 * is fem3d_mass.c), for soil (a layer, an elasto-plastic slope): a slope quad with an edge on the
 * contact face (the slope's surface nodes the contact can reach: the fine zone, out to the
 * boulder's radius) whose eigenvalue lambda_e is below kappa lambda_max keeps alpha =
 * max(FEM_MASS_KEPT_MIN, lambda_e / (kappa lambda_max)) of the face nodes' element masses and
 * gives the rest to the node below each (its neighbour off the face along the quad's other edge);
 * its eigenvalue stays below lambda_e / alpha <= kappa lambda_max, so the step is unchanged.
 * Returns the number of elements changed. */
static long axi_surface_mass_shift(axi_run *S, double *elm, const unsigned char *fixed, double lam_max)
{
    const fem_mesh *mesh = &S->mesh;
    unsigned char *face = calloc((size_t)S->nn, 1);
    if (!face)
        return 0; /* without memory the masses stay lumped as they are */
    const double reach = fmax(S->fine_r, S->H.c); /* soil is penetrated out to the boulder's radius */
    for (long k = 0; k < mesh->n_ssurf; k++) {
        const int i = mesh->ssurf[k];
        face[i] = !(mesh->flags[i] & FEM_OUTER) && mesh->r[i] <= reach * (1 + 1e-9);
    }
    long n = 0;
    for (long e = mesh->boulder_elems; e < S->ne; e++) {
        const int *c = mesh->conn + 4 * e;
        int top[4], nt = 0, distinct = 1;
        for (int a = 0; a < 4; a++) {
            nt += top[a] = face[c[a]];
            for (int b = 0; b < a; b++)
                distinct &= c[b] != c[a];
        }
        if (nt != 2 || !distinct || (top[0] && top[2]) || (top[1] && top[3]))
            continue; /* not one edge on the face, or a collapsed quad */
        const double alpha = fem_mass_kept(axi_element_lambda(S, elm, fixed, e), S->t.surface_mass_kappa, lam_max);
        if (!(alpha > 0) || alpha >= 1)
            continue;
        for (int a = 0; a < 4; a++)
            if (top[a]) {
                const int below = top[(a + 1) % 4] ? (a + 3) % 4 : (a + 1) % 4;
                elm[4 * e + below] += (1 - alpha) * elm[4 * e + a];
                elm[4 * e + a] *= alpha;
            }
        if (S->dte)
            S->dte[e] = 2 / sqrt(axi_element_lambda(S, elm, fixed, e)) / fem_ale_element_size(mesh, e, NULL);
        n++;
    }
    free(face);
    return n;
}

/* Nodal masses from the element-node masses, and their inverses. */
static void axi_nodal_masses(axi_run *S, const double *elm, const unsigned char *fixed)
{
    memset(S->mass, 0, (size_t)S->ndof * sizeof *S->mass);
    for (long e = 0; e < S->ne; e++)
        for (int a = 0; a < 4; a++) {
            const int c = S->mesh.conn[4 * e + a];
            S->mass[2 * c] += elm[4 * e + a], S->mass[2 * c + 1] += elm[4 * e + a];
        }
    for (long d = 0; d < S->ndof; d++)
        S->invm[d] = fixed[d] ? 0 : 1 / S->mass[d];
}

/* Constraints (u_r = 0 on the axis; the outer surface if fixed), nodal
 * masses, the largest element eigenvalue, the time step. */
static void axi_masses(axi_run *S, double *elm, unsigned char *fixed)
{
    const fem_mesh *mesh = &S->mesh;
    for (long i = 0; i < S->nn; i++) {
        if (mesh->flags[i] & FEM_AXIS)
            fixed[2 * i] = 1;
        if (i >= mesh->boulder_nodes && (mesh->flags[i] & FEM_OUTER) && S->fixed_outer)
            fixed[2 * i] = fixed[2 * i + 1] = 1;
    }
    axi_nodal_masses(S, elm, fixed);
    double lam_max = 0;
    for (long e = 0; e < S->ne; e++) {
        if (S->rigid && e < mesh->boulder_elems)
            continue; /* a rigid boulder has no stiffness: the slope sets the step */
        const double lm = axi_element_lambda(S, elm, fixed, e);
        if (S->dte)
            S->dte[e] = 2 / sqrt(lm) / fem_ale_element_size(mesh, e, NULL);
        if (lm > lam_max)
            lam_max = lm;
    }
    if (S->t.surface_mass_kappa > 0 && (S->layer || S->plastic[1]) && /* soil only: section 9e */
        (S->mshift = fem_pool_get(S->pool, P_MSHIFT, (size_t)S->nn * sizeof(double), 1)) &&
        (S->shifted_elems = axi_surface_mass_shift(S, elm, fixed, lam_max)) > 0) {
        for (long i = 0; i < S->nn; i++)
            S->mshift[i] = -S->mass[2 * i];
        axi_nodal_masses(S, elm, fixed);
        for (long i = 0; i < S->nn; i++)
            S->mshift[i] += S->mass[2 * i];
    }
    S->dt = fem_time_step(lam_max, S->t.dt_safety, &S->dt_bound);
}

/* Dashpots on the outer surface (Lysmer & Kuhlemeyer 1969): each outer face
 * gives its two nodes their tributary shares of rho c_p A and rho c_s A with
 * the impedances of the element that owns the face (a layer's face its own,
 * not the bedrock's); normal in the even, tangential in the odd entries of dash. */
static void axi_dashpots(axi_run *S)
{
    const fem_mesh *mesh = &S->mesh;
    S->nouter = 0;
    if (S->fixed_outer)
        return;
    double *C = S->dash;
    for (long e = mesh->boulder_elems; e < S->ne; e++) {
        const int *c = mesh->conn + 4 * e;
        const int mb = S->emat[e];
        const double zp = S->mat[mb].rho * S->w[mb].p, zs = S->mat[mb].rho * S->w[mb].s;
        for (int a = 0; a < 4; a++) {
            int p = c[a], q = c[(a + 1) % 4];
            if (p != q && (mesh->flags[p] & FEM_OUTER) && (mesh->flags[q] & FEM_OUTER)) {
                double l = hypot(mesh->r[q] - mesh->r[p], mesh->z[q] - mesh->z[p]);
                double Ap = 2 * RF_PI * l * (mesh->r[p] / 3 + mesh->r[q] / 6);
                double Aq = 2 * RF_PI * l * (mesh->r[p] / 6 + mesh->r[q] / 3);
                C[2 * p] += Ap * zp, C[2 * p + 1] += Ap * zs;
                C[2 * q] += Aq * zp, C[2 * q + 1] += Aq * zs;
            }
        }
    }
    for (long i = mesh->boulder_nodes; i < S->nn; i++)
        if (mesh->flags[i] & FEM_OUTER)
            S->outer[S->nouter++] = (int)i;
}

/* The material kernel of each body: one block of elements per body. */
static rf_status axi_kernels(axi_run *S, rf_error *err)
{
    const long nbe = S->mesh.boulder_elems;
    const long first[2] = {0, nbe}, count[2] = {nbe, S->ne - nbe};
    for (int b = 0; b < 2; b++) {
        if (b == FEM_BOULDER && S->rigid) {
            fem_kernel_rigid(&S->kernel[b], first[b], count[b], 8);
            continue;
        }
        if (S->plastic[b] || (b == FEM_SLOPE && S->layer)) { /* return maps at the points, B-bar */
            fem_point_law law = fem_point_law_material(&S->matl[b]), law2 = fem_point_law_material(&S->matl[2]);
            const unsigned char *use2 = NULL;
            unsigned char *flags = NULL;
            if (b == FEM_SLOPE && S->layer) { /* layer elements take the layer's law */
                flags = fem_pool_get(S->pool, P_USE2, (size_t)count[b] + 1, 0);
                if (!flags)
                    return rf_fail(err, RF_ENOMEM, "fem: out of memory");
                for (long e = 0; e < count[b]; e++)
                    flags[e] = S->emat[first[b] + e] == 2;
                use2 = flags;
            }
            rf_status st = fem_kernel_points_axi_two(&S->kernel[b], first[b], count[b], S->mesh.r, S->mesh.z,
                                                     S->mesh.conn, &law, &law2, use2, 1, err);
            if (st == RF_OK && S->large)
                st = fem_kernel_points_axi_large(&S->kernel[b], S->mesh.r, S->mesh.z, S->mesh.conn, err);
            if (st != RF_OK)
                return st;
            continue;
        }
        if (S->t.kernel[b] == RF_FEM_KERNEL_STIFFNESS && !S->large) { /* packed if it pays (the same bits), else per element */
            double *pk = NULL;
            if (quad4_packed_pays(S->ne) &&
                !(pk = fem_pool_get(S->pool, P_PACK0 + b, (size_t)quad4_packed_size(count[b]) * sizeof *pk, 0)))
                return rf_fail(err, RF_ENOMEM, "fem: out of memory");
            if (!pk || fem_kernel_linear_axi_packed(&S->kernel[b], first[b], count[b], S->K + 64 * first[b], pk) != 0)
                fem_kernel_linear_axi(&S->kernel[b], first[b], count[b], S->K + 64 * first[b], 1);
            continue;
        }
        const double E = S->mat[b].E, nu = S->mat[b].nu;
        S->lame[b] = (fem_lame){E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))};
        fem_point_law law = fem_point_law_linear(&S->lame[b]);
        rf_status st = fem_kernel_points_axi(&S->kernel[b], first[b], count[b], S->mesh.r, S->mesh.z, S->mesh.conn,
                                             &law, err);
        if (st == RF_OK && S->large) /* a linear (hypoelastic) law on the current geometry */
            st = fem_kernel_points_axi_large(&S->kernel[b], S->mesh.r, S->mesh.z, S->mesh.conn, err);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

static rf_status axi_gravity(axi_run *S, rf_error *err);

/* Assembly: arrays, incidence, element matrices, masses and time step,
 * material kernels (linear elastic, one block per body), dashpots, contact
 * pairs, and the initial state (boulder translating down at V). */
static rf_status axi_assemble(axi_run *S, rf_error *err)
{
    S->nn = S->mesh.n_nodes, S->ndof = 2 * S->nn, S->ne = S->mesh.n_elems, S->nbd = 2 * S->mesh.boulder_nodes;
    rf_status st = axi_alloc(S, err);
    if (st != RF_OK)
        return st;
    axi_incidence(S);
    double *elm = fem_pool_get(S->pool, P_ELM, (size_t)S->ne * 4 * sizeof(double), 0);
    unsigned char *fixed = fem_pool_get(S->pool, P_FIXED, (size_t)S->ndof, 1);
    if (!elm || !fixed)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    if (!(S->emat = fem_pool_get(S->pool, P_EMAT, (size_t)S->ne, 0)))
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    long nlayer = 0;
    for (long e = 0; e < S->ne; e++) { /* the layer: slope elements whose centre lies above -thickness */
        const int *c = S->mesh.conn + 4 * e;
        const double zc = 0.25 * (S->mesh.z[c[0]] + S->mesh.z[c[1]] + S->mesh.z[c[2]] + S->mesh.z[c[3]]);
        S->emat[e] = S->mesh.ebody[e] == FEM_BOULDER ? 0 : S->layer && zc > -S->in->layer_thickness ? 2 : 1;
        nlayer += S->emat[e] == 2;
    }
    if (S->layer && nlayer == 0)
        return rf_fail(err, RF_EINVAL,
                       "fem: layer_thickness = %g m is thinner than half an element at the contact (h = %g m): "
                       "raise refinement or the thickness", S->in->layer_thickness, S->h);
    st = axi_elements(S, elm, err);
    if (st != RF_OK)
        return st;
    if (S->large && !(S->dte = fem_pool_get(S->pool, P_DTE, (size_t)S->ne * sizeof(double), 1)))
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    axi_masses(S, elm, fixed);
    if ((st = axi_kernels(S, err)) != RF_OK)
        return st;
    axi_dashpots(S);
    st = fem_contact_setup(&S->C, &S->mesh, S->ndof, S->H.d, err);
    if (st == RF_OK && S->large)
        st = fem_contact_large(&S->C, &S->mesh, S->ndof, err);
    if (st != RF_OK)
        return st;
    if (S->t.contact_single_pivot)
        S->C.block_rounds = 0;
    if (S->in->friction > 0 && (st = fem_contact_friction_setup(&S->C, S->ndof, S->in->friction, err)) != RF_OK)
        return st;
    S->C.tol = 1e-9 * S->h;
    S->C.band = 0.5 * fmin(S->h, S->hb) + 2 * S->V * S->dt;
    for (long i = 0; i < S->mesh.boulder_nodes; i++)
        S->v[2 * i + 1] = -S->V;
    double Mb = 0, Ms = 0;
    for (long i = 0; i < S->nn; i++)
        *(i < S->mesh.boulder_nodes ? &Mb : &Ms) += S->mass[2 * i + 1];
    S->Mb = Mb;
    S->ke0 = 0.5 * Mb * S->V * S->V;
    if (S->rigid)
        S->C.rigid_invm = 1 / Mb, S->C.rigid_dofs = S->nbd;
    if (S->ale_on) {
        const fem_ale_params ap = {S->t.ale_trigger, fmin(0.5 * (1 + S->t.ale_trigger), 0.95), S->t.ale_sweeps};
        if (!(S->ale_delta = fem_pool_get(S->pool, P_ALE, (size_t)S->ndof * sizeof(double), 1)))
            return rf_fail(err, RF_ENOMEM, "fem: out of memory");
        if ((st = fem_ale_setup(&S->ale, &S->mesh, S->mesh.boulder_elems, S->ne, S->emat, S->invm, &ap, err)) != RF_OK)
            return st;
    }
    return S->g > 0 ? axi_gravity(S, err) : RF_OK;
}

static void axi_internal_force(const axi_run *S, const double *u, double *f);

/* Gravity g along -z (docs/validation-plastic.md "Gravity").  The boulder
 * falls freely at the start (no stress): its load is the lumped weight
 * m_a g of every node (its sum the exact weight M g).  The slope is at rest
 * under its own weight: an integration-point kernel gets the geostatic
 * stress at its points, and the slope's body load is the internal force of
 * that stress at u = 0, computed by the same kernel, so that the slope
 * starts in equilibrium to the last bit (the load the discrete stress
 * balances: m_a g at the nodes to the discretisation error, plus the
 * geostatic traction that the removed far field exerts on a free outer
 * surface).  A precomputed-stiffness slope (linear, small strain) needs
 * neither: its response to gravity superposes and cancels exactly. */
static rf_status axi_gravity(axi_run *S, rf_error *err)
{
    if (!(S->fgrav = fem_pool_get(S->pool, P_FGRAV, (size_t)S->ndof * sizeof(double), 1)))
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    rf_material_params p[2];
    rf_impact_material_params(S->in, 1, &p[0]);
    rf_impact_material_params(S->in, S->layer ? 2 : 1, &p[1]);
    const fem_geostatic geo = {S->g, S->layer ? S->in->layer_thickness : 0, S->mat[2].rho, S->mat[1].rho,
                               {fem_geostatic_k0(&p[0]), fem_geostatic_k0(&p[1])},
                               {S->plastic[1] ? &S->matl[1] : NULL, S->plastic[2] ? &S->matl[2] : NULL}, 0};
    fem_kernel *k = &S->kernel[FEM_SLOPE];
    S->geo_outside = fem_kernel_points_axi_geostatic(k, S->mesh.r, S->mesh.z, S->mesh.conn, &geo);
    if (S->geo_outside >= 0) {
        S->E0 = fmax(fem_kernel_elastic_energy(k), 0);
        axi_internal_force(S, S->u, S->fgrav); /* u = 0 */
        for (int b = 0; b < 2; b++)
            if (S->kernel[b].ops->commit)
                S->kernel[b].ops->commit(&S->kernel[b]);
    } else
        S->geo_outside = 0;
    for (long i = 0; i < S->mesh.boulder_nodes; i++)
        S->fgrav[2 * i] = 0, S->fgrav[2 * i + 1] = -S->mass[2 * i + 1] * S->g;
    return RF_OK;
}

/* Element forces of elements [e0, e1) through the block's kernel, in
 * chunks: into S->fe (f == NULL), or added to f node by node in element
 * order (one thread: the same sums as the node-ordered gather, without the
 * extra pass). */
static void block_forces(const axi_run *S, const fem_kernel *k, const double *u, long e0, long e1, double *f)
{
    const int *conn = S->mesh.conn;
    double ue[FEM_KERNEL_CHUNK * 8], fe[FEM_KERNEL_CHUNK * 8];
    for (long c0 = e0; c0 < e1; c0 += FEM_KERNEL_CHUNK) {
        long c1 = c0 + FEM_KERNEL_CHUNK < e1 ? c0 + FEM_KERNEL_CHUNK : e1;
        for (long e = c0; e < c1; e++) {
            const int *c = conn + 4 * e;
            double *x = ue + 8 * (e - c0);
            for (int a = 0; a < 4; a++)
                x[2 * a] = u[2 * c[a]], x[2 * a + 1] = u[2 * c[a] + 1];
        }
        if (!f) {
            k->ops->forces(k, c0, c1, ue, S->fe + 8 * c0);
            continue;
        }
        k->ops->forces(k, c0, c1, ue, fe);
        for (long e = c0; e < c1; e++) {
            const int *c = conn + 4 * e;
            const double *y = fe + 8 * (e - c0);
            for (int a = 0; a < 4; a++)
                f[2 * c[a]] += y[2 * a], f[2 * c[a] + 1] += y[2 * a + 1];
        }
    }
}

/* Node n's force: its elements' forces summed in element order. */
static inline void gather_node(const axi_run *S, long n, double *f)
{
    double fr = 0, fz = 0;
    for (long p = S->inc_ptr[n]; p < S->inc_ptr[n + 1]; p++) {
        const double *fp = S->fe + 8 * (S->inc[p] >> 2) + 2 * (S->inc[p] & 3);
        fr += fp[0], fz += fp[1];
    }
    f[2 * n] = fr, f[2 * n + 1] = fz;
}

/* f = f_int(u): element forces by the material kernels, then a node-ordered
 * gather (the same sums for any thread count). */
static void axi_internal_force(const axi_run *S, const double *u, double *f)
{
    if (S->threads <= 1) { /* no parallel region, direct assembly */
        memset(f, 0, (size_t)S->ndof * sizeof *f);
        for (int b = 0; b < 2; b++) {
            const fem_kernel *k = &S->kernel[b];
            if (k->ops->assemble)
                k->ops->assemble(k, k->first, k->first + k->count, S->mesh.conn, u, f);
            else
                block_forces(S, k, u, k->first, k->first + k->count, f);
        }
        return;
    }
#ifdef _OPENMP
#pragma omp parallel num_threads(S->threads)
    {
        int tid = omp_get_thread_num(), T = omp_get_num_threads();
        for (int b = 0; b < 2; b++) {
            const fem_kernel *k = &S->kernel[b];
            long n = k->count, a0 = k->first + n * tid / T, a1 = k->first + n * (tid + 1) / T;
            block_forces(S, k, u, a0, a1, NULL);
        }
#pragma omp barrier
#pragma omp for schedule(static)
        for (long n = 0; n < S->nn; n++)
            gather_node(S, n, f);
    }
#endif
}

/* Dashpot forces into fext, semi-implicit: the force -C v_{n+1/2} with the
 * velocity the node reaches under it and the internal force, from the lumped
 * mass m: (m + dt C) v_{n+1/2} = m v_{n-1/2} - dt f_int, solved in the
 * normal and tangential directions (C = C_p n n' + C_s (1 - n n')).  Stable
 * for any dt C / m (the explicit form, -C v_{n-1/2}, needs dt C / m < 2,
 * which a light layer's outer nodes exceed); the predictor then gives the
 * node that velocity.  An axis node (u_r = 0) solves for v_z alone.  Returns
 * half of their work with v_{n-1/2}. */
static inline double other_force(const axi_run *S, long d)
{
    return S->fgrav ? S->fgrav[d] - S->f[d] : -S->f[d];
}

static double axi_dashpot_forces(axi_run *S)
{
    double W = 0;
    const double dt = S->dt;
    for (long k = 0; k < S->nouter; k++) {
        int i = S->outer[k];
        double nr = S->mesh.r[i] / S->L, nz = S->mesh.z[i] / S->L, len = hypot(nr, nz);
        nr /= len, nz /= len;
        const double m = S->mass[2 * i + 1], Cp = S->dash[2 * i], Cs = S->dash[2 * i + 1];
        const double vr = S->v[2 * i], vz = S->v[2 * i + 1];
        double fr, fz;
        if (S->invm[2 * i] == 0) { /* on the axis: v_r = 0 */
            const double Czz = Cp * nz * nz + Cs * nr * nr;
            const double wz = fem_dashpot_velocity(m, Czz, vz, other_force(S, 2 * i + 1), dt);
            fr = -(Cp - Cs) * nr * nz * wz, fz = -Czz * wz;
        } else {
            const double gr = other_force(S, 2 * i), gz = other_force(S, 2 * i + 1);
            const double vn = vr * nr + vz * nz, vt = -vr * nz + vz * nr;
            const double gn = gr * nr + gz * nz, gt = -gr * nz + gz * nr;
            const double wn = fem_dashpot_velocity(m, Cp, vn, gn, dt), wt = fem_dashpot_velocity(m, Cs, vt, gt, dt);
            fr = -(Cp * wn * nr - Cs * wt * nz), fz = -(Cp * wn * nz + Cs * wt * nr);
        }
        S->fext[2 * i] = fr, S->fext[2 * i + 1] = fz;
    }
    for (long k = 0; k < S->nouter; k++) {
        int i = S->outer[k];
        W -= 0.5 * S->dt * (S->fext[2 * i] * S->v[2 * i] + S->fext[2 * i + 1] * S->v[2 * i + 1]);
    }
    return W;
}

/* f_int' v of each body (boulder dofs first). */
static void axi_power(const axi_run *S, double fv[2])
{
    for (long d = 0; d < S->nbd; d++)
        fv[0] += S->f[d] * S->v[d];
    for (long d = S->nbd; d < S->ndof; d++)
        fv[1] += S->f[d] * S->v[d];
}

/* fgrav' v: the power of gravity. */
static double axi_gravity_power(const axi_run *S)
{
    double p = 0;
    for (long d = 0; d < S->ndof; d++)
        p += S->fgrav[d] * S->v[d];
    return p;
}

/* ALE (fem_ale.h), between the Lagrangian steps where the committed state
 * and the nodes are both at u_n: a rezone of the slope if an element has
 * become too small, then the internal force again on the new mesh (a zero
 * increment: the remapped stresses, returned to the yield surface where the
 * mix of two admissible states is not).  The elastic energy the remap
 * changes enters the internal work, so that the stored energy stays the
 * committed stresses'; the remap's energy is its own term of the closure. */
static rf_status axi_rezone(axi_run *S, rf_error *err)
{
    const double el0 = S->ale_acc.elastic;
    const long moved = fem_ale_rezone(&S->ale, &S->mesh, S->u, S->v, S->mass, S->invm, S->fgrav,
                                      &S->kernel[FEM_SLOPE], S->ale_delta, &S->ale_acc, err);
    if (moved < 0)
        return rf_error_prefix(err, "fem");
    if (moved == 0)
        return RF_OK;
    S->W_int[FEM_SLOPE] += S->ale_acc.elastic - el0;
    axi_internal_force(S, S->u, S->f);
    for (int b = 0; b < 2; b++)
        if (S->kernel[b].ops->commit)
            S->kernel[b].ops->commit(&S->kernel[b]);
    return RF_OK;
}

/* One step: internal force -> dashpots -> predictor -> contact.  Returns the
 * total contact force in *Fc and the contact radius in *rad. */
static rf_status axi_step(axi_run *S, double *Fc, double *rad, rf_error *err)
{
    const double dt = S->dt;
    double *u = S->u, *v = S->v;
    axi_internal_force(S, u, S->f);
    for (int b = 0; b < 2; b++) /* the state at u_n is accepted */
        if (S->kernel[b].ops->commit)
            S->kernel[b].ops->commit(&S->kernel[b]);
    rf_status st = S->ale_on ? axi_rezone(S, err) : RF_OK;
    if (st != RF_OK)
        return st;
    double W_abs_inc = axi_dashpot_forces(S);
    double fv[2] = {0, 0};
    if (S->work_account)
        axi_power(S, fv);
    const double gv0 = S->fgrav ? axi_gravity_power(S) : 0;
    fem_contact_begin(&S->C, v);
    if (S->fgrav)
        for (long d = 0; d < S->ndof; d++) {
            v[d] += dt * S->invm[d] * (S->fext[d] + S->fgrav[d] - S->f[d]);
            u[d] += dt * v[d];
        }
    else
        for (long d = 0; d < S->ndof; d++) {
            v[d] += dt * S->invm[d] * (S->fext[d] - S->f[d]);
            u[d] += dt * v[d];
        }
    for (long k = 0; k < S->nouter; k++) { /* the other half of the dashpot work, with v_{n+1/2} */
        int i = S->outer[k];
        W_abs_inc -= 0.5 * dt * (S->fext[2 * i] * v[2 * i] + S->fext[2 * i + 1] * v[2 * i + 1]);
    }
    if (S->large) /* the pairs on the predicted surfaces */
        fem_contact_update(&S->C, u);
    st = S->no_contact ? (*Fc = 0, RF_OK) : fem_contact_step(&S->C, S->invm, dt, u, v, Fc, err);
    if (st != RF_OK)
        return st;
    S->W_abs += W_abs_inc;
    if (S->fgrav) /* fgrav' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        S->W_grav += 0.5 * dt * (gv0 + axi_gravity_power(S));
    if (S->work_account) { /* f_int(u_n)' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        double fv1[2] = {0, 0};
        axi_power(S, fv1);
        S->W_int[0] += 0.5 * dt * (fv[0] + fv1[0]), S->W_int[1] += 0.5 * dt * (fv[1] + fv1[1]);
    }
    const long nb = S->mesh.bsurf[0]; /* the boulder's lowest point (on the axis) */
    const double pen = -(S->mesh.z[nb] + u[2 * nb + 1]);
    if (pen > S->pen_max)
        S->pen_max = pen;
    *rad = fem_contact_measure(&S->C, u);
    return RF_OK;
}

/* Plastic dissipation of body b so far [J]. */
static double axi_plastic_work(const axi_run *S, int b)
{
    fem_kernel_report r;
    fem_kernel_report_get(&S->kernel[b], &r);
    return r.plastic_work;
}

/* A body's running sums: kinetic (m v v), strain (f u), and for the boulder the z momentum and the
 * mass-weighted z displacement; each accumulates its dofs in dof order. */
typedef struct {
    double ke, se, pz, uz;
} axi_sums;

static inline void axi_sums_node(const axi_run *S, long i, int boulder, axi_sums *s)
{
    const double *u = S->u, *v = S->v, *f = S->f, *m = S->mass;
    for (long d = 2 * i; d < 2 * i + 2; d++) {
        s->ke += m[d] * v[d] * v[d];
        s->se += f[d] * u[d];
    }
    if (boulder) {
        s->pz += m[2 * i + 1] * v[2 * i + 1];
        s->uz += m[2 * i + 1] * u[2 * i + 1];
    }
}

/* The sums of both bodies, their nodes interleaved: six independent dependency chains instead of
 * two after two (the time was the latency of the additions), each in the same order as before, so
 * the same bits. */
static void axi_body_sums(const axi_run *S, axi_sums *b, axi_sums *sl)
{
    const long nb = S->nbd / 2, ns = S->nn - nb, common = nb < ns ? nb : ns;
    *b = *sl = (axi_sums){0, 0, 0, 0};
    for (long k = 0; k < common; k++) {
        axi_sums_node(S, k, 1, b);
        axi_sums_node(S, nb + k, 0, sl);
    }
    for (long k = common; k < nb; k++)
        axi_sums_node(S, k, 1, b);
    for (long k = common; k < ns; k++)
        axi_sums_node(S, nb + k, 0, sl);
}

/* Energies at t_{n+1/2} (KE with v_{n+1/2}, strain 1/2 u_n' f_int(u_n) ...
 * with u_{n+1}), the history row, the compression and the closure error. */
static void axi_energy(const axi_run *S, double t, double Fc, double rad, double row[13], double *comp,
                       double *closure)
{
    axi_sums sb, ss;
    axi_body_sums(S, &sb, &ss);
    double ke[2] = {sb.ke, ss.ke}, se[2] = {sb.se, ss.se}, pz = sb.pz, uz = sb.uz;
    ke[0] *= 0.5, ke[1] *= 0.5, se[0] *= 0.5, se[1] *= 0.5;
    if (S->work_account) /* stored elastically: the internal work less the dissipation */
        for (int b = 0; b < 2; b++)
            se[b] = S->W_int[b] - axi_plastic_work(S, b);
    *comp = -uz / S->Mb;
    *closure = ke[0] + ke[1] + se[0] + se[1] + S->W_abs - S->ke0;
    if (S->work_account)
        *closure = ke[0] + ke[1] + S->W_int[0] + S->W_int[1] + S->W_abs - S->ke0;
    if (S->fgrav) /* gravity's work: the potential energy released */
        *closure -= S->W_grav;
    *closure += S->C.W_fric; /* dissipated by friction (0 without) */
    /* ALE: the energy the remaps added (kinetic, elastic, the potential of
       the moved masses, which W_grav does not see) is its own term */
    const fem_ale_account *a = &S->ale_acc;
    *closure -= a->kinetic + a->elastic;
    const double remap = a->kinetic + a->elastic + a->potential;
    const double r[13] = {t, Fc, *comp, rad, ke[0], se[0], ke[1], se[1], S->C.work, S->W_abs, *closure, pz / S->Mb,
                          remap};
    memcpy(row, r, sizeof r);
}

/* The time loop (with VTK frames if asked); *nsteps steps made. */
/* Outputs and diagnostics of the final state. */
static void axi_extract(axi_run *S, const fem_run *R, long nsteps, rf_impact_output *out, rf_fem_history *hist)
{
    const double *u = S->u, *v = S->v, *m = S->mass;
    double pz = 0, ekb = 0, seb = 0, eks = 0, ses = 0;
    for (long d = 1; d < S->nbd; d += 2)
        pz += m[d] * v[d];
    for (long d = 0; d < S->nbd; d++)
        ekb += 0.5 * m[d] * v[d] * v[d];
    for (long d = S->nbd; d < S->ndof; d++)
        eks += 0.5 * m[d] * v[d] * v[d];
    if (S->work_account) { /* stored elastic energy: internal work less dissipation */
        seb = S->W_int[0] - axi_plastic_work(S, 0), ses = S->W_int[1] - axi_plastic_work(S, 1);
    } else {
        axi_internal_force(S, u, S->f); /* strain energy of the final state, 1/2 u' K u */
        for (long d = 0; d < S->nbd; d++)
            seb += 0.5 * S->f[d] * u[d];
        for (long d = S->nbd; d < S->ndof; d++)
            ses += 0.5 * S->f[d] * u[d];
    }
    const double V = S->V;
    double v_after = pz / S->Mb;
    if (S->g > 0) /* with gravity: the velocity at separation (0 at rest) */
        v_after = R->at_rest ? 0 : !R->in_contact && R->episodes > 0 ? R->v_sep : v_after;
    fem_run_outputs(R, nsteps, S->t.duration_threshold, S->ke0, 1.0, S->nn, S->ne, out);
    out->v_n_before = -V;
    out->v_n_after = v_after;
    out->R_n = -v_after / -V;
    out->R_t = NAN;
    out->R_ke = (v_after * v_after) / (V * V);
    fem_kernel_report rep[2];
    for (int b = 0; b < 2; b++)
        fem_kernel_report_get(&S->kernel[b], &rep[b]);
    out->plastic_work = (rep[0].plastic_work + rep[1].plastic_work) / S->ke0;
    out->equivalent_plastic_strain_max = fmax(rep[0].plastic_strain_max, rep[1].plastic_strain_max);
    out->penetration_max = S->pen_max;
    const long ns0 = S->mesh.ssurf[0]; /* the slope's first-contact point */
    out->indentation_depth = -u[2 * ns0 + 1];
    if (!hist)
        return;
    hist->dt = S->dt, hist->dt_bound = S->dt_bound, hist->dt_edge = S->dt_edge;
    hist->h_contact = S->h;
    hist->hertz_radius = S->H.contact_radius, hist->hertz_duration = S->H.duration;
    hist->boulder_mass = S->H.mass, hist->boulder_mesh_mass = S->mesh_mass_b;
    hist->penetration_max = S->C.pen_max, hist->slip_max = S->C.slip_max;
    hist->reflection_time = 2 * S->L / S->w[1].p;
    hist->vibration_energy = ekb + seb - 0.5 * pz * pz / S->Mb; /* about the final rigid motion */
    hist->slope_energy = eks + ses;
    hist->ke0 = S->ke0;
    hist->plastic_work_boulder = rep[0].plastic_work, hist->plastic_work_slope = rep[1].plastic_work;
    for (int b = 0; b < 2; b++) {
        const double Ee = S->plastic[b] || (b == FEM_SLOPE && S->plastic[2]) ? fem_kernel_elastic_energy(&S->kernel[b]) : -1;
        if (Ee >= 0) { /* less the geostatic stress's energy (0 without gravity) */
            hist->elastic_energy_stress += b == FEM_SLOPE ? Ee - S->E0 : Ee;
            hist->elastic_energy_work += S->W_int[b] - rep[b].plastic_work;
        }
    }
    const int bm = rep[1].plastic_strain_max > rep[0].plastic_strain_max ? 1 : 0;
    hist->plastic_strain_max_in = rep[bm].element_max < 0 ? 0 : 1 + bm;
    if (rep[bm].element_max >= 0) {
        const int *c = S->mesh.conn + 4 * rep[bm].element_max;
        for (int a = 0; a < 4; a++) {
            hist->plastic_strain_max_r += 0.25 * S->mesh.r[c[a]];
            hist->plastic_strain_max_z += 0.25 * S->mesh.z[c[a]];
        }
    }
    hist->gravity = S->g, hist->gravity_work = S->W_grav, hist->geostatic_outside = S->geo_outside;
    hist->at_rest = R->at_rest;
    const fem_ale_account *a = &S->ale_acc;
    hist->ale_rezones = a->rezones, hist->ale_nodes_moved = a->nodes_moved;
    hist->ale_kinetic = a->kinetic, hist->ale_elastic = a->elastic, hist->ale_potential = a->potential;
    hist->ale_move_max = a->move_max, hist->ale_ratio_min = a->ratio_min;
    hist->friction_work = S->C.W_fric, hist->friction_sweeps_max = S->C.sweeps_max;
    hist->stick_residual_max = S->C.stick_residual_max;
    hist->stick_fraction = S->C.pair_steps > 0 ? (double)S->C.stick_steps / (double)S->C.pair_steps : 0;
    hist->boulder_nodes = S->mesh.boulder_nodes, hist->boulder_elements = S->mesh.boulder_elems;
    hist->slope_nodes = S->nn - S->mesh.boulder_nodes, hist->slope_elements = S->ne - S->mesh.boulder_elems;
    hist->state_hash = fem_hash(fem_hash(FEM_HASH_SEED, u, (size_t)S->ndof * sizeof *u), v,
                                (size_t)S->ndof * sizeof *v);
    char extra[160] = "";
    if (S->geo_outside > 0)
        snprintf(extra, sizeof extra, "%ld integration points of the geostatic state lie outside the yield surface "
                 "(returned to it at the first step). ", S->geo_outside);
    fem_run_warnings(R, S->fixed_outer, S->L, S->w[1].p, S->in->radius, hist->warning, sizeof hist->warning, extra);
}

/* Check, resolve the automatic settings, take the Hertz reference. */
static rf_status axi_prepare(axi_run *S, const rf_impact_input *in, const rf_fem_options *opt, rf_error *err)
{
    S->in = in;
    if (opt)
        S->o = *opt;
    else
        rf_fem_options_default(&S->o);
    S->t = *fem_tuning_of(&S->o);
    rf_status st = check_input(in, &S->o, err);
    if (st != RF_OK)
        return st;
    S->o.refinement = rf_fem_refinement(&S->o, 0);
    S->o.domain_factor = rf_fem_domain_factor(&S->o, in);
    rf_impact_hertz_reference(in, &S->H);
    S->layer = in->layer_thickness > 0;
    if (S->layer) { /* size the mesh for the finer of the two contacts, run for the longer */
        rf_impact_input lay = *in;
        lay.slope_density = in->layer_density, lay.slope_E = in->layer_E, lay.slope_poisson = in->layer_poisson;
        rf_hertz_reference HL;
        rf_impact_hertz_reference(&lay, &HL);
        S->H.contact_radius = fmin(S->H.contact_radius, HL.contact_radius);
        S->H.duration = fmax(S->H.duration, HL.duration);
        rf_impact_wave_speeds(&lay, 1, &S->w[2]);
    }
    S->V = in->velocity, S->L = S->o.domain_factor * in->radius;
    S->mat[0] = (fem_material){in->boulder_density, in->boulder_E, in->boulder_poisson};
    S->mat[1] = (fem_material){in->slope_density, in->slope_E, in->slope_poisson};
    S->mat[2] = (fem_material){in->layer_density, in->layer_E, in->layer_poisson};
    rf_impact_wave_speeds(in, 0, &S->w[0]);
    rf_impact_wave_speeds(in, 1, &S->w[1]);
    S->threads = S->o.threads > 0 ? S->o.threads : 1;
#ifndef _OPENMP
    S->threads = 1;
#endif
    S->o.boundary = rf_fem_boundary_resolve(S->o.boundary, in);
    S->fixed_outer = S->o.boundary == RF_FEM_BOUNDARY_FIXED;
    for (int b = 0; b < 3; b++) {
        rf_material_params p;
        if (b == 2 && !S->layer) { /* no layer: its (unchecked) inputs are not used */
            S->matl[2] = S->matl[1], S->plastic[2] = 0;
            continue;
        }
        rf_impact_material_params(in, b, &p);
        if ((st = rf_material_init(&S->matl[b], &p, err)) != RF_OK) /* validated above: cannot fail */
            return rf_error_prefix(err, "fem");
        S->plastic[b] = p.model != RF_MATERIAL_ELASTIC && (b < 2 || S->layer);
    }
    S->rigid = in->boulder_material == RF_MATERIAL_RIGID_BODY;
    S->work_account = S->plastic[0] || S->plastic[1] || S->plastic[2];
    S->large = rf_fem_large_deformation(&S->o, in);
    S->g = rf_impact_gravity(in, 0);
    S->work_account |= S->large; /* the energy from the internal work: no K in updated Lagrangian */
    S->ale_on = rf_fem_ale_enabled(&S->o, in);
    return RF_OK;
}

/* The driver's stages (fem_driver.h) over an axi_run. */
static rf_status axi_stage_prepare(void *run, const fem_attempt *a, rf_error *err)
{
    return axi_prepare(run, a->in, a->opt, err);
}

static rf_status axi_stage_mesh(void *run, rf_error *err)
{
    return axi_mesh(run, err);
}

static rf_status axi_stage_assemble(void *run, rf_error *err)
{
    return axi_assemble(run, err);
}

static void axi_params(const void *run, fem_drive_params *p)
{
    const axi_run *S = run;
    *p = (fem_drive_params){S->dt, S->H.duration, S->ke0, S->g, S->ale_on ? 13 : 12};
}

/* A step, its stability in large deformation, and the energy account's row. */
static rf_status axi_stage_step(void *run, double t, fem_step_row *r, rf_error *err)
{
    axi_run *S = run;
    rf_status st = axi_step(S, &r->Fc, &r->rad, err);
    if (st != RF_OK)
        return st;
    if (S->large && (S->unstable = axi_step_violation(S)) >= 0)
        return rf_fail(err, RF_EMODEL, "fem: element %ld was compressed below the stability bound of the time "
                       "step dt = %g s (dt_safety = %g) at t = %g s: a mesh that follows the material cannot "
                       "follow this deformation (docs/validation-plastic.md section 8, JGGE24-L1)",
                       S->unstable, S->dt, S->t.dt_safety, t);
    axi_energy(S, t, r->Fc, r->rad, r->row, &r->comp, &r->closure);
    return RF_OK;
}

static rf_status axi_frame(void *run, int k, double t, rf_error *err)
{
    axi_run *S = run;
    return fem_vtk_frame(S->o.vtk_dir, k, t, &S->mesh, S->u, S->v, S->mat, S->kernel, err);
}

static void axi_stage_extract(void *run, fem_run *R, long nsteps, const fem_attempt *a)
{
    axi_extract(run, R, nsteps, a->out, a->hist);
}

/* With ALE, the history's energy column of the remaps. */
static void axi_history(void *run, fem_run *R, rf_fem_history *hist)
{
    const axi_run *S = run;
    if (S->ale_on)
        hist->remap = R->series.col[12], R->series.col[12] = NULL;
}

static long axi_release(void *run)
{
    axi_run *S = run;
    fem_contact_free(&S->C);
    fem_ale_free(&S->ale);
    fem_kernel_release(&S->kernel[0]);
    fem_kernel_release(&S->kernel[1]);
    if (S->have_mesh)
        fem_mesh_free(&S->mesh);
    return S->unstable;
}

static const fem_geometry axi_geometry = {"fem", axi_stage_prepare, axi_stage_mesh, axi_stage_assemble, axi_params,
                                          axi_stage_step, NULL, axi_frame, axi_stage_extract, axi_history,
                                          axi_release};

/* One attempt of rf_fem_impact_ws (fem_run_halving): a fresh run through the driver. */
static rf_status axi_attempt_fn(void *ctx, const rf_fem_options *o, long *unstable, rf_error *err)
{
    fem_attempt a = *(const fem_attempt *)ctx;
    a.opt = o;
    axi_run S;
    memset(&S, 0, sizeof S);
    S.pool = &a.ws->axi, S.unstable = -1;
    return fem_drive(&axi_geometry, &S, &a, unstable, err);
}

rf_status rf_fem_impact_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                           rf_impact_output *out, rf_fem_history *hist, rf_error *err)
{
    fem_attempt a = {ws, in, opt, NULL, out, hist, NULL};
    return fem_drive_impact(axi_attempt_fn, &a, "fem", err);
}

rf_status rf_fem_impact(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                        rf_fem_history *hist, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    rf_status st = rf_fem_impact_ws(ws, in, opt, out, hist, err);
    rf_fem_workspace_free(ws);
    return st;
}

/* The slope alone under gravity (fem_internal.h): the run's own assembly and
 * steps without the contact. */
rf_status fem_axi_slope_at_rest(const rf_impact_input *in, const rf_fem_options *opt, long steps,
                                fem_rest_check *chk, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    axi_run S;
    memset(&S, 0, sizeof S);
    memset(chk, 0, sizeof *chk);
    S.pool = &ws->axi, S.unstable = -1, S.no_contact = 1;
    rf_status st = axi_prepare(&S, in, opt, err);
    if (st == RF_OK)
        st = axi_mesh(&S, err);
    if (st == RF_OK)
        st = axi_assemble(&S, err);
    for (long n = 0; st == RF_OK && n < steps; n++) {
        double Fc, rad;
        st = axi_step(&S, &Fc, &rad, err);
    }
    if (st == RF_OK) {
        const double *z = S.mesh.z;
        for (long i = S.mesh.boulder_nodes; i < S.nn; i++)
            for (int c = 0; c < 2; c++) {
                chk->v_max = fmax(chk->v_max, fabs(S.v[2 * i + c]));
                chk->u_max = fmax(chk->u_max, fabs(S.u[2 * i + c]));
            }
        chk->elements = S.ne - S.mesh.boulder_elems, chk->outside = S.geo_outside;
        chk->load_ratio_min = INFINITY, chk->load_ratio_max = -INFINITY;
        for (long i = S.mesh.boulder_nodes; S.fgrav && i < S.nn; i++) {
            const double m = S.mass[2 * i + 1] - (S.mshift ? S.mshift[i] : 0); /* the node's own mass */
            if (S.invm[2 * i + 1] > 0)
                chk->load_sum += S.fgrav[2 * i + 1], chk->weight_sum -= m * S.g;
            if (S.mesh.flags[i] || m == 0)
                continue;
            const double ratio = S.fgrav[2 * i + 1] / (-m * S.g);
            chk->load_ratio_min = fmin(chk->load_ratio_min, ratio), chk->load_ratio_max = fmax(chk->load_ratio_max, ratio);
        }
        chk->dt = S.dt;
        for (long e = S.mesh.boulder_elems; e < S.ne; e++) {
            double sig[4], ep = 0, depth = 0;
            if (!fem_kernel_cell_state(&S.kernel[FEM_SLOPE], e, sig, &ep))
                break;
            for (int a = 0; a < 4; a++)
                depth -= 0.25 * z[S.mesh.conn[4 * e + a]];
            if (depth > chk->depth && (S.emat[e] == 2 || !S.layer)) {
                chk->depth = depth, memcpy(chk->sig, sig, sizeof sig), chk->layer_elem = S.emat[e] == 2;
                for (int a = 0; a < 4; a++)
                    chk->zn[a] = z[S.mesh.conn[4 * e + a]];
            }
            chk->plastic_strain_max = fmax(chk->plastic_strain_max, ep);
        }
    }
    fem_contact_free(&S.C);
    fem_ale_free(&S.ale);
    fem_kernel_release(&S.kernel[0]);
    fem_kernel_release(&S.kernel[1]);
    if (S.have_mesh)
        fem_mesh_free(&S.mesh);
    rf_fem_workspace_free(ws);
    return st;
}
