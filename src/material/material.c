/* material.c - the strain-increment driver shared by every constitutive law
 * (elastic predictor, the law's return map from the registry
 * (material_registry.c), then one bookkeeping of plastic strain and
 * dissipation), and the queries that go through the law's operations.
 * References: de Souza Neto, Peric & Owen (2008) "Computational Methods for
 * Plasticity", ch. 7-8; docs/materials.md. */
#include "material/material_internal.h"

#include <math.h>
#include <string.h>

rf_status rf_material_init(rf_material *m, const rf_material_params *p, rf_error *err)
{
    memset(m, 0, sizeof *m);
    const mat_law *law = mat_law_of(p->model);
    if (!law)
        return rf_fail(err, RF_EINVAL, "model = %d: not a material model", (int)p->model);
    rf_status st = mat_check_values(law, p, err);
    if (st == RF_OK && law->validate)
        st = law->validate(p, err);
    if (st != RF_OK)
        return st;
    m->model = p->model;
    m->G = p->E / (2.0 * (1.0 + p->poisson));
    m->K = p->E / (3.0 * (1.0 - 2.0 * p->poisson));
    m->yield = p->yield;
    m->hardening = p->hardening;
    if (law->init)
        law->init(m, p);
    return RF_OK;
}

/* Elastic predictor: trial deviator and mean stress. */
static double trial(const rf_material *m, const double deps[6], const double sig[6], double s_tr[6])
{
    double p_n = mat_split(sig, s_tr);
    double dv = deps[0] + deps[1] + deps[2];
    for (int i = 0; i < 3; i++)
        s_tr[i] += 2.0 * m->G * (deps[i] - dv / 3.0);
    for (int i = 3; i < 6; i++)
        s_tr[i] += m->G * deps[i]; /* engineering shear strain */
    return p_n + m->K * dv;
}

void rf_material_update(const rf_material *m, const double deps[6], double sig[6],
                        rf_material_state *st, double *dissipation)
{
    const mat_law *law = mat_law_of(m->model);
    double s_tr[6];
    double p_tr = trial(m, deps, sig, s_tr);
    mat_return r = {{0}, p_tr, 0.0, 0.0};
    law->ret(m, st, s_tr, p_tr, &r);

    /* Plastic strain = what the return removed from the trial elastic strain. */
    double dvp = (p_tr - r.p) / m->K, deps_p[6];
    for (int i = 0; i < 6; i++) {
        deps_p[i] = (s_tr[i] - r.s[i]) / (2.0 * m->G) + (i < 3 ? dvp / 3.0 : 0.0);
        sig[i] = r.s[i] + (i < 3 ? r.p : 0.0);
    }
    /* sig_n+1 : d eps_p over-counts the hardening of the step by H dgamma^2 / 2
     * (backward Euler); subtracting it makes the sum the exact plastic work
     * of a radial path (trapezoidal rule on a linear hardening law). */
    double work = mat_ddot(sig, deps_p) - 0.5 * m->hardening * r.gamma_j2 * r.gamma_j2
                  - 0.5 * m->cap_hardening * r.compaction * r.compaction;
    if (law->eq_increment)
        st->plastic_strain_eq += law->eq_increment(&r, deps_p);
    st->plastic_volumetric += dvp;
    st->compaction += r.compaction;
    if (dissipation)
        *dissipation = law->eq_increment ? work : 0.0;
}

void rf_material_update_block(const rf_material *m, size_t n, const double *deps, double *sig,
                              rf_material_state *st, double *dissipation)
{
    for (size_t i = 0; i < n; i++)
        rf_material_update(m, deps + 6 * i, sig + 6 * i, st + i, dissipation ? dissipation + i : NULL);
}

int rf_material_admissible(const rf_material *m, const double sig[6], const rf_material_state *st,
                           double tol)
{
    double s[6];
    double p = mat_split(sig, s), sj2 = sqrt(0.5 * mat_ddot(s, s));
    return mat_law_of(m->model)->admissible(m, sj2, p, st, tol);
}

double rf_material_yield(const rf_material *m, const double sig[6], const rf_material_state *st)
{
    double s[6];
    const double p = mat_split(sig, s), sj2 = sqrt(0.5 * mat_ddot(s, s));
    return mat_law_of(m->model)->yield(m, sj2, p, st);
}

double rf_material_elastic_energy(const rf_material *m, const double sig[6])
{
    double s[6];
    double p = mat_split(sig, s);
    return mat_ddot(s, s) / (4.0 * m->G) + p * p / (2.0 * m->K);
}

double rf_material_wave_speed(const rf_material *m, double density)
{
    return sqrt((m->K + 4.0 * m->G / 3.0) / density);
}
