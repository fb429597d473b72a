/* terrain_world.c - the prepared world of a terrain spec: the DEM read with
 * its material classes (or the one material) and roughness, each barrier's
 * line with the distance along it, the release set (every release feature on
 * valid cells of the DEM, no no-data cell inside a polygon) and, for the
 * impact_model law, the impact table.
 * terrain_world_from_surface does all but the reading, for a surface made in
 * memory (rf_terrain_from_nodes). */
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rf_terrain_world_free(rf_terrain_world *w)
{
    if (!w)
        return;
    rf_terrain_free(w->dem);
    for (size_t c = 0; w->col && c < w->ncol; c++)
        free(w->col[c].cum);
    free(w->col);
    terrain_release_free(w->release);
    traj_impact_table_free(w->impact_table);
    free(w);
}

const rf_terrain *rf_terrain_world_surface(const rf_terrain_world *w) { return w ? w->dem : NULL; }

/* Without a class raster every cell is the one material (index d->material). */
static rf_status constant_material(rf_terrain *t, const rf_traj_spec *s, rf_error *err)
{
    const rf_terrain_def *d = s->terrain;
    if (d->classes || t->material || d->material == 0)
        return RF_OK; /* classes read, set by the caller, or material 0 (t->material NULL) */
    if (d->material > UINT16_MAX)
        return rf_fail(err, RF_EINVAL, "terrain.material: index %zu beyond %d materials", d->material, UINT16_MAX);
    size_t n = (t->nx - 1) * (t->ny - 1);
    if (!(t->material = malloc(n * sizeof *t->material)))
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t k = 0; k < n; k++)
        t->material[k] = (uint16_t)d->material;
    return RF_OK;
}

static rf_status barrier_geometry(rf_terrain_world *w, const rf_traj_spec *s, rf_error *err)
{
    const rf_terrain_def *d = s->terrain;
    w->ncol = s->n_collectors;
    if (!w->ncol)
        return RF_OK;
    if (!d->barrier_start || d->n_barriers != w->ncol)
        return rf_fail(err, RF_EINVAL, "barriers: %zu barriers but %zu lines", w->ncol, d->n_barriers);
    if (!(w->col = calloc(w->ncol, sizeof *w->col)))
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t c = 0; c < w->ncol; c++) {
        terrain_barrier_geo *g = &w->col[c];
        size_t a = d->barrier_start[c];
        g->n = d->barrier_start[c + 1] - a;
        g->x = d->barrier_x + a, g->y = d->barrier_y + a;
        if (!(g->cum = malloc(g->n * sizeof *g->cum)))
            return rf_fail(err, RF_ENOMEM, "out of memory");
        g->cum[0] = 0;
        for (size_t k = 1; k < g->n; k++)
            g->cum[k] = g->cum[k - 1] + hypot(g->x[k] - g->x[k - 1], g->y[k] - g->y[k - 1]);
        terrain_barrier_box(g);
    }
    return RF_OK;
}

/* (x, y) on a valid cell, else a message naming feature f, its vertex and point. */
static rf_status on_valid(const rf_terrain *t, const rf_terrain_def *d, size_t f, size_t k, double x, double y,
                          rf_error *err)
{
    static const char *const kind[] = {"points", "lines", "polygons"};
    double z;
    if (rf_terrain_height(t, x, y, &z, NULL))
        return RF_OK;
    const char *src = d->release.file ? d->release.file : "";
    return rf_fail(err, RF_EINVAL, "release.%s[%zu]%s%s%s: the point [%g, %g] (by vertex %zu) lies outside the DEM "
                   "or on a no-data cell", kind[d->release.kind], f, src[0] ? " (from " : "", src,
                   src[0] ? ")" : "", x, y, k);
}

static int in_triangle(const double *v, double x, double y)
{
    double a = (v[2] - v[0]) * (y - v[1]) - (v[3] - v[1]) * (x - v[0]);
    double b = (v[4] - v[2]) * (y - v[3]) - (v[5] - v[3]) * (x - v[2]);
    double c = (v[0] - v[4]) * (y - v[5]) - (v[1] - v[5]) * (x - v[4]);
    return a >= 0 && b >= 0 && c >= 0;
}

/* No no-data cell whose centre lies inside polygon f (its triangles): a
 * hole inside the polygon that its edges do not touch. */
static rf_status polygon_holes(const rf_terrain *t, const rf_terrain_world *w, const rf_terrain_def *d, size_t f,
                               rf_error *err)
{
    const double(*v)[6];
    size_t nt = terrain_release_pieces(w->release, f, &v), a = d->release.start[f], n = d->release.start[f + 1] - a;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (size_t k = a; k < a + n; k++)
        x0 = fmin(x0, d->release.x[k]), x1 = fmax(x1, d->release.x[k]), y0 = fmin(y0, d->release.y[k]),
        y1 = fmax(y1, d->release.y[k]);
    size_t i0 = (size_t)fmax(0, floor((x0 - t->x0) / t->dx)), j0 = (size_t)fmax(0, floor((y0 - t->y0) / t->dy));
    size_t i1 = (size_t)fmin((double)t->nx - 2, (x1 - t->x0) / t->dx);
    size_t j1 = (size_t)fmin((double)t->ny - 2, (y1 - t->y0) / t->dy);
    for (size_t j = j0; j <= j1; j++)
        for (size_t i = i0; i <= i1; i++) {
            if (t->valid[j * (t->nx - 1) + i])
                continue;
            double cx = t->x0 + ((double)i + 0.5) * t->dx, cy = t->y0 + ((double)j + 0.5) * t->dy;
            for (size_t k = 0; k < nt; k++)
                if (in_triangle(v[k], cx, cy))
                    return rf_fail(err, RF_EINVAL, "release.polygons[%zu]: the no-data cell centred at [%g, %g] "
                                   "lies inside the polygon", f, cx, cy);
        }
    return RF_OK;
}

