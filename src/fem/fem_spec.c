/* fem_spec.c - the axisymmetric impact's mesh specification (fem_spec.h).
 * The arithmetic is the solver's own (fem_axi_setup.c, "mesh sizing from the
 * Hertz contact radius"); until the solver calls this function the two must
 * be kept equal, and test_quad4_kernel checks the element count against a
 * solver run (test_soil_mesh for a thick layer with mesh_sizing soil).
 * Also the contact that sizes a thick soil layer's mesh (fem_soil_contact_zone),
 * which the solver calls. */
#include "fem_spec.h"
#include "fem3d_spec.h"

#include <math.h>
#include <string.h>

#include "core/util.h"

int fem_soil_contact_zone(const rf_impact_input *in, const rf_fem_options *o, double *a, double *zone)
{
    if (o->mesh_sizing != RF_FEM_SIZING_SOIL || !(in->layer_thickness > 0))
        return 0;
    f3_layer_contact lc;
    f3_layer_contact_estimate(in, &lc);
    if (!lc.thick)
        return 0;
    *a = lc.radius, *zone = lc.zone_radius;
    return 1;
}

rf_status fem_impact_mesh_spec(const rf_impact_input *in, const rf_fem_options *o, fem_body_spec *bs,
                               fem_body_spec *ss, rf_error *err)
{
    double c = in->radius, d = in->radius;
    if (in->horizontal_axis > 0) {
        c = in->horizontal_axis;
        d = in->vertical_axis > 0 ? in->vertical_axis : in->radius * in->radius * in->radius / (c * c);
    }
    rf_hertz_reference H;
    rf_wave_speeds w;
    rf_impact_hertz_reference(in, &H);
    rf_impact_wave_speeds(in, 1, &w);
    double a = H.contact_radius, duration = H.duration, cr = w.rayleigh, zone = 0;
    if (in->layer_thickness > 0) { /* the finer of the two contacts, the longer duration (axi_prepare) */
        rf_impact_input lay = *in;
        lay.slope_density = in->layer_density, lay.slope_E = in->layer_E, lay.slope_poisson = in->layer_poisson;
        rf_hertz_reference HL;
        rf_impact_hertz_reference(&lay, &HL);
        rf_impact_wave_speeds(&lay, 1, &w);
        a = fmin(a, HL.contact_radius), duration = fmax(duration, HL.duration), cr = fmin(cr, w.rayleigh);
    }
    const rf_fem_tuning *t = fem_tuning_of(o);
    const int soil = fem_soil_contact_zone(in, o, &a, &zone);
    const double L = rf_fem_domain_factor(o, in) * in->radius;
    const double refinement = rf_fem_refinement(o, 0); /* automatic settings resolved as the solver does */
    const double h = a / refinement, hb = h * t->boulder_mesh_ratio;
    const double core = soil ? fmin(zone / a, 0.55 * fmin(c, d) / a) : fmin(t->fine_zone_factor, 0.55 * fmin(c, d) / a);
    if (!soil && core < 1.5) /* soil: the boulder's zone is capped below, not refused (axi_mesh) */
        return rf_fail(err, RF_EINVAL, "fem spec: the Hertz contact radius %.4g m is too large for the boulder", a);
    memset(bs, 0, sizeof *bs), memset(ss, 0, sizeof *ss);
    ss->h = h;
    ss->n = 3 * (int)ceil((soil ? zone / a : core) * refinement / 3 - 1e-9);
    while (!soil && ss->n > 3 && ss->n * h > 0.6 * fmin(c, d))
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
