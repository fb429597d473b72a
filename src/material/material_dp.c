/* material_dp.c - Drucker-Prager return mapping with an optional hardening
 * flat compaction cap.
 *
 * Cone f = sqrt(J2) + eta p - xi c, plastic potential g = sqrt(J2) + eta_bar p
 * (non-associated when psi < phi), perfectly plastic; exact return to the
 * smooth cone and exact apex return (de Souza Neto, Peric & Owen 2008,
 * "Computational Methods for Plasticity", ch. 8, Drucker-Prager).
 * Cap f_c = -p - X(eps_c), X = X0 + H_c eps_c, associated (purely volumetric
 * compaction): the crush curve of Krieg's (1972) soil-and-foam model seen as
 * a flat cap, combined with the cone as in multi-surface cap models
 * (Sandler & Rubin 1979).
 * The cap hardens only with its own compaction eps_c: cone dilatancy does not
 * retract it.  With perfect plasticity on the cone and linear cap hardening
 * every branch is a closed form: cone, apex, cap, and the cone-cap corner (a
 * 2x2 linear system).  The active set is found by trying single surfaces
 * first and accepting a candidate only when it violates no other surface
 * (the multisurface returns of Simo & Hughes 1998).
 * Dilatancy cutoff: the cone's flow is dilatant only while the plastic
 * volume change (dilation positive, the cap's compaction counted negative)
 * is below the cutoff, a critical state past which a sand shears at constant
 * volume (the "dilatancy cut-off" of geotechnical codes such as Plaxis;
 * from void ratios, (e_cs - e_0) / (1 + e_0), docs/materials.md).  A cone
 * return that crosses it is split exactly (cone_return); the corner takes
 * psi or 0 from the state at the start of the increment. */
#include "material/material_internal.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/util.h"

#define DP_FIELD(f) offsetof(rf_material_params, f)
static const rf_material_param params[] = {
    {.name = "cohesion", .offset = DP_FIELD(cohesion), .unit = "Pa", .metavar = "PA",
     .rule = RF_MATERIAL_RULE_NONNEGATIVE, .flags = RF_MATERIAL_PARAM_REQUIRED, .help = "c {}"},
    {.name = "friction_angle", .offset = DP_FIELD(friction_angle), .unit = "deg", .metavar = "DEG",
     .rule = RF_MATERIAL_RULE_ANGLE, .flags = RF_MATERIAL_PARAM_REQUIRED, .help = "phi {}"},
    {.name = "dilatancy_angle", .offset = DP_FIELD(dilatancy_angle), .unit = "deg", .metavar = "DEG",
     .rule = RF_MATERIAL_RULE_ANGLE, .help = "psi {}, at most phi\n(< phi: non-associated)"},
    {.name = "cap_pressure", .offset = DP_FIELD(cap_pressure), .unit = "Pa", .metavar = "PA",
     .rule = RF_MATERIAL_RULE_NONNEGATIVE, .flags = RF_MATERIAL_PARAM_SWITCH, .together = "cap_hardening",
     .feature = "cap", .help = "crush pressure X0 {}: the compressive\nmean stress where plastic compaction starts\n(flat cap)"},
    {.name = "cap_hardening", .offset = DP_FIELD(cap_hardening), .unit = "Pa", .metavar = "PA",
     .rule = RF_MATERIAL_RULE_NONNEGATIVE, .together = "cap_pressure", .feature = "cap",
     .help = "H_c {}: X = X0 + H_c eps_c, eps_c the plastic\ncompaction (the cap needs both options)"},
    {.name = "dilatancy_cutoff", .offset = DP_FIELD(dilatancy_cutoff), .unit = "-", .metavar = "EPS",
     .rule = RF_MATERIAL_RULE_NONNEGATIVE, .flags = RF_MATERIAL_PARAM_SWITCH, .feature = "cutoff",
     .help = "{}: the plastic volumetric strain at which the\ndilatancy stops (critical state); from void ratios,\n"
             "(e_cs - e0) / (1 + e0), e_cs the critical-state\nvoid ratio"},
};

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

double mat_dp_cone(const rf_material *m, double sqrt_j2, double p)
{
    return sqrt_j2 + m->eta * p - m->xi * m->cohesion;
}

double mat_dp_cap(const rf_material *m, double compaction, double p)
{
    return -p - (m->cap_pressure + m->cap_hardening * compaction);
}

static void set_deviator(mat_return *r, const double s_tr[6], double factor)
{
    for (int i = 0; i < 6; i++)
        r->s[i] = factor * s_tr[i];
}

/* Smooth-cone return, or the apex when the cone return overshoots it.
 * room: the plastic dilation still allowed before the cutoff (HUGE_VAL: none).
 * The flow is dilatant (eta_bar) for the first room / eta_bar of the
 * multiplier and isochoric after it, so the consistency condition
 * f_tr - G dgamma - K eta eta_bar dgamma_1 = 0 stays a closed form. */
static void cone_return(const rf_material *m, const double s_tr[6], double sj2_tr, double p_tr,
                        double f_tr, double room, mat_return *r)
{
    double dgamma = f_tr / (m->G + m->K * m->eta * m->eta_bar);
    double dp = m->K * m->eta_bar * dgamma; /* the mean stress's drop (as before the cutoff, to the bit) */
    if (m->eta_bar * dgamma > room) {
        dgamma = (f_tr - m->K * m->eta * room) / m->G;
        dp = m->K * room;
    }
    if (sj2_tr - m->G * dgamma >= 0.0) {
        set_deviator(r, s_tr, 1.0 - m->G * dgamma / sj2_tr);
        r->p = p_tr - dp;
        return;
    }
    /* Apex (perfect plasticity): sigma = p_apex I whatever psi. */
    set_deviator(r, s_tr, 0.0);
    r->p = m->apex_pressure;
}

