/* impact.h - the boulder-on-slope impact problem: inputs (geometry,
 * materials, velocity, slope angle, friction) with their validation, the
 * outputs every impact solver fills, and the analytic references (Hertz,
 * Hunter, rigid-body oblique impact).  This is the low module the FE solvers
 * (fem.h, fem3d.h) build on; the impact model that a study binds fuzzy
 * parameters to sits above them, in impact_model.h.
 *
 * Units: SI throughout (m, kg, s, Pa, N, J, rad).  The boulder is a sphere of
 * radius `radius`, or a spheroid with horizontal semi-axis c and vertical
 * semi-axis d (set horizontal_axis > 0; d = radius^3 / c^2 keeps the volume
 * of the sphere of radius `radius`).  The slope is a half-space, elastic by
 * default; each body may be elasto-plastic (material.h: von Mises for the
 * boulder and the slope, Drucker-Prager with an optional compaction cap for
 * the slope; the FE solvers only, axisymmetric and 3D models).
 * Velocity is the vertical impact speed; slope_angle tilts the slope. */
#ifndef ROCKFUZZ_IMPACT_H
#define ROCKFUZZ_IMPACT_H

#include "rockfuzz/material.h"

#include <stddef.h>
#include "rockfuzz/status.h"

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
    /* Materials (docs/materials.md; defaults elastic, the other fields then unused). */
    rf_material_model boulder_material; /* elastic | von_mises | RF_MATERIAL_RIGID_BODY */
    double boulder_yield;               /* von_mises: initial yield stress Y [Pa] */
    double boulder_hardening;           /* von_mises: H [Pa], sigma_eq = Y + H eps_p */
    rf_material_model slope_material;   /* elastic | von_mises | drucker_prager */
    double slope_yield, slope_hardening; /* von_mises [Pa] */
    double slope_cohesion;              /* drucker_prager: c [Pa] */
    double slope_friction_angle;        /* drucker_prager: phi [rad] (degrees in the CLI and studies) */
    double slope_dilatancy_angle;       /* drucker_prager: psi [rad] in [0, phi] */
    double slope_cap_pressure;          /* drucker_prager: crush pressure X0 [Pa]; 0 = no cap */
    double slope_cap_hardening;         /* drucker_prager: compaction modulus H_c [Pa] */
    double slope_dilatancy_cutoff;      /* drucker_prager: plastic volumetric strain [-] at which
                                           the dilatancy stops; 0 = none (docs/materials.md) */
    /* A layer over the slope's material (the bedrock): 0 = homogeneous slope.
       Its own density, elasticity and material, named as the slope's
       (defaults: the nominal granite, elastic).  FE axisymmetric model only
       (the 3D model refuses it). */
    double layer_thickness;             /* [m], >= 0 */
    double layer_density, layer_E, layer_poisson;
    rf_material_model layer_material;
    double layer_yield, layer_hardening, layer_cohesion;
    double layer_friction_angle, layer_dilatancy_angle; /* [rad] (degrees in the CLI and studies) */
    double layer_cap_pressure, layer_cap_hardening;
    double layer_dilatancy_cutoff;
    /* Gravity [m/s^2] along -z (the slope normal of a normal impact): the
       boulder's weight and the geostatic stress of the slope and layer
       (docs/validation-plastic.md "Gravity"), a magnitude >= 0.  RF_GRAVITY_AUTO
       (the default; other negative values are invalid) = RF_GRAVITY_STANDARD when a body is elasto-plastic,
       0 for elastic bodies (the seed paper's model and the Hertz
       validations); an explicit value >= 0 overrides.  Both FE models (the
       3D one in the slope frame, g (sin theta, 0, -cos theta)). */
    double gravity;
} rf_impact_input;

/* 1 if the boulder (unless rigid), the slope or a layer (thickness > 0) is
 * elasto-plastic: what the automatic settings of gravity, large deformation
 * and the FE model choice look at. */
int rf_impact_has_plastic_body(const rf_impact_input *in);
#define RF_GRAVITY_AUTO (-1.0)
#define RF_GRAVITY_STANDARD 9.81
/* The gravity [m/s^2] an impact runs with: in->gravity if >= 0, else (auto)
 * RF_GRAVITY_STANDARD when the boulder, the slope or a layer is
 * elasto-plastic, else 0; the same for both FE models (three_d is ignored). */
double rf_impact_gravity(const rf_impact_input *in, int three_d);
/* "auto" or a value >= 0 [m/s^2] -> in->gravity (RF_EINVAL otherwise). */
rf_status rf_impact_gravity_parse(const char *text, double *gravity, rf_error *err);

