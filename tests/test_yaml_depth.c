/* test_yaml_depth.c - deeply nested flow collections are refused before
 * libfyaml parses them (issue 31 item 14: 4 MB of '[' as a trajectory file
 * took over 30 s and 1 GB before an error; 16 MB 5.5 GB):
 * - 4 MB of '[' and 4 MB of '{a: ' as a trajectory file and as a study file:
 *   refused naming file:line:column and the limit, in well under a second,
 *   peak RSS growing by less than 64 MB;
 * - 62 levels in a mapping load (libfyaml's own limit is 63 levels in all,
 *   checked after its parse), 65 are refused at the 65th bracket's column;
 * - brackets that open nothing are not counted: in quoted scalars (with
 *   escapes), comments, and plain scalars ("a[1]"), so a file holding 100 of
 *   each loads. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <sys/resource.h>
#include <time.h>

#include "core/yaml.h"
#include "rockfuzz/study.h"
#include "rockfuzz/trajectory.h"
#include "test_util.h"

static long peak_rss_kb(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* n copies of unit. */
static char *repeat(const char *unit, size_t n, size_t *len)
{
    size_t u = strlen(unit);
    char *b = malloc(u * n + 1);
    assert_non_null(b);
    for (size_t k = 0; k < n; k++)
        memcpy(b + k * u, unit, u);
    b[u * n] = '\0';
    *len = u * n;
    return b;
}

static void test_deep_refused_at_once(void **state)
{
    (void)state;
    static const char *const units[] = {"[", "{a: "};
    for (int u = 0; u < 2; u++) {
        size_t len;
        char *b = repeat(units[u], (4u << 20) / strlen(units[u]), &len);
        rf_error err;
        long rss0 = peak_rss_kb();
        double t0 = now();
        rf_traj_spec s;
        assert_int_not_equal(rf_traj_load_buffer("deep.yaml", b, len, &s, &err), RF_OK);
        char want[128]; /* the 65th opening bracket */
        snprintf(want, sizeof want, "deep.yaml:1: column %zu: collections nested deeper than 64 levels",
                 64 * strlen(units[u]) + 1);
        if (!strstr(err.msg, want))
            fail_msg("%s", err.msg);
        rf_study st;
        assert_int_not_equal(rf_study_load_buffer("deep_study.yaml", b, len, &st, &err), RF_OK);
        assert_non_null(strstr(err.msg, "deep_study.yaml:1: column "));
        assert_non_null(strstr(err.msg, "nested deeper than 64 levels"));
        double dt = now() - t0;
        long grown = peak_rss_kb() - rss0;
        print_message("4 MB of '%s': refused in %.3f s, peak RSS +%ld kB\n", units[u], dt, grown);
        assert_true(dt < 1.0 && grown < 64 * 1024);
        free(b);
    }
}

static rf_status load(const char *text, rf_error *err)
{
    yr_doc d;
    rf_status st = yr_doc_load(&d, "n.yaml", text, strlen(text), "test file", err);
    yr_doc_free(&d);
    return st;
}

static void test_limit(void **state)
{
    (void)state;
    size_t a, b;
    char *open64 = repeat("[", 64, &a), *close64 = repeat("]", 64, &b);
    char text[512];
    rf_error err;
    /* libfyaml itself takes 63 levels (the mapping and 62 sequences here) */
    snprintf(text, sizeof text, "x: %s1%s\n", open64 + 2, close64 + 2);
    if (load(text, &err) != RF_OK)
        fail_msg("%s", err.msg);
    snprintf(text, sizeof text, "x:\n  - %s[1]%s\n", open64, close64);
    assert_int_equal(load(text, &err), RF_EPARSE);
    if (!strstr(err.msg, "n.yaml:2: column 69: collections nested deeper than 64 levels"))
        fail_msg("%s", err.msg);
    free(open64), free(close64);
}

static void test_not_counted(void **state)
{
    (void)state;
    size_t n;
    char *br = repeat("[", 100, &n), text[2048];
    rf_error err;
    snprintf(text, sizeof text,
             "a: \"%s \\\" %s\"\n"  /* double-quoted, with an escaped quote */
             "b: '%s '' %s'\n"      /* single-quoted */
             "c: a%s\n"             /* plain scalar */
             "# %s\n"               /* comment */
             "d: [1, 2]  # %s\n", br, br, br, br, br, br, br);
    if (load(text, &err) != RF_OK)
        fail_msg("%s", err.msg);
    free(br);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_deep_refused_at_once),
        cmocka_unit_test(test_limit),
        cmocka_unit_test(test_not_counted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
