/* fuzzy_raster.h - fuzzy hazard rasters of a study whose model writes a
 * raster per evaluation (issue 28 item 6; docs/fuzzy-hazard.md).
 *
 * raster_store.c: the per-point raster store, DIR/<key>.f32 per TM point
 * (key: 16 hex digits of a hash of the point's input bits, the input vector
 * itself in the file's header and checked on read), written to a temporary
 * name and renamed inside the evaluation, i.e. before the result store
 * commits the point.  Its put function is a raster sink (traj_internal.h).
 *
 * fuzzy_raster.c: the per-cell retransformation by blocks of rows: for each
 * chosen band and level j the lower and upper bound of every cell, and the
 * blame (the input with the largest relative measure of influence rho) and
 * that rho, as float bands named
 *   NAME_aA.AA_lower, NAME_aA.AA_upper   (A.AA = j/m, "%.2f"), j = 0..m,
 *   NAME_blame       (1-based input index, 0 = no input has influence),
 *   NAME_blame_rho   (that input's rho, NaN where the blame is 0),
 * in this order for each chosen band. */
#ifndef ROCKFUZZ_FUZZY_RASTER_H
#define ROCKFUZZ_FUZZY_RASTER_H

#include <stdint.h>

#include "rockfuzz/tm.h"
#include "trajectory/terrain_internal.h"

/* ---- raster_store.c */
typedef struct fr_store fr_store;

/* DIR is created if missing (its parent must exist). */
rf_status fr_store_open(const char *dir, fr_store **out, rf_error *err);
void fr_store_close(fr_store *s);
/* 16 hex digits (and NUL) naming the raster of input vector x[0..n-1]:
 * FNV-1a 64 of the doubles' bit patterns, the same at any thread or rank. */
void fr_store_key(const double *x, size_t n, char key[17]);
/* The raster sink: write the bands of the evaluation at x (atomically:
 * temporary file, then rename over DIR/<key>.f32).  Thread-safe. */
rf_status fr_store_put(void *store, const double *x, size_t n, const terrain_band *bands, size_t n_bands,
                       const traj_raster_grid *grid, rf_error *err);
/* 1 if the raster of x is there and whole (header matches x, size right). */
int fr_store_has(fr_store *s, const double *x, size_t n);
/* The grid of a stored raster (the CRS copied). */
typedef struct {
    size_t nx, ny;
    double x0, y0, cell;
    char crs_wkt[4096];
} fr_grid;
/* The grid of the raster of x, and band `name`'s index and unit in it (RF_EINVAL if
 * it has no such band: the message names the bands it has). */
rf_status fr_store_band(fr_store *s, const double *x, size_t n, const char *name, size_t *band, char unit[16],
                        fr_grid *g, rf_error *err);
/* Rows row0 .. row0+nrows-1 of band `band` of the raster of x (which must
 * have nx columns) into out[nrows * nx]. */
rf_status fr_store_read(fr_store *s, const double *x, size_t n, size_t band, size_t nx, size_t row0, size_t nrows,
                        float *out, rf_error *err);

/* The store as the retransformation's source.  TM point inputs x map to the
 * emitting model's inputs xi (the raster's key) through map (e.g. a study's
 * binding: sb_unwrap; NULL: xi = x, n_key = n_inputs). */
#define FR_MAX_BANDS 16
typedef void (*fr_map_fn)(void *ctx, const double *x, double *xi);
typedef struct {
    fr_store *store;
    const rf_tm_result *res;
    size_t n_key;
    fr_map_fn map;
    void *map_ctx;
    size_t band[FR_MAX_BANDS]; /* store band of each chosen band */
    size_t nx;
    fr_grid grid;              /* of point 0's raster (every read checks nx) */
    char unit_text[FR_MAX_BANDS][16];
    const char *units[FR_MAX_BANDS]; /* of each chosen band, for fr_source.units */
} fr_store_reader;
/* Find the chosen bands (names) in the raster of point 0, and its grid. */
rf_status fr_store_reader_init(fr_store_reader *r, fr_store *s, const rf_tm_result *res, size_t n_key, fr_map_fn map,
                               void *map_ctx, const char *const *names, size_t n_names, rf_error *err);
void fr_point_key(const fr_store_reader *r, const double *x, double *xi);
/* An fr_read_fn over an fr_store_reader; a point that failed (the run's
 * tolerate_failures) and has no raster reads as NaN, left out of the bounds. */
rf_status fr_store_read_point(void *reader, size_t id, size_t b, size_t row0, size_t nrows, float *out, rf_error *err);
/* Every TM point (but a failed one) whose raster is missing or damaged (e.g. the result store
 * kept the point but its raster was deleted) is evaluated again by model,
 * which must have the store as its sink (the same x, the same raster:
 * common random numbers); *rebuilt counts them. */
rf_status fr_store_rebuild(const fr_store_reader *r, const rf_model *model, size_t *rebuilt, rf_error *err);

/* ---- fuzzy_raster.c */

/* Reads rows row0 .. row0+nrows-1 (nx each) of chosen band b at TM point id
 * into out[nrows * nx]. */
typedef rf_status (*fr_read_fn)(void *ctx, size_t point_id, size_t b, size_t row0, size_t nrows, float *out,
                                rf_error *err);

typedef struct {
    size_t nx, ny;                /* raster shape (row = nx cells) */
    size_t n_bands;               /* chosen bands */
    const char *const *names;     /* [n_bands] their names (the output bands' prefix) */
    const char *const *units;     /* [n_bands] their units (NULL: "") */
    fr_read_fn read;
    void *ctx;
    size_t budget;                /* working memory to stay within [bytes]; 0 = FR_DEFAULT_BUDGET */
} fr_source;

#define FR_DEFAULT_BUDGET ((size_t)64 << 20)

/* Working memory of the retransformation per raster cell of a block [bytes]
 * for np points, n inputs and m levels (docs/fuzzy-hazard.md). */
size_t fr_bytes_per_cell(size_t np, size_t n, size_t m);
/* Working memory independent of the cells (grids' scratch) [bytes]. */
size_t fr_bytes_fixed(const rf_tm_result *res);
/* Rows per block for a budget, at least 1, at most ny; *bytes: the working
 * memory that block size takes (fixed + rows * nx * per cell). */
size_t fr_block_rows(const rf_tm_result *res, size_t nx, size_t ny, size_t budget, size_t *bytes);

/* The fuzzy rasters of every chosen band (order and names above) into
 * *out[*n_out] (free with terrain_bands_free), units: the band's for the
 * bounds, "" for blame and rho. */
rf_status fr_retransform(const rf_tm_result *res, const fr_source *src, terrain_band **out, size_t *n_out,
                         rf_error *err);

#endif
