/* test_mdr.c - the MDR partial-slip impact model (rockfuzz/mdr.h) against
 * closed forms: Mindlin's static tangential load-displacement curve with
 * Mindlin-Deresiewicz unloading and reloading (Johnson 1985, sec. 7.2-7.3);
 * gross sliding equal to the rigid-body formulas (impact_refs.md sec. 4.1);
 * f = 0; the MBF limits (gross slip throughout exactly from psi1 = 4 chi - 1;
 * psi1 -> 0 against an independent no-slip integration); convergence in the
 * number of springs and time steps; spin invariance; the impact-model wiring. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/impact_model.h"
#include "rockfuzz/mdr.h"

#define DEG (3.14159265358979323846 / 180.0)

static void assert_abs(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: got %.12g, want %.12g (|error| %.3g > %.3g)", what, got, want, fabs(got - want), tol);
}

/* Granite sphere r0 = 1 m falling at V onto a slope at `angle_deg`. */
static rf_mdr_problem granite(double angle_deg, double friction, double e_n)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    double V = 10.0;
    return (rf_mdr_problem){.radius = 1.0, .mass = rf_impact_mass(&in),
                            .inertia = rf_impact_moment_of_inertia(&in),
                            .E_star = rf_impact_effective_modulus(&in),
                            .G_star = rf_mdr_tangential_modulus(&in), .friction = friction, .e_n = e_n,
                            .v_n = V * cos(angle_deg * DEG), .v_t = V * sin(angle_deg * DEG), .omega = 0.0};
}

/* Moduli: G* = 2G/(2-nu) for identical bodies, G* / E* = 2(1-nu)/(2-nu),
 * chi = 1.5 for a solid sphere with nu = 0.25; Dundurs beta = 0 for
 * identical bodies, antisymmetric in the exchange of the bodies. */
static void test_moduli(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    double G = in.boulder_E / 2.5;
    assert_abs(rf_mdr_tangential_modulus(&in) / (2.0 * G / 1.75), 1.0, 1e-14, "G*");
    assert_abs(rf_mdr_tangential_modulus(&in) / rf_impact_effective_modulus(&in), 1.5 / 1.75, 1e-14, "G*/E*");
    assert_abs(rf_mdr_dundurs_beta(&in), 0.0, 0.0, "beta identical");
    rf_mdr_problem p = granite(45.0, 0.5, 1.0);
    rf_mdr_result r;
    assert_int_equal(rf_mdr_impact(&p, NULL, &r, NULL), RF_OK);
    assert_abs(r.chi, 1.5, 1e-12, "chi");
    in.slope_E = 20e9;
    in.slope_poisson = 0.35;
    double b = rf_mdr_dundurs_beta(&in);
    rf_impact_input swapped = in;
    swapped.boulder_E = in.slope_E;
    swapped.slope_E = in.boulder_E;
    swapped.boulder_poisson = in.slope_poisson;
    swapped.slope_poisson = in.boulder_poisson;
    assert_true(fabs(b) > 0.01);
    assert_abs(rf_mdr_dundurs_beta(&swapped), -b, 1e-15, "beta antisymmetric");
}

/* Mindlin (1949) at constant normal force N: F = mu N [1 - (1 - u/u_s)^(3/2)],
 * u_s = mu E* d / G* (the MDR form of 3 mu N (2-nu) / (16 G a)). */
static double mindlin_load(double u, double u_s, double muN)
{
    return muN * (1.0 - pow(1.0 - u / u_s, 1.5));
}

/* Largest error / (mu N) of the bank with n springs over load 0 -> u*,
 * unload u* -> -u* and reload -u* -> u* (Mindlin-Deresiewicz: the unloading
 * curve is the loading curve doubled, F = F* - 2 F_load((u* - u)/2)). */
