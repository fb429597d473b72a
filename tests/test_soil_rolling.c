/* test_soil_rolling.c - the reduced model of the rolling resistance on a
 * layer (src/trajectory/traj_rolling_model.c, docs/soil-impacts.md "Rolling
 * resistance from the layer"), against:
 *  - the closed form of a constant pressure-sinkage law (an ideally plastic
 *    layer of bearing pressure q: F(d) = 2 pi R q d), written out here:
 *    z0 = W / (pi R q), mu_r = (4 / (3 pi)) sqrt(2 z0 / R);
 *  - the closed form of a power law F = A d^m with B_2 = 16/15 by hand;
 *  - a brute-force second method: the force balance of the pressures on the
 *    front half of the contact (2D quadrature of p and p x / R over the
 *    half disc), where the model uses the energy of the rut;
 *  - the physics' trends: a stronger layer rolls easier, and on a plastic
 *    layer a larger block sinks deeper relative to its radius (z0 ~ R^2), so
 *    mu_r grows as sqrt(R). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "trajectory/traj_rolling.h"
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

/* A sphere of radius R and density rho: its weight [N]. */
static double weight(double R, double rho) { return 4.0 / 3.0 * PI * R * R * R * rho * 9.81; }

/* The curve F = A d^m tabulated on n points up to dmax (malloc'd). */
static traj_rolling_curve power_curve(double A, double m, double dmax, size_t n)
{
    double *d = malloc(n * sizeof *d), *f = malloc(n * sizeof *f);
    for (size_t i = 0; i < n; i++)
        d[i] = dmax * (double)(i + 1) / (double)n, f[i] = A * pow(d[i], m);
    return (traj_rolling_curve){n, d, f};
}

static void curve_free(traj_rolling_curve *c)
{
    free((double *)c->depth);
    free((double *)c->force);
}

static double plastic_mu(double q, double R, double W)
{
    traj_rolling_curve c = power_curve(2 * PI * R * q, 1, 1.0, 2);
    traj_rolling_result r;
    rf_error err;
    assert_int_equal(traj_rolling_solve(&c, R, W, &r, &err), RF_OK);
    curve_free(&c);
    return r.mu_r;
}

/* Constant pressure q = 300 kPa, R = 0.5 m granite sphere. */
static void test_constant_pressure_closed_form(void **state)
{
    (void)state;
    double q = 300e3, R = 0.5, W = weight(R, 2600);
    traj_rolling_curve c = power_curve(2 * PI * R * q, 1, 0.5, 3);
    traj_rolling_result r;
    rf_error err;
    assert_int_equal(traj_rolling_solve(&c, R, W, &r, &err), RF_OK);
    double z0 = W / (PI * R * q);
    assert_close(r.sinkage, z0, 1e-12);
    assert_close(r.half_width, sqrt(2 * R * z0), 1e-12);
    assert_close(r.mu_r, 4 / (3 * PI) * sqrt(2 * z0 / R), 1e-12);
    /* the force is the rut's cross-section times q: (4/3) a z0 q */
    assert_close(r.force, 4.0 / 3.0 * r.half_width * z0 * q, 1e-12);
    assert_close(traj_rolling_power_mu(2 * PI * R * q, 1, R, W, NULL), r.mu_r, 1e-12);
    curve_free(&c);
}

/* A power law m = 2 (Bekker's p = K z): B_2 = 16/15; m = 1.5 against the Gamma form. */
static void test_power_law_closed_form(void **state)
{
    (void)state;
    double R = 0.75, W = weight(R, 2600), A = 4e8, z0;
    double mu = traj_rolling_power_mu(A, 2, R, W, &z0);
    assert_close(z0, sqrt(2 * W / A), 1e-12);
    assert_close(mu, 16.0 / 15.0 * sqrt(2 * z0 / R) / PI, 1e-12);
    for (double m = 1.5; m <= 2.01; m += 0.5) {
        traj_rolling_curve c = power_curve(A, m, 3 * pow(2 * W / A, 1 / m), 4000);
        traj_rolling_result r;
        rf_error err;
        assert_int_equal(traj_rolling_solve(&c, R, W, &r, &err), RF_OK);
        assert_close(r.mu_r, traj_rolling_power_mu(A, m, R, W, &z0), 1e-5);
        assert_close(r.sinkage, z0, 1e-5);
        double fa, fm;
        assert_true(traj_rolling_power_fit(&c, 0.2, &fa, &fm) < 1e-12);
        assert_close(fm, m, 1e-10);
        assert_close(fa, A, 1e-9);
        curve_free(&c);
    }
}

