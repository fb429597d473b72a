/* fem_axi_assemble.c - the axisymmetric run's assembly (fem_axi_run.h): the
 * arrays, the node incidence, the element matrices and lumped masses (with the
 * mass redistribution at a soil slope's contact face), the constraints and the
 * time step, the material kernels, the outer dashpots, the contact pairs, the
 * initial state, and gravity's geostatic state and body load. */
#include "fem_axi_run.h"
#include "quad4_kernel.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The run's arrays, from the workspace pool (zeroed where the run expects it). */
static rf_status axi_alloc(axi_run *S, rf_error *err)
{
    fem_pool *P = S->pool;
    const size_t nd = (size_t)S->sys.ndof, ne = (size_t)S->sys.ne, nn = (size_t)S->sys.nn;
    S->sys.K = fem_pool_get(P, P_K, ne * 64 * sizeof(double), 0);
    S->sys.fe = fem_pool_get(P, P_FE, ne * 8 * sizeof(double), 0);
    S->sys.inc_ptr = fem_pool_get(P, P_INC_PTR, (nn + 1) * sizeof(long), 1);
    S->sys.inc = fem_pool_get(P, P_INC, ne * 4 * sizeof(long), 0);
    S->sys.invm = fem_pool_get(P, P_INVM, nd * sizeof(double), 1);
    S->sys.mass = fem_pool_get(P, P_MASS, nd * sizeof(double), 1);
    S->sys.u = fem_pool_get(P, P_U, nd * sizeof(double), 1);
    S->sys.v = fem_pool_get(P, P_V, nd * sizeof(double), 1);
    S->sys.f = fem_pool_get(P, P_F, nd * sizeof(double), 1);
    S->sys.fext = fem_pool_get(P, P_FEXT, nd * sizeof(double), 1);
    S->sys.dash = fem_pool_get(P, P_DASH, nd * sizeof(double), 1);
    S->sys.outer = fem_pool_get(P, P_OUTER, nn * sizeof(int), 0);
    const axi_system *Y = &S->sys;
    if (!Y->K || !Y->fe || !Y->inc_ptr || !Y->inc || !Y->invm || !Y->mass || !Y->u || !Y->v || !Y->f || !Y->fext ||
        !S->sys.dash || !S->sys.outer)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld elements", S->sys.ne);
    return RF_OK;
}

/* Node -> (element * 4 + local node) lists in element order: the assembly
 * then sums each node's element forces in the same order for any thread count. */
static void axi_incidence(axi_run *S)
{
    const int *conn = S->mesh.conn;
    for (long e = 0; e < S->sys.ne; e++)
        for (int a = 0; a < 4; a++)
            S->sys.inc_ptr[conn[4 * e + a] + 1]++;
    for (long n = 0; n < S->sys.nn; n++)
        S->sys.inc_ptr[n + 1] += S->sys.inc_ptr[n];
    for (long e = 0; e < S->sys.ne; e++) /* fill in element order, then restore the pointers */
        for (int a = 0; a < 4; a++)
            S->sys.inc[S->sys.inc_ptr[conn[4 * e + a]]++] = e * 4 + a;
    for (long n = S->sys.nn; n > 0; n--)
        S->sys.inc_ptr[n] = S->sys.inc_ptr[n - 1];
    S->sys.inc_ptr[0] = 0;
}

/* Element matrices and lumped masses; returns the time-step eigenvalue bound
 * inputs.  The boulder mesh is a polygon inside the spheroid: its density is
 * scaled so that the rigid-body mass is exact (stiffness untouched). */
