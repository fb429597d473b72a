/* study_fuzzy_raster.c - the fuzzy hazard rasters of a trajectory study on a
 * terrain file (docs/fuzzy-hazard.md): before the TM the per-point raster
 * store OUT/rasters becomes the trajectory model's raster sink; after it,
 * every point's raster is there (a missing one is rebuilt by evaluating the
 * point again), the chosen bands are retransformed per cell with the blame
 * map, and written as OUT/fuzzy_rasters.tif; with plots, the maps of the
 * first chosen statistic for the report (fuzzy_map_nominal.png,
 * fuzzy_map_upper.png: the alpha = 1 cut and the alpha = 0 upper bound on
 * one colour scale; fuzzy_map_blame.png: the input to blame per cell), drawn
 * by the terrain run's map code (terrain_draw_band_map) over the DEM. */
#include "study/study_internal.h"
#include "study/bind.h"
#include "study/fuzzy_raster.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

static const char *const MAP_STEMS[3] = {"fuzzy_map_nominal", "fuzzy_map_upper", "fuzzy_map_blame"};

/* The band called PREFIX + suffix, or NULL. */
static const terrain_band *band_named(const terrain_band *b, size_t n, const char *prefix, const char *suffix)
{
    char name[sizeof b->name];
    snprintf(name, sizeof name, "%s%s", prefix, suffix);
    for (size_t k = 0; k < n; k++)
        if (!strcmp(b[k].name, name))
            return &b[k];
    return NULL;
}

/* The three maps of the first chosen statistic, on the DEM of the trajectory
 * model's terrain file (its world read once more: the surface and barriers). */
static rf_status draw_maps(const char *out_dir, const rf_study *s, const rf_fuzzy_rasters *f, const terrain_band *b,
                           size_t n, const fr_grid *grid, rf_error *err)
{
    const char *stat = s->fuzzy_rasters[0];
    const terrain_band *nominal = band_named(b, n, stat, "_a1.00_lower"), *upper = band_named(b, n, stat, "_a0.00_upper"),
                       *blame = band_named(b, n, stat, "_blame");
    if (!nominal || !upper || !blame)
        return rf_fail(err, RF_EINTERNAL, "the fuzzy rasters of %s lack the alpha 0, 1 or blame band", stat);
    double x[64] = {0}, xi[SB_MAX_TARGETS];
    for (size_t i = 0; i < s->n_params && i < 64; i++)
        x[i] = rf_fuzzy_nominal(&s->inputs[i]);
    to_targets((void *)&s->model, x, xi);
    rf_traj_spec spec;
    void *table;
    rf_terrain_world *w = NULL;
    rf_status st = traj_model_spec_at(f->inner, xi, &spec, &table, err);
    if (st != RF_OK)
        return st;
    if ((st = rf_terrain_world_create(&spec, &w, err)) == RF_OK) {
        const rf_terrain *dem = rf_terrain_world_surface(w);
        terrain_map_grid g = {grid->nx, grid->ny, grid->x0, grid->y0, grid->cell};
        char t[3][200];
        snprintf(t[0], sizeof t[0], "%s [%s]: nominal (alpha = 1: every fuzzy input at its nominal value)", stat,
                 upper->unit && *upper->unit ? upper->unit : "-");
        snprintf(t[1], sizeof t[1], "%s [%s]: alpha = 0 upper bound (the worst case the fuzzy inputs allow)", stat,
                 upper->unit && *upper->unit ? upper->unit : "-");
        snprintf(t[2], sizeof t[2], "%s: blame, the fuzzy input of largest influence (rho) per cell", stat);
        terrain_map_style style[3] = {{upper, NULL, 0, t[0]}, {upper, NULL, 0, t[1]},
                                      {NULL, (const char *const *)s->param_names, s->n_params, t[2]}};
        const terrain_band *band[3] = {nominal, upper, blame};
        for (int k = 0; k < 3 && st == RF_OK; k++)
            st = terrain_draw_band_map(out_dir, MAP_STEMS[k], &spec, dem, &g, band[k], &style[k], err);
        rf_terrain_world_free(w);
    }
    rf_traj_spec_free(&spec);
    return st;
}

rf_status rf_study_fuzzy_rasters_write(const char *out_dir, const rf_study *s, rf_fuzzy_rasters *f,
                                       const rf_tm_result *res, int plots, rf_error *err)
{
    for (int k = 0; k < 3; k++) { /* an earlier run's maps go: the report shows only this run's */
        char png[PATH_MAX];
        snprintf(png, sizeof png, "%s/%s.png", out_dir, MAP_STEMS[k]);
        unlink(png);
    }
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
    if (!st && plots)
        st = draw_maps(out_dir, s, f, bands, n_out, &rd.grid, err);
    terrain_bands_free(bands, n_out);
    return st ? rf_error_prefix(err, "fuzzy hazard rasters") : RF_OK;
}
