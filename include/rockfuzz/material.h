/* material.h - point-wise small-strain constitutive laws for the explicit FE
 * solvers and the `rockfuzz material` driver (docs/materials.md).
 *
 * Models: isotropic linear elasticity; von Mises (J2) plasticity with linear
 * isotropic hardening (radial return, Wilkins 1964; Simo & Hughes 1998 ch. 3);
 * Drucker-Prager with the cone matched to Mohr-Coulomb's compressive meridian,
 * non-associated flow, exact cone and apex returns (de Souza Neto, Peric &
 * Owen 2008 ch. 8), an optional hardening flat compaction cap (crush curve
 * on the mean stress, Krieg 1972 / LS-DYNA soil-and-foam type) and an optional
 * dilatancy cutoff (the flow turns isochoric once the plastic volume change
 * reaches a critical-state limit, as the "dilatancy cut-off" of geotechnical
 * codes such as Plaxis); and the
 * Hughes-Winget (1980) objective stress rotation for large deformation.
 *
 * Conventions: SI units, tension positive, angles in radians (degrees only at
 * the user interface).  Six-component Voigt order xx, yy, zz, xy, yz, zx:
 * stresses are tensor components; strain increments carry ENGINEERING shear
 * strains (gamma_xy = 2 eps_xy).  An axisymmetric element maps r, z, theta,
 * rz onto xx, yy, zz, xy and passes zero for yz and zx.
 *
 * The stress is not part of rf_material_state: the element owns it (so that
 * it can rotate it objectively before the update) and passes it in and out.
 * The update is a pure function of its arguments: no global state; many
 * threads may call it on different points at once. */
#ifndef ROCKFUZZ_MATERIAL_H
#define ROCKFUZZ_MATERIAL_H

#include <stddef.h>

#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RF_MATERIAL_ELASTIC = 0,
    RF_MATERIAL_VON_MISES,
    RF_MATERIAL_DRUCKER_PRAGER
} rf_material_model;

/* What a user gives.  Fields a model does not use are ignored. */
typedef struct {
    rf_material_model model;
    double E;               /* Young's modulus [Pa], > 0 */
    double poisson;         /* Poisson's ratio, in (-1, 0.5) */
    double yield;           /* von_mises: initial yield stress Y [Pa], > 0 */
    double hardening;       /* von_mises: H [Pa] >= 0, sigma_eq = Y + H eps_p_eq */
    double cohesion;        /* drucker_prager: c [Pa] >= 0 */
    double friction_angle;  /* drucker_prager: phi [rad] in [0, pi/2); c > 0 when phi = 0 */
    double dilatancy_angle; /* drucker_prager: psi [rad] in [0, phi] */
    double cap_pressure;    /* drucker_prager: crush pressure X0 [Pa] at the onset of
                               compaction (a compressive mean stress); 0 = no cap */
    double cap_hardening;   /* drucker_prager: compaction modulus H_c [Pa] >= 0,
                               X = X0 + H_c eps_c (eps_c: plastic compaction) */
    double dilatancy_cutoff; /* drucker_prager: plastic volumetric strain [-] > 0 at which the
                                cone's dilatancy stops (critical state: psi acts only while
                                the plastic volume change is below it); 0 = no cutoff */
} rf_material_params;

/* Derived constants, built once by rf_material_init; read-only afterwards. */
typedef struct {
    rf_material_model model;
    double G, K;             /* shear and bulk moduli [Pa] */
    double yield, hardening; /* von_mises */
    double eta, eta_bar, xi; /* DP: f = sqrt(J2) + eta p - xi c; g = sqrt(J2) + eta_bar p */
    double cohesion;         /* DP: c [Pa] */
    double apex_pressure;    /* DP: xi c / eta = c cot(phi) [Pa] (HUGE_VAL when phi = 0) */
    int cap;                 /* DP: 1 when the compaction cap is on */
    double cap_pressure, cap_hardening;
    double dilatancy_cutoff; /* DP: HUGE_VAL when there is none */
} rf_material;

/* Per integration point, besides the stress.  Zero-initialise to start. */
typedef struct {
    double plastic_strain_eq;     /* accumulated sqrt(2/3 d eps_p : d eps_p) [-] */
    double plastic_volumetric;    /* accumulated trace of eps_p [-] (dilation > 0) */
    double compaction;            /* cap hardening variable eps_c >= 0 [-] */
} rf_material_state;

/* The registry of laws (GSL style): each law is one entry in its own file
 * (material_elastic.c, material_j2.c, material_dp.c) with its parameter
 * table, validation and return map, listed once in material_registry.c in
 * rf_material_model order.  The defaults, the validation of single values,
 * `rockfuzz material` (its options, --help and required options) and the
 * names in messages loop over these tables. */
typedef enum {
    RF_MATERIAL_RULE_POSITIVE = 0, /* finite and > 0 */
    RF_MATERIAL_RULE_NONNEGATIVE,  /* finite and >= 0 */
    RF_MATERIAL_RULE_POISSON,      /* in (-1, 0.5) */
    RF_MATERIAL_RULE_ANGLE         /* in [0, 90) degrees; given in degrees, stored in radians */
} rf_material_rule;

