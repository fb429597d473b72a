/* test_terrain_hazard_cell.c - the rasters' shortcut for a contact step's
 * piece (terrain_hazard_piece_in, used by terrain_contact_state.c tc_emit,
 * and by terrain_fly.c for a flight whose straight map chord lies in its
 * landing cell under the same rule, e.g. every launch at a convex edge):
 * a piece whose map path lies in one DEM cell, on a raster grid that is the
 * DEM's, goes to that cell without the walk over the grid.  Reference: the
 * walk itself (terrain_hazard_piece) fed the same pieces; the packed
 * accumulators (every count, maximum and histogram bin) must be the same
 * bytes.  The pieces are those tc_emit hands over: chords inside the closed
 * cell, starting inside it or on one of its lines going into it (the rule of
 * in_cell_alone), curved (a != 0) or straight, on the ground or flying (the
 * passing heights are evaluated on the surface).  On a raster grid that is
 * not the DEM's (3 m cells on a 2 m DEM, or an origin moved) the shortcut
 * must fall back to the walk: the same bytes again.  End to end: 400
 * trajectories of a sphere simulated on a bumpy DEM (launches at convex
 * edges, flights landing in their next cell, contact steps) into an
 * accumulator with the shortcut and one that walks every piece
 * (terrain_hazard_walk_only): the same bands in every cell but at most one,
 * where the walk counts one passage more: a contact step's end that its
 * chord puts a round-off past the cell's line (the walk's sliver; the
 * flights' shortcut adds no such cell: the same one with it switched off). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "trajectory/terrain_internal.h"
#include "test_terrain_util.h"

#define NX 14
#define NY 11
#define D 2.0
#define X0 100.0
#define Y0 50.0
#define NTRAJ 1500
#define NPIECE 4

static uint64_t rng_state;
static double urand(void) /* splitmix64 -> [0, 1) */
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static rf_terrain *dem_make(void)
{
    double z[NX * NY];
    for (size_t j = 0; j < NY; j++)
        for (size_t i = 0; i < NX; i++)
            z[j * NX + i] = 0.4 * (double)i * D + 0.2 * (double)j * D + sin(0.9 * (double)i) * cos(0.6 * (double)j);
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(NX, NY, X0, Y0, D, D, z, &t, &err), RF_OK);
    return t;
}

/* A coordinate of the start in [lo, lo + D]: on the low line, on the high line, or inside. */
static double start_coord(double lo, int *side)
{
    double u = urand();
    *side = u < 0.15 ? -1 : u < 0.3 ? 1 : 0;
    return *side < 0 ? lo : *side > 0 ? lo + D : lo + D * (0.001 + 0.998 * urand());
}

/* An end coordinate strictly inside [lo, lo + D], on the side of the start's line that is the cell. */
static double end_coord(double lo) { return lo + D * (1e-6 + (1 - 2e-6) * urand()); }

/* A piece in cell (i, j) as tc_emit hands it to the rasters. */
static void piece_make(terrain_piece *pc, const rf_terrain *dem, size_t i, size_t j, double t)
{
    memset(pc, 0, sizeof *pc);
    double xi = X0 + (double)i * D, yj = Y0 + (double)j * D;
    int sx, sy;
    double x = start_coord(xi, &sx), y = start_coord(yj, &sy);
    double xe = end_coord(xi), ye = end_coord(yj), T = 0.01 + 0.5 * urand();
    pc->t = t, pc->T = T;
    pc->on_ground = urand() < 0.5;
    int curved = urand() < 0.7;
    for (int k = 0; k < 2; k++)
        pc->a[k] = curved ? 6 * urand() - 3 : 0;
    pc->a[2] = pc->on_ground ? 0.5 * pc->a[0] : -9.81;
    pc->p[0] = x, pc->p[1] = y;
    double zg;
    assert_true(rf_terrain_height(dem, x, y, &zg, NULL));
    pc->p[2] = zg + (pc->on_ground ? 0 : 0.5 * urand());
    pc->v[0] = (xe - x - 0.5 * pc->a[0] * T * T) / T;
    pc->v[1] = (ye - y - 0.5 * pc->a[1] * T * T) / T;
    pc->v[2] = 4 * urand() - 1;
    pc->e_rot = 100 * urand();
}

static int pack_equal(const rf_terrain_hazard *a, const rf_terrain_hazard *b)
{
    uint64_t *pa, *pb;
    size_t na, nb;
    rf_error err;
    assert_int_equal(terrain_hazard_pack(a, &pa, &na, &err), RF_OK);
    assert_int_equal(terrain_hazard_pack(b, &pb, &nb, &err), RF_OK);
    int same = na == nb && !memcmp(pa, pb, na * sizeof *pa);
    free(pa), free(pb);
    return same;
}

