/* study_run.h - one library call that runs a whole study: load the study
 * file, take the output folder, open its result store, run the TM through the
 * parallel runner (threads, MPI ranks), analyse, and write the outputs.
 * `rockfuzz run` only parses its command line and calls this.
 *
 * What the call guarantees (docs/user-guide.md, "Guarantees"):
 *   - the output folder is locked for the whole run (DIR/rockfuzz.lock, an
 *     exclusive flock): a second run into it is refused, naming the holder;
 *   - a non-empty folder that holds no rockfuzz run is refused unless
 *     opt->force, so the user's own files are never overwritten by surprise;
 *   - a damaged or foreign store is refused before anything in the folder is
 *     written (see rf_store_open);
 *   - the result.json of the last complete run stays until this run has
 *     evaluated and analysed everything; then the report is rewritten and
 *     result.json, written last and atomically, replaces it.
 *
 * Signals: a library must not take over the process's signal handling, so
 * this call installs no handler.  The program does (e.g. SIGINT/SIGTERM set
 * an atomic flag) and passes the flag in opt->interrupt: then no new
 * evaluation starts, external programs in flight are killed and reaped, every
 * finished evaluation is in the store, and the call returns RF_EINTERRUPTED. */
#ifndef ROCKFUZZ_STUDY_RUN_H
#define ROCKFUZZ_STUDY_RUN_H

#include <stdatomic.h>
#include <stdio.h>

#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The lock file inside an output folder; its text names the holder. */
#define RF_RUN_LOCK_FILE "rockfuzz.lock"

typedef struct {
    const char *out_dir;         /* output folder (created if missing); required */
    int jobs;                    /* worker threads; 0 = options.jobs of the study, else automatic */
    long long max_evaluations;   /* cap; -1 = options.max_evaluations of the study */
    int progress;                /* rf_progress_mode (runner.h) */
    int fresh;                   /* discard the stored results (rf_store_open) */
    int tolerate_failures;       /* failed evaluations are stored and left out of the bounds */
    int plots;                   /* write the PNG/SVG figures */
    int force;                   /* accept a non-empty folder that holds no rockfuzz run */
    const atomic_int *interrupt; /* set non-zero to stop (see above); NULL = never */
    FILE *out;                   /* plan and summary (stdout); NULL = silent */
    FILE *log;                   /* warnings and notes (stderr); NULL = silent */
    int mpi_rank, mpi_ranks;     /* from rf_mpi_start (0 and 1 without MPI) */
} rf_study_run_options;

/* What the run did (also filled on failure, as far as it got). */
typedef struct {
    size_t evaluated, failed, resumed; /* this run's fresh, failed and stored-before evaluations */
    double wall_seconds;
    int jobs;
} rf_study_run_stats;

/* Defaults: automatic jobs, the study's cap, plots on, everything else off. */
void rf_study_run_options_default(rf_study_run_options *opt);

/* Run the study file at study_path.  On a worker MPI rank (mpi_rank > 0) this
 * evaluates what rank 0 sends and returns.  Errors name the file and field
 * (study), the folder (lock, store) or the failing evaluation. */
rf_status rf_study_run(const char *study_path, const rf_study_run_options *opt, rf_study_run_stats *stats,
                       rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
