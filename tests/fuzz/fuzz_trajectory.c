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
 * invariant aborts with the file.  The same bytes are also read as a profile
 * CSV (the strict reader: vertices finite, or a located message).  Build and run: docs/user-guide.md,
 * section "Fuzzing". */
#include <math.h>
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

/* The bytes as a profile CSV (profile_csv.c): read, every vertex finite, or refused with a
 * message naming the file and, for a bad line, its number. */
static void profile_csv(const uint8_t *data, size_t size)
{
    rf_traj_material mats[2] = {{"rock", 0.4, 0.7, 30, 0, 0}, {"soil", 0.3, 0.6, 35, 0, 0}};
    rf_traj_spec s;
    memset(&s, 0, sizeof s);
    s.materials = mats, s.n_materials = 2;
    rf_error err;
    memset(&err, 0, sizeof err);
    int named;
    rf_status st = traj_csv_parse("fuzz.csv", (const char *)data, size, &s, &named, &err);
    if (st != RF_OK && st != RF_ENOMEM && strncmp(err.msg, "fuzz.csv:", 9) != 0) {
        fprintf(stderr, "unlocated CSV error message: %s\n", err.msg);
        abort();
    }
    for (size_t i = 0; st == RF_OK && i < s.n_points; i++)
        if (!isfinite(s.px[i]) || !isfinite(s.py[i]) || (i + 1 < s.n_points && s.seg_material[i] >= 2)) {
            fprintf(stderr, "CSV vertex %zu read as (%g, %g), material %zu\n", i, s.px[i], s.py[i], s.seg_material[i]);
            abort();
        }
    free(s.px), free(s.py), free(s.seg_material);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    profile_csv(data, size);
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
