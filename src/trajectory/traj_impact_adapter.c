/* traj_impact_adapter.c - the ONE place where the trajectory code calls
 * rockfuzz's impact models (rockfuzz/impact.h), so that a change of that API
 * is absorbed here.  It calls: rf_impact_model_spec_default,
 * rf_impact_solver_parse, rf_impact_input_default, rf_impact_solve and, for
 * the names a trajectory file takes, rf_impact_n_solvers and
 * rf_impact_solver_name.
 *
 * The impact API describes an impact as a vertical velocity V onto a slope
 * inclined at alpha (v_n = V cos alpha, v_t = V sin alpha).  An impact of
 * normal speed v_n at incidence theta (from the normal) is therefore
 * V = v_n / cos theta on a slope inclined at theta; the FE's gravity takes
 * the ground no steeper than a layer stands (rf_fem_options.ground stable).  Returned: R_n, R_t and
 * the spin ratio omega r / v_t' after the impact (0 when not computed).  At
 * normal incidence R_t is undefined (v_t = 0): incidences below 1 degree are
 * evaluated at 1 degree (closer to normal, the FE's R_t becomes a ratio of
 * numerical noise to a vanishing v_t; the rigid model's R_t is constant
 * there, so nothing is lost); a model that gives no R_t (hertz, hunter:
 * normal impact only) gets R_t = 1 (no tangential loss).  An R_t beyond
 * [-1, 1] (a tangential speed gained: the FE at 1 deg gave 1.147 at v_n 1 m/s
 * on a soil layer, the noise ratio just described) is kept at the bound, as
 * the bounce law's lookup clamps it anyway; stored unclamped, the store's
 * check refused the row on the next read and the study could not resume.
 *
 * A material's own impact model (materials.NAME.impact) is the ground of
 * the impact input: its rows materials.NAME.impact.<field> are stored into
 * the impact input's field of the same name (rf_impact_field_find,
 * rf_impact_field_store: the impact model's units; ground_fields names them), its words
 * boulder_material, slope_material and layer_material parsed by the impact
 * model's parsers. */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"

#include "rockfuzz/impact_model.h"

#include <math.h>
#include <string.h>

const char *traj_impact_solver_name(size_t k)
{
    return k < rf_impact_n_solvers() ? rf_impact_solver_name((rf_impact_solver)k) : NULL;
}

rf_status traj_impact_setup_init(traj_impact_setup *s, const rf_traj_spec *spec, rf_error *err)
{
    memset(s, 0, sizeof *s);
    rf_impact_solver solver;
    if (rf_impact_solver_parse(spec->impact_solver, &solver, err) != RF_OK)
        return rf_error_prefix(err, "bounce.impact.solver");
    s->solver = (int)solver;
    s->radius = spec->radius;
    s->refinement = spec->impact_refinement;
    s->density = spec->density;
    double phi = spec->n_materials ? spec->materials[0].friction_angle : 0;
    s->friction = isnan(spec->impact_friction) ? tan(phi) : spec->impact_friction;
    return RF_OK;
}

rf_status traj_impact_setup_material(traj_impact_setup *s, const rf_traj_spec *spec, size_t k, rf_error *err)
{
    rf_status st = traj_impact_setup_init(s, spec, err);
    if (st != RF_OK || k >= spec->n_materials || !spec->materials[k].impact.given)
        return st;
    const rf_traj_material *m = &spec->materials[k];
    rf_impact_solver solver;
    if (m->impact.solver[0] && rf_impact_solver_parse(m->impact.solver, &solver, err) != RF_OK)
        return rf_error_prefix(err, "materials.%s.impact.solver", m->name);
    if (m->impact.solver[0])
        s->solver = (int)solver;
    s->friction = isnan(spec->impact_friction) ? tan(m->friction_angle) : spec->impact_friction;
    s->has_ground = 1;
    s->ground = m->impact;
    return RF_OK;
}

/* One material word of the ground ("" = the impact model's default) into *dst. */
static rf_status ground_word(const char *word, const char *key, int boulder, rf_material_model *dst, rf_error *err)
{
    if (!word[0])
        return RF_OK;
    rf_status st = boulder ? rf_impact_boulder_material_parse(word, dst, err) : rf_material_model_parse(word, dst, err);
    return st == RF_OK ? RF_OK : rf_error_prefix(err, "%s", key);
}

/* The impact input named by ground number k (the row materials.NAME.impact.<name>
 * of traj_fields.c stores g->v[k]; test_trajectory_impact checks the pairing). */
