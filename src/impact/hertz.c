/* hertz.c - Hertz normal impact of a sphere (or a spheroid at its pole) on an
 * elastic half-space, and Hunter's (1957) elastic-wave loss on top of it.
 * Formulas: impact_refs.md sec. 1.1 (Johnson 1985, ch. 4 and 11.4); wave loss
 * sec. 2.  The tangential/rotational part of the rebound uses the rigid-body
 * Coulomb law (rigid_kinematics.c) with the normal COR of the model. */
#include "impact/impact_internal.h"

#include <math.h>
#include <stdio.h>

/* Integral_0^1 dx / sqrt(1 - x^(5/2)) = (2/5) B(2/5, 1/2), so that
 * t_c = 2 (2/5) B(2/5, 1/2) delta_max / v_n. */
double rf_hertz_duration_factor(void)
{
    return 2.0 * 0.4 * tgamma(0.4) * tgamma(0.5) / tgamma(0.9);
}

static double normal_speed(const rf_impact_input *in)
{
    return in->velocity * cos(in->slope_angle);
}

/* SYSTEM.md writes a = (15 R^2 m v^2 (X_b + X_s) / 16)^(1/5), X = (1-nu^2)/E.
 * This is the same as a = sqrt(R delta_max) with
 * delta_max = [15 m v^2 / (16 E* R^(1/2))]^(2/5): a^5 = R^(5/2) delta^(5/2)
 * = 15 m v^2 R^2 / (16 E*) and 1/E* = X_b + X_s.  The slope is a half-space
 * (effective mass m* = m) and v is the normal velocity component. */
double rf_hertz_contact_radius(const rf_impact_input *in)
{
    double R = rf_impact_contact_curvature_radius(in);
    double m = rf_impact_mass(in), v = normal_speed(in);
    double x_sum = 1.0 / rf_impact_effective_modulus(in);
    return pow(15.0 * R * R * m * v * v * x_sum / 16.0, 0.2);
}

void rf_impact_hertz_reference(const rf_impact_input *in, rf_hertz_reference *h)
{
    h->c = in->horizontal_axis > 0.0 ? in->horizontal_axis : in->radius;
    h->d = rf_impact_vertical_semi_axis(in);
    h->curvature_radius = rf_impact_contact_curvature_radius(in);
    h->mass = rf_impact_mass(in);
    h->effective_modulus = rf_impact_effective_modulus(in);
    h->normal_velocity = normal_speed(in);
    h->tangential_velocity = in->velocity * sin(in->slope_angle);
    const double R = h->curvature_radius, m = h->mass, v = h->normal_velocity, Es = h->effective_modulus;
    /* (1/2) m v^2 = (2/5) k delta^(5/2), k = (4/3) E* R^(1/2) */
    const double delta = pow(15.0 * m * v * v / (16.0 * Es * sqrt(R)), 0.4);
    h->compression = delta;
    h->force = 4.0 / 3.0 * Es * sqrt(R) * pow(delta, 1.5);
    h->contact_radius = sqrt(R * delta);
    h->duration = rf_hertz_duration_factor() * delta / v;
}

static rf_status hertz_normal(const rf_impact_input *in, rf_impact_output *out, rf_error *err)
{
    rf_status st = rf_impact_input_validate(in, err);
    if (st != RF_OK)
        return st;
    rf_hertz_reference h;
    rf_impact_hertz_reference(in, &h);
    out->compression_max = h.compression;
    out->contact_force_max = h.force;
    out->contact_radius = h.contact_radius;
    out->contact_duration = h.duration;
    return RF_OK;
}

rf_status rf_impact_hertz(const rf_impact_input *in, rf_impact_output *out, rf_error *err)
{
    rf_impact_output_clear(out);
    rf_status st = hertz_normal(in, out, err);
    if (st != RF_OK)
        return st;
    return rf_impact_kinematics_(in, 1.0, out, err);
}

/* Hunter (1957), in the form quoted by Johnson (1985, "Contact Mechanics",
 * sec. 11.4): the fraction of the normal kinetic energy radiated as elastic
 * waves into the half-space is lambda = A (v_n/c0)^(3/5), c0 = sqrt(E/rho) of
 * the slope, A = 1.04 (RF_HUNTER_A_JOHNSON; coefficient recalled, not
 * re-verified).  impact_refs.md sec. 2.2 re-derives A = 1.112 (exact Hertz
 * pulse) to 1.171 (half-sine) for nu = 0.25 from the Miller-Pursey radiation
 * of a surface point force; report the spread as the theoretical band.  The
 * law is stated for sphere and half-space of similar material. */
double rf_hunter_loss(const rf_impact_input *in, double A)
{
    double c0 = sqrt(in->slope_E / in->slope_density);
    return A * pow(normal_speed(in) / c0, 0.6);
}

rf_status rf_impact_hunter_A(const rf_impact_input *in, double A, rf_impact_output *out,
                             rf_error *err)
{
    rf_impact_output_clear(out);
    if (!isfinite(A) || A < 0.0)
        return rf_fail(err, RF_EINVAL, "Hunter coefficient A = %g: must be finite and >= 0", A);
    rf_status st = hertz_normal(in, out, err);
    if (st != RF_OK)
        return st;
    double lambda = rf_hunter_loss(in, A);
    if (!(lambda < 1.0))
        return rf_fail(err, RF_EMODEL,
                       "Hunter wave loss lambda = %g >= 1 at normal velocity %g m/s: outside the "
                       "law's range", lambda, normal_speed(in));
    return rf_impact_kinematics_(in, sqrt(1.0 - lambda), out, err);
}

rf_status rf_impact_hunter(const rf_impact_input *in, rf_impact_output *out, rf_error *err)
{
    return rf_impact_hunter_A(in, RF_HUNTER_A_JOHNSON, out, err);
}

static rf_status hertz_solve(const rf_impact_input *in, const rf_impact_law_settings *s, rf_impact_output *out,
                             rf_error *err)
{
    (void)s;
    return rf_impact_hertz(in, out, err);
}

const rf_impact_law rf_impact_law_hertz = {"hertz", "elastic Hertz, R_n = 1", rf_impact_analytic_validate,
                                           hertz_solve, NULL};

static rf_status hunter_solve(const rf_impact_input *in, const rf_impact_law_settings *s, rf_impact_output *out,
                              rf_error *err)
{
    return rf_impact_hunter_A(in, s->hunter_coefficient, out, err);
}

static int hunter_identity(const rf_impact_law_settings *s, char *buf, size_t size)
{
    return snprintf(buf, size, " hunter_A=%.17g", s->hunter_coefficient);
}

const rf_impact_law rf_impact_law_hunter = {"hunter", "Hertz + Hunter (1957) wave loss",
                                            rf_impact_analytic_validate, hunter_solve, hunter_identity};
