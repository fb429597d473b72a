/* test_cantilever.c - the external-program model driving a real FE code:
 * CalculiX (ccx) solves examples/cantilever/beam.inp.tpl, and its tip
 * deflection is compared with beam theory at the interval bounds of every
 * alpha level of the study examples/cantilever/cantilever.yaml.
 *
 * Reference: Euler-Bernoulli, delta = F L^3 / (3 E I), I = h^4 / 12; with
 * shear (Timoshenko) delta_T = delta + F L / (k G A), G = E / (2 (1 + nu)),
 * A = h^2, k = 10 (1 + nu) / (12 + 11 nu) (Cowper 1966, rectangle).
 *
 * Tolerance 1 %.  L/h = 20, so shear adds only 0.19 % (delta_T vs delta);
 * the 40 B32 elements (expanded by ccx into C3D20R bricks, fully clamped
 * cross-section at x = 0) measured -0.17 % from Euler-Bernoulli, and a
 * mesh of 80 elements -0.06 %, i.e. discretisation error ~0.1 %.  A wrong
 * unit, a swapped E/F, a wrong I (e.g. h^4/6) or a wrong placeholder value
 * is off by far more than 1 %.  Linearity (delta E / F constant) is checked
 * to 1e-5, the 7 printed digits of ccx. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/model.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define BEAM_LENGTH 1.0   /* m */
#define BEAM_SIDE 0.05    /* m, square section */
#define POISSON 0.3
#define TOLERANCE 0.01

static double euler_bernoulli(double E, double F)
{
    double I = pow(BEAM_SIDE, 4) / 12.0;
    return F * pow(BEAM_LENGTH, 3) / (3.0 * E * I);
}

static double timoshenko(double E, double F)
{
    double G = E / (2.0 * (1.0 + POISSON));
    double k = 10.0 * (1.0 + POISSON) / (12.0 + 11.0 * POISSON);
    return euler_bernoulli(E, F) + F * BEAM_LENGTH / (k * G * BEAM_SIDE * BEAM_SIDE);
}

static void test_cantilever_against_beam_theory(void **state)
{
    (void)state;
    static const char *const params[] = {"E", "F"};
    char *argv[] = {"ccx", "-i", "beam"};
    char *src[] = {ROCKFUZZ_SOURCE_DIR "/examples/cantilever/beam.inp.tpl"};
    char *dst[] = {"beam.inp"};
    /* Same output definition as examples/cantilever/cantilever.yaml. */
    rf_external_output out[] = {{"tip_deflection", "beam.dat", "^ +81 +[-+.0-9E]+ +([-+.0-9E]+)", "m"}};
    rf_external_spec spec = {
        .argc = 3, .argv = argv, .n_templates = 1, .template_src = src, .template_dst = dst,
        .n_outputs = 1, .outputs = out, .timeout = 60, .workdir_root = NULL, .keep_workdirs = 0,
    };
    rf_model m;
    rf_error err = {0};
    rf_status st = rf_external_model_create(&spec, 2, params, &m, &err);
    if (st != RF_OK && strstr(err.msg, "not found on PATH")) {
        print_message("SKIPPED: CalculiX is not installed (%s)\n", err.msg);
        skip();
    }
    if (st != RF_OK)
        fail_msg("%s", err.msg);
    assert_string_equal(m.output_units[0], "m");

    /* tfn(p, l, r) cut at level mu: [p - (1 - mu) l, p + (1 - mu) r]. */
    const double E_peak = 2.1e11, E_spread = 1.0e10, F_peak = 1000, F_spread = 100;
    double ratio_first = 0;
    print_message("   mu   E (Pa)          F (N)   ccx (m)        Euler-B. (m)   rel.err   Timoshenko rel.err\n");
    for (int j = 0; j <= 4; j++) {
        double mu = j / 4.0;
        double E_lo = E_peak - (1 - mu) * E_spread, E_hi = E_peak + (1 - mu) * E_spread;
        double F_lo = F_peak - (1 - mu) * F_spread, F_hi = F_peak + (1 - mu) * F_spread;
        /* delta falls with E and grows with F: the cut's bounds are the two
         * corners (E_hi, F_lo) and (E_lo, F_hi), as the reduced TM finds. */
        const double corners[2][2] = {{E_hi, F_lo}, {E_lo, F_hi}};
        double bound[2];
        for (int c = 0; c < (j == 4 ? 1 : 2); c++) {
            double y;
            if (rf_model_eval(&m, corners[c], &y, &err) != RF_OK)
                fail_msg("%s", err.msg);
            double E = corners[c][0], F = corners[c][1];
            double eb = euler_bernoulli(E, F), ti = timoshenko(E, F);
            print_message("  %.2f  %.6e  %7.2f  %.6e   %.6e   %+.3f %%  %+.3f %%\n", mu, E, F, y, eb,
                          100 * (y / eb - 1), 100 * (y / ti - 1));
            assert_true(fabs(y / eb - 1) < TOLERANCE);
            assert_true(fabs(y / ti - 1) < TOLERANCE);
            double ratio = y * E / F;
            if (ratio_first == 0)
                ratio_first = ratio;
            assert_true(fabs(ratio / ratio_first - 1) < 1e-5);
            bound[c] = y;
        }
        if (j == 4)
            bound[1] = bound[0];
        double lo = euler_bernoulli(E_hi, F_lo), hi = euler_bernoulli(E_lo, F_hi);
        print_message("        cut: ccx [%.6e, %.6e]  beam theory [%.6e, %.6e]\n", bound[0], bound[1], lo, hi);
        assert_true(bound[0] <= bound[1]);
        assert_true(fabs(bound[0] / lo - 1) < TOLERANCE && fabs(bound[1] / hi - 1) < TOLERANCE);
        if (j < 4)
            assert_true(fabs((bound[1] - bound[0]) / (hi - lo) - 1) < TOLERANCE);
    }
    rf_model_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cantilever_against_beam_theory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
