/* dem.c - a slope profile cut from a digital elevation model along a
 * polyline in map coordinates, read with GDAL (GeoTIFF, ESRI ASCII grid and
 * every other raster GDAL reads).  The profile's x is the distance along the
 * polyline from its first vertex [m], its y the elevation [m], sampled every
 * `step` metres and at every vertex of the polyline, by bilinear
 * interpolation between cell centres (exact for a planar DEM; cells are
 * clamped at the raster's edge).  A cell holding the raster's no-data value
 * anywhere on the line is an error.  Map units must be metres (a geographic or
 * foot-based CRS is refused); only the window of cells the line needs is read
 * (refused beyond DEM_MAX_WINDOW_BYTES, with the figure), and a step that
 * would give more than DEM_MAX_POINTS vertices is refused before reading.
 * GDAL's own messages are kept off the console and added to ours.  (GDAL reads
 * an ASCII grid with decimals as Float32, ~1e-7 relative, unless the
 * environment sets AAIGRID_DATATYPE=Float64.)
 *   profile: {dem: {file: F, line: [[X, Y], ...], step: 1, band: 1}, material: rock} */
#include "trajectory/traj_yaml_internal.h"
#include "core/textfile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef ROCKFUZZ_HAVE_GDAL
#include "trajectory/traj_gdal.h"

#include <gdal.h>

#define DEM_MAX_POINTS 1000000     /* profile vertices, as an inline profile */
#define DEM_MAX_WINDOW_BYTES (1024.0 * 1024 * 1024)

typedef struct {
    double inv[6];        /* map -> pixel of the whole raster */
    int nx, ny;           /* the whole raster */
    int c0, r0, wx, wy;   /* the window read: columns c0..c0+wx-1, rows r0..r0+wy-1 */
    double *z;            /* wy rows of wx values */
    int has_nodata;
    double nodata;
} dem_grid;

/* Fractional pixel (column, row) of map point (X, Y), relative to cell centres. */
static void to_pixel(const double inv[6], double X, double Y, double *c, double *r)
{
    *c = inv[0] + inv[1] * X + inv[2] * Y - 0.5;
    *r = inv[3] + inv[4] * X + inv[5] * Y - 0.5;
}

/* The cells bilinear interpolation along the line needs (its vertices' bounding box, clamped). */
static void line_window(dem_grid *g, const double *X, const double *Y, size_t nv)
{
    double cmin = INFINITY, cmax = -INFINITY, rmin = INFINITY, rmax = -INFINITY, c, r;
    for (size_t k = 0; k < nv; k++) {
        to_pixel(g->inv, X[k], Y[k], &c, &r);
        cmin = fmin(cmin, c), cmax = fmax(cmax, c), rmin = fmin(rmin, r), rmax = fmax(rmax, r);
    }
    double lo[2] = {floor(cmin) - 1, floor(rmin) - 1}, hi[2] = {floor(cmax) + 2, floor(rmax) + 2};
    int n[2] = {g->nx, g->ny}, w0[2], w1[2];
    for (int d = 0; d < 2; d++) {
        w0[d] = (int)fmin(fmax(lo[d], 0), n[d] - 1);
        w1[d] = (int)fmin(fmax(hi[d], 0), n[d] - 1);
    }
    g->c0 = w0[0], g->r0 = w0[1], g->wx = w1[0] - w0[0] + 1, g->wy = w1[1] - w0[1] + 1;
}

/* The window of band band_no the line (X, Y) needs, as Float64. */
static rf_status read_window(GDALDatasetH ds, const char *path, int band_no, const double *X, const double *Y,
                             size_t nv, dem_grid *g, rf_error *err)
{
    double gt[6];
    GDALRasterBandH band = band_no <= GDALGetRasterCount(ds) ? GDALGetRasterBand(ds, band_no) : NULL;
    if (!band)
        return rf_fail(err, RF_EINVAL, "the DEM '%s' has no band %d", path, band_no);
    if (GDALGetGeoTransform(ds, gt) != CE_None || !GDALInvGeoTransform(gt, g->inv))
        return rf_fail(err, RF_EINVAL, "the DEM '%s' has no usable georeferencing", path);
    rf_status st = traj_gdal_check_metres(GDALGetSpatialRef(ds), "DEM", path, err);
    if (st != RF_OK)
        return st;
    g->nx = GDALGetRasterXSize(ds), g->ny = GDALGetRasterYSize(ds);
    line_window(g, X, Y, nv);
    double bytes = (double)g->wx * (double)g->wy * sizeof *g->z;
    if (bytes > DEM_MAX_WINDOW_BYTES)
        return rf_fail(err, RF_EINVAL, "the DEM '%s': the line's bounding box covers %d x %d cells (%.0f MB as "
                       "doubles), more than %.0f MB; cut the line into shorter profiles", path, g->wx, g->wy,
                       bytes / 1048576, DEM_MAX_WINDOW_BYTES / 1048576);
    if (!(g->z = malloc((size_t)bytes)))
        return rf_fail(err, RF_ENOMEM, "out of memory for the DEM window (%d x %d cells)", g->wx, g->wy);
    if (GDALRasterIO(band, GF_Read, g->c0, g->r0, g->wx, g->wy, g->z, g->wx, g->wy, GDT_Float64, 0, 0) != CE_None)
        return rf_fail(err, RF_EIO, "cannot read the elevations of '%s'", path);
    g->nodata = GDALGetRasterNoDataValue(band, &g->has_nodata);
    return RF_OK;
}

