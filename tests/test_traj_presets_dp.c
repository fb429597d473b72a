/* test_traj_presets_dp.c - the Drucker-Prager + cap return mapping
 * (material_dp.c) on the talus preset's layer, checked by a second method
 * (docs/presets.md section 4c, the dilatancy puzzle):
 * - at a cone-cap corner state of the talus layer with psi 15 deg, the
 *   stress and the cap's compaction equal an independent solution of the
 *   backward-Euler equations (bisection on the compaction, the cone
 *   condition solved for the multiplier at each trial: not the code's 2x2
 *   Cramer solve), to 1e-9 relative;
 * - over random states and strain increments (psi 5 and 15 deg), every
 *   return satisfies the discrete Kuhn-Tucker conditions: the stress is
 *   admissible, the deviator is the trial deviator scaled by a factor in
 *   [0, 1] (radial return), the multipliers dgamma = (sqrt J2_tr - sqrt J2)
 *   / G and d eps_c are >= 0, each is > 0 only on its active surface
 *   (complementarity), and the mean stress obeys the non-associated flow
 *   p = p_tr - K eta_bar dgamma + K d eps_c (apex returns excepted: there
 *   the flow is not the cone's). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/material.h"
#include "rockfuzz/presets.h"

#define DEG (3.14159265358979323846 / 180)

/* The talus preset's nominal value of key (the preset table, not a copy). */
static double talus(const char *key)
{
    const rf_traj_preset *p = rf_traj_preset_named("talus");
    assert_non_null(p);
    for (size_t i = 0; i < p->n_values; i++)
        if (!strcmp(p->values[i].key, key))
            return p->values[i].value;
    fail_msg("talus has no %s", key);
    return NAN;
}

/* The talus layer as a material, with dilatancy angle psi [deg]. */
static void talus_layer(rf_material *m, double psi_deg)
{
    rf_material_params p;
    rf_material_params_default(&p);
    p.model = RF_MATERIAL_DRUCKER_PRAGER;
    p.E = talus("impact.layer_E"), p.poisson = talus("impact.layer_poisson");
    p.cohesion = talus("impact.layer_cohesion");
    p.friction_angle = talus("impact.layer_friction_angle") * DEG;
    p.dilatancy_angle = psi_deg * DEG;
    p.cap_pressure = talus("impact.layer_cap_pressure");
    p.cap_hardening = talus("impact.layer_cap_hardening");
    rf_error e;
    assert_int_equal(rf_material_init(m, &p, &e), RF_OK);
}

/* Mean stress (tension > 0) and deviator of a Voigt stress. */
static double split(const double s[6], double dev[6])
{
    double p = (s[0] + s[1] + s[2]) / 3;
    for (int i = 0; i < 6; i++)
        dev[i] = s[i] - (i < 3 ? p : 0);
    return p;
}

