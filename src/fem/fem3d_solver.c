/* fem3d_solver.c - rf_fem3d_impact: the 3D impact run, as the stages of
 * fem_core.h applied to this geometry: check, sizing and meshing
 * (fem3d_mesh.c), assembly of masses, constraints, dashpots and the material
 * kernels (fem_kernel.h), the time step, the time loop (dashpots ->
 * internal force, pairing and predictor in one parallel region -> contact
 * with friction (fem3d_contact.c) -> energy account -> stop test), and the
 * rigid-body outputs of an oblique impact.
 *
 * Time integration (lumped mass M, internal force f_int, forces f):
 *   v_{n+1/2} = v_{n-1/2} + dt M^-1 (f_n - f_int(u_n) + G^T lambda_n),  u_{n+1} = u_n + dt v_{n+1/2}.
 * Energy: with K symmetric, E_n = 1/2 v_{n+1/2}' M v_{n+1/2} + 1/2 u_n' K u_{n+1}
 * changes only by the work f_n' (u_{n+1} - u_{n-1}) / 2 of the forces applied at
 * step n.  The tangential contact work is the frictional dissipation and
 * enters the closure; the normal contact work (ideally 0) and round-off are
 * the closure error.  With a plastic body (fem_kernel_points3d.c, committed
 * after each internal force) the strain energy is replaced by the internal
 * work dt/2 f_int(u_n)' (v_{n-1/2} + v_{n+1/2}) summed over the steps, as in
 * the axisymmetric solver, and the kernels book the plastic dissipation.
 * In large deformation (rf_fem_large_deformation) the plastic bodies (every
 * deformable one with `on`) take the updated-Lagrangian kernel
 * (fem_kernel_points3d_large.c), the energy is always the internal work, and
 * a run whose compressed elements outgrow the step is made again with half
 * the step (fem3d_large.c, fem_run_halving).
 * A layer (fem3d_layer.c mesh) is a second law in the slope's point kernel,
 * its elements found by their centres above the node plane at its bottom; a
 * rigid boulder (fem3d_rigid.c) has no force, no part in the time step, and
 * takes the contact's impulses on its three planar dofs.
 * Determinism: every element writes its own 24 forces; every node then sums
 * its elements in element order; sums over nodes run in fixed chunks added in
 * a fixed order (fem3d_force.c).  The result is the same bit for bit for any
 * thread count (test_fem3d_threads). */
#include "rockfuzz/fem3d.h"
#include "core/util.h"
#include "hex8_step.h"
#include "fem3d_gravity.h"
#include "fem3d_internal.h"
#include "fem3d_large.h"
#include "fem3d_prof.h"
#include "fem3d_spec.h"
#include "fem_core.h"
#include "fem_driver.h"
#include "fem_internal.h"
#include "fem_kernel.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    /* (the 3D model runs for an inclined slope or friction between dissimilar bodies: rf_fem_needs_3d) */
    BAD(in->horizontal_axis > 0 && in->slope_angle != 0,
        "fem3d: a spheroid on an inclined slope is not supported (its contact point is not a pole); got "
        "horizontal_axis = %g m, slope_angle = %g rad",
        in->horizontal_axis, in->slope_angle);
    if (in->horizontal_axis > 0) {
        double c = in->horizontal_axis, d = rf_impact_vertical_semi_axis(in);
        BAD(c / d > 3 || d / c > 3, "fem3d: spheroid aspect c/d = %g outside [1/3, 3] is not supported", c / d);
    }
    BAD(!(o3->fine_box_factor >= 1 && o3->fine_box_factor <= 4), "fem3d: fine_box_factor must be in [1, 4], got %g",
        o3->fine_box_factor);
    BAD(!(o3->elongation >= 0 && o3->elongation <= 4), "fem3d: elongation must be in [0, 4], got %g", o3->elongation);
    BAD(!(o3->layer_aspect >= 0.5 && o3->layer_aspect <= 4), "fem3d: layer_aspect must be in [0.5, 4], got %g",
        o3->layer_aspect);
    BAD(!(o3->boulder_inner >= 2.5 && o3->boulder_inner <= 20), "fem3d: boulder_inner must be in [2.5, 20], got %g",
        o3->boulder_inner);
    return RF_OK;
#undef BAD
}

/* Meshes up to this many elements keep J^-1 and det J (640 B per element: 8 MB). */
#define F3_STORE_J_MAX 13000

/* Buffers of the 3D solver in the workspace pool. */
enum { Q_K, Q_FE, Q_FEL, Q_INC_PTR, Q_INC, Q_U, Q_V, Q_F, Q_FEXT, Q_MASS, Q_INVM, Q_DASH, Q_ELM, Q_LAMX, Q_FIXED,
       Q_OUTER, Q_UB, Q_VTK, Q_EMAT, Q_USE2, Q_DASHL, Q_DNRM, Q_LAMU, Q_ULE, Q_FGRAV, Q_MSHIFT };

/* The state of one 3D run. */
typedef struct {
    const rf_impact_input *in;
    rf_fem_options o;
    rf_fem_tuning t;      /* o.tuning's values, or the defaults */
    rf_fem3d_options o3;
    rf_hertz_reference H;
    f3_material mat[3];   /* boulder, slope (the bedrock under a layer), layer */
    rf_wave_speeds w[3];
    rf_material matl[3];  /* constitutive law of each (plastic[b] != 0: not elastic) */
    fem_lame lame[3];     /* parameters of the linear point laws (kernel = points) */
    int plastic[3], work_account; /* work_account: energies from the internal work (a plastic body) */
    int large;            /* large deformation (rf_fem_large_deformation); work_account then too */
    int ul[2];            /* body b on the updated-Lagrangian kernel: large and (on, or the body plastic) */
    unsigned char *ul_elem; /* large: per element, on the UL kernel (the step check watches those) */
    f3_step_check step_check; /* large: the elements' step bounds at their current size */
    double *lamu;         /* large: each element's Gershgorin bound of lambda_max (reference geometry) */
    double *mshift;       /* per node: mass added by the contact face's redistribution [kg, model] (or NULL) */
    long shifted_elems;   /* contact-face elements whose masses were redistributed */
    long unstable;        /* large: an element whose current step bound fell below dt (-1: none) */
    int layer, rigid;     /* a layer over the slope (fem3d_layer.c); a rigid boulder (fem3d_rigid.c) */
    double a_box;         /* contact radius the fine boxes cover (the larger of slope and layer) [m] */
    f3_layer_contact lc;  /* the layer's contact estimate (fem3d_spec.h); lc.thick: it alone sizes the mesh */
    unsigned char *emat;  /* material of each element: 0 boulder, 1 slope, 2 layer */
    double *dashl, *dnrm; /* layer faces' dashpot areas; outer normals (extruded mesh) */
    double dash_ratio;    /* largest dt C / m of an explicit dashpot (stable below 2) */
    f3_rigid B;
    f3_gravity grav;      /* gravity (fem3d_gravity.c); grav.g = 0: none */
    double sep_v[3], sep_w; /* with gravity: CM velocity (x, y, z) and spin when the contact last opened */
    double W_int[2];      /* internal work of each body so far [J] (model, not full body) */
    double depth_max;     /* deepest position of the boulder's lowest point below z = 0 [m] */
    long crater_node;     /* the slope's surface node at the first-contact point */
    double V, Vn, Vt, L, h, hb, sym_factor;
    f3_mesh_spec ms;
    f3_mesh mesh;
    int have_mesh, threads, fixed_outer, mass_moments_ok;
    int no_contact;       /* fem3d_gravity_free_run: no contact step */
    long nn, ne, ndof, nbn;
    f3_system S;
    float *K;
    double *u, *v, *f, *fext, *mass, *invm, *dash, *elm, *lamx;
    unsigned char *fixed;
    int *outer;
    long nouter;
    double dt, dt_bound, dt_edge, mesh_mass_b, Mb, ke0;
    f3_contact C;
    /* account of the contact over the run */
    double W_n, W_fric, W_abs, pen_max, slip_max, pgs_res_max;
    long stick_steps, pair_steps;
    int pgs_sweeps_max, outside_contact;
    long unlocated_steps; /* pair-steps in contact whose master point was not found to tolerance */
    fem_pool *pool;
} solid_run;

/* A layer over the slope: as the axisymmetric solver (fem_solver.c), the
 * mesh sized for the finer of the two contacts (slope's and layer's Hertz
 * radius), its fine boxes covering the larger, the run as long as the longer
 * Hertz duration; but a thick layer (the boulder stays in it,
 * f3_layer_contact_estimate) sizes all three from its own contact.  The
 * layer's wave speeds. */
static rf_status solid_prepare_layer(solid_run *R, rf_error *err)
{
    const rf_impact_input *in = R->in;
    R->layer = in->layer_thickness > 0;
    if (!R->layer)
        return RF_OK;
    if (!(in->layer_thickness < 0.5 * R->L))
        return rf_fail(err, RF_EINVAL,
                       "fem3d: layer_thickness = %g m must be below half the domain radius (%g m): raise domain_factor",
                       in->layer_thickness, R->L);
    rf_impact_input lay = *in;
    lay.slope_density = in->layer_density, lay.slope_E = in->layer_E, lay.slope_poisson = in->layer_poisson;
    rf_hertz_reference HL;
    rf_impact_hertz_reference(&lay, &HL);
    R->a_box = fmax(R->H.contact_radius, HL.contact_radius);
    R->H.contact_radius = fmin(R->H.contact_radius, HL.contact_radius);
    R->H.duration = fmax(R->H.duration, HL.duration);
    rf_impact_wave_speeds(&lay, 1, &R->w[2]);
    f3_layer_contact_estimate(in, &R->lc);
    if (R->lc.thick) { /* the boulder stays in the layer: its contact alone sizes the mesh and the run */
        R->H.contact_radius = R->lc.radius, R->H.duration = R->lc.duration;
        R->a_box = fmax(R->lc.radius, R->lc.zone_radius / R->o3.fine_box_factor);
    }
    return RF_OK;
}

