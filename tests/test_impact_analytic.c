/* test_impact_analytic.c - Hertz, Hunter and rigid-body impact against the
 * hand-derived numbers of impact_refs.md (sec. 1.2, 2.3, 4.1), scaling laws,
 * the energy identity of R_ke, and input validation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "rockfuzz/impact.h"

#define DEG (3.14159265358979323846 / 180.0)

static void assert_rel(double got, double want, double tol, const char *what)
{
    double rel = fabs(got - want) / fabs(want);
    if (!(rel <= tol))
        fail_msg("%s: got %.8g, want %.8g (relative error %.3g > %.3g)", what, got, want, rel, tol);
}

static void assert_abs(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: got %.8g, want %.8g (|error| %.3g > %.3g)", what, got, want,
                 fabs(got - want), tol);
}

static rf_impact_input granite(double v)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = v;
    return in;
}

static void test_defaults(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    assert_true(in.radius == 1.0 && in.boulder_E == 68.2e9 && in.slope_E == 68.2e9);
    assert_true(in.boulder_density == 2600.0 && in.boulder_poisson == 0.25);
    assert_true(in.velocity == 10.0 && in.slope_angle == 0.0 && in.friction == 0.0);
    assert_true(in.horizontal_axis == 0.0);
    rf_error err = {0};
    assert_int_equal(rf_impact_input_validate(&in, &err), RF_OK);
    /* impact_refs.md header: m = 10 890.85 kg, E* = 36.373 GPa */
    assert_rel(rf_impact_mass(&in), 10890.85, 1e-6, "mass");
    assert_rel(rf_impact_effective_modulus(&in), 36.373e9, 1e-4, "E*");
    assert_rel(rf_impact_moment_of_inertia(&in), 0.4 * 10890.85, 1e-6, "I");
    assert_true(rf_impact_contact_curvature_radius(&in) == 1.0);
}

/* impact_refs.md sec. 1.2: granite sphere r0 = 1 m on granite half-space. */
static void test_hertz_table(void **state)
{
    (void)state;
    static const struct { double v, delta, F, a, tc; } row[] = {
        {1.0, 2.3950e-3, 5.6842e6, 0.04894, 7.0491e-3},
        {10.0, 1.51112e-2, 9.0089e7, 0.12293, 4.4477e-3},
        {30.0, 3.63913e-2, 3.3668e8, 0.19077, 3.5703e-3},
    };
    for (size_t i = 0; i < 3; i++) {
        rf_impact_input in = granite(row[i].v);
        rf_impact_output out;
        rf_error err = {0};
        assert_int_equal(rf_impact_hertz(&in, &out, &err), RF_OK);
        assert_rel(out.compression_max, row[i].delta, 1e-3, "delta_max");
        assert_rel(out.contact_force_max, row[i].F, 1e-3, "F_max");
        assert_rel(out.contact_radius, row[i].a, 1e-3, "a_max");
        assert_rel(out.contact_duration, row[i].tc, 1e-3, "t_c");
        /* SYSTEM.md's fine-zone formula equals sqrt(R delta_max) */
        assert_rel(rf_hertz_contact_radius(&in), out.contact_radius, 1e-12, "a formulas agree");
        /* t_c = 2.94328 delta/V and the 2.86827 closed form */
        assert_rel(out.contact_duration * row[i].v / out.compression_max, 2.94328, 2e-6,
                   "duration factor");
        double m = rf_impact_mass(&in), Es = rf_impact_effective_modulus(&in);
        assert_rel(out.contact_duration, 2.86827 * pow(m * m / (Es * Es * row[i].v), 0.2), 2e-6,
                   "t_c closed form");
        assert_true(out.R_n == 1.0 && out.R_ke == 1.0 && isnan(out.R_t));
        assert_true(out.energy_error == 0.0 && out.nodes == 0.0);
    }
}

static void test_hertz_scaling(void **state)
{
    (void)state;
    rf_impact_output o1, o2;
    rf_error err = {0};
    for (double v = 1.0; v <= 30.0; v *= 3.0) {
        rf_impact_input a = granite(v), b = granite(2.0 * v);
        assert_int_equal(rf_impact_hertz(&a, &o1, &err), RF_OK);
        assert_int_equal(rf_impact_hertz(&b, &o2, &err), RF_OK);
        assert_rel(o2.compression_max / o1.compression_max, pow(2.0, 0.8), 1e-12, "delta ~ V^4/5");
        assert_rel(o2.contact_force_max / o1.contact_force_max, pow(2.0, 1.2), 1e-12, "F ~ V^6/5");
        assert_rel(o2.contact_radius / o1.contact_radius, pow(2.0, 0.4), 1e-12, "a ~ V^2/5");
        assert_rel(o2.contact_duration / o1.contact_duration, pow(2.0, -0.2), 1e-12,
                   "t_c ~ V^-1/5");
    }
    /* Inclined slope: only the normal component counts. */
    rf_impact_input tilted = granite(10.0), normal = granite(10.0 * cos(30 * DEG));
    tilted.slope_angle = 30 * DEG;
    assert_int_equal(rf_impact_hertz(&tilted, &o1, &err), RF_OK);
    assert_int_equal(rf_impact_hertz(&normal, &o2, &err), RF_OK);
    assert_rel(o1.contact_force_max, o2.contact_force_max, 1e-12, "F uses v cos(alpha)");
    assert_rel(o1.R_t, 1.0, 1e-15, "frictionless R_t");
    assert_rel(o1.R_ke, 1.0, 1e-15, "frictionless elastic R_ke");
}

