/* test_dem_window.c - a DEM is read only in the window a run needs (issue 31
 * item 14).  A 40 000 x 40 000 Float32 GeoTIFF (6.4 GB of cells, 12.8 GB as
 * doubles) is made here sparse (tiles never written take no disk), with a
 * 300 x 300 patch of known non-planar values written into it; a small GeoTIFF
 * holds the same patch alone (its geotransform shifted by the patch's
 * offset).  Then:
 * - a profile cut along a line inside the patch is bit for bit the cut of the
 *   small DEM, and the process's peak RSS grows by less than 64 MB;
 * - the terrain surface of a terrain.window around the patch is bit for bit
 *   the small DEM read whole: same extent, every node (the window's edges
 *   included) and points inside cells; peak RSS again within 64 MB;
 * - the whole big DEM (no window) is refused before anything is allocated,
 *   naming the file, its size, the memory figure and the limit; a window
 *   outside the DEM is refused naming both extents; a window clamped at the
 *   raster's border gives the nodes up to the border;
 * - terrain.window in a terrain file: read, checked with file:line, and
 *   handed to the world (its surface is the window's).
 * Skipped without GDAL. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <sys/resource.h>
#include <unistd.h>

#include "trajectory/terrain_internal.h"
#include "test_util.h"

#ifdef ROCKFUZZ_HAVE_GDAL
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#define BIG 40000
#define PATCH 300
#define PC0 20000 /* the patch's first column and row in the big raster */
#define PR0 15000
#define X0 600000.0
#define Y0 5140000.0 /* north edge of the big raster */

static char dir[64];

static const char *at(const char *name)
{
    static char buf[4][256];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

/* Patch value at patch column c, row r (north first), as a float: bilinear interpolation is not exact on it. */
static float patch_value(int c, int r) { return (float)(800 + 0.3 * c - 0.2 * r + 5 * sin(c / 7.0) * cos(r / 11.0)); }

static long peak_rss_kb(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

static GDALDatasetH create(const char *path, int w, int h, double x0, double y0, char **opt)
{
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path, w, h, 1, GDT_Float32, opt);
    assert_non_null(ds);
    double gt[6] = {x0, 1, 0, y0, 0, -1};
    assert_int_equal(GDALSetGeoTransform(ds, gt), CE_None);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    assert_int_equal(OSRImportFromEPSG(srs, 32632), OGRERR_NONE);
    GDALSetSpatialRef(ds, srs);
    OSRDestroySpatialReference(srs);
    return ds;
}

static void write_patch(GDALDatasetH ds, int c0, int r0)
{
    float *v = malloc(PATCH * PATCH * sizeof *v);
    assert_non_null(v);
    for (int r = 0; r < PATCH; r++)
        for (int c = 0; c < PATCH; c++)
            v[r * PATCH + c] = patch_value(c, r);
    assert_int_equal(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, c0, r0, PATCH, PATCH, v, PATCH, PATCH,
                                  GDT_Float32, 0, 0), CE_None);
    free(v);
}

/* big.tif (sparse, tiled, BigTIFF) and small.tif (the patch alone). */
static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/rockfuzz-demwin-XXXXXX");
    if (!mkdtemp(dir))
        return -1;
    GDALAllRegister();
    char **opt = CSLSetNameValue(NULL, "SPARSE_OK", "TRUE");
    opt = CSLSetNameValue(opt, "TILED", "YES");
    opt = CSLSetNameValue(opt, "BIGTIFF", "YES");
    GDALDatasetH big = create(at("big.tif"), BIG, BIG, X0, Y0, opt);
    CSLDestroy(opt);
    write_patch(big, PC0, PR0);
    GDALClose(big);
    GDALDatasetH small = create(at("small.tif"), PATCH, PATCH, X0 + PC0, Y0 - PR0, NULL);
    write_patch(small, 0, 0);
    GDALClose(small);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* ---- the profile ---- */