static rf_status read_grid(const char *path, int band_no, const double *X, const double *Y, size_t nv,
                           dem_grid *g, rf_error *err)
{
    rf_status st = rf_require_regular_file(path, "DEM", err);
    if (st != RF_OK)
        return st;
    traj_gdal_capture cap;
    traj_gdal_begin(&cap);
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    if (!ds)
        st = rf_fail(err, RF_EIO, "cannot read the DEM '%s' with GDAL", path);
    else
        st = read_window(ds, path, band_no, X, Y, nv, g, err);
    if (st != RF_OK)
        traj_gdal_explain(err, &cap);
    if (ds)
        GDALClose(ds);
    traj_gdal_end(&cap);
    return st;
}

/* Bilinear elevation at map point (X, Y); NAN on no-data or outside. */
static double elevation(const dem_grid *g, double X, double Y)
{
    double c, r;
    to_pixel(g->inv, X, Y, &c, &r);
    if (c < -0.5 || r < -0.5 || c > g->nx - 0.5 || r > g->ny - 0.5)
        return NAN;
    c = fmin(fmax(c, 0), g->nx - 1), r = fmin(fmax(r, 0), g->ny - 1);
    int i = (int)floor(c), j = (int)floor(r);
    if (i >= g->nx - 1) i = g->nx > 1 ? g->nx - 2 : 0;
    if (j >= g->ny - 1) j = g->ny > 1 ? g->ny - 2 : 0;
    int i1 = g->nx > 1 ? i + 1 : i, j1 = g->ny > 1 ? j + 1 : j;
    if (i < g->c0 || i1 >= g->c0 + g->wx || j < g->r0 || j1 >= g->r0 + g->wy)
        return NAN; /* not reached: the window holds every cell the line needs */
    double u = c - i, v = r - j;
    size_t a = (size_t)(i - g->c0), b = (size_t)(i1 - g->c0), p = (size_t)(j - g->r0), q = (size_t)(j1 - g->r0);
    double z[4] = {g->z[p * g->wx + a], g->z[p * g->wx + b], g->z[q * g->wx + a], g->z[q * g->wx + b]};
    for (int k = 0; k < 4; k++)
        if (g->has_nodata && z[k] == g->nodata)
            return NAN;
    return (1 - v) * ((1 - u) * z[0] + u * z[1]) + v * ((1 - u) * z[2] + u * z[3]);
}

/* Sample the polyline (X[k], Y[k]) every step into the spec's profile. */
static rf_status cut(ty_ctx *c, struct fy_node *n, const dem_grid *g, const double *X, const double *Y,
                     size_t nv, double step)
{
    size_t cap = 1;
    for (size_t k = 0; k + 1 < nv; k++)
        cap += (size_t)ceil(hypot(X[k + 1] - X[k], Y[k + 1] - Y[k]) / step) + 1;
    rf_traj_spec *s = c->spec;
    if (cap > DEM_MAX_POINTS) /* checked before: not reached */
        return yr_fail(&c->sp, n, "profile.dem.step", "too many points");
    s->px = calloc(cap, sizeof *s->px), s->py = calloc(cap, sizeof *s->py);
    s->seg_material = calloc(cap, sizeof *s->seg_material);
    if (!s->px || !s->py || !s->seg_material)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    double dist = 0;
    for (size_t k = 0; k + 1 < nv; k++) {
        double len = hypot(X[k + 1] - X[k], Y[k + 1] - Y[k]);
        size_t m = (size_t)ceil(len / step);
        for (size_t q = (k ? 1 : 0); q <= m; q++) {
            double f = m ? (double)q / (double)m : 0, x = X[k] + f * (X[k + 1] - X[k]), y = Y[k] + f * (Y[k + 1] - Y[k]);
            double z = elevation(g, x, y);
            if (!isfinite(z))
                return yr_fail(&c->sp, n, "profile.dem.line", "the point (%.10g, %.10g) lies outside the DEM or on "
                                                              "a no-data cell", x, y);
            s->px[s->n_points] = dist + f * len, s->py[s->n_points++] = z;
        }
        dist += len;
    }
    return RF_OK;
}

