/* test_traj_impact_radius.c - the impact table's radius axis on terrain
 * (issue 29 item 3's leftover): the blocks of a terrain run differ in size
 * only through a random block.radius (a terrain release's features carry a
 * share of the blocks, no size of their own: terrain.h, rf_terrain_release),
 * and traj_impact_radius_range covers every radius a sample can draw: the
 * uniform's ends, a normal's mean +- 4 SD clamped to its min/max; a fixed
 * radius gives a one-node axis.  The brute-force reference: the smallest and
 * largest radius of the block.radius values drawn for 2000 samples. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "terrain_fixture.h"
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"

static char dir[] = "/tmp/rf_impact_radius_XXXXXX";

static double ground(double x, double y)
{
    (void)x;
    return 0.5 * y;
}

static const terrain_fixture terrain = {21, 41, 2.0, ground, 60};

static int setup(void **state)
{
    (void)state;
    return fixture_setup(dir, &terrain);
}

static int teardown(void **state)
{
    (void)state;
    fixture_teardown(dir, "r.yaml");
    return 0;
}

static void load(const char *radius, rf_traj_spec *s)
{
    char yaml[2048];
    snprintf(yaml, sizeof yaml,
             "terrain: {dem: %s/dem.asc, material: rock}\n"
             "materials: {rock: {R_n: 0.4, R_t: 0.8, friction_angle: 30}}\n"
             "block: {shape: sphere, radius: %s, density: 2600}\n"
             "release: {points: [[20, 70]], height: 1}\n"
             "bounce: {law: impact_model, impact: {solver: rigid}}\n"
             "samples: 2000\nseed: 3\nsampling: random\n",
             dir, radius);
    fixture_load(dir, "r.yaml", yaml, s);
}

/* The radii the samples draw: each sample's block.radius. */
static void drawn_range(const rf_traj_spec *s, double *lo, double *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    for (size_t i = 0; i < s->samples; i++) {
        double r = s->radius;
        for (size_t k = 0; k < s->n_random; k++) /* the engines' own draw (traj_draw.c), random sampling */
            if (!strcmp(s->random[k].path, "block.radius"))
                r = traj_draw_value(&s->random[k], traj_sample_u(s, NULL, i, k));
        *lo = fmin(*lo, r), *hi = fmax(*hi, r);
    }
}

static void check(const char *radius, double want_lo, double want_hi)
{
    rf_traj_spec s;
    load(radius, &s);
    assert_non_null(s.terrain);
    double lo, hi, dlo, dhi;
    traj_impact_radius_range(&s, &lo, &hi);
    drawn_range(&s, &dlo, &dhi);
    print_message("radius %s: axis [%g, %g] m, drawn [%g, %g] m\n", radius, lo, hi, dlo, dhi);
    assert_true(fabs(lo - want_lo) < 1e-12 && fabs(hi - want_hi) < 1e-12);
    assert_true(lo <= dlo && dhi <= hi);
    rf_traj_spec_free(&s);
}

static void test_uniform(void **state)
{
    (void)state;
    check("{uniform: [0.3, 0.6]}", 0.3, 0.6);
}

static void test_normal_clamped(void **state)
{
    (void)state;
    check("{normal: [0.5, 0.05], min: 0.35, max: 0.6}", 0.35, 0.6);
    check("{normal: [0.5, 0.02]}", 0.42, 0.58);
}

static void test_fixed(void **state)
{
    (void)state;
    check("0.5", 0.5, 0.5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uniform),
        cmocka_unit_test(test_normal_clamped),
        cmocka_unit_test(test_fixed),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
