/* test_trajectory_dem.c - a profile cut from a DEM along a polyline (GDAL):
 * an ESRI ASCII grid written here holding the plane
 * z = 50 - 0.3 (X - 1000) + 0.1 (Y - 2000) at the cell centres is cut
 * exactly (bilinear interpolation reproduces a plane), with x the distance
 * along the line; the same grid converted to GeoTIFF by gdal_translate gives
 * the same profile; a line leaving the grid is an error naming the field.
 * Skipped when rockfuzz is built without GDAL. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_util.h"

static double plane(double X, double Y) { return 50 - 0.3 * (X - 1000) + 0.1 * (Y - 2000); }

static void write_grid(void)
{
    FILE *f = fopen("traj_dem.asc", "w");
    assert_non_null(f);
    int nc = 30, nr = 20;
    double cs = 2, xll = 1000, yll = 2000;
    fprintf(f, "ncols %d\nnrows %d\nxllcorner %g\nyllcorner %g\ncellsize %g\nNODATA_value -9999\n", nc, nr, xll, yll, cs);
    for (int r = 0; r < nr; r++) {
        for (int c = 0; c < nc; c++)
            fprintf(f, "%.15g ", plane(xll + (c + 0.5) * cs, yll + (nr - r - 0.5) * cs));
        fputc('\n', f);
    }
    fclose(f);
}

static const char *yaml_fmt =
    "profile: {dem: {file: %s, line: [[1005, 2010], [1045, 2030], [1050, 2020]], step: 1.5}, material: m}\n"
    "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30}}\n"
    "block: {mass: 1}\n"
    "release: {x: 1, y: 80}\n";

static void check_profile(const char *file)
{
    char yaml[1024];
    snprintf(yaml, sizeof yaml, yaml_fmt, file);
    rf_traj_spec s;
    rf_error err;
    if (rf_traj_load_buffer("dem.yaml", yaml, strlen(yaml), &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    double L1 = hypot(40, 20), L2 = hypot(5, 10);
    assert_int_equal(s.n_points, 1 + (size_t)ceil(L1 / 1.5) + (size_t)ceil(L2 / 1.5));
    assert_true(s.px[0] == 0);
    assert_close(s.px[s.n_points - 1], L1 + L2, 1e-12);
    for (size_t i = 0; i < s.n_points; i++) {
        double d = s.px[i], X, Y;
        if (d <= L1)
            X = 1005 + 40 * d / L1, Y = 2010 + 20 * d / L1;
        else
            X = 1045 + 5 * (d - L1) / L2, Y = 2030 - 10 * (d - L1) / L2;
        assert_close(s.py[i], plane(X, Y), 1e-12);
    }
    rf_traj_spec_free(&s);
}

static void test_dem_cut(void **state)
{
    (void)state;
#ifndef ROCKFUZZ_HAVE_GDAL
    skip();
#endif
    write_grid();
    /* GDAL reads an ASCII grid with decimals as Float32 unless told otherwise:
     * ask for Float64 so that the check can be exact. */
    setenv("AAIGRID_DATATYPE", "Float64", 1);
    check_profile("traj_dem.asc");
    if (system("gdal_translate -q -ot Float64 -of GTiff traj_dem.asc traj_dem.tif > /dev/null 2>&1") == 0)
        check_profile("traj_dem.tif");
    else
        print_message("gdal_translate not available: GeoTIFF not checked\n");
    char yaml[1024];
    snprintf(yaml, sizeof yaml, yaml_fmt, "traj_dem.asc");
    char *p = strstr(yaml, "[1050, 2020]");
    memcpy(p, "[1090, 2020]", 12);
    rf_traj_spec s;
    rf_error err;
    assert_int_not_equal(rf_traj_load_buffer("dem.yaml", yaml, strlen(yaml), &s, &err), RF_OK);
    if (!strstr(err.msg, "dem.yaml:1: profile.dem.line") || !strstr(err.msg, "outside the DEM"))
        fail_msg("%s", err.msg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_dem_cut)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