/* boulder_material value of a rigid boulder ("rigid"; not a material of
 * material.h): exact mass, no deformation (boulder_E and boulder_poisson are
 * ignored, E* = E_s / (1 - nu_s^2)); axisymmetric FE model only. */
#define RF_MATERIAL_RIGID_BODY ((rf_material_model)16)
/* "elastic" | "von_mises" | "rigid" -> boulder_material (RF_EINVAL otherwise). */
rf_status rf_impact_boulder_material_parse(const char *name, rf_material_model *m, rf_error *err);
const char *rf_impact_material_name(rf_material_model m);

/* The constitutive parameters of the boulder (body 0), the slope (body 1) or
 * the layer (body 2); a rigid boulder gives its elastic constants. */
void rf_impact_material_params(const rf_impact_input *in, int body, rf_material_params *p);

/* ---- the one description of the numeric inputs (impact_fields.c) ----
 * Every numeric field of rf_impact_input is one row: its name (the study
 * key, the fuzzy parameter's name, the identity's and the JSON's key; the
 * CLI option is the name with '-' for '_'), where it lives, its unit and
 * default as a user gives them, the rule it must satisfy and a help line.
 * The defaults, the validation of single fields, the binding of fuzzy
 * parameters, the result store's identity and the CLI and study keys all
 * loop over this table, so a new input is one row (and its physics). */
typedef enum {
    RF_FIELD_PLAIN = 0,   /* stored as given */
    RF_FIELD_DEGREES,     /* given in degrees, stored in radians */
    RF_FIELD_GRAVITY      /* >= 0, or RF_GRAVITY_AUTO (given as "auto") */
} rf_field_kind;

typedef enum {
    RF_CHECK_NONE = 0,    /* checked with its body's material (rf_material_init) */
    RF_CHECK_POSITIVE,    /* finite, > 0 */
    RF_CHECK_NONNEGATIVE, /* finite, >= 0 */
    RF_CHECK_POISSON,     /* in (-1, 0.5) */
    RF_CHECK_INCLINATION, /* in [0, 90) degrees */
    RF_CHECK_GRAVITY      /* finite and >= 0, or RF_GRAVITY_AUTO */
} rf_field_check;

typedef struct {
    const char *name;
    size_t offset;           /* of the double in rf_impact_input */
    rf_field_kind kind;
    const char *unit;        /* as given ("deg" for angles; "" dimensionless) */
    double def;              /* default, as given */
    double probe;            /* a valid value, as given, that stands for the field when it is fuzzy
                                while the other inputs are checked (a von Mises yield needs Y > 0) */
    rf_field_check check;
    int bindable;            /* a fuzzy parameter may drive it */
    const char *help;        /* one line: what it is, and its rule where it has one */
} rf_impact_field;

extern const rf_impact_field rf_impact_fields[];
extern const size_t rf_impact_n_fields;
/* The row named name, or NULL. */
const rf_impact_field *rf_impact_field_find(const char *name);
/* Store a value as given (degrees for angles) in the field: a crisp input. */
void rf_impact_field_store(rf_impact_input *in, const rf_impact_field *f, double given);
/* Bind a fuzzy parameter's value: rf_impact_field_store, and binding
 * horizontal_axis also resets vertical_axis to 0 (constant volume). */
void rf_impact_field_set(rf_impact_input *in, const rf_impact_field *f, double given);
/* The field's value as given (degrees for angles). */
double rf_impact_field_get(const rf_impact_input *in, const rf_impact_field *f);
/* "radius [m], horizontal_axis [m], ...": the inputs a fuzzy parameter may
 * drive, with their units, for messages (truncated to size). */
void rf_impact_bindable_list(char *buf, size_t size);
/* 1 if x (as stored) satisfies the field's check. */
int rf_impact_field_ok(const rf_impact_field *f, double stored);

/* The model outputs of an impact (the values a study gets, in this order):
 * one row each, name, place in rf_impact_output, unit and help. */
typedef struct {
    const char *name;
    size_t offset;           /* of the double in rf_impact_output */
    const char *unit;        /* "" dimensionless */
    const char *help;
} rf_impact_output_field;
#define RF_IMPACT_N_OUTPUTS 11
extern const rf_impact_output_field rf_impact_output_fields[RF_IMPACT_N_OUTPUTS];

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
    /* FE only (0 for elastic bodies; NaN for the analytic models): */
    double plastic_work;        /* plastic dissipation / initial KE [-] */
    double penetration_max;     /* deepest position of the boulder's lowest point below the undeformed surface [m] */
    double indentation_depth;   /* permanent depth of the slope surface at the first-contact point at the end [m] */
    double equivalent_plastic_strain_max; /* over both bodies [-] */
    double nodes, elements, steps, wall_seconds; /* FE statistics (0 for analytic models) */
} rf_impact_output;

