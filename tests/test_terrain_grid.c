/* test_terrain_grid.c - the terrain surface from nodes (terrain_grid.c):
 * - a plane's height and normal are exact at random points (bilinear
 *   interpolation reproduces a plane);
 * - on a curved surface the height equals the textbook bilinear weights of
 *   the four nodes, and the normal equals (-dz/dx, -dz/dy, 1) / |.| from
 *   central differences of rf_terrain_height (on a bilinear cell z is linear
 *   in x at fixed y and in y at fixed x, so the differences are exact up to
 *   rounding);
 * - terrain_cell_of at the grid's edges and corners (east / north cell on a
 *   shared edge, the last cell at the last row or column, outside beyond);
 * - a no-data node makes exactly the cells around it outside;
 * - bad spacing and sizes are refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "trajectory/terrain_internal.h"
#include "test_util.h"

#define NX 7
#define NY 5

static const double X0 = 600000.5, Y0 = 5100000.25, DX = 2.0, DY = 3.0;

/* A reproducible uniform in [0, 1). */
static double uni(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static double plane(double x, double y) { return 812.5 - 0.35 * (x - X0) + 0.62 * (y - Y0); }
static double curved(double x, double y)
{
    double u = (x - X0) / 10, v = (y - Y0) / 10;
    return 100 + 7 * sin(u) * cos(1.3 * v) + u * u * v;
}

static rf_terrain *make(double (*f)(double, double))
{
    double z[NX * NY];
    for (int j = 0; j < NY; j++)
        for (int i = 0; i < NX; i++)
            z[j * NX + i] = f(X0 + i * DX, Y0 + j * DY);
    rf_terrain *t;
    rf_error err;
    if (rf_terrain_from_nodes(NX, NY, X0, Y0, DX, DY, z, &t, &err) != RF_OK)
        fail_msg("%s", err.msg);
    return t;
}

static void test_plane_exact(void **state)
{
    (void)state;
    rf_terrain *t = make(plane);
    uint64_t s = 1;
    double nn = sqrt(1 + 0.35 * 0.35 + 0.62 * 0.62);
    for (int k = 0; k < 2000; k++) {
        double x = X0 + uni(&s) * (NX - 1) * DX, y = Y0 + uni(&s) * (NY - 1) * DY, z, n[3];
        assert_int_equal(rf_terrain_height(t, x, y, &z, n), 1);
        assert_true(fabs(z - plane(x, y)) < 1e-9);
        assert_true(fabs(n[0] - 0.35 / nn) < 1e-12 && fabs(n[1] + 0.62 / nn) < 1e-12 && fabs(n[2] - 1 / nn) < 1e-12);
    }
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(t, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    assert_true(xmin == X0 && ymin == Y0 && xmax == X0 + (NX - 1) * DX && ymax == Y0 + (NY - 1) * DY);
    assert_true(dx == DX && dy == DY);
    assert_string_equal(rf_terrain_crs_wkt(t), "");
    rf_terrain_free(t);
}

/* The bilinear interpolation written from its weights, independently of terrain_patch_of. */
static double bilinear(double x, double y)
{
    double fx = (x - X0) / DX, fy = (y - Y0) / DY;
    int i = (int)fx, j = (int)fy;
    double u = fx - i, v = fy - j;
    double xi = X0 + i * DX, yj = Y0 + j * DY;
    return (1 - u) * (1 - v) * curved(xi, yj) + u * (1 - v) * curved(xi + DX, yj) + (1 - u) * v * curved(xi, yj + DY) +
           u * v * curved(xi + DX, yj + DY);
}

static void test_curved_normal(void **state)
{
    (void)state;
    rf_terrain *t = make(curved);
    uint64_t s = 7;
    const double h = 1e-3;
    for (int k = 0; k < 2000; k++) {
        /* inside a cell, at least 2h from its edges: the differences stay in it */
        int i = (int)(uni(&s) * (NX - 1)), j = (int)(uni(&s) * (NY - 1));
        double x = X0 + (i + 0.01 + 0.98 * uni(&s)) * DX, y = Y0 + (j + 0.01 + 0.98 * uni(&s)) * DY;
        double z, n[3], zxp, zxm, zyp, zym;
        assert_int_equal(rf_terrain_height(t, x, y, &z, n), 1);
        assert_true(fabs(z - bilinear(x, y)) < 1e-9);
        assert_true(rf_terrain_height(t, x + h, y, &zxp, NULL) && rf_terrain_height(t, x - h, y, &zxm, NULL));
        assert_true(rf_terrain_height(t, x, y + h, &zyp, NULL) && rf_terrain_height(t, x, y - h, &zym, NULL));
        /* the steps as represented at these coordinates (x ~ 6e5: its ulp is 1e-10) */
        double hx = (x + h) - (x - h), hy = (y + h) - (y - h);
        double zx = (zxp - zxm) / hx, zy = (zyp - zym) / hy, m = sqrt(1 + zx * zx + zy * zy);
        double ref[3] = {-zx / m, -zy / m, 1 / m};
        for (int d = 0; d < 3; d++)
            if (fabs(n[d] - ref[d]) > 1e-8)
                fail_msg("normal[%d] = %.15g, finite differences %.15g at (%g, %g)", d, n[d], ref[d], x, y);
        assert_true(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-14);
    }
    rf_terrain_free(t);
}

static void expect_cell(const rf_terrain *t, double x, double y, size_t ei, size_t ej, double eu, double ev)
{
    size_t i = SIZE_MAX, j = SIZE_MAX;
    double u = NAN, v = NAN;
    if (!terrain_cell_of(t, x, y, &i, &j, &u, &v))
        fail_msg("(%g, %g) not in a cell", x - X0, y - Y0);
    if (i != ei || j != ej || fabs(u - eu) > 1e-12 || fabs(v - ev) > 1e-12)
        fail_msg("(%g, %g): cell (%zu, %zu) u %g v %g, expected (%zu, %zu) %g %g", x - X0, y - Y0, i, j, u, v, ei, ej, eu,
                 ev);
}

static void test_cell_of_edges(void **state)
{
    (void)state;
    rf_terrain *t = make(plane);
    double xe = X0 + (NX - 1) * DX, ye = Y0 + (NY - 1) * DY;
    expect_cell(t, X0, Y0, 0, 0, 0, 0);                         /* south-west corner */
    expect_cell(t, xe, ye, NX - 2, NY - 2, 1, 1);               /* north-east corner: the last cell */
    expect_cell(t, xe, Y0, NX - 2, 0, 1, 0);                    /* south-east */
    expect_cell(t, X0, ye, 0, NY - 2, 0, 1);                    /* north-west */
    expect_cell(t, X0 + 2 * DX, Y0 + 0.5 * DY, 2, 0, 0, 0.5);   /* shared vertical edge: the east cell */
    expect_cell(t, X0 + 0.5 * DX, Y0 + 3 * DY, 0, 3, 0.5, 0);   /* shared horizontal edge: the north cell */
    expect_cell(t, X0 + 3 * DX, Y0 + 2 * DY, 3, 2, 0, 0);       /* an inner node: the north-east cell */
    size_t i, j;
    double u, v, z;
    const double out[][2] = {{X0 - 1e-9, Y0}, {X0, Y0 - 1e-9}, {xe + 1e-9, ye}, {xe, ye + 1e-9}, {X0 - 5, Y0 + 4}};
    for (size_t k = 0; k < sizeof out / sizeof *out; k++) {
        assert_int_equal(terrain_cell_of(t, out[k][0], out[k][1], &i, &j, &u, &v), 0);
        assert_int_equal(rf_terrain_height(t, out[k][0], out[k][1], &z, NULL), 0);
    }
    assert_int_equal(rf_terrain_height(t, NAN, Y0, &z, NULL), 0);
    /* the corners give the nodes' heights */
    assert_true(rf_terrain_height(t, xe, ye, &z, NULL) && fabs(z - plane(xe, ye)) < 1e-10);
    assert_true(rf_terrain_height(t, X0, Y0, &z, NULL) && z == plane(X0, Y0));
    rf_terrain_free(t);
}

static void test_nodata_cells(void **state)
{
    (void)state;
    double z[NX * NY];
    for (int k = 0; k < NX * NY; k++)
        z[k] = 10 + k;
    z[2 * NX + 3] = NAN; /* an inner node: its four cells go */
    z[0] = NAN;          /* the south-west corner node: one cell */
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(NX, NY, X0, Y0, DX, DY, z, &t, &err), RF_OK);
    int out = 0;
    for (int j = 0; j + 1 < NY; j++)
        for (int i = 0; i + 1 < NX; i++) {
            int expect_out = (i == 0 && j == 0) || ((i == 2 || i == 3) && (j == 1 || j == 2));
            double zz, x = X0 + (i + 0.5) * DX, y = Y0 + (j + 0.5) * DY;
            assert_int_equal(rf_terrain_height(t, x, y, &zz, NULL), !expect_out);
            assert_int_equal(t->valid[j * (NX - 1) + i], !expect_out);
            out += expect_out;
        }
    assert_int_equal(out, 5);
    rf_terrain_free(t);
}

static void test_bad_input(void **state)
{
    (void)state;
    double z[4] = {0, 0, 0, 0};
    rf_terrain *t = (rf_terrain *)1;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(2, 2, 0, 0, 0, 1, z, &t, &err), RF_EINVAL);
    assert_null(t);
    assert_non_null(strstr(err.msg, "dx = 0"));
    assert_int_equal(rf_terrain_from_nodes(2, 2, 0, 0, 1, NAN, z, &t, &err), RF_EINVAL);
    assert_int_equal(rf_terrain_from_nodes(1, 4, 0, 0, 1, 1, z, &t, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "1 x 4 nodes"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plane_exact),   cmocka_unit_test(test_curved_normal), cmocka_unit_test(test_cell_of_edges),
        cmocka_unit_test(test_nodata_cells), cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
