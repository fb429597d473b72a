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
#include <string.h>

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

void mat_return_drucker_prager(const rf_material *m, const rf_material_state *st, const double s_tr[6],
                               double p_tr, mat_return *r)
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