static rf_status axi_elements(axi_run *S, double *elm, rf_error *err)
{
    const fem_mesh *mesh = &S->mesh;
    S->ts.dt_edge = DBL_MAX, S->sys.mesh_mass_b = 0;
    for (long e = 0; e < S->sys.ne; e++) {
        const int *c = mesh->conn + 4 * e;
        double r[4], z[4], mass, area;
        for (int a = 0; a < 4; a++)
            r[a] = mesh->r[c[a]], z[a] = mesh->z[c[a]];
        const int b = mesh->ebody[e], mb = S->body.emat[e];
        fem_element_matrices(r, z, &S->body.mat[mb], S->sys.K + 64 * e, elm + 4 * e, &mass, &area);
        if (!(area > 0))
            return rf_fail(err, RF_EINTERNAL, "fem mesh: element %ld has non-positive area", e);
        if (b == FEM_BOULDER)
            S->sys.mesh_mass_b += mass;
        for (int a = 0; a < 4; a++) {
            double ed = hypot(r[(a + 1) % 4] - r[a], z[(a + 1) % 4] - z[a]);
            if (ed > 1e-12 * S->sys.h && ed / S->body.w[mb].p < S->ts.dt_edge)
                S->ts.dt_edge = ed / S->body.w[mb].p;
        }
    }
    const double mscale = S->set.H.mass / S->sys.mesh_mass_b;
    for (long e = 0; e < mesh->boulder_elems; e++)
        for (int a = 0; a < 4; a++)
            elm[4 * e + a] *= mscale;
    return RF_OK;
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
    return fem_element_lambda_max(S->sys.K + 64 * e, me, freed);
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
    unsigned char *face = calloc((size_t)S->sys.nn, 1);
    if (!face)
        return 0; /* without memory the masses stay lumped as they are */
    const double reach = fmax(S->sys.fine_r, S->set.H.c); /* soil is penetrated out to the boulder's radius */
    for (long k = 0; k < mesh->n_ssurf; k++) {
        const int i = mesh->ssurf[k];
        face[i] = !(mesh->flags[i] & FEM_OUTER) && mesh->r[i] <= reach * (1 + 1e-9);
    }
    long n = 0;
    for (long e = mesh->boulder_elems; e < S->sys.ne; e++) {
        const int *c = mesh->conn + 4 * e;
        int top[4], nt = 0, distinct = 1;
        for (int a = 0; a < 4; a++) {
            nt += top[a] = face[c[a]];
            for (int b = 0; b < a; b++)
                distinct &= c[b] != c[a];
        }
        if (nt != 2 || !distinct || (top[0] && top[2]) || (top[1] && top[3]))
            continue; /* not one edge on the face, or a collapsed quad */
        const double alpha = fem_mass_kept(axi_element_lambda(S, elm, fixed, e), S->set.t.surface_mass_kappa, lam_max);
        if (!(alpha > 0) || alpha >= 1)
            continue;
        for (int a = 0; a < 4; a++)
            if (top[a]) {
                const int below = top[(a + 1) % 4] ? (a + 3) % 4 : (a + 1) % 4;
                elm[4 * e + below] += (1 - alpha) * elm[4 * e + a];
                elm[4 * e + a] *= alpha;
            }
        if (S->ts.dte)
            S->ts.dte[e] = 2 / sqrt(axi_element_lambda(S, elm, fixed, e)) / fem_ale_element_size(mesh, e, NULL);
        n++;
    }
    free(face);
    return n;
}

/* Nodal masses from the element-node masses, and their inverses. */
static void axi_nodal_masses(axi_run *S, const double *elm, const unsigned char *fixed)
{
    memset(S->sys.mass, 0, (size_t)S->sys.ndof * sizeof *S->sys.mass);
    for (long e = 0; e < S->sys.ne; e++)
        for (int a = 0; a < 4; a++) {
            const int c = S->mesh.conn[4 * e + a];
            S->sys.mass[2 * c] += elm[4 * e + a], S->sys.mass[2 * c + 1] += elm[4 * e + a];
        }
    for (long d = 0; d < S->sys.ndof; d++)
        S->sys.invm[d] = fixed[d] ? 0 : 1 / S->sys.mass[d];
}

/* rock_mass_scale K: the rock's element masses times K *after* the contact
 * face's mass redistribution, which therefore is the full model's (its
 * reference is the unscaled rock's largest eigenvalue: the face keeps the
 * energy-conserving treatment of docs/validation-plastic.md 9e, whose
 * redistributed elements then bound the step at kappa lambda_max of the
 * unscaled mesh, a gain of at most 1/sqrt(kappa)); the nodal masses and the
 * largest eigenvalue again.  Returns that eigenvalue. */
static double axi_scale_rock_masses(axi_run *S, double *elm, const unsigned char *fixed)
{
    for (long e = S->mesh.boulder_elems; e < S->sys.ne; e++)
        if (S->body.emat[e] == 1)
            for (int a = 0; a < 4; a++)
                elm[4 * e + a] *= S->set.o.rock_mass_scale;
    axi_nodal_masses(S, elm, fixed);
    double lam_max = 0;
    for (long e = 0; e < S->sys.ne; e++) {
        if (S->set.rigid && e < S->mesh.boulder_elems)
            continue;
        const double lm = axi_element_lambda(S, elm, fixed, e);
        if (S->ts.dte)
            S->ts.dte[e] = 2 / sqrt(lm) / fem_ale_element_size(&S->mesh, e, NULL);
        lam_max = fmax(lam_max, lm);
    }
    return lam_max;
}

