/* test_external.c - the external-program model, driven with standard tools
 * (awk, cat, printf, sleep) executed directly, never through a shell. */
#undef _POSIX_C_SOURCE
#define _XOPEN_SOURCE 700 /* nftw */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/model.h"

#include <dirent.h>
#include <ftw.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static char root[64]; /* per-run scratch directory; eval dirs go below it */

static const char *const ab[] = {"a", "b"};

static int rm_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    remove(path);
    return 0;
}

static int setup(void **state)
{
    (void)state;
    snprintf(root, sizeof root, "/tmp/rf-test-external-XXXXXX");
    return mkdtemp(root) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    nftw(root, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
    return 0;
}

/* A fresh workdir root per test, so tests can count what was left behind. */
static char *fresh_root(const char *name)
{
    static char path[160];
    snprintf(path, sizeof path, "%s/%s", root, name);
    return path;
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += e->d_name[0] != '.';
    closedir(d);
    return n;
}

/* The one eval-* directory under dir (kept by keep_workdirs or failure). */
static void only_entry(const char *dir, char *out, size_t size)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    out[0] = '\0';
    for (struct dirent *e; (e = readdir(d));) {
        if (e->d_name[0] != '.')
            snprintf(out, size, "%s/%s", dir, e->d_name);
    }
    closedir(d);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    static char buf[4096];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    return buf;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static rf_external_spec spec_of(size_t argc, char **argv, size_t n_outputs, rf_external_output *outputs,
                                const char *workdir)
{
    rf_external_spec s;
    memset(&s, 0, sizeof s);
    s.argc = argc;
    s.argv = argv;
    s.n_outputs = n_outputs;
    s.outputs = outputs;
    s.timeout = 10;
    s.workdir_root = (char *)workdir;
    return s;
}

static void test_stdout_named_values(void **state)
{
    (void)state;
    char *argv[] = {"awk", "BEGIN{printf \"y = %.17g\\nz: %.17g\\n  w %.17g m\\nyy = 99\\n\", ({a})*({b}), "
                           "({a})+({b}), ({a})-({b})}"};
    rf_external_output out[] = {{"y", NULL, NULL, "m^2"}, {"z", NULL, NULL, NULL}, {"w", NULL, NULL, NULL}};
    const char *wd = fresh_root("named");
    rf_external_spec s = spec_of(2, argv, 3, out, wd);
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
    assert_int_equal(m.n_inputs, 2);
    assert_int_equal(m.n_outputs, 3);
    assert_string_equal(m.output_units[0], "m^2");
    assert_string_equal(m.output_units[1], "");
    print_message("identity: %s\n", m.identity);
    const double xs[][2] = {{3, 4}, {-2.5, 0.1}, {1e-300, 7e12}};
    for (size_t t = 0; t < 3; t++) {
        double y[3];
        if (rf_model_eval(&m, xs[t], y, &err) != RF_OK)
            fail_msg("%s", err.msg);
        /* %.17g round-trips, so awk sees exactly the double we passed. */
        assert_true(y[0] == xs[t][0] * xs[t][1]);
        assert_true(y[1] == xs[t][0] + xs[t][1]);
        assert_true(y[2] == xs[t][0] - xs[t][1]);
    }
    assert_int_equal(count_entries(wd), 0); /* removed after success */
    rf_model_free(&m);
}

static void test_template_and_file_output(void **state)
{
    (void)state;
    char tpl[160];
    snprintf(tpl, sizeof tpl, "%s/in.txt.tpl", root);
    write_text(tpl, "{a}\n{{a} stays literal, {b} is b, { also }\n");
    char *argv[] = {"awk", "NR == 1 {print \"z:\", $1*2 > \"other.txt\"}", "in.txt"};
    rf_external_output out[] = {{"z", "sub/out.txt", NULL, NULL}};
    const char *wd = fresh_root("template");
    rf_external_spec s = spec_of(3, argv, 1, out, wd);
    char *src[] = {tpl}, *dst[] = {"in.txt"};
    s.n_templates = 1;
    s.template_src = src;
    s.template_dst = dst;
    rf_model m;
    rf_error err = {0};
    /* The program writes another file than the one the output names. */
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
    double x[2] = {1.25, 8}, y;
    assert_int_equal(rf_model_eval(&m, x, &y, &err), RF_EMODEL);
    print_message("missing file: %s\n", err.msg);
    assert_non_null(strstr(err.msg, "program 'awk' at (a=1.25, b=8): output 'z': cannot read sub/out.txt: No such file"));
    assert_non_null(strstr(err.msg, "working directory kept: "));
    rf_model_free(&m);

    argv[1] = "NR == 1 {print \"z:\", $1*2 > \"out.txt\"}";
    out[0].file = "out.txt";
    s.keep_workdirs = 1;
    s.workdir_root = fresh_root("template-ok");
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
    if (rf_model_eval(&m, x, &y, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_true(y == 2.5);
    char dir[400], path[480];
    only_entry(s.workdir_root, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/in.txt", dir);
    assert_string_equal(slurp(path), "1.25\n{a} stays literal, 8 is b, { also }\n");

    /* The template's contents are part of the identity. */
    char *id1 = strdup(m.identity);
    rf_model_free(&m);
    write_text(tpl, "{a}\n");
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
    assert_string_not_equal(id1, m.identity);
    free(id1);
    rf_model_free(&m);
}

static void test_regex_outputs(void **state)
{
    (void)state;
    char *argv[] = {"printf", "header\nresult: value=%s [m]\n force  %s D-format\n", "{a}", "1.5D-03"};
    rf_external_output out[] = {{"deflection", NULL, "value=([-+0-9.eE]+)", "m"},
                                {"force", NULL, "^ *force +([^ ]+)", "N"}};
    rf_external_spec s = spec_of(4, argv, 2, out, fresh_root("regex"));
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_external_model_create(&s, 1, ab, &m, &err), RF_OK);
    double x = -1.25e-3, y[2];
    if (rf_model_eval(&m, &x, y, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_true(y[0] == -1.25e-3);
    assert_true(y[1] == 1.5e-3);
    rf_model_free(&m);

    rf_external_output none[] = {{"d", NULL, "value=[0-9]+", NULL}};
    s.outputs = none;
    s.n_outputs = 1;
    assert_int_equal(rf_external_model_create(&s, 1, ab, &m, &err), RF_EINVAL);
    print_message("no group: %s\n", err.msg);
    assert_non_null(strstr(err.msg, "capture group"));
    rf_external_output bad[] = {{"d", NULL, "value=([0-9]+", NULL}};
    s.outputs = bad;
    assert_int_equal(rf_external_model_create(&s, 1, ab, &m, &err), RF_EINVAL);
    print_message("bad regex: %s\n", err.msg);
    assert_non_null(strstr(err.msg, "invalid pattern"));
}

static void test_timeout_kills_quickly(void **state)
{
    (void)state;
    char *argv[] = {"sleep", "10"};
    rf_external_output out[] = {{"y", NULL, NULL, NULL}};
    rf_external_spec s = spec_of(2, argv, 1, out, fresh_root("timeout"));
    s.timeout = 0.5;
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    double x[2] = {1, 2}, y;
    assert_int_equal(rf_model_eval(&m, x, &y, &err), RF_EMODEL);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    print_message("after %.3f s: %s\n", seconds, err.msg);
    assert_true(seconds >= 0.5 && seconds < 2.0);
    assert_non_null(strstr(err.msg, "program 'sleep' timed out after 0.5 s at (a=1, b=2)"));
    assert_non_null(strstr(err.msg, "working directory kept: "));
    assert_int_equal(count_entries(s.workdir_root), 1);
    rf_model_free(&m);
}

static void test_nonzero_exit(void **state)
{
    (void)state;
    char *argv[] = {"awk", "BEGIN{print \"y = 1\"; print \"solver diverged at step\", {b} > \"/dev/stderr\"; exit 3}"};
    rf_external_output out[] = {{"y", NULL, NULL, NULL}};
    rf_external_spec s = spec_of(2, argv, 1, out, fresh_root("exit"));
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
    double x[2] = {2.1e11, 1000}, y;
    assert_int_equal(rf_model_eval(&m, x, &y, &err), RF_EMODEL);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "program 'awk' exited with status 3 at (a=2.1e+11, b=1000); "
                                    "stderr tail: solver diverged at step 1000; working directory kept: "));
    char dir[400], path[480];
    only_entry(s.workdir_root, dir, sizeof dir);
    assert_non_null(strstr(err.msg, dir));
    snprintf(path, sizeof path, "%s/stdout.txt", dir);
    assert_string_equal(slurp(path), "y = 1\n");
    rf_model_free(&m);
}

static void test_missing_program(void **state)
{
    (void)state;
    rf_external_output out[] = {{"y", NULL, NULL, NULL}};
    rf_model m;
    rf_error err = {0};
    char *argv1[] = {"rockfuzz-no-such-program", "{a}"};
    rf_external_spec s = spec_of(2, argv1, 1, out, fresh_root("missing"));
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_EINVAL);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "program 'rockfuzz-no-such-program' not found on PATH"));
    char *argv2[] = {"/nonexistent/solver"};
    s = spec_of(1, argv2, 1, out, fresh_root("missing"));
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_EINVAL);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "program '/nonexistent/solver' not found"));
}

