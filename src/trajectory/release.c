/* release.c - where and how a trajectory starts (docs/trajectories.md sec. 2):
 * the release velocity from vx, vy or from a speed and an angle; and the
 * release kinds that draw the point per trajectory: uniformly by length
 * along a polyline (`line`), or uniformly along the ground inside a zone
 * (`zone`: a polygon, or an x-range), on the ground.  Both are a set of
 * straight pieces with their cumulative lengths, prepared once per world;
 * the point of a uniform u in (0, 1) is found by a binary search. */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct traj_release_set {
    size_t n;
    double *ax, *ay, *bx, *by;   /* pieces */
    double *cum;                 /* cum[i]: length of pieces 0..i-1; cum[n] the total [m] */
};

void traj_release_velocity(const rf_traj_spec *s, double *vx, double *vy)
{
    if (s->release_by_speed)
        *vx = s->speed0 * cos(s->angle0), *vy = s->speed0 * sin(s->angle0);
    else
        *vx = s->vx0, *vy = s->vy0;
}

void traj_release_free(traj_release_set *r)
{
    if (!r)
        return;
    free(r->ax), free(r->ay), free(r->bx), free(r->by), free(r->cum);
    free(r);
}

static int add_piece(traj_release_set *r, size_t cap, double ax, double ay, double bx, double by)
{
    double len = hypot(bx - ax, by - ay);
    if (!(len > 0) || r->n >= cap)
        return 0;
    r->ax[r->n] = ax, r->ay[r->n] = ay, r->bx[r->n] = bx, r->by[r->n] = by;
    r->cum[r->n + 1] = r->cum[r->n] + len;
    r->n++;
    return 1;
}

/* Point in polygon (even-odd rule). */
static int inside(const rf_traj_spec *s, double x, double y)
{
    int in = 0;
    for (size_t i = 0, j = s->n_release - 1; i < s->n_release; j = i++) {
        double xi = s->release_px[i], yi = s->release_py[i], xj = s->release_px[j], yj = s->release_py[j];
        if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi)
            in = !in;
    }
    return in;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The parts of ground segment g inside the zone: parameters where it crosses
 * the polygon's edges (or the x-range's ends), the pieces between them whose
 * midpoint lies inside. */
static void zone_pieces(const rf_traj_spec *s, const traj_segment *g, traj_release_set *r, size_t cap)
{
    double u[66] = {0, 1};
    size_t n = 2;
    if (!s->n_release) {
        u[n++] = (s->zone_x0 - g->ax) / (g->bx - g->ax), u[n++] = (s->zone_x1 - g->ax) / (g->bx - g->ax);
    }
    for (size_t i = 0; s->n_release && i < s->n_release && n < 66; i++) {
        size_t j = (i + 1) % s->n_release;
        double ex = s->release_px[j] - s->release_px[i], ey = s->release_py[j] - s->release_py[i];
        double dx = g->bx - g->ax, dy = g->by - g->ay, den = dx * ey - dy * ex;
        if (den == 0)
            continue;
        double wx = s->release_px[i] - g->ax, wy = s->release_py[i] - g->ay;
        double t = (wx * ey - wy * ex) / den, v = (wx * dy - wy * dx) / den;
        if (v >= 0 && v <= 1)
            u[n++] = t;
    }
    qsort(u, n, sizeof *u, cmp_double);
    for (size_t k = 0; k + 1 < n; k++) {
        double u0 = fmax(u[k], 0), u1 = fmin(u[k + 1], 1), um = 0.5 * (u0 + u1);
        if (!(u1 > u0))
            continue;
        double mx = g->ax + um * (g->bx - g->ax), my = g->ay + um * (g->by - g->ay);
        int in = s->n_release ? inside(s, mx, my) : mx >= s->zone_x0 && mx <= s->zone_x1;
        if (in)
            add_piece(r, cap, g->ax + u0 * (g->bx - g->ax), g->ay + u0 * (g->by - g->ay),
                      g->ax + u1 * (g->bx - g->ax), g->ay + u1 * (g->by - g->ay));
    }
}

static traj_release_set *alloc_set(size_t cap)
{
    traj_release_set *r = calloc(1, sizeof *r);
    if (!r)
        return NULL;
    r->ax = malloc(cap * sizeof *r->ax), r->ay = malloc(cap * sizeof *r->ay);
    r->bx = malloc(cap * sizeof *r->bx), r->by = malloc(cap * sizeof *r->by);
    r->cum = calloc(cap + 1, sizeof *r->cum);
    if (!r->ax || !r->ay || !r->bx || !r->by || !r->cum) {
        traj_release_free(r);
        return NULL;
    }
    return r;
}

rf_status traj_release_prepare(const rf_traj_spec *s, rf_traj_world *w, rf_error *err)
{
    w->release = NULL;
    if (s->release_kind == RF_TRAJ_RELEASE_POINT)
        return RF_OK;
    int line = s->release_kind == RF_TRAJ_RELEASE_LINE;
    size_t cap = line ? s->n_release : w->nseg * ((s->n_release ? s->n_release : 2) + 1);
    traj_release_set *r = alloc_set(cap ? cap : 1);
    if (!r)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; line && i + 1 < s->n_release; i++)
        add_piece(r, cap, s->release_px[i], s->release_py[i], s->release_px[i + 1], s->release_py[i + 1]);
    for (size_t k = 0; !line && k < w->nseg; k++)
        if (w->seg[k].ny > 0) /* ground that can carry a block: not a vertical step */
            zone_pieces(s, &w->seg[k], r, cap);
    if (!(r->n > 0 && r->cum[r->n] > 0)) {
        traj_release_free(r);
        return rf_fail(err, RF_EINVAL, "release.%s: %s", line ? "line" : "zone",
                       line ? "has no length" : "holds no ground of the profile (no part of a non-vertical "
                                                "segment lies inside it)");
    }
    w->release = r;
    return RF_OK;
}

void traj_release_point(const rf_traj_world *w, double u, double *x, double *y)
{
    const traj_release_set *r = w->release;
    double at = u * r->cum[r->n];
    size_t lo = 0, hi = r->n - 1;
    while (lo < hi) { /* the last piece with cum[i] <= at */
        size_t mid = (lo + hi + 1) / 2;
        if (r->cum[mid] <= at)
            lo = mid;
        else
            hi = mid - 1;
    }
    double f = (at - r->cum[lo]) / (r->cum[lo + 1] - r->cum[lo]);
    f = fmin(fmax(f, 0), 1);
    *x = r->ax[lo] + f * (r->bx[lo] - r->ax[lo]);
    *y = r->ay[lo] + f * (r->by[lo] - r->ay[lo]);
}

