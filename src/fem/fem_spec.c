/* fem_spec.c - the axisymmetric impact's mesh specification (fem_spec.h).
 * The arithmetic is the solver's own (fem_axi_setup.c, "mesh sizing from the
 * Hertz contact radius"); until the solver calls this function the two must
 * be kept equal, and test_quad4_kernel checks the element count against a
 * solver run. */
#include "fem_spec.h"
#include "core/util.h"

#include <math.h>
#include <string.h>

#include "core/util.h"

rf_status fem_impact_mesh_spec(const rf_impact_input *in, const rf_fem_options *o, fem_body_spec *bs,
                               fem_body_spec *ss, rf_error *err)
{
    double c = in->radius, d = in->radius;
    if (in->horizontal_axis > 0) {
        c = in->horizontal_axis;
        d = in->vertical_axis > 0 ? in->vertical_axis : in->radius * in->radius * in->radius / (c * c);
    }
    const double R = c * c / d, mass = 4.0 / 3.0 * RF_PI * c * c * d * in->boulder_density, V = in->velocity;
    const double Estar = 1 / ((1 - in->boulder_poisson * in->boulder_poisson) / in->boulder_E +
                              (1 - in->slope_poisson * in->slope_poisson) / in->slope_E);
    const double delta = pow(15 * mass * V * V / (16 * Estar * sqrt(R)), 0.4);
    const double a = sqrt(R * delta), duration = 2.94328 * delta / V, L = rf_fem_domain_factor(o, in) * in->radius;
    const double nu = in->slope_poisson, mu = in->slope_E / (2 * (1 + nu));
    const double cs = sqrt(mu / in->slope_density), cr = cs * (0.87 + 1.12 * nu) / (1 + nu);
    const rf_fem_tuning *t = fem_tuning_of(o);
    const double refinement = rf_fem_refinement(o, 0); /* automatic settings resolved as the solver does */
    const double h = a / refinement, hb = h * t->boulder_mesh_ratio;
    const double core = fmin(t->fine_zone_factor, 0.55 * fmin(c, d) / a);
    if (core < 1.5)
        return rf_fail(err, RF_EINVAL, "fem spec: the Hertz contact radius %.4g m is too large for the boulder", a);
    memset(bs, 0, sizeof *bs), memset(ss, 0, sizeof *ss);
    ss->h = h;
    ss->n = 3 * (int)ceil(core * refinement / 3 - 1e-9);
    while (ss->n > 3 && ss->n * h > 0.6 * fmin(c, d))
        ss->n -= 3;
    ss->grading = t->grading;
    ss->h_far = fmax(h, fmin(cr * duration / 12, L / 8));
    ss->extent = L;
    bs->h = hb;
    bs->n = 3 * (int)ceil(core * refinement / t->boulder_mesh_ratio / 3 - 1e-9);
    while (bs->n > 3 && bs->n * hb > 0.6 * fmin(c, d))
        bs->n -= 3;
    bs->grading = t->grading;
    bs->h_far = fmax(hb, fmin(c, d) / 10);
    bs->extent = c;
    bs->height = d;
    return RF_OK;
}
