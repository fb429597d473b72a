/* impact.h - boulder-on-slope impact: inputs, outputs, analytic references,
 * and the impact model that the study layer binds fuzzy parameters to.
 *
 * Units: SI throughout (m, kg, s, Pa, N, J, rad).  The boulder is a sphere of
 * radius `radius`, or a spheroid with horizontal semi-axis c and vertical
 * semi-axis d (set horizontal_axis > 0; d = radius^3 / c^2 keeps the volume
 * of the sphere of radius `radius`).  The slope is an elastic half-space.
 * Velocity is the vertical impact speed; slope_angle tilts the slope. */
#ifndef ROCKFUZZ_IMPACT_H
#define ROCKFUZZ_IMPACT_H

#include "rockfuzz/status.h"
#include "rockfuzz/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double radius;           /* r0 [m] (sphere radius; volume-equivalent radius of a spheroid) */
    double horizontal_axis;  /* c [m]; <= 0 means sphere */
    double vertical_axis;    /* d [m]; derived = radius^3/c^2 when c > 0 and d <= 0 */
    double boulder_density;  /* [kg/m^3] */
    double slope_density;    /* [kg/m^3] */
    double boulder_E;        /* [Pa] */
    double slope_E;          /* [Pa] */
    double boulder_poisson;  /* [-] */
    double slope_poisson;    /* [-] */
    double velocity;         /* vertical impact speed [m/s], > 0 */
    double slope_angle;      /* [rad], 0 = horizontal slope */
    double friction;         /* Coulomb coefficient [-], static = kinetic */
} rf_impact_input;

/* Nominal granite of SYSTEM.md: r0 = 1 m, rho 2600, E 68.2 GPa, nu 0.25,
 * 10 m/s, horizontal slope, friction 0. */
void rf_impact_input_default(rf_impact_input *in);

/* Check ranges; the message names the field and value. */
rf_status rf_impact_input_validate(const rf_impact_input *in, rf_error *err);

typedef struct {
    double contact_force_max;   /* [N] */
    double compression_max;     /* [m] approach of the boulder CM after first contact */
    double contact_duration;    /* [s] */
    double contact_radius;      /* [m] at peak force */
    double R_n, R_t, R_ke;      /* coefficients of restitution [-] (R_t NaN when v_t = 0) */
    double v_n_before, v_t_before, v_n_after, v_t_after; /* [m/s], n along outward slope normal */
    double omega_after;         /* [rad/s] */
    double energy_error;        /* energy closure error / initial KE [-] (0 for analytic models) */
    double nodes, elements, steps, wall_seconds; /* FE statistics (0 for analytic models) */
} rf_impact_output;

/* --- analytic references (impact_refs.md) --- */

/* Effective modulus 1/E* = (1-nu_b^2)/E_b + (1-nu_s^2)/E_s [Pa]. */
double rf_impact_effective_modulus(const rf_impact_input *in);
/* Boulder mass [kg], and curvature radius at the contact point [m]
 * (r0 for a sphere, c^2/d at the pole of a spheroid). */
double rf_impact_mass(const rf_impact_input *in);
double rf_impact_contact_curvature_radius(const rf_impact_input *in);
/* Hertz contact radius at maximum compression, the fine-zone size of SYSTEM.md [m]. */
double rf_hertz_contact_radius(const rf_impact_input *in);

/* Hertz normal impact on a half-space (normal velocity component). */
rf_status rf_impact_hertz(const rf_impact_input *in, rf_impact_output *out, rf_error *err);
/* Hunter-type wave-loss COR: Hertz plus lambda = A (v/c0)^(3/5); A documented in impact.c. */
rf_status rf_impact_hunter(const rf_impact_input *in, rf_impact_output *out, rf_error *err);
/* Rigid-body oblique impact with Coulomb friction, normal COR e_n given. */
rf_status rf_impact_rigid(const rf_impact_input *in, double e_n, rf_impact_output *out, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
