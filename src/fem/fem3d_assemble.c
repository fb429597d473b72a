/* fem3d_assemble.c - the assembly of a 3D impact run (fem3d_run.h): the
 * arrays in the workspace pool, incidence lists and constraints, element
 * matrices and lumped masses (the boulder's with the spheroid's exact mass,
 * centre and I_yy; the contact face's mass redistribution), the time step,
 * the material kernel of each body, the absorbing boundary's dashpots, the
 * contact's slaves, the rigid boulder, gravity's load and the initial
 * state; and the release of what a run owns beyond the pool. */
#include "fem3d_run.h"
#include "hex8_step.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Meshes up to this many elements keep J^-1 and det J (640 B per element: 8 MB). */
#define F3_STORE_J_MAX 13000

static rf_status solid_alloc(solid_run *R, rf_error *err)
{
    fem_pool *P = R->pool;
    const size_t nn = (size_t)R->grid.nn, ne = (size_t)R->grid.ne, nd = (size_t)R->grid.ndof;
    solid_system *Y = &R->sys;
    solid_boundary *D = &R->bound;
    f3_system *S = &Y->S;
    S->fel = fem_pool_get(P, Q_FEL, 3 * (size_t)R->grid.nbn * sizeof(double), 0);
    S->ub = fem_pool_get(P, Q_UB, 3 * (size_t)R->grid.nbn * sizeof(double), 0);
    Y->K = fem_pool_get(P, Q_K, ne * 576 * sizeof(float), 0);
    S->fe = fem_pool_get(P, Q_FE, ne * 24 * sizeof(double), 0);
    S->inc_ptr = fem_pool_get(P, Q_INC_PTR, (nn + 1) * sizeof(long), 1);
    S->inc = fem_pool_get(P, Q_INC, ne * 8 * sizeof(long), 0);
    Y->u = fem_pool_get(P, Q_U, nd * sizeof(double), 1);
    Y->v = fem_pool_get(P, Q_V, nd * sizeof(double), 1);
    Y->f = fem_pool_get(P, Q_F, nd * sizeof(double), 1);
    Y->fext = fem_pool_get(P, Q_FEXT, nd * sizeof(double), 1);
    Y->mass = fem_pool_get(P, Q_MASS, nd * sizeof(double), 1);
    Y->invm = fem_pool_get(P, Q_INVM, nd * sizeof(double), 1);
    D->dash = fem_pool_get(P, Q_DASH, nn * sizeof(double), 1);
    Y->elm = fem_pool_get(P, Q_ELM, ne * 8 * sizeof(double), 0);
    Y->lamx = fem_pool_get(P, Q_LAMX, ne * sizeof(double), 0);
    Y->fixed = fem_pool_get(P, Q_FIXED, nd, 1);
    D->outer = fem_pool_get(P, Q_OUTER, nn * sizeof(int), 0);
    R->grid.emat = fem_pool_get(P, Q_EMAT, ne, 0);
    D->dashl = fem_pool_get(P, Q_DASHL, nn * sizeof(double), 1);
    D->dnrm = fem_pool_get(P, Q_DNRM, 3 * nn * sizeof(double), 1);
    if (!R->grid.emat || !D->dashl || !D->dnrm)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", R->grid.ne);
    if (!Y->K || !S->fe || !S->fel || !S->ub || !S->inc_ptr || !S->inc || !Y->u || !Y->v || !Y->f || !Y->fext ||
        !Y->mass || !Y->invm || !D->dash || !Y->elm || !Y->lamx || !Y->fixed || !D->outer)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", R->grid.ne);
    return RF_OK;
}

/* Incidence lists in element order; constraints: symmetry plane u_y = 0,
 * fixed outer surface. */
