/* test_profile_csv.c - the strict profile CSV reader (issue 31 point 11): a
 * UTF-8 byte order mark does not cost a vertex, only a header naming the
 * columns is skipped, a long comment never becomes a vertex, empty fields,
 * NUL bytes, a fourth column, unknown or missing materials are errors naming
 * file:line, the field and the value; devices are refused (point 13).  Every
 * case goes through the public rf_traj_profile_read_csv on a real file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_util.h"

#define CSV "test_profile.csv"

static void write_bytes(const char *text, size_t len)
{
    FILE *f = fopen(CSV, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, len, f), len);
    assert_int_equal(fclose(f), 0);
}

static rf_traj_material mats[2] = {{"rock", 0.4, 0.7, 30, 0, 0, {0}}, {"soil", 0.3, 0.6, 35, 0, 0, {0}}};

static rf_status read_len(const char *text, size_t len, rf_traj_spec *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    s->n_materials = 2, s->materials = mats;
    write_bytes(text, len);
    return rf_traj_profile_read_csv(CSV, s, err);
}

static void free_points(rf_traj_spec *s) { free(s->px), free(s->py), free(s->seg_material); }

/* text reads to n vertices with x = xs[k], y = ys[k] and materials ms[k]. */
static void expect_points(const char *text, size_t len, size_t n, const double *xs, const double *ys, const size_t *ms)
{
    rf_traj_spec s;
    rf_error err = {0};
    rf_status st = read_len(text, len, &s, &err);
    if (st != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s.n_points, n);
    for (size_t k = 0; k < n; k++) {
        assert_true(s.px[k] == xs[k] && s.py[k] == ys[k]);
        if (ms && k + 1 < n)
            assert_int_equal(s.seg_material[k], ms[k]);
    }
    free_points(&s);
}

/* text fails with a message holding want1 and want2. */
static void expect_error(const char *text, size_t len, const char *want1, const char *want2)
{
    rf_traj_spec s;
    rf_error err = {0};
    rf_status st = read_len(text, len, &s, &err);
    if (st == RF_OK) {
        free_points(&s);
        fail_msg("accepted: '%s' (%zu points)", text, s.n_points);
    }
    if (!strstr(err.msg, want1) || (want2 && !strstr(err.msg, want2)))
        fail_msg("message '%s' lacks '%s' / '%s'", err.msg, want1, want2 ? want2 : "");
}

#define TXT(s) s, sizeof(s) - 1

static void test_bom_keeps_first_vertex(void **state)
{
    (void)state;
    const double x[3] = {0, 10, 20}, y[3] = {5, 0, -1};
    expect_points(TXT("\xEF\xBB\xBF" "0,5\n10,0\n20,-1\n"), 3, x, y, NULL);
    expect_points(TXT("\xEF\xBB\xBF" "x_m,y_m\r\n0,5\r\n10,0\r\n20,-1\r\n"), 3, x, y, NULL);
}

static void test_header_only_when_it_names_columns(void **state)
{
    (void)state;
    const double x[3] = {0, 10, 20}, y[3] = {5, 0, -1};
    const size_t m[2] = {1, 0};
    expect_points(TXT("# a profile\n\nx,y,material\n0,5,soil\n10,0,rock\n20,-1\n"), 3, x, y, m);
    expect_error(TXT("distance,height\n0,5\n10,0\n"), CSV ":1:", "distance");
    expect_error(TXT("0,5\nx,y\n10,0\n"), CSV ":2:", "x = x");
}

static void test_long_comment_is_no_vertex(void **state)
{
    (void)state;
    char text[9000];
    size_t n = (size_t)snprintf(text, sizeof text, "0,5\n#");
    memset(text + n, 'c', 4094), n += 4094; /* fgets(4096) would cut "7,7" off as a line */
    n += (size_t)snprintf(text + n, sizeof text - n, "7,7\n10,0\n");
    const double x[2] = {0, 10}, y[2] = {5, 0};
    expect_points(text, n, 2, x, y, NULL);
}

static void test_empty_and_extra_fields(void **state)
{
    (void)state;
    expect_error(TXT("0,,20\n10,0\n"), CSV ":1:", "y is empty");
    expect_error(TXT("0,5\n,0\n"), CSV ":2:", "x is empty");
    expect_error(TXT("0,5,\n10,0\n"), CSV ":1:", "material is empty");
    expect_error(TXT("0,5,rock,9\n10,0\n"), CSV ":1:", "more than 3 fields");
    expect_error(TXT("0 5\n10,0\n"), CSV ":1:", "x = 0 5");
    expect_error(TXT("0,5\n10,1e999\n"), CSV ":2:", "y = 1e999");
    expect_error(TXT("0;5\n10;0\n"), CSV ":1:", "0;5");
}

static void test_nul_refused(void **state)
{
    (void)state;
    expect_error(TXT("0,5\n10\0,0\n20,0\n"), CSV ":2:", "NUL");
}

static void test_materials(void **state)
{
    (void)state;
    expect_error(TXT("0,5,rock\n10,0,clay\n20,0\n"), CSV ":2:", "material = clay");
    expect_error(TXT("0,5,rock\n10,0\n20,0,rock\n30,0\n"), CSV ":2:", "no material");
    expect_error(TXT("x,y\n0,5\n"), "1 points", NULL);
}

static void test_device_refused(void **state)
{
    (void)state;
    rf_traj_spec s;
    memset(&s, 0, sizeof s);
    rf_error err = {0};
    assert_int_not_equal(rf_traj_profile_read_csv("/dev/zero", &s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "not a regular file"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bom_keeps_first_vertex),
        cmocka_unit_test(test_header_only_when_it_names_columns),
        cmocka_unit_test(test_long_comment_is_no_vertex),
        cmocka_unit_test(test_empty_and_extra_fields),
        cmocka_unit_test(test_nul_refused),
        cmocka_unit_test(test_materials),
        cmocka_unit_test(test_device_refused),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    remove(CSV);
    return rc;
}
