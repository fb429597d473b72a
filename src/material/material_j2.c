/* material_j2.c - von Mises (J2) plasticity with linear isotropic hardening:
 * the radial return of Wilkins (1964), in the form of Simo & Hughes (1998)
 * "Computational Inelasticity" ch. 3 and de Souza Neto, Peric & Owen (2008)
 * ch. 7.  Closed form for linear hardening, exact for
 * radial (proportional) strain paths; the mean stress stays elastic. */
#include "material/material_internal.h"

#include <math.h>
#include <stddef.h>

static const rf_material_param params[] = {
    {.name = "yield", .offset = offsetof(rf_material_params, yield), .unit = "Pa", .metavar = "PA",
     .rule = RF_MATERIAL_RULE_POSITIVE, .flags = RF_MATERIAL_PARAM_REQUIRED, .help = "initial yield stress Y {}"},
    {.name = "hardening", .offset = offsetof(rf_material_params, hardening), .unit = "Pa", .metavar = "PA",
     .rule = RF_MATERIAL_RULE_NONNEGATIVE, .help = "H {}, sigma_eq = Y + H eps_p_eq"},
};

static void von_mises_return(const rf_material *m, const rf_material_state *st, const double s_tr[6],
                             double p_tr, mat_return *r)
{
    double q_tr = sqrt(1.5 * mat_ddot(s_tr, s_tr));
    double sigma_y = m->yield + m->hardening * st->plastic_strain_eq;
    double gamma = 0.0, scale = 1.0;
    if (q_tr > sigma_y) {
        gamma = (q_tr - sigma_y) / (3.0 * m->G + m->hardening);
        scale = 1.0 - 3.0 * m->G * gamma / q_tr;
    }
    for (int i = 0; i < 6; i++)
        r->s[i] = scale * s_tr[i];
    r->p = p_tr;
    r->gamma_j2 = gamma;
    r->compaction = 0.0;
}

/* The multiplier is the increment of eps_p_eq (radial return). */
static double von_mises_eq_increment(const mat_return *r, const double deps_p[6])
{
    (void)deps_p;
    return r->gamma_j2;
}

static double von_mises_yield(const rf_material *m, double sj2, double p, const rf_material_state *st)
{
    (void)p;
    return sqrt(3.0) * sj2 - (m->yield + m->hardening * st->plastic_strain_eq);
}

static int von_mises_admissible(const rf_material *m, double sj2, double p, const rf_material_state *st,
                                double tol)
{
    (void)p;
    double sy = m->yield + m->hardening * st->plastic_strain_eq;
    return sqrt(3.0) * sj2 - sy <= tol * sy;
}

const mat_law mat_law_von_mises = {
    {"von_mises", "J2, linear isotropic hardening", params,
     sizeof params / sizeof params[0]},
    NULL, NULL, von_mises_return, von_mises_eq_increment, von_mises_yield, von_mises_admissible,
};