static void solid_topology(solid_run *R)
{
    f3_system *S = &R->sys.S;
    const f3_mesh *mesh = &R->grid.mesh;
    for (long e = 0; e < R->grid.ne; e++)
        for (int a = 0; a < 8; a++)
            S->inc_ptr[mesh->conn[8 * e + a] + 1]++;
    for (long n = 0; n < R->grid.nn; n++)
        S->inc_ptr[n + 1] += S->inc_ptr[n];
    for (long e = 0; e < R->grid.ne; e++) /* fill in element order, then restore the pointers */
        for (int a = 0; a < 8; a++)
            S->inc[S->inc_ptr[mesh->conn[8 * e + a]]++] = e * 8 + a;
    for (long n = R->grid.nn; n > 0; n--)
        S->inc_ptr[n] = S->inc_ptr[n - 1];
    S->inc_ptr[0] = 0;
    R->bound.nouter = 0;
    for (long i = 0; i < R->grid.nn; i++) {
        if (mesh->flags[i] & F3_SYM)
            R->sys.fixed[3 * i + 1] = 1;
        if (i >= R->grid.nbn && (mesh->flags[i] & F3_OUTER)) {
            R->bound.outer[R->bound.nouter++] = (int)i;
            if (R->set.fixed_outer)
                R->sys.fixed[3 * i] = R->sys.fixed[3 * i + 1] = R->sys.fixed[3 * i + 2] = 1;
        }
    }
}

/* Element stiffness (stored in float for the kernel) and lumped masses,
 * independent per element. */
static rf_status solid_elements(solid_run *R, rf_error *err)
{
    const f3_mesh *mesh = &R->grid.mesh;
    int bad_elem = 0;
    double *vols = R->sys.lamx; /* reuse: element volumes */
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(R->set.threads) reduction(| : bad_elem)
#endif
    for (long e = 0; e < R->grid.ne; e++) {
        double xe[24];
        const int *cn = mesh->conn + 8 * e;
        for (int a = 0; a < 8; a++)
            for (int q = 0; q < 3; q++)
                xe[3 * a + q] = mesh->x[3 * cn[a] + q];
        double Kd[576];
        f3_hex_matrices(xe, &R->body.mat[R->grid.emat[e]], Kd, R->sys.elm + 8 * e, &vols[e]);
        for (int q = 0; q < 576; q++)
            R->sys.K[576 * e + q] = (float)Kd[q];
        for (int a = 0; a < 8; a++)
            if (!(R->sys.elm[8 * e + a] > 0))
                bad_elem |= 1;
    }
    if (bad_elem)
        return rf_fail(err, RF_EINTERNAL,
                       "fem3d mesh: an element has a non-positive nodal mass (distorted hexahedron)");
    return RF_OK;
}

/* The lumped masses of the faceted boulder with the spheroid's mass, centre
 * (0, ., d) and I_yy (fem3d_mass.c, docs/fem-speed.md section 5). */
static void boulder_inertia(solid_run *R)
{
    const rf_hertz_reference *H = &R->set.H;
    const double M = H->mass / R->grid.sym_factor, I = M * (H->c * H->c + H->d * H->d) / 5;
    R->sys.mass_moments_ok = f3_boulder_mass_moments(&R->grid.mesh, R->sys.elm, M, 0, H->d, I);
}

/* Element e's free dofs and double stiffness (from the stored float K). */
static void element_free_k(const solid_run *R, long e, unsigned char fr[24], double Kd[576])
{
    const int *cn = R->grid.mesh.conn + 8 * e;
    for (int a = 0; a < 8; a++)
        for (int q = 0; q < 3; q++)
            fr[3 * a + q] = !R->sys.fixed[3 * cn[a] + q];
    for (int q = 0; q < 576; q++)
        Kd[q] = R->sys.K[576 * e + q];
}

/* Element e as hex8_max_eigenvalue takes it (ctx: the run). */
static void solid_element(void *ctx, long e, double K[576], double m[8], unsigned char fr[24])
{
    const solid_run *R = ctx;
    element_free_k(R, e, fr, K);
    if (R->body.rigid && e < R->grid.mesh.boulder_elems) /* no stiffness: the slope alone sets the step */
        memset(K, 0, 576 * sizeof *K);
    memcpy(m, R->sys.elm + 8 * e, 8 * sizeof *m);
}

/* max_e lambda_max(M_e^-1 K_e), with the exact eigen-solve pruned by
 * Gershgorin bounds (hex8_step.c, docs/fem-speed.md plan step 6): bit for bit
 * the maximum over every element, at ~1 % of the solves. */
