/* test_store.c - the SQLite result store and the runner on top of it:
 * results survive a reopen bit for bit, a second run evaluates nothing,
 * a store of another model / version / inputs is refused (and --fresh
 * discards it), foreign and corrupt files are refused and left unchanged,
 * a full disk (injected with max_page_count) stops the run with a clear
 * message and keeps what was committed, failures are stored with their
 * message, a point that kills the process is left marked "started, never
 * finished", and the JSONL progress has one object per evaluation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include "rockfuzz/runner.h"
#include "rockfuzz/store.h"
#include "rockfuzz/tm.h"
#include "test_util.h"

static const char *const IN[2] = {"x0", "x1"};
static const char *const OUT[2] = {"y0", "y1"};

static rf_store_key key_for(const char *identity, const char *version)
{
    rf_store_key k = {identity, version, 2, 2, IN, OUT};
    return k;
}

static void tmp_path(char *buf, size_t size, const char *name)
{
    static char dir[256];
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/rf_test_store_XXXXXX");
        assert_non_null(mkdtemp(dir));
    }
    snprintf(buf, size, "%s/%s", dir, name);
}

static void remove_store(const char *path)
{
    char p[600];
    unlink(path);
    snprintf(p, sizeof p, "%s-wal", path);
    unlink(p);
    snprintf(p, sizeof p, "%s-shm", path);
    unlink(p);
}

/* Counting, thread-safe model: y0 = x0*x1 + sin(x0), y1 = exp(-x1); fails (or NaN) for x0 in a window. */
typedef struct {
    double fail_lo, fail_hi;
    int nan_instead;
    _Atomic size_t calls;
} count_ctx;

static rf_status count_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    count_ctx *c = ctx;
    c->calls++;
    if (x[0] >= c->fail_lo && x[0] <= c->fail_hi) {
        if (c->nan_instead) {
            y[0] = y[1] = NAN;
            return RF_OK;
        }
        return rf_fail(err, RF_EMODEL, "solver diverged at x0 = %g", x[0]);
    }
    y[0] = x[0] * x[1] + sin(x[0]);
    y[1] = exp(-x[1]);
    return RF_OK;
}

static rf_model count_model(count_ctx *ctx)
{
    rf_model m;
    memset(&m, 0, sizeof m);
    rf_model_init_outputs(&m, 2, OUT, NULL, NULL);
    m.n_inputs = 2;
    m.eval = count_eval;
    m.ctx = ctx;
    m.threads_per_eval = 1;
    return m;
}

static void file_bytes(const char *path, char *buf, size_t size, size_t *len)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    *len = fread(buf, 1, size, f);
    fclose(f);
}

static void test_put_lookup_reopen(void **state)
{
    (void)state;
    char path[512];
    tmp_path(path, sizeof path, "a.sqlite");
    remove_store(path);
    rf_store_key key = key_for("model A", "0.1.0");
    rf_store *s = NULL;
    rf_error err;
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    double x[2] = {0.1, 1.0 / 3.0}, y[2] = {3.141592653589793, -0.0}, got[2] = {0, 0};
    assert_int_equal(rf_store_lookup(s, x, got, &err), 0);
    assert_int_equal(rf_store_put(s, x, 1, y, NULL, 0.5, &err), RF_OK);
    double xf[2] = {2, 3};
    assert_int_equal(rf_store_put(s, xf, 0, NULL, "it broke", 0.1, &err), RF_OK);
    assert_int_equal(rf_store_begin_run(s, 10, "t", &err), RF_OK);
    rf_store_close(s);

    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    assert_int_equal(rf_store_lookup(s, x, got, &err), 1);
    assert_memory_equal(got, y, sizeof y); /* bit for bit, -0.0 included */
    assert_int_equal(rf_store_lookup(s, xf, got, &err), 0); /* a failure is evaluated again */
    double x_near[2] = {0.1, nextafter(1.0 / 3.0, 1)};
    assert_int_equal(rf_store_lookup(s, x_near, got, &err), 0); /* exact bytes only */
    rf_store_close(s);

    rf_store_info info;
    assert_int_equal(rf_store_read_info(path, &info, &err), RF_OK);
    assert_int_equal(info.planned_total, 10);
    assert_int_equal(info.done, 1);
    assert_int_equal(info.failed, 1);
    assert_string_equal(info.identity, "model A");
    assert_string_equal(info.study, "t");
    char xs[4][512], msgs[4][512];
    assert_int_equal(rf_store_failures(path, 4, xs, msgs, &err), 1);
    assert_string_equal(xs[0], "2, 3");
    assert_string_equal(msgs[0], "it broke");
}

