/* terrain_io_release.c - release features (rf_terrain_release) read with
 * GDAL/OGR: from a vector layer (GeoPackage, shapefile, GeoJSON, any OGR
 * format) or from a release raster.
 *
 * Vector: one kind per layer: points, lines or polygons (their multi-
 * geometries split into parts; curves, collections and mixed kinds refused).
 * A feature's weight is its `count_field` (1 without one; with per_area the
 * field is blocks per m^2 of a polygon, the weight that times the area); a
 * multi-geometry's parts share it in proportion to their length (lines),
 * area (polygons) or equally (points).  A polygon with holes is refused:
 * release areas are simple rings (cut a hole into parts in a GIS).  A polygon
 * ring is stored without its repeated first vertex.  Only x, y are read.
 * A geographic or non-metre CRS is refused (a GeoJSON file without a "crs"
 * member is WGS 84 by its standard); no CRS is accepted.
 *
 * Raster: every cell holding a positive value (not no-data) becomes a square
 * polygon (south-west, south-east, north-east, north-west corner) of that
 * weight. */
#include "trajectory/terrain_internal.h"
#include "trajectory/traj_gdal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef ROCKFUZZ_HAVE_GDAL
#include <gdal.h>
#include <ogr_api.h>

/* The features as they grow. */
typedef struct {
    rf_terrain_release r;
    size_t cap_f, cap_v;
    int have_kind;
} release_buf;

static void release_buf_free(release_buf *b)
{
    free(b->r.start), free(b->r.x), free(b->r.y), free(b->r.weight), free(b->r.file);
    memset(b, 0, sizeof *b);
}

/* Start a feature (no vertices yet) of weight w. */
static rf_status add_feature(release_buf *b, double w, rf_error *err)
{
    if (b->r.n_features + 2 > b->cap_f) {
        size_t cap = b->cap_f ? 2 * b->cap_f : 64;
        size_t *s = realloc(b->r.start, cap * sizeof *s);
        if (s)
            b->r.start = s;
        double *wt = realloc(b->r.weight, cap * sizeof *wt);
        if (wt)
            b->r.weight = wt;
        if (!s || !wt)
            return rf_fail(err, RF_ENOMEM, "out of memory for the release features");
        if (!b->cap_f)
            b->r.start[0] = 0;
        b->cap_f = cap;
    }
    b->r.weight[b->r.n_features++] = w;
    b->r.start[b->r.n_features] = b->r.start[b->r.n_features - 1];
    return RF_OK;
}

/* Append a vertex to the last feature. */
static rf_status add_vertex(release_buf *b, double x, double y, rf_error *err)
{
    size_t n = b->r.start[b->r.n_features];
    if (n + 1 > b->cap_v) {
        size_t cap = b->cap_v ? 2 * b->cap_v : 256;
        double *nx = realloc(b->r.x, cap * sizeof *nx);
        if (nx)
            b->r.x = nx;
        double *ny = realloc(b->r.y, cap * sizeof *ny);
        if (ny)
            b->r.y = ny;
        if (!nx || !ny)
            return rf_fail(err, RF_ENOMEM, "out of memory for the release features");
        b->cap_v = cap;
    }
    b->r.x[n] = x, b->r.y[n] = y;
    b->r.start[b->r.n_features] = n + 1;
    return RF_OK;
}

/* Hand the features over with the file's name. */
static rf_status release_finish(release_buf *b, const char *path, rf_terrain_release *out, rf_error *err)
{
    if (!(b->r.file = strdup(path)))
        return rf_fail(err, RF_ENOMEM, "out of memory");
    *out = b->r;
    memset(b, 0, sizeof *b);
    return RF_OK;
}

/* ---- vector ---- */

typedef struct {
    const char *path;
    long long fid;              /* the feature being read (messages) */
    release_buf b;
} vec_ctx;