/* Check, resolve the automatic settings, Hertz reference with the normal
 * velocity component. */
static rf_status solid_prepare(solid_run *R, const rf_impact_input *in, const rf_fem_options *opt,
                               const rf_fem3d_options *o3p, rf_error *err)
{
    R->in = in;
    if (opt)
        R->o = *opt;
    else
        rf_fem_options_default(&R->o);
    if (o3p)
        R->o3 = *o3p;
    else
        rf_fem3d_options_default(&R->o3);
    R->t = *fem_tuning_of(&R->o);
    rf_status st = check_input(in, &R->o, &R->o3, err);
    if (st != RF_OK)
        return st;
    R->o.refinement = rf_fem_refinement(&R->o, 1);
    R->o.domain_factor = rf_fem_domain_factor(&R->o, in);
    rf_impact_hertz_reference(in, &R->H);
    R->V = in->velocity, R->Vn = R->H.normal_velocity, R->Vt = R->H.tangential_velocity;
    R->L = R->o.domain_factor * in->radius;
    R->mat[0] = (f3_material){in->boulder_density, in->boulder_E, in->boulder_poisson};
    R->mat[1] = (f3_material){in->slope_density, in->slope_E, in->slope_poisson};
    R->mat[2] = (f3_material){in->layer_density, in->layer_E, in->layer_poisson};
    rf_impact_wave_speeds(in, 0, &R->w[0]);
    rf_impact_wave_speeds(in, 1, &R->w[1]);
    R->w[2] = R->w[1];
    R->rigid = in->boulder_material == RF_MATERIAL_RIGID_BODY;
    R->a_box = R->H.contact_radius;
    if ((st = solid_prepare_layer(R, err)) != RF_OK)
        return st;
    R->threads = R->o.threads > 0 ? R->o.threads : 1;
#ifndef _OPENMP
    R->threads = 1;
#endif
    R->o.boundary = rf_fem_boundary_resolve(R->o.boundary, in); /* the axisymmetric model's rule */
    R->fixed_outer = R->o.boundary == RF_FEM_BOUNDARY_FIXED;
    for (int b = 0; b < 3; b++) {
        rf_material_params p;
        if (b == 2 && !R->layer) { /* no layer: its (unchecked) inputs are not used */
            R->matl[2] = R->matl[1], R->plastic[2] = 0;
            continue;
        }
        rf_impact_material_params(in, b, &p);
        if ((st = rf_material_init(&R->matl[b], &p, err)) != RF_OK) /* validated above: cannot fail */
            return rf_error_prefix(err, "fem3d");
        R->plastic[b] = p.model != RF_MATERIAL_ELASTIC && !(b == 0 && R->rigid);
    }
    R->work_account = R->plastic[0] || R->plastic[1] || R->plastic[2];
    R->large = rf_fem_large_deformation(&R->o, in);
    R->work_account |= R->large; /* the energy from the internal work: no K in updated Lagrangian */
    /* auto leaves an elastic body on its small-strain kernel: its strains stay ~a/r0 (section 9c) */
    const int all = R->o.large_deformation == RF_FEM_LARGE_DEFORMATION;
    R->ul[0] = R->large && !R->rigid && (all || R->plastic[0]);
    R->ul[1] = R->large && (all || R->plastic[1] || R->plastic[2]);
    /* gravity: the energy from the internal work (the slope's geostatic pre-stress is not in 1/2 u' K u) */
    R->grav.g = rf_impact_gravity(in, 1);
    R->work_account |= R->grav.g > 0;
    double fs;
    return R->grav.g > 0 ? f3_gravity_stability(in, R->grav.g, R->L, &fs, err) : RF_OK;
}

/* The boulder's fine box in its half-space image.  An elastic boulder: at most
 * 0.6 r0 long (its elements must stay near the contact, where the inversion
 * keeps their size).  A rigid one carries only the contact's slave nodes: the
 * box may cover the whole lower half of the ball; its farthest corner must
 * leave room for the graded layers out to boulder_inner * r0. */
static rf_status boulder_box_fits(const solid_run *R, rf_error *err)
{
    const f3_box *b = &R->ms.boulder;
    const double r0 = R->in->radius;
    if (R->rigid) {
        const int nx = b->nxm > b->nxp ? b->nxm : b->nxp;
        const double corner = b->h * sqrt((double)nx * nx + (double)b->ny * b->ny + (double)b->nz * b->nz);
        if (corner > 0.8 * R->o3.boulder_inner * r0)
            return rf_fail(err, RF_EINVAL,
                           "fem3d: the rigid boulder's fine zone (corner %.3g m in its half-space image) needs "
                           "boulder_inner >= %.3g (got %g); lower the impact speed or take a stiffer layer",
                           corner, corner / (0.8 * r0), R->o3.boulder_inner);
        return RF_OK;
    }
    const double box_b = (b->nxp + b->nxm) * b->h;
    if (box_b > 0.6 * r0)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: the fine zone (%.3g m) does not fit the boulder (r0 = %g m): the contact radius "
                       "%.3g m%s is too large for an elastic boulder; lower the impact speed, or "
                       "take boulder_material rigid",
                       box_b, r0, R->a_box, R->layer ? " (the larger of the slope's and the layer's)" : "");
    return RF_OK;
}

/* Sizing and meshing: fine boxes of uniform cubes over core_factor * a,
 * elongated down-slope by the patch travel; graded layers out to L. */
static rf_status solid_mesh(solid_run *R, rf_error *err)
{
    const rf_fem_options *o = &R->o;
    const rf_fem3d_options *o3 = &R->o3;
    const double a_h = R->H.contact_radius, c = R->H.c, d = R->H.d, r0 = R->in->radius;
    R->h = a_h / o->refinement, R->hb = R->h * R->t.boulder_mesh_ratio;
    const double h = R->h, hb = R->hb, travel = o3->elongation * R->Vt * R->H.duration;
    f3_mesh_spec *ms = &R->ms;
    memset(ms, 0, sizeof *ms);
    ms->full = o3->full_model != 0;
    const double a_x = R->a_box; /* = a_h without a layer */
    int n_s = (int)ceil(o3->fine_box_factor * a_x / h - 1e-9), n_b = (int)ceil(o3->fine_box_factor * a_x / hb - 1e-9);
    ms->slope = (f3_box){n_s, n_s + (int)ceil(travel / h - 1e-9), n_s, n_s, h};
    ms->extruded = R->layer || o3->layered_mesh;
    ms->layer_depth = R->layer ? R->in->layer_thickness : 0;
    if (R->layer && R->in->layer_thickness < h)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: layer_thickness = %g m is thinner than the element at the contact (h = %g m): raise "
                       "refinement or the thickness", R->in->layer_thickness, h);
    /* the boulder's half-space image is scaled by c (x, y) and d (z) afterwards */
    const double sxy = c / r0, sz = d / r0, hb0 = hb / sxy;
    ms->boulder = (f3_box){n_b, n_b + (int)ceil(travel / hb - 1e-9), n_b, n_b, hb0};
    if (R->rigid && R->lc.thick)
        f3_soft_boulder_box(&ms->boulder, o3->fine_box_factor * a_x, travel, r0, sxy);
    ms->radius = r0;
    ms->scale_xy = sxy, ms->scale_z = sz;
    ms->boulder_inner = o3->boulder_inner;
    ms->domain = R->L;
    ms->layer_aspect = o3->layer_aspect;
    rf_status st = boulder_box_fits(R, err);
    if (st != RF_OK)
        return st;
    if ((ms->slope.nxm + ms->slope.nxp) * h * 4 > R->L)
        return rf_fail(err, RF_EINVAL, "fem3d: domain radius %g m is too small for the fine zone", R->L);
    st = f3_mesh_build(ms, &R->mesh, R->t.max_elements, err);
    R->have_mesh = st == RF_OK;
    return st;
}

