/* runner.c - the parallel rf_evaluator (see runner.h).
 *
 * Workers pull point indices from an atomic counter (dynamic distribution);
 * each writes only its own y rows, so the result does not depend on the
 * thread count or the order of completion.  The first failure raises a stop
 * flag; the lowest failing index and its message are kept under a mutex.
 * The calling thread only draws the progress line while the workers run. */
#include "rockfuzz/runner.h"

#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

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

typedef struct {
    const rf_model *model;
    size_t count;
    const double *x;
    double *y;
    atomic_size_t next;      /* next index to hand out */
    atomic_size_t done;      /* finished (ok or failed) */
    atomic_size_t nfailed;
    atomic_int stop;
    atomic_int workers_left; /* started workers that have not returned */
    pthread_mutex_t lock;    /* guards the fields below */
    size_t first_failed;     /* lowest failing index, count if none */
    rf_error first_err;
    double eval_seconds;
} batch;

static void *worker(void *arg)
{
    batch *b = arg;
    size_t nin = b->model->n_inputs, nout = b->model->n_outputs;
    double busy = 0;
    rf_error err;
    for (;;) {
        if (atomic_load(&b->stop))
            break;
        size_t k = atomic_fetch_add(&b->next, 1);
        if (k >= b->count)
            break;
        double t0 = now_seconds();
        memset(&err, 0, sizeof err);
        rf_status st = rf_model_eval(b->model, b->x + k * nin, b->y + k * nout, &err);
        busy += now_seconds() - t0;
        if (st != RF_OK) {
            if (err.code == RF_OK)
                err.code = st;
            pthread_mutex_lock(&b->lock);
            if (k < b->first_failed) {
                b->first_failed = k;
                b->first_err = err;
                if (b->first_err.msg[0] == '\0')
                    rf_fail(&b->first_err, st, "model evaluation failed (%s)", rf_status_name(st));
            }
            pthread_mutex_unlock(&b->lock);
            atomic_fetch_add(&b->nfailed, 1);
            atomic_store(&b->stop, 1);
        }
        atomic_fetch_add(&b->done, 1);
    }
    pthread_mutex_lock(&b->lock);
    b->eval_seconds += busy;
    pthread_mutex_unlock(&b->lock);
    atomic_fetch_sub(&b->workers_left, 1);
    return NULL;
}

static void format_duration(double s, char *buf, size_t size)
{
    if (!(s >= 0) || s > 1e8)
        snprintf(buf, size, "?");
    else if (s < 60)
        snprintf(buf, size, "%.1fs", s);
    else if (s < 3600)
        snprintf(buf, size, "%dm%02ds", (int)(s / 60), (int)s % 60);
    else
        snprintf(buf, size, "%dh%02dm", (int)(s / 3600), ((int)s % 3600) / 60);
}

static void progress_line(rf_runner *r, batch *b, double t_start, int final)
{
    FILE *f = r->stream ? r->stream : stderr;
    size_t done_batch = atomic_load(&b->done);
    size_t done = r->evaluated + r->failed + done_batch;
    size_t total = r->planned_total > done ? r->planned_total : r->evaluated + r->failed + b->count;
    if (total < done)
        total = done;
    double elapsed = r->wall_seconds + (now_seconds() - t_start);
    /* Time left from the measured throughput of this run (evaluations per wall second). */
    double left = done > 0 ? elapsed / (double)done * (double)(total - done) : -1;
    char e[32], l[32];
    format_duration(elapsed, e, sizeof e);
    format_duration(left, l, sizeof l);
    fprintf(f, "\r  evaluations %zu/%zu  failed %zu  elapsed %s  left %s   ", done, total,
            r->failed + atomic_load(&b->nfailed), e, final ? "0.0s" : l);
    if (final)
        fputc('\n', f);
    fflush(f);
}

rf_status rf_runner_evaluate(rf_runner *r, const rf_model *model, size_t count, const double *x, double *y,
                             size_t *failed_index, rf_error *err)
{
    if (!r || !model || (count && (!x || !y)))
        return rf_fail(err, RF_EINTERNAL, "rf_runner_evaluate: NULL argument");
    if (count == 0)
        return RF_OK;
    int jobs = r->jobs > 0 ? r->jobs : rf_runner_default_jobs(model);
    if ((size_t)jobs > count)
        jobs = (int)count;
    r->jobs_used = jobs;

    batch b;
    memset(&b, 0, sizeof b);
    b.model = model;
    b.count = count;
    b.x = x;
    b.y = y;
    atomic_init(&b.next, 0);
    atomic_init(&b.done, 0);
    atomic_init(&b.nfailed, 0);
    atomic_init(&b.stop, 0);
    atomic_init(&b.workers_left, jobs);
    b.first_failed = count;
    if (pthread_mutex_init(&b.lock, NULL) != 0)
        return rf_fail(err, RF_EINTERNAL, "cannot create a mutex");

    double t0 = now_seconds();
    pthread_t *threads = calloc((size_t)jobs, sizeof *threads);
    int started = 0;
    if (threads) {
        for (; started < jobs; started++)
            if (pthread_create(&threads[started], NULL, worker, &b) != 0)
                break;
    }
    atomic_fetch_sub(&b.workers_left, jobs - started);
    if (started == 0) {
        worker(&b); /* no thread could be created: evaluate here */
    } else if (r->progress) {
        /* The calling thread only draws, so the line moves even with one job. */
        double last = 0;
        while (atomic_load(&b.workers_left) > 0) {
            double t = now_seconds();
            if (t - last >= 0.5) {
                progress_line(r, &b, t0, 0);
                last = t;
            }
            struct timespec ts = {0, 20 * 1000 * 1000};
            nanosleep(&ts, NULL);
        }
    }
    for (int k = 0; k < started; k++)
        pthread_join(threads[k], NULL);
    free(threads);
    if (r->progress)
        progress_line(r, &b, t0, 1);

    r->wall_seconds += now_seconds() - t0;
    r->eval_seconds += b.eval_seconds;
    size_t nfailed = atomic_load(&b.nfailed);
    r->failed += nfailed;
    r->evaluated += atomic_load(&b.done) - nfailed;
    pthread_mutex_destroy(&b.lock);
    if (b.first_failed < count) {
        if (failed_index)
            *failed_index = b.first_failed;
        if (err)
            *err = b.first_err;
        return b.first_err.code != RF_OK ? b.first_err.code : RF_EMODEL;
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
