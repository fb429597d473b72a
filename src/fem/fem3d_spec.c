/* fem3d_spec.c - the 3D impact's mesh specification (see fem3d_spec.h).
 * The arithmetic is the solver's own (fem3d_solver.c, "fine boxes"): Hertz
 * radius and duration from the normal velocity component, uniform cubes of
 * size a/refinement over core_factor * a, elongated down-slope by the patch
 * travel.  Until the solver calls this function, the two must be kept equal;
 * test_hex8_kernel checks the element count against the solver's. */
#include "fem3d_spec.h"
#include "core/util.h"

#include <math.h>
#include <string.h>

#include "core/util.h"

void f3_impact_mesh_spec(const rf_impact_input *in, const rf_fem_options *o, const rf_fem3d_options *o3,
                         f3_mesh_spec *ms, double *h_out, double *a_hertz)
{
    const double alpha = in->slope_angle, V = in->velocity;
    const double Vn = V * cos(alpha), Vt = V * sin(alpha);
    double c = in->radius, d = in->radius;
    if (in->horizontal_axis > 0) {
        c = in->horizontal_axis;
        d = in->vertical_axis > 0 ? in->vertical_axis : in->radius * in->radius * in->radius / (c * c);
    }
    const double Rc = c * c / d, mass = 4.0 / 3.0 * RF_PI * c * c * d * in->boulder_density;
    const double Estar = rf_impact_effective_modulus(in); /* a rigid boulder: the slope's alone */
    double delta_h = pow(15 * mass * Vn * Vn / (16 * Estar * sqrt(Rc)), 0.4);
    double a_h = sqrt(Rc * delta_h), a_x = a_h;
    if (in->layer_thickness > 0) { /* the finer of the slope's and the layer's contacts, the longer duration */
        rf_impact_input lay = *in;
        lay.slope_E = in->layer_E, lay.slope_poisson = in->layer_poisson;
        const double dl = pow(15 * mass * Vn * Vn / (16 * rf_impact_effective_modulus(&lay) * sqrt(Rc)), 0.4);
        a_x = fmax(a_h, sqrt(Rc * dl)), a_h = fmin(a_h, sqrt(Rc * dl)), delta_h = fmax(delta_h, dl);
    }
    const double t_h = 2.94328 * delta_h / Vn;
    const double refinement = rf_fem_refinement(o, 1);
    const double h = a_h / refinement, hb = h * o->boulder_mesh_ratio, travel = o3->elongation * Vt * t_h;
    memset(ms, 0, sizeof *ms);
    ms->full = o3->full_model != 0;
    int n_s = (int)ceil(o3->core_factor * a_x / h - 1e-9), n_b = (int)ceil(o3->core_factor * a_x / hb - 1e-9);
    ms->slope = (f3_box){n_s, n_s + (int)ceil(travel / h - 1e-9), n_s, n_s, h};
    const double sxy = c / in->radius, sz = d / in->radius;
    ms->boulder = (f3_box){n_b, n_b + (int)ceil(travel / hb - 1e-9), n_b, n_b, hb / sxy};
    ms->radius = in->radius;
    ms->scale_xy = sxy, ms->scale_z = sz;
    ms->boulder_inner = o3->boulder_inner;
    ms->domain = rf_fem_domain_factor(o, in) * in->radius; /* automatic settings resolved as the solver does */
    ms->layer_aspect = o3->layer_aspect;
    ms->extruded = in->layer_thickness > 0 || o3->layered_mesh;
    ms->layer_depth = in->layer_thickness > 0 ? in->layer_thickness : 0;
    if (h_out)
        *h_out = h;
    if (a_hertz)
        *a_hertz = a_h;
}