/* Constraints (u_r = 0 on the axis; the outer surface if fixed), nodal
 * masses, the largest element eigenvalue, the time step. */
static void axi_masses(axi_run *S, double *elm, unsigned char *fixed)
{
    const fem_mesh *mesh = &S->mesh;
    for (long i = 0; i < S->sys.nn; i++) {
        if (mesh->flags[i] & FEM_AXIS)
            fixed[2 * i] = 1;
        if (i >= mesh->boulder_nodes && (mesh->flags[i] & FEM_OUTER) && S->set.fixed_outer)
            fixed[2 * i] = fixed[2 * i + 1] = 1;
    }
    axi_nodal_masses(S, elm, fixed);
    double lam_max = 0;
    for (long e = 0; e < S->sys.ne; e++) {
        if (S->set.rigid && e < mesh->boulder_elems)
            continue; /* a rigid boulder has no stiffness: the slope sets the step */
        const double lm = axi_element_lambda(S, elm, fixed, e);
        if (S->ts.dte)
            S->ts.dte[e] = 2 / sqrt(lm) / fem_ale_element_size(mesh, e, NULL);
        if (lm > lam_max)
            lam_max = lm;
    }
    if (S->set.t.surface_mass_kappa > 0 && (S->set.layer || S->body.plastic[1]) && /* soil only: section 9e */
        (S->sys.mshift = fem_pool_get(S->pool, P_MSHIFT, (size_t)S->sys.nn * sizeof(double), 1)) &&
        (S->sys.shifted_elems = axi_surface_mass_shift(S, elm, fixed, lam_max)) > 0) {
        for (long i = 0; i < S->sys.nn; i++)
            S->sys.mshift[i] = -S->sys.mass[2 * i];
        axi_nodal_masses(S, elm, fixed);
        for (long i = 0; i < S->sys.nn; i++)
            S->sys.mshift[i] += S->sys.mass[2 * i];
    }
    if (S->set.layer && S->set.o.rock_mass_scale > 1)
        lam_max = axi_scale_rock_masses(S, elm, fixed);
    S->ts.dt = fem_time_step(lam_max, S->set.t.dt_safety, &S->ts.dt_bound);
}

/* Dashpots on the outer surface (Lysmer & Kuhlemeyer 1969): each outer face
 * gives its two nodes their tributary shares of rho c_p A and rho c_s A with
 * the impedances of the element that owns the face (a layer's face its own,
 * not the bedrock's); normal in the even, tangential in the odd entries of dash. */
