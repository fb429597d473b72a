/* test_material.c - the point-wise constitutive laws of src/material against
 * closed forms (docs/materials.md, "Validation"): J2 under uniaxial strain,
 * Drucker-Prager under simple shear from an isotropic pressure, under
 * hydrostatic tension (apex), confined compression that only the cap yields,
 * independence of the number of increments for these radial paths, plastic
 * work against its closed form, huge strength = elastic, admissibility on
 * random paths, and input validation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "core/util.h"
#include "rockfuzz/material.h"
#include "test_util.h"

#define DEG (RF_PI / 180.0)

static const int increment_counts[] = {1, 7, 100, 1000};
#define N_COUNTS (sizeof increment_counts / sizeof increment_counts[0])

static rf_material make(const rf_material_params *p)
{
    rf_material m;
    rf_error err = {0};
    if (rf_material_init(&m, p, &err) != RF_OK)
        fail_msg("rf_material_init: %s", err.msg);
    return m;
}

static rf_material_params von_mises(double Y, double H)
{
    rf_material_params p;
    rf_material_params_default(&p);
    p.model = RF_MATERIAL_VON_MISES;
    p.E = 200e9;
    p.poisson = 0.3;
    p.yield = Y;
    p.hardening = H;
    return p;
}

/* Loose-to-medium sand (docs/materials.md table). */
static rf_material_params sand(double phi_deg, double psi_deg, double X0, double Hc)
{
    rf_material_params p;
    rf_material_params_default(&p);
    p.model = RF_MATERIAL_DRUCKER_PRAGER;
    p.E = 30e6;
    p.poisson = 0.3;
    p.cohesion = 2e3;
    p.friction_angle = phi_deg * DEG;
    p.dilatancy_angle = psi_deg * DEG;
    p.cap_pressure = X0;
    p.cap_hardening = Hc;
    return p;
}

/* Drives a point from the isotropic stress p0 along strain_total in n equal
 * increments; returns the plastic work. */
static double drive(const rf_material *m, double p0, const double strain_total[6], int n, double sig[6],
                    rf_material_state *st)
{
    double deps[6], work = 0.0, d;
    for (int i = 0; i < 6; i++) {
        deps[i] = strain_total[i] / n;
        sig[i] = i < 3 ? p0 : 0.0;
    }
    memset(st, 0, sizeof *st);
    for (int k = 0; k < n; k++) {
        rf_material_update(m, deps, sig, st, &d);
        assert_true(d >= -1e-9 * (fabs(work) + 1.0));
        work += d;
    }
    return work;
}

static void test_j2_elastic_limit(void **state)
{
    (void)state;
    rf_material_params p = von_mises(250e6, 0.0);
    rf_material m = make(&p);
    double nu = p.poisson, eps_y = p.yield / (2.0 * m.G), sig[6];
    rf_material_state st;
    double e[6] = {eps_y * (1.0 - 1e-12), 0, 0, 0, 0, 0};
    drive(&m, 0.0, e, 1, sig, &st);
    assert_close(sig[0], p.yield * (1.0 - nu) / (1.0 - 2.0 * nu), 1e-11);
    assert_true(st.plastic_strain_eq == 0.0);
    e[0] = eps_y * (1.0 + 1e-6);
    drive(&m, 0.0, e, 1, sig, &st);
    assert_true(st.plastic_strain_eq > 0.0);
}

/* Uniaxial strain eps, elastic-plastic: eps_p = (2G|eps| - Y)/(3G + H),
 * |sxx - syy| = Y + H eps_p, p = K eps, W_p = Y eps_p + H eps_p^2 / 2. */
static void test_j2_uniaxial_strain(void **state)
{
    (void)state;
    const double H[] = {0.0, 2e9};
    const double eps[] = {0.01, -0.004};
    for (int h = 0; h < 2; h++)
        for (int s = 0; s < 2; s++)
            for (size_t c = 0; c < N_COUNTS; c++) {
                rf_material_params p = von_mises(250e6, H[h]);
                rf_material m = make(&p);
                double e[6] = {eps[s], 0, 0, 0, 0, 0}, sig[6];
                rf_material_state st;
                double work = drive(&m, 0.0, e, increment_counts[c], sig, &st);
                double ep = (2.0 * m.G * fabs(eps[s]) - p.yield) / (3.0 * m.G + p.hardening);
                double q = p.yield + p.hardening * ep, sign = eps[s] > 0 ? 1.0 : -1.0;
                assert_close(st.plastic_strain_eq, ep, 1e-10);
                assert_close(sig[0] - sig[1], sign * q, 1e-10);
                assert_close(sig[0], m.K * eps[s] + sign * 2.0 * q / 3.0, 1e-10);
                assert_close(sig[1], sig[2], 1e-12);
                assert_close(work, p.yield * ep + 0.5 * p.hardening * ep * ep, 1e-10);
            }
}

