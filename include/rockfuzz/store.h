/* store.h - the result store of a study run: every model evaluation, committed
 * to an SQLite database (DIR/store.sqlite) the moment it finishes.
 *
 * What it is for: a study killed at any point loses only the evaluations in
 * flight; rerunning it into the same directory looks every point up by its
 * exact parameter vector (the bytes of the doubles) and evaluates only the
 * missing ones.  The store remembers the model identity (rf_model.identity),
 * the rockfuzz version and the input/output names; a store written by a
 * different model, setting or version is refused, never silently mixed.
 *
 * Layout (format_version 1):
 *   meta(key TEXT PRIMARY KEY, value TEXT)   format = "rockfuzz-store", identity,
 *                                            rockfuzz_version, inputs, outputs, and
 *                                            the current run's plan (planned_total,
 *                                            run_started, run_pid, run_host, study)
 *   results(x BLOB PRIMARY KEY, ok INTEGER, y BLOB, error TEXT, seconds REAL,
 *           finished REAL, x_text TEXT)
 *   ok = 1 result, 0 failed (error), -1 started but never finished (the
 *   process was killed, or the evaluation crashed it: `status` lists these)
 * WAL journal; one transaction per row (INSERT OR REPLACE: a stored failure
 * or unfinished point is evaluated again on the next run and replaced).
 *
 * Thread safety: every function may be called from any thread; calls on one
 * store are serialised by its own mutex (one writer at a time). */
#ifndef ROCKFUZZ_STORE_H
#define ROCKFUZZ_STORE_H

#include <stddef.h>

#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rf_store rf_store;

#define RF_STORE_FILE "store.sqlite"

/* What a store belongs to: results are reused only when all of this matches. */
typedef struct {
    const char *identity;             /* rf_model.identity (model + settings) */
    const char *version;              /* rockfuzz version that computes the outputs */
    size_t n_inputs, n_outputs;
    const char *const *input_names;   /* x[i] is the value of input_names[i] */
    const char *const *output_names;
} rf_store_key;

/* Open (or create) the store at path for the given key.  An existing file
 * is first checked, reading only: it must be a rockfuzz store and pass
 * SQLite's integrity check (PRAGMA quick_check).  A foreign or damaged file is
 * refused (RF_EIO) and left exactly as it was.  A rockfuzz store of a
 * different key is refused (RF_EINVAL) with the first difference named.  With
 * fresh set, a store of another key has its results deleted, and a damaged
 * store is moved aside to PATH.damaged (with its -wal/-shm files) and a new
 * one created; a foreign file is never touched. */
rf_status rf_store_open(const char *path, const rf_store_key *key, int fresh, rf_store **out, rf_error *err);

/* Record the start of a run: distinct points planned, study name, pid, host, time. */
rf_status rf_store_begin_run(rf_store *s, size_t planned_total, const char *study_name, rf_error *err);

/* 1: a successful result for x exists and was copied to y[0..n_outputs-1];
 * 0: none (or only a failure); RF_* < 0 never: errors return -1 with err set. */
int rf_store_lookup(rf_store *s, const double *x, double *y, rf_error *err);

/* Commit one result: y (n_outputs values) when ok, else the error message. */
rf_status rf_store_put(rf_store *s, const double *x, int ok, const double *y, const char *error, double seconds,
                       rf_error *err);

/* Mark x as being evaluated now (ok = -1), so that a point that kills the
 * process leaves a trace; rf_store_put replaces the row. */
rf_status rf_store_put_started(rf_store *s, const double *x, rf_error *err);

void rf_store_close(rf_store *s);

/* A note kept with the store's meta data (key must not be one of the store's
 * own keys, e.g. "model_warnings"); get returns "" when absent. */
rf_status rf_store_note_set(rf_store *s, const char *key, const char *value, rf_error *err);
rf_status rf_store_note_get(rf_store *s, const char *key, char *buf, size_t size, rf_error *err);

/* Side rows of a model (rf_model_side_store, model.h): width doubles under a
 * text key, committed at once (an identical row kept once); each calls fn
 * on every row of key in the order written, checks each row's width (a
 * wrong one: RF_EIO naming the store) and stops at fn's first error. */
rf_status rf_store_side_put(rf_store *s, const char *key, const double *row, size_t width, rf_error *err);
rf_status rf_store_side_each(rf_store *s, const char *key, size_t width, rf_status (*fn)(void *u, const double *row),
                             void *u, rf_error *err);

/* Fault injection for tests (SQLite's PRAGMA max_page_count): writes beyond
 * this many pages fail as a full disk would. */
rf_status rf_store_limit_pages(rf_store *s, long pages, rf_error *err);

/* What `rockfuzz status` shows, read without modifying the store. */
typedef struct {
    char identity[2048];
    char version[64];
    char study[256];
    char host[256];
    long pid;
    size_t planned_total;     /* distinct points of the current plan (0 if never started) */
    size_t done;              /* successful results stored */
    size_t failed;            /* failed evaluations stored */
    size_t unfinished;        /* started but never finished (killed, or crashed the process) */
    size_t done_this_run;     /* results (ok or failed) finished since run_started */
    double run_started;       /* Unix time [s], 0 if unknown */
    double first_update;      /* Unix time of the first / last stored result, 0 if none */
    double last_update;
    double eval_seconds;      /* sum of the stored evaluation times [s] */
} rf_store_info;

rf_status rf_store_read_info(const char *path, rf_store_info *info, rf_error *err);

/* The failed evaluations (parameter vector as text, message; unfinished ones
 * with the message "started, never finished"), up to max; returns the count written. */
size_t rf_store_failures(const char *path, size_t max, char (*x_text)[512], char (*message)[512], rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