static void load_profile(const char *dem, rf_traj_spec *s)
{
    char yaml[1024];
    /* a line inside the patch, in map metres (the patch spans x 620000..620300, y 5124700..5125000) */
    snprintf(yaml, sizeof yaml,
             "profile: {dem: {file: %s, line: [[620020.25, 5124980.5], [620150.75, 5124850.125], "
             "[620270.5, 5124720.75]], step: 0.7}, material: m}\n"
             "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30}}\nblock: {mass: 1}\nrelease: {x: 1, y: 900}\n",
             dem);
    rf_error err;
    if (rf_traj_load_buffer("cut.yaml", yaml, strlen(yaml), s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

static void test_profile_window(void **state)
{
    (void)state;
    rf_traj_spec small, big;
    load_profile(at("small.tif"), &small);
    long rss0 = peak_rss_kb();
    load_profile(at("big.tif"), &big);
    long grown = peak_rss_kb() - rss0;
    print_message("profile cut of the 40000^2 DEM: peak RSS grew by %ld kB, %zu points\n", grown, big.n_points);
    assert_true(grown < 64 * 1024);
    assert_true(small.n_points > 300);
    assert_int_equal(big.n_points, small.n_points);
    for (size_t i = 0; i < big.n_points; i++) {
        if (memcmp(&big.px[i], &small.px[i], sizeof(double)) || memcmp(&big.py[i], &small.py[i], sizeof(double)))
            fail_msg("point %zu: big (%.17g, %.17g), small (%.17g, %.17g)", i, big.px[i], big.py[i], small.px[i],
                     small.py[i]);
    }
    rf_traj_spec_free(&small);
    rf_traj_spec_free(&big);
}

/* ---- the terrain ---- */

static rf_terrain *read_window(const char *path, const double *win)
{
    rf_terrain *t;
    rf_error err;
    if (rf_terrain_read_window(path, 1, win, &t, &err) != RF_OK)
        fail_msg("%s", err.msg);
    return t;
}

static void same_bits(double a, double b, const char *what, double x, double y)
{
    if (memcmp(&a, &b, sizeof a))
        fail_msg("%s at (%.10g, %.10g): %.17g != %.17g", what, x, y, a, b);
}

static void test_terrain_window(void **state)
{
    (void)state;
    rf_terrain *whole = read_window(at("small.tif"), NULL);
    /* node centres of the patch at X0 + PC0 + k + 0.5: a window 0.3 m inside the outer ones needs all of them */
    const double xs = X0 + PC0, yn = Y0 - PR0;
    const double win[4] = {xs + 1.2, yn - PATCH + 1.2, xs + PATCH - 1.2, yn - 1.2};
    long rss0 = peak_rss_kb();
    rf_terrain *part = read_window(at("big.tif"), win);
    long grown = peak_rss_kb() - rss0;
    print_message("terrain window of the 40000^2 DEM: peak RSS grew by %ld kB\n", grown);
    assert_true(grown < 64 * 1024);
    double e1[6], e2[6];
    rf_terrain_extent(whole, &e1[0], &e1[1], &e1[2], &e1[3], &e1[4], &e1[5]);
    rf_terrain_extent(part, &e2[0], &e2[1], &e2[2], &e2[3], &e2[4], &e2[5]);
    assert_memory_equal(e1, e2, sizeof e1);
    assert_int_equal(part->nx, PATCH);
    assert_int_equal(part->ny, PATCH);
    for (size_t j = 0; j < PATCH; j++)
        for (size_t i = 0; i < PATCH; i++) {
            same_bits(part->z[j * PATCH + i], whole->z[j * PATCH + i], "node", (double)i, (double)j);
            /* the raster's value itself: row PATCH - 1 - j of the patch */
            same_bits(part->z[j * PATCH + i], patch_value((int)i, (int)(PATCH - 1 - j)), "node value", (double)i,
                      (double)j);
        }
    for (double x = e1[0]; x <= e1[1]; x += 7.37)
        for (double y = e1[2]; y <= e1[3]; y += 5.91) {
            double z1, z2, n1[3], n2[3];
            assert_int_equal(rf_terrain_height(whole, x, y, &z1, n1), 1);
            assert_int_equal(rf_terrain_height(part, x, y, &z2, n2), 1);
            same_bits(z1, z2, "height", x, y);
            same_bits(n1[0], n2[0], "normal", x, y);
        }
    rf_terrain_free(part);
    rf_terrain_free(whole);
}

static void test_terrain_refusals(void **state)
{
    (void)state;
    rf_terrain *t = (rf_terrain *)1;
    rf_error err;
    long rss0 = peak_rss_kb();
    assert_int_equal(rf_terrain_read_window(at("big.tif"), 1, NULL, &t, &err), RF_EINVAL);
    assert_null(t);
    assert_true(peak_rss_kb() - rss0 < 64 * 1024);
    if (!strstr(err.msg, at("big.tif")) || !strstr(err.msg, "(40000 x 40000 cells): the whole DEM (no terrain.window)")
        || !strstr(err.msg, "which would take 14.40 GB of memory; at most 1048576 cells per side, 2147483648 in all and 4.29 GB are read") || !strstr(err.msg, "terrain.window"))
        fail_msg("%s", err.msg);
    const double outside[4] = {X0 - 500, Y0 - 100, X0 - 10, Y0 - 50};
    assert_int_equal(rf_terrain_read_window(at("big.tif"), 1, outside, &t, &err), RF_EINVAL);
    if (!strstr(err.msg, "terrain.window [599500, 5139900, 599990, 5139950] lies outside its extent "
                         "[600000, 5100000, 640000, 5140000]"))
        fail_msg("%s", err.msg);
    /* a window reaching beyond the small DEM's west and north edges: clamped to its border */
    const double xs = X0 + PC0, yn = Y0 - PR0, edge[4] = {xs - 50, yn - 10.2, xs + 3.4, yn + 50};
    rf_terrain *part = read_window(at("small.tif"), edge);
    assert_int_equal(part->nx, 4);  /* centres 0.5 .. 2.5 east of the edge, and 3.5 beyond 3.4 */
    assert_int_equal(part->ny, 11); /* centres 0.5 .. 9.5 south of the north edge, and 10.5 beyond 10.2 */
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(part, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    assert_true(xmin == xs + 0.5 && xmax == xs + 3.5 && ymax == yn - 0.5 && ymin == yn - 10.5);
    assert_true(part->z[(part->ny - 1) * part->nx] == patch_value(0, 0));
    rf_terrain_free(part);
}

/* ---- terrain.window in a terrain file ---- */

static const char *terrain_fmt =
    "name: w\n"
    "terrain: {dem: %s, material: rock%s}\n"
    "materials: {rock: {R_n: 0.5, R_t: 0.8, friction_angle: 30}}\n"
    "block: {shape: sphere, radius: 0.5, density: 2600}\n"
    "release: {points: [[620150, 5124850]], height: 1.0, velocity: [0, 0, 0]}\n"
    "bounce: {law: constant}\nsamples: 4\nseed: 1\n";

static rf_status load_terrain(const char *window, rf_traj_spec *s, rf_error *err)
{
    char yaml[2048];
    snprintf(yaml, sizeof yaml, terrain_fmt, at("big.tif"), window);
    return rf_traj_load_buffer("w.yaml", yaml, strlen(yaml), s, err);
}

static void test_terrain_file_window(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    if (load_terrain(", window: [620010, 5124710, 620290, 5124990]", &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_true(s.terrain->has_window);
    assert_true(s.terrain->window[0] == 620010 && s.terrain->window[3] == 5124990);
    rf_terrain_world *w = NULL;
    long rss0 = peak_rss_kb();
    if (rf_terrain_world_create(&s, &w, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_true(peak_rss_kb() - rss0 < 64 * 1024);
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(w->dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    assert_true(xmin == 620009.5 && xmax == 620290.5 && ymin == 5124709.5 && ymax == 5124990.5);
    rf_terrain_world_free(w);
    rf_traj_spec_free(&s);
    /* without a window: the whole DEM, refused before allocating */
    if (load_terrain("", &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(rf_terrain_world_create(&s, &w, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "14.40 GB"));
    rf_traj_spec_free(&s);
    static const char *const bad[][2] = {
        {", window: [620290, 5124710, 620010, 5124990]", "w.yaml:2: terrain.window"},
        {", window: [620010, 5124710, 620290]", "w.yaml:2: terrain.window"},
        {", window: [1e300, 5124710, 620290, 5124990]", "is not a map coordinate"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        assert_int_not_equal(load_terrain(bad[k][0], &s, &err), RF_OK);
        if (!strstr(err.msg, bad[k][1]))
            fail_msg("%s: %s", bad[k][0], err.msg);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_profile_window),
        cmocka_unit_test(test_terrain_window),
        cmocka_unit_test(test_terrain_refusals),
        cmocka_unit_test(test_terrain_file_window),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

#else

static void test_without_gdal(void **state)
{
    (void)state;
    skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_without_gdal)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#endif