/* Outer-cone constants against plasticity_refs.md sec. 2.2. */
static void test_dp_constants(void **state)
{
    (void)state;
    const double phi[] = {25, 30, 35, 40}, eta[] = {0.568, 0.693, 0.819, 0.945},
                 xi[] = {1.218, 1.200, 1.170, 1.126};
    for (int i = 0; i < 4; i++) {
        assert_true(fabs(rf_material_dp_eta(phi[i] * DEG) - eta[i]) < 6e-4);
        assert_true(fabs(rf_material_dp_xi(phi[i] * DEG) - xi[i]) < 6e-4);
    }
    /* Outer cone = Mohr-Coulomb in triaxial compression: q = 6 (c cos + p' sin)/(3 - sin). */
    double f = 33 * DEG, c = 5e3, pc = 1e5, sn = sin(f);
    double q_mc = 6.0 * (c * cos(f) + pc * sn) / (3.0 - sn);
    assert_close(sqrt(3.0) * (rf_material_dp_xi(f) * c + rf_material_dp_eta(f) * pc), q_mc, 1e-14);
}

/* Simple shear gamma at constant volume from p0 < 0, psi = 0: p stays p0,
 * tau -> xi c - eta p0; the plastic shear is gamma - tau/G. */
static void test_dp_simple_shear(void **state)
{
    (void)state;
    for (size_t c = 0; c < N_COUNTS; c++) {
        rf_material_params p = sand(32, 0, 0, 0);
        rf_material m = make(&p);
        double p0 = -1e5, gamma = 0.05, e[6] = {0, 0, 0, gamma, 0, 0}, sig[6];
        rf_material_state st;
        double work = drive(&m, p0, e, increment_counts[c], sig, &st);
        double tau = rf_material_dp_xi(p.friction_angle) * p.cohesion - rf_material_dp_eta(p.friction_angle) * p0;
        double gp = gamma - tau / m.G;
        assert_close(sig[3], tau, 1e-10);
        for (int i = 0; i < 3; i++)
            assert_close(sig[i], p0, 1e-12);
        assert_close(st.plastic_strain_eq, gp / sqrt(3.0), 1e-10);
        assert_close(work, tau * gp, 1e-10);
        assert_true(st.plastic_volumetric == 0.0);
    }
}

/* Same with dilatancy psi > 0 at constant volume: plastic dilation raises the
 * confinement, p = p0 - K eta_bar G_p, tau = xi c - eta p = G (gamma - G_p),
 * G_p = (G gamma - xi c + eta p0) / (G + K eta eta_bar). */
static void test_dp_simple_shear_dilatant(void **state)
{
    (void)state;
    for (size_t c = 0; c < N_COUNTS; c++) {
        rf_material_params p = sand(36, 8, 0, 0);
        rf_material m = make(&p);
        double p0 = -5e4, gamma = 0.02, e[6] = {0, 0, 0, gamma, 0, 0}, sig[6];
        rf_material_state st;
        drive(&m, p0, e, increment_counts[c], sig, &st);
        double gp = (m.G * gamma - m.xi * p.cohesion + m.eta * p0) / (m.G + m.K * m.eta * m.eta_bar);
        double pf = p0 - m.K * m.eta_bar * gp;
        assert_close(sig[0], pf, 1e-10);
        assert_close(sig[3], m.xi * p.cohesion - m.eta * pf, 1e-10);
        assert_close(sig[3], m.G * (gamma - gp), 1e-10);
        assert_close(st.plastic_volumetric, m.eta_bar * gp, 1e-10);
    }
}

/* The dilatancy cutoff (critical state): the same dilatant shear stops
 * dilating at a plastic volume change eps_cut, after which it is isochoric,
 * so p = p0 - K eps_cut and tau = xi c - eta p for any number of increments;
 * below the cutoff the law is the one without it, to the bit. */
