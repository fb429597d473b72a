/* block_traj_vtk.c - ParaView output of recorded rigid-block trajectories
 * (`outputs: {vtk: true}`; docs/block-shape.md "Wiring"): per trajectory k
 * (the first `record`) DIR/vtk/block_k.pvd and DIR/vtk/block_k_NNNN.vtp, a time
 * series of the block's surface at its events, written by
 * rf_block_write_vtk (block_vtk.c), with the shape of that sample (its
 * random volume, axis ratios and edges drawn again as the run drew them:
 * recorded trajectory k is sample k in both engines).  A terrain run's
 * trajectories.csv of a block is written here too (block_traj_paths.c). */
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

/* The events of a recorded trajectory as points (x, y, z), quaternions and times (malloc'd); of events at
 * one time (an exit or the end right at a regular event) the last is kept: a frame per time. */
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
    size_t m = 0;
    for (size_t i = 0; i < *n; i++) {
        if (m && (*ts)[i] <= (*ts)[m - 1])
            m--; /* the same time as the frame before: this later event replaces it */
        memmove(*pts + 3 * m, *pts + 3 * i, 3 * sizeof(double)), memmove(*qs + 4 * m, *qs + 4 * i, 4 * sizeof(double));
        (*ts)[m++] = (*ts)[i];
    }
    *n = m;
    return RF_OK;
}

/* The random inputs of the run, drawn again: a copy of the spec whose bound fields take sample i's
 * values (traj_draw.c, with the same Latin hypercube as the engine's run when the spec asks for one). */
typedef struct {
    rf_traj_spec local;
    const rf_traj_field **row;
    double **field;
    size_t *perm;
} redraw;

static rf_status redraw_init(redraw *r, const rf_traj_spec *s, int terrain, rf_error *err)
{
    memset(r, 0, sizeof *r);
    size_t nr = s->n_random ? s->n_random : 1;
    /* the engines' dimensions: the random inputs, then the release point's (terrain: 3; a profile: 1 unless a point) */
    size_t dims = s->n_random + (terrain ? 3 : s->release_kind != RF_TRAJ_RELEASE_POINT);
    r->row = calloc(nr, sizeof *r->row), r->field = calloc(nr, sizeof *r->field);
    if (!r->row || !r->field || (s->lhs && dims && !(r->perm = traj_lhs_permutations(s, dims))))
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_status rc = rf_traj_spec_copy(s, &r->local, err);
    if (rc == RF_OK)
        traj_draw_bind(&r->local, s, r->row, r->field);
    return rc;
}

static void redraw_free(redraw *r)
{
    rf_traj_spec_free(&r->local);
    free(r->row), free(r->field), free(r->perm);
}

/* Sample k's shape. */
static rf_status sample_shape(redraw *r, const rf_traj_spec *s, size_t k, rf_block_shape *shape, rf_error *err)
{
    traj_draw_inputs(s, r->perm, k, r->row, r->field);
    return traj_block_shape(&r->local, shape, err);
}

rf_status traj_block_write_vtk_runs(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e, rf_error *err)
{
    if (s->block_kind && e->terrain) {
        rf_status rc = traj_block_write_terrain_paths(dir, s, e, err); /* block_traj_paths.c */
        if (rc != RF_OK)
            return rc;
    }
    if (!s->block_kind || !s->outputs.vtk)
        return RF_OK;
    char sub[4096]; /* the frames in DIR/vtk: thousands of files beside the engineer's tables would bury them */
    if ((size_t)snprintf(sub, sizeof sub, "%s/vtk", dir) >= sizeof sub)
        return rf_fail(err, RF_EINVAL, "output folder name too long: %s", dir);
    if (mkdir(sub, 0777) != 0 && errno != EEXIST)
        return rf_fail(err, RF_EIO, "cannot create %s: %s", sub, strerror(errno));
    redraw r;
    rf_status rc = redraw_init(&r, s, e->terrain != NULL, err);
    size_t nrec = e->terrain ? e->terrain->n_recorded : e->n_recorded;
    for (size_t k = 0; rc == RF_OK && k < nrec; k++) {
        size_t n;
        double *pts = NULL, *qs = NULL, *ts = NULL;
        rf_block_shape shape; /* sample k's */
        if ((rc = sample_shape(&r, s, k, &shape, err)) != RF_OK) {
            rf_block_shape_free(&shape);
            break;
        }
        if (gather(e, k, &n, &pts, &qs, &ts) != RF_OK)
            rc = rf_fail(err, RF_ENOMEM, "out of memory");
        else
            rc = write_one(sub, &shape, k, n, pts, qs, ts, err);
        free(pts), free(qs), free(ts);
        rf_block_shape_free(&shape);
    }
    redraw_free(&r);
    return rc;
}
