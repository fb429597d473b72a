/* test_terrain_flight.c - the exact first impact of a parabola with the
 * bilinear surface (terrain_flight.c) against closed forms and a brute-force
 * second method:
 *   a plane of any slope and aspect, from any point (impact time and point to
 *   1e-9, with map coordinates of a projected CRS, far from 0);
 *   a vertical drop on a twisted cell (d != 0);
 *   paths through many cells diagonally (through the nodes) and along a cell
 *   line (beside a no-data cell);
 *   a flight starting on the surface (just bounced: not tau = 0 again);
 *   a one-node-wide ridge and random rough DEMs: the engine's impact against
 *   a dense sampling of the gap (never flown through, no early hit);
 *   leaving the border and entering a no-data cell. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_terrain_util.h"
#include "test_util.h"

/* Closed form on the plane: gap(t) = C + B t - g t^2 / 2. */
static double plane_time(const tt_plane *pl, const double p[3], const double v[3])
{
    double C = p[2] - tt_plane_z((void *)pl, p[0], p[1]), B = v[2] - pl->sx * v[0] - pl->sy * v[1];
    return (B + sqrt(B * B + 2 * TT_G * C)) / TT_G;
}

static void check_plane_hit(const rf_terrain *t, const tt_plane *pl, const double p[3], const double v[3])
{
    double tau;
    size_t ci, cj;
    assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 1);
    double T = plane_time(pl, p, v);
    assert_close(tau, T, 1e-9);
    double x = p[0] + v[0] * T, y = p[1] + v[1] * T;
    /* the cell holds the point */
    assert_true(x >= t->x0 + (double)ci * t->dx - 1e-9 && x <= t->x0 + (double)(ci + 1) * t->dx + 1e-9);
    assert_true(y >= t->y0 + (double)cj * t->dy - 1e-9 && y <= t->y0 + (double)(cj + 1) * t->dy + 1e-9);
    double xe = p[0] + v[0] * tau, ye = p[1] + v[1] * tau, ze = p[2] + v[2] * tau - 0.5 * TT_G * tau * tau;
    assert_near(xe, x, 1e-9 * (1 + fabs(v[0]) * T));
    assert_near(ye, y, 1e-9 * (1 + fabs(v[1]) * T));
    assert_near(ze, tt_plane_z((void *)pl, x, y), 1e-9 * (1 + fabs(ze - pl->z0) + TT_G * T * T));
}

/* 300 planes of slope up to 60 deg and any aspect, on grids of unequal
 * spacing placed at UTM-like coordinates; starts up to 50 m above. */
static void test_plane_any_slope_aspect(void **state)
{
    (void)state;
    uint64_t seed = 12345;
    for (int k = 0; k < 300; k++) {
        double slope = tt_uniform(&seed, 0, 60) * TT_DEG, aspect = tt_uniform(&seed, -180, 180) * TT_DEG;
        double dx = tt_uniform(&seed, 0.5, 5), dy = tt_uniform(&seed, 0.5, 5);
        double x0 = 4.5e5 + tt_uniform(&seed, 0, 1e4), y0 = 5.2e6 + tt_uniform(&seed, 0, 1e4);
        size_t n = 121;
        tt_plane pl = {800, tan(slope) * sin(aspect), tan(slope) * cos(aspect), x0 + 60 * dx, y0 + 60 * dy};
        rf_terrain *t = tt_dem(n, n, x0, y0, dx, dy, tt_plane_z, &pl);
        double p[3] = {pl.xc + tt_uniform(&seed, -5, 5) * dx, pl.yc + tt_uniform(&seed, -5, 5) * dy, 0};
        p[2] = tt_plane_z(&pl, p[0], p[1]) + tt_uniform(&seed, 0.01, 50);
        double sp = tt_uniform(&seed, 0, 6), dir = tt_uniform(&seed, 0, 2 * TT_PI);
        double v[3] = {sp * cos(dir), sp * sin(dir), tt_uniform(&seed, -10, 10)};
        check_plane_hit(t, &pl, p, v);
        rf_terrain_free(t);
    }
}