static void test_dp_dilatancy_cutoff(void **state)
{
    (void)state;
    rf_material_params p = sand(36, 8, 0, 0), q = p;
    q.dilatancy_cutoff = 5e-4;
    rf_material m = make(&p), mc = make(&q);
    double p0 = -5e4, gamma = 0.02, e[6] = {0, 0, 0, gamma, 0, 0}, sig[6], sig_free[6];
    rf_material_state st, st_free;
    drive(&m, p0, e, 100, sig_free, &st_free);
    assert_true(st_free.plastic_volumetric > 2.0 * q.dilatancy_cutoff); /* the cutoff is crossed */
    for (size_t c = 0; c < N_COUNTS; c++) {
        drive(&mc, p0, e, increment_counts[c], sig, &st);
        double pf = p0 - m.K * q.dilatancy_cutoff, tau = m.xi * p.cohesion - m.eta * pf;
        assert_close(st.plastic_volumetric, q.dilatancy_cutoff, 1e-12);
        assert_close(sig[0], pf, 1e-12);
        assert_close(sig[3], tau, 1e-12);
    }
    /* Below the cutoff: identical to the law without it. */
    double gp_cut = q.dilatancy_cutoff / m.eta_bar;
    double gamma_below = 0.5 * (gp_cut * (m.G + m.K * m.eta * m.eta_bar) + m.xi * p.cohesion - m.eta * p0) / m.G;
    double e_below[6] = {0, 0, 0, gamma_below, 0, 0};
    drive(&m, p0, e_below, 50, sig_free, &st_free);
    drive(&mc, p0, e_below, 50, sig, &st);
    assert_true(st.plastic_volumetric > 0.0 && st.plastic_volumetric < q.dilatancy_cutoff);
    assert_memory_equal(sig, sig_free, sizeof sig);
    assert_memory_equal(&st, &st_free, sizeof st);
}

/* Compaction on the cap lowers the plastic volume change, so a compacted
 * sand dilates again up to the same critical state: compress on the cap,
 * unload elastically, shear at constant volume; the dilation ends at the
 * cutoff, not at the cutoff plus the compaction. */
static void test_dp_cutoff_after_compaction(void **state)
{
    (void)state;
    rf_material_params p = sand(36, 8, 200e3, 50e6);
    p.dilatancy_cutoff = 5e-3;
    rf_material m = make(&p);
    double sig[6] = {0}, d;
    rf_material_state st = {0};
    double S = -0.01 / 50, comp[6] = {S, S, S, 0, 0, 0};
    for (int k = 0; k < 50; k++)
        rf_material_update(&m, comp, sig, &st, &d);
    double ec = st.compaction;
    assert_true(ec > 2e-3);
    assert_close(st.plastic_volumetric, -ec, 1e-12);
    double unload = (-5e4 - sig[0]) / (3.0 * m.K) / 10, back[6] = {unload, unload, unload, 0, 0, 0};
    for (int k = 0; k < 10; k++)
        rf_material_update(&m, back, sig, &st, &d);
    assert_close(sig[0], -5e4, 1e-9);
    assert_true(st.compaction == ec); /* elastic unloading */
    double p1 = sig[0], shear[6] = {0, 0, 0, 0.2 / 200, 0, 0};
    for (int k = 0; k < 200; k++)
        rf_material_update(&m, shear, sig, &st, &d);
    assert_close(st.plastic_volumetric, p.dilatancy_cutoff, 1e-12);
    assert_close(sig[0], p1 - m.K * (p.dilatancy_cutoff + ec), 1e-12);
    assert_close(sig[3], m.xi * p.cohesion - m.eta * sig[0], 1e-12);
    assert_true(st.compaction == ec); /* the cap stayed elastic: -p < X */
}

/* Hydrostatic tension: the mean stress stops at the apex c cot(phi), the
 * deviator stays zero, W_p = p_apex * (3 S - p_apex / K), whatever psi. */
static void test_dp_apex(void **state)
{
    (void)state;
    const double psi[] = {0, 15, 30};
    for (int k = 0; k < 3; k++)
        for (size_t c = 0; c < N_COUNTS; c++) {
            rf_material_params p = sand(30, psi[k], 0, 0);
            rf_material m = make(&p);
            double S = 1e-3, e[6] = {S, S, S, 0, 0, 0}, sig[6];
            rf_material_state st;
            double work = drive(&m, 0.0, e, increment_counts[c], sig, &st);
            double apex = p.cohesion / tan(p.friction_angle), evp = 3.0 * S - apex / m.K;
            for (int i = 0; i < 3; i++)
                assert_close(sig[i], apex, 1e-12);
            assert_true(sig[3] == 0.0 && sig[4] == 0.0 && sig[5] == 0.0);
            assert_close(st.plastic_volumetric, evp, 1e-10);
            assert_close(work, apex * evp, 1e-10);
        }
}

