/* mpi.h - studies distributed over MPI ranks (optional: ROCKFUZZ_HAVE_MPI).
 *
 * `mpirun -np K rockfuzz run STUDY.yaml --out DIR`: every rank loads the same
 * study; rank 0 runs the TM, owns the result store and hands points out one at
 * a time (dynamic balance); ranks 1..K-1 evaluate them and send the outputs
 * back.  Outputs depend only on x, so the result is the same bit for bit as a
 * serial run.  With K = 1, or without mpirun, nothing changes.
 *
 * Protocol (tags): a worker first sends HELLO (loaded ok? + model identity;
 * rank 0 refuses to run if any rank has a different identity), then answers
 * every WORK message (x) with one RESULT (status, seconds, y, message) until
 * it receives STOP.  Rank 0 always collects every HELLO and always ends with
 * STOP to every worker, also on errors, so no rank is left waiting.
 * MPI is called from rank 0's main thread only (MPI_THREAD_FUNNELED). */
#ifndef ROCKFUZZ_MPI_H
#define ROCKFUZZ_MPI_H

#include "rockfuzz/model.h"
#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1 if this build has MPI. */
int rf_mpi_built(void);

/* Initialise MPI if the process was started by mpirun/srun (environment),
 * else rank 0 of 1.  Returns RF_OK with *rank and *size set. */
rf_status rf_mpi_start(int *argc, char ***argv, int *rank, int *size, rf_error *err);

/* Finalise MPI if rf_mpi_start initialised it. */
void rf_mpi_stop(void);

/* Ranks > 0: say hello (model == NULL: the study failed to load, load_error
 * says why), then evaluate until STOP.  Returns the process exit status. */
int rf_mpi_worker(const rf_model *model, const char *load_error);

/* Rank 0: collect every worker's HELLO; fails if one could not load the study
 * or has a different model identity. */
rf_status rf_mpi_gather_hello(const rf_model *model, rf_error *err);

/* Rank 0: send STOP to every worker. */
void rf_mpi_release_workers(void);

#ifdef __cplusplus
}
#endif
#endif
