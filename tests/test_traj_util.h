/* test_traj_util.h - the trajectory invariants (src/trajectory/traj_invariants.c)
 * asserted on recorded trajectories: include after <cmocka.h>.  Every
 * trajectory test that simulates calls one of these on what it ran. */
#ifndef ROCKFUZZ_TEST_TRAJ_UTIL_H
#define ROCKFUZZ_TEST_TRAJ_UTIL_H

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

#endif