static double solid_lambda_max(solid_run *R, double *lam_upper)
{
    return hex8_max_eigenvalue(R->grid.ne, solid_element, R, lam_upper, NULL);
}

/* Node n's lumped mass: the sum of its element-node masses (incidence order). */
static double node_mass(const solid_run *R, long n)
{
    double m = 0;
    for (long p = R->sys.S.inc_ptr[n]; p < R->sys.S.inc_ptr[n + 1]; p++)
        m += R->sys.elm[R->sys.S.inc[p]];
    return m;
}

/* The mass redistribution at the slope's contact face (fem3d_mass.c): the nodes of the master
 * grid, the element-node masses and the nodal masses again; mshift = each node's change. */
static void surface_mass_shift(solid_run *R, double *lam_upper, double lam_max)
{
    solid_system *Y = &R->sys;
    const f3_mesh *mesh = &R->grid.mesh;
    unsigned char *face = calloc((size_t)R->grid.nn, 1);
    Y->mshift = fem_pool_get(R->pool, Q_MSHIFT, (size_t)R->grid.nn * sizeof(double), 1);
    if (!face || !Y->mshift) { /* without memory the masses stay lumped as they are */
        free(face);
        Y->mshift = NULL;
        return;
    }
    for (long k = 0; k < (long)mesh->nxt_s * mesh->nyt_s; k++)
        face[mesh->top_s[k]] = !(mesh->flags[mesh->top_s[k]] & F3_OUTER);
    Y->shifted_elems = f3_surface_mass_shift(mesh, face, Y->elm, lam_upper, lam_max, R->set.t.surface_mass_kappa);
    free(face);
    for (long n = R->grid.nbn; n < R->grid.nn && Y->shifted_elems > 0; n++) {
        const double m = node_mass(R, n);
        Y->mshift[n] = m - Y->mass[3 * n];
        for (int q = 0; q < 3; q++) {
            Y->mass[3 * n + q] = m;
            Y->invm[3 * n + q] = Y->fixed[3 * n + q] ? 0 : 1 / m;
        }
    }
}

/* The smallest edge / c_p of the deformable elements [s] (for comparison only). */
static double solid_edge_time(const solid_run *R)
{
    static const int ed[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    const f3_mesh *mesh = &R->grid.mesh;
    double dt_edge = DBL_MAX;
    for (long e = 0; e < R->grid.ne; e++) {
        const int *cn = mesh->conn + 8 * e;
        const int b = R->grid.emat[e];
        if (R->body.rigid && b == 0)
            continue;
        for (int k = 0; k < 12; k++) {
            const double *p = mesh->x + 3 * cn[ed[k][0]], *q = mesh->x + 3 * cn[ed[k][1]];
            double l = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                            (p[2] - q[2]) * (p[2] - q[2]));
            if (l / R->body.w[b].p < dt_edge)
                dt_edge = l / R->body.w[b].p;
        }
    }
    return dt_edge;
}

/* rock_mass_scale K: the rock's element masses times K *after* the contact
 * face's mass redistribution, which therefore is the full model's (its
 * reference is the unscaled rock's largest eigenvalue: the face keeps the
 * energy-conserving treatment of docs/validation-plastic.md 9e, whose
 * redistributed elements then bound the step at kappa lambda_max of the
 * unscaled mesh); the nodal masses, the Gershgorin bounds and the largest
 * eigenvalue again.  Returns that eigenvalue. */
static double solid_scale_rock_masses(solid_run *R, double *lam_upper)
{
    solid_system *Y = &R->sys;
    for (long e = R->grid.mesh.boulder_elems; e < R->grid.ne; e++)
        if (R->grid.emat[e] == 1)
            for (int a = 0; a < 8; a++)
                Y->elm[8 * e + a] *= R->set.o.rock_mass_scale;
    for (long n = R->grid.nbn; n < R->grid.nn; n++) {
        const double m = node_mass(R, n);
        for (int q = 0; q < 3; q++) {
            Y->mass[3 * n + q] = m;
            Y->invm[3 * n + q] = Y->fixed[3 * n + q] ? 0 : 1 / m;
        }
    }
    return solid_lambda_max(R, lam_upper);
}