/* Length of a line string, or the area of a ring (shoelace), of g [m or m^2]. */
static double part_measure(OGRGeometryH g, rf_terrain_feature_kind kind)
{
    int n = OGR_G_GetPointCount(g);
    double s = 0;
    for (int k = 0; k + 1 < n; k++) {
        double x0 = OGR_G_GetX(g, k), y0 = OGR_G_GetY(g, k), x1 = OGR_G_GetX(g, k + 1), y1 = OGR_G_GetY(g, k + 1);
        s += kind == RF_TERRAIN_LINES ? hypot(x1 - x0, y1 - y0) : x0 * y1 - x1 * y0;
    }
    if (kind == RF_TERRAIN_POLYGONS && n > 0) /* closing edge if the ring is not closed */
        s += OGR_G_GetX(g, n - 1) * OGR_G_GetY(g, 0) - OGR_G_GetX(g, 0) * OGR_G_GetY(g, n - 1);
    return kind == RF_TERRAIN_LINES ? s : fabs(s) / 2;
}

/* The kind of a simple geometry type, -1 if none we take. */
static int kind_of(OGRwkbGeometryType flat, int *multi)
{
    *multi = flat == wkbMultiPoint || flat == wkbMultiLineString || flat == wkbMultiPolygon;
    if (flat == wkbPoint || flat == wkbMultiPoint)
        return RF_TERRAIN_POINTS;
    if (flat == wkbLineString || flat == wkbMultiLineString)
        return RF_TERRAIN_LINES;
    if (flat == wkbPolygon || flat == wkbMultiPolygon)
        return RF_TERRAIN_POLYGONS;
    return -1;
}

/* One simple part (point, line string, polygon) as a feature of weight w. */
static rf_status add_part(vec_ctx *c, OGRGeometryH g, rf_terrain_feature_kind kind, double w, rf_error *err)
{
    OGRGeometryH line = g;
    if (kind == RF_TERRAIN_POLYGONS) {
        if (OGR_G_GetGeometryCount(g) > 1)
            return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld is a polygon with a hole; release "
                           "areas are simple polygons (cut it into parts without holes)", c->path, c->fid);
        line = OGR_G_GetGeometryRef(g, 0);
    }
    int n = line ? OGR_G_GetPointCount(line) : 0;
    if (kind == RF_TERRAIN_POLYGONS && n > 1 && OGR_G_GetX(line, 0) == OGR_G_GetX(line, n - 1) &&
        OGR_G_GetY(line, 0) == OGR_G_GetY(line, n - 1))
        n--; /* the repeated first vertex */
    int need = kind == RF_TERRAIN_POINTS ? 1 : kind == RF_TERRAIN_LINES ? 2 : 3;
    if (n < need)
        return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld has a part of %d vertices (a %s needs "
                       "%d)", c->path, c->fid, n, kind == RF_TERRAIN_LINES ? "line" : "polygon", need);
    rf_status st = add_feature(&c->b, w, err);
    for (int k = 0; k < n && st == RF_OK; k++) {
        double x = OGR_G_GetX(line, k), y = OGR_G_GetY(line, k);
        if (!(fabs(x) <= RF_TRAJ_MAX_COORD && fabs(y) <= RF_TRAJ_MAX_COORD))
            return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld has the vertex (%g, %g), beyond "
                           "+-%g m", c->path, c->fid, x, y, RF_TRAJ_MAX_COORD);
        st = add_vertex(&c->b, x, y, err);
    }
    return st;
}

/* The measure of part k of g (1 for points). */
static double measure_of(OGRGeometryH g, int multi, int k, rf_terrain_feature_kind kind)
{
    OGRGeometryH p = multi ? OGR_G_GetGeometryRef(g, k) : g;
    if (kind == RF_TERRAIN_POINTS)
        return 1;
    if (kind == RF_TERRAIN_POLYGONS)
        return OGR_G_GetGeometryCount(p) > 0 ? part_measure(OGR_G_GetGeometryRef(p, 0), kind) : 0;
    return part_measure(p, kind);
}

/* The weight of feature f before it is split: its count, or count per m^2 times its area. */
static rf_status feature_weight(vec_ctx *c, OGRFeatureH f, int field, int per_area, double total, double *w,
                                rf_error *err)
{
    *w = 1;
    if (field < 0)
        return RF_OK;
    if (!OGR_F_IsFieldSetAndNotNull(f, field))
        return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld has no value in its count field",
                       c->path, c->fid);
    *w = OGR_F_GetFieldAsDouble(f, field);
    if (!(*w >= 0 && isfinite(*w)))
        return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld has the count %g; a count is a finite "
                       "number >= 0", c->path, c->fid, *w);
    if (per_area)
        *w *= total;
    return RF_OK;
}

