/* test_runner.c - the parallel evaluator: the same outputs bit for bit with
 * 1, 2 and 4 threads (directly and through rf_tm_run), and failure
 * propagation (the lowest failing index, its message, and the TM's
 * parameter vector in the final message), and interruption (RF_EINTERRUPTED,
 * no new points, every finished one stored). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdatomic.h>
#include <unistd.h>

#include "rockfuzz/runner.h"
#include "rockfuzz/store.h"
#include "rockfuzz/tm.h"
#include "test_util.h"

/* Thread-safe model: y0 = x0*x1 + sin(x0), y1 = exp(-x1); fails when x0 >= fail_at. */
typedef struct {
    double fail_at;
    atomic_int *interrupt; /* raised by the evaluation of x0 >= interrupt_at (a "signal") */
    double interrupt_at;
} runner_ctx;

static rf_status runner_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    const runner_ctx *c = ctx;
    if (c->interrupt && x[0] >= c->interrupt_at)
        atomic_store(c->interrupt, 1);
    if (x[0] >= c->fail_at)
        return rf_fail(err, RF_EMODEL, "x0 = %g is past the failure threshold", x[0]);
    y[0] = x[0] * x[1] + sin(x[0]);
    y[1] = exp(-x[1]);
    return RF_OK;
}

static rf_model runner_model(runner_ctx *ctx)
{
    rf_model m;
    memset(&m, 0, sizeof m);
    const char *names[2] = {"y0", "y1"};
    rf_model_init_outputs(&m, 2, names, NULL, NULL);
    m.n_inputs = 2;
    m.eval = runner_eval;
    m.ctx = ctx;
    m.threads_per_eval = 1;
    return m;
}

#define NPOINTS 2000

static void test_same_outputs_any_thread_count(void **state)
{
    (void)state;
    runner_ctx ctx = {INFINITY, NULL, 0};
    rf_model m = runner_model(&ctx);
    double *x = malloc(2 * NPOINTS * sizeof *x);
    double *y[3];
    for (size_t k = 0; k < NPOINTS; k++) {
        x[2 * k] = 0.001 * (double)k;
        x[2 * k + 1] = 1.0 - 0.0005 * (double)k;
    }
    const int jobs[3] = {1, 2, 4};
    for (int t = 0; t < 3; t++) {
        y[t] = calloc(2 * NPOINTS, sizeof(double));
        rf_runner r;
        rf_runner_init(&r);
        r.jobs = jobs[t];
        size_t failed = 12345;
        rf_error err;
        assert_int_equal(rf_runner_evaluate(&r, &m, NPOINTS, x, y[t], &failed, &err), RF_OK);
        assert_int_equal(failed, 12345); /* untouched on success */
        assert_int_equal(r.evaluated, NPOINTS);
        assert_int_equal(r.failed, 0);
        assert_int_equal(r.jobs_used, jobs[t]);
    }
    assert_memory_equal(y[0], y[1], 2 * NPOINTS * sizeof(double));
    assert_memory_equal(y[0], y[2], 2 * NPOINTS * sizeof(double));
    for (int t = 0; t < 3; t++)
        free(y[t]);
    free(x);
    rf_model_free(&m);
}

/* Without a store and JSONL lines the workers take chunks of points (one clock pair and one lock
 * per chunk): the same y as the model's point by point, every point counted once, the
 * failures tolerated and counted, their rows NaN, and the evaluation time accounted. */
static void test_chunks_same_results_and_counts(void **state)
{
    (void)state;
    enum { N = 20000 };
    runner_ctx ctx = {15.0, NULL, 0}; /* x0 = 0.001 k fails from k = 15000 on */
    rf_model m = runner_model(&ctx);
    double *x = malloc(2 * N * sizeof *x), *y0 = calloc(2 * N, sizeof(double)), *y1 = calloc(2 * N, sizeof(double));
    for (size_t k = 0; k < N; k++) {
        x[2 * k] = 0.001 * (double)k;
        x[2 * k + 1] = 0.25 + 0.0001 * (double)k;
    }
    for (size_t k = 0; k < N; k++) /* the serial values */
        assert_int_equal(runner_eval(&ctx, x + 2 * k, y0 + 2 * k, &(rf_error){0}), k < 15000 ? RF_OK : RF_EMODEL);
    for (int jobs = 1; jobs <= 2; jobs++) {
        rf_runner r;
        rf_runner_init(&r);
        r.jobs = jobs;
        r.tolerate_failures = 1;
        rf_error err;
        memset(&err, 0, sizeof err);
        assert_int_equal(rf_runner_evaluate(&r, &m, N, x, y1, NULL, &err), RF_OK);
        assert_int_equal(r.evaluated, 15000);
        assert_int_equal(r.failed, N - 15000);
        assert_true(r.eval_seconds > 0 && r.eval_seconds <= jobs * r.wall_seconds * 1.01 + 1e-3);
        assert_memory_equal(y0, y1, 2 * 15000 * sizeof(double));
        for (size_t k = 15000; k < N; k++)
            assert_true(isnan(y1[2 * k]) && isnan(y1[2 * k + 1]));
    }
    free(x), free(y0), free(y1);
    rf_model_free(&m);
}