/* Nodal masses (the boulder's density scaled so that the rigid-body mass is
 * exact: its mesh is a polyhedron inside the spheroid), the largest element
 * eigenvalue and the time step. */
static void solid_masses(solid_run *R)
{
    const f3_mesh *mesh = &R->grid.mesh;
    solid_system *Y = &R->sys;
    Y->mesh_mass_b = 0;
    for (long e = 0; e < mesh->boulder_elems; e++)
        for (int a = 0; a < 8; a++)
            Y->mesh_mass_b += Y->elm[8 * e + a];
    R->grid.sym_factor = R->grid.ms.full ? 1.0 : 2.0;
    const double mscale = R->set.H.mass / R->grid.sym_factor / Y->mesh_mass_b;
    for (long e = 0; e < mesh->boulder_elems * 8; e++)
        Y->elm[e] *= mscale;
    boulder_inertia(R);
    for (long n = 0; n < R->grid.nn; n++)
        Y->mass[3 * n] = Y->mass[3 * n + 1] = Y->mass[3 * n + 2] = node_mass(R, n);
    for (long dd = 0; dd < R->grid.ndof; dd++)
        Y->invm[dd] = Y->fixed[dd] ? 0 : 1 / Y->mass[dd];
    double *lam_upper = fem_pool_get(R->pool, Q_LAMU, (size_t)R->grid.ne * sizeof(double), 0);
    const double lam_max = solid_lambda_max(R, lam_upper);
    const rf_fem_tuning *t = &R->set.t;
    if (lam_upper && t->surface_mass_kappa > 0 && t->surface_mass_3d && (R->body.layer || R->body.plastic[1])) /* 9e */
        surface_mass_shift(R, lam_upper, lam_max);
    const double lam_step = R->body.layer && R->set.o.rock_mass_scale > 1 ? solid_scale_rock_masses(R, lam_upper) : lam_max;
    R->step.lamu = R->body.large ? lam_upper : NULL;
    R->step.dt_edge = solid_edge_time(R);
    R->step.dt = fem_time_step(lam_step, t->dt_safety, &R->step.dt_bound);
}

/* The largest dt C / m of the explicit dashpots (stable below 2): C = the
 * node's tributary area times rho c_p of its faces' material. */
static void solid_dashpot_check(solid_run *R)
{
    solid_boundary *D = &R->bound;
    const solid_bodies *b = &R->body;
    const double dt = R->step.dt;
    D->dash_ratio = 0;
    for (long k = 0; k < D->nouter; k++) {
        const int i = D->outer[k];
        const double C = D->dash[i] * b->mat[1].rho * b->w[1].p + D->dashl[i] * b->mat[2].rho * b->w[2].p;
        if (dt * C / R->sys.mass[3 * i] > D->dash_ratio)
            D->dash_ratio = dt * C / R->sys.mass[3 * i];
    }
}

/* Dashpots on the outer surface (Lysmer & Kuhlemeyer 1969): tributary areas
 * (a layer's faces apart, with its own impedance), and the outer normals of
 * the extruded mesh (summed face normals). */
