/* terrain_io.c - the terrain's rasters read with GDAL (terrain.h): the DEM
 * as a surface, and the per-cell material classes and roughness.
 *
 * DEM: any raster GDAL reads, north-up; its cell centres are the surface's
 * nodes (node (i, j) at gt[0] + (i + 0.5) gt[1], gt[3] + (h - j - 0.5) gt[5]:
 * the raster's rows flipped so that j grows to the north; dx != dy allowed).
 * No-data cells (and NaN) become NaN nodes; a value beyond
 * RF_TRAJ_MAX_COORD that is not the declared no-data is refused (a Float32
 * DEM holding 3.4e38 without saying it is no-data).  Only the nodes a
 * terrain.window needs are read (all without one), row by row; the memory
 * they take is estimated before anything is allocated and refused beyond
 * RF_TERRAIN_MAX_DEM_BYTES (terrain.h) with the figure.
 *
 * Classes and roughness: a raster in the DEM's CRS (or none), on any north-up
 * grid, sampled at each surface cell's centre (the midpoint of its four
 * nodes) by the pixel holding it; a centre on a pixel edge takes the pixel to
 * the east / north (as terrain_cell_of).  Where that pixel is no-data or the
 * centre lies outside the raster, the surface cell becomes invalid (outside,
 * as a DEM no-data cell).  Nothing of the surface changes unless the whole
 * raster is good. */
#include "trajectory/terrain_internal.h"
#include "trajectory/traj_gdal.h"
#include "core/util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef ROCKFUZZ_HAVE_GDAL
#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#define TERRAIN_MAX_SIDE ((size_t)1 << 20)        /* terrain_alloc's limits */
#define TERRAIN_MAX_NODES ((size_t)1 << 31)
#define TERRAIN_MAX_WINDOW_BYTES (4.0 * 1024 * 1024 * 1024)  /* a class or roughness raster's window */
#define TERRAIN_TIE 1e-6                          /* [pixel] a centre this close to a pixel edge is on it */

/* ---- the DEM ---- */

/* The part of the raster read: columns c0 .. c0 + w - 1, rows r0 .. r0 + h - 1. */
typedef struct {
    int c0, r0, w, h;
    const double *window;       /* the terrain.window asked, or NULL: the whole raster */
} dem_window;

/* The cell centres within [lo, hi] along one axis (pixel coordinate f = (map
 * - origin) / size, centres at k + 0.5) and the next beyond each side, clamped
 * to [0, n - 1]; 0 when none of them is in the raster. */
static int axis_range(double lo, double hi, int n, int *k0, int *k1)
{
    double a = floor(lo - 0.5), b = ceil(hi - 0.5);
    if (!(b >= 0 && a <= n - 1))
        return 0;
    *k0 = (int)fmax(a, 0), *k1 = (int)fmin(b, n - 1);
    return 1;
}

/* The nodes the window needs (the whole raster without one). */
static rf_status dem_window_of(const traj_gdal_raster *r, const char *path, const double *win, dem_window *w,
                               rf_error *err)
{
    w->window = win;
    if (!win) {
        *w = (dem_window){0, 0, r->w, r->h, NULL};
        return RF_OK;
    }
    int c0 = 0, c1 = 0, r0 = 0, r1 = 0;
    int in = axis_range((win[0] - r->gt[0]) / r->gt[1], (win[2] - r->gt[0]) / r->gt[1], r->w, &c0, &c1) &&
             axis_range((win[3] - r->gt[3]) / r->gt[5], (win[1] - r->gt[3]) / r->gt[5], r->h, &r0, &r1);
    if (!in)
        return rf_fail(err, RF_EINVAL, "the DEM '%s': terrain.window [%.10g, %.10g, %.10g, %.10g] lies outside its "
                       "extent [%.10g, %.10g, %.10g, %.10g]", path, win[0], win[1], win[2], win[3], r->gt[0],
                       r->gt[3] + r->h * r->gt[5], r->gt[0] + r->w * r->gt[1], r->gt[3]);
    *w = (dem_window){c0, r0, c1 - c0 + 1, r1 - r0 + 1, win};
    return RF_OK;
}