/* eta K/G >= 2/sqrt3: the elastic oedometric path never reaches the cone
 * (plasticity_refs.md sec. 2.3), so a plain cone stays elastic for ever. */
static void test_dp_cone_never_yields_confined(void **state)
{
    (void)state;
    rf_material_params p = sand(35, 0, 0, 0);
    rf_material m = make(&p);
    assert_true(m.eta * m.K / m.G > 2.0 / sqrt(3.0));
    assert_close(m.eta * m.K / m.G, 1.77, 5e-3); /* table of sec. 2.3, nu = 0.3 */
    double e[6] = {-0.2, 0, 0, 0, 0, 0}, sig[6];
    rf_material_state st;
    double work = drive(&m, 0.0, e, 100, sig, &st);
    assert_close(sig[0], (m.K + 4.0 * m.G / 3.0) * e[0], 1e-12);
    assert_close(sig[1], (m.K - 2.0 * m.G / 3.0) * e[0], 1e-12);
    assert_true(st.plastic_strain_eq == 0.0 && work == 0.0);
}

/* The cap yields it.  Oedometric compression S > X0/K: (cone inactive or with
 * psi = 0 not changing the volume) eps_c = (K S - X0)/(K + H_c),
 * p = -(X0 + H_c eps_c); deviator elastic (cap only) or on the cone
 * (corner): sqrt(J2) = xi c - eta p. */
static void check_oedometer(const rf_material *m, const rf_material_params *p, double S, int n,
                            int corner)
{
    double e[6] = {-S, 0, 0, 0, 0, 0}, sig[6];
    rf_material_state st;
    double work = drive(m, 0.0, e, n, sig, &st);
    double ec = (m->K * S - p->cap_pressure) / (m->K + p->cap_hardening);
    double X = p->cap_pressure + p->cap_hardening * ec;
    double sj2 = corner ? m->xi * p->cohesion + m->eta * X : 2.0 * m->G * S / sqrt(3.0);
    assert_close(st.compaction, ec, 1e-10);
    assert_close((sig[0] + sig[1] + sig[2]) / 3.0, -X, 1e-10);
    assert_close(sig[1] - sig[0], sqrt(3.0) * sj2, 1e-10);
    assert_close(sig[1], sig[2], 1e-12);
    assert_close(st.plastic_volumetric, -ec, 1e-10);
    if (!corner) /* cap only: radial, W_p = X0 eps_c + H_c eps_c^2 / 2 exactly */
        assert_close(work, p->cap_pressure * ec + 0.5 * p->cap_hardening * ec * ec, 1e-10);
    assert_true(rf_material_admissible(m, sig, &st, 1e-10));
}

static void test_dp_cap_confined(void **state)
{
    (void)state;
    rf_material_params p = sand(35, 0, 50e3, 5e6);
    rf_material m = make(&p);
    /* Cap only until 2G S/sqrt3 = xi c + eta X(S). */
    double S_corner = 0.0;
    for (double S = p.cap_pressure / m.K; S < 1.0; S += 1e-5) {
        double ec = (m.K * S - p.cap_pressure) / (m.K + p.cap_hardening);
        if (2.0 * m.G * S / sqrt(3.0) > m.xi * p.cohesion + m.eta * (p.cap_pressure + p.cap_hardening * ec)) {
            S_corner = S;
            break;
        }
    }
    assert_true(S_corner > 1.5 * p.cap_pressure / m.K); /* room for a cap-only phase */
    for (size_t c = 0; c < N_COUNTS; c++) {
        check_oedometer(&m, &p, 0.9 * S_corner, increment_counts[c], 0);
        check_oedometer(&m, &p, 2.0 * S_corner, increment_counts[c], 1);
    }
    /* Below X0/K nothing yields. */
    double e[6] = {-0.99 * p.cap_pressure / m.K, 0, 0, 0, 0, 0}, sig[6];
    rf_material_state st;
    assert_true(drive(&m, 0.0, e, 10, sig, &st) == 0.0 && st.compaction == 0.0);
}