static void test_refuses_other_model_and_version(void **state)
{
    (void)state;
    char path[512];
    tmp_path(path, sizeof path, "b.sqlite");
    remove_store(path);
    rf_store_key key = key_for("impact v1 solver=fem refinement=4 base: radius=1", "0.1.0");
    rf_store *s = NULL;
    rf_error err;
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    double x[2] = {1, 2}, y[2] = {3, 4}, got[2];
    assert_int_equal(rf_store_put(s, x, 1, y, NULL, 0, &err), RF_OK);
    rf_store_close(s);

    rf_store_key other = key_for("impact v1 solver=fem refinement=5 base: radius=1", "0.1.0");
    memset(&err, 0, sizeof err);
    assert_int_equal(rf_store_open(path, &other, 0, &s, &err), RF_EINVAL);
    assert_null(s);
    assert_non_null(strstr(err.msg, "different model or its settings"));
    assert_non_null(strstr(err.msg, "refinement=4"));
    assert_non_null(strstr(err.msg, "refinement=5"));
    assert_non_null(strstr(err.msg, "--fresh"));

    rf_store_key newer = key_for(key.identity, "0.2.0");
    assert_int_equal(rf_store_open(path, &newer, 0, &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "rockfuzz version"));

    const char *const swapped[2] = {"x1", "x0"};
    rf_store_key names = key;
    names.input_names = swapped;
    assert_int_equal(rf_store_open(path, &names, 0, &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "input names"));

    /* the refusals changed nothing: the original key still finds its result */
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    assert_int_equal(rf_store_lookup(s, x, got, &err), 1);
    rf_store_close(s);

    /* --fresh: the other model starts over, the old results are gone */
    assert_int_equal(rf_store_open(path, &other, 1, &s, &err), RF_OK);
    assert_int_equal(rf_store_lookup(s, x, got, &err), 0);
    rf_store_close(s);
    rf_store_info info;
    assert_int_equal(rf_store_read_info(path, &info, &err), RF_OK);
    assert_string_equal(info.identity, other.identity);
    assert_int_equal(info.done, 0);
}

static void test_foreign_and_corrupt_files_untouched(void **state)
{
    (void)state;
    char path[512];
    rf_error err;
    rf_store *s = NULL;
    rf_store_key key = key_for("m", "v");
    char before[8192], after[8192];
    size_t nb, na;

    /* an SQLite database of something else */
    tmp_path(path, sizeof path, "foreign.sqlite");
    remove_store(path);
    sqlite3 *db = NULL;
    assert_int_equal(sqlite3_open(path, &db), SQLITE_OK);
    assert_int_equal(sqlite3_exec(db, "CREATE TABLE photos(id INTEGER, name TEXT); INSERT INTO photos VALUES(1,'a')",
                                  NULL, NULL, NULL),
                     SQLITE_OK);
    sqlite3_close(db);
    file_bytes(path, before, sizeof before, &nb);
    for (int fresh = 0; fresh < 2; fresh++) {
        memset(&err, 0, sizeof err);
        assert_int_equal(rf_store_open(path, &key, fresh, &s, &err), RF_EIO);
        assert_null(s);
        assert_non_null(strstr(err.msg, "not a rockfuzz result store"));
    }
    file_bytes(path, after, sizeof after, &na);
    assert_int_equal(na, nb);
    assert_memory_equal(before, after, nb);
    rf_store_info info;
    assert_int_equal(rf_store_read_info(path, &info, &err), RF_EIO);

    /* garbage (a truncated copy, random text) */
    tmp_path(path, sizeof path, "corrupt.sqlite");
    remove_store(path);
    FILE *f = fopen(path, "wb");
    for (int k = 0; k < 300; k++)
        fprintf(f, "not a database %d\n", k);
    fclose(f);
    file_bytes(path, before, sizeof before, &nb);
    memset(&err, 0, sizeof err);
    assert_int_equal(rf_store_open(path, &key, 1, &s, &err), RF_EIO);
    assert_non_null(strstr(err.msg, "not a rockfuzz result store"));
    assert_non_null(strstr(err.msg, "left untouched"));
    file_bytes(path, after, sizeof after, &na);
    assert_int_equal(na, nb);
    assert_memory_equal(before, after, nb);
}

#define NPTS 400