static void axi_dashpots(axi_run *S)
{
    const fem_mesh *mesh = &S->mesh;
    S->sys.nouter = 0;
    if (S->set.fixed_outer)
        return;
    double *C = S->sys.dash;
    for (long e = mesh->boulder_elems; e < S->sys.ne; e++) {
        const int *c = mesh->conn + 4 * e;
        const int mb = S->body.emat[e];
        const double zp = S->body.mat[mb].rho * S->body.w[mb].p, zs = S->body.mat[mb].rho * S->body.w[mb].s;
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
    for (long i = mesh->boulder_nodes; i < S->sys.nn; i++)
        if (mesh->flags[i] & FEM_OUTER)
            S->sys.outer[S->sys.nouter++] = (int)i;
}

/* The material kernel of each body: one block of elements per body. */
static rf_status axi_kernels(axi_run *S, rf_error *err)
{
    const long nbe = S->mesh.boulder_elems;
    const long first[2] = {0, nbe}, count[2] = {nbe, S->sys.ne - nbe};
    for (int b = 0; b < 2; b++) {
        if (b == FEM_BOULDER && S->set.rigid) {
            fem_kernel_rigid(&S->body.kernel[b], first[b], count[b], 8);
            continue;
        }
        if (S->body.plastic[b] || (b == FEM_SLOPE && S->set.layer)) { /* return maps at the points, B-bar */
            fem_point_law law = fem_point_law_material(&S->body.matl[b]);
            fem_point_law law2 = fem_point_law_material(&S->body.matl[2]);
            const unsigned char *use2 = NULL;
            unsigned char *flags = NULL;
            if (b == FEM_SLOPE && S->set.layer) { /* layer elements take the layer's law */
                flags = fem_pool_get(S->pool, P_USE2, (size_t)count[b] + 1, 0);
                if (!flags)
                    return rf_fail(err, RF_ENOMEM, "fem: out of memory");
                for (long e = 0; e < count[b]; e++)
                    flags[e] = S->body.emat[first[b] + e] == 2;
                use2 = flags;
            }
            rf_status st = fem_kernel_points_axi_two(&S->body.kernel[b], first[b], count[b], S->mesh.r, S->mesh.z,
                                                     S->mesh.conn, &law, &law2, use2, 1, err);
            if (st == RF_OK && S->set.large)
                st = fem_kernel_points_axi_large(&S->body.kernel[b], S->mesh.r, S->mesh.z, S->mesh.conn, err);
            if (st != RF_OK)
                return st;
            continue;
        }
        /* packed if it pays (the same bits), else per element */
        if (S->set.t.kernel[b] == RF_FEM_KERNEL_STIFFNESS && !S->set.large) {
            double *pk = NULL;
            if (quad4_packed_pays(S->sys.ne) &&
                !(pk = fem_pool_get(S->pool, P_PACK0 + b, (size_t)quad4_packed_size(count[b]) * sizeof *pk, 0)))
                return rf_fail(err, RF_ENOMEM, "fem: out of memory");
            if (!pk ||
                fem_kernel_linear_axi_packed(&S->body.kernel[b], first[b], count[b], S->sys.K + 64 * first[b], pk) != 0)
                fem_kernel_linear_axi(&S->body.kernel[b], first[b], count[b], S->sys.K + 64 * first[b], 1);
            continue;
        }
        const double E = S->body.mat[b].E, nu = S->body.mat[b].nu;
        S->body.lame[b] = (fem_lame){E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))};
        fem_point_law law = fem_point_law_linear(&S->body.lame[b]);
        rf_status st = fem_kernel_points_axi(&S->body.kernel[b], first[b], count[b], S->mesh.r, S->mesh.z, S->mesh.conn,
                                             &law, err);
        if (st == RF_OK && S->set.large) /* a linear (hypoelastic) law on the current geometry */
            st = fem_kernel_points_axi_large(&S->body.kernel[b], S->mesh.r, S->mesh.z, S->mesh.conn, err);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

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
    if (!(S->grav.fgrav = fem_pool_get(S->pool, P_FGRAV, (size_t)S->sys.ndof * sizeof(double), 1)))
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    rf_material_params p[2];
    rf_impact_material_params(S->set.in, 1, &p[0]);
    rf_impact_material_params(S->set.in, S->set.layer ? 2 : 1, &p[1]);
    const fem_geostatic geo = {S->grav.g,
                               S->set.layer ? S->set.in->layer_thickness : 0,
                               S->body.mat[2].rho,
                               S->set.in->slope_density, /* the rock's weight, not its scaled inertia */
                               {fem_geostatic_k0(&p[0]), fem_geostatic_k0(&p[1])},
                               {S->body.plastic[1] ? &S->body.matl[1] : NULL,
                                S->body.plastic[2] ? &S->body.matl[2] : NULL},
                               0};
    fem_kernel *k = &S->body.kernel[FEM_SLOPE];
    S->grav.geo_outside = fem_kernel_points_axi_geostatic(k, S->mesh.r, S->mesh.z, S->mesh.conn, &geo);
    if (S->grav.geo_outside >= 0) {
        S->grav.E0 = fmax(fem_kernel_elastic_energy(k), 0);
        axi_internal_force(S, S->sys.u, S->grav.fgrav); /* u = 0 */
        axi_commit(S);
    } else
        S->grav.geo_outside = 0;
    for (long i = 0; i < S->mesh.boulder_nodes; i++)
        S->grav.fgrav[2 * i] = 0, S->grav.fgrav[2 * i + 1] = -S->sys.mass[2 * i + 1] * S->grav.g;
    return RF_OK;
}

/* rock_mass_scale K (fem.h): under a layer the rock's inertia times K, its
 * stiffness kept.  Its waves: c / sqrt K, the impedance rho c sqrt K of its
 * dashpots (here, after the masses); its masses: axi_masses.  Its weight is
 * not scaled (axi_gravity takes the input's density).  The mesh and the
 * domain were sized from the true rock. */
static void axi_rock_mass_scale(axi_run *S)
{
    const double k = S->set.o.rock_mass_scale;
    if (!S->set.layer || !(k > 1))
        return;
    S->body.mat[1].rho *= k;
    rf_wave_speeds *w = &S->body.w[1];
    w->p /= sqrt(k), w->s /= sqrt(k), w->rayleigh /= sqrt(k);
}

