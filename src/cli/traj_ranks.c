/* traj_ranks.c - `mpirun -np K rockfuzz trajectory TERRAIN.yaml`: the
 * samples shared over the ranks.  Rank r runs the contiguous part
 * [N r / K, N (r + 1) / K) with its threads (rf_terrain_run_part), ranks > 0
 * pack their part, every rank agrees on success or on the first failure
 * (rf_mpi_agree: an error on any rank ends every rank with its message), and
 * rank 0 joins the parts in rank order (rf_mpi_gather_bytes,
 * rf_terrain_part_join).  Each sample's results depend only on the seed and
 * its index and the rasters merge by adding counts, so rank 0 ends with the
 * one-process ensemble, bit for bit.  The progress line is rank 0's own part,
 * scaled to the whole run. */
#include "cli/cli.h"
#include "core/util.h"
#include "rockfuzz/mpi.h"
#include "rockfuzz/terrain.h"

#include <stdlib.h>

typedef struct {
    rf_traj_progress_fn fn;
    void *ctx;
    size_t part, total;
} scaled_progress;

/* Rank 0's done of its part as done of the whole run (the ranks go at one pace). */
static void progress_scaled(void *ctx, size_t done, size_t part)
{
    const scaled_progress *p = ctx;
    (void)part;
    size_t whole = p->part ? (size_t)((double)done * (double)p->total / (double)p->part) : p->total;
    p->fn(p->ctx, whole < p->total ? whole : p->total, p->total);
}

static rf_status join_part(void *ctx, int rank, const void *buf, size_t bytes, rf_error *err)
{
    (void)rank;
    return rf_terrain_part_join(ctx, buf, bytes, err);
}

rf_status rf_cli_terrain_ranks(const rf_traj_spec *spec, int threads, int rank, int size, rf_traj_progress_fn progress,
                               void *ctx, rf_traj_ensemble *ens, rf_error *err)
{
    double t0 = rf_monotonic_seconds();
    size_t N = spec->samples, first = N * (size_t)rank / (size_t)size, end = N * (size_t)(rank + 1) / (size_t)size;
    scaled_progress sp = {progress, ctx, end - first, N};
    int shown = rank == 0 && progress;
    rf_status st = rf_terrain_run_part(spec, first, end, threads, shown ? progress_scaled : NULL, shown ? &sp : NULL,
                                       ens, err);
    void *buf = NULL;
    size_t bytes = 0;
    if (rank > 0 && st == RF_OK) {
        st = rf_terrain_part_pack(ens, first, &buf, &bytes, err);
        rf_traj_ensemble_free(ens); /* the part travels as bytes */
    }
    st = rf_mpi_agree(st, 0, err);
    if (st == RF_OK)
        st = rf_mpi_gather_bytes(buf, bytes, join_part, ens, err);
    free(buf);
    if (rank > 0 || st != RF_OK)
        rf_traj_ensemble_free(ens);
    else
        ens->wall_seconds = rf_monotonic_seconds() - t0;
    return st;
}
