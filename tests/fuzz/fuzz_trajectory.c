/* fuzz_trajectory.c - libFuzzer target for the trajectory-file parser and
 * the engine behind it.
 *
 * Feeds arbitrary bytes to rf_traj_load_buffer.  A load either fails with a
 * located message "NAME:LINE: ..." or succeeds; then a few trajectories are
 * run (at most 4 samples of at most 200 events, analytic laws only, so that
 * every input finishes quickly): any crash, hang, leak or sanitizer report
 * is a bug.  Build and run: docs/user-guide.md, section "Fuzzing". */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/trajectory.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rf_traj_spec s;
    rf_error err;
    memset(&err, 0, sizeof err);
    rf_status st = rf_traj_load_buffer("fuzz.yaml", (const char *)data, size, &s, &err);
    if (st != RF_OK) {
        if (st != RF_ENOMEM && strncmp(err.msg, "fuzz.yaml:", 10) != 0) {
            fprintf(stderr, "unlocated error message: %s\n", err.msg);
            abort();
        }
        return 0;
    }
    if (s.samples > 4)
        s.samples = 4;
    if (s.record > s.samples)
        s.record = s.samples;
    if (s.max_steps > 200)
        s.max_steps = 200;
    if (s.law == RF_BOUNCE_IMPACT_MODEL)
        s.law = RF_BOUNCE_RIGID_SPHERE;
    rf_traj_ensemble e;
    if (rf_traj_run(&s, 1, &e, &err) == RF_OK) {
        rf_traj_stats t;
        if (rf_traj_stats_compute(&e, &t, &err) == RF_OK)
            rf_traj_stats_free(&t);
        rf_traj_ensemble_free(&e);
    }
    rf_traj_spec_free(&s);
    return 0;
}
