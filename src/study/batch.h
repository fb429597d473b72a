/* batch.h - one batch of the runner (batch.c), shared by runner.c (threads)
 * and mpi.c (rank 0 serving worker ranks from the same queue). */
#ifndef ROCKFUZZ_BATCH_H
#define ROCKFUZZ_BATCH_H

#include <pthread.h>
#include <stdatomic.h>

#include "core/util.h"
#include "rockfuzz/runner.h"

typedef struct {
    rf_runner *runner;
    const rf_model *model;
    size_t count;            /* points in the batch */
    const double *x;
    double *y;
    size_t *todo;            /* batch indices still to evaluate (not in the store) */
    size_t ntodo;
    size_t resumed;          /* found in the store */
    double t_start;          /* start of the evaluation phase (monotonic s) */
    atomic_size_t next;      /* next position in todo to hand out */
    atomic_size_t done;      /* finished (ok or failed) fresh points */
    atomic_size_t nfailed;
    atomic_int stop;
    atomic_int workers_left; /* started local workers that have not returned */
    pthread_mutex_t lock;    /* guards the fields below, the store writes and the JSONL stream */
    size_t first_failed;     /* lowest failing batch index, count if none */
    rf_error first_err;
    int store_failed;        /* a store write failed: the batch stops with store_err */
    rf_error store_err;
    double eval_seconds;
    size_t remote;
    size_t interrupted;      /* evaluations that returned RF_EINTERRUPTED */
} rf_batch;

/* Take the next todo position, or return 0 when there is none or the batch stops. */
int rf_batch_take(rf_batch *b, size_t *pos);

/* Take up to want consecutive todo positions [*pos, *pos + *got), or return 0 as rf_batch_take. */
int rf_batch_take_chunk(rf_batch *b, size_t want, size_t *pos, size_t *got);

/* Record n successful evaluations (y rows written) that took seconds in all: one lock, no store
 * write, no JSONL line (for a batch without a store and without JSONL progress). */
void rf_batch_finish_ok(rf_batch *b, size_t n, double seconds);

/* Mark todo[pos] as started in the store (before evaluating it). */
void rf_batch_start(rf_batch *b, size_t pos);

/* Record a finished evaluation of todo[pos]: y row already written (or not, on
 * failure), commit to the store, update counts, print a JSONL line. */
void rf_batch_finish(rf_batch *b, size_t pos, rf_status st, const rf_error *err, double seconds);

/* Draw the progress line (final: with a newline). */
void rf_batch_progress(rf_batch *b, int final);

#endif
