/* block_vtk.c - ParaView output of a block moving along its path (issue 30):
 * dir/stem.pvd (a VTK collection, one data set per recorded time) and one
 * dir/stem_NNNN.vtp per recorded state (VTK XML PolyData, ASCII): the
 * block's surface in space at that pose, p = x + R(q) p_body.  A
 * polyhedron's hull triangles as they are; a sphere or an ellipsoid as a
 * latitude-longitude tessellation of its surface (VTK_LAT x VTK_LON).  Each
 * piece carries the time [s] as field data and the velocity of each surface
 * point [m/s] (v + R (w x p_body)) as point data.  Coordinates in m, printed
 * with 17 significant digits (they read back exactly). */
#include "trajectory/block_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VTK_LAT 12 /* rings of a smooth block's tessellation, poles included as points */
#define VTK_LON 24

/* The body-frame surface: np points, nt triangles (malloc'd). */
typedef struct {
    size_t np, nt;
    double *p;
    int *t;
} surface;

static void ring_tris(int *t, size_t *nt, int a, int b, int c)
{
    t[3 * *nt] = a, t[3 * *nt + 1] = b, t[3 * *nt + 2] = c;
    (*nt)++;
}

/* A smooth block: poles 0 and 1, then VTK_LAT - 1 rings of VTK_LON points;
 * triangles counter-clockwise seen from outside. */
static void smooth_surface(const rf_block_shape *s, surface *m)
{
    const double pi = 3.14159265358979323846;
    m->np = 2, m->nt = 0;
    m->p[0] = 0, m->p[1] = 0, m->p[2] = s->semi[2];
    m->p[3] = 0, m->p[4] = 0, m->p[5] = -s->semi[2];
    for (int i = 1; i < VTK_LAT; i++)
        for (int j = 0; j < VTK_LON; j++, m->np++) {
            double th = pi * i / VTK_LAT, ph = 2 * pi * j / VTK_LON;
            m->p[3 * m->np] = s->semi[0] * sin(th) * cos(ph);
            m->p[3 * m->np + 1] = s->semi[1] * sin(th) * sin(ph);
            m->p[3 * m->np + 2] = s->semi[2] * cos(th);
        }
    for (int j = 0; j < VTK_LON; j++) {
        int j1 = (j + 1) % VTK_LON, last = 2 + (VTK_LAT - 2) * VTK_LON;
        ring_tris(m->t, &m->nt, 0, 2 + j, 2 + j1);
        ring_tris(m->t, &m->nt, 1, last + j1, last + j);
        for (int i = 0; i < VTK_LAT - 2; i++) {
            int a = 2 + i * VTK_LON + j, b = 2 + i * VTK_LON + j1;
            ring_tris(m->t, &m->nt, a, a + VTK_LON, b);
            ring_tris(m->t, &m->nt, b, a + VTK_LON, b + VTK_LON);
        }
    }
}

static rf_status make_surface(const rf_block_shape *s, surface *m, rf_error *err)
{
    int poly = s->kind == RF_BLOCK_POLYHEDRON;
    size_t np = poly ? s->n_vertices : 2 + (VTK_LAT - 1) * VTK_LON;
    size_t nt = poly ? s->n_faces : 2 * VTK_LON * (VTK_LAT - 1);
    m->p = malloc(3 * np * sizeof *m->p), m->t = malloc(3 * nt * sizeof *m->t);
    if (!m->p || !m->t) {
        free(m->p), free(m->t);
        return rf_fail(err, RF_ENOMEM, "block VTK output: out of memory");
    }
    if (poly) {
        m->np = np, m->nt = nt;
        memcpy(m->p, s->vertices, 3 * np * sizeof *m->p);
        memcpy(m->t, s->faces, 3 * nt * sizeof *m->t);
    } else {
        smooth_surface(s, m);
    }
    return RF_OK;
}

