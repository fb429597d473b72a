/* runner.h - parallel evaluation of the TM's points (an rf_evaluator).
 *
 * A batch of points is evaluated by N worker threads that take the next
 * point from a shared atomic counter, so slow and fast evaluations balance
 * themselves.  Each point's output depends only on its x, so results are
 * identical whatever the thread count.  On a failure no new points are
 * handed out, and the failing point with the LOWEST index is reported (all
 * lower indices were handed out before it, so this is deterministic).
 *
 * The runner optionally prints one progress line to a stream (done/total,
 * failures, elapsed, estimated time left from the measured evaluation times). */
#ifndef ROCKFUZZ_RUNNER_H
#define ROCKFUZZ_RUNNER_H

#include <stdio.h>

#include "rockfuzz/model.h"
#include "rockfuzz/tm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int jobs;              /* worker threads; 0 = rf_runner_default_jobs(model) */
    int progress;          /* print a progress line (caller decides: TTY or --progress) */
    FILE *stream;          /* progress stream, NULL = stderr */
    size_t planned_total;  /* total points expected over all batches (for the progress line), 0 = per batch */

    /* Statistics, accumulated over batches (read them after rf_tm_run). */
    size_t evaluated;      /* points evaluated successfully */
    size_t failed;         /* points that failed */
    double eval_seconds;   /* sum of the single evaluation times [s] */
    double wall_seconds;   /* wall time spent inside batches [s] */
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
