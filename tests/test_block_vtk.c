/* test_block_vtk.c - ParaView output of a block (block_vtk.c): a tumbling
 * box (1 x 2 x 3 m, free flight) written at five times gives stem.pvd with
 * five data sets at those times and five .vtp files, each with the hull's
 * 8 points and 12 triangles, the points equal to x + R(q) p_body of the
 * body-frame hull at that pose (to 1e-12 m; printed with 17 digits), the
 * triangles the hull's; a sphere's tessellation has its points on the
 * sphere and encloses the right side (the signed volume of its triangles is
 * positive and below 4/3 pi r^3); the files are well-formed XML (python3's
 * minidom, when python3 is there); bad arguments are refused with a message. */
#define _XOPEN_SOURCE 700 /* mkdtemp */
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

#include "rockfuzz/block.h"

#define PI 3.14159265358979323846

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *s = malloc((size_t)n + 1);
    assert_non_null(s);
    assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
    s[n] = 0;
    fclose(f);
    return s;
}

static long attr(const char *s, const char *name)
{
    const char *p = strstr(s, name);
    assert_non_null(p);
    return strtol(p + strlen(name) + 2, NULL, 10); /* name="N" */
}

/* The n numbers after the first "format=\"ascii\">" following tag. */
static void numbers(const char *s, const char *tag, double *out, size_t n)
{
    const char *p = strstr(s, tag);
    assert_non_null(p);
    p = strstr(p, "format=\"ascii\">");
    assert_non_null(p);
    p += strlen("format=\"ascii\">");
    for (size_t i = 0; i < n; i++) {
        char *end;
        out[i] = strtod(p, &end);
        assert_true(end != p);
        p = end;
    }
}

/* Every file in dir parses as XML (one python3 start: they are slow on a loaded machine). */
static void well_formed(const char *dir)
{
    if (system("command -v python3 >/dev/null 2>&1") != 0)
        return;
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "python3 -c 'import sys, glob, xml.dom.minidom as m\n"
                              "for f in glob.glob(sys.argv[1] + \"/*\"): m.parse(f)' %s", dir);
    if (system(cmd) != 0)
        fail_msg("a file in %s is not well-formed XML", dir);
}

static void clean(const char *dir, const char *stem, size_t n)
{
    char path[512];
    for (size_t k = 0; k < n; k++) {
        snprintf(path, sizeof path, "%s/%s_%04zu.vtp", dir, stem, k);
        unlink(path);
    }
    snprintf(path, sizeof path, "%s/%s.pvd", dir, stem);
    unlink(path);
}

static void test_tumbling_box(void **state)
{
    (void)state;
    char dir[] = "/tmp/rf-test-block-vtk-XXXXXX";
    assert_non_null(mkdtemp(dir));
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_box(1, 2, 3, 2650, &s, &err), RF_OK);
    rf_block_state st[5] = {{{10, 20, 30}, {1, 0, 0, 0}, {4, 1, 2}, {0.3, 2.0, 0.5}}};
    double t[5] = {0, 0.25, 0.5, 0.75, 1.0};
    for (int k = 1; k < 5; k++) {
        st[k] = st[k - 1];
        for (int i = 0; i < 250; i++)
            rf_block_flight_step(&s, &st[k], 9.81, 1e-3);
    }
    assert_int_equal(rf_block_write_vtk(dir, "box", &s, st, t, 5, &err), RF_OK);
    char path[512];
    well_formed(dir);
    snprintf(path, sizeof path, "%s/box.pvd", dir);
    char *pvd = slurp(path), *p = pvd;
    for (int k = 0; k < 5; k++) {
        char want[128];
        snprintf(want, sizeof want, "timestep=\"%.17g\" group=\"\" part=\"0\" file=\"box_%04d.vtp\"", t[k], k);
        p = strstr(p, want);
        if (!p)
            fail_msg("box.pvd lacks (in order) %s", want);
    }
    assert_null(strstr(p + 1, "<DataSet"));
    free(pvd);
    for (int k = 0; k < 5; k++) {
        snprintf(path, sizeof path, "%s/box_%04d.vtp", dir, k);
        char *v = slurp(path);
        assert_int_equal(attr(v, "NumberOfPoints"), 8);
        assert_int_equal(attr(v, "NumberOfPolys"), 12);
        double x[24], conn[36], off[12], time;
        numbers(v, "Name=\"TimeValue\"", &time, 1);
        assert_true(time == t[k]);
        numbers(v, "<Points>", x, 24);
        numbers(v, "Name=\"connectivity\"", conn, 36);
        numbers(v, "Name=\"offsets\"", off, 12);
        for (int i = 0; i < 8; i++) {
            double p3[3];
            rf_block_to_space(st[k].q, s.vertices + 3 * i, p3);
            for (int j = 0; j < 3; j++)
                if (fabs(x[3 * i + j] - (st[k].x[j] + p3[j])) > 1e-12)
                    fail_msg("state %d, point %d, axis %d: %.17g, want %.17g", k, i, j, x[3 * i + j],
                             st[k].x[j] + p3[j]);
        }
        for (int i = 0; i < 36; i++)
            assert_true(conn[i] == s.faces[i]);
        for (int i = 0; i < 12; i++)
            assert_true(off[i] == 3 * (i + 1));
        free(v);
    }
    /* the box did tumble: the last pose is not the first */
    assert_true(fabs(st[4].q[0] - st[0].q[0]) > 0.1);
    clean(dir, "box", 5);
    rmdir(dir);
    rf_block_shape_free(&s);
}