/* A vertical drop onto a twisted cell: the height there is the bilinear
 * value, t = (vz + sqrt(vz^2 + 2 g (z - zs))) / g. */
static double twisted(void *ctx, double x, double y)
{
    (void)ctx;
    return 3 * x * y + 0.5 * x - 0.2 * y + 100; /* on nodes 0, 1, 2: exactly bilinear per cell */
}

static void test_vertical_drop(void **state)
{
    (void)state;
    rf_terrain *t = tt_dem(3, 3, 0, 0, 1, 1, twisted, NULL);
    uint64_t seed = 99;
    for (int k = 0; k < 200; k++) {
        double x = tt_uniform(&seed, 0, 2), y = tt_uniform(&seed, 0, 2), zs = twisted(NULL, x, y);
        double p[3] = {x, y, zs + tt_uniform(&seed, 0.001, 20)}, v[3] = {0, 0, tt_uniform(&seed, -5, 5)};
        double tau;
        size_t ci, cj;
        assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 1);
        double T = (v[2] + sqrt(v[2] * v[2] + 2 * TT_G * (p[2] - zs))) / TT_G;
        assert_close(tau, T, 1e-9);
    }
    /* the same from a node and from a cell line (x = 1) */
    double p[3] = {1, 1, 110}, v[3] = {0, 0, 0}, tau;
    size_t ci, cj;
    assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 1);
    assert_close(tau, sqrt(2 * (110 - twisted(NULL, 1, 1)) / TT_G), 1e-12);
    p[1] = 0.3;
    assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 1);
    assert_close(tau, sqrt(2 * (110 - twisted(NULL, 1, 0.3)) / TT_G), 1e-12);
    rf_terrain_free(t);
}

/* Through the nodes on the diagonal, and along a cell line, across many
 * cells, onto a gentle plane: the closed form to 1e-9. */
static void test_diagonal_and_cell_lines(void **state)
{
    (void)state;
    tt_plane pl = {0, 0.05, -0.03, 0, 0};
    rf_terrain *t = tt_dem(201, 201, 0, 0, 1, 1, tt_plane_z, &pl);
    double p[3] = {10, 10, 80}, v[3] = {7, 7, 3}; /* through every node (10 + k, 10 + k) */
    double tau;
    size_t ci, cj;
    assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 1);
    assert_true(v[0] * tau > 20); /* many cells crossed */
    assert_close(tau, plane_time(&pl, p, v), 1e-9);
    double q[3] = {20, 50, 60}, w[3] = {9, 0, 2}; /* along the line y = 50 */
    check_plane_hit(t, &pl, q, w);
    double q2[3] = {150, 50, 60}, w2[3] = {0, -9, 2}; /* along x = 150, southwards */
    check_plane_hit(t, &pl, q2, w2);
    double q3[3] = {150, 150, 60}, w3[3] = {-5, -5, 0}; /* diagonal south-west */
    check_plane_hit(t, &pl, q3, w3);
    rf_terrain_free(t);
    /* along a cell line with no data on its north side: the south cells carry it */
    double *z = malloc(21 * 21 * sizeof *z);
    for (size_t j = 0; j < 21; j++)
        for (size_t i = 0; i < 21; i++)
            z[j * 21 + i] = j > 10 ? NAN : tt_plane_z(&pl, (double)i, (double)j);
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(21, 21, 0, 0, 1, 1, z, &t, &err), RF_OK);
    free(z);
    double a[3] = {2, 10, 5}, b[3] = {1.5, 0, 0}; /* on the line y = 10, the valid cells south of it */
    check_plane_hit(t, &pl, a, b);
    rf_terrain_free(t);
}

/* A block just bounced off the plane, on its surface, leaving it: the next
 * impact is at 2 (v.n) / (g n_z), not at once; moving into it: at once. */