/* Hydrostatic compression with the cap (cone never reached: s = 0). */
static void test_dp_cap_hydrostatic(void **state)
{
    (void)state;
    rf_material_params p = sand(30, 5, 40e3, 2e6);
    rf_material m = make(&p);
    for (size_t c = 0; c < N_COUNTS; c++) {
        double S = -0.01, e[6] = {S, S, S, 0, 0, 0}, sig[6];
        rf_material_state st;
        double work = drive(&m, 0.0, e, increment_counts[c], sig, &st);
        double ec = (-3.0 * S * m.K - p.cap_pressure) / (m.K + p.cap_hardening);
        assert_close(sig[0], -(p.cap_pressure + p.cap_hardening * ec), 1e-10);
        assert_close(work, p.cap_pressure * ec + 0.5 * p.cap_hardening * ec * ec, 1e-10);
        assert_close(st.plastic_strain_eq, sqrt(2.0) / 3.0 * ec, 1e-10);
    }
}

/* Tangent constrained moduli d sigma_xx / d eps_xx in uniaxial strain, the
 * squared wave speeds times rho of the 1D wave check (docs/materials.md):
 * J2 plastic K + 4GH/(3(3G + H)); cap only K_t + 4G/3; corner (psi = 0)
 * K_t (1 + 2 eta/sqrt3), K_t = K H_c/(K + H_c). */
static double oedometer_slope(const rf_material *m, double e1, double e2)
{
    double a[6] = {e1, 0, 0, 0, 0, 0}, b[6] = {e2, 0, 0, 0, 0, 0}, sa[6], sb[6];
    rf_material_state st;
    drive(m, 0.0, a, 50, sa, &st);
    drive(m, 0.0, b, 50, sb, &st);
    return (sb[0] - sa[0]) / (e2 - e1);
}

static void test_uniaxial_strain_tangent_moduli(void **state)
{
    (void)state;
    rf_material_params pv = von_mises(250e6, 2e9), pd = sand(35, 0, 50e3, 5e6);
    rf_material mv = make(&pv), md = make(&pd);
    double G = mv.G, K = mv.K, H = pv.hardening;
    assert_close(oedometer_slope(&mv, 0.004, 0.006), K + 4.0 * G * H / (3.0 * (3.0 * G + H)), 1e-9);
    double Kt = md.K * pd.cap_hardening / (md.K + pd.cap_hardening);
    double s_cap = pd.cap_pressure / md.K; /* onset of compaction */
    assert_close(oedometer_slope(&md, -1.2 * s_cap, -1.4 * s_cap), Kt + 4.0 * md.G / 3.0, 1e-9);
    assert_close(oedometer_slope(&md, -0.04, -0.05), Kt * (1.0 + 2.0 * md.eta / sqrt(3.0)), 1e-9);
}

/* A fixed pseudo-random strain path (LCG), the same in every run. */
static void random_increment(uint64_t *seed, double scale, double deps[6])
{
    for (int i = 0; i < 6; i++) {
        *seed = *seed * 6364136223846793005ULL + 1442695040888963407ULL;
        deps[i] = scale * ((double)(*seed >> 11) / 9007199254740992.0 - 0.5);
    }
    deps[0] -= 0.3 * scale; /* drift into compression */
}

/* With a huge strength every model is the elastic model, bit for bit. */
static void test_huge_strength_is_elastic(void **state)
{
    (void)state;
    rf_material_params pe = von_mises(1e300, 0), pv = von_mises(1e30, 1e9), pd = sand(30, 10, 1e30, 1e6);
    pe.model = RF_MATERIAL_ELASTIC;
    pd.E = pv.E = pe.E;
    pd.poisson = pv.poisson = pe.poisson;
    pd.cohesion = 1e30;
    rf_material me = make(&pe), mv = make(&pv), md = make(&pd);
    double se[6] = {0}, sv[6] = {0}, sd[6] = {0}, deps[6], d;
    rf_material_state ste = {0}, stv = {0}, std = {0};
    uint64_t seed = 42;
    for (int k = 0; k < 500; k++) {
        random_increment(&seed, 1e-3, deps);
        rf_material_update(&me, deps, se, &ste, &d);
        rf_material_update(&mv, deps, sv, &stv, &d);
        assert_true(d == 0.0);
        rf_material_update(&md, deps, sd, &std, &d);
        assert_true(d == 0.0);
    }
    for (int i = 0; i < 6; i++) {
        assert_close(sv[i], se[i], 1e-14);
        assert_close(sd[i], se[i], 1e-14);
    }
    assert_true(stv.plastic_strain_eq == 0.0 && std.plastic_strain_eq == 0.0);
}