static const char *const ground_fields[RF_TRAJ_IMPACT_N] = {
    "slope_E", "slope_poisson", "slope_density", "slope_yield", "slope_hardening", "layer_thickness", "layer_E",
    "layer_poisson", "layer_density", "layer_yield", "layer_hardening", "layer_cohesion", "layer_friction_angle",
    "layer_dilatancy_angle", "layer_cap_pressure", "layer_cap_hardening"};

const char *traj_impact_ground_field(size_t k) { return k < RF_TRAJ_IMPACT_N ? ground_fields[k] : NULL; }

double traj_impact_layer_thickness(const rf_traj_impact_ground *g)
{
    for (size_t k = 0; k < RF_TRAJ_IMPACT_N; k++)
        if (!strcmp(ground_fields[k], "layer_thickness"))
            return g->v[k];
    return 0;
}

/* The ground g into the impact input: every number by its impact input's name, then the words. */
static rf_status ground_apply(const rf_traj_impact_ground *g, rf_impact_input *in, rf_error *err)
{
    for (size_t k = 0; k < RF_TRAJ_IMPACT_N; k++) {
        const rf_impact_field *f = rf_impact_field_find(ground_fields[k]);
        if (!f)
            return rf_fail(err, RF_EINVAL, "internal: impact input %s unknown", ground_fields[k]);
        rf_impact_field_store(in, f, g->v[k]);
    }
    rf_status st = ground_word(g->boulder_material, "boulder_material", 1, &in->boulder_material, err);
    if (st == RF_OK)
        st = ground_word(g->slope_material, "slope_material", 0, &in->slope_material, err);
    if (st == RF_OK)
        st = ground_word(g->layer_material, "layer_material", 0, &in->layer_material, err);
    return st;
}

rf_status traj_impact_ground_check(const rf_traj_impact_ground *g, const char *run_solver, rf_error *err)
{
    rf_impact_solver solver;
    const char *name = g->solver[0] ? g->solver : run_solver;
    if (rf_impact_solver_parse(name, &solver, err) != RF_OK)
        return rf_error_prefix(err, "solver");
    rf_impact_input in;
    rf_impact_input_default(&in);
    rf_status st = ground_apply(g, &in, err);
    if (st == RF_OK)
        st = rf_impact_input_validate(&in, err);
    const rf_impact_law *law = rf_impact_solver_law(solver);
    rf_impact_law_settings settings = {NAN, 1.04, NULL}; /* the analytic solvers' checks read neither */
    if (st == RF_OK && solver != RF_IMPACT_FEM && law && law->validate)
        st = law->validate(law, &in, &settings, err);
    return st;
}

int traj_impact_fem(const traj_impact_setup *s)
{
    return s->solver == RF_IMPACT_FEM;
}

int traj_impact_layer_preset(const traj_impact_setup *s)
{
    return s->solver == RF_IMPACT_FEM && s->has_ground && traj_impact_layer_thickness(&s->ground) > 0;
}

rf_status traj_impact_coefficients(const traj_impact_setup *s, double vn, double theta, double *R_n, double *R_t,
                                   double *spin, rf_error *err)
{
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = (rf_impact_solver)s->solver;
    spec.fem.refinement = s->refinement;
    spec.fem.interrupt = s->stop;
    /* a layer that cannot stand at a grazing incidence still has an impact there: the ground no steeper
       than it stands with FS 1.25 (docs/soil-impacts.md section 4b; unchanged where it stands) */
    spec.fem.ground = RF_FEM_GROUND_STABLE;
    if (traj_impact_layer_preset(s))
        spec.fem.rock_mass_scale = 100;
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.radius = s->radius;
    in.boulder_density = s->density;
    in.friction = s->friction;
    rf_status gst = s->has_ground ? ground_apply(&s->ground, &in, err) : RF_OK;
    if (gst != RF_OK)
        return gst;
    const double min_incidence = RF_PI / 180;
    if (theta < min_incidence)
        theta = min_incidence;
    in.velocity = vn / cos(theta);
    in.slope_angle = theta;
    rf_impact_output out;
    rf_status st = rf_impact_solve(&spec, &in, &out, err);
    if (st != RF_OK)
        return rf_error_prefix(err, "impact model at v_n = %g m/s, incidence %g deg", vn, theta * 180 / RF_PI);
    *R_n = out.R_n;
    *R_t = isfinite(out.R_t) ? fmin(fmax(out.R_t, -1), 1) : 1; /* beyond +-1: near-normal noise (above) */
    *spin = isfinite(out.omega_after) && fabs(out.v_t_after) > 1e-12 ? out.omega_after * s->radius / out.v_t_after : 0;
    if (!isfinite(*R_n))
        return rf_fail(err, RF_EMODEL, "impact model at v_n = %g m/s, incidence %g deg: no R_n", vn,
                       theta * 180 / RF_PI);
    return RF_OK;
}
