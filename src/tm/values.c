/* values.c - extra outputs of a finished TM run (tm_spec s.3-4, s.5;
 * docs/fuzzy-hazard.md): values a caller derives at every distinct point
 * (e.g. each cell of a hazard raster) retransformed, and analysed, by the
 * very code that treats the model's outputs.
 *
 * The finished run keeps its grids (point ids per grid position) and every
 * distinct point's value indices.  A result for the extra outputs is a view:
 * a shallow copy of the run's data whose output columns are the caller's
 * (n_out = columns, one column of rf_tm_point_count values each), with its
 * own cuts.  tm_retransform and rf_analysis_compute then run unchanged on
 * it, so a scalar output fed back gives its cuts and measures to the bit. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/tm.h"
#include "tm/tm_internal.h"

size_t rf_tm_point_count(const rf_tm_result *res) { return res && res->data ? res->data->npoints : 0; }

rf_status rf_tm_point_inputs(const rf_tm_result *res, size_t id, double *x, rf_error *err)
{
    const struct rf_tm_data *d = res ? res->data : NULL;
    if (!d)
        return rf_fail(err, RF_EINVAL, "the TM result holds no evaluation data");
    if (id >= d->npoints)
        return rf_fail(err, RF_EINVAL, "point id %zu: the run has %zu distinct points", id, d->npoints);
    for (size_t i = 0; i < d->n; i++)
        x[i] = d->values[i][rf_tm_tuple(d, id, i)];
    return RF_OK;
}

int rf_tm_point_failed(const rf_tm_result *res, size_t id)
{
    const struct rf_tm_data *d = res ? res->data : NULL;
    if (!d || id >= d->npoints)
        return 0;
    for (size_t k = 0; k < d->n_out; k++)
        if (!isnan(rf_tm_y(d, id, k)))
            return 0;
    return 1;
}

void tm_values_result_free(rf_tm_result *out)
{
    if (!out)
        return;
    free(out->x_lo); /* one block: x_lo, x_hi, nominal (and lo, hi when owned) */
    free(out->output_undefined);
    free(out->nan_points);
    free(out->data); /* the view only: grids and values belong to the run */
    memset(out, 0, sizeof *out);
}

/* Per column: NaN values counted; all NaN = undefined (cuts NaN). */
static void scan_columns(rf_tm_result *out, size_t np, const double *y)
{
    for (size_t c = 0; c < out->n_outputs; c++) {
        size_t nan = 0;
        for (size_t p = 0; p < np; p++)
            nan += isnan(y[c * np + p]) != 0;
        out->nan_points[c] = nan;
        out->output_undefined[c] = nan == np;
    }
}

/* The view's arrays; lo and hi are the caller's when given (else owned). */
static rf_status view_alloc(const rf_tm_result *res, size_t nc, double *lo, double *hi, rf_tm_result *out,
                            rf_error *err)
{
    size_t n = res->n_inputs, m1 = res->levels + 1, own = (lo && hi) ? 0 : 2 * nc * m1;
    out->x_lo = malloc((2 * nc * m1 * n + nc + own) * sizeof(double));
    out->output_undefined = calloc(nc ? nc : 1, 1);
    out->nan_points = calloc(nc ? nc : 1, sizeof *out->nan_points);
    out->data = malloc(sizeof *out->data);
    if (!out->x_lo || !out->output_undefined || !out->nan_points || !out->data)
        return rf_fail(err, RF_ENOMEM, "out of memory for the retransformation of %zu extra outputs", nc);
    out->x_hi = out->x_lo + nc * m1 * n;
    out->nominal = out->x_hi + nc * m1 * n;
    out->lo = own ? out->nominal + nc : lo;
    out->hi = own ? out->lo + nc * m1 : hi;
    return RF_OK;
}

rf_status tm_values_result(const rf_tm_result *res, size_t n_cols, const double *y, double *lo, double *hi,
                           rf_tm_result *out, rf_error *err)
{
    memset(out, 0, sizeof *out);
    const struct rf_tm_data *d = res ? res->data : NULL;
    if (!d || !d->main || !d->main[0].ids)
        return rf_fail(err, RF_EINVAL, "the TM result holds no evaluation data");
    if (n_cols == 0 || !y)
        return rf_fail(err, RF_EINVAL, "no extra outputs to retransform");
    out->n_inputs = res->n_inputs;
    out->n_outputs = n_cols;
    out->levels = res->levels;
    out->scheme = res->scheme;
    out->in_lo = res->in_lo; /* borrowed */
    out->in_hi = res->in_hi;
    out->in_nominal = res->in_nominal;
    out->requested = res->requested;
    out->distinct = res->distinct;
    rf_status st = view_alloc(res, n_cols, lo, hi, out, err);
    if (st) {
        tm_values_result_free(out);
        return st;
    }
    *out->data = *d;
    out->data->n_out = n_cols;
    out->data->y = (double *)y; /* read only: nothing writes through the view */
    out->data->cap_points = d->npoints;
    scan_columns(out, d->npoints, y);
    for (size_t c = 0; c < n_cols; c++)
        out->nominal[c] = y[c * d->npoints + d->nominal_id];
    if (tm_retransform(out->data, out)) {
        tm_values_result_free(out);
        return rf_fail(err, RF_ENOMEM, "out of memory for the retransformation");
    }
    return RF_OK;
}

rf_status rf_tm_retransform_values(const rf_tm_result *res, size_t n_cols, const double *y, double *lo, double *hi,
                                   rf_error *err)
{
    rf_tm_result v;
    rf_status st = tm_values_result(res, n_cols, y, lo, hi, &v, err);
    tm_values_result_free(&v);
    return st;
}