static rf_status solid_alloc(solid_run *R, rf_error *err)
{
    fem_pool *P = R->pool;
    const size_t nn = (size_t)R->nn, ne = (size_t)R->ne, nd = (size_t)R->ndof;
    f3_system *S = &R->S;
    S->fel = fem_pool_get(P, Q_FEL, 3 * (size_t)R->nbn * sizeof(double), 0);
    S->ub = fem_pool_get(P, Q_UB, 3 * (size_t)R->nbn * sizeof(double), 0);
    R->K = fem_pool_get(P, Q_K, ne * 576 * sizeof(float), 0);
    S->fe = fem_pool_get(P, Q_FE, ne * 24 * sizeof(double), 0);
    S->inc_ptr = fem_pool_get(P, Q_INC_PTR, (nn + 1) * sizeof(long), 1);
    S->inc = fem_pool_get(P, Q_INC, ne * 8 * sizeof(long), 0);
    R->u = fem_pool_get(P, Q_U, nd * sizeof(double), 1);
    R->v = fem_pool_get(P, Q_V, nd * sizeof(double), 1);
    R->f = fem_pool_get(P, Q_F, nd * sizeof(double), 1);
    R->fext = fem_pool_get(P, Q_FEXT, nd * sizeof(double), 1);
    R->mass = fem_pool_get(P, Q_MASS, nd * sizeof(double), 1);
    R->invm = fem_pool_get(P, Q_INVM, nd * sizeof(double), 1);
    R->dash = fem_pool_get(P, Q_DASH, nn * sizeof(double), 1);
    R->elm = fem_pool_get(P, Q_ELM, ne * 8 * sizeof(double), 0);
    R->lamx = fem_pool_get(P, Q_LAMX, ne * sizeof(double), 0);
    R->fixed = fem_pool_get(P, Q_FIXED, nd, 1);
    R->outer = fem_pool_get(P, Q_OUTER, nn * sizeof(int), 0);
    R->emat = fem_pool_get(P, Q_EMAT, ne, 0);
    R->dashl = fem_pool_get(P, Q_DASHL, nn * sizeof(double), 1);
    R->dnrm = fem_pool_get(P, Q_DNRM, 3 * nn * sizeof(double), 1);
    if (!R->emat || !R->dashl || !R->dnrm)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", R->ne);
    if (!R->K || !S->fe || !S->fel || !S->ub || !S->inc_ptr || !S->inc || !R->u || !R->v || !R->f || !R->fext || !R->mass ||
        !R->invm || !R->dash || !R->elm || !R->lamx || !R->fixed || !R->outer)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", R->ne);
    return RF_OK;
}

/* Incidence lists in element order; constraints: symmetry plane u_y = 0,
 * fixed outer surface. */
static void solid_topology(solid_run *R)
{
    f3_system *S = &R->S;
    const f3_mesh *mesh = &R->mesh;
    for (long e = 0; e < R->ne; e++)
        for (int a = 0; a < 8; a++)
            S->inc_ptr[mesh->conn[8 * e + a] + 1]++;
    for (long n = 0; n < R->nn; n++)
        S->inc_ptr[n + 1] += S->inc_ptr[n];
    for (long e = 0; e < R->ne; e++) /* fill in element order, then restore the pointers */
        for (int a = 0; a < 8; a++)
            S->inc[S->inc_ptr[mesh->conn[8 * e + a]]++] = e * 8 + a;
    for (long n = R->nn; n > 0; n--)
        S->inc_ptr[n] = S->inc_ptr[n - 1];
    S->inc_ptr[0] = 0;
    R->nouter = 0;
    for (long i = 0; i < R->nn; i++) {
        if (mesh->flags[i] & F3_SYM)
            R->fixed[3 * i + 1] = 1;
        if (i >= R->nbn && (mesh->flags[i] & F3_OUTER)) {
            R->outer[R->nouter++] = (int)i;
            if (R->fixed_outer)
                R->fixed[3 * i] = R->fixed[3 * i + 1] = R->fixed[3 * i + 2] = 1;
        }
    }
}

/* Element stiffness (stored in float for the kernel) and lumped masses,
 * independent per element. */
static rf_status solid_elements(solid_run *R, rf_error *err)
{
    const f3_mesh *mesh = &R->mesh;
    int bad_elem = 0;
    double *vols = R->lamx; /* reuse: element volumes */
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(R->threads) reduction(| : bad_elem)
#endif
    for (long e = 0; e < R->ne; e++) {
        double xe[24];
        const int *cn = mesh->conn + 8 * e;
        for (int a = 0; a < 8; a++)
            for (int q = 0; q < 3; q++)
                xe[3 * a + q] = mesh->x[3 * cn[a] + q];
        double Kd[576];
        f3_hex_matrices(xe, &R->mat[R->emat[e]], Kd, R->elm + 8 * e, &vols[e]);
        for (int q = 0; q < 576; q++)
            R->K[576 * e + q] = (float)Kd[q];
        for (int a = 0; a < 8; a++)
            if (!(R->elm[8 * e + a] > 0))
                bad_elem |= 1;
    }
    if (bad_elem)
        return rf_fail(err, RF_EINTERNAL, "fem3d mesh: an element has a non-positive nodal mass (distorted hexahedron)");
    return RF_OK;
}

/* The lumped masses of the faceted boulder with the spheroid's mass, centre
 * (0, ., d) and I_yy (fem3d_mass.c, docs/fem-speed.md section 5). */
static void boulder_inertia(solid_run *R)
{
    const double M = R->H.mass / R->sym_factor, I = M * (R->H.c * R->H.c + R->H.d * R->H.d) / 5;
    R->mass_moments_ok = f3_boulder_mass_moments(&R->mesh, R->elm, M, 0, R->H.d, I);
}

/* Element e's free dofs and double stiffness (from the stored float K). */
static void element_free_k(const solid_run *R, long e, unsigned char fr[24], double Kd[576])
{
    const int *cn = R->mesh.conn + 8 * e;
    for (int a = 0; a < 8; a++)
        for (int q = 0; q < 3; q++)
            fr[3 * a + q] = !R->fixed[3 * cn[a] + q];
    for (int q = 0; q < 576; q++)
        Kd[q] = R->K[576 * e + q];
}

/* Element e as hex8_max_eigenvalue takes it (ctx: the run). */
static void solid_element(void *ctx, long e, double K[576], double m[8], unsigned char fr[24])
{
    const solid_run *R = ctx;
    element_free_k(R, e, fr, K);
    if (R->rigid && e < R->mesh.boulder_elems) /* no stiffness: the slope alone sets the step */
        memset(K, 0, 576 * sizeof *K);
    memcpy(m, R->elm + 8 * e, 8 * sizeof *m);
}

/* max_e lambda_max(M_e^-1 K_e), with the exact eigen-solve pruned by
 * Gershgorin bounds (hex8_step.c, docs/fem-speed.md plan step 6): bit for bit
 * the maximum over every element, at ~1 % of the solves. */
static double solid_lambda_max(solid_run *R, double *lam_upper)
{
    return hex8_max_eigenvalue(R->ne, solid_element, R, lam_upper, NULL);
}

/* Node n's lumped mass: the sum of its element-node masses (incidence order). */
static double node_mass(const solid_run *R, long n)
{
    double m = 0;
    for (long p = R->S.inc_ptr[n]; p < R->S.inc_ptr[n + 1]; p++)
        m += R->elm[R->S.inc[p]];
    return m;
}

/* The mass redistribution at the slope's contact face (fem3d_mass.c): the nodes of the master
 * grid, the element-node masses and the nodal masses again; mshift = each node's change. */
static void surface_mass_shift(solid_run *R, double *lam_upper, double lam_max)
{
    unsigned char *face = calloc((size_t)R->nn, 1);
    R->mshift = fem_pool_get(R->pool, Q_MSHIFT, (size_t)R->nn * sizeof(double), 1);
    if (!face || !R->mshift) { /* without memory the masses stay lumped as they are */
        free(face);
        R->mshift = NULL;
        return;
    }
    for (long k = 0; k < (long)R->mesh.nxt_s * R->mesh.nyt_s; k++)
        face[R->mesh.top_s[k]] = !(R->mesh.flags[R->mesh.top_s[k]] & F3_OUTER);
    R->shifted_elems = f3_surface_mass_shift(&R->mesh, face, R->elm, lam_upper, lam_max, R->t.surface_mass_kappa);
    free(face);
    for (long n = R->nbn; n < R->nn && R->shifted_elems > 0; n++) {
        const double m = node_mass(R, n);
        R->mshift[n] = m - R->mass[3 * n];
        for (int q = 0; q < 3; q++) {
            R->mass[3 * n + q] = m;
            R->invm[3 * n + q] = R->fixed[3 * n + q] ? 0 : 1 / m;
        }
    }
}

/* Nodal masses (the boulder's density scaled so that the rigid-body mass is
 * exact: its mesh is a polyhedron inside the spheroid), the largest element
 * eigenvalue and the time step. */
