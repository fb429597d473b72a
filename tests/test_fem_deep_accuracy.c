/* test_fem_deep_accuracy.c - the deep case of tests/test_fem_deep.c at
 * a/h = 4, the mesh its energy closure needs: the contact's loss (each soil
 * node caught by the block loses its relative velocity, the whole energy
 * error here) is 9.2e-3 KE0 at a/h = 2 and 2.9e-3 at a/h = 4.  Labelled
 * `accuracy`: the sanitizer half leaves it out; the same code paths run in
 * tests/test_fem_deep.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem_deep_inputs.h"

static void test_deep_energy_closure(void **state)
{
    (void)state;
    rf_impact_output out;
    double overlap, sag;
    deep_run(4, &out, &overlap, &sag);
    assert_true(out.penetration_max > 0.55);
    assert_true(overlap < sag);
    assert_true(out.energy_error < 5e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_deep_energy_closure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
