/* runner.c - the parallel rf_evaluator (see runner.h).
 *
 * A batch first looks every point up in the result store (if any); the
 * missing ones form a queue that workers drain through an atomic counter
 * (dynamic distribution).  Each worker writes only its own y rows, so the
 * result does not depend on the thread count, the MPI ranks or the order of
 * completion.  Whoever takes a point marks it started in the store, and
 * whoever finishes it commits the result, both under the batch mutex (one
 * writer at a time), so a point that crashes the process leaves a trace.  The first failure raises a stop flag
 * (unless failures are tolerated); the lowest failing index and its message
 * are kept.  The calling thread draws the progress line, or serves the MPI
 * worker ranks (mpi.c) while the local threads evaluate. */
#include "rockfuzz/runner.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "study/batch.h"
#include "study/mpi_internal.h"

void rf_runner_init(rf_runner *r)
{
    memset(r, 0, sizeof *r);
}

int rf_runner_default_jobs(const rf_model *model)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (cores < 1)
        cores = 1;
    int per = model && model->threads_per_eval > 1 ? model->threads_per_eval : 1;
    long jobs = cores / per;
    return jobs < 1 ? 1 : (int)jobs;
}

/* Chunks of points for a batch that needs no per-point record (no store, no JSONL line): one pair
 * of clock reads and one lock per chunk instead of per point.  A worker's chunk doubles while it
 * takes under CHUNK_SECONDS / 2, halves above 2 CHUNK_SECONDS, at most CHUNK_MAX points: a
 * chunk of a slow model is one point.  A chunk is evaluated to its end, as a taken point is: every
 * point below a taken one is evaluated, so the lowest failing index stays the lowest. */
#define CHUNK_MAX 64
#define CHUNK_SECONDS 1e-3

static void worker_chunks(rf_batch *b)
{
    size_t nin = b->model->n_inputs, nout = b->model->n_outputs, want = 1, pos, got;
    rf_error err;
    while (rf_batch_take_chunk(b, want, &pos, &got)) {
        double t0 = rf_monotonic_seconds();
        size_t ok = 0;
        for (size_t i = pos; i < pos + got; i++) {
            size_t k = b->todo[i];
            memset(&err, 0, sizeof err);
            rf_status st = rf_model_eval(b->model, b->x + k * nin, b->y + k * nout, &err);
            if (st == RF_OK)
                ok++;
            else
                rf_batch_finish(b, i, st, &err, 0); /* its time is in the chunk's */
        }
        double dt = rf_monotonic_seconds() - t0;
        rf_batch_finish_ok(b, ok, dt);
        if (dt < 0.5 * CHUNK_SECONDS && want < CHUNK_MAX)
            want *= 2;
        else if (dt > 2 * CHUNK_SECONDS && want > 1)
            want /= 2;
    }
}

static void *worker(void *arg)
{
    rf_batch *b = arg;
    size_t nin = b->model->n_inputs, nout = b->model->n_outputs;
    rf_error err;
    size_t pos;
    if (!b->runner->store && b->runner->progress != RF_PROGRESS_JSONL) {
        worker_chunks(b);
        atomic_fetch_sub(&b->workers_left, 1);
        return NULL;
    }
    while (rf_batch_take(b, &pos)) {
        size_t k = b->todo[pos];
        rf_batch_start(b, pos);
        double t0 = rf_monotonic_seconds();
        memset(&err, 0, sizeof err);
        rf_status st = rf_model_eval(b->model, b->x + k * nin, b->y + k * nout, &err);
        rf_batch_finish(b, pos, st, &err, rf_monotonic_seconds() - t0);
    }
    atomic_fetch_sub(&b->workers_left, 1);
    return NULL;
}

/* Evaluate b's todo list on jobs threads (or the MPI ranks), the calling
 * thread drawing the progress line. */
static void run_batch(rf_batch *b, int jobs)
{
    const rf_runner *r = b->runner;
    int started = 0;
    pthread_t *threads = NULL;
    if (b->ntodo > 0) {
        threads = calloc((size_t)jobs, sizeof *threads);
        if (threads) {
            for (; started < jobs; started++)
                if (pthread_create(&threads[started], NULL, worker, b) != 0)
                    break;
        }
        atomic_fetch_sub(&b->workers_left, jobs - started);
        if (r->mpi_workers > 0) {
            rf_mpi_serve_batch(b); /* returns when the queue is drained and the ranks are idle */
        } else if (started == 0) {
            atomic_fetch_add(&b->workers_left, 1);
            worker(b); /* no thread could be created: evaluate here */
        } else if (r->progress == RF_PROGRESS_LINE) {
            /* The calling thread only draws, so the line moves even with one job. */
            double last = 0;
            while (atomic_load(&b->workers_left) > 0) {
                double t = rf_monotonic_seconds();
                if (t - last >= 0.5) {
                    rf_batch_progress(b, 0);
                    last = t;
                }
                struct timespec ts = {0, 20 * 1000 * 1000};
                nanosleep(&ts, NULL);
            }
        }
        for (int k = 0; k < started; k++)
            pthread_join(threads[k], NULL);
        free(threads);
    }
}