static void solid_dashpots(solid_run *R)
{
    if (R->set.fixed_outer)
        return;
    const f3_mesh *mesh = &R->grid.mesh;
    for (long q = 0; q < mesh->n_outer_quads; q++) {
        const int *qn = mesh->outer_quads + 4 * q;
        /* a quad whose 4 nodes lie in the layer (z >= -thickness) has the layer's impedance */
        int in_layer = R->body.layer;
        for (int a = 0; a < 4 && in_layer; a++)
            in_layer = mesh->x[3 * qn[a] + 2] >= -R->set.in->layer_thickness * (1 + 1e-12);
        double *area_to = in_layer ? R->bound.dashl : R->bound.dash;
        const double *p0 = mesh->x + 3 * qn[0], *p1 = mesh->x + 3 * qn[1], *p2 = mesh->x + 3 * qn[2],
                     *p3 = mesh->x + 3 * qn[3];
        double d1[3], d2[3], cr[3];
        for (int a = 0; a < 3; a++)
            d1[a] = p2[a] - p0[a], d2[a] = p3[a] - p1[a];
        cr[0] = d1[1] * d2[2] - d1[2] * d2[1];
        cr[1] = d1[2] * d2[0] - d1[0] * d2[2];
        cr[2] = d1[0] * d2[1] - d1[1] * d2[0];
        double area = 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        for (int a = 0; a < 4; a++) {
            area_to[qn[a]] += 0.25 * area;
            const double side = cr[0] * p0[0] + cr[1] * p0[1] + cr[2] * p0[2] > 0 ? 0.5 : -0.5;
            for (int d = 0; d < 3; d++) /* outward: away from the contact point at the origin */
                R->bound.dnrm[3 * qn[a] + d] += side * cr[d];
        }
    }
    solid_dashpot_check(R);
}

static void contact_release(f3_contact *C)
{
    free(C->slave), free(C->lam), free(C->mnode), free(C->N), free(C->S), free(C->gap), free(C->ds), free(C->s0);
    free(C->A), free(C->gvo), free(C->Xm), free(C->outside), free(C->cand), free(C->du), free(C->rr), free(C->wr);
    memset(C, 0, sizeof *C);
}

/* What a run owns beyond the workspace pool (its contact, step check,
 * kernels and mesh): one release for the impact and the gravity check. */
void f3_run_release(solid_run *R)
{
    contact_release(&R->C);
    f3_step_check_free(&R->step.check);
    fem_kernel_release(&R->sys.S.kernel[0]);
    fem_kernel_release(&R->sys.S.kernel[1]);
    if (R->grid.have_mesh)
        f3_mesh_free(&R->grid.mesh);
}

/* Contact: slaves are the boulder's fine-box face nodes; in sphere mode (a rigid sphere with
   sphere_contact_3d) the slope's, against the exact sphere. */
static rf_status solid_contact_setup(solid_run *R, rf_error *err)
{
    f3_contact *C = &R->C;
    const f3_mesh *mesh = &R->grid.mesh;
    C->sphere = R->set.t.sphere_contact_3d && R->body.rigid && R->set.H.c == R->set.H.d;
    C->radius = R->set.H.d;
    const size_t ns = C->sphere ? (size_t)mesh->nxt_s * (size_t)mesh->nyt_s : (size_t)mesh->nxt_b * (size_t)mesh->nyt_b;
    C->nslave = (long)ns;
    C->slave = malloc(ns * sizeof *C->slave);
    C->lam = calloc(ns * 3, sizeof *C->lam);
    C->mnode = malloc(ns * F3_NM * sizeof *C->mnode);
    C->N = malloc(ns * F3_NM * sizeof *C->N);
    C->S = calloc(ns * 2, sizeof *C->S);
    C->gap = malloc(ns * sizeof *C->gap);
    C->ds = malloc(ns * 3 * sizeof *C->ds);
    C->s0 = malloc(ns * 3 * sizeof *C->s0);
    C->A = malloc(ns * 3 * sizeof *C->A);
    C->gvo = malloc(ns * 3 * sizeof *C->gvo);
    C->Xm = malloc(ns * 2 * sizeof *C->Xm);
    C->outside = calloc(ns, 1);
    C->cand = malloc(ns * sizeof *C->cand);
    C->du = calloc((size_t)R->grid.ndof, sizeof *C->du);
    if (!C->slave || !C->lam || !C->mnode || !C->N || !C->S || !C->gap || !C->ds || !C->s0 || !C->A || !C->gvo ||
        !C->Xm || !C->outside || !C->cand || !C->du)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    if (C->sphere && !(C->wr = calloc(ns * 9, sizeof *C->wr)))
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    memcpy(C->slave, C->sphere ? mesh->top_s : mesh->top_b, ns * sizeof *C->slave);
    for (size_t k = 0; k < ns; k++)
        C->Xm[2 * k] = mesh->x[3 * C->slave[k]], C->Xm[2 * k + 1] = mesh->x[3 * C->slave[k] + 1];
    C->solve.friction = R->set.in->friction;
    C->solve.tol = 1e-9 * R->grid.h;
    C->solve.band = 0.5 * fmin(R->grid.h, R->grid.hb) + 2 * R->set.V * R->step.dt;
    C->solve.max_sweeps = 2000;
    /* the first-contact point is the slope frame's origin: the nearest node of the slope's top grid */
    const double hs = mesh->h_s;
    long i = lround(-mesh->x0_s / hs), j = lround(-mesh->y0_s / hs);
    i = i < 0 ? 0 : i >= mesh->nxt_s ? mesh->nxt_s - 1 : i;
    j = j < 0 ? 0 : j >= mesh->nyt_s ? mesh->nyt_s - 1 : j;
    R->grid.crater_node = mesh->top_s[i * mesh->nyt_s + j];
    return RF_OK;
}