/* Random non-radial paths: every state admissible, every dissipation >= 0,
 * and the work identity W_int = elastic energy + plastic work holds to first
 * order (trapezoidal internal work). */
static void test_random_paths_admissible(void **state)
{
    (void)state;
    rf_material_params ps[3] = {von_mises(100e6, 1e9), sand(35, 5, 50e3, 5e6), sand(28, 0, 20e3, 0)};
    ps[0].E = 30e6 * 1e3;
    for (int k = 0; k < 3; k++) {
        rf_material m = make(&ps[k]);
        double sig[6] = {-1e4, -1e4, -1e4, 0, 0, 0}, old[6], deps[6], d, w_int = 0.0, w_p = 0.0;
        double psi0 = rf_material_elastic_energy(&m, sig);
        rf_material_state st = {0};
        uint64_t seed = 7 + (uint64_t)k;
        for (int i = 0; i < 20000; i++) {
            random_increment(&seed, 2e-5, deps);
            memcpy(old, sig, sizeof old);
            rf_material_update(&m, deps, sig, &st, &d);
            assert_true(d >= 0.0);
            assert_true(rf_material_admissible(&m, sig, &st, 1e-9));
            for (int j = 0; j < 6; j++)
                w_int += 0.5 * (old[j] + sig[j]) * deps[j];
            w_p += d;
        }
        double psi = rf_material_elastic_energy(&m, sig) - psi0;
        assert_true(w_p > 0.0);
        assert_true(fabs(w_int - psi - w_p) < 2e-3 * w_p); /* first order in the increment (docs/materials.md) */
    }
}

static double uniform(uint64_t *seed, double lo, double hi)
{
    *seed = *seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * ((double)(*seed >> 11) / 9007199254740992.0);
}

/* 300 random Drucker-Prager materials (with and without cap, psi in [0, phi],
 * nu up to 0.49) on random paths with LARGE increments (up to 5 %), which
 * exercise every branch of the multisurface return: every state finite and
 * admissible, every plastic work and cap multiplier >= 0. */
static void test_random_materials_large_steps(void **state)
{
    (void)state;
    uint64_t seed = 2026;
    for (int k = 0; k < 300; k++) {
        rf_material_params p = sand(uniform(&seed, 0.0, 50.0), 0.0, 0.0, 0.0);
        p.dilatancy_angle = uniform(&seed, 0.0, 1.0) * p.friction_angle;
        p.poisson = uniform(&seed, 0.0, 0.49);
        p.cohesion = k % 5 == 0 ? 0.0 : uniform(&seed, 0.0, 5e4);
        if (p.friction_angle < 1e-3 * DEG)
            p.cohesion = 1e4;
        if (k % 3 == 0)
            p.dilatancy_cutoff = uniform(&seed, 1e-4, 2e-2);
        if (k % 2) {
            p.cap_pressure = uniform(&seed, 1e3, 2e5);
            p.cap_hardening = k % 4 == 1 ? 0.0 : uniform(&seed, 0.0, 1e8);
        }
        rf_material m = make(&p);
        double sig[6] = {0}, deps[6], d;
        rf_material_state st = {0};
        double scale = uniform(&seed, 1e-4, 5e-2);
        for (int i = 0; i < 200; i++) {
            double compaction = st.compaction;
            random_increment(&seed, scale, deps);
            rf_material_update(&m, deps, sig, &st, &d);
            for (int j = 0; j < 6; j++)
                assert_true(isfinite(sig[j]));
            assert_true(st.compaction >= compaction); /* cap multiplier >= 0 */
            if (!(d >= -1e-9 * (fabs(sig[0]) + m.xi * p.cohesion + p.cap_pressure) * scale))
                fail_msg("material %d step %d: plastic work %g < 0", k, i, d);
            if (!rf_material_admissible(&m, sig, &st, 1e-9))
                fail_msg("material %d step %d: inadmissible state", k, i);
        }
    }
}