static void solid_masses(solid_run *R)
{
    const f3_mesh *mesh = &R->mesh;
    R->mesh_mass_b = 0;
    for (long e = 0; e < mesh->boulder_elems; e++)
        for (int a = 0; a < 8; a++)
            R->mesh_mass_b += R->elm[8 * e + a];
    R->sym_factor = R->ms.full ? 1.0 : 2.0;
    const double mscale = R->H.mass / R->sym_factor / R->mesh_mass_b;
    for (long e = 0; e < mesh->boulder_elems * 8; e++)
        R->elm[e] *= mscale;
    boulder_inertia(R);
    for (long n = 0; n < R->nn; n++)
        R->mass[3 * n] = R->mass[3 * n + 1] = R->mass[3 * n + 2] = node_mass(R, n);
    for (long dd = 0; dd < R->ndof; dd++)
        R->invm[dd] = R->fixed[dd] ? 0 : 1 / R->mass[dd];
    double *lam_upper = fem_pool_get(R->pool, Q_LAMU, (size_t)R->ne * sizeof(double), 0);
    const double lam_max = solid_lambda_max(R, lam_upper);
    if (lam_upper && R->t.surface_mass_kappa > 0 && R->t.surface_mass_3d && (R->layer || R->plastic[1])) /* 9e */
        surface_mass_shift(R, lam_upper, lam_max);
    R->lamu = R->large ? lam_upper : NULL;
    R->dt_edge = DBL_MAX;
    static const int ed[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (long e = 0; e < R->ne; e++) {
        const int *cn = mesh->conn + 8 * e;
        const int b = R->emat[e];
        if (R->rigid && b == 0)
            continue;
        for (int k = 0; k < 12; k++) {
            const double *p = mesh->x + 3 * cn[ed[k][0]], *q = mesh->x + 3 * cn[ed[k][1]];
            double l = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
            if (l / R->w[b].p < R->dt_edge)
                R->dt_edge = l / R->w[b].p;
        }
    }
    R->dt = fem_time_step(lam_max, R->t.dt_safety, &R->dt_bound);
}

/* The largest dt C / m of the explicit dashpots (stable below 2): C = the
 * node's tributary area times rho c_p of its faces' material. */
static void solid_dashpot_check(solid_run *R)
{
    R->dash_ratio = 0;
    for (long k = 0; k < R->nouter; k++) {
        const int i = R->outer[k];
        const double C = R->dash[i] * R->mat[1].rho * R->w[1].p + R->dashl[i] * R->mat[2].rho * R->w[2].p;
        if (R->dt * C / R->mass[3 * i] > R->dash_ratio)
            R->dash_ratio = R->dt * C / R->mass[3 * i];
    }
}

/* Dashpots on the outer surface (Lysmer & Kuhlemeyer 1969): tributary areas
 * (a layer's faces apart, with its own impedance), and the outer normals of
 * the extruded mesh (summed face normals). */
static void solid_dashpots(solid_run *R)
{
    if (R->fixed_outer)
        return;
    const f3_mesh *mesh = &R->mesh;
    for (long q = 0; q < mesh->n_outer_quads; q++) {
        const int *qn = mesh->outer_quads + 4 * q;
        /* a quad whose 4 nodes lie in the layer (z >= -thickness) has the layer's impedance */
        int in_layer = R->layer;
        for (int a = 0; a < 4 && in_layer; a++)
            in_layer = mesh->x[3 * qn[a] + 2] >= -R->in->layer_thickness * (1 + 1e-12);
        double *area_to = in_layer ? R->dashl : R->dash;
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
            for (int d = 0; d < 3; d++) /* outward: away from the contact point at the origin */
                R->dnrm[3 * qn[a] + d] += (cr[0] * p0[0] + cr[1] * p0[1] + cr[2] * p0[2] > 0 ? 0.5 : -0.5) * cr[d];
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
static void solid_release(solid_run *R)
{
    contact_release(&R->C);
    f3_step_check_free(&R->step_check);
    fem_kernel_release(&R->S.kernel[0]);
    fem_kernel_release(&R->S.kernel[1]);
    if (R->have_mesh)
        f3_mesh_free(&R->mesh);
}

/* Contact: slaves are the boulder's fine-box face nodes; in sphere mode (a rigid sphere with
   sphere_contact_3d) the slope's, against the exact sphere. */
static rf_status solid_contact_setup(solid_run *R, rf_error *err)
{
    f3_contact *C = &R->C;
    C->sphere = R->t.sphere_contact_3d && R->rigid && R->H.c == R->H.d;
    C->radius = R->H.d;
    const size_t ns = C->sphere ? (size_t)R->mesh.nxt_s * (size_t)R->mesh.nyt_s
                                : (size_t)R->mesh.nxt_b * (size_t)R->mesh.nyt_b;
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
    C->du = calloc((size_t)R->ndof, sizeof *C->du);
    if (!C->slave || !C->lam || !C->mnode || !C->N || !C->S || !C->gap || !C->ds || !C->s0 || !C->A || !C->gvo ||
        !C->Xm || !C->outside || !C->cand || !C->du)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    if (C->sphere && !(C->wr = calloc(ns * 9, sizeof *C->wr)))
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    memcpy(C->slave, C->sphere ? R->mesh.top_s : R->mesh.top_b, ns * sizeof *C->slave);
    for (size_t k = 0; k < ns; k++)
        C->Xm[2 * k] = R->mesh.x[3 * C->slave[k]], C->Xm[2 * k + 1] = R->mesh.x[3 * C->slave[k] + 1];
    C->friction = R->in->friction;
    C->tol = 1e-9 * R->h;
    C->band = 0.5 * fmin(R->h, R->hb) + 2 * R->V * R->dt;
    C->max_sweeps = 2000;
    /* the first-contact point is the slope frame's origin: the nearest node of the slope's top grid */
    const double hs = R->mesh.h_s;
    long i = lround(-R->mesh.x0_s / hs), j = lround(-R->mesh.y0_s / hs);
    i = i < 0 ? 0 : i >= R->mesh.nxt_s ? R->mesh.nxt_s - 1 : i;
    j = j < 0 ? 0 : j >= R->mesh.nyt_s ? R->mesh.nyt_s - 1 : j;
    R->crater_node = R->mesh.top_s[i * R->mesh.nyt_s + j];
    return RF_OK;
}

/* The linear point law of material b (0 boulder, 1 slope, 2 layer; lame[b] filled). */
static fem_point_law solid_point_law(solid_run *R, int b)
{
    const f3_material *m = &R->mat[b];
    R->lame[b] = (fem_lame){m->E * m->nu / ((1 + m->nu) * (1 - 2 * m->nu)), m->E / (2 * (1 + m->nu))};
    return fem_point_law_linear3d(&R->lame[b]);
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
        use2[e] = R->emat[first + e] == 2;
    const int plastic = R->plastic[1] || R->plastic[2];
    /* one shape for both laws: the material library's return maps (an elastic one among them) if either
       is plastic, else the linear law */
    const fem_point_law law = plastic ? fem_point_law_material3d(&R->matl[1]) : solid_point_law(R, 1);
    const fem_point_law law2 = plastic ? fem_point_law_material3d(&R->matl[2]) : solid_point_law(R, 2);
    return fem_kernel_points_hex(&R->S.kernel[F3_SLOPE], first, count, R->mesh.x, R->mesh.conn, &law, &law2, use2,
                                 plastic, err);
}

/* The material of each element (0 boulder, 1 slope, 2 layer: a slope
 * element above the layer's node plane); fails if no element is in the layer. */
static rf_status solid_materials(solid_run *R, rf_error *err)
{
    long nlayer = 0;
    for (long e = 0; e < R->ne; e++) {
        const int *c = R->mesh.conn + 8 * e;
        double zc = 0;
        for (int a = 0; a < 8; a++)
            zc += R->mesh.x[3 * c[a] + 2] / 8;
        R->emat[e] = e < R->mesh.boulder_elems ? 0 : R->layer && zc > -R->in->layer_thickness ? 2 : 1;
        nlayer += R->emat[e] == 2;
    }
    if (R->layer && nlayer == 0)
        return rf_fail(err, RF_EINVAL, "fem3d: layer_thickness = %g m has no element (h = %g m)",
                       R->in->layer_thickness, R->h);
    return RF_OK;
}

/* The rigid boulder's state (at rest relative to its initial translation)
 * and its coupling into the contact: exact model mass and I_yy, no inverse
 * mass of its own nodes. */
static rf_status solid_rigid_setup(solid_run *R, rf_error *err)
{
    if (!R->rigid)
        return RF_OK;
    f3_rigid *B = &R->B;
    B->on = 1;
    B->M = R->H.mass / R->sym_factor;
    B->I = B->M * (R->H.c * R->H.c + R->H.d * R->H.d) / 5;
    memcpy(B->c0, R->S.c0, sizeof B->c0);
    B->V[0] = R->Vt, B->V[1] = -R->Vn;
    for (long dd = 0; dd < 3 * R->nbn; dd++)
        R->invm[dd] = 0;
    f3_contact *C = &R->C;
    C->rigid_invm = 1 / B->M, C->rigid_invi = 1 / B->I;
    if (!(C->rr = calloc((size_t)C->nslave * 2, sizeof *C->rr)))
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    f3_rigid_place(B, &R->mesh, R->nbn, R->u, R->v);
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
    f3_system *S = &R->S;
    const long nbe = R->mesh.boulder_elems;
    const int store_j = R->ne <= F3_STORE_J_MAX;
    for (int b = 0; b < 2; b++) {
        const f3_material *m = &R->mat[b];
        const double lam = m->E * m->nu / ((1 + m->nu) * (1 - 2 * m->nu)), mu = m->E / (2 * (1 + m->nu));
        const long first = b == F3_BOULDER ? 0 : nbe, count = b == F3_BOULDER ? nbe : R->ne - nbe;
        rf_status st;
        if (b == F3_BOULDER && R->rigid) {
            f3_rigid_kernel(&S->kernel[b], first, count, S->fe);
            continue;
        }
        if (b == F3_SLOPE && R->layer)
            st = solid_layer_kernel(R, first, count, err);
        else if (R->plastic[b]) {
            const fem_point_law law = fem_point_law_material3d(&R->matl[b]);
            st = fem_kernel_points_hex(&S->kernel[b], first, count, R->mesh.x, R->mesh.conn, &law, NULL, NULL, 1,
                                       err);
        } else if (R->t.kernel[b] == RF_FEM_KERNEL_POINTS || R->ul[b]) {
            R->lame[b] = (fem_lame){lam, mu};
            const fem_point_law law = fem_point_law_linear3d(&R->lame[b]);
            st = fem_kernel_points_hex(&S->kernel[b], first, count, R->mesh.x, R->mesh.conn, &law, NULL, NULL, 0,
                                       err);
        } else
            st = fem_kernel_hex8_matfree(&S->kernel[b], first, count, R->mesh.x, R->mesh.conn, lam, mu, store_j,
                                         err);
        if (st == RF_OK && R->ul[b]) /* (an elastic body: the linear, hypoelastic, law on the current geometry) */
            st = fem_kernel_points_hex_large(&S->kernel[b], R->mesh.x, err);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

/* Large deformation: the step check watches the elements on the UL kernel. */
static rf_status solid_step_check(solid_run *R, rf_error *err)
{
    R->ul_elem = fem_pool_get(R->pool, Q_ULE, (size_t)R->ne + 1, 0);
    if (!R->lamu || !R->ul_elem)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for %ld elements", R->ne);
    for (long e = 0; e < R->ne; e++)
        R->ul_elem[e] = (unsigned char)R->ul[e < R->mesh.boulder_elems ? F3_BOULDER : F3_SLOPE];
    return f3_step_check_init(&R->step_check, &R->mesh, R->ne, R->ul_elem, R->lamu, solid_element, R, err);
}

/* Assembly: arrays, topology, elements, masses and time step, material
 * kernels (one block per body), dashpots, contact, and the
 * initial state (boulder translating at (V sin alpha, 0, -V cos alpha) in the
 * slope frame). */
static rf_status solid_assemble(solid_run *R, rf_error *err)
{
    R->nn = R->mesh.n_nodes, R->ne = R->mesh.n_elems, R->ndof = 3 * R->nn, R->nbn = R->mesh.boulder_nodes;
    f3_system *S = &R->S;
    S->nn = R->nn, S->ne = R->ne, S->ndof = R->ndof, S->nbn = R->nbn, S->mesh = &R->mesh;
    S->threads = R->threads, S->full = R->ms.full;
    rf_status st = solid_alloc(R, err);
    if (st != RF_OK)
        return st;
    solid_topology(R);
    if ((st = solid_materials(R, err)) != RF_OK || (st = solid_elements(R, err)) != RF_OK)
        return st;
    solid_masses(R);
    if (!R->mass_moments_ok)
        return rf_fail(err, RF_EINTERNAL, "fem3d: no positive boulder mass weighting with the spheroid's moments");
    if ((st = solid_kernels(R, err)) != RF_OK)
        return st;
    if (R->large && (st = solid_step_check(R, err)) != RF_OK)
        return st;
    solid_dashpots(R);
    if (R->dash_ratio >= 2)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: the absorbing boundary is unstable here (dt C / m = %.3g >= 2 on an outer node of a "
                       "light layer); use boundary: fixed", R->dash_ratio);
    if ((st = solid_contact_setup(R, err)) != RF_OK)
        return st;
    for (long i = 0; i < R->nbn; i++)
        R->v[3 * i] = R->Vt, R->v[3 * i + 2] = -R->Vn;
    double Mb = 0;
    for (long i = 0; i < R->nbn; i++)
        Mb += R->mass[3 * i];
    R->Mb = Mb;
    R->ke0 = 0.5 * Mb * R->V * R->V; /* of the model (half of the boulder in the half model) */
    S->mass = R->mass, S->Mb = Mb;
    for (long i = 0; i < R->nbn; i++)
        for (int q = 0; q < 3; q++)
            S->c0[q] += R->mass[3 * i] * R->mesh.x[3 * i + q] / Mb;
    if (!R->ms.full)
        S->c0[1] = 0;
    if ((st = solid_rigid_setup(R, err)) != RF_OK || !(R->grav.g > 0))
        return st;
    double *fgrav = fem_pool_get(R->pool, Q_FGRAV, (size_t)R->ndof * sizeof(double), 1);
    if (!fgrav)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    return f3_gravity_setup(&R->grav, S, R->in, R->matl, R->plastic, R->u, fgrav, err);
}

/* Dashpot forces from v_{n-1/2}: normal rho c_p v_n, shear rho c_s v_s,
 * radial normal; returns half of their work with v_{n-1/2}. */
static double solid_dashpot_forces(solid_run *R)
{
    double W = 0;
    if (R->fixed_outer)
        return 0;
    const double rho = R->mat[1].rho, cp = R->w[1].p, cs = R->w[1].s;
    const double rl = R->mat[2].rho, cpl = R->w[2].p, csl = R->w[2].s;
    for (long k = 0; k < R->nouter; k++) {
        int i = R->outer[k];
        const double *x = R->mesh.extruded ? R->dnrm + 3 * i : R->mesh.x + 3 * i, *v = R->v + 3 * i;
        double *fx = R->fext + 3 * i;
        double rr = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        double nv[3] = {x[0] / rr, x[1] / rr, x[2] / rr};
        double vn = v[0] * nv[0] + v[1] * nv[1] + v[2] * nv[2];
        for (int q = 0; q < 3; q++)
            fx[q] = -R->dash[i] * rho * (cp * vn * nv[q] + cs * (v[q] - vn * nv[q]));
        if (R->layer)
            for (int q = 0; q < 3; q++)
                fx[q] -= R->dashl[i] * rl * (cpl * vn * nv[q] + csl * (v[q] - vn * nv[q]));
        for (int q = 0; q < 3; q++)
            if (R->fixed[3 * i + q])
                fx[q] = 0;
        for (int q = 0; q < 3; q++)
            W -= 0.5 * R->dt * fx[q] * v[q];
    }
    return W;
}

/* 1 if slave k (top_b order) is on the edge of the boulder's fine box: soil
 * beyond it would meet no slave (the contact has outgrown the fine zone). */
static int slave_on_edge(const f3_mesh *mesh, int full, int sphere, long k)
{
    const long nx = sphere ? mesh->nxt_s : mesh->nxt_b, ny = sphere ? mesh->nyt_s : mesh->nyt_b;
    const long i = k / ny, j = k % ny;
    return i == 0 || i == nx - 1 || j == ny - 1 || (full && j == 0);
}

/* Contact force, work, radius (force-weighted second moment: <rho^2> = 0.4 a^2
 * for Hertz) and the statistics of the step's closed pairs. */
static double solid_contact_account(solid_run *R, double *rad)
{
    const f3_contact *C = &R->C;
    const double dt = R->dt, *u = R->u;
    double Fc = 0, sx = 0, sy = 0, sxx = 0;
    for (long q = 0; q < C->ncand; q++) {
        long k = C->cand[q];
        const double *lam = C->lam + 3 * k;
        if (lam[0] <= 0)
            continue;
        int s = C->slave[k];
        double gvn[3];
        double gvo[3];
        f3_contact_gv(C, k, R->v, gvn);
        f3_contact_gvo(C, k, gvo);
        R->W_n += lam[0] * dt * (gvn[0] + gvo[0]) / 2;
        R->W_fric -= (lam[1] * (gvn[1] + gvo[1]) + lam[2] * (gvn[2] + gvo[2])) * dt / 2;
        double slip = hypot(gvn[1], gvn[2]) * dt;
        if (slip > R->slip_max)
            R->slip_max = slip;
        R->pair_steps++;
        double Fn, Ft;
        f3_contact_forces(C, k, &Fn, &Ft);
        if (Ft < (1 - 1e-9) * C->friction * Fn)
            R->stick_steps++;
        if (C->outside[k] == 1 || slave_on_edge(&R->mesh, R->ms.full, C->sphere, k))
            R->outside_contact = 1;
        if (C->outside[k] == 2)
            R->unlocated_steps++;
        double X = R->mesh.x[3 * s] + u[3 * s], Y = R->mesh.x[3 * s + 1] + u[3 * s + 1];
        Fc += lam[0];
        sx += lam[0] * X;
        sy += lam[0] * Y;
        sxx += lam[0] * (X * X + Y * Y);
    }
    *rad = 0;
    if (Fc > 0) {
        double mx = sx / Fc, my = R->ms.full ? sy / Fc : 0;
        double var = sxx / Fc - mx * mx - my * my;
        *rad = sqrt(fmax(0, 2.5 * var));
    }
    for (long q = 0; q < C->ncand; q++) { /* penetration after the correction */
        const double g = f3_contact_gap_now(C, &R->mesh, C->cand[q], u);
        if (-g > R->pen_max)
            R->pen_max = -g;
    }
    return Fc;
}

/* f_int' v of each body (boulder dofs first). */
static void solid_power(const solid_run *R, double fv[2])
{
    const long nb3 = 3 * R->nbn;
    for (long dd = 0; dd < nb3; dd++)
        fv[0] += R->f[dd] * R->v[dd];
    for (long dd = nb3; dd < R->ndof; dd++)
        fv[1] += R->f[dd] * R->v[dd];
}

/* The boulder's lowest point (its contact-face nodes) below the undeformed slope surface z = 0. */
static void solid_depth(solid_run *R)
{
    if (R->C.sphere) { /* the exact sphere's */
        const double d = R->C.radius - R->C.rigid_c[1];
        if (d > R->depth_max)
            R->depth_max = d;
        return;
    }
    for (long k = 0; k < R->C.nslave; k++) {
        const long s = R->C.slave[k];
        const double d = -(R->mesh.x[3 * s + 2] + R->u[3 * s + 2]);
        if (d > R->depth_max)
            R->depth_max = d;
    }
}

/* Plastic dissipation of body b so far [J] (model). */
static double solid_plastic_work(const solid_run *R, int b)
{
    fem_kernel_report r;
    fem_kernel_report_get(&R->S.kernel[b], &r);
    return r.plastic_work;
}

/* Pairing at step n (u_n, G v_{n-1/2}): the slaves shared among the force's threads. */
static void pairing_share(void *ctx)
{
    solid_run *R = ctx;
    F3P_MARK(m);
    f3_contact_locate(&R->C, &R->mesh, R->u, R->v, R->threads, 1);
    F3P_LAP(F3P_LOCATE, m);
}

/* The contact-free predictor v += dt M^-1 (f_ext - f_int), u += dt v of dofs [d0, d1). */
static inline void predict_dofs(solid_run *R, long d0, long d1)
{
    const double dt = R->dt, *invm = R->invm, *fext = R->fext, *f = R->f, *fg = R->grav.fgrav;
    double *u = R->u, *v = R->v;
    if (fg) /* gravity's body load */
        for (long dd = d0; dd < d1; dd++) {
            v[dd] += dt * invm[dd] * (fext[dd] + fg[dd] - f[dd]);
            u[dd] += dt * v[dd];
        }
    else
        for (long dd = d0; dd < d1; dd++) {
            v[dd] += dt * invm[dd] * (fext[dd] - f[dd]);
            u[dd] += dt * v[dd];
        }
}

/* The predictor shared among the threads: the boulder's node chunks in the loop form that
   f3_force_hooks asks for (no barrier after the force), then the slope's. */
static void predictor_share(void *ctx)
{
    solid_run *R = ctx;
    const long nbn = R->nbn, nd = R->ndof;
    F3P_MARK(m);
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < F3_CHUNKS; k++)
        predict_dofs(R, 3 * f3_chunk_begin(nbn, k), 3 * f3_chunk_begin(nbn, k + 1));
    const long ns = nd / 3 - nbn;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < F3_CHUNKS; k++)
        predict_dofs(R, 3 * (nbn + f3_chunk_begin(ns, k)), 3 * (nbn + f3_chunk_begin(ns, k + 1)));
    F3P_LAP(F3P_UPDATE, m);
}

/* Internal force at u_n, pairing and predictor in the force's parallel region; with a plastic
   body the power f_int(u_n)' v_{n-1/2} is summed (serially) before the predictor. */
static void solid_force_predict(solid_run *R, double fv[2])
{
    const f3_force_hooks hooks = {pairing_share, R->work_account ? NULL : predictor_share, R};
    f3_internal_force_hooked(&R->S, R->u, R->f, &hooks);
    if (!R->work_account)
        return;
    solid_power(R, fv);
#ifdef _OPENMP
#pragma omp parallel num_threads(R->threads) if (R->threads > 1)
#endif
    predictor_share(R);
}

/* The rigid boulder's centre (x, z) for the contact: its CM, or in sphere mode the exact sphere's
   centre (the first-contact point + r0 along z at rest; the same point as the CM to round-off). */
static void solid_rigid_centre(solid_run *R)
{
    const double *c = R->C.sphere ? (const double[3]){0, 0, R->C.radius} : R->B.c0;
    R->C.rigid_c[0] = c[0] + R->B.X[0], R->C.rigid_c[1] = c[2] + R->B.X[1];
}

/* One step: dashpots (v_{n-1/2}) -> internal force, pairing, predictor -> contact. */
static rf_status solid_step(solid_run *R, double *Fc, double *rad, rf_error *err)
{
    const double dt = R->dt;
    double *u = R->u, *v = R->v;
    F3P_MARK(m);
    double W_abs_inc = solid_dashpot_forces(R);
    F3P_LAP(F3P_DASH, m);
    double fv[2] = {0, 0};
    const double gv0 = R->grav.fgrav ? f3_gravity_power(&R->grav, &R->B, v, R->nbn, R->ndof) : 0;
    solid_force_predict(R, fv);
    F3P_SET(m, f3p_now()); /* (its phases are timed inside) */
    for (int b = 0; b < 2; b++) /* the state at u_n is accepted */
        if (R->S.kernel[b].ops->commit)
            R->S.kernel[b].ops->commit(&R->S.kernel[b]);
    F3P_LAP(F3P_COMMIT, m);
    if (!R->fixed_outer)
        for (long k = 0; k < R->nouter; k++) {
            int i = R->outer[k];
            for (int q = 0; q < 3; q++)
                W_abs_inc -= 0.5 * dt * R->fext[3 * i + q] * v[3 * i + q];
        }
    if (R->rigid) { /* the boulder's predicted rigid state (its nodes moved along straight lines above) */
        f3_rigid *B = &R->B;
        const double Xn[3] = {B->X[0], B->X[1], B->th};
        R->C.body_vo[0] = B->V[0], R->C.body_vo[1] = B->V[1], R->C.body_vo[2] = B->w;
        if (R->grav.fgrav) /* its weight M g at the centre of mass */
            B->V[0] += dt * R->grav.g * R->grav.dir[0], B->V[1] += dt * R->grav.g * R->grav.dir[2];
        f3_rigid_predict(B, dt);
        f3_rigid_place(B, &R->mesh, R->nbn, u, v);
        R->C.body_d[0] = B->X[0] - Xn[0], R->C.body_d[1] = B->X[1] - Xn[1], R->C.body_d[2] = B->th - Xn[2];
        solid_rigid_centre(R);
    }
    if (R->no_contact)
        R->C.ncand = 0;
    else
        f3_contact_predict(&R->C, &R->mesh, u, R->invm, dt, R->threads);
    F3P_LAP(F3P_PREDICT, m);
    rf_status st = R->no_contact ? RF_OK : f3_contact_solve(&R->C, R->invm, dt, u, v, err);
    F3P_LAP(F3P_SOLVE, m);
    if (st != RF_OK)
        return st;
    if (R->rigid) { /* the contact's impulse on the rigid dofs */
        f3_rigid_correct(&R->B, R->C.rigid_du, dt);
        f3_rigid_place(&R->B, &R->mesh, R->nbn, u, v);
        if (R->C.sphere) { /* the account's and the depth's body */
            solid_rigid_centre(R);
            R->C.body_v[0] = R->B.V[0], R->C.body_v[1] = R->B.V[1], R->C.body_v[2] = R->B.w;
        }
    }
    if (R->C.sweeps > R->pgs_sweeps_max)
        R->pgs_sweeps_max = R->C.sweeps;
    if (R->C.residual > R->pgs_res_max)
        R->pgs_res_max = R->C.residual;
    *Fc = solid_contact_account(R, rad);
    R->W_abs += W_abs_inc;
    if (R->grav.fgrav) /* fgrav' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        R->grav.W += 0.5 * dt * (gv0 + f3_gravity_power(&R->grav, &R->B, v, R->nbn, R->ndof));
    if (R->work_account) { /* f_int(u_n)' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        double fv1[2] = {0, 0};
        solid_power(R, fv1);
        R->W_int[0] += 0.5 * dt * (fv[0] + fv1[0]), R->W_int[1] += 0.5 * dt * (fv[1] + fv1[1]);
    }
    solid_depth(R);
    F3P_LAP(F3P_ACCOUNT, m);
    return RF_OK;
}

/* Energies at t_{n+1/2} (KE with v_{n+1/2}, strain 1/2 u_n' K u_{n+1}), the
 * history row (full-body energies), compression and closure error. */
static void solid_energy(solid_run *R, double t, double Fc, double rad, double row[13], double *comp,
                         double *closure)
{
    const double *u = R->u, *v = R->v, *f = R->f;
    f3_state_sums sum; /* in parallel, fixed order */
    f3_state_sums_compute(&R->S, u, v, f, &sum);
    double ke[2] = {sum.mv2[0], sum.mv2[1]}, se[2] = {2 * sum.boulder_strain, sum.slope_fu};
    const double pz = sum.boulder_pz, uz = sum.boulder_uz;
    ke[0] *= 0.5, ke[1] *= 0.5, se[0] *= 0.5, se[1] *= 0.5;
    if (R->rigid)
        ke[0] = f3_rigid_energy(&R->B);
    if (R->work_account) /* stored elastically: the internal work less the dissipation */
        for (int b = 0; b < 2; b++)
            se[b] = R->W_int[b] - solid_plastic_work(R, b);
    *comp = -uz / R->Mb;
    *closure = ke[0] + ke[1] + se[0] + se[1] + R->W_abs + R->W_fric - R->ke0;
    if (R->work_account)
        *closure = ke[0] + ke[1] + R->W_int[0] + R->W_int[1] + R->W_abs + R->W_fric - R->ke0 - R->grav.W;
    const double sf = R->sym_factor;
    const double r[13] = {t,          Fc * sf,      *comp,        rad,        ke[0] * sf,   se[0] * sf, ke[1] * sf,
                          se[1] * sf, R->W_n * sf, R->W_abs * sf, *closure * sf, pz / R->Mb, R->W_fric * sf};
    memcpy(row, r, sizeof r);
}

/* VTK frame of the state u_n (the kernels' committed state is that of u_{n-1}). */
static rf_status solid_vtk(solid_run *R, int frame, double t, rf_error *err)
{
    f3_internal_force(&R->S, R->u, R->f); /* the boulder's co-rotated field of u_n, for its elastic stresses */
    return f3_vtk_frame(R->o.vtk_dir, frame, t, &R->S, R->u, R->v, R->mat, err);
}

static void solid_rigid_state(const solid_run *R, double P[3], double omega[3], double *Iyy);

/* With gravity: the boulder's CM velocity and spin when the contact opens
 * (the rebound's R_n, R_t, R_ke, before its weight turns it). */
static void solid_separation(solid_run *R)
{
    if (R->rigid) { /* its own dofs */
        R->sep_v[0] = R->B.V[0], R->sep_v[1] = 0, R->sep_v[2] = R->B.V[1], R->sep_w = R->B.w;
        return;
    }
    double omega[3], Iyy;
    solid_rigid_state(R, R->sep_v, omega, &Iyy);
    R->sep_w = omega[1];
}


/* Rigid-body state of the boulder after the impact: CM velocity P, angular
 * velocity omega from the angular momentum about the CM with the lumped
 * inertia tensor (current positions); *Iyy about the y axis. */
static void solid_rigid_state(const solid_run *R, double P[3], double omega[3], double *Iyy)
{
    const double *u = R->u, *v = R->v, *m = R->mass, *x = R->mesh.x;
    double X[3] = {0, 0, 0};
    P[0] = P[1] = P[2] = 0;
    for (long i = 0; i < R->nbn; i++)
        for (int q = 0; q < 3; q++) {
            P[q] += m[3 * i] * v[3 * i + q];
            X[q] += m[3 * i] * (x[3 * i + q] + u[3 * i + q]);
        }
    for (int q = 0; q < 3; q++)
        P[q] /= R->Mb, X[q] /= R->Mb;
    double Lm[3] = {0, 0, 0}, I[3][3] = {{0}};
    for (long i = 0; i < R->nbn; i++) {
        double mi = m[3 * i], r[3], w[3];
        for (int q = 0; q < 3; q++)
            r[q] = x[3 * i + q] + u[3 * i + q] - X[q], w[q] = v[3 * i + q];
        Lm[0] += mi * (r[1] * w[2] - r[2] * w[1]);
        Lm[1] += mi * (r[2] * w[0] - r[0] * w[2]);
        Lm[2] += mi * (r[0] * w[1] - r[1] * w[0]);
        double rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                I[a][b] += mi * ((a == b ? rr : 0) - r[a] * r[b]);
    }
    omega[0] = omega[1] = omega[2] = 0;
    if (R->ms.full) { /* solve I omega = L (Cramer) */
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
    *Iyy = I[1][1];
}

/* The plastic diagnostics of hist (full body): dissipation per body, the
 * elastic energy of the committed stresses against the internal work less
 * the dissipation, and where the largest plastic strain is (r: distance
 * from the impact axis). */
static void solid_history_plastic(const solid_run *R, rf_fem_history *hist)
{
    const double sf = R->sym_factor;
    fem_kernel_report rep[2];
    for (int b = 0; b < 2; b++) {
        fem_kernel_report_get(&R->S.kernel[b], &rep[b]);
        const double Ee = R->plastic[b] || (b == 1 && R->plastic[2]) ? fem_kernel_points_hex_energy(&R->S.kernel[b]) : -1;
        if (Ee >= 0) {
            hist->elastic_energy_stress += Ee * sf;
            hist->elastic_energy_work += (R->W_int[b] - rep[b].plastic_work) * sf;
        }
    }
    hist->plastic_work_boulder = rep[0].plastic_work * sf, hist->plastic_work_slope = rep[1].plastic_work * sf;
    const int bm = rep[1].plastic_strain_max > rep[0].plastic_strain_max ? 1 : 0;
    hist->plastic_strain_max_in = rep[bm].element_max < 0 ? 0 : 1 + bm;
    if (rep[bm].element_max < 0)
        return;
    const int *c = R->mesh.conn + 8 * rep[bm].element_max;
    double xc[3] = {0, 0, 0};
    for (int a = 0; a < 8; a++)
        for (int q = 0; q < 3; q++)
            xc[q] += R->mesh.x[3 * c[a] + q] / 8;
    hist->plastic_strain_max_r = hypot(xc[0], xc[1]), hist->plastic_strain_max_z = xc[2];
}

/* Diagnostics of the final state into hist (energies of the full body). */
static void solid_history(solid_run *R, const fem_run *run, double K_after, rf_fem_history *hist)
{
    const double *u = R->u, *v = R->v, *m = R->mass, sf = R->sym_factor;
    double seb = 0, ses = 0, eks = 0, ekb = 0;
    for (long dd = 0; dd < 3 * R->nbn; dd++)
        ekb += 0.5 * m[dd] * v[dd] * v[dd];
    seb = f3_boulder_strain(&R->S, u);
    if (R->rigid)
        ekb = K_after;
    for (long dd = 3 * R->nbn; dd < R->ndof; dd++)
        ses += 0.5 * R->f[dd] * u[dd], eks += 0.5 * m[dd] * v[dd] * v[dd];
    if (R->work_account) /* stored elastic energy: internal work less dissipation */
        seb = R->W_int[0] - solid_plastic_work(R, 0), ses = R->W_int[1] - solid_plastic_work(R, 1);
    hist->dt = R->dt, hist->dt_bound = R->dt_bound, hist->dt_edge = R->dt_edge;
    hist->h_contact = R->h;
    hist->hertz_radius = R->H.contact_radius, hist->hertz_duration = R->H.duration;
    hist->boulder_mass = R->H.mass, hist->boulder_mesh_mass = R->mesh_mass_b * sf;
    hist->penetration_max = R->pen_max, hist->slip_max = R->slip_max;
    hist->reflection_time = 2 * R->L / R->w[1].p;
    hist->vibration_energy = (ekb + seb - K_after) * sf;
    hist->slope_energy = (eks + ses) * sf;
    hist->ke0 = R->ke0 * sf;
    hist->boulder_nodes = R->mesh.boulder_nodes, hist->boulder_elements = R->mesh.boulder_elems;
    hist->slope_nodes = R->nn - R->mesh.boulder_nodes, hist->slope_elements = R->ne - R->mesh.boulder_elems;
    hist->state_hash = fem_hash(fem_hash(FEM_HASH_SEED, u, (size_t)R->ndof * sizeof *u), v,
                                (size_t)R->ndof * sizeof *v);
    char extra[640] = "";
    if (R->outside_contact)
        snprintf(extra, sizeof extra, "The contact reached the edge of the uniform fine zone (sized from the elastic "
                 "contact radius): its outer pairs lie on graded, coarser elements than refinement says. ");
    if (!R->large && (R->plastic[1] || R->plastic[2]))
        snprintf(extra + strlen(extra), sizeof extra - strlen(extra), "Small strain with an elasto-plastic slope "
                 "or layer: the 3D contact follows the deformed face, the soil its reference geometry; where the "
                 "soil yields the boulder sinks too deep (docs/validation-plastic.md 9d). Large deformation (auto, "
                 "the default) is consistent. ");
    if (R->grav.outside > 0)
        snprintf(extra + strlen(extra), sizeof extra - strlen(extra), "%ld integration points of the geostatic "
                 "state lie outside the yield surface (returned to it at the first step). ", R->grav.outside);
    fem_run_warnings(run, R->fixed_outer, R->L, R->w[1].p, R->in->radius, hist->warning, sizeof hist->warning,
                     extra[0] ? extra : NULL);
    solid_history_plastic(R, hist);
    if (R->plastic[1] || R->plastic[2]) /* less the geostatic stress's energy (0 without gravity) */
        hist->elastic_energy_stress -= R->grav.E0 * sf;
    hist->gravity = R->grav.g, hist->gravity_work = R->grav.W * sf, hist->geostatic_outside = R->grav.outside;
    hist->at_rest = run->at_rest;
}

static void solid_report(solid_run *R, fem_run *run, const double P[3], double w_after, double Iyy,
                         rf_fem3d_report *rep)
{
    const double sf = R->sym_factor, c = R->H.c, d = R->H.d;
    rep->friction_work = R->W_fric * sf;
    rep->normal_work = R->W_n * sf;
    rep->slip_max = R->slip_max;
    rep->contact_point_velocity = P[0] - w_after * d;
    rep->inertia_lumped = Iyy * sf;
    rep->inertia_exact = R->H.mass * (c * c + d * d) / 5;
    rep->v_y_after = P[1];
    rep->stick_fraction = R->pair_steps ? (double)R->stick_steps / (double)R->pair_steps : 0;
    rep->pgs_sweeps_max = R->pgs_sweeps_max;
    rep->pgs_residual_max = R->pgs_res_max;
    rep->unlocated_pair_steps = R->unlocated_steps;
    rep->state_hash = fem_hash(fem_hash(FEM_HASH_SEED, R->u, (size_t)R->ndof * sizeof *R->u), R->v,
                               (size_t)R->ndof * sizeof *R->v);
    rep->n = run->series.n;
    rep->friction_series = run->series.col[12];
    run->series.col[12] = NULL;
}

/* plastic_work (/ KE0), the largest equivalent plastic strain, the deepest
 * position of the boulder's lowest point and the permanent depth of the slope
 * surface at the first-contact point (both normal to the slope). */
static void solid_plastic_outputs(const solid_run *R, rf_impact_output *out)
{
    fem_kernel_report rep[2];
    for (int b = 0; b < 2; b++)
        fem_kernel_report_get(&R->S.kernel[b], &rep[b]);
    out->plastic_work = (rep[0].plastic_work + rep[1].plastic_work) / R->ke0;
    out->equivalent_plastic_strain_max = fmax(rep[0].plastic_strain_max, rep[1].plastic_strain_max);
    out->penetration_max = R->depth_max;
    out->indentation_depth = -R->u[3 * R->crater_node + 2];
}

/* Outputs, diagnostics and report of the final state. */
static void solid_extract(solid_run *R, fem_run *run, long nsteps, rf_impact_output *out, rf_fem_history *hist,
                          rf_fem3d_report *rep)
{
    double P[3], omega[3], Iyy;
    solid_rigid_state(R, P, omega, &Iyy);
    if (R->rigid) { /* the rigid dofs themselves */
        P[0] = R->B.V[0], P[1] = 0, P[2] = R->B.V[1];
        omega[0] = omega[2] = 0, omega[1] = R->B.w, Iyy = R->B.I;
    }
    if (R->grav.g > 0 && run->at_rest) /* settled in contact: R_n = 0 (it may still slide or roll) */
        P[2] = 0;
    else if (R->grav.g > 0 && !run->in_contact && run->episodes > 0) /* the state at the last separation */
        memcpy(P, R->sep_v, sizeof R->sep_v), omega[1] = R->sep_w;
    const double vn_after = P[2], vt_after = P[0], w_after = omega[1];
    const double K_after = 0.5 * R->Mb * (vn_after * vn_after + vt_after * vt_after) + 0.5 * Iyy * w_after * w_after;
    fem_run_outputs(run, nsteps, R->t.duration_threshold, R->ke0, R->sym_factor, R->nn, R->ne, out);
    solid_plastic_outputs(R, out);
    out->v_n_before = -R->Vn;
    out->v_t_before = R->Vt;
    out->v_n_after = vn_after;
    out->v_t_after = vt_after;
    out->omega_after = w_after;
    out->R_n = vn_after / R->Vn;
    out->R_t = R->Vt > 0 ? vt_after / R->Vt : NAN;
    out->R_ke = K_after / R->ke0;
    if (hist || rep)
        f3_internal_force(&R->S, R->u, R->f);
    if (hist)
        solid_history(R, run, K_after, hist);
    if (rep)
        solid_report(R, run, P, w_after, Iyy, rep);
}

/* The driver's stages (fem_driver.h) over a solid_run. */
static rf_status solid_stage_prepare(void *run, const fem_attempt *a, rf_error *err)
{
    return solid_prepare(run, a->in, a->opt, a->o3, err);
}

static rf_status solid_stage_mesh(void *run, rf_error *err)
{
    return solid_mesh(run, err);
}

static rf_status solid_stage_assemble(void *run, rf_error *err)
{
    return solid_assemble(run, err);
}

static void solid_params(const void *run, fem_drive_params *p)
{
    const solid_run *R = run;
    *p = (fem_drive_params){R->dt, R->H.duration, R->ke0, R->grav.g, 13};
}

/* A step, its stability in large deformation, and the energy account's row. */
static rf_status solid_stage_step(void *run, double t, fem_step_row *r, rf_error *err)
{
    solid_run *R = run;
    rf_status st = solid_step(R, &r->Fc, &r->rad, err);
    if (st != RF_OK)
        return st;
    if (R->large && (R->unstable = f3_step_violation(&R->step_check, R->dt, R->u)) >= 0)
        return rf_fail(err, RF_EMODEL, "fem3d: element %ld was compressed below the stability bound of the time "
                       "step dt = %g s (dt_safety = %g) at t = %g s", R->unstable, R->dt, R->t.dt_safety, t);
    F3P_MARK(m);
    solid_energy(R, t, r->Fc, r->rad, r->row, &r->comp, &r->closure);
    F3P_LAP(F3P_ENERGY, m);
    return RF_OK;
}

/* Gravity: the boulder leaves the contact (solid_separation). */
static void solid_accounted(void *run, int was_in_contact, int in_contact)
{
    solid_run *R = run;
    if (R->grav.g > 0 && was_in_contact && !in_contact)
        solid_separation(R);
}

static rf_status solid_frame(void *run, int k, double t, rf_error *err)
{
    return solid_vtk(run, k, t, err);
}

static void solid_stage_extract(void *run, fem_run *F, long nsteps, const fem_attempt *a)
{
    solid_run *R = run;
    F3P_REPORT(nsteps, R->ne, R->nn, R->nbn);
    solid_extract(R, F, nsteps, a->out, a->hist, a->rep);
}

static long solid_stage_release(void *run)
{
    solid_run *R = run;
    solid_release(R);
    return R->unstable;
}

static const fem_geometry solid_geometry = {"fem3d", solid_stage_prepare, solid_stage_mesh, solid_stage_assemble,
                                            solid_params, solid_stage_step, solid_accounted, solid_frame,
                                            solid_stage_extract, NULL, solid_stage_release};

/* One attempt of rf_fem3d_impact_ws (fem_run_halving): a fresh run through the driver. */
static rf_status solid_attempt_fn(void *ctx, const rf_fem_options *o, long *unstable, rf_error *err)
{
    fem_attempt a = *(const fem_attempt *)ctx;
    a.opt = o;
    solid_run R;
    memset(&R, 0, sizeof R);
    R.pool = &a.ws->solid, R.unstable = -1;
    return fem_drive(&solid_geometry, &R, &a, unstable, err);
}

rf_status rf_fem3d_impact_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                             const rf_fem3d_options *o3, rf_impact_output *out, rf_fem_history *hist,
                             rf_fem3d_report *rep, rf_error *err)
{
    fem_attempt a = {ws, in, opt, o3, out, hist, rep};
    return fem_drive_impact(solid_attempt_fn, &a, "fem3d", err);
}

rf_status rf_fem3d_impact_ex(const rf_impact_input *in, const rf_fem_options *opt, const rf_fem3d_options *o3,
                             rf_impact_output *out, rf_fem_history *hist, rf_fem3d_report *rep, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    rf_status st = rf_fem3d_impact_ws(ws, in, opt, o3, out, hist, rep, err);
    rf_fem_workspace_free(ws);
    return st;
}

rf_status rf_fem3d_impact(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                          rf_fem_history *hist, rf_error *err)
{
    return rf_fem3d_impact_ex(in, opt, NULL, out, hist, NULL, err);
}

/* 1 if element e is an axis-aligned box (two values of each coordinate). */
static int element_is_box(const f3_mesh *m, long e)
{
    const int *c = m->conn + 8 * e;
    for (int q = 0; q < 3; q++) {
        const double lo = m->x[3 * (long)c[0] + q];
        double hi = lo;
        for (int a = 1; a < 8; a++) {
            const double x = m->x[3 * (long)c[a] + q];
            if (x != lo && hi != lo && x != hi)
                return 0;
            if (x != lo)
                hi = x;
        }
    }
    return 1;
}

/* The body load against the lumped weight at the nodes of the fine box's boxes. */
static void gravity_load_check(const solid_run *R, f3_gravity_check *chk)
{
    const f3_mesh *m = &R->mesh;
    const f3_system *S = &R->S;
    const double *fg = R->grav.fgrav;
    for (long i = R->nbn; fg && i < R->nn; i++) {
        int box = !(m->flags[i] & (F3_OUTER | F3_SYM));
        for (long p = S->inc_ptr[i]; box && p < S->inc_ptr[i + 1]; p++)
            box = element_is_box(m, S->inc[p] / 8);
        if (!box)
            continue;
        chk->box_nodes++;
        for (int q = 0; q < 3; q++) {
            const double w = (R->mass[3 * i] - (R->mshift ? R->mshift[i] : 0)) * R->grav.g; /* its own weight */
            chk->load_err = fmax(chk->load_err, fabs(fg[3 * i + q] - w * R->grav.dir[q]) / w);
        }
    }
}

/* What fem3d_gravity_free_run reports of the state after its steps. */
static void gravity_free_report(solid_run *R, f3_gravity_check *chk, double closure)
{
    for (long d = 3 * R->nbn; d < R->ndof; d++)
        chk->slope_u_max = fmax(chk->slope_u_max, fabs(R->u[d])), chk->slope_v_max = fmax(chk->slope_v_max, fabs(R->v[d]));
    for (long i = 0; i < R->nbn; i++)
        for (int q = 0; q < 3; q++)
            chk->cm_u[q] += R->mass[3 * i] * R->u[3 * i + q] / R->Mb, chk->cm_v[q] += R->mass[3 * i] * R->v[3 * i + q] / R->Mb;
    for (long i = 0; i < R->nbn; i++)
        for (int q = 0; q < 3; q++)
            chk->spread_u = fmax(chk->spread_u, fabs(R->u[3 * i + q] - chk->cm_u[q]));
    chk->dt = R->dt, chk->closure = closure, chk->gravity_work = R->grav.W, chk->outside = R->grav.outside;
    gravity_load_check(R, chk);
    const f3_mesh *m = &R->mesh;
    for (long e = m->boulder_elems; chk->cell && e < R->ne; e++) {
        double sig[6], ep, zc = 0;
        if (!fem_kernel_points_hex_cell(&R->S.kernel[F3_SLOPE], e, sig, &ep))
            return;
        for (int a = 0; a < 8; a++)
            zc += m->x[3 * (long)m->conn[8 * e + a] + 2] / 8;
        chk->cell(chk->ctx, -zc, R->emat[e] == 2, sig);
    }
}

rf_status fem3d_gravity_free_run(const rf_impact_input *in, const rf_fem_options *opt, const rf_fem3d_options *o3,
                                 long steps, f3_gravity_check *chk, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    solid_run R;
    memset(&R, 0, sizeof R);
    R.pool = &ws->solid, R.no_contact = 1;
    rf_status st = solid_prepare(&R, in, opt, o3, err);
    if (st == RF_OK)
        st = solid_mesh(&R, err);
    if (st == RF_OK)
        st = solid_assemble(&R, err);
    double closure = 0;
    for (long n = 0; st == RF_OK && n < steps; n++) {
        double Fc, rad, row[13], comp;
        if ((st = solid_step(&R, &Fc, &rad, err)) == RF_OK)
            solid_energy(&R, (double)n * R.dt, Fc, rad, row, &comp, &closure);
    }
    if (st == RF_OK)
        gravity_free_report(&R, chk, closure);
    solid_release(&R);
    rf_fem_workspace_free(ws);
    return st;
}