/* The linear point law of material b (0 boulder, 1 slope, 2 layer; lame[b] filled). */
static fem_point_law solid_point_law(solid_run *R, int b)
{
    const f3_material *m = &R->body.mat[b];
    R->body.lame[b] = (fem_lame){m->E * m->nu / ((1 + m->nu) * (1 - 2 * m->nu)), m->E / (2 * (1 + m->nu))};
    return fem_point_law_linear3d(&R->body.lame[b]);
}

/* The slope block under a layer: the integration-point kernel with the
 * layer's law in its elements and the bedrock's below (B-bar if either is
 * plastic; an elastic pair takes the linear law without B-bar, the form of
 * kernel = points, so that a layer of the slope's own material gives the
 * homogeneous run's bits). */
static rf_status solid_layer_kernel(solid_run *R, long first, long count, rf_error *err)
{
    unsigned char *use2 = fem_pool_get(R->pool, Q_USE2, (size_t)count + 1, 0);
    if (!use2)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    for (long e = 0; e < count; e++)
        use2[e] = R->grid.emat[first + e] == 2;
    const int plastic = R->body.plastic[1] || R->body.plastic[2];
    /* one shape for both laws: the material library's return maps (an elastic one among them) if either
       is plastic, else the linear law */
    const fem_point_law law = plastic ? fem_point_law_material3d(&R->body.matl[1]) : solid_point_law(R, 1);
    const fem_point_law law2 = plastic ? fem_point_law_material3d(&R->body.matl[2]) : solid_point_law(R, 2);
    const f3_mesh *mesh = &R->grid.mesh;
    return fem_kernel_points_hex(&R->sys.S.kernel[F3_SLOPE], first, count, mesh->x, mesh->conn, &law, &law2, use2,
                                 plastic, err);
}

/* The material of each element (0 boulder, 1 slope, 2 layer: a slope
 * element above the layer's node plane); fails if no element is in the layer. */
static rf_status solid_materials(solid_run *R, rf_error *err)
{
    const f3_mesh *mesh = &R->grid.mesh;
    unsigned char *emat = R->grid.emat;
    long nlayer = 0;
    for (long e = 0; e < R->grid.ne; e++) {
        const int *c = mesh->conn + 8 * e;
        double zc = 0;
        for (int a = 0; a < 8; a++)
            zc += mesh->x[3 * c[a] + 2] / 8;
        emat[e] = e < mesh->boulder_elems ? 0 : R->body.layer && zc > -R->set.in->layer_thickness ? 2 : 1;
        nlayer += emat[e] == 2;
    }
    if (R->body.layer && nlayer == 0)
        return rf_fail(err, RF_EINVAL, "fem3d: layer_thickness = %g m has no element (h = %g m)",
                       R->set.in->layer_thickness, R->grid.h);
    return RF_OK;
}

/* The rigid boulder's state (at rest relative to its initial translation)
 * and its coupling into the contact: exact model mass and I_yy, no inverse
 * mass of its own nodes. */
