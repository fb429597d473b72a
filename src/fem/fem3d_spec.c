/* fem3d_spec.c - the 3D impact's mesh specification (see fem3d_spec.h).
 * The arithmetic is the solver's own (fem3d_prepare.c, "fine boxes"): Hertz
 * radius and duration from the normal velocity component, uniform cubes of
 * size a/refinement over core_factor * a, elongated down-slope by the patch
 * travel; a thick layer's own contact (f3_layer_contact_estimate, below).
 * Until the solver calls this function, the two must be kept equal;
 * test_hex8_kernel (granite) and test_fem3d_layer (a soft layer) check the
 * element count against the solver's. */
#include "fem3d_spec.h"
#include "core/util.h"

#include <math.h>
#include <string.h>

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
    double t_h = 2.94328 * delta_h / Vn;
    f3_layer_contact lc = {0};
    if (in->layer_thickness > 0)
        f3_layer_contact_estimate(in, &lc);
    if (lc.thick) /* the boulder stays in the layer: its contact alone */
        a_h = lc.radius, a_x = fmax(lc.radius, lc.zone_radius / o3->fine_box_factor), t_h = lc.duration;
    const double refinement = rf_fem_refinement(o, 1);
    const double h = a_h / refinement, hb = h * fem_tuning_of(o)->boulder_mesh_ratio, travel = o3->elongation * Vt * t_h;
    memset(ms, 0, sizeof *ms);
    ms->full = o3->full_model != 0;
    int n_s = (int)ceil(o3->fine_box_factor * a_x / h - 1e-9), n_b = (int)ceil(o3->fine_box_factor * a_x / hb - 1e-9);
    ms->slope = (f3_box){n_s, n_s + (int)ceil(travel / h - 1e-9), n_s, n_s, h};
    const double sxy = c / in->radius, sz = d / in->radius;
    ms->boulder = (f3_box){n_b, n_b + (int)ceil(travel / hb - 1e-9), n_b, n_b, hb / sxy};
    if (lc.thick && in->boulder_material == RF_MATERIAL_RIGID_BODY)
        f3_soft_boulder_box(&ms->boulder, o3->fine_box_factor * a_x, travel, in->radius, sxy);
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

/* W(delta) = int_0^delta pi R s p(s) ds for the mean pressure p = A + B sqrt(s / R). */
static double branch_work(double A, double B, double R, double s)
{
    return RF_PI * R * (A * s * s / 2 + 0.4 * B * pow(s, 2.5) / sqrt(R));
}

/* Work of p = min(k_e sqrt(s/R), A + B sqrt(s/R)) (B < k_e) up to delta. */
static double soft_work(double ke, double A, double B, double R, double delta)
{
    const double cross = ke > B ? R * (A / (ke - B)) * (A / (ke - B)) : INFINITY;
    if (delta <= cross)
        return branch_work(0, ke, R, delta);
    return branch_work(0, ke, R, cross) + branch_work(A, B, R, delta) - branch_work(A, B, R, cross);
}

void f3_layer_contact_estimate(const rf_impact_input *in, f3_layer_contact *lc)
{
    rf_impact_input lay = *in;
    lay.slope_density = in->layer_density, lay.slope_E = in->layer_E, lay.slope_poisson = in->layer_poisson;
    rf_hertz_reference HL;
    rf_impact_hertz_reference(&lay, &HL);
    memset(lc, 0, sizeof *lc);
    lc->compression = HL.compression, lc->radius = HL.contact_radius, lc->zone_radius = HL.contact_radius;
    lc->duration = HL.duration;
    const double R = HL.curvature_radius, Es = HL.effective_modulus, ke = 4 / (3 * RF_PI) * Es;
    double A = 0, B = ke;
    if (in->layer_material == RF_MATERIAL_VON_MISES)
        A = 3 * in->layer_yield, B = 0; /* fully plastic indentation, p_m = 3 Y (Johnson 1985, ch. 6) */
    else if (in->layer_material == RF_MATERIAL_DRUCKER_PRAGER && in->layer_cap_pressure > 0) {
        const double E = in->layer_E, nu = in->layer_poisson, Hc = in->layer_cap_hardening;
        const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)); /* constrained modulus */
        A = in->layer_cap_pressure, B = ke * Hc / (Hc + M);
    }
    if (in->layer_material != RF_MATERIAL_ELASTIC) {
        const double ke0 = 0.5 * HL.mass * HL.normal_velocity * HL.normal_velocity;
        double lo = 0, hi = HL.compression;
        while (soft_work(ke, A, B, R, hi) < ke0 && hi < 1e3 * R)
            hi *= 2;
        for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; it++) {
            const double mid = 0.5 * (lo + hi);
            if (soft_work(ke, A, B, R, mid) < ke0)
                lo = mid;
            else
                hi = mid;
        }
        const double d = hi;
        lc->compression = d, lc->radius = sqrt(R * d);
        const double d2 = fmin(2 * d, R); /* margin: the estimate is within ~10-20 % (section 9c) */
        lc->zone_radius = fmin(fmax(sqrt(2 * R * d2 - d2 * d2), lc->radius), 0.95 * HL.c);
        lc->duration = rf_hertz_duration_factor() * d / HL.normal_velocity;
    }
    /* the boulder stays in the layer, and the stress under the contact spreads in it before the rock */
    lc->thick = in->layer_thickness > 0 && lc->compression <= 0.5 * in->layer_thickness &&
                lc->radius <= in->layer_thickness;
}

double f3_ball_image_radius(double s, double r)
{
    const double q = fmin(s / r, 0.95);
    return q > 1e-6 ? 2 * r * (1 - sqrt(1 - q * q)) / q : s;
}

void f3_soft_boulder_box(f3_box *b, double half_width, double travel, double r0, double scale_xy)
{
    const double s = half_width / scale_xy, st = (half_width + travel) / scale_xy;
    b->nxm = b->ny = b->nz = (int)ceil(f3_ball_image_radius(s, r0) / b->h - 1e-9);
    b->nxp = (int)ceil(f3_ball_image_radius(st, r0) / b->h - 1e-9);
}