/* The surface's memory (a double per node, a byte per cell), estimated before allocating. */
static rf_status check_dem_size(const traj_gdal_raster *r, const char *path, const dem_window *win, rf_error *err)
{
    size_t w = (size_t)win->w, h = (size_t)win->h;
    char where[200] = "the whole DEM (no terrain.window)";
    if (win->window)
        snprintf(where, sizeof where, "terrain.window [%.10g, %.10g, %.10g, %.10g]", win->window[0], win->window[1],
                 win->window[2], win->window[3]);
    if (w < 2 || h < 2)
        return rf_fail(err, RF_EINVAL, "the DEM '%s' (%d x %d cells): %s covers %zu x %zu cells; a surface needs at "
                       "least 2 x 2", path, r->w, r->h, where, w, h);
    double bytes = (double)w * (double)h * sizeof(double) + (double)(w - 1) * (double)(h - 1);
    if (w > TERRAIN_MAX_SIDE || h > TERRAIN_MAX_SIDE || (double)w * (double)h > (double)TERRAIN_MAX_NODES ||
        bytes > RF_TERRAIN_MAX_DEM_BYTES)
        return rf_fail(err, RF_EINVAL, "the DEM '%s' (%d x %d cells): %s covers %zu x %zu cells, which would take "
                       "%.2f GB of memory; at most %zu cells per side, %zu in all and %.2f GB are read: give a "
                       "smaller terrain.window [xmin, ymin, xmax, ymax], cut the DEM (gdal_translate -projwin) or "
                       "coarsen it (gdalwarp -tr)", path, r->w, r->h, where, w, h, bytes / 1e9, TERRAIN_MAX_SIDE,
                       TERRAIN_MAX_NODES, RF_TERRAIN_MAX_DEM_BYTES / 1e9);
    return RF_OK;
}

/* Raster row `row` (columns of the window) into surface row j = r0 + h - 1 - row, no-data as NaN; refuses a huge
 * undeclared value. */
static rf_status dem_row(const traj_gdal_raster *r, const char *path, const dem_window *w, int row, rf_terrain *t,
                         rf_error *err)
{
    double *z = t->z + (size_t)(w->r0 + w->h - 1 - row) * t->nx;
    if (GDALRasterIO(r->band, GF_Read, w->c0, row, w->w, 1, z, w->w, 1, GDT_Float64, 0, 0) != CE_None)
        return rf_fail(err, RF_EIO, "cannot read row %d of the DEM '%s'", row, path);
    for (int k = 0; k < w->w; k++) {
        int c = w->c0 + k;
        if (traj_gdal_is_nodata(r, z[k])) {
            z[k] = NAN;
        } else if (!(fabs(z[k]) <= RF_TRAJ_MAX_COORD)) {
            char nd[64] = "none is declared";
            if (r->has_nodata)
                snprintf(nd, sizeof nd, "it is %.9g", r->nodata);
            return rf_fail(err, RF_EINVAL, "the DEM '%s': cell (column %d, row %d) at map point (%.10g, %.10g) holds "
                           "%g, beyond +-%g m and not the no-data value (%s); declare the no-data value "
                           "(gdal_edit.py -a_nodata VALUE) or correct the cell", path, c, row,
                           r->gt[0] + (c + 0.5) * r->gt[1], r->gt[3] + (row + 0.5) * r->gt[5], z[k], RF_TRAJ_MAX_COORD,
                           nd);
        }
    }
    return RF_OK;
}

static rf_status dem_crs(const traj_gdal_raster *r, rf_terrain *t, rf_error *err)
{
    OGRSpatialReferenceH srs = GDALGetSpatialRef(r->ds);
    char *wkt = NULL;
    if (!srs)
        return RF_OK;
    if (OSRExportToWkt(srs, &wkt) != OGRERR_NONE || !wkt) {
        CPLFree(wkt);
        return rf_fail(err, RF_EINVAL, "cannot write the DEM's CRS as WKT");
    }
    char *copy = strdup(wkt);
    CPLFree(wkt);
    if (!copy)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    free(t->crs_wkt);
    t->crs_wkt = copy;
    return RF_OK;
}

/* The window's rows one at a time (GDAL reads the blocks holding them). */
static rf_status dem_build(const traj_gdal_raster *r, const char *path, const double *window, rf_terrain **out,
                           rf_error *err)
{
    dem_window w = {0};
    rf_status st = dem_window_of(r, path, window, &w, err);
    if (st == RF_OK)
        st = check_dem_size(r, path, &w, err);
    rf_terrain *t = NULL;
    if (st == RF_OK && (st = terrain_alloc((size_t)w.w, (size_t)w.h, &t, err)) != RF_OK)
        rf_error_prefix(err, "the DEM '%s'", path);
    for (int row = w.r0; st == RF_OK && row < w.r0 + w.h; row++)
        st = dem_row(r, path, &w, row, t, err);
    if (st == RF_OK)
        st = dem_crs(r, t, err);
    if (st != RF_OK) {
        rf_terrain_free(t);
        return st;
    }
    t->dx = r->gt[1], t->dy = -r->gt[5];
    t->x0 = r->gt[0] + (w.c0 + 0.5) * r->gt[1];
    t->y0 = r->gt[3] + (w.r0 + w.h - 0.5) * r->gt[5];
    terrain_finish(t);
    *out = t;
    return RF_OK;
}