static void test_unknown_placeholder(void **state)
{
    (void)state;
    rf_external_output out[] = {{"y", NULL, NULL, NULL}};
    rf_model m;
    rf_error err = {0};
    char *argv[] = {"printf", "y = %s\n", "{a}{x9}"};
    rf_external_spec s = spec_of(3, argv, 1, out, fresh_root("placeholder"));
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_EINVAL);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "argv[2], line 1: unknown placeholder '{x9}' (parameters: a, b"));

    char tpl[160];
    snprintf(tpl, sizeof tpl, "%s/bad.tpl", root);
    write_text(tpl, "*NODE\n1, {a}, {b}\n*ELASTIC\n{E}, 0.3\n");
    char *argv2[] = {"cat", "in.txt"};
    s = spec_of(2, argv2, 1, out, fresh_root("placeholder"));
    char *src[] = {tpl}, *dst[] = {"in.txt"};
    s.n_templates = 1;
    s.template_src = src;
    s.template_dst = dst;
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_EINVAL);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "bad.tpl', line 4: unknown placeholder '{E}'"));

    char *bad_dst[] = {"../escape.txt"};
    s.template_dst = bad_dst;
    write_text(tpl, "{a}\n");
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "plain file name"));
}

static void test_unparsable_output(void **state)
{
    (void)state;
    rf_external_output out[] = {{"y", NULL, NULL, NULL}};
    const char *cases[][2] = {{"y = abc\ny = 2\n", "line 1 of stdout has no number after 'y': \"y = abc\""},
                              {"x = 1\nyy = 2\n", "no line starting with 'y =', 'y:' or 'y ' in stdout"},
                              {"y = inf\n", "non-finite value"},
                              {"y = 3e400\n", "non-finite value"},
                              {"", "no line starting with 'y ='"}};
    for (size_t t = 0; t < sizeof cases / sizeof cases[0]; t++) {
        char *argv[] = {"printf", (char *)cases[t][0]};
        rf_external_spec s = spec_of(2, argv, 1, out, fresh_root("unparsable"));
        rf_model m;
        rf_error err = {0};
        assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
        double x[2] = {0.5, -1}, y;
        assert_int_equal(rf_model_eval(&m, x, &y, &err), RF_EMODEL);
        print_message("%s\n", err.msg);
        assert_non_null(strstr(err.msg, cases[t][1]));
        assert_non_null(strstr(err.msg, "program 'printf' at (a=0.5, b=-1): output 'y': "));
        rf_model_free(&m);
    }
}

