/* test_terrain_parts.c - a terrain run in parts (rf_terrain_run_part,
 * rf_terrain_part_pack, rf_terrain_part_join: what MPI ranks exchange,
 * src/cli/traj_ranks.c), without MPI: the parts [0, 37), [37, 37) (empty),
 * [37, 90), [90, 161) of a Latin hypercube run with random inputs, packed and
 * joined in order, give the whole run (rf_terrain_run) bit for bit: every
 * per-sample array, every recorded trajectory (60 recorded: they span two
 * parts) with its impacts, events and crossings, and every hazard band.  A
 * part joined out of order, cut short (inside its header, in its samples,
 * by its last byte) or of another build (magic) is refused with the reason;
 * the first ones leave the ensemble as it was (the right part still joins),
 * the last one freeable. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "terrain_fixture.h"
#include "trajectory/terrain_internal.h"

#define NX 61
#define NY 81
#define CELL 2.0
#define SAMPLES 161

static char dir[] = "/tmp/rf_terrain_parts_XXXXXX";

/* A slope falling to the south with bumps across, a flatter runout. */
static double ground(double x, double y)
{
    double z = y > 100 ? 40 + 0.7 * (y - 100) : 20 + 0.2 * y;
    return z + 0.6 * sin(x / 7.0) * cos(y / 9.0);
}

static const terrain_fixture terrain = {NX, NY, CELL, ground, 100};

static void load(rf_traj_spec *s)
{
    char yaml[4096];
    snprintf(yaml, sizeof yaml,
             "name: parts\n"
             "terrain: {dem: %s/dem.asc, materials: {raster: %s/classes.asc, classes: {1: rock, 2: talus}}}\n"
             "materials:\n"
             "  rock:  {R_n: {uniform: [0.3, 0.6]}, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1, "
             "roughness: 5}\n"
             "  talus: {R_n: 0.35, R_t: 0.75, friction_angle: 35, rolling_resistance: {uniform: [0.15, 0.35]}, "
             "roughness: 10}\n"
             "block: {shape: sphere, radius: {uniform: [0.3, 0.6]}, density: 2600}\n"
             "release: {lines: [[[40, 150], [80, 150]]], height: {uniform: [1, 3]}, velocity: [0, 0, 0]}\n"
             "bounce: {law: constant}\n"
             "barriers: [{name: fence, line: [[10, 60], [110, 60]], height: 2, capacity: 1.0e5}]\n"
             "rasters: {cell: 4, statistics: [passages, reach_probability, deposits, energy_p95, height_p95]}\n"
             "samples: %d\nseed: 5\nsampling: lhs\nrecord: 60\n",
             dir, dir, SAMPLES);
    fixture_load(dir, "parts.yaml", yaml, s);
}

static int setup(void **state)
{
    (void)state;
    return fixture_setup(dir, &terrain);
}

static int teardown(void **state)
{
    (void)state;
    fixture_teardown(dir, "parts.yaml");
    return 0;
}

static void same_result(const rf_terrain_result *a, const rf_terrain_result *b, size_t nc)
{
    assert_int_equal(a->state, b->state);
    assert_memory_equal(a->start, b->start, sizeof a->start);
    assert_memory_equal(a->end, b->end, sizeof a->end);
    double da[4] = {a->t_end, a->runout, a->reach_angle, a->rebound_height};
    double db[4] = {b->t_end, b->runout, b->reach_angle, b->rebound_height};
    assert_memory_equal(da, db, sizeof da);
    assert_int_equal(a->n_impacts, b->n_impacts);
    assert_int_equal(a->n_steps, b->n_steps);
    assert_int_equal(a->n_events, b->n_events);
    assert_memory_equal(a->crossings, b->crossings, nc * sizeof *a->crossings);
    assert_memory_equal(a->impacts, b->impacts, a->n_impacts * sizeof *a->impacts);
    assert_memory_equal(a->events, b->events, a->n_events * sizeof *a->events);
}