rf_status rf_terrain_read_window(const char *path, int band, const double *window, rf_terrain **t, rf_error *err)
{
    *t = NULL;
    traj_gdal_capture cap;
    traj_gdal_raster r;
    traj_gdal_begin(&cap);
    rf_status st = traj_gdal_raster_open(path, band, "DEM", &r, err);
    if (st == RF_OK)
        st = dem_build(&r, path, window, t, err);
    if (st != RF_OK)
        traj_gdal_explain(err, &cap);
    traj_gdal_raster_close(&r);
    traj_gdal_end(&cap);
    return st;
}

rf_status rf_terrain_read(const char *path, int band, rf_terrain **t, rf_error *err)
{
    return rf_terrain_read_window(path, band, NULL, t, err);
}

/* ---- rasters sampled at the surface's cell centres ---- */

/* Fills one surface cell from the raster value v at its centre (x, y). */
typedef rf_status (*cell_fill)(void *ctx, size_t cell, double v, double x, double y, rf_error *err);

typedef struct {
    traj_gdal_raster r;
    const char *what, *path;
    int c0, r0, wc, wr;         /* the window read: columns c0 .. c0 + wc - 1, rows r0 .. r0 + wr - 1 */
    double *v;                  /* wr rows of wc values */
} cell_sampler;

/* The pixel index along one axis of pixel coordinate f (corner-based); on an
 * edge (within TERRAIN_TIE) the higher index when `up`, else the lower one; -1
 * outside [0, n]. */
static long pixel_index(double f, int n, int up)
{
    double k = round(f);
    if (fabs(f - k) < TERRAIN_TIE) {
        long i = up ? (long)k : (long)k - 1;
        if (k == 0 || k == n)       /* the raster's own border: the pixel inside */
            i = k == 0 ? 0 : n - 1;
        return k < 0 || k > n ? -1 : i;
    }
    return f < 0 || f >= n ? -1 : (long)floor(f);
}

/* Column and row of the pixel holding map point (x, y): on an edge the one to the east / north. */
static int pixel_of(const traj_gdal_raster *r, double x, double y, long *c, long *row)
{
    *c = pixel_index((x - r->gt[0]) / r->gt[1], r->w, 1);
    *row = pixel_index((y - r->gt[3]) / r->gt[5], r->h, 0);
    return *c >= 0 && *row >= 0;
}

