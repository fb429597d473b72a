/* test_terrain_util.h - what the 3D trajectory tests share (include after
 * <cmocka.h>): a DEM from a function of (x, y), a spec with one material
 * built in memory, a world filled by hand (the DEM and barrier polylines; the
 * file engineer's world builder is not needed), a result with its records,
 * a small deterministic random generator, and |a - b| <= atol. */
#ifndef ROCKFUZZ_TEST_TERRAIN_UTIL_H
#define ROCKFUZZ_TEST_TERRAIN_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/terrain.h"
#include "trajectory/terrain_internal.h"

#define TT_G 9.81
#define TT_PI 3.14159265358979323846
#define TT_DEG (TT_PI / 180.0)

#define assert_near(a, b, atol)                                                                             \
    do {                                                                                                    \
        double a_ = (a), b_ = (b);                                                                          \
        if (!(fabs(a_ - b_) <= (atol)))                                                                     \
            fail_msg("%s = %.17g, expected %.17g (atol %g)", #a, a_, b_, (double)(atol));                   \
    } while (0)

/* xorshift64*: uniform in [0, 1) */
static inline double tt_rand(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ull) >> 11) * 0x1.0p-53;
}
static inline double tt_uniform(uint64_t *s, double a, double b) { return a + (b - a) * tt_rand(s); }

typedef double (*tt_height_fn)(void *ctx, double x, double y);

/* A DEM of nx x ny nodes from z = f(ctx, x, y). */
static inline rf_terrain *tt_dem(size_t nx, size_t ny, double x0, double y0, double dx, double dy, tt_height_fn f,
                                 void *ctx)
{
    double *z = malloc(nx * ny * sizeof *z);
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++)
            z[j * nx + i] = f(ctx, x0 + (double)i * dx, y0 + (double)j * dy);
    rf_terrain *t;
    rf_error err;
    if (rf_terrain_from_nodes(nx, ny, x0, y0, dx, dy, z, &t, &err) != RF_OK)
        fail_msg("dem: %s", err.msg);
    free(z);
    return t;
}

/* A plane z = z0 + sx (x - xc) + sy (y - yc). */
typedef struct {
    double z0, sx, sy, xc, yc;
} tt_plane;
static inline double tt_plane_z(void *ctx, double x, double y)
{
    const tt_plane *p = ctx;
    return p->z0 + p->sx * (x - p->xc) + p->sy * (y - p->yc);
}

/* A spec in memory: one material, a point block of 1000 kg (or a sphere
 * with tt_sphere), law constant, contact_speed 0.1, v_stop 0.1. */
typedef struct {
    rf_traj_spec spec;
    rf_traj_material mat[4];
    rf_traj_collector col[4];
} tt_spec;

static inline void tt_spec_init(tt_spec *t, double Rn, double Rt)
{
    memset(t, 0, sizeof *t);
    rf_traj_spec *s = &t->spec;
    s->gravity = TT_G;
    s->n_materials = 1, s->materials = t->mat;
    t->mat[0] = (rf_traj_material){"rock", Rn, Rt, 30 * TT_DEG, 0.1, 0, {0}};
    s->mass = 1000;
    s->law = RF_BOUNCE_CONSTANT;
    s->scale_speed = RF_TRAJ_PFEIFFER_BOWEN_K;
    s->contact_speed = 0.1, s->v_stop = 0.1, s->max_steps = 10000;
    s->collectors = t->col;
    s->height0 = 0;
}

static inline void tt_sphere(tt_spec *t, double radius, double density)
{
    t->spec.sphere = 1, t->spec.radius = radius, t->spec.density = density;
    t->spec.mass = 4.0 / 3.0 * TT_PI * radius * radius * radius * density;
}

/* A world on dem with up to 4 barrier polylines added by tt_world_barrier. */
typedef struct {
    rf_terrain_world w;
    terrain_barrier_geo geo[4];
    double bx[4][8], by[4][8], cum[4][8];
} tt_world;

static inline void tt_world_init(tt_world *tw, rf_terrain *dem)
{
    memset(tw, 0, sizeof *tw);
    tw->w.dem = dem;
    tw->w.col = tw->geo;
}

/* Barrier polyline of n <= 8 vertices with capacity [J] and height [m]. */
static inline void tt_world_barrier(tt_world *tw, tt_spec *ts, size_t n, const double *x, const double *y,
                                    double capacity, double height)
{
    size_t c = tw->w.ncol++;
    terrain_barrier_geo *g = &tw->geo[c];
    g->n = n, g->x = tw->bx[c], g->y = tw->by[c], g->cum = tw->cum[c];
    for (size_t k = 0; k < n; k++) {
        tw->bx[c][k] = x[k], tw->by[c][k] = y[k];
        tw->cum[c][k] = k ? tw->cum[c][k - 1] + hypot(x[k] - x[k - 1], y[k] - y[k - 1]) : 0;
    }
    terrain_barrier_box(g);
    rf_traj_collector *col = &ts->col[c];
    memset(col, 0, sizeof *col);
    col->name = "fence", col->capacity = capacity, col->height = height;
    ts->spec.n_collectors = tw->w.ncol;
}

/* A result recording impacts and events. */
typedef struct {
    rf_terrain_result res;
    rf_traj_crossing cross[4];
} tt_result;

static inline void tt_result_init(tt_result *r)
{
    memset(r, 0, sizeof *r);
    r->res.crossings = r->cross;
    r->res.impacts = malloc(16 * sizeof *r->res.impacts);
    r->res.impacts_cap = 16;
    r->res.events = malloc(16 * sizeof *r->res.events);
    r->res.events_cap = 16;
}

static inline void tt_result_free(tt_result *r)
{
    free(r->res.impacts);
    free(r->res.events);
}

/* Simulate from start and assert the invariants. */
static inline void tt_simulate(const tt_world *tw, const tt_spec *ts, uint64_t sample, const double start[3],
                               tt_result *r)
{
    rf_error err;
    if (rf_terrain_simulate(&tw->w, &ts->spec, 7, sample, start, &r->res, &err) != RF_OK)
        fail_msg("simulate: %s", err.msg);
    if (terrain_check_invariants(&ts->spec, tw->w.dem, &r->res, &err) != RF_OK)
        fail_msg("invariant broken: %s", err.msg);
}

#endif
