/* fem_axi_setup.c - the axisymmetric run's first stages (fem_axi_run.h):
 * the check of what this model can take, the automatic settings, the Hertz
 * reference that sizes the mesh and the run, the bodies' laws; the sizing and
 * meshing (fem_mesh.c); and the release of what the run holds outside the pool. */
#include "fem_axi_run.h"
#include "fem_spec.h"

#include <math.h>

/* What the axisymmetric model can do beyond the ranges every impact model
 * shares (rf_impact_input_validate) and the option rules (rf_fem_options_validate). */
static rf_status check_input(const rf_impact_input *in, const rf_fem_options *o, rf_error *err)
{
    if (!in || !o)
        return rf_fail(err, RF_EINVAL, "fem: NULL input or options");
    if (!(in->slope_angle == 0))
        return rf_fail(err, RF_EINVAL,
                       "fem: the axisymmetric FE model handles only normal impact (slope_angle = 0); "
                       "got slope_angle = %g rad",
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

/* Sizing and meshing: the fine zone from the Hertz contact radius, graded
 * elements out to the domain radius. */
rf_status axi_mesh(axi_run *S, rf_error *err)
{
    const rf_fem_options *o = &S->set.o;
    const rf_hertz_reference *H = &S->set.H;
    double a_soil = 0, zone = 0; /* mesh_sizing soil: a thick layer's own contact (fem_spec.h) */
    const int soil = fem_soil_contact_zone(S->set.in, o, &a_soil, &zone);
    const double a = soil ? a_soil : H->contact_radius;
    S->sys.h = a / o->refinement, S->sys.hb = S->sys.h * S->set.t.boulder_mesh_ratio;
    const double h = S->sys.h, hb = S->sys.hb;
    /* the uniform fine zone must stay well inside the boulder: shrink it at
       very high speed (a/R > 0.24 with the default 2.5 a) down to 1.5 a */
    double core = soil ? fmin(zone / a, 0.55 * fmin(H->c, H->d) / a) /* a soil contact wider than the */
                       : fmin(S->set.t.fine_zone_factor, 0.55 * fmin(H->c, H->d) / H->contact_radius);
    if (!soil && core < 1.5) /* boulder's fine zone: the slaves beyond it are graded, not refused */
        return rf_fail(err, RF_EINVAL,
                       "fem: the Hertz contact radius a = %.4g m is too large for the boulder (c = %g m, d = %g m): "
                       "a fine zone of 1.5 a must fit in 0.55 min(c, d); Hertz-based meshing needs a << min(c, d)",
                       H->contact_radius, H->c, H->d);
    fem_body_spec bs = {0}, ss = {0};
    ss.h = h;
    ss.n = 3 * (int)ceil((soil ? zone / a : core) * o->refinement / 3 - 1e-9);
    while (!soil && ss.n > 3 && ss.n * h > 0.6 * fmin(H->c, H->d))
        ss.n -= 3;
    ss.grading = S->set.t.grading;
    const double c_r = S->set.layer ? fmin(S->body.w[1].rayleigh, S->body.w[2].rayleigh) : S->body.w[1].rayleigh;
    ss.h_far = fmax(h, fmin(c_r * H->duration / 12, S->set.L / 8));
    ss.extent = S->set.L;
    bs.h = hb;
    bs.n = 3 * (int)ceil(core * o->refinement / S->set.t.boulder_mesh_ratio / 3 - 1e-9);
    while (bs.n > 3 && bs.n * hb > 0.6 * fmin(H->c, H->d))
        bs.n -= 3;
    bs.grading = S->set.t.grading;
    bs.h_far = fmax(hb, fmin(H->c, H->d) / 10);
    bs.extent = H->c;
    bs.height = H->d;
    if (bs.n * bs.h > 0.7 * fmin(H->c, H->d))
        return rf_fail(err, RF_EINVAL,
                       "fem: the Hertz contact radius %.4g m is too large for the boulder (c = %g m, d = %g m): the "
                       "fine zone does not fit; lower the impact speed or raise refinement",
                       H->contact_radius, H->c, H->d);
    if (ss.n * ss.h * 4 > S->set.L)
        return rf_fail(err, RF_EINVAL, "fem: domain radius %g m is too small for the fine zone (%g m)", S->set.L,
                       ss.n * ss.h);
    S->sys.fine_r = ss.n * ss.h;
    rf_status st = fem_mesh_build(&bs, &ss, &S->mesh, S->set.t.max_elements, err);
    S->sys.have_mesh = st == RF_OK;
    return st;
}

/* Check, resolve the automatic settings, take the Hertz reference. */
rf_status axi_prepare(axi_run *S, const rf_impact_input *in, const rf_fem_options *opt, rf_error *err)
{
    S->set.in = in;
    if (opt)
        S->set.o = *opt;
    else
        rf_fem_options_default(&S->set.o);
    S->set.t = *fem_tuning_of(&S->set.o);
    rf_status st = check_input(in, &S->set.o, err);
    if (st != RF_OK)
        return st;
    S->set.o.refinement = rf_fem_refinement(&S->set.o, 0);
    S->set.o.domain_factor = rf_fem_domain_factor(&S->set.o, in);
    rf_impact_hertz_reference(in, &S->set.H);
    S->set.layer = in->layer_thickness > 0;
    if (S->set.layer) { /* size the mesh for the finer of the two contacts, run for the longer */
        rf_impact_input lay = *in;
        lay.slope_density = in->layer_density, lay.slope_E = in->layer_E, lay.slope_poisson = in->layer_poisson;
        rf_hertz_reference HL;
        rf_impact_hertz_reference(&lay, &HL);
        S->set.H.contact_radius = fmin(S->set.H.contact_radius, HL.contact_radius);
        S->set.H.duration = fmax(S->set.H.duration, HL.duration);
        rf_impact_wave_speeds(&lay, 1, &S->body.w[2]);
    }
    S->set.V = in->velocity, S->set.L = S->set.o.domain_factor * in->radius;
    S->body.mat[0] = (fem_material){in->boulder_density, in->boulder_E, in->boulder_poisson};
    S->body.mat[1] = (fem_material){in->slope_density, in->slope_E, in->slope_poisson};
    S->body.mat[2] = (fem_material){in->layer_density, in->layer_E, in->layer_poisson};
    rf_impact_wave_speeds(in, 0, &S->body.w[0]);
    rf_impact_wave_speeds(in, 1, &S->body.w[1]);
    S->set.threads = S->set.o.threads > 0 ? S->set.o.threads : 1;
#ifndef _OPENMP
    S->set.threads = 1;
#endif
    S->set.o.boundary = rf_fem_boundary_resolve(S->set.o.boundary, in);
    S->set.fixed_outer = S->set.o.boundary == RF_FEM_BOUNDARY_FIXED;
    for (int b = 0; b < 3; b++) {
        rf_material_params p;
        if (b == 2 && !S->set.layer) { /* no layer: its (unchecked) inputs are not used */
            S->body.matl[2] = S->body.matl[1], S->body.plastic[2] = 0;
            continue;
        }
        rf_impact_material_params(in, b, &p);
        if ((st = rf_material_init(&S->body.matl[b], &p, err)) != RF_OK) /* validated above: cannot fail */
            return rf_error_prefix(err, "fem");
        S->body.plastic[b] = p.model != RF_MATERIAL_ELASTIC && (b < 2 || S->set.layer);
    }
    S->set.rigid = in->boulder_material == RF_MATERIAL_RIGID_BODY;
    S->set.work_account = S->body.plastic[0] || S->body.plastic[1] || S->body.plastic[2];
    S->set.large = rf_fem_large_deformation(&S->set.o, in);
    S->grav.g = rf_impact_gravity(in, 0);
    S->set.work_account |= S->set.large; /* the energy from the internal work: no K in updated Lagrangian */
    S->ale.on = rf_fem_ale_enabled(&S->set.o, in);
    return RF_OK;
}

/* What the run holds outside the workspace pool. */
void axi_free(axi_run *S)
{
    fem_contact_free(&S->C);
    fem_ale_free(&S->ale.state);
    fem_kernel_release(&S->body.kernel[0]);
    fem_kernel_release(&S->body.kernel[1]);
    if (S->sys.have_mesh)
        fem_mesh_free(&S->mesh);
}
