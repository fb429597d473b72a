/* dem.c - a slope profile cut from a digital elevation model along a
 * polyline in map coordinates, read with GDAL (GeoTIFF, ESRI ASCII grid and
 * every other raster GDAL reads).  The profile's x is the distance along the
 * polyline from its first vertex [m], its y the elevation [m], sampled every
 * `step` metres and at every vertex of the polyline, by bilinear
 * interpolation between cell centres (exact for a planar DEM; cells are
 * clamped at the raster's edge).  A cell holding the raster's no-data value
 * anywhere on the line is an error.  Map units must be metres.  (GDAL reads
 * an ASCII grid with decimals as Float32, ~1e-7 relative, unless the
 * environment sets AAIGRID_DATATYPE=Float64.)
 *   profile: {dem: {file: F, line: [[X, Y], ...], step: 1, band: 1}, material: rock} */
#include "trajectory/traj_yaml_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef ROCKFUZZ_HAVE_GDAL
#include <gdal.h>

typedef struct {
    double inv[6];        /* map -> pixel */
    int nx, ny;
    double *z;            /* ny rows of nx values */
    int has_nodata;
    double nodata;
} dem_grid;

static rf_status read_grid(const char *path, int band_no, dem_grid *g, rf_error *err)
{
    GDALAllRegister();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    CPLPopErrorHandler();
    if (!ds)
        return rf_fail(err, RF_EIO, "cannot read the DEM '%s' with GDAL", path);
    double gt[6];
    rf_status st = RF_OK;
    GDALRasterBandH band = band_no <= GDALGetRasterCount(ds) ? GDALGetRasterBand(ds, band_no) : NULL;
    if (!band)
        st = rf_fail(err, RF_EINVAL, "the DEM '%s' has no band %d", path, band_no);
    else if (GDALGetGeoTransform(ds, gt) != CE_None || !GDALInvGeoTransform(gt, g->inv))
        st = rf_fail(err, RF_EINVAL, "the DEM '%s' has no usable georeferencing", path);
    if (st == RF_OK) {
        g->nx = GDALGetRasterXSize(ds), g->ny = GDALGetRasterYSize(ds);
        g->z = malloc((size_t)g->nx * (size_t)g->ny * sizeof *g->z);
        if (!g->z)
            st = rf_fail(err, RF_ENOMEM, "out of memory for the DEM (%d x %d)", g->nx, g->ny);
        else if (GDALRasterIO(band, GF_Read, 0, 0, g->nx, g->ny, g->z, g->nx, g->ny, GDT_Float64, 0, 0) != CE_None)
            st = rf_fail(err, RF_EIO, "cannot read the elevations of '%s'", path);
        g->nodata = GDALGetRasterNoDataValue(band, &g->has_nodata);
    }
    GDALClose(ds);
    return st;
}

/* Bilinear elevation at map point (X, Y); NAN on no-data or outside. */
static double elevation(const dem_grid *g, double X, double Y)
{
    double c = g->inv[0] + g->inv[1] * X + g->inv[2] * Y - 0.5; /* relative to cell centres */
    double r = g->inv[3] + g->inv[4] * X + g->inv[5] * Y - 0.5;
    if (c < -0.5 || r < -0.5 || c > g->nx - 0.5 || r > g->ny - 0.5)
        return NAN;
    c = fmin(fmax(c, 0), g->nx - 1), r = fmin(fmax(r, 0), g->ny - 1);
    int i = (int)floor(c), j = (int)floor(r);
    if (i >= g->nx - 1) i = g->nx > 1 ? g->nx - 2 : 0;
    if (j >= g->ny - 1) j = g->ny > 1 ? g->ny - 2 : 0;
    int i1 = g->nx > 1 ? i + 1 : i, j1 = g->ny > 1 ? j + 1 : j;
    double u = c - i, v = r - j, z[4] = {g->z[(size_t)j * g->nx + i], g->z[(size_t)j * g->nx + i1],
                                         g->z[(size_t)j1 * g->nx + i], g->z[(size_t)j1 * g->nx + i1]};
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
        if ((st = read_grid(full, (int)band, &g, c->sp.err)) != RF_OK)
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
