/* pending_test_terrain_montecarlo.c - the terrain Monte Carlo end to end
 * (rf_terrain_run on a terrain file whose DEM and class raster are ESRI
 * ASCII grids written here): the same bits for 1, 2 and 3 threads of every
 * per-sample array, the recorded trajectories and the hazard bands; the
 * random inputs drawn as in 2D (input j of sample i is a + U(seed, 2i, j)
 * (b - a) for a uniform input, rf_traj_uniform being the documented stream);
 * the Latin hypercube stratifying the release point on a one-segment line
 * (one start per stratum, which plain sampling almost never gives).
 * PENDING: it needs the simulator, the file reader and world, the release
 * sampling, the hazard rasters and the simulator's terrain_simulate_hazard;
 * the integrator renames it tests/test_terrain_montecarlo.c after merging. */
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

/* |a - b| <= tol in double (cmocka's assert_float_equal compares floats). */
#define assert_near(a, b, tol)                                                                              \
    do {                                                                                                    \
        double a_ = (a), b_ = (b);                                                                          \
        if (!(fabs(a_ - b_) <= (tol)))                                                                      \
            fail_msg("%s = %.17g, expected %.17g (tol %g)", #a, a_, b_, (double)(tol));                     \
    } while (0)

#define NX 151
#define NY 201
#define CELL 2.0

static char dir[] = "/tmp/rf_terrain_mc_XXXXXX";

/* A slope falling to the south: steep above y = 250 m, a bench, a flatter
 * runout, bumps across so that paths spread. */
static double ground(double x, double y)
{
    double z = y > 250 ? 60 + 0.7 * (y - 250) : y > 150 ? 40 + 0.2 * (y - 150) : 40 - 0.05 * (150 - y);
    return z + 0.6 * sin(x / 7.0) * cos(y / 9.0);
}

static const terrain_fixture terrain = {NX, NY, CELL, ground, 250};

static void load(rf_traj_spec *s, int lhs, size_t samples)
{
    char yaml[4096];
    snprintf(yaml, sizeof yaml,
             "name: mc\n"
             "terrain: {dem: %s/dem.asc, materials: {raster: %s/classes.asc, classes: {1: rock, 2: talus}}}\n"
             "materials:\n"
             "  rock:  {R_n: {uniform: [0.3, 0.6]}, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1, "
             "roughness: 5}\n"
             "  talus: {R_n: 0.35, R_t: 0.75, friction_angle: 35, rolling_resistance: 0.3, roughness: 10}\n"
             "block: {shape: sphere, radius: 0.5, density: 2600}\n"
             "release: {lines: [[[100, 390], [200, 390]]], height: {uniform: [1, 3]}, velocity: [0, 0, 0]}\n"
             "bounce: {law: constant}\n"
             "barriers: [{name: fence, line: [[20, 150], [280, 150]], height: 4, capacity: 2.0e6}]\n"
             "rasters: {cell: 4, statistics: [passages, reach_probability, deposits, energy_p95, height_p95]}\n"
             "samples: %zu\nseed: 11\nsampling: %s\nrecord: 20\n",
             dir, dir, samples, lhs ? "lhs" : "random");
    fixture_load(dir, "mc.yaml", yaml, s);
}

static int setup(void **state)
{
    (void)state;
    return fixture_setup(dir, &terrain);
}

static int teardown(void **state)
{
    (void)state;
    fixture_teardown(dir, "mc.yaml");
    return 0;
}

static void run(const rf_traj_spec *s, int threads, rf_traj_ensemble *e)
{
    rf_error err;
    if (rf_terrain_run(s, threads, NULL, NULL, e, &err) != RF_OK)
        fail_msg("%d threads: %s", threads, err.msg);
}

static void same_arrays(const rf_traj_ensemble *a, const rf_traj_ensemble *b)
{
    size_t N = a->samples, nc = a->n_collectors;
    assert_int_equal(b->samples, N);
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
    for (size_t i = 0; i < p->n_recorded; i++) {
        assert_int_equal(p->recorded[i].n_impacts, q->recorded[i].n_impacts);
        assert_int_equal(p->recorded[i].n_events, q->recorded[i].n_events);
        assert_memory_equal(p->recorded[i].impacts, q->recorded[i].impacts,
                            p->recorded[i].n_impacts * sizeof *p->recorded[i].impacts);
    }
}

/* Every band of the two runs' rasters byte for byte; returns the sum of the passages. */
static double same_bands(const rf_traj_spec *s, const rf_traj_ensemble *a, const rf_traj_ensemble *b)
{
    terrain_band *ba, *bb;
    size_t na, nb, nx, ny;
    double x0, y0, cell, passages = 0;
    rf_error err;
    assert_non_null(a->terrain->hazard);
    assert_int_equal(terrain_hazard_bands(a->terrain->hazard, s, a->samples, &ba, &na, &err), RF_OK);
    assert_int_equal(terrain_hazard_bands(b->terrain->hazard, s, b->samples, &bb, &nb, &err), RF_OK);
    terrain_hazard_grid(a->terrain->hazard, &nx, &ny, &x0, &y0, &cell);
    assert_int_equal(na, nb);
    assert_true(na >= 5);
    for (size_t k = 0; k < na; k++) {
        assert_string_equal(ba[k].name, bb[k].name);
        assert_memory_equal(ba[k].data, bb[k].data, nx * ny * sizeof(float));
        if (!strcmp(ba[k].name, "passages"))
            for (size_t c = 0; c < nx * ny; c++)
                passages += ba[k].data[c];
    }
    terrain_bands_free(ba, na);
    terrain_bands_free(bb, nb);
    return passages;
}

static void test_threads_same_bits(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(&s, 0, 300);
    rf_traj_ensemble e1, e2, e3;
    run(&s, 1, &e1);
    run(&s, 2, &e2);
    run(&s, 3, &e3);
    same_arrays(&e1, &e2);
    same_arrays(&e1, &e3);
    same_bands(&s, &e1, &e3);
    /* every block passes at least its release cell: the pieces reach the rasters */
    assert_true(same_bands(&s, &e1, &e2) >= (double)s.samples);
    size_t moved = 0;
    for (size_t i = 0; i < s.samples; i++)
        moved += e1.runout_x[i] > 20;
    assert_true(moved > s.samples / 2); /* the slope is steep: most blocks run down it */
    rf_traj_ensemble_free(&e1);
    rf_traj_ensemble_free(&e2);
    rf_traj_ensemble_free(&e3);
    rf_traj_spec_free(&s);
}

/* release.height is the second random input (after materials.rock.R_n): each
 * block starts U(seed, 2i, 1) of the way from 1 to 3 m above the ground. */
static void test_draws_as_2d(void **state)
{
    (void)state;
    rf_traj_spec s;
    load(&s, 0, 50);
    assert_int_equal(s.n_random, 2);
    assert_string_equal(s.random[1].path, "release.height");
    rf_traj_ensemble e;
    run(&s, 2, &e);
    for (size_t i = 0; i < s.samples; i++) {
        const double *p = &e.terrain->start[3 * i];
        double z;
        assert_true(rf_terrain_height(e.terrain_dem, p[0], p[1], &z, NULL));
        double want = 1 + 2 * rf_traj_uniform(s.seed, 2 * (uint64_t)i, 1);
        assert_near(p[2] - z, want, 1e-9);
        assert_near(p[1], 390, 1e-9);
    }
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

/* How many of the N strata of [100, 200] hold a start point. */
static size_t strata_hit(const rf_traj_ensemble *e)
{
    size_t N = e->samples, hit = 0;
    char *seen = calloc(N, 1);
    for (size_t i = 0; i < N; i++) {
        size_t k = (size_t)((e->terrain->start[3 * i] - 100) / 100 * (double)N);
        if (k < N && !seen[k])
            seen[k] = 1, hit++;
    }
    free(seen);
    return hit;
}

static void test_lhs(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_traj_ensemble e;
    load(&s, 1, 40);
    run(&s, 3, &e);
    assert_int_equal(strata_hit(&e), 40);
    rf_traj_ensemble e1;
    run(&s, 1, &e1);
    same_arrays(&e, &e1);
    rf_traj_ensemble_free(&e);
    rf_traj_ensemble_free(&e1);
    rf_traj_spec_free(&s);
    load(&s, 0, 40); /* plain sampling: all 40 strata hit has probability 40!/40^40 ~ 1e-16 */
    run(&s, 1, &e);
    assert_true(strata_hit(&e) < 40);
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_same_bits),
        cmocka_unit_test(test_draws_as_2d),
        cmocka_unit_test(test_lhs),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
