/* material.c - parameters, validation and the strain-increment driver shared
 * by every constitutive model (elastic predictor, model-specific return in
 * material_j2.c / material_dp.c, then one bookkeeping of plastic strain and
 * dissipation).  References: de Souza Neto, Peric & Owen (2008)
 * "Computational Methods for Plasticity", ch. 7-8; docs/materials.md. */
#include "material/material_internal.h"

#include <math.h>
#include <string.h>

#include "core/util.h"

static const char *const model_names[] = {"elastic", "von_mises", "drucker_prager"};

void rf_material_params_default(rf_material_params *p)
{
    memset(p, 0, sizeof *p);
    p->model = RF_MATERIAL_ELASTIC;
    p->E = 68.2e9;
    p->poisson = 0.25;
}

const char *rf_material_model_name(rf_material_model model)
{
    return (unsigned)model < 3 ? model_names[model] : "unknown";
}

rf_status rf_material_model_parse(const char *name, rf_material_model *model, rf_error *err)
{
    const int i = rf_name_index(name, model_names, 3);
    if (i >= 0) {
        *model = (rf_material_model)i;
        return RF_OK;
    }
    return rf_fail(err, RF_EINVAL, "material model '%s' is not one of elastic, von_mises, drucker_prager",
                   name ? name : "(null)");
}

double rf_material_dp_eta(double angle)
{
    double s = sin(angle);
    return 6.0 * s / (sqrt(3.0) * (3.0 - s));
}

double rf_material_dp_xi(double angle)
{
    double s = sin(angle);
    return 6.0 * cos(angle) / (sqrt(3.0) * (3.0 - s));
}

static rf_status validate_von_mises(const rf_material_params *p, rf_error *err)
{
    if (!(p->yield > 0.0 && isfinite(p->yield)))
        return rf_fail(err, RF_EINVAL, "yield = %g: the yield stress must be a finite number > 0 Pa",
                       p->yield);
    if (!(p->hardening >= 0.0 && isfinite(p->hardening)))
        return rf_fail(err, RF_EINVAL, "hardening = %g: the hardening modulus must be finite and >= 0 Pa",
                       p->hardening);
    return RF_OK;
}

static rf_status validate_drucker_prager(const rf_material_params *p, rf_error *err)
{
    double deg = 180.0 / RF_PI;
    if (!(p->cohesion >= 0.0 && isfinite(p->cohesion)))
        return rf_fail(err, RF_EINVAL, "cohesion = %g: must be finite and >= 0 Pa", p->cohesion);
    if (!(p->friction_angle >= 0.0 && p->friction_angle < 0.5 * RF_PI))
        return rf_fail(err, RF_EINVAL, "friction_angle = %g deg: must lie in [0, 90) degrees",
                       p->friction_angle * deg);
    if (p->friction_angle == 0.0 && !(p->cohesion > 0.0))
        return rf_fail(err, RF_EINVAL, "cohesion = %g: must be > 0 when friction_angle = 0 "
                       "(the material would have no strength)", p->cohesion);
    if (!(p->dilatancy_angle >= 0.0 && p->dilatancy_angle <= p->friction_angle))
        return rf_fail(err, RF_EINVAL, "dilatancy_angle = %g deg: must lie in [0, friction_angle = %g deg]",
                       p->dilatancy_angle * deg, p->friction_angle * deg);
    if (!(p->cap_pressure >= 0.0 && isfinite(p->cap_pressure)))
        return rf_fail(err, RF_EINVAL, "cap_pressure = %g: must be finite and > 0 Pa (0 = no cap)",
                       p->cap_pressure);
    if (!(p->cap_hardening >= 0.0 && isfinite(p->cap_hardening)))
        return rf_fail(err, RF_EINVAL, "cap_hardening = %g: must be finite and >= 0 Pa", p->cap_hardening);
    if (!(p->dilatancy_cutoff >= 0.0 && isfinite(p->dilatancy_cutoff)))
        return rf_fail(err, RF_EINVAL, "dilatancy_cutoff = %g: must be a finite plastic volumetric strain "
                       ">= 0 (0 = no cutoff)", p->dilatancy_cutoff);
    return RF_OK;
}