static rf_status solid_rigid_setup(solid_run *R, rf_error *err)
{
    if (!R->body.rigid)
        return RF_OK;
    f3_rigid *B = &R->B;
    const rf_hertz_reference *H = &R->set.H;
    B->on = 1;
    B->M = H->mass / R->grid.sym_factor;
    B->I = B->M * (H->c * H->c + H->d * H->d) / 5;
    memcpy(B->c0, R->sys.S.c0, sizeof B->c0);
    B->V[0] = R->set.Vt, B->V[1] = -R->set.Vn;
    for (long dd = 0; dd < 3 * R->grid.nbn; dd++)
        R->sys.invm[dd] = 0;
    f3_contact *C = &R->C;
    C->rigid_invm = 1 / B->M, C->rigid_invi = 1 / B->I;
    if (!(C->rr = calloc((size_t)C->nslave * 2, sizeof *C->rr)))
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    f3_rigid_place(B, &R->grid.mesh, R->grid.nbn, R->sys.u, R->sys.v);
    return RF_OK;
}

/* The material kernel of each body, one block per body: an elasto-plastic
 * body's return maps at the integration points with B-bar
 * (fem_kernel_points3d.c); an elastic body matrix-free (docs/fem-speed.md:
 * J^-1 stored while the mesh is small enough for the 640 B per element to
 * stay in cache, recomputed from x beyond), or with the linear point law if
 * its kernel option is `points`.  In large deformation a body with ul[b]
 * takes the updated-Lagrangian form of the point kernel (an elastic one the
 * linear law). */