static rf_status read_spec(ty_ctx *c, struct fy_node *n, char **file, double **X, double **Y, size_t *nv,
                           double *step, long long *band)
{
    const char *path = "profile.dem", *key;
    struct fy_node *step_node = NULL;
    rf_status st = yr_mapping(&c->sp, n, path);
    yr_iter it = {n, NULL, 0, {0}};
    struct fy_node *k, *v;
    char p[300];
    while (st == RF_OK) {
        if ((st = yr_next(&c->sp, &it, path, &key, &k, &v)) != RF_OK || !key)
            break;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (!strcmp(key, "file")) {
            st = yr_string_dup(&c->sp, v, p, file);
        } else if (!strcmp(key, "step")) {
            step_node = v;
            if ((st = yr_number(&c->sp, v, p, step)) == RF_OK && !(*step > 0))
                st = yr_fail(&c->sp, v, p, "must be > 0 [m]");
        } else if (!strcmp(key, "band")) {
            st = yr_integer(&c->sp, v, p, 1, 1000000, band);
        } else if (!strcmp(key, "line")) {
            if ((st = yr_sequence(&c->sp, v, p, 2, 100000, nv)) != RF_OK)
                break;
            *X = calloc(*nv, sizeof **X), *Y = calloc(*nv, sizeof **Y);
            if (!*X || !*Y)
                return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
            for (size_t i = 0; i < *nv && st == RF_OK; i++) {
                double xy[2];
                char q[320];
                yr_pathf(q, sizeof q, "%s[%zu]", p, i);
                st = yr_numbers(&c->sp, fy_node_sequence_get_by_index(v, (int)i), q, 2, 2, xy, NULL);
                (*X)[i] = xy[0], (*Y)[i] = xy[1];
            }
        } else {
            st = yr_fail(&c->sp, k, p, "unknown key; dem takes file, line, step, band");
        }
    }
    if (st == RF_OK && (!*file || !*X))
        st = yr_fail(&c->sp, n, path, "file and line ([[X, Y], ...] in map metres) are required");
    double points = 1;
    for (size_t k = 0; st == RF_OK && k + 1 < *nv; k++)
        points += ceil(hypot((*X)[k + 1] - (*X)[k], (*Y)[k + 1] - (*Y)[k]) / *step) + 1;
    if (st == RF_OK && !(points <= DEM_MAX_POINTS))
        st = yr_fail(&c->sp, step_node ? step_node : n, "profile.dem.step", "the line would be sampled at %.3g "
                     "points, more than %d; choose a larger step [m]", points, DEM_MAX_POINTS);
    return st;
}

rf_status ty_dem_profile(ty_ctx *c, struct fy_node *n)
{
    char *file = NULL, full[4096];
    double *X = NULL, *Y = NULL, step = 1;
    size_t nv = 0;
    long long band = 1;
    dem_grid g;
    memset(&g, 0, sizeof g);
    rf_status st = read_spec(c, n, &file, &X, &Y, &nv, &step, &band);
    if (st == RF_OK) {
        if (file[0] == '/' || !strcmp(c->sp.dir, "."))
            snprintf(full, sizeof full, "%s", file);
        else
            snprintf(full, sizeof full, "%s/%s", c->sp.dir, file);
        if ((st = read_grid(full, (int)band, X, Y, nv, &g, c->sp.err)) != RF_OK)
            st = yr_prefix(&c->sp, n, "profile.dem.file");
    }
    if (st == RF_OK)
        st = cut(c, n, &g, X, Y, nv, step);
    if (st == RF_OK)
        ty_remember(c, "profile.points", n);
    free(g.z), free(file), free(X), free(Y);
    return st;
}

#else

rf_status ty_dem_profile(ty_ctx *c, struct fy_node *n)
{
    return yr_fail(&c->sp, n, "profile.dem", "this rockfuzz was built without GDAL (install libgdal-dev and "
                                             "rebuild), so DEM profiles are not available");
}

#endif