/* Arguments go to the program as they are: no word splitting, no command
 * substitution, no ';' - there is no shell.  A parameter value is a double
 * printed with %.17g, so it cannot carry text of its own either. */
static void test_no_shell_injection(void **state)
{
    (void)state;
    const char *text = "y = {a} ; touch INJECTED1; $(touch INJECTED2) `touch INJECTED3` | touch INJECTED4 &&";
    char *argv[] = {"printf", "%s\n", (char *)text};
    rf_external_output out[] = {{"y", NULL, NULL, NULL}, {"args", NULL, NULL, NULL}};
    rf_external_spec s = spec_of(3, argv, 1, out, fresh_root("injection"));
    s.keep_workdirs = 1;
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_external_model_create(&s, 1, ab, &m, &err), RF_OK);
    double x = 3, y;
    if (rf_model_eval(&m, &x, &y, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_true(y == 3);
    char dir[400], path[480];
    only_entry(s.workdir_root, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/stdout.txt", dir);
    assert_string_equal(slurp(path),
                        "y = 3 ; touch INJECTED1; $(touch INJECTED2) `touch INJECTED3` | touch INJECTED4 &&\n");
    for (int i = 1; i <= 4; i++) {
        snprintf(path, sizeof path, "%s/INJECTED%d", dir, i);
        assert_int_not_equal(access(path, F_OK), 0);
        snprintf(path, sizeof path, "INJECTED%d", i);
        assert_int_not_equal(access(path, F_OK), 0);
    }
    rf_model_free(&m);

    /* Arguments with spaces and ';' arrive as single arguments. */
    char *argv2[] = {"awk", "BEGIN{print \"args =\", ARGC - 1; print \"y =\", length(ARGV[1])}", "a b {a}", "c;d"};
    s = spec_of(4, argv2, 2, out, fresh_root("injection2"));
    out[0] = (rf_external_output){"args", NULL, NULL, NULL};
    out[1] = (rf_external_output){"y", NULL, NULL, NULL};
    assert_int_equal(rf_external_model_create(&s, 1, ab, &m, &err), RF_OK);
    double y2[2];
    if (rf_model_eval(&m, &x, y2, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_true(y2[0] == 2 && y2[1] == 5); /* "a b 3" */
    rf_model_free(&m);
}

typedef struct {
    const rf_model *m;
    int id;
    int failures;
    char msg[RF_ERROR_MAX];
} thread_arg;

static void *evaluate_many(void *p)
{
    thread_arg *a = p;
    rf_error err = {0};
    for (int it = 0; it < 10; it++) {
        double x[2] = {a->id + 0.5, it}, y;
        if (rf_model_eval(a->m, x, &y, &err) != RF_OK) {
            snprintf(a->msg, sizeof a->msg, "%s", err.msg);
            a->failures++;
        } else if (y != x[0] * 1000 + x[1]) {
            snprintf(a->msg, sizeof a->msg, "thread %d: got %g for (%g, %g)", a->id, y, x[0], x[1]);
            a->failures++;
        }
    }
    return NULL;
}

static void test_concurrent_evaluations(void **state)
{
    (void)state;
    char tpl[160];
    snprintf(tpl, sizeof tpl, "%s/conc.tpl", root);
    write_text(tpl, "{a} {b}\n");
    char *argv[] = {"awk", "{printf \"y = %.17g\\n\", $1*1000 + $2}", "in.txt"};
    rf_external_output out[] = {{"y", NULL, NULL, NULL}};
    rf_external_spec s = spec_of(3, argv, 1, out, fresh_root("concurrent"));
    char *src[] = {tpl}, *dst[] = {"in.txt"};
    s.n_templates = 1;
    s.template_src = src;
    s.template_dst = dst;
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_external_model_create(&s, 2, ab, &m, &err), RF_OK);
    enum { N_THREADS = 4 };
    pthread_t th[N_THREADS];
    thread_arg args[N_THREADS];
    for (int t = 0; t < N_THREADS; t++) {
        args[t] = (thread_arg){.m = &m, .id = t};
        assert_int_equal(pthread_create(&th[t], NULL, evaluate_many, &args[t]), 0);
    }
    for (int t = 0; t < N_THREADS; t++) {
        pthread_join(th[t], NULL);
        if (args[t].failures)
            fail_msg("%s", args[t].msg);
    }
    assert_int_equal(count_entries(s.workdir_root), 0);
    rf_model_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stdout_named_values),
        cmocka_unit_test(test_template_and_file_output),
        cmocka_unit_test(test_regex_outputs),
        cmocka_unit_test(test_timeout_kills_quickly),
        cmocka_unit_test(test_nonzero_exit),
        cmocka_unit_test(test_missing_program),
        cmocka_unit_test(test_unknown_placeholder),
        cmocka_unit_test(test_unparsable_output),
        cmocka_unit_test(test_no_shell_injection),
        cmocka_unit_test(test_concurrent_evaluations),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
