/* fuzz_trajectory.c - libFuzzer target for the trajectory-file parser and
 * the engine behind it.
 *
 * Feeds arbitrary bytes to rf_traj_load_buffer.  A load either fails with a
 * located message "NAME:LINE: ..." or succeeds; then a few trajectories are
 * run (at most 4 samples of at most 200 events, analytic laws only, so that
 * every input finishes quickly): any crash, hang, leak or sanitizer report
 * is a bug.  The crisp trajectory of a file that loads is also run with its
 * events recorded and must keep the invariants (never inside the ground,
 * energy never gained: traj_invariants.c).  The same bytes also drive the
 * profile generator of tests/traj_gen.h (slopes, vertical steps, pits,
 * V-notches), whose trajectory must keep the invariants too; a broken
 * invariant aborts with the file.  Build and run: docs/user-guide.md,
 * section "Fuzzing". */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/trajectory.h"
#include "trajectory/traj_internal.h"
#include "../traj_gen.h"

/* The bytes as a generated profile: it always loads and keeps the invariants. */
static void generated(const uint8_t *data, size_t size)
{
    char yaml[8192];
    size_t len = traj_gen_yaml(data, size, yaml, sizeof yaml);
    rf_error err;
    int st = traj_gen_run(yaml, len, size, &err);
    if (st != 0 && !(st > 0 && err.code == RF_ENOMEM)) {
        fprintf(stderr, "generated file %s: %s\n%s\n", st < 0 ? "does not load" : "breaks an invariant", err.msg, yaml);
        abort();
    }
}

/* The spec's own values, one trajectory with its events: the invariants hold. */
static void crisp(const rf_traj_spec *s)
{
    rf_error err;
    rf_traj_world *w = NULL;
    rf_traj_crossing cross[1];
    rf_traj_result r;
    memset(&r, 0, sizeof r);
    r.crossings = s->n_collectors ? calloc(s->n_collectors, sizeof *r.crossings) : cross;
    r.events = malloc(16 * sizeof *r.events), r.events_cap = 16;
    if (r.crossings && r.events && rf_traj_spec_validate(s, &err) == RF_OK && rf_traj_world_create(s, &w, &err) == RF_OK &&
        rf_traj_simulate(w, s, s->seed, 0, &r, &err) == RF_OK && traj_check_invariants(s, &r, &err) != RF_OK) {
        fprintf(stderr, "invariant broken: %s\n", err.msg);
        abort();
    }
    if (r.crossings != cross)
        free(r.crossings);
    free(r.events);
    rf_traj_world_free(w);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    generated(data, size);
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
    crisp(&s);
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
