/* batch.c - one batch of the runner: the shared queue of points, the store
 * writes around each evaluation, the counts and the progress output.  Used by
 * runner.c (local threads) and mpi.c (rank 0 serving worker ranks); it calls
 * neither, so the two never include each other. */
#include "study/batch.h"
#include "core/util.h"
#include "core/json.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rf_batch_take(rf_batch *b, size_t *pos)
{
    if (atomic_load(&b->stop) || (b->runner->interrupt && atomic_load(b->runner->interrupt)))
        return 0;
    size_t k = atomic_fetch_add(&b->next, 1);
    if (k >= b->ntodo)
        return 0;
    *pos = k;
    return 1;
}

int rf_batch_take_chunk(rf_batch *b, size_t want, size_t *pos, size_t *got)
{
    if (atomic_load(&b->stop) || (b->runner->interrupt && atomic_load(b->runner->interrupt)))
        return 0;
    size_t k = atomic_fetch_add(&b->next, want);
    if (k >= b->ntodo)
        return 0;
    *pos = k;
    *got = b->ntodo - k < want ? b->ntodo - k : want;
    return 1;
}

void rf_batch_finish_ok(rf_batch *b, size_t n, double seconds)
{
    pthread_mutex_lock(&b->lock);
    b->eval_seconds += seconds;
    pthread_mutex_unlock(&b->lock);
    atomic_fetch_add(&b->done, n);
}

/* Counts over the whole run so far: done (incl. resumed), total, failed, time left. */
static void run_counts(rf_batch *b, size_t *done, size_t *total, size_t *failed, double *left, double *elapsed)
{
    rf_runner *r = b->runner;
    size_t fresh_batch = atomic_load(&b->done);
    size_t fresh = r->evaluated + r->failed + fresh_batch;
    *done = r->resumed + b->resumed + fresh;
    size_t t = r->planned_total > *done ? r->planned_total : r->resumed + r->evaluated + r->failed + b->count;
    *total = t < *done ? *done : t;
    *failed = r->failed + atomic_load(&b->nfailed);
    double phase = rf_monotonic_seconds() - b->t_start;
    *elapsed = r->wall_seconds + phase;
    /* Only fresh evaluations measure the speed: points found in the store took no time. */
    double fresh_wall = r->fresh_wall + phase;
    *left = fresh > 0 ? fresh_wall / (double)fresh * (double)(*total - *done) : (*total == *done ? 0 : -1);
}

void rf_batch_progress(rf_batch *b, int final)
{
    rf_runner *r = b->runner;
    if (r->progress != RF_PROGRESS_LINE)
        return;
    FILE *f = r->stream ? r->stream : stderr;
    size_t done, total, failed;
    double left, elapsed;
    run_counts(b, &done, &total, &failed, &left, &elapsed);
    char e[32], l[32];
    rf_format_duration(elapsed, RF_DURATION_COMPACT, e, sizeof e);
    rf_format_duration(left, RF_DURATION_COMPACT, l, sizeof l);
    fprintf(f, "\r  evaluations %zu/%zu  failed %zu  elapsed %s  left %s   ", done, total, failed, e,
            final ? "0.0s" : l);
    if (final)
        fputc('\n', f);
    fflush(f);
}

/* Called with b->lock held. */
static void jsonl_line(rf_batch *b, size_t k, int ok, const rf_error *err, double seconds)
{
    rf_runner *r = b->runner;
    FILE *f = r->stream ? r->stream : stderr;
    size_t done, total, failed;
    double left, elapsed;
    run_counts(b, &done, &total, &failed, &left, &elapsed);
    fprintf(f, "{\"event\": \"evaluation\", \"done\": %zu, \"total\": %zu, \"failed\": %zu, \"ok\": %s, "
               "\"seconds\": %.6g, \"elapsed\": %.6g, \"left\": ",
            done, total, failed, ok ? "true" : "false", seconds, elapsed);
    if (left >= 0)
        fprintf(f, "%.6g", left);
    else
        fputs("null", f);
    fputs(", \"x\": [", f);
    const double *x = b->x + k * b->model->n_inputs;
    for (size_t i = 0; i < b->model->n_inputs; i++)
        fprintf(f, i ? ", %.17g" : "%.17g", x[i]);
    fputc(']', f);
    if (!ok) {
        fputs(", \"error\": ", f);
        rf_json_string(f, err && err->msg[0] ? err->msg : "failed");
    }
    fputs("}\n", f);
    fflush(f);
}

void rf_batch_start(rf_batch *b, size_t pos)
{
    rf_runner *r = b->runner;
    if (!r->store)
        return;
    pthread_mutex_lock(&b->lock);
    if (!b->store_failed) {
        rf_error serr;
        memset(&serr, 0, sizeof serr);
        if (rf_store_put_started(r->store, b->x + b->todo[pos] * b->model->n_inputs, &serr) != RF_OK) {
            b->store_failed = 1;
            b->store_err = serr;
            atomic_store(&b->stop, 1);
        }
    }
    pthread_mutex_unlock(&b->lock);
}

void rf_batch_finish(rf_batch *b, size_t pos, rf_status st, const rf_error *err, double seconds)
{
    rf_runner *r = b->runner;
    size_t k = b->todo[pos];
    size_t nin = b->model->n_inputs, nout = b->model->n_outputs;
    rf_error local;
    memset(&local, 0, sizeof local);
    if (st != RF_OK) {
        local = *err;
        if (local.code == RF_OK)
            local.code = st;
        if (local.msg[0] == '\0')
            rf_fail(&local, st, "model evaluation failed (%s)", rf_status_name(st));
        for (size_t o = 0; o < nout; o++)
            b->y[k * nout + o] = NAN;
    }
    pthread_mutex_lock(&b->lock);
    b->eval_seconds += seconds;
    if (st == RF_EINTERRUPTED) {
        /* stopped on request: neither a result nor a failure; the store keeps it as unfinished */
        b->interrupted++;
        atomic_store(&b->stop, 1);
        pthread_mutex_unlock(&b->lock);
        return;
    }
    if (r->store && !b->store_failed) {
        rf_error serr;
        memset(&serr, 0, sizeof serr);
        if (rf_store_put(r->store, b->x + k * nin, st == RF_OK, b->y + k * nout, local.msg, seconds, &serr) !=
            RF_OK) {
            b->store_failed = 1;
            b->store_err = serr;
            atomic_store(&b->stop, 1);
        }
    }
    if (st != RF_OK) {
        if (k < b->first_failed) {
            b->first_failed = k;
            b->first_err = local;
        }
        atomic_fetch_add(&b->nfailed, 1);
        if (!r->tolerate_failures)
            atomic_store(&b->stop, 1);
    }
    atomic_fetch_add(&b->done, 1);
    if (r->progress == RF_PROGRESS_JSONL)
        jsonl_line(b, k, st == RF_OK, &local, seconds);
    pthread_mutex_unlock(&b->lock);
}