static rf_status solid_kernels(solid_run *R, rf_error *err)
{
    f3_system *S = &R->sys.S;
    const double *x = R->grid.mesh.x;
    const int *conn = R->grid.mesh.conn;
    const long nbe = R->grid.mesh.boulder_elems;
    const int store_j = R->grid.ne <= F3_STORE_J_MAX;
    for (int b = 0; b < 2; b++) {
        const f3_material *m = &R->body.mat[b];
        const double lam = m->E * m->nu / ((1 + m->nu) * (1 - 2 * m->nu)), mu = m->E / (2 * (1 + m->nu));
        const long first = b == F3_BOULDER ? 0 : nbe, count = b == F3_BOULDER ? nbe : R->grid.ne - nbe;
        rf_status st;
        if (b == F3_BOULDER && R->body.rigid) {
            f3_rigid_kernel(&S->kernel[b], first, count, S->fe);
            continue;
        }
        if (b == F3_SLOPE && R->body.layer)
            st = solid_layer_kernel(R, first, count, err);
        else if (R->body.plastic[b]) {
            const fem_point_law law = fem_point_law_material3d(&R->body.matl[b]);
            st = fem_kernel_points_hex(&S->kernel[b], first, count, x, conn, &law, NULL, NULL, 1, err);
        } else if (R->set.t.kernel[b] == RF_FEM_KERNEL_POINTS || R->body.ul[b]) {
            R->body.lame[b] = (fem_lame){lam, mu};
            const fem_point_law law = fem_point_law_linear3d(&R->body.lame[b]);
            st = fem_kernel_points_hex(&S->kernel[b], first, count, x, conn, &law, NULL, NULL, 0, err);
        } else
            st = fem_kernel_hex8_matfree(&S->kernel[b], first, count, x, conn, lam, mu, store_j, err);
        if (st == RF_OK && R->body.ul[b]) /* (an elastic body: the linear, hypoelastic, law on the current geometry) */
            st = fem_kernel_points_hex_large(&S->kernel[b], x, err);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

/* Large deformation: the step check watches the elements on the UL kernel. */
static rf_status solid_step_check(solid_run *R, rf_error *err)
{
    solid_timestep *T = &R->step;
    const long ne = R->grid.ne;
    T->ul_elem = fem_pool_get(R->pool, Q_ULE, (size_t)ne + 1, 0);
    if (!T->lamu || !T->ul_elem)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", ne);
    for (long e = 0; e < ne; e++)
        T->ul_elem[e] = (unsigned char)R->body.ul[e < R->grid.mesh.boulder_elems ? F3_BOULDER : F3_SLOPE];
    return f3_step_check_init(&T->check, &R->grid.mesh, ne, T->ul_elem, T->lamu, solid_element, R, err);
}

/* The initial state: the boulder translating at (V sin alpha, 0, -V cos
 * alpha) in the slope frame, its mass, KE0 and reference CM. */
static void solid_initial_state(solid_run *R)
{
    solid_system *Y = &R->sys;
    f3_system *S = &Y->S;
    const long nbn = R->grid.nbn;
    for (long i = 0; i < nbn; i++)
        Y->v[3 * i] = R->set.Vt, Y->v[3 * i + 2] = -R->set.Vn;
    double Mb = 0;
    for (long i = 0; i < nbn; i++)
        Mb += Y->mass[3 * i];
    Y->Mb = Mb;
    Y->ke0 = 0.5 * Mb * R->set.V * R->set.V; /* of the model (half of the boulder in the half model) */
    S->mass = Y->mass, S->Mb = Mb;
    for (long i = 0; i < nbn; i++)
        for (int q = 0; q < 3; q++)
            S->c0[q] += Y->mass[3 * i] * R->grid.mesh.x[3 * i + q] / Mb;
    if (!R->grid.ms.full)
        S->c0[1] = 0;
}

/* Assembly: arrays, topology, elements, masses and time step, material
 * kernels (one block per body), dashpots, contact, the initial state, the
 * rigid boulder and gravity's load. */
/* rock_mass_scale K (fem.h): a layer's bedrock with its inertia times K, its
 * stiffness kept.  Its wave speeds c / sqrt K for the dashpots' impedance
 * rho c sqrt K and the edge bound (here, after the masses); its masses:
 * solid_masses.  Its weight is the input's (fem3d_gravity.c); the mesh and
 * the domain were sized from the true rock. */
static void solid_rock_mass_scale(solid_run *R)
{
    const double k = R->set.o.rock_mass_scale;
    if (!R->body.layer || !(k > 1))
        return;
    R->body.mat[1].rho *= k;
    rf_wave_speeds *w = &R->body.w[1];
    w->p /= sqrt(k), w->s /= sqrt(k), w->rayleigh /= sqrt(k);
}

rf_status f3_run_assemble(solid_run *R, rf_error *err)
{
    solid_grid *G = &R->grid;
    G->nn = G->mesh.n_nodes, G->ne = G->mesh.n_elems, G->ndof = 3 * G->nn, G->nbn = G->mesh.boulder_nodes;
    f3_system *S = &R->sys.S;
    S->nn = G->nn, S->ne = G->ne, S->ndof = G->ndof, S->nbn = G->nbn, S->mesh = &G->mesh;
    S->threads = R->set.threads, S->full = G->ms.full;
    rf_status st = solid_alloc(R, err);
    if (st != RF_OK)
        return st;
    solid_topology(R);
    if ((st = solid_materials(R, err)) != RF_OK || (st = solid_elements(R, err)) != RF_OK)
        return st;
    solid_masses(R);
    solid_rock_mass_scale(R);
    if (!R->sys.mass_moments_ok)
        return rf_fail(err, RF_EINTERNAL, "fem3d: no positive boulder mass weighting with the spheroid's moments");
    if ((st = solid_kernels(R, err)) != RF_OK)
        return st;
    if (R->body.large && (st = solid_step_check(R, err)) != RF_OK)
        return st;
    solid_dashpots(R);
    if (R->bound.dash_ratio >= 2)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: the absorbing boundary is unstable here (dt C / m = %.3g >= 2 on an outer node of a "
                       "light layer); use boundary: fixed", R->bound.dash_ratio);
    if ((st = solid_contact_setup(R, err)) != RF_OK)
        return st;
    solid_initial_state(R);
    if ((st = solid_rigid_setup(R, err)) != RF_OK || !(R->grav.g > 0))
        return st;
    double *fgrav = fem_pool_get(R->pool, Q_FGRAV, (size_t)G->ndof * sizeof(double), 1);
    if (!fgrav)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    return f3_gravity_setup(&R->grav, S, &R->set.ground, R->body.matl, R->body.plastic, R->sys.u, fgrav, err);
}
