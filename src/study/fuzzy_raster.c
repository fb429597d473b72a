/* fuzzy_raster.c - fuzzy hazard rasters: the per-cell retransformation of
 * per-point rasters by blocks of rows, and the blame map (fuzzy_raster.h,
 * docs/fuzzy-hazard.md).
 *
 * Every raster cell is one extra output of the finished TM run: its values
 * at the run's distinct points are retransformed and analysed by the TM's
 * own code (rf_analysis_compute_values), a block of rows at a time, so the
 * working memory is (rows x nx) x fr_bytes_per_cell plus a fixed part,
 * whatever the raster's size; only the output bands are whole rasters. */
#include "study/fuzzy_raster.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/analysis.h"

#define BAND_NAME_MAX 35 /* + "_a0.00_lower" fits terrain_band.name */

/* Per cell of a block (see rf_analysis_compute_values, tm/values.c and
 * tm/analysis.c for what they allocate per output column):
 *   values at every point (double)     8 np      this file
 *   one point's block as read (float)  4
 *   lower and upper cuts               16 (m+1)
 *   bound-producing inputs (view)      16 (m+1) n
 *   nominal, NaN count, undefined      17
 *   grid differences (analysis)        8 n (3m+2)
 *   gains                              8 n m
 *   8 measures per input               64 n
 *   3 reason codes per input           12 n
 *   degree of uncertainty etc.         20 */
size_t fr_bytes_per_cell(size_t np, size_t n, size_t m)
{
    return 8 * np + 4 + 16 * (m + 1) + 16 * (m + 1) * n + 17 + 8 * n * (3 * m + 2) + 8 * n * m + 64 * n + 12 * n +
           20;
}

/* Scratch of the retransformation and the analysis (a grid's outputs, at
 * most np values, 1 + 4 lanes; 3 (m+1) level sums), the view of the run's
 * data and the allocator's headers of the ~40 blocks. */
size_t fr_bytes_fixed(const rf_tm_result *res)
{
    size_t np = rf_tm_point_count(res), m = res->levels;
    return (5 * np + 3 * (m + 1)) * sizeof(double) + 4096;
}

size_t fr_block_rows(const rf_tm_result *res, size_t nx, size_t ny, size_t budget, size_t *bytes)
{
    size_t per_row = (nx ? nx : 1) * fr_bytes_per_cell(rf_tm_point_count(res), res->n_inputs, res->levels);
    size_t fixed = fr_bytes_fixed(res), rows = budget > fixed ? (budget - fixed) / per_row : 0;
    rows = rows < 1 ? 1 : rows > ny ? (ny ? ny : 1) : rows;
    if (bytes)
        *bytes = fixed + rows * per_row;
    return rows;
}

/* The output bands of chosen band b: 2 (m+1) bounds, blame, blame_rho. */
static rf_status name_bands(const fr_source *src, size_t m, terrain_band *out, rf_error *err)
{
    size_t per = 2 * (m + 1) + 2;
    for (size_t b = 0; b < src->n_bands; b++) {
        const char *name = src->names[b], *unit = src->units && src->units[b] ? src->units[b] : "";
        if (strlen(name) > BAND_NAME_MAX)
            return rf_fail(err, RF_EINVAL, "band name '%s' longer than %d characters", name, BAND_NAME_MAX);
        terrain_band *o = out + b * per;
        for (size_t j = 0; j <= m; j++) {
            double a = (double)j / (double)m;
            snprintf(o[2 * j].name, sizeof o[2 * j].name, "%s_a%.2f_lower", name, a);
            snprintf(o[2 * j + 1].name, sizeof o[2 * j + 1].name, "%s_a%.2f_upper", name, a);
            o[2 * j].unit = o[2 * j + 1].unit = unit;
        }
        snprintf(o[per - 2].name, sizeof o[per - 2].name, "%s_blame", name);
        snprintf(o[per - 1].name, sizeof o[per - 1].name, "%s_blame_rho", name);
        o[per - 2].unit = o[per - 1].unit = "";
    }
    return RF_OK;
}