static double mindlin_cycle_error(size_t n, int steps)
{
    double R = 1.0, E = 3.6e10, G = 3.1e10, mu = 0.4, d = 0.01;
    rf_mdr_contact c;
    assert_int_equal(rf_mdr_contact_init(&c, n, sqrt(R * d), R, E, G, mu, NULL), RF_OK);
    double N = 0.0;
    rf_mdr_contact_step(&c, d, 0.0, 1.0, &N); /* press first, then shear */
    assert_abs(N / (4.0 / 3.0 * E * sqrt(R) * pow(d, 1.5)), 1.0, 1e-13, "Hertz force of the bank");
    double u_s = mu * E * d / G, muN = mu * N, u_star = 0.8 * u_s, u = 0.0, err = 0.0;
    for (int leg = 0; leg < 3; leg++) {
        double from = leg == 0 ? 0.0 : (leg == 1 ? u_star : -u_star), to = leg == 1 ? -u_star : u_star;
        for (int k = 1; k <= steps; k++) {
            double next = from + (to - from) * k / steps;
            double F = rf_mdr_contact_step(&c, d, next - u, 1.0, NULL), want;
            u = next;
            if (leg == 0)
                want = mindlin_load(u, u_s, muN);
            else if (leg == 1)
                want = mindlin_load(u_star, u_s, muN) - 2.0 * mindlin_load((u_star - u) / 2.0, u_s, muN);
            else
                want = -mindlin_load(u_star, u_s, muN) + 2.0 * mindlin_load((u + u_star) / 2.0, u_s, muN);
            err = fmax(err, fabs(F - want) / muN);
        }
    }
    rf_mdr_contact_free(&c);
    return err;
}

static void test_mindlin_static(void **state)
{
    (void)state;
    double e100 = mindlin_cycle_error(100, 50), e400 = mindlin_cycle_error(400, 50);
    /* second order in the spring width: measured 6.6e-5 and 4.3e-6 */
    if (!(e100 < 1e-4 && e400 < 1e-5 && e400 < e100 / 8.0))
        fail_msg("Mindlin cycle: error %.3g (100 springs), %.3g (400 springs)", e100, e400);
    /* the step size does not matter for a rate-independent monotone path */
    assert_abs(mindlin_cycle_error(400, 7), e400, 2e-6, "coarse steps");
}

/* Initial stiffness of a stuck contact: 2 G* a (= 8 G_Johnson a). */
static void test_stuck_stiffness(void **state)
{
    (void)state;
    double R = 2.0, E = 5e10, G = 4e10, d = 1e-3, a = sqrt(R * d), du = 1e-9;
    rf_mdr_contact c;
    assert_int_equal(rf_mdr_contact_init(&c, 200, a, R, E, G, 1.0, NULL), RF_OK);
    rf_mdr_contact_step(&c, d, 0.0, 1.0, NULL);
    double F = rf_mdr_contact_step(&c, d, du, 1.0, NULL);
    assert_abs(F / du / (2.0 * G * a), 1.0, 1e-12, "stuck stiffness 2 G* a");
    rf_mdr_contact_free(&c);
}

static rf_mdr_result run(const rf_mdr_problem *p, size_t springs, size_t steps)
{
    rf_mdr_options o = {springs, steps};
    rf_mdr_result r;
    assert_int_equal(rf_mdr_impact(p, springs ? &o : NULL, &r, NULL), RF_OK);
    return r;
}

/* Gross sliding (psi1 = 14.8 on 60 deg with f = 0.1): the tangential impulse
 * is f times the normal one at every instant, so the rigid-body formulas
 * hold with the model's own R_n: v_t' = v_t - f (1 + R_n) v_n,
 * omega' = omega + f (1 + R_n) v_n m R / I; also with an initial spin. */
