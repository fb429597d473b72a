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
 * V = v_n / cos theta on a slope inclined at theta.  Returned: R_n, R_t and
 * the spin ratio omega r / v_t' after the impact (0 when not computed).  At
 * normal incidence R_t is undefined (v_t = 0): incidences below 1 degree are
 * evaluated at 1 degree (closer to normal, the FE's R_t becomes a ratio of
 * numerical noise to a vanishing v_t; the rigid model's R_t is constant
 * there, so nothing is lost); a model that gives no R_t (hertz, hunter:
 * normal impact only) gets R_t = 1 (no tangential loss). */
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

rf_status traj_impact_coefficients(const traj_impact_setup *s, double vn, double theta, double *R_n, double *R_t,
                                   double *spin, rf_error *err)
{
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = (rf_impact_solver)s->solver;
    spec.fem.refinement = s->refinement;
    spec.fem.interrupt = s->stop;
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.radius = s->radius;
    in.boulder_density = s->density;
    in.friction = s->friction;
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
    *R_t = isfinite(out.R_t) ? out.R_t : 1;
    *spin = isfinite(out.omega_after) && fabs(out.v_t_after) > 1e-12 ? out.omega_after * s->radius / out.v_t_after : 0;
    if (!isfinite(*R_n))
        return rf_fail(err, RF_EMODEL, "impact model at v_n = %g m/s, incidence %g deg: no R_n", vn,
                       theta * 180 / RF_PI);
    return RF_OK;
}