static void test_sphere_tessellation(void **state)
{
    (void)state;
    char dir[] = "/tmp/rf-test-block-vtk-XXXXXX";
    assert_non_null(mkdtemp(dir));
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_sphere(0.5, 2650, &s, &err), RF_OK);
    rf_block_state st = {{1, 2, 3}, {0.5, 0.5, 0.5, 0.5}, {0}, {0}};
    double t = 2.5;
    assert_int_equal(rf_block_write_vtk(dir, "ball", &s, &st, &t, 1, &err), RF_OK);
    char path[512];
    well_formed(dir);
    snprintf(path, sizeof path, "%s/ball_0000.vtp", dir);
    char *v = slurp(path);
    long np = attr(v, "NumberOfPoints"), nt = attr(v, "NumberOfPolys");
    assert_int_equal(np, 2 + 11 * 24);
    assert_int_equal(nt, 2 * 24 * 11);
    double *x = malloc(3 * (size_t)np * sizeof *x), *c = malloc(3 * (size_t)nt * sizeof *c);
    numbers(v, "<Points>", x, 3 * (size_t)np);
    numbers(v, "Name=\"connectivity\"", c, 3 * (size_t)nt);
    for (long i = 0; i < np; i++)
        assert_true(fabs(hypot(hypot(x[3 * i] - 1, x[3 * i + 1] - 2), x[3 * i + 2] - 3) - 0.5) < 1e-12);
    double vol = 0; /* sum of a . (b x c) / 6 about the centre: positive when outward */
    for (long k = 0; k < nt; k++) {
        double p[3][3];
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 3; i++)
                p[j][i] = x[3 * (long)c[3 * k + j] + i] - (double[]){1, 2, 3}[i];
        vol += (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) - p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) / 6;
    }
    double exact = 4.0 / 3 * PI * 0.125;
    if (!(vol > 0.95 * exact && vol < exact))
        fail_msg("tessellation volume %.6g, want just below %.6g", vol, exact);
    free(x), free(c), free(v);
    clean(dir, "ball", 1);
    rmdir(dir);
    rf_block_shape_free(&s);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_sphere(0.5, 2650, &s, &err), RF_OK);
    rf_block_state st[2] = {{{0, 0, 0}, {1, 0, 0, 0}, {0}, {0}}, {{0, 0, 0}, {1, 0, 0, 0}, {0}, {0}}};
    double t[2] = {1, 1};
    assert_int_equal(rf_block_write_vtk("/tmp", "a/b", &s, st, t, 1, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "a/b"));
    assert_int_equal(rf_block_write_vtk("/tmp", "x", &s, st, t, 2, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "times[1]"));
    assert_int_equal(rf_block_write_vtk("/nonexistent-rf-dir", "x", &s, st, t, 1, &err), RF_EIO);
    assert_non_null(strstr(err.msg, "/nonexistent-rf-dir/x_0000.vtp"));
    rf_block_shape_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tumbling_box),
        cmocka_unit_test(test_sphere_tessellation),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