rf_status rf_runner_evaluate(rf_runner *r, const rf_model *model, size_t count, const double *x, double *y,
                             size_t *failed_index, rf_error *err)
{
    if (!r || !model || (count && (!x || !y)))
        return rf_fail(err, RF_EINTERNAL, "rf_runner_evaluate: NULL argument");
    if (count == 0)
        return RF_OK;
    double t_batch = rf_monotonic_seconds();
    rf_batch b;
    memset(&b, 0, sizeof b);
    b.runner = r;
    b.model = model;
    b.count = count;
    b.x = x;
    b.y = y;
    b.first_failed = count;
    if (!(b.todo = malloc(count * sizeof *b.todo)))
        return rf_fail(err, RF_ENOMEM, "out of memory for the runner");
    for (size_t k = 0; k < count; k++) {
        int found = 0;
        if (r->store) {
            found = rf_store_lookup(r->store, x + k * model->n_inputs, y + k * model->n_outputs, err);
            if (found < 0) {
                free(b.todo);
                if (failed_index)
                    *failed_index = count; /* not a model failure */
                return RF_EIO;
            }
        }
        if (found)
            b.resumed++;
        else
            b.todo[b.ntodo++] = k;
    }

    int jobs = r->jobs > 0 ? r->jobs : rf_runner_default_jobs(model);
    if ((size_t)jobs > b.ntodo)
        jobs = b.ntodo > 0 ? (int)b.ntodo : 1;
    r->jobs_used = jobs;
    atomic_init(&b.next, 0);
    atomic_init(&b.done, 0);
    atomic_init(&b.nfailed, 0);
    atomic_init(&b.stop, 0);
    atomic_init(&b.workers_left, jobs);
    if (pthread_mutex_init(&b.lock, NULL) != 0) {
        free(b.todo);
        return rf_fail(err, RF_EINTERNAL, "cannot create a mutex");
    }

    b.t_start = rf_monotonic_seconds();
    run_batch(&b, jobs);
    rf_batch_progress(&b, 1);

    double t_end = rf_monotonic_seconds();
    if (b.ntodo > 0)
        r->fresh_wall += t_end - b.t_start;
    r->wall_seconds += t_end - t_batch;
    r->eval_seconds += b.eval_seconds;
    r->resumed += b.resumed;
    r->remote += b.remote;
    size_t nfailed = atomic_load(&b.nfailed);
    r->failed += nfailed;
    r->evaluated += atomic_load(&b.done) - nfailed;
    pthread_mutex_destroy(&b.lock);
    free(b.todo);
    if (b.store_failed) {
        if (err)
            *err = b.store_err;
        if (failed_index)
            *failed_index = count; /* not a model failure */
        return RF_EIO;
    }
    int interrupted = b.interrupted > 0 || (r->interrupt && atomic_load(r->interrupt));
    if (b.first_failed < count && !r->tolerate_failures) {
        if (failed_index)
            *failed_index = b.first_failed;
        if (err)
            *err = b.first_err;
        return b.first_err.code != RF_OK ? b.first_err.code : RF_EMODEL;
    }
    size_t finished = atomic_load(&b.done);
    if (interrupted && finished < b.ntodo) {
        if (failed_index)
            *failed_index = count; /* not a model failure */
        return rf_fail(err, RF_EINTERRUPTED, "interrupted after %zu of the %zu evaluations of this batch (every "
                       "finished one is stored; %zu stopped mid-way)", finished, b.ntodo, b.interrupted);
    }
    return RF_OK;
}

static rf_status evaluate_cb(void *user, const rf_model *model, size_t count, const double *x, double *y,
                             size_t *failed_index, rf_error *err)
{
    return rf_runner_evaluate(user, model, count, x, y, failed_index, err);
}

rf_evaluator rf_runner_evaluator(rf_runner *runner)
{
    rf_evaluator ev = {evaluate_cb, runner};
    return ev;
}