static void init_drucker_prager(rf_material *m, const rf_material_params *p)
{
    m->eta = rf_material_dp_eta(p->friction_angle);
    m->xi = rf_material_dp_xi(p->friction_angle);
    m->eta_bar = rf_material_dp_eta(p->dilatancy_angle);
    m->cohesion = p->cohesion;
    m->apex_pressure = m->eta > 0.0 ? m->xi * p->cohesion / m->eta : HUGE_VAL;
    m->cap = p->cap_pressure > 0.0;
    m->cap_pressure = p->cap_pressure;
    m->cap_hardening = p->cap_hardening;
    m->dilatancy_cutoff = p->dilatancy_cutoff > 0.0 ? p->dilatancy_cutoff : HUGE_VAL;
}

rf_status rf_material_init(rf_material *m, const rf_material_params *p, rf_error *err)
{
    memset(m, 0, sizeof *m);
    if ((unsigned)p->model > RF_MATERIAL_DRUCKER_PRAGER)
        return rf_fail(err, RF_EINVAL, "model = %d: not a material model", (int)p->model);
    if (!(p->E > 0.0 && isfinite(p->E)))
        return rf_fail(err, RF_EINVAL, "E = %g: Young's modulus must be a finite number > 0 Pa", p->E);
    if (!(p->poisson > -1.0 && p->poisson < 0.5))
        return rf_fail(err, RF_EINVAL, "poisson = %g: Poisson's ratio must lie in (-1, 0.5)", p->poisson);
    rf_status st = RF_OK;
    if (p->model == RF_MATERIAL_VON_MISES)
        st = validate_von_mises(p, err);
    else if (p->model == RF_MATERIAL_DRUCKER_PRAGER)
        st = validate_drucker_prager(p, err);
    if (st != RF_OK)
        return st;
    m->model = p->model;
    m->G = p->E / (2.0 * (1.0 + p->poisson));
    m->K = p->E / (3.0 * (1.0 - 2.0 * p->poisson));
    m->yield = p->yield;
    m->hardening = p->hardening;
    if (p->model == RF_MATERIAL_DRUCKER_PRAGER)
        init_drucker_prager(m, p);
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
    double s_tr[6];
    double p_tr = trial(m, deps, sig, s_tr);
    mat_return r = {{0}, p_tr, 0.0, 0.0};
    if (m->model == RF_MATERIAL_VON_MISES)
        mat_return_von_mises(m, st->plastic_strain_eq, s_tr, p_tr, &r);
    else if (m->model == RF_MATERIAL_DRUCKER_PRAGER)
        mat_return_drucker_prager(m, st, s_tr, p_tr, &r);
    else
        memcpy(r.s, s_tr, sizeof r.s);

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
    if (m->model == RF_MATERIAL_VON_MISES)
        st->plastic_strain_eq += r.gamma_j2;
    else if (m->model == RF_MATERIAL_DRUCKER_PRAGER)
        st->plastic_strain_eq += sqrt(2.0 / 3.0 * mat_ddot(deps_p, deps_p));
    st->plastic_volumetric += dvp;
    st->compaction += r.compaction;
    if (dissipation)
        *dissipation = m->model == RF_MATERIAL_ELASTIC ? 0.0 : work;
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
    if (m->model == RF_MATERIAL_VON_MISES) {
        double sy = m->yield + m->hardening * st->plastic_strain_eq;
        return sqrt(3.0) * sj2 - sy <= tol * sy;
    }
    if (m->model != RF_MATERIAL_DRUCKER_PRAGER)
        return 1;
    double scale = fmax(fmax(fabs(p), sj2), fmax(m->xi * m->cohesion, m->cap_pressure));
    if (mat_dp_cone(m, sj2, p) > tol * scale)
        return 0;
    return !m->cap || mat_dp_cap(m, st->compaction, p) <= tol * scale;
}

double rf_material_yield(const rf_material *m, const double sig[6], const rf_material_state *st)
{
    double s[6];
    const double p = mat_split(sig, s), sj2 = sqrt(0.5 * mat_ddot(s, s));
    if (m->model == RF_MATERIAL_VON_MISES)
        return sqrt(3.0) * sj2 - (m->yield + m->hardening * st->plastic_strain_eq);
    if (m->model != RF_MATERIAL_DRUCKER_PRAGER)
        return -HUGE_VAL;
    const double f = mat_dp_cone(m, sj2, p);
    return m->cap ? fmax(f, mat_dp_cap(m, st->compaction, p)) : f;
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
