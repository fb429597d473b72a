/* fem3d_prepare.c - the first stages of a 3D impact run (fem3d_run.h):
 * the check of what the 3D model can take, the automatic settings, the
 * Hertz reference with the normal velocity component (a layer's contact
 * when it is the finer one), the bodies' laws and the choice of kernels
 * (small strain, updated Lagrangian), and the sizing and meshing of the
 * fine boxes (fem3d_mesh.c). */
#include "fem3d_run.h"

#include <math.h>
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

/* A layer over the slope: as the axisymmetric solver (fem_solver.c), the
 * mesh sized for the finer of the two contacts (slope's and layer's Hertz
 * radius), its fine boxes covering the larger, the run as long as the longer
 * Hertz duration; but a thick layer (the boulder stays in it,
 * f3_layer_contact_estimate) sizes all three from its own contact.  The
 * layer's wave speeds. */
static rf_status solid_prepare_layer(solid_run *R, rf_error *err)
{
    solid_settings *set = &R->set;
    const rf_impact_input *in = set->in;
    R->body.layer = in->layer_thickness > 0;
    if (!R->body.layer)
        return RF_OK;
    if (!(in->layer_thickness < 0.5 * set->L))
        return rf_fail(err, RF_EINVAL,
                       "fem3d: layer_thickness = %g m must be below half the domain radius (%g m): raise domain_factor",
                       in->layer_thickness, set->L);
    rf_impact_input lay = *in;
    lay.slope_density = in->layer_density, lay.slope_E = in->layer_E, lay.slope_poisson = in->layer_poisson;
    rf_hertz_reference HL;
    rf_impact_hertz_reference(&lay, &HL);
    set->a_box = fmax(set->H.contact_radius, HL.contact_radius);
    set->H.contact_radius = fmin(set->H.contact_radius, HL.contact_radius);
    set->H.duration = fmax(set->H.duration, HL.duration);
    rf_impact_wave_speeds(&lay, 1, &R->body.w[2]);
    f3_layer_contact_estimate(in, &set->lc);
    if (set->lc.thick) { /* the boulder stays in the layer: its contact alone sizes the mesh and the run */
        set->H.contact_radius = set->lc.radius, set->H.duration = set->lc.duration;
        set->a_box = fmax(set->lc.radius, set->lc.zone_radius / set->o3.fine_box_factor);
    }
    return RF_OK;
}

/* Each body's law (plastic[b]: not elastic, a rigid boulder apart), large
 * deformation and the bodies on the updated-Lagrangian kernel, and whether
 * the energies come from the internal work. */
static rf_status solid_prepare_laws(solid_run *R, rf_error *err)
{
    const rf_impact_input *in = R->set.in;
    solid_bodies *body = &R->body;
    for (int b = 0; b < 3; b++) {
        rf_material_params p;
        if (b == 2 && !body->layer) { /* no layer: its (unchecked) inputs are not used */
            body->matl[2] = body->matl[1], body->plastic[2] = 0;
            continue;
        }
        rf_impact_material_params(in, b, &p);
        if (rf_material_init(&body->matl[b], &p, err) != RF_OK) /* validated above: cannot fail */
            return rf_error_prefix(err, "fem3d");
        body->plastic[b] = p.model != RF_MATERIAL_ELASTIC && !(b == 0 && body->rigid);
    }
    body->work_account = body->plastic[0] || body->plastic[1] || body->plastic[2];
    body->large = rf_fem_large_deformation(&R->set.o, in);
    body->work_account |= body->large; /* the energy from the internal work: no K in updated Lagrangian */
    /* auto leaves an elastic body on its small-strain kernel: its strains stay ~a/r0 (section 9c) */
    const int all = R->set.o.large_deformation == RF_FEM_LARGE_DEFORMATION;
    body->ul[0] = body->large && !body->rigid && (all || body->plastic[0]);
    body->ul[1] = body->large && (all || body->plastic[1] || body->plastic[2]);
    return RF_OK;
}

/* Check, resolve the automatic settings, Hertz reference with the normal
 * velocity component, the bodies' laws, gravity. */
rf_status f3_run_prepare(solid_run *R, const rf_impact_input *in, const rf_fem_options *opt,
                         const rf_fem3d_options *o3p, rf_error *err)
{
    solid_settings *set = &R->set;
    solid_bodies *body = &R->body;
    set->in = in;
    if (opt)
        set->o = *opt;
    else
        rf_fem_options_default(&set->o);
    if (o3p)
        set->o3 = *o3p;
    else
        rf_fem3d_options_default(&set->o3);
    set->t = *fem_tuning_of(&set->o);
    rf_status st = check_input(in, &set->o, &set->o3, err);
    if (st != RF_OK)
        return st;
    set->o.refinement = rf_fem_refinement(&set->o, 1);
    set->o.domain_factor = rf_fem_domain_factor(&set->o, in);
    rf_impact_hertz_reference(in, &set->H);
    set->V = in->velocity, set->Vn = set->H.normal_velocity, set->Vt = set->H.tangential_velocity;
    set->L = set->o.domain_factor * in->radius;
    body->mat[0] = (f3_material){in->boulder_density, in->boulder_E, in->boulder_poisson};
    body->mat[1] = (f3_material){in->slope_density, in->slope_E, in->slope_poisson};
    body->mat[2] = (f3_material){in->layer_density, in->layer_E, in->layer_poisson};
    rf_impact_wave_speeds(in, 0, &body->w[0]);
    rf_impact_wave_speeds(in, 1, &body->w[1]);
    body->w[2] = body->w[1];
    body->rigid = in->boulder_material == RF_MATERIAL_RIGID_BODY;
    set->a_box = set->H.contact_radius;
    if ((st = solid_prepare_layer(R, err)) != RF_OK)
        return st;
    set->threads = set->o.threads > 0 ? set->o.threads : 1;
#ifndef _OPENMP
    set->threads = 1;
#endif
    set->o.boundary = rf_fem_boundary_resolve(set->o.boundary, in); /* the axisymmetric model's rule */
    set->fixed_outer = set->o.boundary == RF_FEM_BOUNDARY_FIXED;
    if ((st = solid_prepare_laws(R, err)) != RF_OK)
        return st;
    /* gravity: the energy from the internal work (the slope's geostatic pre-stress is not in 1/2 u' K u) */
    R->grav.g = rf_impact_gravity(in, 1);
    body->work_account |= R->grav.g > 0;
    set->ground = *in; /* gravity's ground: inclined at the incidence, or less (rf_fem_ground) */
    set->ground.slope_angle = f3_ground_angle(in, set->o.ground, R->grav.g, set->L);
    double fs;
    return R->grav.g > 0 ? f3_gravity_stability(&set->ground, R->grav.g, set->L, &fs, err) : RF_OK;
}