static void test_start_on_surface(void **state)
{
    (void)state;
    uint64_t seed = 4242;
    for (int k = 0; k < 200; k++) {
        double slope = tt_uniform(&seed, 0, 50) * TT_DEG, aspect = tt_uniform(&seed, -180, 180) * TT_DEG;
        tt_plane pl = {300, tan(slope) * sin(aspect), tan(slope) * cos(aspect), 50, 50};
        rf_terrain *t = tt_dem(101, 101, 0, 0, 1, 1, tt_plane_z, &pl);
        double nz = 1 / sqrt(1 + pl.sx * pl.sx + pl.sy * pl.sy), n[3] = {-pl.sx * nz, -pl.sy * nz, nz};
        /* start on a node, a cell line, or inside a cell */
        double x = k % 3 == 0 ? 50 : 50 + tt_uniform(&seed, 0, 1), y = k % 3 == 1 ? 49 : 50 + tt_uniform(&seed, 0, 1);
        double p[3] = {x, y, tt_plane_z(&pl, x, y)};
        double v[3] = {tt_uniform(&seed, -3, 3), tt_uniform(&seed, -3, 3), 0};
        double vn0 = v[0] * n[0] + v[1] * n[1] + v[2] * n[2], up = tt_uniform(&seed, 0.05, 5);
        for (int q = 0; q < 3; q++)
            v[q] += (up - vn0) * n[q]; /* v.n = up > 0 */
        double tau;
        size_t ci, cj;
        assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 1);
        assert_close(tau, 2 * up / (TT_G * nz), 1e-9);
        for (int q = 0; q < 3; q++)
            v[q] -= 2 * up * n[q]; /* into the plane */
        assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 1);
        assert_true(tau == 0);
        rf_terrain_free(t);
    }
}

/* The gap of the path at time s (NaN off the surface). */
static double gap_at(const rf_terrain *t, const double p[3], const double v[3], double s)
{
    double z;
    if (!rf_terrain_height(t, p[0] + v[0] * s, p[1] + v[1] * s, &z, NULL))
        return NAN;
    return p[2] + v[2] * s - 0.5 * TT_G * s * s - z;
}

/* The engine's answer against 20000 samples of the gap: no sample before the
 * impact (or the exit) is below the ground; the impact point is on it; just
 * after it the path is in the ground or touching it. */
static void check_brute(const rf_terrain *t, const double p[3], const double v[3], int *hits, size_t *ci)
{
    double tau;
    size_t cj;
    *ci = (size_t)-1;
    int hit = terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, ci, &cj);
    assert_true(isfinite(tau));
    const int N = 20000;
    for (int k = 0; k < N; k++) {
        double s = tau * k / N, gp = gap_at(t, p, v, s);
        if (!isnan(gp) && !(gp >= -1e-9 * (1 + fabs(p[2]))))
            fail_msg("flown through: gap %g at s = %.17g before the engine's %s at %.17g", gp, s,
                     hit ? "impact" : "exit", tau);
    }
    if (hit) {
        (*hits)++;
        assert_near(gap_at(t, p, v, tau), 0, 1e-9 * (1 + fabs(p[2])));
        double after = gap_at(t, p, v, tau + 1e-6);
        assert_true(isnan(after) || after <= 1e-9);
    }
}

static double ridge(void *ctx, double x, double y)
{
    (void)ctx, (void)y;
    return fabs(x - 12) < 0.5 ? 6 : 0; /* one column of nodes, x = 12, raised 6 m */
}

static double rough(void *ctx, double x, double y)
{
    uint64_t s = (uint64_t)(x * 1000 + 7) * 2654435761u + (uint64_t)(y * 1000 + 3) * 40503u + *(uint64_t *)ctx;
    for (int k = 0; k < 3; k++)
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
    return 0.3 * x + 4 * (double)(s % 10000) / 10000.0; /* spikes up to 4 m on a 17 deg slope */
}

