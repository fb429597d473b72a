/* mpi_share.c - the two collective steps of a run shared over MPI ranks
 * (mpi.h: rf_mpi_agree, rf_mpi_gather_bytes), used by `mpirun rockfuzz
 * trajectory` on a terrain file (src/cli/traj_ranks.c): every rank agrees on
 * success or on the first failure (so that an error on any rank ends every
 * rank with its message, none left waiting), and rank 0 gathers each rank's
 * bytes in rank order.  MPI is called from each rank's main thread only.
 * Without ROCKFUZZ_HAVE_MPI (or outside mpirun) there is one rank and both
 * are trivial. */
#include "rockfuzz/mpi.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef ROCKFUZZ_HAVE_MPI
#include <mpi.h>

#define CHUNK ((size_t)1 << 24) /* bytes per message: far below MPI's int counts */
enum { TAG_SIZE = 11, TAG_BYTES = 12 };

typedef struct {
    int64_t status;
    uint64_t identity;
    char msg[RF_ERROR_MAX];
} agree_rec;

/* The ranks (1 when MPI is not running). */
static int ranks(int *rank)
{
    int on = 0, size = 1;
    *rank = 0;
    MPI_Initialized(&on);
    if (on) {
        int off = 0;
        MPI_Finalized(&off);
        if (!off) {
            MPI_Comm_rank(MPI_COMM_WORLD, rank);
            MPI_Comm_size(MPI_COMM_WORLD, &size);
        }
    }
    return size;
}

rf_status rf_mpi_agree(rf_status st, uint64_t identity, rf_error *err)
{
    int rank, size = ranks(&rank);
    if (size == 1)
        return st;
    agree_rec mine, *all = malloc((size_t)size * sizeof *all);
    memset(&mine, 0, sizeof mine);
    mine.status = st, mine.identity = identity;
    if (st != RF_OK && err)
        snprintf(mine.msg, sizeof mine.msg, "%s", err->msg);
    if (!all) {
        fprintf(stderr, "rockfuzz: MPI rank %d: out of memory agreeing with the other ranks\n", rank);
        MPI_Abort(MPI_COMM_WORLD, 1);
        return RF_ENOMEM;
    }
    MPI_Allgather(&mine, (int)sizeof mine, MPI_BYTE, all, (int)sizeof mine, MPI_BYTE, MPI_COMM_WORLD);
    rf_status out = RF_OK;
    for (int r = 0; r < size && out == RF_OK; r++) {
        all[r].msg[RF_ERROR_MAX - 1] = '\0';
        if (all[r].status != RF_OK)
            out = r == 0 ? rf_fail(err, (rf_status)all[r].status, "%s", all[r].msg)
                         : rf_fail(err, (rf_status)all[r].status, "MPI rank %d: %s", r, all[r].msg);
        else if (all[r].identity != all[0].identity)
            out = rf_fail(err, RF_EINVAL, "MPI rank %d read different inputs than rank 0 (identity %016llx vs "
                                          "%016llx): are the files the same on every node?",
                          r, (unsigned long long)all[r].identity, (unsigned long long)all[0].identity);
    }
    free(all);
    return out;
}

static void send_bytes(const void *buf, size_t bytes)
{
    uint64_t n = bytes;
    MPI_Send(&n, 1, MPI_UINT64_T, 0, TAG_SIZE, MPI_COMM_WORLD);
    for (size_t at = 0; at < bytes; at += CHUNK) {
        size_t k = bytes - at < CHUNK ? bytes - at : CHUNK;
        MPI_Send((const char *)buf + at, (int)k, MPI_BYTE, 0, TAG_BYTES, MPI_COMM_WORLD);
    }
}

/* Rank r's bytes into a new buffer (NULL when out of memory: they are
 * received and dropped, so that rank r does not wait forever). */
static void *recv_bytes(int r, size_t *bytes)
{
    uint64_t n = 0;
    MPI_Recv(&n, 1, MPI_UINT64_T, r, TAG_SIZE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    char *buf = n <= SIZE_MAX ? malloc(n ? (size_t)n : 1) : NULL;
    char *scratch = buf ? NULL : malloc(CHUNK);
    if (!buf && !scratch) {
        fprintf(stderr, "rockfuzz: MPI rank 0: out of memory receiving %llu bytes from rank %d\n",
                (unsigned long long)n, r);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    for (uint64_t at = 0; at < n; at += CHUNK) {
        size_t k = n - at < CHUNK ? (size_t)(n - at) : CHUNK;
        MPI_Recv(buf ? buf + at : scratch, (int)k, MPI_BYTE, r, TAG_BYTES, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
    free(scratch);
    *bytes = (size_t)n;
    return buf;
}

rf_status rf_mpi_gather_bytes(const void *buf, size_t bytes, rf_mpi_take_fn take, void *ctx, rf_error *err)
{
    int rank, size = ranks(&rank);
    if (size == 1)
        return RF_OK;
    if (rank > 0) {
        send_bytes(buf, bytes);
        return RF_OK;
    }
    rf_status st = RF_OK;
    for (int r = 1; r < size; r++) {
        size_t n = 0;
        void *got = recv_bytes(r, &n);
        if (st == RF_OK && !got)
            st = rf_fail(err, RF_ENOMEM, "out of memory receiving %zu bytes from MPI rank %d", n, r);
        else if (st == RF_OK && (st = take(ctx, r, got, n, err)) != RF_OK)
            rf_error_prefix(err, "MPI rank %d", r);
        free(got);
    }
    return st;
}

#else /* no MPI: one rank */

rf_status rf_mpi_agree(rf_status st, uint64_t identity, rf_error *err)
{
    (void)identity;
    (void)err;
    return st;
}

rf_status rf_mpi_gather_bytes(const void *buf, size_t bytes, rf_mpi_take_fn take, void *ctx, rf_error *err)
{
    (void)buf, (void)bytes, (void)take, (void)ctx, (void)err;
    return RF_OK;
}

#endif
