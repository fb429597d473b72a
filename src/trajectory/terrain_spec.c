/* terrain_spec.c - the terrain part of a trajectory spec (rf_terrain_def):
 * free, deep copy, the hash of everything a run reads (the bytes of every
 * file it names included, so that an edited DEM changes the model's
 * identity), and the checks of the validation (materials, barrier lines,
 * rasters, release features).  The world is terrain_world.c. */
#include "trajectory/terrain_internal.h"
#include "core/hash.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void release_free(rf_terrain_release *r)
{
    free(r->start);
    free(r->x);
    free(r->y);
    free(r->weight);
    free(r->file);
}

void rf_terrain_def_free(rf_terrain_def *d)
{
    if (!d)
        return;
    free(d->dem);
    free(d->classes);
    free(d->class_value);
    free(d->class_material);
    free(d->roughness);
    release_free(&d->release);
    free(d->barrier_start);
    free(d->barrier_x);
    free(d->barrier_y);
    memset(d, 0, sizeof *d);
}

static void *dup_mem(const void *p, size_t n, int *ok)
{
    if (!p)
        return NULL;
    void *q = malloc(n ? n : 1);
    if (q && n)
        memcpy(q, p, n);
    *ok &= q != NULL;
    return q;
}

static char *dup_str(const char *s, int *ok)
{
    return s ? dup_mem(s, strlen(s) + 1, ok) : NULL;
}