/* Cap alone: purely volumetric, deviator unchanged. */
static void cap_return(const rf_material *m, const double s_tr[6], double p_tr, double f_cap,
                       mat_return *r)
{
    double dc = f_cap / (m->K + m->cap_hardening);
    set_deviator(r, s_tr, 1.0);
    r->p = p_tr + m->K * dc;
    r->compaction = dc;
}

/* Cone and cap both active: solve for (dgamma, d eps_c), eb the dilatancy
 * coefficient eta_bar (0 once the cutoff is reached).
 *   [G + K eta eb   -eta K  ] [dgamma]   [f_cone_tr]
 *   [-K eb           K + H_c] [d eps_c] = [f_cap_tr ]           */
static void corner_return(const rf_material *m, double eb, const double s_tr[6], double sj2_tr,
                          double p_tr, double f_cone, double f_cap, mat_return *r)
{
    double a11 = m->G + m->K * m->eta * eb, kh = m->K + m->cap_hardening;
    double det = a11 * kh - m->eta * eb * m->K * m->K;
    double dgamma = (f_cone * kh + m->eta * m->K * f_cap) / det;
    double dc = (a11 * f_cap + m->K * eb * f_cone) / det;
    set_deviator(r, s_tr, sj2_tr > 0.0 ? 1.0 - m->G * dgamma / sj2_tr : 0.0);
    r->p = p_tr - m->K * eb * dgamma + m->K * dc;
    r->compaction = dc;
}

static void dp_return(const rf_material *m, const rf_material_state *st, const double s_tr[6], double p_tr,
                      mat_return *r)
{
    double compaction = st->compaction;
    double room = fmax(0.0, m->dilatancy_cutoff - st->plastic_volumetric);
    double sj2_tr = sqrt(0.5 * mat_ddot(s_tr, s_tr));
    double f_cone = mat_dp_cone(m, sj2_tr, p_tr);
    double f_cap = m->cap ? mat_dp_cap(m, compaction, p_tr) : -HUGE_VAL;
    double tol = 1e-12 * (fabs(p_tr) + sj2_tr + m->xi * m->cohesion + m->cap_pressure);
    r->gamma_j2 = 0.0;
    r->compaction = 0.0;
    if (f_cone <= 0.0 && f_cap <= 0.0) {
        set_deviator(r, s_tr, 1.0);
        r->p = p_tr;
        return;
    }
    if (f_cone > 0.0) {
        cone_return(m, s_tr, sj2_tr, p_tr, f_cone, room, r);
        if (!m->cap || mat_dp_cap(m, compaction, r->p) <= tol)
            return;
    }
    if (f_cap > 0.0) {
        cap_return(m, s_tr, p_tr, f_cap, r);
        if (mat_dp_cone(m, sj2_tr, r->p) <= tol)
            return;
    }
    corner_return(m, room > 0.0 ? m->eta_bar : 0.0, s_tr, sj2_tr, p_tr, f_cone, f_cap, r);
}

/* Across fields (each value was checked against its rule). */
static rf_status dp_validate(const rf_material_params *p, rf_error *err)
{
    const double deg = 180.0 / RF_PI;
    if (p->friction_angle == 0.0 && !(p->cohesion > 0.0))
        return rf_fail(err, RF_EINVAL, "cohesion = %g: must be > 0 when friction_angle = 0 "
                       "(the material would have no strength)", p->cohesion);
    if (!(p->dilatancy_angle <= p->friction_angle))
        return rf_fail(err, RF_EINVAL, "dilatancy_angle = %g deg: must lie in [0, friction_angle = %g deg]",
                       p->dilatancy_angle * deg, p->friction_angle * deg);
    return RF_OK;
}

static void dp_init(rf_material *m, const rf_material_params *p)
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

/* Non-associated flow: eps_p_eq from the plastic strain itself. */
static double dp_eq_increment(const mat_return *r, const double deps_p[6])
{
    (void)r;
    return sqrt(2.0 / 3.0 * mat_ddot(deps_p, deps_p));
}

static double dp_yield(const rf_material *m, double sj2, double p, const rf_material_state *st)
{
    const double f = mat_dp_cone(m, sj2, p);
    return m->cap ? fmax(f, mat_dp_cap(m, st->compaction, p)) : f;
}

static int dp_admissible(const rf_material *m, double sj2, double p, const rf_material_state *st, double tol)
{
    double scale = fmax(fmax(fabs(p), sj2), fmax(m->xi * m->cohesion, m->cap_pressure));
    if (mat_dp_cone(m, sj2, p) > tol * scale)
        return 0;
    return !m->cap || mat_dp_cap(m, st->compaction, p) <= tol * scale;
}

const mat_law mat_law_drucker_prager = {
    {"drucker_prager", "cone matched to Mohr-Coulomb in triaxial compression",
     params, sizeof params / sizeof params[0]},
    dp_validate, dp_init, dp_return, dp_eq_increment, dp_yield, dp_admissible,
};
