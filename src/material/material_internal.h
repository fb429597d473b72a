/* material_internal.h - tensor helpers and the per-model return mappings
 * shared by the files of src/material (not public API).
 *
 * Six-component Voigt storage, order xx, yy, zz, xy, yz, zx, stresses as
 * tensor components.  The returns take the elastic trial state split into a
 * deviator s_tr and a mean stress p_tr and return the final deviator s, mean
 * stress p and the hardening multipliers, so that rf_material_update does the
 * bookkeeping (plastic strain, dissipation) once for every model. */
#ifndef ROCKFUZZ_MATERIAL_INTERNAL_H
#define ROCKFUZZ_MATERIAL_INTERNAL_H

#include "rockfuzz/material.h"

/* The outcome of a return mapping. */
typedef struct {
    double s[6];         /* final deviator */
    double p;            /* final mean stress */
    double gamma_j2;     /* von Mises multiplier = increment of eps_p_eq (hardening H) */
    double compaction;   /* cap multiplier: increment of eps_c (hardening H_c) */
} mat_return;

/* s : s for a symmetric tensor in Voigt storage (shear counted twice). */
static inline double mat_ddot(const double a[6], const double b[6])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

/* Splits sig into its deviator s and mean stress p. */
static inline double mat_split(const double sig[6], double s[6])
{
    double p = (sig[0] + sig[1] + sig[2]) / 3.0;
    for (int i = 0; i < 6; i++)
        s[i] = sig[i] - (i < 3 ? p : 0.0);
    return p;
}

/* A law's operations (one entry per file, listed in material_registry.c).
 * sj2 = sqrt(J2) and p the mean stress of the stress at hand. */
typedef struct {
    rf_material_law_info info;
    /* checks across fields (each single value was checked against its rule) */
    rf_status (*validate)(const rf_material_params *p, rf_error *err);
    /* the law's derived constants (G, K, yield, hardening are set) */
    void (*init)(rf_material *m, const rf_material_params *p);
    /* the return map of the elastic trial state */
    void (*ret)(const rf_material *m, const rf_material_state *st, const double s_tr[6], double p_tr,
                mat_return *r);
    /* the increment of eps_p_eq from the return and the plastic strain; NULL: an elastic law
       (no plastic strain, no dissipation) */
    double (*eq_increment)(const mat_return *r, const double deps_p[6]);
    double (*yield)(const rf_material *m, double sj2, double p, const rf_material_state *st);
    int (*admissible)(const rf_material *m, double sj2, double p, const rf_material_state *st, double tol);
} mat_law;

extern const mat_law mat_law_elastic, mat_law_von_mises, mat_law_drucker_prager;

/* The law of a model (NULL when model is not one). */
const mat_law *mat_law_of(rf_material_model model);

/* E, poisson and the law's own values of p, each against its rule (material_registry.c). */
rf_status mat_check_values(const mat_law *law, const rf_material_params *p, rf_error *err);

/* Yield functions of the DP cone and cap at (sqrt(J2), p) [Pa]. */
double mat_dp_cone(const rf_material *m, double sqrt_j2, double p);
double mat_dp_cap(const rf_material *m, double compaction, double p);

#endif
