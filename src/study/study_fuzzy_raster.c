/* study_fuzzy_raster.c - the fuzzy hazard rasters of a trajectory study on a
 * terrain file (docs/fuzzy-hazard.md): before the TM the per-point raster
 * store OUT/rasters becomes the trajectory model's raster sink; after it,
 * every point's raster is there (a missing one is rebuilt by evaluating the
 * point again), the chosen bands are retransformed per cell with the blame
 * map, and written as OUT/fuzzy_rasters.tif. */
#include "study/study_internal.h"
#include "study/bind.h"
#include "study/fuzzy_raster.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

struct rf_fuzzy_rasters {
    fr_store *store;
    const rf_model *inner; /* the trajectory model behind the binding */
};

/* The trajectory model's own inputs (the rasters' keys) at the study's x. */
static void to_targets(void *ctx, const double *x, double *xi)
{
    sb_unwrap(ctx, x, xi);
}

rf_status rf_study_fuzzy_rasters_begin(const char *out_dir, rf_study *s, rf_fuzzy_rasters **out, rf_error *err)
{
    *out = NULL;
    if (s->model_kind != RF_STUDY_MODEL_TRAJECTORY || s->n_fuzzy_rasters == 0)
        return RF_OK;
    if (s->n_fuzzy_rasters > FR_MAX_BANDS)
        return rf_fail(err, RF_EINVAL, "at most %d fuzzy rasters", FR_MAX_BANDS);
    rf_fuzzy_rasters *f = calloc(1, sizeof *f);
    if (!f)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    double x[64] = {0}, xi[SB_MAX_TARGETS];
    f->inner = sb_unwrap(&s->model, x, xi);
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%s/rasters", out_dir);
    rf_status st = fr_store_open(dir, &f->store, err);
    if (!st)
        st = traj_model_raster_sink_set(f->inner, fr_store_put, f->store, err);
    if (st) {
        fr_store_close(f->store);
        free(f);
        return st;
    }
    *out = f;
    return RF_OK;
}

void rf_study_fuzzy_rasters_end(rf_fuzzy_rasters *f)
{
    if (!f)
        return;
    traj_model_raster_sink_set(f->inner, NULL, NULL, NULL);
    fr_store_close(f->store);
    free(f);
}

rf_status rf_study_fuzzy_rasters_write(const char *out_dir, const rf_study *s, rf_fuzzy_rasters *f,
                                       const rf_tm_result *res, rf_error *err)
{
    if (!f)
        return RF_OK;
    const char *const *names = (const char *const *)s->fuzzy_rasters;
    fr_store_reader rd;
    size_t rebuilt = 0, n_out = 0;
    /* point 0's raster names the grid: rebuild first if it is the missing one */
    fr_store_reader_init(&rd, f->store, res, f->inner->n_inputs, to_targets, (void *)&s->model, names,
                         s->n_fuzzy_rasters, err);
    rf_status st = fr_store_rebuild(&rd, &s->model, &rebuilt, err);
    if (!st)
        st = fr_store_reader_init(&rd, f->store, res, f->inner->n_inputs, to_targets, (void *)&s->model, names,
                                  s->n_fuzzy_rasters, err);
    terrain_band *bands = NULL;
    if (!st) {
        fr_source src = {rd.grid.nx, rd.grid.ny, s->n_fuzzy_rasters, names, rd.units, fr_store_read_point, &rd, 0};
        st = fr_retransform(res, &src, &bands, &n_out, err);
    }
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/fuzzy_rasters.tif", out_dir);
    if (!st)
        st = terrain_geotiff_write(path, rd.grid.crs_wkt, rd.grid.nx, rd.grid.ny, rd.grid.x0, rd.grid.y0,
                                   rd.grid.cell, bands, n_out, err);
    terrain_bands_free(bands, n_out);
    return st ? rf_error_prefix(err, "fuzzy hazard rasters") : RF_OK;
}