static void test_gross_sliding(void **state)
{
    (void)state;
    const double e_n[] = {1.0, 0.9, 0.5}, spin[] = {0.0, -5.0, 3.0};
    for (int k = 0; k < 3; k++) {
        rf_mdr_problem p = granite(60.0, 0.1, e_n[k]);
        p.omega = spin[k];
        rf_mdr_result r = run(&p, 0, 0);
        double Rn = r.v_n_after / p.v_n, P = p.friction * (1.0 + Rn) * p.v_n; /* impulse / m */
        /* the restitution force starts at a step boundary: O(dt (1 - e_n^2)),
         * measured 1.3e-5 at e_n = 0.5 */
        assert_abs(Rn, e_n[k], 3e-5 * (1.0 - e_n[k] * e_n[k]) / 0.75 + 1e-8, "R_n = e_n");
        assert_abs(r.v_t_after, p.v_t - P, 1e-12 * p.v_t, "v_t' rigid sliding");
        assert_abs(r.omega_after, p.omega + P * p.mass * p.radius / p.inertia, 1e-11, "omega' rigid sliding");
        assert_true(r.psi1 > 5.0);
        assert_true(r.friction_work > 0.0);
    }
}

/* f = 0: no tangential force at all. */
static void test_frictionless(void **state)
{
    (void)state;
    rf_mdr_problem p = granite(45.0, 0.0, 1.0);
    rf_mdr_result r = run(&p, 0, 0);
    assert_true(r.v_t_after == p.v_t);
    assert_true(r.omega_after == 0.0);
    assert_true(r.tangential_force_max == 0.0);
    assert_abs(r.v_n_after / p.v_n, 1.0, 1e-8, "elastic R_n");
}

/* MBF: sliding throughout exactly when psi1 >= 4 chi - 1 (= 5 here), although
 * the rigid-body criterion is psi1 >= 4 chi; below, partial slip and the
 * rigid sliding formula no longer hold. */
static double sliding_formula_gap(double psi1)
{
    rf_mdr_problem p = granite(45.0, 0.3, 1.0);
    p.v_t = psi1 * p.friction * p.v_n * p.E_star / p.G_star;
    rf_mdr_result r = run(&p, 400, 1600);
    assert_abs(r.psi1, psi1, 1e-12, "psi1");
    return (r.v_t_after - (p.v_t - p.friction * (1.0 + r.v_n_after / p.v_n) * p.v_n)) / p.v_t;
}

static void test_gross_slip_threshold(void **state)
{
    (void)state;
    assert_abs(sliding_formula_gap(6.0), 0.0, 1e-12, "psi1 = 6");
    assert_abs(sliding_formula_gap(5.2), 0.0, 1e-7, "psi1 = 5.2"); /* discrete edge spring: 2e-8 */
    assert_true(sliding_formula_gap(4.8) > 1e-3);                   /* measured 1.6e-3 */
    assert_true(sliding_formula_gap(4.0) > 3e-2);                   /* rigid threshold: 3.7e-2 */
}

/* psi1 -> 0 (f -> infinity): no spring ever slips, and the tangential force
 * is Q = 2 G* [U a - integral_0^a U_entry(x) dx], U the tangential
 * displacement, U_entry(x) its value when the growing contact reached x; a
 * receding contact drops the springs beyond a with their force.  This
 * independent integration (no springs, no caps; its own Verlet loop) must
 * give the MDR's R_t: it differs by 8.6e-5 with 4000 steps, 5.8e-6 with
 * 16000 (its own discretisation error). */
typedef struct {
    double a[20000], U[20000];
    size_t n;
} entry_log;

static double entry_integral(const entry_log *log, double a)
{
    double sum = 0.0;
    for (size_t k = 1; k < log->n && log->a[k - 1] < a; k++) {
        double hi = fmin(log->a[k], a), lo = log->a[k - 1];
        double U_hi = log->U[k - 1] + (log->U[k] - log->U[k - 1]) * (hi - lo) / (log->a[k] - lo);
        sum += 0.5 * (log->U[k - 1] + U_hi) * (hi - lo);
    }
    return sum;
}