static void test_block_equals_points(void **state)
{
    (void)state;
    rf_material_params p = sand(33, 3, 30e3, 3e6);
    rf_material m = make(&p);
    enum { N = 5 };
    double deps[6 * N], sig[6 * N] = {0}, sig1[6 * N] = {0}, d[N], d1;
    rf_material_state st[N] = {{0}}, st1[N] = {{0}};
    uint64_t seed = 3;
    for (int i = 0; i < N; i++)
        random_increment(&seed, 4e-3, deps + 6 * i);
    rf_material_update_block(&m, N, deps, sig, st, d);
    for (int i = 0; i < N; i++) {
        rf_material_update(&m, deps + 6 * i, sig1 + 6 * i, st1 + i, &d1);
        assert_true(d1 == d[i] && st1[i].compaction == st[i].compaction);
        assert_memory_equal(sig1 + 6 * i, sig + 6 * i, 6 * sizeof(double));
    }
}

static void test_wave_speed(void **state)
{
    (void)state;
    rf_material_params p = von_mises(1e8, 0);
    p.E = 68.2e9;
    p.poisson = 0.25;
    rf_material m = make(&p);
    double nu = 0.25, c = sqrt(p.E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * 2600.0));
    assert_close(rf_material_wave_speed(&m, 2600.0), c, 1e-14);
    double sig[6] = {1e6, -2e6, 0.5e6, 3e5, 0, -1e5};
    /* 1/2 sig : C^-1 : sig with the compliance written out. */
    double w = (sig[0] * sig[0] + sig[1] * sig[1] + sig[2] * sig[2]) / (2 * p.E)
               - nu / p.E * (sig[0] * sig[1] + sig[1] * sig[2] + sig[2] * sig[0])
               + (1 + nu) / p.E * (sig[3] * sig[3] + sig[4] * sig[4] + sig[5] * sig[5]);
    assert_close(rf_material_elastic_energy(&m, sig), w, 1e-13);
}

static double det3(const double v[6])
{
    return v[0] * (v[1] * v[2] - v[4] * v[4]) - v[3] * (v[3] * v[2] - v[4] * v[5])
           + v[5] * (v[3] * v[4] - v[1] * v[5]);
}

/* Hughes-Winget: n steps of spin 2 tan(theta/(2n)) about z turn a uniaxial
 * stress exactly by theta; any spin keeps the invariants. */
static void test_rotation(void **state)
{
    (void)state;
    const double theta = 1.1, c = cos(theta), s = sin(theta);
    for (size_t k = 0; k < N_COUNTS; k++) {
        int n = increment_counts[k];
        double sig[6] = {1e6, 0, 0, 0, 0, 0}, w[3] = {0, 0, 2.0 * tan(theta / (2.0 * n))};
        for (int i = 0; i < n; i++)
            rf_material_rotate(sig, w);
        assert_true(fabs(sig[0] - 1e6 * c * c) < 1e-9 * 1e6 && fabs(sig[1] - 1e6 * s * s) < 1e-9 * 1e6);
        assert_true(fabs(sig[3] - 1e6 * c * s) < 1e-9 * 1e6 && fabs(sig[2]) < 1e-9 && fabs(sig[4]) < 1e-9);
    }
    double sig[6] = {3e5, -1e5, -4e5, 2e5, -5e4, 1e5}, w[3] = {0.3, -0.7, 0.45}, s0[6];
    memcpy(s0, sig, sizeof s0);
    rf_material_rotate(sig, w);
    double i1 = s0[0] + s0[1] + s0[2], i1r = sig[0] + sig[1] + sig[2];
    double t[6], tr[6];
    for (int i = 0; i < 6; i++)
        t[i] = s0[i] - (i < 3 ? i1 / 3 : 0), tr[i] = sig[i] - (i < 3 ? i1r / 3 : 0);
    double j2 = 0.5 * (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) + t[3] * t[3] + t[4] * t[4] + t[5] * t[5];
    double j2r = 0.5 * (tr[0] * tr[0] + tr[1] * tr[1] + tr[2] * tr[2]) + tr[3] * tr[3] + tr[4] * tr[4] + tr[5] * tr[5];
    assert_close(i1r, i1, 1e-13);
    assert_close(j2r, j2, 1e-13);
    assert_close(det3(sig), det3(s0), 1e-12);
    assert_true(fabs(sig[0] - s0[0]) > 1e4); /* it did rotate */
    double zero[3] = {0, 0, 0};
    memcpy(s0, sig, sizeof s0);
    rf_material_rotate(sig, zero);
    assert_memory_equal(sig, s0, sizeof s0);
}

static void expect_invalid(const rf_material_params *p, const char *field)
{
    rf_material m;
    rf_error err = {0};
    assert_int_equal(rf_material_init(&m, p, &err), RF_EINVAL);
    if (!strstr(err.msg, field))
        fail_msg("message '%s' does not name '%s'", err.msg, field);
}

