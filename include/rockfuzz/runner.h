/* runner.h - parallel evaluation of the TM's points (an rf_evaluator).
 *
 * A batch of points is evaluated by N worker threads that take the next
 * point from a shared atomic counter, so slow and fast evaluations balance
 * themselves.  Each point's output depends only on its x, so results are
 * identical whatever the thread count.  On a failure no new points are
 * handed out, and the failing point with the LOWEST index is reported (all
 * lower indices were handed out before it, so this is deterministic).
 *
 * With a result store (store.h) every point is first looked up by its exact
 * parameter vector; only missing points are evaluated, and each finished
 * evaluation (or failure) is committed at once by the thread that finished
 * it, under the store's mutex.  A store write error stops the batch (RF_EIO).
 *
 * Under MPI (mpi.h) the calling thread of rank 0 also hands points to the
 * worker ranks and commits what they send back; the local threads go on
 * evaluating from the same queue.
 *
 * Progress: one line (done/total including points found in the store,
 * failures, elapsed, time left estimated from the fresh evaluations only), or
 * one JSON object per finished evaluation (RF_PROGRESS_JSONL) for batch systems.
 *
 * Interruption: when *interrupt becomes non-zero (the caller's signal handler
 * sets it; the library installs none) no new point is handed out; the points
 * in flight finish and are stored, except those whose evaluation itself
 * returns RF_EINTERRUPTED (they stay marked "started, never finished").
 *
 * tolerate_failures: a failed point gets NaN outputs and the batch goes on
 * (the TM must then run with rf_tm_options.tolerate_failures, see tm.h). */
#ifndef ROCKFUZZ_RUNNER_H
#define ROCKFUZZ_RUNNER_H

#include <stdio.h>

#include "rockfuzz/model.h"
#include "rockfuzz/store.h"
#include "rockfuzz/tm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { RF_PROGRESS_NONE = 0, RF_PROGRESS_LINE = 1, RF_PROGRESS_JSONL = 2 } rf_progress_mode;

typedef struct {
    int jobs;              /* worker threads; 0 = rf_runner_default_jobs(model) */
    int progress;          /* rf_progress_mode (caller decides: TTY, --progress, --progress=jsonl) */
    FILE *stream;          /* progress stream, NULL = stderr */
    size_t planned_total;  /* total points expected over all batches (for the progress line), 0 = per batch */
    rf_store *store;       /* result store, NULL = none */
    int tolerate_failures; /* failed points get NaN outputs instead of stopping the batch */
    int mpi_workers;       /* worker ranks served by this (rank 0) process, 0 = no MPI */
    const atomic_int *interrupt; /* non-zero: hand out no more points, return RF_EINTERRUPTED
                                  * once those in flight have finished (NULL = never) */

    /* Statistics, accumulated over batches (read them after rf_tm_run). */
    size_t evaluated;      /* points evaluated successfully */
    size_t failed;         /* points that failed */
    size_t resumed;        /* points found in the store (not evaluated again) */
    double eval_seconds;   /* sum of the single evaluation times [s] (fresh evaluations) */
    double wall_seconds;   /* wall time spent inside batches [s] */
    double fresh_wall;     /* wall time of the batches' evaluation phases (for the estimate) [s] */
    size_t remote;         /* of the evaluated/failed points, how many ran on other MPI ranks */
    int jobs_used;         /* threads used by the last batch */
} rf_runner;

/* Defaults: automatic jobs, no progress, stderr. */
void rf_runner_init(rf_runner *runner);

/* Online cores / model->threads_per_eval, at least 1. */
int rf_runner_default_jobs(const rf_model *model);

/* The evaluator to put into rf_tm_options.evaluator; runner must outlive the run. */
rf_evaluator rf_runner_evaluator(rf_runner *runner);

/* Evaluate one batch directly (what the evaluator calls). */
rf_status rf_runner_evaluate(rf_runner *runner, const rf_model *model, size_t count, const double *x, double *y,
                             size_t *failed_index, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
