/* test_fem_large_accuracy.c - the axisymmetric large-deformation model
 * against the small-strain one at small speed (1 m/s, a/h = 3; labelled
 * `accuracy`: the sanitizer half of scripts/test.sh leaves it out; the
 * large-deformation elastic path runs there in tests/test_fem_plastic.c's
 * coarse test_huge_strength_never_yields and test_layer_logic). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem_plastic_inputs.h" /* axi_options */
#include "rockfuzz/fem.h"

/* Elastic granite on granite at 1 m/s: the contact strain delta_max / a
 * (= a / R in Hertz) is 5e-2, the material strain p0 / E 2e-2.  The geometric
 * terms the small-strain model drops change the force by a relative amount
 * of that order, and the loss 1 - R_n (waves radiated into the slope) by a
 * relative amount of that order too. */
static void test_small_velocity_agrees(void **state)
{
    (void)state;
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = 1;
    rf_impact_output s, l;
    rf_error err = {0};
    rf_fem_options os = axi_options(3, RF_FEM_KINEMATICS_AUTO), ol = axi_options(3, RF_FEM_LARGE_DEFORMATION);
    assert_int_equal(rf_fem_large_deformation(&os, &in), 0); /* auto: elastic = small strain */
    assert_int_equal(rf_fem_impact(&in, &os, &s, NULL, &err), RF_OK);
    assert_int_equal(rf_fem_impact(&in, &ol, &l, NULL, &err), RF_OK);
    const double strain = s.compression_max / s.contact_radius;
    printf("1 m/s elastic: R_n small strain %.8f, large deformation %.8f (diff %.2e; contact strain %.2e); "
           "F_max ratio %.6f; energy error %.1e / %.1e\n", s.R_n, l.R_n, fabs(l.R_n - s.R_n), strain,
           l.contact_force_max / s.contact_force_max, s.energy_error, l.energy_error);
    assert_true(fabs(l.R_n - s.R_n) < strain * (1 - s.R_n));
    assert_true(fabs(l.contact_force_max / s.contact_force_max - 1) < strain);
    assert_true(l.energy_error < 1e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_velocity_agrees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
