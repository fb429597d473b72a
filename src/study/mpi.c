/* mpi.c - rank 0 hands points to worker ranks, workers evaluate (see mpi.h).
 *
 * Rank 0's main thread serves the workers from the batch queue of the runner
 * (rf_batch_take / rf_batch_finish), while its local threads evaluate from
 * the same queue; so the store, the counts, the JSONL lines and the progress
 * line are the same code path as without MPI.  Without ROCKFUZZ_HAVE_MPI every
 * function is a stub that reports one rank. */
#include "rockfuzz/mpi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "study/mpi_internal.h"

#ifdef ROCKFUZZ_HAVE_MPI
#include <mpi.h>

enum { TAG_HELLO = 1, TAG_WORK = 2, TAG_RESULT = 3, TAG_STOP = 4 };
#define HELLO_BYTES 4096

static int we_initialised = 0;
static int world_size = 1;

int rf_mpi_built(void)
{
    return 1;
}

static int launched_by_mpi(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS",
                                       "SLURM_STEP_NUM_TASKS"};
    for (size_t k = 0; k < sizeof vars / sizeof *vars; k++)
        if (getenv(vars[k]))
            return 1;
    return 0;
}

rf_status rf_mpi_start(int *argc, char ***argv, int *rank, int *size, rf_error *err)
{
    *rank = 0;
    *size = 1;
    if (!launched_by_mpi())
        return RF_OK;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return rf_fail(err, RF_EIO, "MPI_Init_thread failed");
    we_initialised = 1;
    if (provided < MPI_THREAD_FUNNELED)
        return rf_fail(err, RF_EIO, "the MPI library does not support MPI_THREAD_FUNNELED");
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    world_size = *size;
    return RF_OK;
}

void rf_mpi_stop(void)
{
    if (we_initialised)
        MPI_Finalize();
    we_initialised = 0;
}