static void test_thin_ridge_and_rough_dem(void **state)
{
    (void)state;
    rf_terrain *t = tt_dem(25, 11, 0, 0, 1, 1, ridge, NULL);
    uint64_t seed = 77;
    int hits = 0, on_ridge = 0, k;
    size_t ci;
    for (k = 0; k < 400; k++) { /* grazing the crest: the peak within +-0.5 m of the path's height there */
        double v[3] = {tt_uniform(&seed, 3, 12), tt_uniform(&seed, -1, 1), tt_uniform(&seed, -2, 2)};
        double p[3] = {tt_uniform(&seed, 1, 8), tt_uniform(&seed, 3, 7), 0};
        double s = (12 - p[0]) / v[0];
        p[2] = 6 - v[2] * s + 0.5 * TT_G * s * s + tt_uniform(&seed, -0.5, 0.5);
        check_brute(t, p, v, &hits, &ci);
        on_ridge += ci == 11 || ci == 12;
    }
    assert_true(on_ridge > 100 && on_ridge < 300); /* both sides of the crest were tried */
    rf_terrain_free(t);
    for (uint64_t dem = 1; dem <= 5; dem++) {
        t = tt_dem(41, 41, 0, 0, tt_uniform(&seed, 0.5, 2), tt_uniform(&seed, 0.5, 2), rough, &dem);
        for (k = 0; k < 200; k++) {
            double xm = t->dx * 40, ym = t->dy * 40, x = tt_uniform(&seed, 0, xm), y = tt_uniform(&seed, 0, ym), z;
            assert_true(rf_terrain_height(t, x, y, &z, NULL));
            double p[3] = {x, y, z + tt_uniform(&seed, 0.001, 3)};
            double v[3] = {tt_uniform(&seed, -8, 8), tt_uniform(&seed, -8, 8), tt_uniform(&seed, -3, 6)};
            check_brute(t, p, v, &hits, &ci);
        }
        rf_terrain_free(t);
    }
}

/* Over flat ground 20 m below, the path leaves through the east border at
 * x = 10, or at the first no-data cell: cells 6 and 7 of row j lose data
 * with the node (7, j). */
static void test_border_and_nodata(void **state)
{
    (void)state;
    double z[11 * 5];
    for (int k = 0; k < 55; k++)
        z[k] = 0;
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(11, 5, 0, 0, 1, 1, z, &t, &err), RF_OK);
    double p[3] = {1.5, 2.5, 20}, v[3] = {20, 0, 5}, tau;
    size_t ci, cj;
    assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 0);
    assert_close(tau, 8.5 / 20, 1e-15);
    double w[3] = {-20, -10, 5}; /* through the south border y = 0 first: t = 0.25 (x = -3.5 < 0: west border
                                    at t = 0.075 first) */
    assert_int_equal(terrain_first_impact(t, p, w, TT_G, INFINITY, &tau, &ci, &cj), 0);
    assert_close(tau, 1.5 / 20, 1e-15);
    rf_terrain_free(t);
    z[2 * 11 + 7] = NAN;
    assert_int_equal(rf_terrain_from_nodes(11, 5, 0, 0, 1, 1, z, &t, &err), RF_OK);
    assert_int_equal(terrain_first_impact(t, p, v, TT_G, INFINITY, &tau, &ci, &cj), 0);
    assert_close(tau, 4.5 / 20, 1e-15); /* enters cell 6 (x = 6) of row 2 */
    double low[3] = {1.5, 2.5, 0.5}, slow[3] = {2, 0, 5}; /* lands before the hole: an impact */
    assert_int_equal(terrain_first_impact(t, low, slow, TT_G, INFINITY, &tau, &ci, &cj), 1);
    assert_close(tau, plane_time(&(tt_plane){0, 0, 0, 0, 0}, low, slow), 1e-12);
    double out[4][3] = {{-1, 2, 3}, {1e300, 2, 3}, {2, -1e300, 3}, {NAN, 2, 3}}; /* off the DEM: leaves at once */
    for (int k = 0; k < 4; k++) {
        assert_int_equal(terrain_first_impact(t, out[k], v, TT_G, INFINITY, &tau, &ci, &cj), 0);
        assert_true(tau == 0);
    }
    /* tmax: no impact and no exit within it */
    assert_int_equal(terrain_first_impact(t, p, v, TT_G, 0.1, &tau, &ci, &cj), 0);
    assert_true(isinf(tau));
    rf_terrain_free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plane_any_slope_aspect),
        cmocka_unit_test(test_vertical_drop),
        cmocka_unit_test(test_diagonal_and_cell_lines),
        cmocka_unit_test(test_start_on_surface),
        cmocka_unit_test(test_thin_ridge_and_rough_dem),
        cmocka_unit_test(test_border_and_nodata),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