static double no_slip_Rt(const rf_mdr_problem *p, size_t steps)
{
    static entry_log log;
    log.n = 1;
    log.a[0] = log.U[0] = 0.0;
    double k = 4.0 / 3.0 * p->E_star * sqrt(p->radius);
    double d_max = pow(15.0 * p->mass * p->v_n * p->v_n / (16.0 * p->E_star * sqrt(p->radius)), 0.4);
    double dt = 3.0 * d_max / p->v_n / (double)steps;
    double d = 0.0, w = p->v_n, vt = p->v_t, om = p->omega, U = 0.0, Fn = 0.0, Q = 0.0;
    for (size_t i = 0; i < 4 * steps; i++) {
        w -= Fn / p->mass * 0.5 * dt;
        vt -= Q / p->mass * 0.5 * dt;
        om += Q * p->radius / p->inertia * 0.5 * dt;
        U += 0.5 * (vt - om * p->radius) * dt; /* U at mid-step for a growing contact */
        d += w * dt;
        if (d <= 0.0)
            break;
        double a = sqrt(p->radius * d);
        if (a > log.a[log.n - 1] && log.n < 20000) {
            log.a[log.n] = a;
            log.U[log.n++] = U;
        }
        U += 0.5 * (vt - om * p->radius) * dt;
        Fn = k * pow(d, 1.5);
        Q = 2.0 * p->G_star * (U * a - entry_integral(&log, a));
        w -= Fn / p->mass * 0.5 * dt;
        vt -= Q / p->mass * 0.5 * dt;
        om += Q * p->radius / p->inertia * 0.5 * dt;
    }
    return vt / p->v_t;
}

static void test_no_slip_limit(void **state)
{
    (void)state;
    rf_mdr_problem p = granite(45.0, 1e9, 1.0);
    rf_mdr_result r = run(&p, 0, 0);
    double Rt = r.v_t_after / p.v_t, ref = no_slip_Rt(&p, 4000);
    assert_abs(Rt, ref, 1e-4, "R_t, f -> infinity");
    /* R_t above the rigid 5/7: the stored tangential energy partly returns */
    assert_true(Rt > 0.79 && Rt < 0.80);
    assert_abs(r.beta_t, 1.0 - 3.5 * (1.0 - Rt), 1e-12, "beta_t = 1 - 3.5 (1 - R_t) without spin");
    /* no spring slips, yet energy goes: the springs leaving the receding
     * contact take their stored energy with them (Mindlin-Deresiewicz) */
    assert_true(r.friction_work > 0.05 * 0.5 * p.mass * p.v_t * p.v_t);
}

/* Convergence on 45 deg, f = 0.6 (partial slip) and f = 5: 4x more springs or
 * steps shrink the error at least 4x (measured 9-19x: order 1.6-2); the defaults (100 springs, 400
 * steps) are within 3e-5 of 800 springs x 3200 steps. */
static void test_convergence(void **state)
{
    (void)state;
    const double friction[] = {0.6, 5.0};
    for (int k = 0; k < 2; k++) {
        rf_mdr_problem p = granite(45.0, friction[k], 1.0);
        double fine = run(&p, 800, 3200).v_t_after / p.v_t;
        double def = run(&p, 0, 0).v_t_after / p.v_t;
        assert_abs(def, fine, 3e-5, "defaults vs fine");
        double s25 = run(&p, 25, 3200).v_t_after / p.v_t, s100 = run(&p, 100, 3200).v_t_after / p.v_t;
        double t100 = run(&p, 800, 100).v_t_after / p.v_t, t400 = run(&p, 800, 400).v_t_after / p.v_t;
        if (!(fabs(s100 - fine) < fabs(s25 - fine) / 4.0 && fabs(t400 - fine) < fabs(t100 - fine) / 4.0))
            fail_msg("f = %g: springs 25/100 err %.3g/%.3g, steps 100/400 err %.3g/%.3g", friction[k],
                     s25 - fine, s100 - fine, t100 - fine, t400 - fine);
    }
}

/* Mirror symmetry: (v_t, omega) -> (-v_t, -omega) mirrors the result. */
static void test_mirror(void **state)
{
    (void)state;
    rf_mdr_problem p = granite(30.0, 0.4, 0.95), q;
    p.omega = 2.0;
    q = p;
    q.v_t = -p.v_t;
    q.omega = -p.omega;
    rf_mdr_result a = run(&p, 0, 0), b = run(&q, 0, 0);
    assert_true(a.v_t_after == -b.v_t_after && a.omega_after == -b.omega_after);
    assert_true(a.v_n_after == b.v_n_after);
}

