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

#include <stddef.h>
#include <stdint.h>

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

/* ---- a run shared by every rank (mpi_share.c; `mpirun rockfuzz
 * trajectory` on a terrain file, src/cli/traj_ranks.c) ---- */

/* Collective (every rank calls it, in the same order): each rank gives its
 * status (err->msg its message when not RF_OK) and an identity of what it
 * read; every rank gets RF_OK, or the lowest failing rank's status and
 * message ("MPI rank r: ..."), or RF_EINVAL when a rank's identity is not
 * rank 0's.  One rank: returns st. */
rf_status rf_mpi_agree(rf_status st, uint64_t identity, rf_error *err);
/* Collective: every rank > 0 sends its bytes to rank 0 and returns RF_OK;
 * rank 0 hands them to take(ctx, r, buf, bytes, err) for r = 1, 2, ... in
 * order, receives every rank's bytes even after a failure (no rank waits
 * forever) and returns the first failure, prefixed "MPI rank r".  One rank:
 * nothing. */
typedef rf_status (*rf_mpi_take_fn)(void *ctx, int rank, const void *buf, size_t bytes, rf_error *err);
rf_status rf_mpi_gather_bytes(const void *buf, size_t bytes, rf_mpi_take_fn take, void *ctx, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
