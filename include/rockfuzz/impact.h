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


/* --- additions (impact module) --- */

/* Vertical semi-axis d [m] actually used: radius for a sphere, vertical_axis
 * if set, else radius^3/c^2 (constant volume). */
double rf_impact_vertical_semi_axis(const rf_impact_input *in);
/* Moment of inertia of the boulder about a horizontal axis through its
 * centre [kg m^2]: 2/5 m r0^2 (sphere), m (c^2 + d^2)/5 (spheroid). */
double rf_impact_moment_of_inertia(const rf_impact_input *in);
/* Name of the first field that rf_impact_input_validate rejects, or NULL. */
const char *rf_impact_input_first_invalid(const rf_impact_input *in);

/* Hunter (1957) wave-loss coefficients A in lambda = A (v_n/c0)^(3/5):
 * the value quoted in Johnson 1985 sec. 11.4, and the band re-derived in
 * impact_refs.md sec. 2.2 for nu = 0.25 (exact Hertz pulse, half-sine pulse). */
#define RF_HUNTER_A_JOHNSON 1.04
#define RF_HUNTER_A_EXACT_PULSE 1.112
#define RF_HUNTER_A_HALF_SINE 1.171
/* Fraction lambda of the normal kinetic energy radiated into the slope,
 * A (v_n / c0)^(3/5) with c0 = sqrt(E_slope/rho_slope); v_n = V cos(angle). */
double rf_hunter_loss(const rf_impact_input *in, double A);
/* Hunter with an explicit coefficient A (rf_impact_hunter uses RF_HUNTER_A_JOHNSON). */
rf_status rf_impact_hunter_A(const rf_impact_input *in, double A, rf_impact_output *out,
                             rf_error *err);

/* --- the impact model behind the rf_model interface --- */

typedef enum {
    RF_IMPACT_FEM = 0,  /* explicit finite elements (rockfuzz/fem.h) */
    RF_IMPACT_HERTZ,    /* elastic Hertz: R_n = 1 */
    RF_IMPACT_HUNTER,   /* Hertz + Hunter wave loss */
    RF_IMPACT_RIGID,    /* rigid-body oblique impact with Coulomb friction, e_n given */
    RF_IMPACT_MDR       /* Hertz + Mindlin-Deresiewicz partial slip (rockfuzz/mdr.h), e_n given */
} rf_impact_solver;

typedef enum {
    RF_IMPACT_BOUNDARY_FIXED = 0,    /* fixed outer surface of the slope domain */
    RF_IMPACT_BOUNDARY_ABSORBING     /* viscous (Lysmer-Kuhlemeyer) dashpots */
} rf_impact_boundary;

/* "fem" | "hertz" | "hunter" | "rigid" | "mdr" <-> enum; "fixed" | "absorbing". */
const char *rf_impact_solver_name(rf_impact_solver s);
rf_status rf_impact_solver_parse(const char *name, rf_impact_solver *s, rf_error *err);
const char *rf_impact_boundary_name(rf_impact_boundary b);
rf_status rf_impact_boundary_parse(const char *name, rf_impact_boundary *b, rf_error *err);

typedef struct {
    rf_impact_solver solver;
    rf_impact_input base;          /* crisp values of the inputs not bound to parameters (SI, angle in rad) */
    double e_n;                    /* rigid solver: normal COR; NaN = Hunter's e_n from the current inputs */
    double hunter_coefficient;     /* A of Hunter's loss (hunter solver, and rigid with e_n = NaN) */
    /* FE settings (mirrors of rf_fem_options, kept plain so this header does not need fem.h) */
    double fem_refinement;         /* a/h in the fine zone; 0 (default) = 10 axisymmetric, 6 in 3D */
    double fem_domain_factor;      /* slope domain radius / r0, default 10 */
    rf_impact_boundary fem_boundary; /* default fixed */
    int fem_threads;               /* threads of one FE evaluation, default 1 */
    const char *fem_vtk_dir;       /* VTK output directory or NULL; ignored by the model (CLI only) */
} rf_impact_model_spec;

/* Defaults: FEM solver, nominal granite, e_n = NaN (Hunter), A = 1.04,
 * refinement 0 (solver default), domain factor 10, fixed boundary, 1 thread, no VTK. */
void rf_impact_model_spec_default(rf_impact_model_spec *spec);

/* Run one impact with the spec's solver and settings on the input `in`
 * (validated here). */
rf_status rf_impact_solve(const rf_impact_model_spec *spec, const rf_impact_input *in,
                          rf_impact_output *out, rf_error *err);

/* Parameter names a study may bind (slope_angle in DEGREES here), and the
 * model outputs in order, with their units. */
#define RF_IMPACT_N_PARAMS 11
#define RF_IMPACT_N_OUTPUTS 7
extern const char *const rf_impact_param_names[RF_IMPACT_N_PARAMS];
extern const char *const rf_impact_output_names[RF_IMPACT_N_OUTPUTS];
extern const char *const rf_impact_output_units[RF_IMPACT_N_OUTPUTS];

/* Create the impact model: x[i] is the value of param_names[i] (one of
 * rf_impact_param_names; an unknown or repeated name is RF_EINVAL).  Outputs:
 * contact_force_max [N], compression_max [m], contact_duration [s],
 * contact_radius [m], R_n, R_t, R_ke [-].  eval copies spec->base, overwrites
 * the bound inputs, validates them and runs the solver; thread-safe.  Free
 * with rf_model_free. */
rf_status rf_impact_model_create(const rf_impact_model_spec *spec, const char *const *param_names,
                                 size_t n_params, rf_model *model, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