rf_status rf_terrain_def_copy(const rf_terrain_def *src, rf_terrain_def *dst, rf_error *err)
{
    int ok = 1;
    *dst = *src;
    dst->dem = dup_str(src->dem, &ok);
    dst->classes = dup_str(src->classes, &ok);
    dst->roughness = dup_str(src->roughness, &ok);
    dst->class_value = dup_mem(src->class_value, src->n_classes * sizeof *src->class_value, &ok);
    dst->class_material = dup_mem(src->class_material, src->n_classes * sizeof *src->class_material, &ok);
    const rf_terrain_release *r = &src->release;
    size_t nv = r->start ? r->start[r->n_features] : 0;
    dst->release.start = dup_mem(r->start, (r->n_features + 1) * sizeof *r->start, &ok);
    dst->release.x = dup_mem(r->x, nv * sizeof *r->x, &ok);
    dst->release.y = dup_mem(r->y, nv * sizeof *r->y, &ok);
    dst->release.weight = dup_mem(r->weight, r->n_features * sizeof *r->weight, &ok);
    dst->release.file = dup_str(r->file, &ok);
    size_t nb = src->n_barriers, nbv = src->barrier_start ? src->barrier_start[nb] : 0;
    dst->barrier_start = dup_mem(src->barrier_start, (nb + 1) * sizeof *src->barrier_start, &ok);
    dst->barrier_x = dup_mem(src->barrier_x, nbv * sizeof *src->barrier_x, &ok);
    dst->barrier_y = dup_mem(src->barrier_y, nbv * sizeof *src->barrier_y, &ok);
    if (!ok) {
        rf_terrain_def_free(dst);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    return RF_OK;
}

static uint64_t hash_str(uint64_t h, const char *s) { return rf_fnv1a(h, s ? s : "", s ? strlen(s) + 1 : 1); }

/* The bytes of file `path` (a missing file hashes as its name only: the
 * world reports it when it is read). */
static uint64_t hash_file(uint64_t h, const char *path)
{
    h = hash_str(h, path);
    FILE *f = path ? fopen(path, "rb") : NULL;
    if (!f)
        return h;
    char buf[1 << 16];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        h = rf_fnv1a(h, buf, n);
    fclose(f);
    return h;
}

/* A file and, for a shapefile, its companions (.dbf, .shx, .prj). */
static uint64_t hash_files(uint64_t h, const char *path)
{
    h = hash_file(h, path);
    size_t n = path ? strlen(path) : 0;
    if (n < 4 || strcmp(path + n - 4, ".shp"))
        return h;
    char other[4096];
    const char *ext[] = {".dbf", ".shx", ".prj"};
    for (int k = 0; k < 3 && n < sizeof other; k++) {
        snprintf(other, sizeof other, "%.*s%s", (int)(n - 4), path, ext[k]);
        h = hash_file(h, other);
    }
    return h;
}

uint64_t rf_terrain_def_hash(const rf_terrain_def *d, uint64_t h)
{
    if (!d)
        return h;
    h = hash_files(hash_files(hash_files(h, d->dem), d->classes), d->roughness);
    int ints[4] = {d->band, d->classes_band, d->roughness_band, (int)d->release.kind};
    h = rf_fnv1a(h, ints, sizeof ints);
    h = rf_fnv1a(h, d->class_value, d->n_classes * sizeof *d->class_value);
    h = rf_fnv1a(h, d->class_material, d->n_classes * sizeof *d->class_material);
    size_t counts[4] = {d->n_classes, d->material, d->release.n_features, d->max_paths};
    h = rf_fnv1a(h, counts, sizeof counts);
    const rf_terrain_release *r = &d->release;
    size_t nv = r->start ? r->start[r->n_features] : 0;
    h = rf_fnv1a(h, r->start, r->start ? (r->n_features + 1) * sizeof *r->start : 0);
    h = rf_fnv1a(h, r->x, nv * sizeof *r->x);
    h = rf_fnv1a(h, r->y, nv * sizeof *r->y);
    h = rf_fnv1a(h, r->weight, r->n_features * sizeof *r->weight);
    h = hash_files(h, r->file);
    size_t nb = d->n_barriers, nbv = d->barrier_start ? d->barrier_start[nb] : 0;
    h = rf_fnv1a(h, d->barrier_start, d->barrier_start ? (nb + 1) * sizeof *d->barrier_start : 0);
    h = rf_fnv1a(h, d->barrier_x, nbv * sizeof *d->barrier_x);
    h = rf_fnv1a(h, d->barrier_y, nbv * sizeof *d->barrier_y);
    h = rf_fnv1a(h, &d->raster_cell, sizeof d->raster_cell);
    h = rf_fnv1a(h, &d->statistics, sizeof d->statistics);
    return d->has_window ? rf_fnv1a(h, d->window, sizeof d->window) : h; /* files without one: identity unchanged */
}

/* Every material is used: by a class of the class raster, or as the one material. */
static rf_status check_materials(const rf_traj_spec *s, const rf_terrain_def *d, rf_error *err)
{
    if (!d->classes && d->material >= s->n_materials)
        return rf_fail(err, RF_EINVAL, "terrain.material: no such material (index %zu)", d->material);
    for (size_t k = 0; k < d->n_classes; k++)
        if (d->class_material[k] >= s->n_materials)
            return rf_fail(err, RF_EINVAL, "terrain.materials.classes.%ld: no such material", d->class_value[k]);
    for (size_t m = 0; m < s->n_materials; m++) {
        int used = !d->classes && d->material == m;
        for (size_t k = 0; k < d->n_classes && !used; k++)
            used = d->class_material[k] == m;
        if (!used)
            return rf_fail(err, RF_EINVAL, "materials.%s: not used by the terrain (%s)", s->materials[m].name,
                           d->classes ? "no class of terrain.materials.classes names it"
                                      : "terrain.material names another one");
    }
    return RF_OK;
}

/* Each barrier line: at least 2 vertices, finite coordinates within +-1e7 m. */
static rf_status check_barriers(const rf_traj_spec *s, const rf_terrain_def *d, rf_error *err)
{
    if (s->n_collectors && (!d->barrier_start || d->n_barriers != s->n_collectors))
        return rf_fail(err, RF_EINVAL, "barriers: %zu barriers but %zu lines", s->n_collectors, d->n_barriers);
    for (size_t c = 0; c < s->n_collectors; c++) {
        size_t a = d->barrier_start[c], b = d->barrier_start[c + 1];
        if (b < a + 2)
            return rf_fail(err, RF_EINVAL, "barriers.%s.line: %zu vertices; a barrier line needs at least 2",
                           s->collectors[c].name, b - a);
        for (size_t k = a; k < b; k++)
            if (!(fabs(d->barrier_x[k]) <= RF_TRAJ_MAX_COORD && fabs(d->barrier_y[k]) <= RF_TRAJ_MAX_COORD))
                return rf_fail(err, RF_EINVAL, "barriers.%s.line[%zu] = [%g, %g]: coordinates must be finite and "
                               "within +-1e+07 m", s->collectors[c].name, k - a, d->barrier_x[k], d->barrier_y[k]);
    }
    return RF_OK;
}

static rf_status check_release(const rf_terrain_def *d, rf_error *err)
{
    static const char *const kind[] = {"points", "lines", "polygons"};
    const rf_terrain_release *r = &d->release;
    if (!r->start || r->n_features == 0)
        return rf_fail(err, RF_EINVAL, "release: no release feature (points, lines, polygons, file or raster)");
    for (size_t f = 0; f < r->n_features; f++)
        for (size_t k = r->start[f]; k < r->start[f + 1]; k++)
            if (!(fabs(r->x[k]) <= RF_TRAJ_MAX_COORD && fabs(r->y[k]) <= RF_TRAJ_MAX_COORD))
                return rf_fail(err, RF_EINVAL, "release.%s[%zu] = [%g, %g]: coordinates must be finite and within "
                               "+-1e+07 m", kind[r->kind], f, r->x[k], r->y[k]);
    return RF_OK;
}

rf_status terrain_spec_check(const rf_traj_spec *s, rf_error *err)
{
    const rf_terrain_def *d = s->terrain;
    if (!d->dem || !d->dem[0])
        return rf_fail(err, RF_EINVAL, "terrain.dem: missing (the DEM file)");
    if (!(isfinite(d->raster_cell) && d->raster_cell >= 0))
        return rf_fail(err, RF_EINVAL, "rasters.cell = %g: must be > 0 [m]", d->raster_cell);
    if (d->statistics & ~(RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS |
                          RF_TERRAIN_ENERGY | RF_TERRAIN_HEIGHT))
        return rf_fail(err, RF_EINVAL, "rasters.statistics: unknown statistic (mask %#x)", d->statistics);
    rf_status st = check_materials(s, d, err);
    if (st == RF_OK)
        st = check_barriers(s, d, err);
    if (st == RF_OK)
        st = check_release(d, err);
    terrain_release_set *set = NULL;
    if (st == RF_OK) /* weights, vertex counts, simple polygons */
        st = terrain_release_prepare(s, &set, err);
    terrain_release_free(set);
    return st;
}