static double sqrt_j2(const double s[6])
{
    return sqrt(0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
}

/* The elastic trial state of sig + C deps (engineering shear strains). */
static void trial(const rf_material *m, const double sig[6], const double deps[6], double s_tr[6], double *p_tr)
{
    double dv = deps[0] + deps[1] + deps[2];
    *p_tr = split(sig, s_tr) + m->K * dv;
    for (int i = 0; i < 6; i++)
        s_tr[i] += i < 3 ? 2 * m->G * (deps[i] - dv / 3) : m->G * deps[i];
}

/* Second method at a corner: for a compaction dc the cone condition fixes
 * dgamma; bisect on dc until the cap condition holds. */
static void corner_by_bisection(const rf_material *m, double sj2_tr, double p_tr, double c0, double *dgamma,
                                double *dc)
{
    double lo = 0, hi = 1;
    for (int it = 0; it < 200; it++) {
        double x = 0.5 * (lo + hi);
        double dg = (sj2_tr + m->eta * (p_tr + m->K * x) - m->xi * m->cohesion) / (m->G + m->K * m->eta * m->eta_bar);
        double p = p_tr - m->K * m->eta_bar * dg + m->K * x;
        double cap = -p - (m->cap_pressure + m->cap_hardening * (c0 + x));
        if (cap > 0)
            lo = x;
        else
            hi = x;
    }
    *dc = 0.5 * (lo + hi);
    *dgamma = (sj2_tr + m->eta * (p_tr + m->K * *dc) - m->xi * m->cohesion) / (m->G + m->K * m->eta * m->eta_bar);
}

static void test_corner_by_hand(void **state)
{
    (void)state;
    rf_material m;
    talus_layer(&m, 15);
    /* On the cap (p = -X0) with a deviator inside the cone, then an isochoric
       punch-like increment: axial shortening 1e-3, lateral extension 5e-4. */
    const double X0 = m.cap_pressure;
    double sig[6] = {-X0 + 5e3, -X0 + 5e3, -X0 - 10e3, 0, 0, 0};
    double deps[6] = {5e-4, 5e-4, -1e-3, 2e-4, 0, 0}, s_tr[6], p_tr;
    rf_material_state st = {0};
    trial(&m, sig, deps, s_tr, &p_tr);
    const double sj2_tr = sqrt_j2(s_tr);
    assert_true(sj2_tr + m.eta * p_tr - m.xi * m.cohesion > 0); /* outside the cone */
    double dg, dc;
    corner_by_bisection(&m, sj2_tr, p_tr, 0, &dg, &dc);
    assert_true(dg > 0 && dc > 0); /* a genuine corner */
    double out[6];
    memcpy(out, sig, sizeof out);
    rf_material_update(&m, deps, out, &st, NULL);
    double s[6];
    const double p = split(out, s), scale = 1 - m.G * dg / sj2_tr;
    assert_true(fabs(p - (p_tr - m.K * m.eta_bar * dg + m.K * dc)) <= 1e-9 * X0);
    for (int i = 0; i < 6; i++)
        assert_true(fabs(s[i] - scale * s_tr[i]) <= 1e-9 * X0);
    assert_true(fabs(st.compaction - dc) <= 1e-9 * dc);
    /* The corner's volume change: dilation eta_bar dgamma less the compaction. */
    assert_true(fabs(st.plastic_volumetric - (m.eta_bar * dg - dc)) <= 1e-9 * dc);
}

/* Kuhn-Tucker conditions of one return from (sig, st) under deps; counts[]
 * the returns per branch: elastic, cone, cap, corner, apex. */
static int counts[5];

static void check_return(const rf_material *m, const double sig0[6], double c0, const double deps[6])
{
    double s_tr[6], p_tr, sig[6], s[6];
    trial(m, sig0, deps, s_tr, &p_tr);
    rf_material_state st = {0, 0, c0};
    memcpy(sig, sig0, sizeof sig);
    rf_material_update(m, deps, sig, &st, NULL);
    const double p = split(sig, s), sj2_tr = sqrt_j2(s_tr), sj2 = sqrt_j2(s);
    const double scale = fmax(fmax(fabs(p_tr), sj2_tr), m->cap_pressure + m->cap_hardening * c0), tol = 1e-9 * scale;
    assert_true(rf_material_admissible(m, sig, &st, 1e-9));
    const double k = sj2_tr > 0 ? sj2 / sj2_tr : 1;
    assert_true(k >= -1e-12 && k <= 1 + 1e-12);
    for (int i = 0; i < 6; i++)
        assert_true(fabs(s[i] - k * s_tr[i]) <= tol);
    const double dg = (sj2_tr - sj2) / m->G, dc = st.compaction - c0;
    assert_true(dg >= -tol / m->G && dc >= 0);
    const double f_cone = sj2 + m->eta * p - m->xi * m->cohesion;
    const double f_cap = -p - (m->cap_pressure + m->cap_hardening * st.compaction);
    if (dg > tol / m->G)
        assert_true(fabs(f_cone) <= tol);
    if (dc > 1e-15)
        assert_true(fabs(f_cap) <= tol);
    const int apex = sj2 <= tol && fabs(p - m->apex_pressure) <= tol;
    counts[apex ? 4 : (dg > tol / m->G) + 2 * (dc > 1e-15)]++;
    if (!apex)
        assert_true(fabs(p - (p_tr - m->K * m->eta_bar * dg + m->K * dc)) <= tol);
}

static double uniform(double a, double b) { return a + (b - a) * (double)rand() / RAND_MAX; }

static void test_return_kkt_random(void **state)
{
    (void)state;
    srand(29);
    const double psis[2] = {5, 15};
    for (int j = 0; j < 2; j++) {
        rf_material m;
        talus_layer(&m, psis[j]);
        for (int n = 0; n < 20000; n++) {
            /* An admissible start: mean stress down to a hardened cap, a deviator inside the cone. */
            const double c0 = uniform(0, 0.02), X = m.cap_pressure + m.cap_hardening * c0;
            const double p0 = uniform(-X, fmin(0, m.apex_pressure)), q = uniform(0, 1) * (m.xi * m.cohesion - m.eta * p0);
            double d[6] = {uniform(-1, 1), uniform(-1, 1), 0, uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
            d[2] = -d[0] - d[1];
            const double r = sqrt_j2(d);
            double sig0[6], deps[6];
            for (int i = 0; i < 6; i++)
                sig0[i] = q * d[i] / r + (i < 3 ? p0 : 0), deps[i] = uniform(-2e-3, 2e-3);
            check_return(&m, sig0, c0, deps);
        }
    }
    for (int b = 0; b < 5; b++) /* every branch met (elastic, cone, cap, corner, apex) */
        assert_true(counts[b] >= 50);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corner_by_hand),
        cmocka_unit_test(test_return_kkt_random),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