/* The boulder's fine box in its half-space image.  An elastic boulder: at most
 * 0.6 r0 long (its elements must stay near the contact, where the inversion
 * keeps their size).  A rigid one carries only the contact's slave nodes: the
 * box may cover the whole lower half of the ball; its farthest corner must
 * leave room for the graded layers out to boulder_inner * r0. */
static rf_status boulder_box_fits(const solid_run *R, rf_error *err)
{
    const f3_box *b = &R->grid.ms.boulder;
    const double r0 = R->set.in->radius;
    if (R->body.rigid) {
        const int nx = b->nxm > b->nxp ? b->nxm : b->nxp;
        const double corner = b->h * sqrt((double)nx * nx + (double)b->ny * b->ny + (double)b->nz * b->nz);
        if (corner > 0.8 * R->set.o3.boulder_inner * r0)
            return rf_fail(err, RF_EINVAL,
                           "fem3d: the rigid boulder's fine zone (corner %.3g m in its half-space image) needs "
                           "boulder_inner >= %.3g (got %g); lower the impact speed or take a stiffer layer",
                           corner, corner / (0.8 * r0), R->set.o3.boulder_inner);
        return RF_OK;
    }
    const double box_b = (b->nxp + b->nxm) * b->h;
    if (box_b > 0.6 * r0)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: the fine zone (%.3g m) does not fit the boulder (r0 = %g m): the contact radius "
                       "%.3g m%s is too large for an elastic boulder; lower the impact speed, or "
                       "take boulder_material rigid",
                       box_b, r0, R->set.a_box, R->body.layer ? " (the larger of the slope's and the layer's)" : "");
    return RF_OK;
}

/* Sizing and meshing: fine boxes of uniform cubes over core_factor * a,
 * elongated down-slope by the patch travel; graded layers out to L. */
rf_status f3_run_mesh(solid_run *R, rf_error *err)
{
    const solid_settings *set = &R->set;
    const rf_fem_options *o = &set->o;
    const rf_fem3d_options *o3 = &set->o3;
    const double a_h = set->H.contact_radius, c = set->H.c, d = set->H.d, r0 = set->in->radius;
    const double thick = set->in->layer_thickness;
    R->grid.h = a_h / o->refinement, R->grid.hb = R->grid.h * set->t.boulder_mesh_ratio;
    const double h = R->grid.h, hb = R->grid.hb, travel = o3->elongation * set->Vt * set->H.duration;
    f3_mesh_spec *ms = &R->grid.ms;
    memset(ms, 0, sizeof *ms);
    ms->full = o3->full_model != 0;
    const double a_x = set->a_box; /* = a_h without a layer */
    int n_s = (int)ceil(o3->fine_box_factor * a_x / h - 1e-9), n_b = (int)ceil(o3->fine_box_factor * a_x / hb - 1e-9);
    ms->slope = (f3_box){n_s, n_s + (int)ceil(travel / h - 1e-9), n_s, n_s, h};
    ms->extruded = R->body.layer || o3->layered_mesh;
    ms->layer_depth = R->body.layer ? thick : 0;
    if (R->body.layer && thick < h)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: layer_thickness = %g m is thinner than the element at the contact (h = %g m): raise "
                       "refinement or the thickness", thick, h);
    /* the boulder's half-space image is scaled by c (x, y) and d (z) afterwards */
    const double sxy = c / r0, sz = d / r0, hb0 = hb / sxy;
    ms->boulder = (f3_box){n_b, n_b + (int)ceil(travel / hb - 1e-9), n_b, n_b, hb0};
    if (R->body.rigid && set->lc.thick)
        f3_soft_boulder_box(&ms->boulder, o3->fine_box_factor * a_x, travel, r0, sxy);
    ms->radius = r0;
    ms->scale_xy = sxy, ms->scale_z = sz;
    ms->boulder_inner = o3->boulder_inner;
    ms->domain = set->L;
    ms->layer_aspect = o3->layer_aspect;
    rf_status st = boulder_box_fits(R, err);
    if (st != RF_OK)
        return st;
    if ((ms->slope.nxm + ms->slope.nxp) * h * 4 > set->L)
        return rf_fail(err, RF_EINVAL, "fem3d: domain radius %g m is too small for the fine zone", set->L);
    st = f3_mesh_build(ms, &R->grid.mesh, set->t.max_elements, err);
    R->grid.have_mesh = st == RF_OK;
    return st;
}
