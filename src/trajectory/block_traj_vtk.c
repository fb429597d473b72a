/* block_traj_vtk.c - ParaView output of recorded rigid-block trajectories
 * (`outputs: {vtk: true}`; docs/block-shape.md "Wiring"): per trajectory k
 * (the first `record`) DIR/block_k.pvd, a time series of the block's hull
 * at its events.  The writer is rf_block_write_vtk (block_vtk.c, the
 * blockfast engineer's); it is not on main yet, so block_write_vtk_stub here
 * has its signature and writes the same files (legacy-free VTK XML
 * PolyData: the hull's triangles; an ellipsoid as its 26-point support
 * polyhedron).  Replace the stub's call once rf_block_write_vtk is in. */
#include "trajectory/block_traj.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A smooth shape's surface as the hull of its support points along 26 directions. */
static rf_status hull_of(const rf_block_shape *s, rf_block_shape *poly, rf_error *err)
{
    double pts[26 * 3];
    int n = 0;
    for (int i = -1; i <= 1; i++)
        for (int j = -1; j <= 1; j++)
            for (int k = -1; k <= 1; k++)
                if (i || j || k) {
                    double d[3] = {i, j, k};
                    rf_block_support(s, d, pts + 3 * n++);
                }
    return rf_block_polyhedron((size_t)n, pts, s->density, poly, err);
}

static void write_frame(FILE *f, const rf_block_shape *p, const rf_block_state *st)
{
    fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData>\n"
               "<Piece NumberOfPoints=\"%zu\" NumberOfPolys=\"%zu\">\n<Points>\n"
               "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n", p->n_vertices, p->n_faces);
    for (size_t i = 0; i < p->n_vertices; i++) {
        double s[3];
        rf_block_to_space(st->q, p->vertices + 3 * i, s);
        fprintf(f, "%.9g %.9g %.9g\n", st->x[0] + s[0], st->x[1] + s[1], st->x[2] + s[2]);
    }
    fputs("</DataArray>\n</Points>\n<Polys>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n", f);
    for (size_t i = 0; i < p->n_faces; i++)
        fprintf(f, "%d %d %d\n", p->faces[3 * i], p->faces[3 * i + 1], p->faces[3 * i + 2]);
    fputs("</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n", f);
    for (size_t i = 0; i < p->n_faces; i++)
        fprintf(f, "%zu\n", 3 * (i + 1));
    fputs("</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n", f);
}

/* The signature of rf_block_write_vtk: DIR/STEM.pvd and DIR/STEM_K.vtp. */
static rf_status block_write_vtk_stub(const char *dir, const char *stem, const rf_block_shape *s,
                                      const rf_block_state *states, const double *times, size_t n, rf_error *err)
{
    rf_block_shape poly;
    rf_status st = s->kind == RF_BLOCK_POLYHEDRON ? rf_block_copy(s, &poly, err) : hull_of(s, &poly, err);
    if (st != RF_OK)
        return st;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.pvd", dir, stem);
    FILE *pvd = fopen(path, "w");
    if (!pvd) {
        rf_block_shape_free(&poly);
        return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
    }
    fputs("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n", pvd);
    for (size_t k = 0; k < n && st == RF_OK; k++) {
        snprintf(path, sizeof path, "%s/%s_%zu.vtp", dir, stem, k);
        FILE *f = fopen(path, "w");
        if (!f) {
            st = rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
            break;
        }
        write_frame(f, &poly, &states[k]);
        if (fclose(f) != 0)
            st = rf_fail(err, RF_EIO, "cannot write %s", path);
        fprintf(pvd, "<DataSet timestep=\"%.9g\" file=\"%s_%zu.vtp\"/>\n", times[k], stem, k);
    }
    fputs("</Collection>\n</VTKFile>\n", pvd);
    if (fclose(pvd) != 0 && st == RF_OK)
        st = rf_fail(err, RF_EIO, "cannot write %s/%s.pvd", dir, stem);
    rf_block_shape_free(&poly);
    return st;
}

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
    rf_status rc = block_write_vtk_stub(dir, stem, s, st, ts, n, err);
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
    rf_block_shape shape; /* at the file's values (a random volume is not followed here) */
    rf_status rc = traj_block_shape(s, &shape, err);
    size_t nrec = e->terrain ? e->terrain->n_recorded : e->n_recorded;
    for (size_t k = 0; rc == RF_OK && k < nrec; k++) {
        size_t n;
        double *pts = NULL, *qs = NULL, *ts = NULL;
        if (gather(e, k, &n, &pts, &qs, &ts) != RF_OK)
            rc = rf_fail(err, RF_ENOMEM, "out of memory");
        else
            rc = write_one(dir, &shape, k, n, pts, qs, ts, err);
        free(pts), free(qs), free(ts);
    }
    rf_block_shape_free(&shape); /* zeroed when it could not be built */
    return rc;
}