static void write_piece(FILE *f, const surface *m, const rf_block_state *st, double time)
{
    double r[9];
    bk_quat_matrix(st->q, r);
    fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "<PolyData>\n<FieldData>\n<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
               "format=\"ascii\">%.17g</DataArray>\n</FieldData>\n",
            time);
    fprintf(f, "<Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
               "NumberOfPolys=\"%zu\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
               "format=\"ascii\">\n",
            m->np, m->nt);
    for (size_t i = 0; i < m->np; i++) {
        double p[3];
        bk_mat_vec(r, m->p + 3 * i, p);
        fprintf(f, "%.17g %.17g %.17g\n", st->x[0] + p[0], st->x[1] + p[1], st->x[2] + p[2]);
    }
    fprintf(f, "</DataArray>\n</Points>\n<PointData Vectors=\"velocity\">\n<DataArray type=\"Float64\" "
               "Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (size_t i = 0; i < m->np; i++) {
        double wb[3], u[3];
        bk_cross(st->w, m->p + 3 * i, wb);
        bk_mat_vec(r, wb, u);
        fprintf(f, "%.9g %.9g %.9g\n", st->v[0] + u[0], st->v[1] + u[1], st->v[2] + u[2]);
    }
    fprintf(f, "</DataArray>\n</PointData>\n<Polys>\n<DataArray type=\"Int32\" Name=\"connectivity\" "
               "format=\"ascii\">\n");
    for (size_t k = 0; k < m->nt; k++)
        fprintf(f, "%d %d %d\n", m->t[3 * k], m->t[3 * k + 1], m->t[3 * k + 2]);
    fprintf(f, "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for (size_t k = 0; k < m->nt; k++)
        fprintf(f, "%zu%c", 3 * (k + 1), k + 1 == m->nt || (k + 1) % 16 == 0 ? '\n' : ' ');
    fprintf(f, "</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n");
}

static rf_status check_args(const char *dir, const char *stem, const rf_block_state *states, const double *times,
                            size_t n, rf_error *err)
{
    if (!dir || !*dir || !stem || !*stem || strchr(stem, '/'))
        return rf_fail(err, RF_EINVAL, "block VTK output: stem '%s' must be a non-empty file name without '/' (and "
                       "dir non-empty)", stem ? stem : "(null)");
    if (!n || !states || !times)
        return rf_fail(err, RF_EINVAL, "block VTK output: no states to write (n = %zu)", n);
    for (size_t k = 0; k < n; k++)
        if (!isfinite(times[k]) || (k && !(times[k] > times[k - 1])))
            return rf_fail(err, RF_EINVAL, "block VTK output: times[%zu] = %g; finite, increasing times are needed",
                           k, times[k]);
    return RF_OK;
}

static rf_status close_file(FILE *f, const char *path, rf_error *err)
{
    int bad = ferror(f);
    if (fclose(f) || bad)
        return rf_fail(err, RF_EIO, "block VTK output: writing %s failed: %s", path, strerror(errno));
    return RF_OK;
}

static rf_status write_pvd(const char *dir, const char *stem, const double *times, size_t n, rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.pvd", dir, stem);
    FILE *f = fopen(path, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "block VTK output: cannot write %s: %s", path, strerror(errno));
    fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "<Collection>\n");
    for (size_t k = 0; k < n; k++)
        fprintf(f, "<DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"%s_%04zu.vtp\"/>\n", times[k], stem, k);
    fprintf(f, "</Collection>\n</VTKFile>\n");
    return close_file(f, path, err);
}

rf_status rf_block_write_vtk(const char *dir, const char *stem, const rf_block_shape *s, const rf_block_state *states,
                             const double *times, size_t n, rf_error *err)
{
    rf_status rc = check_args(dir, stem, states, times, n, err);
    if (rc)
        return rc;
    if (strlen(dir) + strlen(stem) > 4000)
        return rf_fail(err, RF_EINVAL, "block VTK output: the path %s/%s is too long", dir, stem);
    surface m;
    if ((rc = make_surface(s, &m, err)))
        return rc;
    for (size_t k = 0; k < n && !rc; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s_%04zu.vtp", dir, stem, k);
        FILE *f = fopen(path, "w");
        if (!f) {
            rc = rf_fail(err, RF_EIO, "block VTK output: cannot write %s: %s", path, strerror(errno));
            break;
        }
        write_piece(f, &m, &states[k], times[k]);
        rc = close_file(f, path, err);
    }
    free(m.p), free(m.t);
    return rc ? rc : write_pvd(dir, stem, times, n, err);
}