/* One feature: its kind checked against the layer's, split into parts. */
static rf_status add_geometry(vec_ctx *c, OGRFeatureH f, int field, int per_area, rf_error *err)
{
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    if (!g || OGR_G_IsEmpty(g))
        return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld has no geometry", c->path, c->fid);
    int multi, kind = kind_of(wkbFlatten(OGR_G_GetGeometryType(g)), &multi);
    if (kind < 0)
        return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld is a %s; releases are points, lines or "
                       "polygons", c->path, c->fid, OGR_G_GetGeometryName(g));
    if (c->b.have_kind && (int)c->b.r.kind != kind)
        return rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld is a %s but the features before it are "
                       "not; a release layer holds one kind (points, lines or polygons)", c->path, c->fid,
                       OGR_G_GetGeometryName(g));
    if (per_area && kind != RF_TERRAIN_POLYGONS)
        return rf_fail(err, RF_EINVAL, "the release file '%s': a count per area needs polygons, feature %lld is a "
                       "%s", c->path, c->fid, OGR_G_GetGeometryName(g));
    c->b.r.kind = (rf_terrain_feature_kind)kind, c->b.have_kind = 1;
    int parts = multi ? OGR_G_GetGeometryCount(g) : 1;
    double total = 0, w;
    for (int k = 0; k < parts; k++)
        total += measure_of(g, multi, k, (rf_terrain_feature_kind)kind);
    rf_status st = feature_weight(c, f, field, per_area, total, &w, err);
    if (st == RF_OK && !(total > 0))
        st = rf_fail(err, RF_EINVAL, "the release file '%s': feature %lld has no length or area", c->path, c->fid);
    for (int k = 0; k < parts && st == RF_OK; k++) {
        double share = measure_of(g, multi, k, (rf_terrain_feature_kind)kind) / total;
        st = add_part(c, multi ? OGR_G_GetGeometryRef(g, k) : g, (rf_terrain_feature_kind)kind, w * share, err);
    }
    return st;
}

static rf_status read_layer(vec_ctx *c, OGRLayerH lay, const char *count_field, int per_area, rf_error *err)
{
    rf_status st = traj_gdal_check_metres(OGR_L_GetSpatialRef(lay), "release file", c->path, err);
    int field = -1;
    if (st == RF_OK && count_field && (field = OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(lay), count_field)) < 0)
        st = rf_fail(err, RF_EINVAL, "the release file '%s': layer '%s' has no field '%s'", c->path,
                     OGR_L_GetName(lay), count_field);
    OGR_L_ResetReading(lay);
    OGRFeatureH f;
    while (st == RF_OK && (f = OGR_L_GetNextFeature(lay))) {
        c->fid = (long long)OGR_F_GetFID(f);
        st = add_geometry(c, f, field, per_area, err);
        OGR_F_Destroy(f);
    }
    if (st == RF_OK && !c->b.r.n_features)
        st = rf_fail(err, RF_EINVAL, "the release file '%s': layer '%s' holds no feature", c->path, OGR_L_GetName(lay));
    double sum = 0;
    for (size_t k = 0; st == RF_OK && k < c->b.r.n_features; k++)
        sum += c->b.r.weight[k];
    if (st == RF_OK && !(sum > 0))
        st = rf_fail(err, RF_EINVAL, "the release file '%s': no feature of layer '%s' has a positive count in '%s'",
                     c->path, OGR_L_GetName(lay), count_field ? count_field : "");
    return st;
}

