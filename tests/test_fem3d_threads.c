/* test_fem3d_threads.c - the 3D solver's threaded step (docs/fem-speed.md,
 * "Threads"): every output, not only the final state, is the same bit for bit
 * on 1, 2 and 3 threads.  The sums over nodes (boulder frame, torque, energy
 * account) run in fixed chunks combined in a fixed order; 3 threads split the
 * 64 chunks unevenly, which an order that followed the threads would show.
 * Covered: the elastic half model (force, pairing and predictor in one
 * parallel region), the full model (the CM's y component is free) and a
 * plastic slope (the power sum between force and predictor).  Coarse meshes
 * and a short run: this checks logic, not accuracy. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fem3d_inputs.h" /* granite() */

typedef struct {
    rf_impact_output out;
    double vibration_energy, slope_energy, elastic_energy_work, friction_work, normal_work;
    uint64_t hash;
} result;

static void run_case(const rf_impact_input *in, int full, int threads, result *r)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 2;
    o.end_time = 0.6e-3;
    o.domain_factor = 5;
    o.threads = threads;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    o3.full_model = full;
    rf_fem_history hist;
    rf_fem3d_report rep;
    rf_error err;
    memset(r, 0, sizeof *r);
    rf_status st = rf_fem3d_impact_ex(in, &o, &o3, &r->out, &hist, &rep, &err);
    if (st != RF_OK)
        printf("# %s\n", err.msg);
    assert_int_equal(st, RF_OK);
    r->out.wall_seconds = 0;
    r->vibration_energy = hist.vibration_energy, r->slope_energy = hist.slope_energy;
    r->elastic_energy_work = hist.elastic_energy_work;
    r->friction_work = rep.friction_work, r->normal_work = rep.normal_work;
    r->hash = rep.state_hash;
    rf_fem_history_free(&hist);
    rf_fem3d_report_free(&rep);
}

/* 1, 2 and 3 threads give the same result record, bit for bit. */
static void check_threads(const rf_impact_input *in, int full, const char *what)
{
    result r[3];
    for (int t = 0; t < 3; t++)
        run_case(in, full, t + 1, &r[t]);
    printf("# %s: hash %016llx, R_n %.12f, energy error %.3e\n", what, (unsigned long long)r[0].hash, r[0].out.R_n,
           r[0].out.energy_error);
    assert_true(r[0].out.steps > 10);
    for (int t = 1; t < 3; t++)
        assert_memory_equal(&r[0], &r[t], sizeof r[0]);
}

static void test_elastic_half(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 45, 0.6);
    check_threads(&in, 0, "elastic, half model");
}

static void test_elastic_full(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 30, 0.3);
    check_threads(&in, 1, "elastic, full model");
}

static void test_plastic_slope(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 45, 0.5);
    in.slope_material = RF_MATERIAL_VON_MISES;
    in.slope_yield = 200e6;
    check_threads(&in, 0, "von Mises slope, half model");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_elastic_half),
        cmocka_unit_test(test_elastic_full),
        cmocka_unit_test(test_plastic_slope),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
