/* block_traj_vtk.c - ParaView output of recorded rigid-block trajectories
 * (`outputs: {vtk: true}`; docs/block-shape.md "Wiring"): per trajectory k
 * (the first `record`) DIR/vtk/block_k.pvd and DIR/vtk/block_k_NNNN.vtp, a time
 * series of the block's surface at its events, written by
 * rf_block_write_vtk (block_vtk.c). */
#include "trajectory/block_traj.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The centre from an event's lowest point p and orientation q. */
static void state_of(const rf_block_shape *s, const double p[3], const double q[4], rf_block_state *st)
{
    const double up[3] = {0, 0, 1};
    double lp[3];
    memset(st, 0, sizeof *st);
    memcpy(st->q, q, sizeof st->q);
    rf_block_lowest_point(s, st, up, lp);
    for (int k = 0; k < 3; k++)
        st->x[k] = p[k] - lp[k];
}

/* Trajectory k's events (n of them: point, q) as states and times, written. */
static rf_status write_one(const char *dir, const rf_block_shape *s, size_t k, size_t n, const double *pts,
                           const double *qs, const double *ts, rf_error *err)
{
    rf_block_state *st = malloc((n ? n : 1) * sizeof *st);
    if (!st)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; i++)
        state_of(s, pts + 3 * i, qs + 4 * i, &st[i]);
    char stem[64];
    snprintf(stem, sizeof stem, "block_%zu", k);
    rf_status rc = rf_block_write_vtk(dir, stem, s, st, ts, n, err);
    free(st);
    return rc;
}

/* The events of a recorded trajectory as points (x, y, z), quaternions and times (malloc'd). */
static rf_status gather(const rf_traj_ensemble *e, size_t k, size_t *n, double **pts, double **qs, double **ts)
{
    int terrain = e->terrain != NULL;
    *n = terrain ? e->terrain->recorded[k].n_events : e->recorded[k].n_events;
    *pts = malloc((3 * *n + 1) * sizeof **pts), *qs = malloc((4 * *n + 1) * sizeof **qs);
    *ts = malloc((*n + 1) * sizeof **ts);
    if (!*pts || !*qs || !*ts)
        return RF_ENOMEM;
    for (size_t i = 0; i < *n; i++) {
        if (terrain) {
            const rf_terrain_event *v = &e->terrain->recorded[k].events[i];
            memcpy(*pts + 3 * i, v->p, 3 * sizeof(double)), memcpy(*qs + 4 * i, v->q, 4 * sizeof(double));
            (*ts)[i] = v->t;
        } else {
            const rf_traj_event *v = &e->recorded[k].events[i];
            double p[3] = {v->x, 0, v->y};
            memcpy(*pts + 3 * i, p, sizeof p), memcpy(*qs + 4 * i, v->q, 4 * sizeof(double));
            (*ts)[i] = v->t;
        }
    }
    return RF_OK;
}

rf_status traj_block_write_vtk_runs(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e, rf_error *err)
{
    if (!s->block_kind || !s->outputs.vtk)
        return RF_OK;
    char sub[4096]; /* the frames in DIR/vtk: thousands of files beside the engineer's tables would bury them */
    if ((size_t)snprintf(sub, sizeof sub, "%s/vtk", dir) >= sizeof sub)
        return rf_fail(err, RF_EINVAL, "output folder name too long: %s", dir);
    if (mkdir(sub, 0777) != 0 && errno != EEXIST)
        return rf_fail(err, RF_EIO, "cannot create %s: %s", sub, strerror(errno));
    rf_block_shape shape; /* at the file's values (a random volume is not followed here) */
    rf_status rc = traj_block_shape(s, &shape, err);
    size_t nrec = e->terrain ? e->terrain->n_recorded : e->n_recorded;
    for (size_t k = 0; rc == RF_OK && k < nrec; k++) {
        size_t n;
        double *pts = NULL, *qs = NULL, *ts = NULL;
        if (gather(e, k, &n, &pts, &qs, &ts) != RF_OK)
            rc = rf_fail(err, RF_ENOMEM, "out of memory");
        else
            rc = write_one(sub, &shape, k, n, pts, qs, ts, err);
        free(pts), free(qs), free(ts);
    }
    rf_block_shape_free(&shape); /* zeroed when it could not be built */
    return rc;
}