/* Feed NTRAJ random trajectories to the walk (ref) and to the shortcut (cut); the packed bytes. */
static void run(double cell, double move_origin)
{
    rf_terrain *dem = dem_make();
    rf_traj_spec s;
    rf_terrain_def d;
    memset(&s, 0, sizeof s), memset(&d, 0, sizeof d);
    d.raster_cell = cell;
    d.statistics = RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS | RF_TERRAIN_ENERGY |
                   RF_TERRAIN_HEIGHT;
    s.terrain = &d;
    rf_terrain *shifted = NULL;
    if (move_origin != 0) { /* the rasters of a DEM whose origin is moved: not the pieces' DEM grid */
        double z[NX * NY];
        for (size_t k = 0; k < NX * NY; k++)
            z[k] = dem->z[k];
        rf_error err;
        assert_int_equal(rf_terrain_from_nodes(NX, NY, X0 + move_origin, Y0, D, D, z, &shifted, &err), RF_OK);
    }
    rf_terrain_hazard *ref = terrain_hazard_create(&s, shifted ? shifted : dem);
    rf_terrain_hazard *cut = terrain_hazard_create(&s, shifted ? shifted : dem);
    assert_non_null(ref), assert_non_null(cut);
    rng_state = 20261129;
    size_t pieces = 0;
    for (size_t k = 0; k < NTRAJ; k++) {
        terrain_piece pc[NPIECE];
        size_t ci[NPIECE], cj[NPIECE];
        size_t n = 1 + (size_t)(urand() * NPIECE);
        for (size_t q = 0; q < n; q++) {
            ci[q] = (size_t)(urand() * (NX - 1)), cj[q] = (size_t)(urand() * (NY - 1));
            piece_make(&pc[q], dem, ci[q], cj[q], (double)q);
        }
        double end[3] = {pc[n - 1].p[0], pc[n - 1].p[1], pc[n - 1].p[2]};
        int stopped = urand() < 0.7;
        terrain_hazard_begin(ref), terrain_hazard_begin(cut);
        for (size_t q = 0; q < n; q++) {
            terrain_hazard_piece(ref, dem, 2000, &pc[q]);
            terrain_hazard_piece_in(cut, dem, 2000, &pc[q], ci[q], cj[q]);
        }
        terrain_hazard_end(ref, stopped, end), terrain_hazard_end(cut, stopped, end);
        pieces += n;
    }
    assert_true(pieces > 3 * NTRAJ / 2);
    assert_true(pack_equal(ref, cut));
    /* and the check can fail: one piece more in one accumulator */
    terrain_piece extra;
    piece_make(&extra, dem, 3, 4, 0);
    terrain_hazard_begin(cut);
    terrain_hazard_piece_in(cut, dem, 2000, &extra, 3, 4);
    terrain_hazard_end(cut, 0, extra.p);
    assert_false(pack_equal(ref, cut));
    terrain_hazard_free(ref), terrain_hazard_free(cut);
    rf_terrain_free(dem), rf_terrain_free(shifted);
}

static void test_dem_grid_same_bytes(void **state)
{
    (void)state;
    run(D, 0);
}

static void test_other_grid_falls_back(void **state)
{
    (void)state;
    run(3.0, 0);  /* coarser cells */
    run(D, 0.5);  /* the same cell size, another origin */
}

/* Bumps on a slope: curved cells, convex and concave edges. */
static double bumpy_z(void *ctx, double x, double y)
{
    (void)ctx;
    return 0.55 * (60 - x) + 0.1 * y + 0.8 * sin(0.7 * x) * cos(0.5 * y) + 0.3 * sin(1.9 * x + 0.3 * y);
}

static void test_simulated_against_walk(void **state)
{
    (void)state;
    rf_terrain *dem = tt_dem(31, 21, 0, 0, D, D, bumpy_z, NULL);
    tt_spec ts;
    tt_spec_init(&ts, 0.3, 0.7);
    tt_sphere(&ts, 0.4, 2600);
    ts.mat[0].rolling_resistance = 0.05;
    tt_world tw;
    tt_world_init(&tw, dem);
    rf_terrain_hazard *fast = terrain_hazard_create(&ts.spec, dem), *walk = terrain_hazard_create(&ts.spec, dem);
    terrain_hazard_walk_only(walk);
    uint64_t rs = 99;
    size_t landings = 0;
    for (uint64_t k = 0; k < 400; k++) {
        double start[3] = {tt_uniform(&rs, 2, 14), tt_uniform(&rs, 4, 36), NAN};
        ts.spec.height0 = tt_uniform(&rs, 0, 2);
        for (int pass = 0; pass < 2; pass++) {
            tt_result r;
            tt_result_init(&r);
            rf_error err;
            assert_int_equal(terrain_simulate_hazard(&tw.w, &ts.spec, 5, k, start, pass ? walk : fast, &r.res, &err),
                             RF_OK);
            for (size_t e = 0; pass == 0 && e < r.res.n_events; e++)
                landings += r.res.events[e].kind == RF_EV_CONTACT;
            tt_result_free(&r);
        }
    }
    assert_true(landings > 2000); /* the flights that land softly, most of them edge launches */
    /* The same bands, but for a contact step whose end the walk's chord puts a
     * round-off past its cell's line (a sliver: one passage more in the
     * neighbour, at the step's end energy, height 0): at most one such cell
     * here (seen: one, from the contact steps' shortcut; the flights' adds none) */
    terrain_band *a, *b;
    size_t na, nb, sliver = SIZE_MAX, n_sliver = 0;
    rf_error err;
    assert_int_equal(terrain_hazard_bands(fast, &ts.spec, 400, &a, &na, &err), RF_OK);
    assert_int_equal(terrain_hazard_bands(walk, &ts.spec, 400, &b, &nb, &err), RF_OK);
    assert_int_equal(na, nb);
    assert_string_equal(a[0].name, "passages");
    for (size_t c = 0; c < 30 * 20; c++)
        if (a[0].data[c] != b[0].data[c]) {
            assert_true(b[0].data[c] == a[0].data[c] + 1);
            sliver = c, n_sliver++;
        }
    assert_true(n_sliver <= 1);
    for (size_t q = 0; q < na; q++)
        for (size_t c = 0; c < 30 * 20; c++)
            if (c != sliver)
                assert_memory_equal(&a[q].data[c], &b[q].data[c], sizeof(float));
    terrain_bands_free(a, na), terrain_bands_free(b, nb);
    terrain_hazard_free(fast), terrain_hazard_free(walk);
    rf_terrain_free(dem);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dem_grid_same_bytes),
        cmocka_unit_test(test_other_grid_falls_back),
        cmocka_unit_test(test_simulated_against_walk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
