/* rigid_kinematics.c - rigid-body oblique impact of a sphere with Coulomb
 * friction (impact_refs.md sec. 4.1; Stronge 2000 "Impact Mechanics",
 * Brach 1991).  The sphere falls vertically at V onto a slope inclined at
 * alpha, without spin: v_n = V cos alpha into the slope, v_t = V sin alpha
 * down-slope.  Normal impulse P_n = m (1 + e_n) v_n, tangential P_t <= mu P_n.
 * With k = I/(m R^2) the slip of the contact point stops after a tangential
 * impulse m v_t / (1 + 1/k), so the sphere slides throughout iff
 * mu (1 + e_n) v_n < v_t / (1 + 1/k).  Signs: n along the outward slope
 * normal, t and omega positive down-slope (rolling). */
#include "impact/impact_internal.h"

#include <math.h>

rf_status rf_impact_kinematics_(const rf_impact_input *in, double e_n, rf_impact_output *out,
                                rf_error *err)
{
    double V = in->velocity;
    double vn = V * cos(in->slope_angle), vt = V * sin(in->slope_angle);
    double mu = in->friction;
    if (vt > 0.0 && in->horizontal_axis > 0.0)
        return rf_fail(err, RF_EINVAL,
                       "horizontal_axis = %g with slope_angle = %g deg: the analytic models treat "
                       "a spheroid only in normal impact on its pole (slope_angle = 0); use the "
                       "FE solver", in->horizontal_axis, in->slope_angle * 180.0 / RF_PI);
    double R = in->radius;
    double k = rf_impact_moment_of_inertia(in) / (rf_impact_mass(in) * R * R); /* 2/5 */
    double vt_after = vt, omega = 0.0;
    if (vt > 0.0) {
        double Pt_stick = vt / (1.0 + 1.0 / k);   /* per unit mass */
        double Pt_slide = mu * (1.0 + e_n) * vn;  /* per unit mass */
        double Pt = Pt_slide < Pt_stick ? Pt_slide : Pt_stick;
        vt_after = vt - Pt;
        omega = Pt / (k * R);
    }
    out->v_n_before = -vn;
    out->v_t_before = vt;
    out->v_n_after = e_n * vn;
    out->v_t_after = vt_after;
    out->omega_after = omega;
    out->R_n = e_n;
    out->R_t = vt > 0.0 ? vt_after / vt : NAN;
    double ke_after = (e_n * vn) * (e_n * vn) + vt_after * vt_after + k * R * R * omega * omega;
    out->R_ke = ke_after / (V * V);
    return RF_OK;
}

rf_status rf_impact_rigid(const rf_impact_input *in, double e_n, rf_impact_output *out,
                          rf_error *err)
{
    rf_impact_output_clear(out);
    rf_status st = rf_impact_input_validate(in, err);
    if (st != RF_OK)
        return st;
    if (!isfinite(e_n) || e_n < 0.0 || e_n > 1.0)
        return rf_fail(err, RF_EINVAL, "e_n = %g: the normal COR must lie in [0, 1]", e_n);
    /* Impulsive contact: force, compression, duration and contact radius are
     * not defined by a rigid-body model and stay NaN. */
    return rf_impact_kinematics_(in, e_n, out, err);
}