/* rf_material_yield: the closed forms.  Von Mises uniaxial sigma: |sigma| - (Y + H eps_p); Drucker-Prager
   shear tau at mean stress p0: tau + eta p0 - xi c; hydrostatic compression P beyond the cap: P - X(eps_c);
   elastic: -HUGE_VAL. */
static void test_yield_function(void **state)
{
    (void)state;
    rf_material_params pv = von_mises(100e6, 1e9);
    rf_material mv = make(&pv);
    rf_material_state st = {0.01, 0, 0};
    const double s1[6] = {-150e6, 0, 0, 0, 0, 0};
    assert_close(rf_material_yield(&mv, s1, &st), 150e6 - (100e6 + 1e9 * 0.01), 1e-12);
    rf_material_params pd = sand(32, 0, 200e3, 40e6);
    rf_material md = make(&pd);
    const double p0 = -1e5, tau = 3e4, s2[6] = {p0, p0, p0, tau, 0, 0};
    const double eta = rf_material_dp_eta(pd.friction_angle), xi = rf_material_dp_xi(pd.friction_angle);
    st = (rf_material_state){0, 0, 0};
    assert_close(rf_material_yield(&md, s2, &st), tau + eta * p0 - xi * pd.cohesion, 1e-12);
    const double P = 3e5, s3[6] = {-P, -P, -P, 0, 0, 0};
    st.compaction = 1e-3;
    assert_close(rf_material_yield(&md, s3, &st), P - (200e3 + 40e6 * 1e-3), 1e-12);
    rf_material_params pe;
    rf_material_params_default(&pe);
    rf_material me = make(&pe);
    assert_true(rf_material_yield(&me, s3, &st) == -HUGE_VAL);
}

static void test_validation(void **state)
{
    (void)state;
    rf_material_params p = von_mises(1e8, 0);
    p.E = -1;
    expect_invalid(&p, "E = -1");
    p = von_mises(1e8, 0), p.poisson = 0.5;
    expect_invalid(&p, "poisson = 0.5");
    p = von_mises(0, 0);
    expect_invalid(&p, "yield = 0");
    p = von_mises(1e8, -1);
    expect_invalid(&p, "hardening = -1");
    p = sand(30, 31, 0, 0);
    expect_invalid(&p, "dilatancy_angle = 31");
    p = sand(90, 0, 0, 0);
    expect_invalid(&p, "friction_angle = 90");
    p = sand(0, 0, 0, 0), p.cohesion = 0;
    expect_invalid(&p, "cohesion = 0");
    p = sand(30, 0, -1, 0);
    expect_invalid(&p, "cap_pressure = -1");
    p = sand(30, 0, 1e4, NAN);
    expect_invalid(&p, "cap_hardening = nan");
    p = sand(30, 5, 0, 0), p.dilatancy_cutoff = -1e-3;
    expect_invalid(&p, "dilatancy_cutoff = -0.001");
    p.dilatancy_cutoff = INFINITY;
    expect_invalid(&p, "dilatancy_cutoff = inf");
    rf_material_model model;
    rf_error err = {0};
    assert_int_equal(rf_material_model_parse("mohr", &model, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "'mohr'"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_j2_elastic_limit),
        cmocka_unit_test(test_j2_uniaxial_strain),
        cmocka_unit_test(test_dp_constants),
        cmocka_unit_test(test_dp_simple_shear),
        cmocka_unit_test(test_dp_simple_shear_dilatant),
        cmocka_unit_test(test_dp_dilatancy_cutoff),
        cmocka_unit_test(test_dp_cutoff_after_compaction),
        cmocka_unit_test(test_dp_apex),
        cmocka_unit_test(test_dp_cone_never_yields_confined),
        cmocka_unit_test(test_dp_cap_confined),
        cmocka_unit_test(test_dp_cap_hydrostatic),
        cmocka_unit_test(test_uniaxial_strain_tangent_moduli),
        cmocka_unit_test(test_huge_strength_is_elastic),
        cmocka_unit_test(test_random_paths_admissible),
        cmocka_unit_test(test_random_materials_large_steps),
        cmocka_unit_test(test_block_equals_points),
        cmocka_unit_test(test_wave_speed),
        cmocka_unit_test(test_rotation),
        cmocka_unit_test(test_yield_function),
        cmocka_unit_test(test_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