/* impact_refs.md sec. 2.3. */
static void test_hunter_table(void **state)
{
    (void)state;
    static const double v[3] = {1.0, 10.0, 30.0};
    static const double A[3] = {RF_HUNTER_A_JOHNSON, RF_HUNTER_A_EXACT_PULSE, RF_HUNTER_A_HALF_SINE};
    static const double lambda[3][3] = {{0.00619, 0.00661, 0.00696},
                                        {0.02463, 0.02632, 0.02772},
                                        {0.04761, 0.05088, 0.05359}};
    static const double e[3][3] = {{0.99690, 0.99669, 0.99651},
                                   {0.98761, 0.98675, 0.98604},
                                   {0.97591, 0.97423, 0.97284}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            rf_impact_input in = granite(v[i]);
            rf_impact_output out;
            rf_error err = {0};
            /* table rounded to 5 decimals; the band constants A to 4 digits */
            assert_abs(rf_hunter_loss(&in, A[j]), lambda[i][j],
                       6e-6 + (j ? 5e-4 * lambda[i][j] : 0.0), "lambda");
            assert_int_equal(rf_impact_hunter_A(&in, A[j], &out, &err), RF_OK);
            assert_abs(out.R_n, e[i][j], j ? 2e-5 : 6e-6, "e_n");
            assert_rel(out.R_ke, out.R_n * out.R_n, 1e-12, "R_ke = e^2");
            if (j == 0) {
                rf_impact_output o2;
                assert_int_equal(rf_impact_hunter(&in, &o2, &err), RF_OK);
                assert_true(o2.R_n == out.R_n);
                /* Hertz quantities unchanged */
                assert_int_equal(rf_impact_hertz(&in, &o2, &err), RF_OK);
                assert_true(o2.contact_force_max == out.contact_force_max);
            }
        }
}

/* impact_refs.md sec. 4.1, V = 10 m/s, R = 1 m, e_n = 0.98. */
static void test_rigid_table(void **state)
{
    (void)state;
    static const struct {
        double slope, mu;
        int slide;
        double vn, vt, Rt, omega, RE, rot_share;
    } row[] = {
        {30, 0.0, 0, 8.487, 5.000, 1.000, 0.000, 0.970, 0.0},
        {30, 0.2, 0, 8.487, 3.571, 0.714, 3.571, 0.899, 0.057},
        {30, 0.6, 0, 8.487, 3.571, 0.714, 3.571, 0.899, 0.057},
        {30, 1.0, 0, 8.487, 3.571, 0.714, 3.571, 0.899, 0.057},
        {45, 0.0, 0, 6.930, 7.071, 1.000, 0.000, 0.980, 0.0},
        {45, 0.2, 0, 6.930, 5.051, 0.714, 5.051, 0.837, 0.122},
        {45, 0.6, 0, 6.930, 5.051, 0.714, 5.051, 0.837, 0.122},
        {45, 1.0, 0, 6.930, 5.051, 0.714, 5.051, 0.837, 0.122},
        {60, 0.0, 0, 4.900, 8.660, 1.000, 0.000, 0.990, 0.0},
        {60, 0.2, 1, 4.900, 6.680, 0.771, 4.950, 0.784, 0.125},
        {60, 0.6, 0, 4.900, 6.186, 0.714, 6.186, 0.776, 0.197},
        {60, 1.0, 0, 4.900, 6.186, 0.714, 6.186, 0.776, 0.197},
    };
    for (size_t i = 0; i < sizeof row / sizeof row[0]; i++) {
        rf_impact_input in = granite(10.0);
        in.slope_angle = row[i].slope * DEG;
        in.friction = row[i].mu;
        rf_impact_output out;
        rf_error err = {0};
        assert_int_equal(rf_impact_rigid(&in, 0.98, &out, &err), RF_OK);
        assert_abs(out.v_n_after, row[i].vn, 6e-4, "v_n'");
        assert_abs(out.v_t_after, row[i].vt, 6e-4, "v_t'");
        assert_abs(out.R_t, row[i].Rt, 6e-4, "R_t");
        assert_abs(out.omega_after, row[i].omega, 6e-4, "omega'");
        assert_abs(out.R_ke, row[i].RE, 6e-4, "R_E");
        assert_abs(out.R_n, 0.98, 1e-15, "R_n");
        double rot = 0.4 * out.omega_after * out.omega_after / 100.0 / out.R_ke;
        assert_abs(rot, row[i].rot_share, 6e-4, "rotational share");
        /* regime: rolling ends with zero slip at the contact point */
        double slip = out.v_t_after - out.omega_after * in.radius;
        if (row[i].mu > 0 && !row[i].slide)
            assert_abs(slip, 0.0, 1e-12, "no slip after rolling");
        if (row[i].slide)
            assert_true(slip > 1e-3);
        /* rigid model leaves the deformation outputs undefined */
        assert_true(isnan(out.contact_force_max) && isnan(out.compression_max));
        assert_true(isnan(out.contact_duration) && isnan(out.contact_radius));
    }
    /* sliding thresholds: mu* = tan(alpha) / (3.5 (1 + e_n)) */
    static const double slope[3] = {30, 45, 60}, mu_star[3] = {0.083, 0.144, 0.250};
    for (int j = 0; j < 3; j++) {
        double ms = tan(slope[j] * DEG) / (3.5 * 1.98);
        assert_abs(ms, mu_star[j], 6e-4, "threshold");
        rf_impact_input in = granite(10.0);
        rf_impact_output below, above;
        rf_error err = {0};
        in.slope_angle = slope[j] * DEG;
        in.friction = ms * 0.999;
        assert_int_equal(rf_impact_rigid(&in, 0.98, &below, &err), RF_OK);
        in.friction = ms * 1.001;
        assert_int_equal(rf_impact_rigid(&in, 0.98, &above, &err), RF_OK);
        assert_true(below.R_t > 5.0 / 7.0 + 1e-6);
        assert_abs(above.R_t, 5.0 / 7.0, 1e-12, "rolling R_t");
    }
}