static void test_runner_resumes_from_store(void **state)
{
    (void)state;
    char path[512];
    tmp_path(path, sizeof path, "r.sqlite");
    remove_store(path);
    count_ctx ctx = {INFINITY, INFINITY, 0, 0};
    rf_model m = count_model(&ctx);
    rf_model_set_identity(&m, "count model", NULL);
    double *x = malloc(2 * NPTS * sizeof *x), *y1 = calloc(2 * NPTS, sizeof(double)),
           *y2 = calloc(2 * NPTS, sizeof(double)), *y0 = calloc(2 * NPTS, sizeof(double));
    for (size_t k = 0; k < NPTS; k++) {
        x[2 * k] = 0.01 * (double)k;
        x[2 * k + 1] = 1.0 - 0.001 * (double)k;
    }
    rf_error err;
    /* reference without a store */
    rf_runner r0;
    rf_runner_init(&r0);
    r0.jobs = 1;
    assert_int_equal(rf_runner_evaluate(&r0, &m, NPTS, x, y0, NULL, &err), RF_OK);

    rf_store_key key = {m.identity, "t", 2, 2, IN, OUT};
    rf_store *s = NULL;
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    /* first run: only half of the points (as if killed after NPTS/2) */
    rf_runner r;
    rf_runner_init(&r);
    r.jobs = 2;
    r.store = s;
    ctx.calls = 0;
    assert_int_equal(rf_runner_evaluate(&r, &m, NPTS / 2, x, y1, NULL, &err), RF_OK);
    assert_int_equal(ctx.calls, NPTS / 2);
    rf_store_close(s);
    /* second run: all points, only the missing half is evaluated */
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    rf_runner_init(&r);
    r.jobs = 2;
    r.store = s;
    char *line = NULL;
    size_t line_size = 0;
    FILE *f = open_memstream(&line, &line_size);
    r.progress = RF_PROGRESS_LINE;
    r.stream = f;
    r.planned_total = NPTS;
    ctx.calls = 0;
    assert_int_equal(rf_runner_evaluate(&r, &m, NPTS, x, y2, NULL, &err), RF_OK);
    fclose(f);
    assert_non_null(strstr(line, "evaluations 400/400")); /* stored points count as done */
    free(line);
    assert_int_equal(ctx.calls, NPTS - NPTS / 2);
    assert_int_equal(r.resumed, NPTS / 2);
    assert_int_equal(r.evaluated, NPTS - NPTS / 2);
    assert_memory_equal(y0, y2, 2 * NPTS * sizeof(double));
    rf_store_close(s);
    free(x);
    free(y0);
    free(y1);
    free(y2);
    rf_model_free(&m);
}

static void test_full_disk_stops_and_keeps_committed(void **state)
{
    (void)state;
    char path[512];
    tmp_path(path, sizeof path, "full.sqlite");
    remove_store(path);
    count_ctx ctx = {INFINITY, INFINITY, 0, 0};
    rf_model m = count_model(&ctx);
    rf_model_set_identity(&m, "count model", NULL);
    rf_store_key key = {m.identity, "t", 2, 2, IN, OUT};
    rf_store *s = NULL;
    rf_error err;
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    assert_int_equal(rf_store_limit_pages(s, 12, &err), RF_OK); /* a few kB: fills after some dozens of rows */
    enum { N = 3000 };
    double *x = malloc(2 * N * sizeof *x), *y = calloc(2 * N, sizeof(double));
    for (size_t k = 0; k < N; k++) {
        x[2 * k] = 0.001 * (double)k;
        x[2 * k + 1] = 0.5;
    }
    rf_runner r;
    rf_runner_init(&r);
    r.jobs = 2;
    r.store = s;
    size_t failed = 0;
    memset(&err, 0, sizeof err);
    assert_int_equal(rf_runner_evaluate(&r, &m, N, x, y, &failed, &err), RF_EIO);
    assert_int_equal(failed, N); /* not a model failure */
    assert_non_null(strstr(err.msg, "full"));
    assert_non_null(strstr(err.msg, "cannot commit a result"));
    assert_true(r.evaluated < N);
    rf_store_close(s);
    /* what was committed is there and readable */
    rf_store_info info;
    assert_int_equal(rf_store_read_info(path, &info, &err), RF_OK);
    assert_true(info.done > 0);
    assert_true(info.done < N);
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    double got[2];
    size_t found = 0;
    for (size_t k = 0; k < N; k++)
        if (rf_store_lookup(s, x + 2 * k, got, &err) == 1) {
            found++;
            assert_memory_equal(got, y + 2 * k, sizeof got);
        }
    assert_int_equal(found, info.done);
    rf_store_close(s);
    free(x);
    free(y);
    rf_model_free(&m);
}

