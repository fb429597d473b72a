/* test_traj_util.h - the trajectory invariants (src/trajectory/traj_invariants.c)
 * asserted on recorded trajectories: include after <cmocka.h>.  Every
 * trajectory test that simulates calls one of these on what it ran. */
#ifndef ROCKFUZZ_TEST_TRAJ_UTIL_H
#define ROCKFUZZ_TEST_TRAJ_UTIL_H

#include <stdlib.h>
#include <string.h>

#include "rockfuzz/trajectory.h"
#include "trajectory/traj_internal.h"

/* One trajectory simulated with the values of `spec`. */
static inline void assert_traj_invariants(const rf_traj_spec *spec, const rf_traj_result *res)
{
    rf_error err;
    if (traj_check_invariants(spec, res, &err) != RF_OK)
        fail_msg("trajectory invariant broken: %s", err.msg);
}

/* The recorded trajectories of an ensemble of `spec`.  The energy check needs
 * each sample's gravity and block, so those must not be random here. */
static inline void assert_ensemble_invariants(const rf_traj_spec *spec, const rf_traj_ensemble *ens)
{
    for (size_t i = 0; i < spec->n_random; i++)
        if (!strcmp(spec->random[i].path, "gravity") || !strncmp(spec->random[i].path, "block.", 6))
            fail_msg("%s is random: the invariants need each sample's value", spec->random[i].path);
    for (size_t i = 0; i < ens->n_recorded; i++) {
        rf_error err;
        if (traj_check_invariants(spec, &ens->recorded[i], &err) != RF_OK)
            fail_msg("recorded trajectory %zu: invariant broken: %s", i, err.msg);
    }
}

/* One trajectory run from a YAML text, its impacts and events recorded (the
 * arrays grow as needed) and its invariants asserted; free with traj_case_free. */
typedef struct {
    rf_traj_spec spec;
    rf_traj_world *world;
    rf_traj_result res;
    rf_traj_crossing cross[4];
} traj_case;

static inline void traj_case_run(traj_case *c, const char *yaml)
{
    rf_error err;
    memset(c, 0, sizeof *c);
    if (rf_traj_load_buffer("case.yaml", yaml, strlen(yaml), &c->spec, &err) != RF_OK)
        fail_msg("load: %s", err.msg);
    if (rf_traj_world_create(&c->spec, &c->world, &err) != RF_OK)
        fail_msg("world: %s", err.msg);
    c->res.crossings = c->cross;
    c->res.impacts = malloc(16 * sizeof *c->res.impacts);
    c->res.impacts_cap = 16;
    c->res.events = malloc(16 * sizeof *c->res.events);
    c->res.events_cap = 16;
    assert_int_equal(rf_traj_simulate(c->world, &c->spec, c->spec.seed, 0, &c->res, &err), RF_OK);
    assert_traj_invariants(&c->spec, &c->res);
}

static inline void traj_case_free(traj_case *c)
{
    free(c->res.impacts);
    free(c->res.events);
    rf_traj_world_free(c->world);
    rf_traj_spec_free(&c->spec);
}

#endif