static void test_energy_identity(void **state)
{
    (void)state;
    for (int a = 0; a < 80; a += 7)
        for (double mu = 0.0; mu <= 1.0; mu += 0.15) {
            rf_impact_input in = granite(3.0 + a * 0.2);
            in.radius = 0.3 + 0.01 * a;
            in.slope_angle = a * DEG;
            in.friction = mu;
            rf_impact_output out;
            rf_error err = {0};
            assert_int_equal(rf_impact_hunter(&in, &out, &err), RF_OK);
            double V = in.velocity, vn = V * cos(in.slope_angle), vt = V * sin(in.slope_angle);
            double Im = rf_impact_moment_of_inertia(&in) / rf_impact_mass(&in);
            double ke = pow(out.R_n * vn, 2) + pow(out.v_t_after, 2) + Im * pow(out.omega_after, 2);
            assert_rel(out.R_ke, ke / (V * V), 1e-12, "R_ke identity");
            if (vt > 0) {
                assert_rel(out.v_t_after, out.R_t * vt, 1e-12, "R_t definition");
                assert_true(out.R_ke <= 1.0 + 1e-15); /* friction never adds energy */
            } else {
                assert_true(isnan(out.R_t));
            }
            assert_rel(-out.v_n_after / out.v_n_before, out.R_n, 1e-12, "R_n definition");
        }
}

static void test_spheroid(void **state)
{
    (void)state;
    rf_impact_input in = granite(10.0);
    double m0 = rf_impact_mass(&in);
    in.horizontal_axis = 1.1;
    double d = 1.0 / (1.1 * 1.1);
    assert_rel(rf_impact_vertical_semi_axis(&in), d, 1e-14, "d = r0^3/c^2");
    assert_rel(rf_impact_mass(&in), m0, 1e-14, "constant volume");
    assert_rel(rf_impact_contact_curvature_radius(&in), 1.1 * 1.1 / d, 1e-14, "pole radius");
    assert_rel(rf_impact_moment_of_inertia(&in), m0 * (1.1 * 1.1 + d * d) / 5, 1e-14, "I");
    rf_impact_output sph, flat;
    rf_error err = {0};
    rf_impact_input s = granite(10.0);
    assert_int_equal(rf_impact_hertz(&s, &sph, &err), RF_OK);
    assert_int_equal(rf_impact_hertz(&in, &flat, &err), RF_OK);
    /* flatter pole (R = c^4/r0^3 = 1.4641): stiffer, shorter contact */
    assert_rel(flat.compression_max / sph.compression_max, pow(1.4641, -0.2), 1e-10, "delta ~ R^-1/5");
    assert_true(flat.contact_force_max > sph.contact_force_max);
    /* explicit d */
    in.vertical_axis = 0.5;
    assert_rel(rf_impact_vertical_semi_axis(&in), 0.5, 0, "explicit d");
    /* spheroid on an inclined slope is not an analytic case */
    in.vertical_axis = 0.0;
    in.slope_angle = 30 * DEG;
    assert_int_equal(rf_impact_hertz(&in, &flat, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "horizontal_axis"));
    assert_int_equal(rf_impact_rigid(&in, 0.98, &flat, &err), RF_EINVAL);
}