/* Assembly: arrays, incidence, element matrices, masses and time step,
 * material kernels (linear elastic, one block per body), dashpots, contact
 * pairs, and the initial state (boulder translating down at V). */
rf_status axi_assemble(axi_run *S, rf_error *err)
{
    S->sys.nn = S->mesh.n_nodes, S->sys.ndof = 2 * S->sys.nn;
    S->sys.ne = S->mesh.n_elems, S->sys.nbd = 2 * S->mesh.boulder_nodes;
    rf_status st = axi_alloc(S, err);
    if (st != RF_OK)
        return st;
    axi_incidence(S);
    double *elm = fem_pool_get(S->pool, P_ELM, (size_t)S->sys.ne * 4 * sizeof(double), 0);
    unsigned char *fixed = fem_pool_get(S->pool, P_FIXED, (size_t)S->sys.ndof, 1);
    if (!elm || !fixed)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    if (!(S->body.emat = fem_pool_get(S->pool, P_EMAT, (size_t)S->sys.ne, 0)))
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    long nlayer = 0;
    for (long e = 0; e < S->sys.ne; e++) { /* the layer: slope elements whose centre lies above -thickness */
        const int *c = S->mesh.conn + 4 * e;
        const double zc = 0.25 * (S->mesh.z[c[0]] + S->mesh.z[c[1]] + S->mesh.z[c[2]] + S->mesh.z[c[3]]);
        const int in_layer = S->set.layer && zc > -S->set.in->layer_thickness;
        S->body.emat[e] = S->mesh.ebody[e] == FEM_BOULDER ? 0 : in_layer ? 2 : 1;
        nlayer += S->body.emat[e] == 2;
    }
    if (S->set.layer && nlayer == 0)
        return rf_fail(err, RF_EINVAL,
                       "fem: layer_thickness = %g m is thinner than half an element at the contact (h = %g m): "
                       "raise refinement or the thickness", S->set.in->layer_thickness, S->sys.h);
    st = axi_elements(S, elm, err);
    if (st != RF_OK)
        return st;
    if (S->set.large && !(S->ts.dte = fem_pool_get(S->pool, P_DTE, (size_t)S->sys.ne * sizeof(double), 1)))
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    axi_masses(S, elm, fixed);
    axi_rock_mass_scale(S);
    if ((st = axi_kernels(S, err)) != RF_OK)
        return st;
    axi_dashpots(S);
    st = fem_contact_setup(&S->C, &S->mesh, S->sys.ndof, S->set.H.d, err);
    if (st == RF_OK && S->set.large)
        st = fem_contact_large(&S->C, &S->mesh, S->sys.ndof, err);
    if (st != RF_OK)
        return st;
    if (S->set.t.contact_single_pivot)
        S->C.block_rounds = 0;
    if (S->set.in->friction > 0 &&
        (st = fem_contact_friction_setup(&S->C, S->sys.ndof, S->set.in->friction, err)) != RF_OK)
        return st;
    S->C.tol = 1e-9 * S->sys.h;
    S->C.band = 0.5 * fmin(S->sys.h, S->sys.hb) + 2 * S->set.V * S->ts.dt;
    for (long i = 0; i < S->mesh.boulder_nodes; i++)
        S->sys.v[2 * i + 1] = -S->set.V;
    double Mb = 0, Ms = 0;
    for (long i = 0; i < S->sys.nn; i++)
        *(i < S->mesh.boulder_nodes ? &Mb : &Ms) += S->sys.mass[2 * i + 1];
    S->sys.Mb = Mb;
    S->acc.ke0 = 0.5 * Mb * S->set.V * S->set.V;
    if (S->set.rigid)
        S->C.rigid_invm = 1 / Mb, S->C.rigid_dofs = S->sys.nbd;
    if (S->ale.on) {
        const rf_fem_tuning *t = &S->set.t;
        const fem_ale_params ap = {t->ale_trigger, fmin(0.5 * (1 + t->ale_trigger), 0.95), t->ale_sweeps};
        if (!(S->ale.delta = fem_pool_get(S->pool, P_ALE, (size_t)S->sys.ndof * sizeof(double), 1)))
            return rf_fail(err, RF_ENOMEM, "fem: out of memory");
        st = fem_ale_setup(&S->ale.state, &S->mesh, S->mesh.boulder_elems, S->sys.ne, S->body.emat, S->sys.invm, &ap,
                           err);
        if (st != RF_OK)
            return st;
    }
    return S->grav.g > 0 ? axi_gravity(S, err) : RF_OK;
}