/* An interruption (the caller's signal handler raising the flag) stops the
 * hand-out: the batch returns RF_EINTERRUPTED, not a model failure, and every
 * evaluation that finished is in the store. */
static void test_interrupt_stops_and_keeps_finished(void **state)
{
    (void)state;
    atomic_int flag = 0;
    runner_ctx ctx = {INFINITY, &flag, 0.1}; /* raised at k = 100 */
    rf_model m = runner_model(&ctx);
    double *x = malloc(2 * NPOINTS * sizeof *x), *y = calloc(2 * NPOINTS, sizeof(double));
    for (size_t k = 0; k < NPOINTS; k++) {
        x[2 * k] = 0.001 * (double)k;
        x[2 * k + 1] = 0.5;
    }
    char dir[] = "/tmp/rockfuzz-test-runner-XXXXXX", path[64];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/store.sqlite", dir);
    static const char *const in[2] = {"x0", "x1"}, *const out[2] = {"y0", "y1"};
    rf_store_key key = {"runner-test", "1", 2, 2, in, out};
    rf_store *store = NULL;
    rf_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(rf_store_open(path, &key, 0, &store, &err), RF_OK);
    for (int jobs = 1; jobs <= 4; jobs *= 2) {
        atomic_store(&flag, 0);
        rf_runner r;
        rf_runner_init(&r);
        r.jobs = jobs;
        r.interrupt = &flag;
        r.store = jobs == 1 ? store : NULL;
        size_t failed = 0;
        memset(&err, 0, sizeof err);
        assert_int_equal(rf_runner_evaluate(&r, &m, NPOINTS, x, y, &failed, &err), RF_EINTERRUPTED);
        assert_int_equal(failed, NPOINTS); /* not a model failure */
        assert_non_null(strstr(err.msg, "interrupted after"));
        assert_int_equal(r.failed, 0);
        assert_true(r.evaluated >= 101 && r.evaluated < NPOINTS);
    }
    rf_store_close(store);
    rf_store_info info;
    assert_int_equal(rf_store_read_info(path, &info, &err), RF_OK);
    assert_true(info.done >= 101 && info.done < NPOINTS);
    assert_int_equal(info.failed, 0);
    assert_int_equal(info.unfinished, 0);
    /* raised before the batch: nothing is evaluated */
    rf_runner r;
    rf_runner_init(&r);
    r.interrupt = &flag;
    assert_int_equal(rf_runner_evaluate(&r, &m, NPOINTS, x, y, NULL, &err), RF_EINTERRUPTED);
    assert_int_equal(r.evaluated, 0);
    unlink(path);
    char side[80];
    snprintf(side, sizeof side, "%s-wal", path);
    unlink(side);
    snprintf(side, sizeof side, "%s-shm", path);
    unlink(side);
    rmdir(dir);
    free(x);
    free(y);
    rf_model_free(&m);
}

static void test_failure_reports_lowest_index(void **state)
{
    (void)state;
    runner_ctx ctx = {1.0, NULL, 0}; /* x0 = 0.001 k fails from k = 1000 on */
    rf_model m = runner_model(&ctx);
    double *x = malloc(2 * NPOINTS * sizeof *x), *y = calloc(2 * NPOINTS, sizeof(double));
    for (size_t k = 0; k < NPOINTS; k++) {
        x[2 * k] = 0.001 * (double)k;
        x[2 * k + 1] = 0.5;
    }
    for (int jobs = 1; jobs <= 4; jobs *= 2) {
        rf_runner r;
        rf_runner_init(&r);
        r.jobs = jobs;
        size_t failed = 0;
        rf_error err;
        memset(&err, 0, sizeof err);
        assert_int_equal(rf_runner_evaluate(&r, &m, NPOINTS, x, y, &failed, &err), RF_EMODEL);
        assert_int_equal(failed, 1000);
        assert_non_null(strstr(err.msg, "x0 = 1 is past"));
        assert_true(r.failed >= 1);
        /* work stops being handed out: far fewer than all points ran */
        assert_true(r.evaluated + r.failed < NPOINTS);
    }
    free(x);
    free(y);
    rf_model_free(&m);
}