/* Every vertex of every release feature, and points along every edge at a
 * quarter of a cell, on valid cells; no no-data cell centred inside a
 * polygon. */
static rf_status release_on_dem(const rf_terrain *t, const rf_terrain_world *w, const rf_terrain_def *d,
                                rf_error *err)
{
    const rf_terrain_release *r = &d->release;
    double step = 0.25 * fmin(t->dx, t->dy);
    for (size_t f = 0; f < r->n_features; f++) {
        size_t a = r->start[f], n = r->start[f + 1] - a;
        size_t edges = r->kind == RF_TERRAIN_POINTS ? 0 : r->kind == RF_TERRAIN_LINES ? n - 1 : n;
        rf_status st = on_valid(t, d, f, 0, r->x[a], r->y[a], err);
        for (size_t e = 0; e < edges && st == RF_OK; e++) {
            size_t i = a + e, j = a + (e + 1) % n;
            double len = hypot(r->x[j] - r->x[i], r->y[j] - r->y[i]);
            size_t m = (size_t)ceil(fmin(len / step, 1e6));
            for (size_t q = 1; q <= m && st == RF_OK; q++) {
                double u = (double)q / (double)m;
                st = on_valid(t, d, f, (e + (q == m)) % n, r->x[i] + u * (r->x[j] - r->x[i]),
                              r->y[i] + u * (r->y[j] - r->y[i]), err);
            }
        }
        if (st == RF_OK && r->kind == RF_TERRAIN_POLYGONS)
            st = polygon_holes(t, w, d, f, err);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

/* The world; with_table: and the impact table of the impact_model law (else left NULL for the caller to build). */
static rf_status world_from_surface(const rf_traj_spec *s, rf_terrain *dem, int with_table, rf_terrain_world **out,
                                    rf_error *err)
{
    *out = NULL;
    rf_terrain_world *w = calloc(1, sizeof *w);
    if (!w) {
        rf_terrain_free(dem);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    w->dem = dem;
    rf_status st = s->terrain ? RF_OK : rf_fail(err, RF_EINVAL, "not a terrain spec (no terrain:)");
    if (st == RF_OK)
        st = constant_material(dem, s, err);
    if (st == RF_OK)
        st = barrier_geometry(w, s, err);
    if (st == RF_OK)
        st = terrain_release_prepare(s, &w->release, err);
    if (st == RF_OK)
        st = release_on_dem(dem, w, s->terrain, err);
    if (st == RF_OK && with_table && s->law == RF_BOUNCE_IMPACT_MODEL)
        st = traj_impact_table_build(s, (traj_impact_table **)&w->impact_table, err);
    if (st != RF_OK) {
        rf_terrain_world_free(w);
        return st;
    }
    *out = w;
    return RF_OK;
}

rf_status terrain_world_from_surface(const rf_traj_spec *s, rf_terrain *dem, rf_terrain_world **out, rf_error *err)
{
    return world_from_surface(s, dem, 1, out, err);
}

/* The world read from the spec's files; with_table as world_from_surface. */
static rf_status world_create(const rf_traj_spec *s, int with_table, rf_terrain_world **w, rf_error *err)
{
    *w = NULL;
    const rf_terrain_def *d = s->terrain;
    if (!d)
        return rf_fail(err, RF_EINVAL, "not a terrain spec (no terrain:)");
    rf_terrain *t = NULL;
    rf_status st = rf_terrain_read_window(d->dem, d->band ? d->band : 1, d->has_window ? d->window : NULL, &t, err);
    if (st == RF_OK && d->classes)
        st = rf_terrain_read_classes(t, d->classes, d->classes_band ? d->classes_band : 1, d->n_classes,
                                     d->class_value, d->class_material, err);
    if (st == RF_OK && d->roughness)
        st = rf_terrain_read_roughness(t, d->roughness, d->roughness_band ? d->roughness_band : 1, err);
    if (st != RF_OK) {
        rf_terrain_free(t);
        return st;
    }
    return world_from_surface(s, t, with_table, w, err);
}

rf_status rf_terrain_world_create(const rf_traj_spec *s, rf_terrain_world **w, rf_error *err)
{
    return world_create(s, 1, w, err);
}

rf_status terrain_world_create_deferred(const rf_traj_spec *s, rf_terrain_world **w, rf_error *err)
{
    return world_create(s, 0, w, err);
}