/* The raster's CRS must be the DEM's when both have one. */
static rf_status check_same_crs(const cell_sampler *s, const rf_terrain *t, rf_error *err)
{
    OGRSpatialReferenceH srs = GDALGetSpatialRef(s->r.ds);
    if (!srs || !t->crs_wkt[0])
        return RF_OK;
    OGRSpatialReferenceH dem = OSRNewSpatialReference(t->crs_wkt);
    const char *opts[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", "CRITERION=EQUIVALENT", NULL};
    int same = dem && OSRIsSameEx(srs, dem, opts);
    rf_status st = RF_OK;
    if (!same)
        st = rf_fail(err, RF_EINVAL, "the %s raster '%s' is in the CRS \"%s\", the DEM in \"%s\"; reproject it to the "
                     "DEM's CRS (gdalwarp -t_srs)", s->what, s->path, OSRGetName(srs) ? OSRGetName(srs) : "unnamed",
                     dem && OSRGetName(dem) ? OSRGetName(dem) : "unnamed");
    if (dem)
        OSRDestroySpatialReference(dem);
    return st;
}

/* Read the window of pixels holding the surface's cell centres. */
static rf_status read_window(cell_sampler *s, const rf_terrain *t, rf_error *err)
{
    double xa = t->x0 + 0.5 * t->dx, xb = t->x0 + ((double)t->nx - 1.5) * t->dx;
    double ya = t->y0 + 0.5 * t->dy, yb = t->y0 + ((double)t->ny - 1.5) * t->dy;
    long ca, cb, ra, rb;
    /* clamped: pixel_of gives -1 outside; the window is the overlap */
    double fa = fmax(0, fmin(s->r.w - 1, floor((xa - s->r.gt[0]) / s->r.gt[1]) - 1));
    double fb = fmax(0, fmin(s->r.w - 1, floor((xb - s->r.gt[0]) / s->r.gt[1]) + 1));
    double ga = fmax(0, fmin(s->r.h - 1, floor((yb - s->r.gt[3]) / s->r.gt[5]) - 1));
    double gb = fmax(0, fmin(s->r.h - 1, floor((ya - s->r.gt[3]) / s->r.gt[5]) + 1));
    ca = (long)fa, cb = (long)fb, ra = (long)ga, rb = (long)gb;
    s->c0 = (int)ca, s->r0 = (int)ra, s->wc = (int)(cb - ca + 1), s->wr = (int)(rb - ra + 1);
    double bytes = (double)s->wc * (double)s->wr * sizeof *s->v;
    if (bytes > TERRAIN_MAX_WINDOW_BYTES)
        return rf_fail(err, RF_EINVAL, "the %s raster '%s': the DEM's extent covers %d x %d of its pixels (%.1f GB as "
                       "doubles), more than %.1f GB; coarsen it to about the DEM's cell (gdalwarp -tr)", s->what,
                       s->path, s->wc, s->wr, bytes / 1e9, TERRAIN_MAX_WINDOW_BYTES / 1e9);
    if (!(s->v = malloc((size_t)bytes)))
        return rf_fail(err, RF_ENOMEM, "out of memory for the %s raster's window (%d x %d)", s->what, s->wc, s->wr);
    if (GDALRasterIO(s->r.band, GF_Read, s->c0, s->r0, s->wc, s->wr, s->v, s->wc, s->wr, GDT_Float64, 0, 0) != CE_None)
        return rf_fail(err, RF_EIO, "cannot read the %s raster '%s'", s->what, s->path);
    return RF_OK;
}

/* Visit every valid surface cell: fill() with the value at its centre, or
 * clear its bit in valid (a copy of t->valid) on no-data or outside. */
static rf_status visit_cells(const cell_sampler *s, const rf_terrain *t, unsigned char *valid, cell_fill fill, void *ctx,
                             rf_error *err)
{
    size_t ncx = t->nx - 1;
    for (size_t j = 0; j + 1 < t->ny; j++)
        for (size_t i = 0; i < ncx; i++) {
            size_t cell = j * ncx + i;
            if (!valid[cell])
                continue;
            double x = t->x0 + ((double)i + 0.5) * t->dx, y = t->y0 + ((double)j + 0.5) * t->dy;
            long c, r;
            int in = pixel_of(&s->r, x, y, &c, &r) && c >= s->c0 && c < s->c0 + s->wc && r >= s->r0 &&
                     r < s->r0 + s->wr;
            double v = in ? s->v[(size_t)(r - s->r0) * (size_t)s->wc + (size_t)(c - s->c0)] : NAN;
            if (!in || traj_gdal_is_nodata(&s->r, v))
                valid[cell] = 0;
            else if (fill(ctx, cell, v, x, y, err) != RF_OK)
                return err->code;
        }
    return RF_OK;
}

/* Open, check and read the raster, then visit the cells into valid (a copy of t->valid). */
static rf_status sample_cells(const rf_terrain *t, const char *path, int band, const char *what, unsigned char *valid,
                              cell_fill fill, void *ctx, rf_error *err)
{
    cell_sampler s;
    memset(&s, 0, sizeof s);
    s.what = what, s.path = path;
    char kind[64];
    snprintf(kind, sizeof kind, "%s raster", what);
    traj_gdal_capture cap;
    traj_gdal_begin(&cap);
    rf_status st = traj_gdal_raster_open(path, band, kind, &s.r, err);
    if (st == RF_OK)
        st = check_same_crs(&s, t, err);
    if (st == RF_OK)
        st = read_window(&s, t, err);
    if (st == RF_OK)
        st = visit_cells(&s, t, valid, fill, ctx, err);
    if (st == RF_OK && !memchr(valid, 1, (t->nx - 1) * (t->ny - 1)))
        st = rf_fail(err, RF_EINVAL, "the %s raster '%s' holds data at no cell of the DEM (outside it, or no-data "
                     "there)", what, path);
    if (st != RF_OK)
        traj_gdal_explain(err, &cap);
    free(s.v);
    traj_gdal_raster_close(&s.r);
    traj_gdal_end(&cap);
    return st;
}

/* ---- classes ---- */

typedef struct {
    const char *path;
    size_t n;
    const long *value;
    const size_t *material;
    uint16_t *out;
} class_ctx;

static rf_status fill_class(void *ctx, size_t cell, double v, double x, double y, rf_error *err)
{
    class_ctx *c = ctx;
    for (size_t k = 0; k < c->n && v == floor(v); k++)
        if ((double)c->value[k] == v) {
            c->out[cell] = (uint16_t)c->material[k];
            return RF_OK;
        }
    char list[256] = "";
    for (size_t k = 0, len = 0; k < c->n && len + 24 < sizeof list; k++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%ld", k ? ", " : "", c->value[k]);
    return rf_fail(err, RF_EINVAL, "the classes raster '%s' holds %.10g at map point (%.10g, %.10g), which is not "
                   "one of the classes listed (%s)", c->path, v, x, y, list);
}

rf_status rf_terrain_read_classes(rf_terrain *t, const char *path, int band, size_t n_classes, const long *class_value,
                                  const size_t *class_material, rf_error *err)
{
    for (size_t k = 0; k < n_classes; k++)
        if (class_material[k] > UINT16_MAX)
            return rf_fail(err, RF_EINVAL, "class %ld: material index %zu beyond %d", class_value[k],
                           class_material[k], UINT16_MAX);
    size_t cells = (t->nx - 1) * (t->ny - 1);
    class_ctx c = {path, n_classes, class_value, class_material, calloc(cells, sizeof(uint16_t))};
    unsigned char *valid = malloc(cells);
    rf_status st = c.out && valid ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory for the classes");
    if (st == RF_OK) {
        memcpy(valid, t->valid, cells);
        st = sample_cells(t, path, band, "classes", valid, fill_class, &c, err);
    }
    if (st == RF_OK) {
        memcpy(t->valid, valid, cells);
        free(t->material);
        t->material = c.out, c.out = NULL;
    }
    free(c.out), free(valid);
    return st;
}

/* ---- roughness ---- */

typedef struct {
    const char *path;
    float *out;
} rough_ctx;

static rf_status fill_roughness(void *ctx, size_t cell, double v, double x, double y, rf_error *err)
{
    rough_ctx *c = ctx;
    if (!(v >= 0 && v <= 45))
        return rf_fail(err, RF_EINVAL, "the roughness raster '%s' holds %.10g deg at map point (%.10g, %.10g); a "
                       "roughness SD lies in [0, 45] deg", c->path, v, x, y);
    c->out[cell] = (float)(v * RF_PI / 180);
    return RF_OK;
}

rf_status rf_terrain_read_roughness(rf_terrain *t, const char *path, int band, rf_error *err)
{
    size_t cells = (t->nx - 1) * (t->ny - 1);
    rough_ctx c = {path, calloc(cells, sizeof(float))};
    unsigned char *valid = malloc(cells);
    rf_status st = c.out && valid ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory for the roughness");
    if (st == RF_OK) {
        memcpy(valid, t->valid, cells);
        st = sample_cells(t, path, band, "roughness", valid, fill_roughness, &c, err);
    }
    if (st == RF_OK) {
        memcpy(t->valid, valid, cells);
        free(t->roughness);
        t->roughness = c.out, c.out = NULL;
    }
    free(c.out), free(valid);
    return st;
}

#else

static rf_status no_gdal(const char *path, const char *what, rf_error *err)
{
    return rf_fail(err, RF_EINVAL, "%s: cannot read the %s: this rockfuzz was built without GDAL (install "
                   "libgdal-dev and rebuild)", path, what);
}

rf_status rf_terrain_read(const char *path, int band, rf_terrain **t, rf_error *err)
{
    (void)band;
    *t = NULL;
    return no_gdal(path, "DEM", err);
}

rf_status rf_terrain_read_window(const char *path, int band, const double *window, rf_terrain **t, rf_error *err)
{
    (void)window;
    return rf_terrain_read(path, band, t, err);
}

rf_status rf_terrain_read_classes(rf_terrain *t, const char *path, int band, size_t n_classes, const long *class_value,
                                  const size_t *class_material, rf_error *err)
{
    (void)t, (void)band, (void)n_classes, (void)class_value, (void)class_material;
    return no_gdal(path, "classes raster", err);
}

rf_status rf_terrain_read_roughness(rf_terrain *t, const char *path, int band, rf_error *err)
{
    (void)t, (void)band;
    return no_gdal(path, "roughness raster", err);
}

#endif
