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
