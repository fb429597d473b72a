/* terrain_grid.c - the terrain surface (terrain.h): made from nodes, freed,
 * and evaluated: the bilinear interpolation of the nodes, z = a + b X + c Y
 * + d X Y on each cell (terrain_patch_of), and its exact normal
 * (-dz/dx, -dz/dy, 1) / |.|, with dz/dx = b + d Y, dz/dy = c + d X. */
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Mark the cells whose four nodes hold data. */
static void mark_valid(rf_terrain *t)
{
    for (size_t j = 0; j + 1 < t->ny; j++)
        for (size_t i = 0; i + 1 < t->nx; i++) {
            const double *z = t->z + j * t->nx + i;
            t->valid[j * (t->nx - 1) + i] =
                isfinite(z[0]) && isfinite(z[1]) && isfinite(z[t->nx]) && isfinite(z[t->nx + 1]);
        }
}

/* An empty surface of nx x ny nodes (z uninitialised). */
rf_status terrain_alloc(size_t nx, size_t ny, rf_terrain **out, rf_error *err)
{
    *out = NULL;
    if (nx < 2 || ny < 2 || nx > (size_t)1 << 20 || ny > (size_t)1 << 20 || nx * ny > (size_t)1 << 31)
        return rf_fail(err, RF_EINVAL, "terrain: %zu x %zu nodes: need 2 to 2^20 per side and at most 2^31 in all",
                       nx, ny);
    rf_terrain *t = calloc(1, sizeof *t);
    if (!t)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    t->nx = nx, t->ny = ny;
    t->z = malloc(nx * ny * sizeof *t->z);
    t->valid = malloc((nx - 1) * (ny - 1));
    t->crs_wkt = calloc(1, 1);
    if (!t->z || !t->valid || !t->crs_wkt) {
        rf_terrain_free(t);
        return rf_fail(err, RF_ENOMEM, "terrain: out of memory for %zu x %zu nodes", nx, ny);
    }
    *out = t;
    return RF_OK;
}

/* After z is filled: the valid cells. */
void terrain_finish(rf_terrain *t) { mark_valid(t); }

rf_status rf_terrain_from_nodes(size_t nx, size_t ny, double x0, double y0, double dx, double dy, const double *z,
                                rf_terrain **out, rf_error *err)
{
    *out = NULL;
    if (!(dx > 0 && dy > 0 && isfinite(dx) && isfinite(dy) && isfinite(x0) && isfinite(y0)))
        return rf_fail(err, RF_EINVAL, "terrain: node spacing dx = %g, dy = %g must be positive and finite", dx, dy);
    rf_terrain *t;
    rf_status st = terrain_alloc(nx, ny, &t, err);
    if (st != RF_OK)
        return st;
    t->x0 = x0, t->y0 = y0, t->dx = dx, t->dy = dy;
    memcpy(t->z, z, nx * ny * sizeof *z);
    terrain_finish(t);
    *out = t;
    return RF_OK;
}

void rf_terrain_free(rf_terrain *t)
{
    if (!t)
        return;
    free(t->z);
    free(t->valid);
    free(t->material);
    free(t->roughness);
    free(t->crs_wkt);
    free(t);
}

int rf_terrain_height(const rf_terrain *t, double x, double y, double *z, double normal[3])
{
    size_t i, j;
    double u, v;
    if (!terrain_cell_of(t, x, y, &i, &j, &u, &v))
        return 0;
    terrain_patch p = terrain_patch_of(t, i, j);
    double X = x - p.xi, Y = y - p.yj;
    *z = p.a + p.b * X + p.c * Y + p.d * X * Y;
    if (normal) {
        double zx = p.b + p.d * Y, zy = p.c + p.d * X, s = 1 / sqrt(1 + zx * zx + zy * zy);
        normal[0] = -zx * s, normal[1] = -zy * s, normal[2] = s;
    }
    return 1;
}

void rf_terrain_extent(const rf_terrain *t, double *xmin, double *xmax, double *ymin, double *ymax, double *dx,
                       double *dy)
{
    *xmin = t->x0, *xmax = t->x0 + (double)(t->nx - 1) * t->dx;
    *ymin = t->y0, *ymax = t->y0 + (double)(t->ny - 1) * t->dy;
    *dx = t->dx, *dy = t->dy;
}

const char *rf_terrain_crs_wkt(const rf_terrain *t) { return t->crs_wkt ? t->crs_wkt : ""; }