/* Zero the output and mark the quantities every model may leave undefined
 * (force, compression, duration, contact radius, the three COR) as NaN. */
void rf_impact_output_clear(rf_impact_output *out);

/* --- analytic references (impact_refs.md) --- */

/* Effective modulus 1/E* = (1-nu_b^2)/E_b + (1-nu_s^2)/E_s [Pa]. */
double rf_impact_effective_modulus(const rf_impact_input *in);
/* Dundurs' second parameter [-] of two bodies (E [Pa], nu): 0 when a normal
 * contact causes no tangential traction (identical constants, among others);
 * E1 = INFINITY is the rigid-body limit (1 - 2 nu2) / (2 (1 - nu2)). */
double rf_dundurs_beta(double E1, double nu1, double E2, double nu2);
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

/* --- the analytic impact solvers as a registry (GSL style) ---
 * Each solver is one rf_impact_law in its own file (hertz.c: hertz, hunter;
 * rigid_kinematics.c: rigid; mdr.c: mdr), listed once with the FE solver in
 * the impact model's table (src/model/impact_solvers.c), whose order is
 * rf_impact_solver's.  `--solver`'s help and error listing loop over it. */
typedef struct {
    double e_n;                /* normal COR in [0, 1]; NaN: Hunter's e_n from the input */
    double hunter_coefficient; /* A of Hunter's loss */
    void *context;             /* the solver's own state (the FE solver's options and workspace) */
} rf_impact_law_settings;

typedef struct rf_impact_law rf_impact_law;
struct rf_impact_law {
    const char *name; /* the --solver / study-file name */
    const char *help; /* what it computes; '\n' starts a continuation line in --help */
    /* what the solver (law itself) cannot take of a valid input (a layer, a plastic body, ...) */
    rf_status (*validate)(const rf_impact_law *law, const rf_impact_input *in, const rf_impact_law_settings *s,
                          rf_error *err);
    rf_status (*solve)(const rf_impact_input *in, const rf_impact_law_settings *s, rf_impact_output *out,
                       rf_error *err);
    /* The settings of s its results depend on, as " key=value" words written
     * to buf (snprintf's contract: returns the length it needed); the impact
     * model's identity appends them after the solver's name, so a store never
     * serves a result of other settings.  NULL: none. */
    int (*identity)(const rf_impact_law_settings *s, char *buf, size_t size);
};

extern const rf_impact_law rf_impact_law_hertz, rf_impact_law_hunter, rf_impact_law_rigid, rf_impact_law_mdr;

/* The identity of a solver that takes e_n (rigid, mdr): Hunter's A when e_n
 * comes from Hunter's loss, then e_n ("hunter" or its value). */
int rf_impact_en_identity(const rf_impact_law_settings *s, char *buf, size_t size);

/* The validate of the analytic solvers: a layer, a plastic body and gravity
 * refused (the message names the field, its value and law's name). */
rf_status rf_impact_analytic_validate(const rf_impact_law *law, const rf_impact_input *in,
                                      const rf_impact_law_settings *s, rf_error *err);

/* --- the Hertz reference every solver sizes itself from (impact_refs.md sec. 1) --- */

/* Hertz impact on a half-space with the normal velocity component.  One
 * place computes it: the analytic models, the FE mesh sizing, time span and
 * diagnostics all use this. */
typedef struct {
    double c, d;                  /* horizontal and vertical semi-axes [m] (c = d = r0 for a sphere) */
    double curvature_radius;      /* R at the contact point [m] */
    double mass;                  /* [kg] */
    double effective_modulus;     /* E* [Pa] */
    double normal_velocity;       /* V cos(angle) [m/s] */
    double tangential_velocity;   /* V sin(angle) [m/s] */
    double compression;           /* delta_max [m] */
    double force;                 /* F_max [N] */
    double contact_radius;        /* a at F_max [m] */
    double duration;              /* t_c [s] */
} rf_hertz_reference;

/* Fill ref for the input (not validated: call rf_impact_input_validate first). */
void rf_impact_hertz_reference(const rf_impact_input *in, rf_hertz_reference *ref);
/* t_c = factor * delta_max / v_n, factor = 2 (2/5) B(2/5, 1/2) = 2.9432... */
double rf_hertz_duration_factor(void);

/* Elastic wave speeds of the boulder (body 0) or the slope (body 1) [m/s]:
 * P, S, and Rayleigh (Viktorov's approximation). */
typedef struct {
    double p, s, rayleigh;
} rf_wave_speeds;
void rf_impact_wave_speeds(const rf_impact_input *in, int body, rf_wave_speeds *w);

#ifdef __cplusplus
}
#endif
#endif