static void test_failures_stored_and_jsonl(void **state)
{
    (void)state;
    char path[512];
    tmp_path(path, sizeof path, "fail.sqlite");
    remove_store(path);
    count_ctx ctx = {0.5, 0.7, 0, 0};
    rf_model m = count_model(&ctx);
    rf_model_set_identity(&m, "count model", NULL);
    rf_store_key key = {m.identity, "t", 2, 2, IN, OUT};
    rf_store *s = NULL;
    rf_error err;
    assert_int_equal(rf_store_open(path, &key, 0, &s, &err), RF_OK);
    double x[10 * 2], y[10 * 2];
    for (int k = 0; k < 10; k++) {
        x[2 * k] = 0.1 * k;
        x[2 * k + 1] = 1;
    }
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    rf_runner r;
    rf_runner_init(&r);
    r.jobs = 2;
    r.store = s;
    r.tolerate_failures = 1;
    r.progress = RF_PROGRESS_JSONL;
    r.stream = f;
    r.planned_total = 10;
    assert_int_equal(rf_runner_evaluate(&r, &m, 10, x, y, NULL, &err), RF_OK);
    fclose(f);
    rf_store_close(s);
    assert_int_equal(r.failed, 2); /* x0 = 0.5 and 0.6 (0.7 is 0.7000000000000001) */
    assert_int_equal(r.evaluated, 8);
    assert_true(isnan(y[2 * 5]) && isnan(y[2 * 6 + 1]));
    size_t lines = 0;
    for (char *p = buf; (p = strchr(p, '\n')); p++)
        lines++;
    assert_int_equal(lines, 10);
    assert_non_null(strstr(buf, "\"total\": 10"));
    assert_non_null(strstr(buf, "\"done\": 10"));
    assert_non_null(strstr(buf, "\"ok\": false"));
    assert_non_null(strstr(buf, "\"error\": \"solver diverged at x0 = 0.5\""));
    free(buf);
    char xs[4][512], msgs[4][512];
    assert_int_equal(rf_store_failures(path, 4, xs, msgs, &err), 2);
    assert_non_null(strstr(msgs[0], "solver diverged"));
    rf_model_free(&m);
}

/* A model that takes the whole process down at x0 == 3 (as a segfaulting solver would). */
static rf_status crash_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    (void)ctx;
    (void)err;
    if (x[0] == 3.0)
        _exit(77);
    y[0] = x[0];
    y[1] = x[1];
    return RF_OK;
}

static void test_crash_leaves_unfinished_mark(void **state)
{
    (void)state;
    char path[512];
    tmp_path(path, sizeof path, "crash.sqlite");
    remove_store(path);
    rf_store_key key = {"crash model", "t", 2, 2, IN, OUT};
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        rf_model m;
        memset(&m, 0, sizeof m);
        rf_model_init_outputs(&m, 2, OUT, NULL, NULL);
        m.n_inputs = 2;
        m.eval = crash_eval;
        m.threads_per_eval = 1;
        rf_store *s = NULL;
        rf_error err;
        if (rf_store_open(path, &key, 0, &s, &err) != RF_OK)
            _exit(1);
        double x[10] = {0, 0, 1, 0, 2, 0, 3, 0, 4, 0}, y[10];
        rf_runner r;
        rf_runner_init(&r);
        r.jobs = 1; /* serial: points 0, 1, 2 finish, point 3 kills the process */
        r.store = s;
        rf_runner_evaluate(&r, &m, 5, x, y, NULL, &err);
        _exit(2);
    }
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 77);
    rf_store_info info;
    rf_error err;
    assert_int_equal(rf_store_read_info(path, &info, &err), RF_OK);
    assert_int_equal(info.done, 3);
    assert_int_equal(info.failed, 0);
    assert_int_equal(info.unfinished, 1);
    char xs[4][512], msgs[4][512];
    assert_int_equal(rf_store_failures(path, 4, xs, msgs, &err), 1);
    assert_string_equal(xs[0], "3, 0");
    assert_non_null(strstr(msgs[0], "never finished"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_put_lookup_reopen),
        cmocka_unit_test(test_refuses_other_model_and_version),
        cmocka_unit_test(test_foreign_and_corrupt_files_untouched),
        cmocka_unit_test(test_runner_resumes_from_store),
        cmocka_unit_test(test_full_disk_stops_and_keeps_committed),
        cmocka_unit_test(test_failures_stored_and_jsonl),
        cmocka_unit_test(test_crash_leaves_unfinished_mark),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