static void expect_invalid(rf_impact_input in, const char *field, const char *text)
{
    rf_error err = {0};
    rf_impact_output out;
    assert_int_equal(rf_impact_input_validate(&in, &err), RF_EINVAL);
    if (!strstr(err.msg, text))
        fail_msg("message '%s' lacks '%s'", err.msg, text);
    assert_string_equal(rf_impact_input_first_invalid(&in), field);
    assert_int_equal(rf_impact_hertz(&in, &out, &err), RF_EINVAL);
    assert_int_equal(rf_impact_hunter(&in, &out, &err), RF_EINVAL);
    assert_int_equal(rf_impact_rigid(&in, 0.9, &out, &err), RF_EINVAL);
    assert_true(isnan(out.R_n));
}

static void test_validation(void **state)
{
    (void)state;
    rf_impact_input in = granite(10.0);
    assert_null(rf_impact_input_first_invalid(&in));
    in.boulder_poisson = 0.5;
    expect_invalid(in, "boulder_poisson",
                   "boulder_poisson = 0.5: Poisson's ratio must lie in (-1, 0.5)");
    in = granite(10.0);
    in.slope_poisson = -1.0;
    expect_invalid(in, "slope_poisson", "slope_poisson = -1");
    in = granite(10.0);
    in.slope_E = -5e9;
    expect_invalid(in, "slope_E", "slope_E = -5e+09");
    in = granite(10.0);
    in.boulder_E = NAN;
    expect_invalid(in, "boulder_E", "boulder_E = nan");
    in = granite(10.0);
    in.boulder_density = 0.0;
    expect_invalid(in, "boulder_density", "boulder_density = 0");
    in = granite(10.0);
    in.radius = INFINITY;
    expect_invalid(in, "radius", "radius = inf");
    in = granite(0.0);
    expect_invalid(in, "velocity", "velocity = 0");
    in = granite(10.0);
    in.slope_angle = 90 * DEG;
    expect_invalid(in, "slope_angle", "(90 deg)");
    in = granite(10.0);
    in.friction = -0.1;
    expect_invalid(in, "friction", "friction = -0.1");
    in = granite(10.0);
    in.horizontal_axis = -1.0;
    expect_invalid(in, "horizontal_axis", "horizontal_axis = -1");
    in = granite(10.0);
    in.vertical_axis = 0.8;
    expect_invalid(in, "vertical_axis", "needs horizontal_axis > 0");
    /* bad e_n */
    in = granite(10.0);
    rf_impact_output out;
    rf_error err = {0};
    assert_int_equal(rf_impact_rigid(&in, 1.5, &out, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "e_n = 1.5"));
    /* Hunter outside its range */
    in.velocity = 1e7;
    assert_int_equal(rf_impact_hunter(&in, &out, &err), RF_EMODEL);
    assert_non_null(strstr(err.msg, "lambda"));
}

/* Dundurs' beta: zero for identical bodies, odd under exchange of the
 * bodies, and a rigid first body is the limit of an ever stiffer one:
 * (1 - 2 nu) / (2 (1 - nu)) = 1/3 at nu = 0.25 (Johnson 1985, ch. 5). */
static void test_dundurs_beta(void **state)
{
    (void)state;
    assert_true(rf_dundurs_beta(68.2e9, 0.25, 68.2e9, 0.25) == 0.0);
    const double b = rf_dundurs_beta(68.2e9, 0.25, 30e9, 0.3);
    assert_true(b > 0 && fabs(b + rf_dundurs_beta(30e9, 0.3, 68.2e9, 0.25)) < 1e-15);
    assert_true(fabs(rf_dundurs_beta(INFINITY, 0.2, 68.2e9, 0.25) - 1.0 / 3.0) < 1e-15);
    assert_true(fabs(rf_dundurs_beta(68.2e15, 0.2, 68.2e9, 0.25) - 1.0 / 3.0) < 1e-5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),       cmocka_unit_test(test_hertz_table),
        cmocka_unit_test(test_hertz_scaling),  cmocka_unit_test(test_hunter_table),
        cmocka_unit_test(test_rigid_table),    cmocka_unit_test(test_energy_identity),
        cmocka_unit_test(test_spheroid),       cmocka_unit_test(test_validation),
        cmocka_unit_test(test_dundurs_beta),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