static void same_run(const rf_traj_spec *s, const rf_traj_ensemble *a, const rf_traj_ensemble *b)
{
    size_t N = a->samples, nc = a->n_collectors;
    assert_int_equal(b->samples, N);
    assert_int_equal(b->n_collectors, nc);
    assert_memory_equal(a->state, b->state, N);
    assert_memory_equal(a->runout_x, b->runout_x, N * sizeof(double));
    assert_memory_equal(a->rebound_height, b->rebound_height, N * sizeof(double));
    assert_memory_equal(a->crossings, b->crossings, N * nc * sizeof *a->crossings);
    const rf_terrain_samples *p = a->terrain, *q = b->terrain;
    assert_memory_equal(p->start, q->start, 3 * N * sizeof(double));
    assert_memory_equal(p->end, q->end, 3 * N * sizeof(double));
    assert_memory_equal(p->runout, q->runout, N * sizeof(double));
    assert_memory_equal(p->reach_angle, q->reach_angle, N * sizeof(double));
    assert_int_equal(p->n_recorded, q->n_recorded);
    for (size_t i = 0; i < p->n_recorded; i++)
        same_result(&p->recorded[i], &q->recorded[i], nc);
    terrain_band *ba, *bb;
    size_t na, nb, nx, ny;
    double x0, y0, cell, passages = 0;
    rf_error err;
    assert_int_equal(terrain_hazard_bands(p->hazard, s, N, &ba, &na, &err), RF_OK);
    assert_int_equal(terrain_hazard_bands(q->hazard, s, N, &bb, &nb, &err), RF_OK);
    terrain_hazard_grid(p->hazard, &nx, &ny, &x0, &y0, &cell);
    assert_int_equal(na, nb);
    for (size_t k = 0; k < na; k++) {
        assert_string_equal(ba[k].name, bb[k].name);
        assert_memory_equal(ba[k].data, bb[k].data, nx * ny * sizeof(float));
        for (size_t c = 0; !strcmp(ba[k].name, "passages") && c < nx * ny; c++)
            passages += ba[k].data[c];
    }
    assert_true(passages >= (double)N); /* every block passes its release cell at least */
    terrain_bands_free(ba, na);
    terrain_bands_free(bb, nb);
}

static void run_part(const rf_traj_spec *s, size_t first, size_t end, rf_traj_ensemble *e)
{
    rf_error err;
    if (rf_terrain_run_part(s, first, end, 2, NULL, NULL, e, &err) != RF_OK)
        fail_msg("[%zu, %zu): %s", first, end, err.msg);
    assert_int_equal(e->samples, end - first);
}

/* The part [first, end) packed (its ensemble freed). */
static void *packed(const rf_traj_spec *s, size_t first, size_t end, size_t *bytes)
{
    rf_traj_ensemble e;
    run_part(s, first, end, &e);
    void *buf;
    rf_error err;
    assert_int_equal(rf_terrain_part_pack(&e, first, &buf, bytes, &err), RF_OK);
    rf_traj_ensemble_free(&e);
    return buf;
}

static void test_parts_join_to_the_whole_run(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(&s);
    rf_traj_ensemble whole, joined;
    rf_error err;
    assert_int_equal(rf_terrain_run(&s, 1, NULL, NULL, &whole, &err), RF_OK);
    assert_int_equal(whole.terrain->n_recorded, 60);
    run_part(&s, 0, 37, &joined);
    assert_int_equal(joined.terrain->n_recorded, 37);
    const size_t cut[4] = {37, 37, 90, SAMPLES};
    for (int k = 0; k < 3; k++) {
        size_t bytes;
        void *buf = packed(&s, cut[k], cut[k + 1], &bytes);
        if (rf_terrain_part_join(&joined, buf, bytes, &err) != RF_OK)
            fail_msg("part [%zu, %zu): %s", cut[k], cut[k + 1], err.msg);
        free(buf);
        assert_int_equal(joined.samples, cut[k + 1]);
    }
    same_run(&s, &whole, &joined);
    rf_traj_ensemble_free(&whole);
    rf_traj_ensemble_free(&joined);
    rf_traj_spec_free(&s);
}

static void refused(rf_traj_ensemble *e, const void *buf, size_t bytes, const char *why)
{
    rf_error err = {0};
    size_t before = e->samples;
    assert_int_equal(rf_terrain_part_join(e, buf, bytes, &err), RF_EINVAL);
    if (!strstr(err.msg, why))
        fail_msg("expected '%s' in: %s", why, err.msg);
    assert_int_equal(e->samples, before);
}

static void test_bad_parts_are_refused(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(&s);
    rf_traj_ensemble e;
    run_part(&s, 0, 40, &e);
    size_t bytes, bytes3;
    unsigned char *two = packed(&s, 40, 100, &bytes), *three = packed(&s, 100, SAMPLES, &bytes3);
    refused(&e, three, bytes3, "joined in order");
    refused(&e, two, 40, "cut short");            /* inside the header */
    refused(&e, two, 100, "cut short");           /* the samples */
    unsigned char *other = malloc(bytes);
    assert_non_null(other);
    memcpy(other, two, bytes);
    other[0] ^= 1;
    refused(&e, other, bytes, "another rockfuzz build");
    free(other);
    rf_error err;
    assert_int_equal(rf_terrain_part_join(&e, two, bytes, &err), RF_OK); /* the real one still joins */
    assert_int_equal(e.samples, 100);
    refused(&e, three, bytes3 - 1, "rasters"); /* the last raster word: after it, e is only to be freed */
    free(two);
    free(three);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parts_join_to_the_whole_run),
        cmocka_unit_test(test_bad_parts_are_refused),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