static void test_tm_through_runner(void **state)
{
    (void)state; /* tm_spec 6.1 through the threaded evaluator, 1 and 2 threads */
    runner_ctx ctx = {INFINITY, NULL, 0};
    rf_model m = runner_model(&ctx);
    rf_fuzzy in[2];
    rf_fuzzy_tfn(&in[0], 2, 1, 1, NULL);
    rf_fuzzy_tfn(&in[1], 3, 1, 2, NULL);
    rf_tm_result res[2];
    for (int t = 0; t < 2; t++) {
        rf_runner r;
        rf_runner_init(&r);
        r.jobs = t + 1;
        rf_evaluator ev = rf_runner_evaluator(&r);
        rf_tm_options opt;
        rf_tm_options_default(&opt);
        opt.scheme = RF_TM_GENERAL;
        opt.levels = 4;
        opt.evaluator = &ev;
        rf_error err;
        assert_int_equal(rf_tm_run(in, 2, &m, &opt, &res[t], &err), RF_OK);
        assert_int_equal(r.evaluated, res[t].distinct);
    }
    size_t cnt = 2 * 5;
    assert_memory_equal(res[0].lo, res[1].lo, cnt * sizeof(double));
    assert_memory_equal(res[0].hi, res[1].hi, cnt * sizeof(double));
    assert_memory_equal(res[0].x_lo, res[1].x_lo, cnt * 2 * sizeof(double));

    /* failure through the TM: the message carries the failing parameter vector */
    ctx.fail_at = 2.5;
    rf_runner r;
    rf_runner_init(&r);
    r.jobs = 2;
    rf_evaluator ev = rf_runner_evaluator(&r);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.levels = 4;
    opt.evaluator = &ev;
    rf_tm_result bad;
    rf_error err;
    memset(&err, 0, sizeof err);
    assert_int_not_equal(rf_tm_run(in, 2, &m, &opt, &bad, &err), RF_OK);
    assert_non_null(strstr(err.msg, "past the failure threshold"));
    rf_tm_result_free(&bad);
    for (int t = 0; t < 2; t++)
        rf_tm_result_free(&res[t]);
    rf_fuzzy_free(&in[0]);
    rf_fuzzy_free(&in[1]);
    rf_model_free(&m);
}

static void test_default_jobs(void **state)
{
    (void)state;
    rf_model m;
    memset(&m, 0, sizeof m);
    m.threads_per_eval = 1;
    int one = rf_runner_default_jobs(&m);
    assert_true(one >= 1);
    m.threads_per_eval = 1000;
    assert_int_equal(rf_runner_default_jobs(&m), 1);
    m.threads_per_eval = 2;
    assert_int_equal(rf_runner_default_jobs(&m), one / 2 > 0 ? one / 2 : 1);
}

static void test_progress_line(void **state)
{
    (void)state;
    runner_ctx ctx = {INFINITY, NULL, 0};
    rf_model m = runner_model(&ctx);
    double x[8] = {0, 1, 1, 1, 2, 1, 3, 1}, y[8];
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    rf_runner r;
    rf_runner_init(&r);
    r.jobs = 2;
    r.progress = 1;
    r.stream = f;
    r.planned_total = 4;
    rf_error err;
    assert_int_equal(rf_runner_evaluate(&r, &m, 4, x, y, NULL, &err), RF_OK);
    fclose(f);
    assert_non_null(strstr(buf, "evaluations 4/4"));
    assert_non_null(strstr(buf, "failed 0"));
    free(buf);
    rf_model_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_outputs_any_thread_count),
        cmocka_unit_test(test_failure_reports_lowest_index),
        cmocka_unit_test(test_chunks_same_results_and_counts),
        cmocka_unit_test(test_interrupt_stops_and_keeps_finished),
        cmocka_unit_test(test_tm_through_runner),
        cmocka_unit_test(test_default_jobs),
        cmocka_unit_test(test_progress_line),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