int rf_mpi_worker(const rf_model *model, const char *load_error)
{
    char hello[HELLO_BYTES];
    memset(hello, 0, sizeof hello);
    hello[0] = model ? 1 : 0;
    snprintf(hello + 1, sizeof hello - 1, "%s", model ? (model->identity ? model->identity : "") : load_error);
    MPI_Send(hello, HELLO_BYTES, MPI_BYTE, 0, TAG_HELLO, MPI_COMM_WORLD);
    size_t nin = model ? model->n_inputs : 0, nout = model ? model->n_outputs : 0;
    size_t bytes = 2 * sizeof(double) + nout * sizeof(double) + RF_ERROR_MAX;
    double *x = malloc((nin + 1) * sizeof(double));
    unsigned char *out = malloc(bytes);
    int rc = model ? 0 : 1;
    for (;;) {
        MPI_Status status;
        MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
        if (status.MPI_TAG == TAG_STOP) {
            MPI_Recv(NULL, 0, MPI_BYTE, 0, TAG_STOP, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            break;
        }
        MPI_Recv(x, (int)nin, MPI_DOUBLE, 0, TAG_WORK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        rf_error err;
        memset(&err, 0, sizeof err);
        double t0 = rf_monotonic_seconds();
        double *y = (double *)(void *)(out + 2 * sizeof(double));
        rf_status st = model ? rf_model_eval(model, x, y, &err) : RF_EINTERNAL;
        double head[2] = {rf_monotonic_seconds() - t0, (double)st};
        memcpy(out, head, sizeof head);
        memcpy(out + 2 * sizeof(double) + nout * sizeof(double), err.msg, RF_ERROR_MAX);
        MPI_Send(out, (int)bytes, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
    }
    free(x);
    free(out);
    return rc;
}

rf_status rf_mpi_gather_hello(const rf_model *model, rf_error *err)
{
    rf_status st = RF_OK;
    char hello[HELLO_BYTES];
    for (int r = 1; r < world_size; r++) {
        MPI_Recv(hello, HELLO_BYTES, MPI_BYTE, r, TAG_HELLO, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        hello[HELLO_BYTES - 1] = '\0';
        if (st != RF_OK)
            continue;
        if (!hello[0])
            st = rf_fail(err, RF_EINVAL, "MPI rank %d could not load the study: %s", r, hello + 1);
        else if (model && strcmp(hello + 1, model->identity ? model->identity : "") != 0)
            st = rf_fail(err, RF_EINVAL, "MPI rank %d built a different model (identity '%.300s' vs '%.300s'): "
                                         "is the study file the same on every node?",
                         r, hello + 1, model->identity ? model->identity : "");
    }
    return st;
}

void rf_mpi_release_workers(void)
{
    for (int r = 1; r < world_size; r++)
        MPI_Send(NULL, 0, MPI_BYTE, r, TAG_STOP, MPI_COMM_WORLD);
}

void rf_mpi_serve_batch(rf_batch *b)
{
    int nw = b->runner->mpi_workers;
    size_t nin = b->model->n_inputs, nout = b->model->n_outputs;
    size_t bytes = 2 * sizeof(double) + nout * sizeof(double) + RF_ERROR_MAX;
    size_t *pos = calloc((size_t)nw + 1, sizeof *pos);
    unsigned char *busy = calloc((size_t)nw + 1, 1);
    unsigned char *in = malloc(bytes);
    if (!pos || !busy || !in) {
        /* no memory to serve: the local threads still drain the queue */
        free(pos);
        free(busy);
        free(in);
        while (atomic_load(&b->workers_left) > 0) {
            struct timespec ts = {0, 20 * 1000 * 1000};
            nanosleep(&ts, NULL);
        }
        return;
    }
    double last_draw = 0;
    for (;;) {
        int nbusy = 0;
        for (int r = 1; r <= nw; r++) {
            size_t p;
            if (!busy[r] && rf_batch_take(b, &p)) {
                rf_batch_start(b, p);
                MPI_Send(b->x + b->todo[p] * nin, (int)nin, MPI_DOUBLE, r, TAG_WORK, MPI_COMM_WORLD);
                busy[r] = 1;
                pos[r] = p;
            }
            nbusy += busy[r];
        }
        if (nbusy == 0 && atomic_load(&b->workers_left) <= 0)
            break;
        int flag = 0;
        MPI_Status status;
        if (nbusy > 0)
            MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag, &status);
        if (flag) {
            int r = status.MPI_SOURCE;
            MPI_Recv(in, (int)bytes, MPI_BYTE, r, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            double head[2];
            memcpy(head, in, sizeof head);
            rf_status st = (rf_status)(int)head[1];
            rf_error err;
            memset(&err, 0, sizeof err);
            if (st == RF_OK)
                memcpy(b->y + b->todo[pos[r]] * nout, in + 2 * sizeof(double), nout * sizeof(double));
            else {
                memcpy(err.msg, in + 2 * sizeof(double) + nout * sizeof(double), RF_ERROR_MAX);
                err.msg[RF_ERROR_MAX - 1] = '\0';
                err.code = st;
                rf_error_prefix(&err, "MPI rank %d", r);
            }
            rf_batch_finish(b, pos[r], st, &err, head[0]);
            b->remote++;
            busy[r] = 0;
            continue;
        }
        double t = rf_monotonic_seconds();
        if (t - last_draw >= 0.5) {
            rf_batch_progress(b, 0);
            last_draw = t;
        }
        struct timespec ts = {0, 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    free(pos);
    free(busy);
    free(in);
}

#else /* no MPI: one rank */

int rf_mpi_built(void)
{
    return 0;
}

rf_status rf_mpi_start(int *argc, char ***argv, int *rank, int *size, rf_error *err)
{
    (void)argc;
    (void)argv;
    *rank = 0;
    *size = 1;
    /* Started by mpirun with several ranks: each would run the whole study into the same store. */
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"};
    for (size_t k = 0; k < sizeof vars / sizeof *vars; k++) {
        const char *v = getenv(vars[k]);
        if (v && atoi(v) > 1)
            return rf_fail(err, RF_EINVAL, "started with %s=%s ranks, but this rockfuzz was built without MPI "
                                           "(ROCKFUZZ_MPI=OFF or no MPI found): every rank would run the whole "
                                           "study; rebuild with MPI or run without mpirun",
                           vars[k], v);
    }
    return RF_OK;
}

void rf_mpi_stop(void) {}

int rf_mpi_worker(const rf_model *model, const char *load_error)
{
    (void)model;
    (void)load_error;
    return 1;
}

rf_status rf_mpi_gather_hello(const rf_model *model, rf_error *err)
{
    (void)model;
    (void)err;
    return RF_OK;
}

void rf_mpi_release_workers(void) {}

void rf_mpi_serve_batch(rf_batch *b)
{
    while (atomic_load(&b->workers_left) > 0) {
        struct timespec ts = {0, 20 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
}

#endif