/* The force balance on the front half contact, by brute force: p(z) =
 * F'(z) / (2 pi R), the sphere's surface z = z0 - (x^2 + y^2)/(2R), x >= 0
 * ahead of the lowest point; vertical V = integral p dA, horizontal
 * H = integral p x / R dA (the surface's slope). */
static void force_balance(double A, double m, double R, double z0, double *V, double *H)
{
    const int n = 1200;
    double a = sqrt(2 * R * z0), h = 2 * a / n, v = 0, f = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n / 2; j++) {
            double y = -a + (i + 0.5) * h, x = (j + 0.5) * h, z = z0 - (x * x + y * y) / (2 * R);
            if (z <= 0)
                continue;
            double p = A * m * pow(z, m - 1) / (2 * PI * R);
            v += p * h * h, f += p * x / R * h * h;
        }
    *V = v, *H = f;
}

static void test_force_balance_second_method(void **state)
{
    (void)state;
    double R = 0.5, W = weight(R, 2600);
    for (double m = 1; m <= 2.51; m += 0.75) {
        double A = m == 1 ? 2 * PI * R * 300e3 : 5e6 * pow(10, m), z0, V, H;
        double mu = traj_rolling_power_mu(A, m, R, W, &z0);
        force_balance(A, m, R, z0, &V, &H);
        assert_close(V, W, 3e-3);      /* the front half carries the weight */
        assert_close(H / V, mu, 3e-3); /* the horizontal force is the rut's work */
    }
}

/* Stronger layer: smaller mu_r (q doubled: z0 halves, mu_r / sqrt 2); plastic
 * layer, R doubled: z0 x 4, z0/R x 2, mu_r x sqrt 2; a power law of m > 2
 * reverses the radius trend (z0/R ~ R^(2/m - 1) under A ~ R). */
static void test_trends(void **state)
{
    (void)state;
    double R = 0.5, W = weight(R, 2600);
    double mu = plastic_mu(300e3, R, W);
    assert_true(plastic_mu(600e3, R, W) < mu);
    assert_close(plastic_mu(600e3, R, W), mu / sqrt(2), 1e-12);
    assert_close(plastic_mu(300e3, 2 * R, weight(2 * R, 2600)), mu * sqrt(2), 1e-12);
    double small = traj_rolling_power_mu(1e9 * 2 * PI * R, 3, R, W, NULL);
    double big = traj_rolling_power_mu(1e9 * 2 * PI * 2 * R, 3, 2 * R, weight(2 * R, 2600), NULL);
    assert_true(big < small);
}

/* A curve that stops below 2 W is refused with both forces named. */
static void test_curve_too_short(void **state)
{
    (void)state;
    double R = 0.5, W = weight(R, 2600);
    traj_rolling_curve c = power_curve(1e6, 1, 0.01, 10); /* ends at 1e4 N < 2 W */
    traj_rolling_result r;
    rf_error err;
    assert_int_equal(traj_rolling_solve(&c, R, W, &r, &err), RF_EMODEL);
    assert_non_null(strstr(err.msg, "2 W ="));
    assert_true(isnan(traj_rolling_curve_force(&c, 0.02)));
    assert_close(traj_rolling_curve_force(&c, 0.0005), 500, 1e-12);
    curve_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constant_pressure_closed_form),
        cmocka_unit_test(test_power_law_closed_form),
        cmocka_unit_test(test_force_balance_second_method),
        cmocka_unit_test(test_trends),
        cmocka_unit_test(test_curve_too_short),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