rf_status terrain_read_release_vector(const char *path, const char *layer, const char *count_field, int per_area,
                                      rf_terrain_release *out, rf_error *err)
{
    memset(out, 0, sizeof *out);
    vec_ctx c;
    memset(&c, 0, sizeof c);
    c.path = path, c.fid = -1;
    traj_gdal_capture cap;
    traj_gdal_begin(&cap);
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR | GDAL_OF_READONLY, NULL, NULL, NULL);
    OGRLayerH lay = NULL;
    rf_status st = RF_OK;
    if (!ds)
        st = rf_fail(err, RF_EIO, "cannot read the release file '%s' as a vector file with GDAL/OGR", path);
    else if (!(lay = layer ? GDALDatasetGetLayerByName(ds, layer) : GDALDatasetGetLayer(ds, 0)))
        st = rf_fail(err, RF_EINVAL, "the release file '%s' has no layer%s%s", path, layer ? " named " : "",
                     layer ? layer : "");
    if (st == RF_OK)
        st = read_layer(&c, lay, count_field, per_area, err);
    if (st == RF_OK)
        st = release_finish(&c.b, path, out, err);
    if (st != RF_OK)
        traj_gdal_explain(err, &cap);
    release_buf_free(&c.b);
    if (ds)
        GDALClose(ds);
    traj_gdal_end(&cap);
    return st;
}

/* ---- raster ---- */

/* The cell (c, row) of weight w as a square polygon. */
static rf_status add_cell(release_buf *b, const double gt[6], int c, int row, double w, rf_error *err)
{
    double xw = gt[0] + c * gt[1], xe = xw + gt[1], yn = gt[3] + row * gt[5], ys = yn + gt[5];
    rf_status st = add_feature(b, w, err);
    if (st == RF_OK)
        st = add_vertex(b, xw, ys, err);
    if (st == RF_OK)
        st = add_vertex(b, xe, ys, err);
    if (st == RF_OK)
        st = add_vertex(b, xe, yn, err);
    if (st == RF_OK)
        st = add_vertex(b, xw, yn, err);
    return st;
}

static rf_status read_cells(const traj_gdal_raster *r, const char *path, release_buf *b, rf_error *err)
{
    double *row = malloc((size_t)r->w * sizeof *row);
    rf_status st = row ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory");
    b->r.kind = RF_TERRAIN_POLYGONS;
    for (int j = 0; j < r->h && st == RF_OK; j++) {
        if (GDALRasterIO(r->band, GF_Read, 0, j, r->w, 1, row, r->w, 1, GDT_Float64, 0, 0) != CE_None)
            st = rf_fail(err, RF_EIO, "cannot read row %d of the release raster '%s'", j, path);
        for (int i = 0; i < r->w && st == RF_OK; i++)
            if (!traj_gdal_is_nodata(r, row[i]) && row[i] > 0) {
                if (!isfinite(row[i]))
                    st = rf_fail(err, RF_EINVAL, "the release raster '%s': cell (column %d, row %d) holds %g", path,
                                 i, j, row[i]);
                else
                    st = add_cell(b, r->gt, i, j, row[i], err);
            }
    }
    free(row);
    if (st == RF_OK && !b->r.n_features)
        st = rf_fail(err, RF_EINVAL, "the release raster '%s' has no cell with a positive count", path);
    return st;
}

rf_status terrain_read_release_raster(const char *path, int band, rf_terrain_release *out, rf_error *err)
{
    memset(out, 0, sizeof *out);
    release_buf b;
    memset(&b, 0, sizeof b);
    traj_gdal_capture cap;
    traj_gdal_raster r;
    traj_gdal_begin(&cap);
    rf_status st = traj_gdal_raster_open(path, band, "release raster", &r, err);
    if (st == RF_OK)
        st = read_cells(&r, path, &b, err);
    if (st == RF_OK)
        st = release_finish(&b, path, out, err);
    if (st != RF_OK)
        traj_gdal_explain(err, &cap);
    release_buf_free(&b);
    traj_gdal_raster_close(&r);
    traj_gdal_end(&cap);
    return st;
}

#else

rf_status terrain_read_release_vector(const char *path, const char *layer, const char *count_field, int per_area,
                                      rf_terrain_release *out, rf_error *err)
{
    (void)layer, (void)count_field, (void)per_area;
    memset(out, 0, sizeof *out);
    return rf_fail(err, RF_EINVAL, "%s: cannot read the release file: this rockfuzz was built without GDAL (install "
                   "libgdal-dev and rebuild)", path);
}

rf_status terrain_read_release_raster(const char *path, int band, rf_terrain_release *out, rf_error *err)
{
    (void)band;
    memset(out, 0, sizeof *out);
    return rf_fail(err, RF_EINVAL, "%s: cannot read the release raster: this rockfuzz was built without GDAL "
                   "(install libgdal-dev and rebuild)", path);
}

#endif