static rf_status alloc_bands(const fr_source *src, size_t m, terrain_band **out, size_t *n_out, rf_error *err)
{
    size_t nb = src->n_bands * (2 * (m + 1) + 2), cells = src->nx * src->ny;
    *out = calloc(nb ? nb : 1, sizeof **out);
    *n_out = nb;
    if (!*out)
        return rf_fail(err, RF_ENOMEM, "out of memory for the fuzzy rasters");
    for (size_t k = 0; k < nb; k++)
        if (!((*out)[k].data = malloc((cells ? cells : 1) * sizeof(float))))
            return rf_fail(err, RF_ENOMEM, "out of memory for the fuzzy rasters (%zu bands of %zu x %zu cells)", nb,
                           src->nx, src->ny);
    return name_bands(src, m, *out, err);
}

/* The input with the largest rho (first of equals; NaN skipped): 1-based, 0 none. */
static size_t blame_of(const double *rho, size_t n, double *best)
{
    size_t who = 0;
    *best = NAN;
    for (size_t i = 0; i < n; i++)
        if (!isnan(rho[i]) && (who == 0 || rho[i] > *best)) {
            who = i + 1;
            *best = rho[i];
        }
    return who;
}

typedef struct {
    double *y, *lo, *hi; /* [cells * np], [cells * (m+1)] x 2 */
    float *buf;          /* [cells] */
} block_mem;

/* One block of rows of chosen band b: read every point, retransform, analyse. */
static rf_status do_block(const rf_tm_result *res, const fr_source *src, size_t b, size_t row0, size_t nr,
                          block_mem *w, terrain_band *o, rf_error *err)
{
    size_t np = rf_tm_point_count(res), n = res->n_inputs, m = res->levels, cells = nr * src->nx;
    for (size_t id = 0; id < np; id++) {
        rf_status st = src->read(src->ctx, id, b, row0, nr, w->buf, err);
        if (st)
            return st;
        for (size_t c = 0; c < cells; c++)
            w->y[c * np + id] = w->buf[c];
    }
    rf_analysis an;
    rf_status st = rf_analysis_compute_values(res, cells, w->y, w->lo, w->hi, &an, err);
    if (st)
        return st;
    size_t at0 = row0 * src->nx, per = 2 * (m + 1) + 2;
    for (size_t c = 0; c < cells; c++) {
        for (size_t j = 0; j <= m; j++) {
            o[2 * j].data[at0 + c] = (float)w->lo[c * (m + 1) + j];
            o[2 * j + 1].data[at0 + c] = (float)w->hi[c * (m + 1) + j];
        }
        double best;
        o[per - 2].data[at0 + c] = (float)blame_of(an.rho + c * n, n, &best);
        o[per - 1].data[at0 + c] = (float)best;
    }
    rf_analysis_free(&an);
    return RF_OK;
}

rf_status fr_retransform(const rf_tm_result *res, const fr_source *src, terrain_band **out, size_t *n_out,
                         rf_error *err)
{
    *out = NULL;
    *n_out = 0;
    size_t np = rf_tm_point_count(res), m = res->levels;
    if (np == 0 || !src->read || src->nx == 0 || src->ny == 0)
        return rf_fail(err, RF_EINVAL, "fuzzy rasters: no TM points or an empty raster");
    size_t rows = fr_block_rows(res, src->nx, src->ny, src->budget ? src->budget : FR_DEFAULT_BUDGET, NULL);
    size_t cells = rows * src->nx;
    block_mem w = {malloc(cells * np * sizeof(double)), malloc(cells * (m + 1) * sizeof(double)),
                   malloc(cells * (m + 1) * sizeof(double)), malloc(cells * sizeof(float))};
    rf_status st = alloc_bands(src, m, out, n_out, err);
    if (!st && (!w.y || !w.lo || !w.hi || !w.buf))
        st = rf_fail(err, RF_ENOMEM, "out of memory for a block of %zu rows of the fuzzy rasters", rows);
    for (size_t b = 0; !st && b < src->n_bands; b++)
        for (size_t row0 = 0; !st && row0 < src->ny; row0 += rows) {
            size_t nr = src->ny - row0 < rows ? src->ny - row0 : rows;
            st = do_block(res, src, b, row0, nr, &w, *out + b * (2 * (m + 1) + 2), err);
        }
    free(w.y);
    free(w.lo);
    free(w.hi);
    free(w.buf);
    if (st) {
        terrain_bands_free(*out, *n_out);
        *out = NULL;
        *n_out = 0;
    }
    return st;
}