/* Initial spin: the contact sees only the contact-point velocity v_c = v_t -
 * omega R, so (v_t, omega) and (v_t + s R, omega + s) take the same impulse
 * (partial slip, 45 deg, f = 0.6): v_t' and omega' shift by s R and s. */
static void test_spin_invariance(void **state)
{
    (void)state;
    rf_mdr_problem p = granite(45.0, 0.6, 1.0), q;
    q = p;
    q.omega = 3.0;
    q.v_t = p.v_t + 3.0 * p.radius;
    rf_mdr_result a = run(&p, 0, 0), b = run(&q, 0, 0);
    assert_abs(b.v_t_after - a.v_t_after, 3.0 * p.radius, 1e-12, "v_t' shift");
    assert_abs(b.omega_after - a.omega_after, 3.0, 1e-12, "omega' shift");
    assert_abs(b.psi2, a.psi2, 1e-12, "psi2");
    assert_true(a.psi1 < 4.0 * a.chi - 1.0); /* partial slip, not gross sliding */
}

/* The impact model: "mdr" parses; e_n unset = Hunter's; bound parameters. */
static void test_model_wiring(void **state)
{
    (void)state;
    rf_impact_solver s;
    assert_int_equal(rf_impact_solver_parse("mdr", &s, NULL), RF_OK);
    assert_int_equal(s, RF_IMPACT_MDR);
    assert_string_equal(rf_impact_solver_name(RF_IMPACT_MDR), "mdr");
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = RF_IMPACT_MDR;
    spec.base.slope_angle = 45.0 * DEG;
    spec.base.friction = 0.6;
    rf_impact_output out, hunter, direct;
    assert_int_equal(rf_impact_solve(&spec, &spec.base, &out, NULL), RF_OK);
    assert_int_equal(rf_impact_hunter(&spec.base, &hunter, NULL), RF_OK);
    assert_int_equal(rf_impact_mdr(&spec.base, hunter.R_n, &direct, NULL), RF_OK);
    assert_abs(out.R_n, hunter.R_n, 1e-6, "R_n = Hunter's e_n");
    assert_true(out.R_t == direct.R_t && out.R_ke == direct.R_ke);
    double ke = (out.v_n_after * out.v_n_after + out.v_t_after * out.v_t_after +
                 0.4 * out.omega_after * out.omega_after) / 100.0;
    assert_abs(out.R_ke, ke, 1e-12, "R_ke with rotation");

    const char *names[] = {"slope_angle", "friction"};
    rf_model m;
    assert_int_equal(rf_impact_model_create(&spec, names, 2, &m, NULL), RF_OK);
    double x[2] = {45.0, 0.6}, y[RF_IMPACT_N_OUTPUTS];
    assert_int_equal(rf_model_eval(&m, x, y, NULL), RF_OK);
    assert_true(y[5] == out.R_t && y[4] == out.R_n);
    rf_model_free(&m);

    spec.base.horizontal_axis = 1.1; /* a spheroid on a slope is the FE's job */
    assert_int_equal(rf_impact_solve(&spec, &spec.base, &out, NULL), RF_EINVAL);
    spec.base.horizontal_axis = 0.0;
    spec.e_n = 0.0;
    assert_int_equal(rf_impact_solve(&spec, &spec.base, &out, NULL), RF_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_moduli),
        cmocka_unit_test(test_mindlin_static),
        cmocka_unit_test(test_stuck_stiffness),
        cmocka_unit_test(test_gross_sliding),
        cmocka_unit_test(test_frictionless),
        cmocka_unit_test(test_gross_slip_threshold),
        cmocka_unit_test(test_no_slip_limit),
        cmocka_unit_test(test_convergence),
        cmocka_unit_test(test_mirror),
        cmocka_unit_test(test_spin_invariance),
        cmocka_unit_test(test_model_wiring),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