enum {
    RF_MATERIAL_PARAM_REQUIRED = 1, /* the command line needs it with its law */
    RF_MATERIAL_PARAM_SWITCH = 2    /* 0 = the feature is off: a value given must be > 0 */
};

/* One parameter: a double of rf_material_params. */
typedef struct {
    const char *name;     /* the field's name, the start of its messages ("name = value ...");
                             the option --name with '-' for '_' */
    size_t offset;        /* offsetof(rf_material_params, field) */
    const char *unit;     /* "Pa", "deg" (radians stored) or "-" */
    const char *metavar;  /* the value's word in --help (PA, DEG, NU, EPS) */
    double default_value; /* as stored (SI, radians) */
    rf_material_rule rule;
    int flags;            /* RF_MATERIAL_PARAM_* */
    const char *together; /* a parameter that must be given with this one, or NULL */
    const char *feature;  /* what a switch (or a pair) turns on, for messages ("cap"), or NULL */
    const char *help;     /* what it is, "{}" where --help shows its rule; '\n' starts a
                             continuation line */
} rf_material_param;

/* What a law shows of itself. */
typedef struct {
    const char *name;                /* "elastic", "von_mises", "drucker_prager" */
    const char *help;                /* a few words */
    const rf_material_param *params; /* its own, besides rf_material_common_params */
    size_t n_params;
} rf_material_law_info;

/* E and poisson, which every law takes. */
extern const rf_material_param rf_material_common_params[2];

/* The number of laws, and law k (k = its rf_material_model); NULL out of range. */
size_t rf_material_n_laws(void);
const rf_material_law_info *rf_material_law(rf_material_model model);

/* The parameter called name (common or of any law), or NULL. */
const rf_material_param *rf_material_param_find(const char *name);

/* The field of p a parameter describes. */
double *rf_material_param_field(rf_material_params *p, const rf_material_param *param);

/* Checks one value against its rule; the message starts "name = value". */
rf_status rf_material_param_check(const rf_material_param *param, double value, rf_error *err);

/* Elastic defaults (E = 68.2 GPa, nu = 0.25, granite) and zero for the rest. */
void rf_material_params_default(rf_material_params *p);

/* Validates p and fills m.  On error names the field and value. */
rf_status rf_material_init(rf_material *m, const rf_material_params *p, rf_error *err);

/* One strain increment at one point: sig (in: stress at t_n, out: at t_n+1),
 * st (in/out).  *dissipation (may be NULL) receives the plastic work of the
 * increment per unit volume [J/m^3], >= 0, exact for radial paths (see
 * docs/materials.md). */
void rf_material_update(const rf_material *m, const double deps[6], double sig[6],
                        rf_material_state *st, double *dissipation);

/* The same over n points stored contiguously: deps[6n], sig[6n], st[n],
 * dissipation[n] (may be NULL). */
void rf_material_update_block(const rf_material *m, size_t n, const double *deps, double *sig,
                              rf_material_state *st, double *dissipation);

/* Objective rotation of a stress before its update in large deformation
 * (Hughes & Winget 1980): sig <- Q sig Q^T, Q = (I - W/2)^-1 (I + W/2),
 * W = skew(spin), spin = the rotation-vector increment 1/2 curl(v) dt
 * evaluated at mid-step [rad].  Axisymmetric elements pass
 * {0, 0, 1/2 (dv_z/dr - dv_r/dz) dt} (r, z in slots x, y). */
void rf_material_rotate(double sig[6], const double spin[3]);

/* 1 when sig with st is admissible (every yield function <= tol * scale). */
int rf_material_admissible(const rf_material *m, const double sig[6], const rf_material_state *st,
                           double tol);

/* The largest yield function of sig with st [Pa]: von Mises sqrt(3 J2) -
 * (Y + H eps_p); Drucker-Prager max(cone, cap) (the cap if on); -HUGE_VAL for
 * the elastic model.  <= 0: admissible. */
double rf_material_yield(const rf_material *m, const double sig[6], const rf_material_state *st);

/* Elastic (complementary) energy density 1/2 sig : C^-1 : sig [J/m^3]. */
double rf_material_elastic_energy(const rf_material *m, const double sig[6]);

/* P-wave speed sqrt((K + 4G/3)/rho) [m/s]: plasticity only lowers the
 * tangent stiffness, so this bounds the explicit time step. */
double rf_material_wave_speed(const rf_material *m, double density);

/* The registry's names <-> rf_material_model ("unknown" out of range). */
const char *rf_material_model_name(rf_material_model model);
rf_status rf_material_model_parse(const char *name, rf_material_model *model, rf_error *err);

/* Mohr-Coulomb outer-cone constants (compressive meridian): eta and xi of an
 * angle phi [rad], eta = 6 sin/(sqrt3 (3 - sin)), xi = 6 cos/(sqrt3 (3 - sin)). */
double rf_material_dp_eta(double angle);
double rf_material_dp_xi(double angle);

#ifdef __cplusplus
}
#endif
#endif
