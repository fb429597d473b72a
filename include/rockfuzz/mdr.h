/* mdr.h - oblique impact of an elastic sphere on an elastic half-space with
 * Hertz normal contact and exact Mindlin-Deresiewicz partial slip under
 * Coulomb friction, solved with the method of dimensionality reduction (MDR;
 * Popov & Hess 2015, "Method of Dimensionality Reduction in Contact Mechanics
 * and Friction", ch. 2-3 and 8; Popov & Hess 2014, Facta Universitatis 12:1).
 * This is Maw, Barber & Fawcett's problem (Wear 38:101, 1976).
 *
 * The 3D contact is mapped onto a row of independent 1D springs on the
 * profile g(x) = x^2/R: normal stiffness E* dx, tangential stiffness G* dx,
 * each tangential spring sticking or slipping under its own Coulomb limit
 * |q(x)| <= mu E* (d - g(x)).  This is exact (within the Cattaneo-Mindlin
 * assumptions: tractions along the motion, tangential tractions do not change
 * the pressure) for any history of normal and tangential displacement,
 * including unloading and reversal.
 *
 * Moduli (SI, Pa):
 *   1/E* = (1-nu_b^2)/E_b + (1-nu_s^2)/E_s
 *   1/G* = (2-nu_b)/(4 G_b) + (2-nu_s)/(4 G_s),  G = E / (2 (1+nu))
 * The stuck-contact tangential stiffness is 2 G* a (= 8 G_J a with Johnson's
 * 1/G_J = (2-nu_b)/G_b + (2-nu_s)/G_s).
 *
 * Dissimilar materials: the normal-tangential coupling, measured by Dundurs'
 * beta (rf_mdr_dundurs_beta), is NEUTRALISED (taken as 0), as in Mindlin,
 * MBF and most DEM.  It is exactly 0 for identical materials (granite on
 * granite); for |beta| < 0.1 its effect on the tangential response is a few
 * percent of the tangential force near the contact edge.
 *
 * Sign conventions: n along the outward slope normal, t down-slope, omega
 * positive when rolling down-slope; contact-point velocity v_c = v_t - omega R. */
#ifndef ROCKFUZZ_MDR_H
#define ROCKFUZZ_MDR_H

#include "rockfuzz/impact.h"
#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --- the spring bank: a static contact under a prescribed history --- */

typedef struct {
    size_t n;        /* springs on 0 <= x <= n dx (the other half by symmetry) */
    double dx;       /* spring width [m] */
    double R;        /* curvature radius of the sphere [m] */
    double E_star;   /* [Pa] */
    double G_star;   /* MDR tangential modulus [Pa] */
    double friction; /* Coulomb coefficient [-] */
    double a;        /* contact radius of the last step [m] */
    double *q;       /* tangential force of each spring [N] (one half of the contact) */
    double *w;       /* integral of g(x) = x^2/R over each whole strip [m^2] */
} rf_mdr_contact;

/* Springs covering contact radii up to a_max [m] (keep sqrt(R d) <= a_max in
 * rf_mdr_contact_step: beyond it the bank is cut off).  Free with
 * rf_mdr_contact_free. */
rf_status rf_mdr_contact_init(rf_mdr_contact *c, size_t n, double a_max, double R, double E_star,
                              double G_star, double friction, rf_error *err);
void rf_mdr_contact_free(rf_mdr_contact *c);
/* Move the contact to indentation d [m] (normal forces scaled by `scale`,
 * 1 = elastic) while the sphere moves tangentially by du [m] relative to the
 * half-space far field.  Returns the tangential force on the half-space [N]
 * (the sphere feels its negative); *normal_force receives the normal force [N]. */
double rf_mdr_contact_step(rf_mdr_contact *c, double d, double du, double scale, double *normal_force);

/* --- the impact --- */

typedef struct {
    double radius;    /* R: curvature radius at the contact and lever arm [m] */
    double mass;      /* [kg] */
    double inertia;   /* about the axis normal to the plane of motion [kg m^2] */
    double E_star;    /* [Pa] */
    double G_star;    /* [Pa], MDR tangential modulus */
    double friction;  /* [-] */
    double e_n;       /* normal COR in (0, 1]: 1 elastic; < 1 scales the normal
                         force of the restitution phase by e_n^2 (see mdr.c) */
    double v_n;       /* approach speed towards the slope [m/s], > 0 */
    double v_t;       /* tangential CM velocity before [m/s] */
    double omega;     /* spin before [rad/s] */
} rf_mdr_problem;

typedef struct {
    size_t springs;   /* springs over the largest contact radius (default 100) */
    size_t steps;     /* time steps per elastic Hertz contact duration (default 400);
                         the defaults keep R_t within 3e-5 of the converged value */
} rf_mdr_options;

void rf_mdr_options_default(rf_mdr_options *o);

typedef struct {
    double v_n_after;        /* rebound speed away from the slope [m/s] */
    double v_t_after;        /* [m/s] */
    double omega_after;      /* [rad/s] */
    double contact_force_max, tangential_force_max; /* [N] */
    double compression_max;  /* [m] */
    double contact_duration; /* [s] */
    double contact_radius;   /* at maximum compression [m] */
    double friction_work;    /* energy dissipated in the contact [J]: slip, and the release
                                of stuck springs at a receding contact edge */
    double beta_t;           /* v_c' / v_c: contact-point velocity after / before (NaN if v_c = 0) */
    double chi;              /* MBF: (G_star/E_star)(1 + m R^2/I)/2 */
    double psi1, psi2;       /* MBF: (G_star/E_star) v_c/(mu v_n), and the same with v_c after */
    size_t steps;            /* time steps taken */
} rf_mdr_result;

rf_status rf_mdr_impact(const rf_mdr_problem *p, const rf_mdr_options *o, rf_mdr_result *r, rf_error *err);

/* --- the impact model's inputs --- */

/* MDR tangential modulus G* [Pa] and Dundurs' beta [-] of boulder and slope. */
double rf_mdr_tangential_modulus(const rf_impact_input *in);
double rf_mdr_dundurs_beta(const rf_impact_input *in);

/* The boulder of `in` (sphere; a spheroid only in normal impact) falling
 * vertically without spin, with normal COR e_n (1 = elastic); fills the
 * rf_impact_output like rf_impact_rigid, plus the contact quantities. */
rf_status rf_impact_mdr(const rf_impact_input *in, double e_n, rf_impact_output *out, rf_error *err);
/* The same with e_n = NaN meaning Hunter's e_n = sqrt(1 - lambda), lambda =
 * A (v_n/c0)^(3/5) (rf_hunter_loss): the impact model's default. */
rf_status rf_impact_mdr_hunter(const rf_impact_input *in, double e_n, double hunter_A, rf_impact_output *out,
                               rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
