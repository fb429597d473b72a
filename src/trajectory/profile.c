/* profile.c - the slope profile: geometric validation (x non-decreasing, no
 * zero-length segment, no self-intersection), the prepared segments
 * (tangent, outward normal, length, x-range) shared read-only by all
 * trajectories, the ground under a given x, and collector geometry. */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdlib.h>

/* Orientation of c relative to the line a->b: >0 left, <0 right, 0 on it. */
static double orient(double ax, double ay, double bx, double by, double cx, double cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

static int on_box(double ax, double ay, double bx, double by, double cx, double cy)
{
    return cx >= fmin(ax, bx) && cx <= fmax(ax, bx) && cy >= fmin(ay, by) && cy <= fmax(ay, by);
}

/* Closed segments [p, q] and [r, s] share a point. */
static int segments_meet(const double *x, const double *y, size_t i, size_t j)
{
    double d1 = orient(x[j], y[j], x[j + 1], y[j + 1], x[i], y[i]);
    double d2 = orient(x[j], y[j], x[j + 1], y[j + 1], x[i + 1], y[i + 1]);
    double d3 = orient(x[i], y[i], x[i + 1], y[i + 1], x[j], y[j]);
    double d4 = orient(x[i], y[i], x[i + 1], y[i + 1], x[j + 1], y[j + 1]);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return 1;
    return (d1 == 0 && on_box(x[j], y[j], x[j + 1], y[j + 1], x[i], y[i])) ||
           (d2 == 0 && on_box(x[j], y[j], x[j + 1], y[j + 1], x[i + 1], y[i + 1])) ||
           (d3 == 0 && on_box(x[i], y[i], x[i + 1], y[i + 1], x[j], y[j])) ||
           (d4 == 0 && on_box(x[i], y[i], x[i + 1], y[i + 1], x[j + 1], y[j + 1]));
}

/* No two non-adjacent segments meet.  Sorted by x, segment i can only meet the
 * segments starting at or before its right end.  A run of vertical segments on
 * one x is monotone (no fold-back, checked before), so its non-adjacent members
 * are disjoint and are skipped as a block: vertices sharing one x cost O(n),
 * not O(n^2). */
static rf_status check_crossings(const rf_traj_spec *s, rf_error *err)
{
    const double *x = s->px, *y = s->py;
    size_t nseg = s->n_points - 1;
    size_t *run_end = malloc(nseg * sizeof *run_end); /* first segment after i's vertical run */
    if (!run_end)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = nseg; i-- > 0;)
        run_end[i] = x[i + 1] != x[i] ? i + 1 : i + 1 < nseg && x[i + 2] == x[i] ? run_end[i + 1] : i + 1;
    rf_status st = RF_OK;
    for (size_t i = 0; i < nseg && st == RF_OK; i++)
        for (size_t j = i + 2; j < nseg; j++) {
            if (x[j] > fmax(x[i], x[i + 1]))
                break; /* sorted by x: later segments lie further right */
            if (x[i + 1] == x[i] && j < run_end[i]) {
                j = run_end[i] - 1; /* the rest of i's own vertical run */
                continue;
            }
            if (segments_meet(x, y, i, j)) {
                st = rf_fail(err, RF_EINVAL, "profile.points: segment %zu ([%g, %g] to [%g, %g]) meets segment %zu "
                             "([%g, %g] to [%g, %g]): the profile intersects itself", i, x[i], y[i], x[i + 1],
                             y[i + 1], j, x[j], y[j], x[j + 1], y[j + 1]);
                break;
            }
        }
    free(run_end);
    return st;
}

rf_status traj_profile_check(const rf_traj_spec *s, rf_error *err)
{
    const double *x = s->px, *y = s->py;
    if (s->n_points < 2)
        return rf_fail(err, RF_EINVAL, "profile.points: %zu points; a profile needs at least 2", s->n_points);
    for (size_t i = 0; i < s->n_points; i++)
        if (!isfinite(x[i]) || !isfinite(y[i]))
            return rf_fail(err, RF_EINVAL, "profile.points[%zu] = [%g, %g]: not finite", i, x[i], y[i]);
        else if (!(fabs(x[i]) <= RF_TRAJ_MAX_COORD && fabs(y[i]) <= RF_TRAJ_MAX_COORD))
            return rf_fail(err, RF_EINVAL, "profile.points[%zu] = [%g, %g]: beyond %g m; coordinates must lie "
                           "within +-%g m (a no-data value taken as a height?)", i, x[i], y[i], RF_TRAJ_MAX_COORD,
                           RF_TRAJ_MAX_COORD);
    for (size_t i = 0; i + 1 < s->n_points; i++) {
        if (x[i + 1] < x[i])
            return rf_fail(err, RF_EINVAL, "profile.points[%zu] = [%g, %g]: x decreases (previous x = %g); "
                           "the profile must be sorted by x (vertical steps allowed)", i + 1, x[i + 1], y[i + 1], x[i]);
        if (x[i + 1] == x[i] && y[i + 1] == y[i])
            return rf_fail(err, RF_EINVAL, "profile.points[%zu] = [%g, %g]: repeats the previous point", i + 1,
                           x[i + 1], y[i + 1]);
    }
    size_t nseg = s->n_points - 1;
    for (size_t i = 0; i + 1 < nseg; i++) { /* adjacent segments folding back onto each other */
        double c = orient(x[i], y[i], x[i + 1], y[i + 1], x[i + 2], y[i + 2]);
        double d = (x[i + 1] - x[i]) * (x[i + 2] - x[i + 1]) + (y[i + 1] - y[i]) * (y[i + 2] - y[i + 1]);
        if (c == 0 && d < 0)
            return rf_fail(err, RF_EINVAL, "profile.points[%zu] = [%g, %g]: segments %zu and %zu fold back onto "
                           "each other (self-intersecting profile)", i + 2, x[i + 2], y[i + 2], i, i + 1);
    }
    return check_crossings(s, err);
}

/* The first segment whose end (0: its start ax, 1: its end bx) is >= x
 * (past: > x), nseg if none: both ends are non-decreasing along the profile. */
static size_t first_end(const rf_traj_world *w, int end, int past, double x)
{
    size_t lo = 0, hi = w->nseg;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        double e = end ? w->seg[mid].bx : w->seg[mid].ax;
        if (past ? e > x : e >= x)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* The segments covering x are the contiguous range [first with bx >= x, last with ax <= x]:
 * found by bisection, O(log n) per lookup. */
double traj_ground_y(const rf_traj_world *w, double x, size_t *segment)
{
    double best = NAN;
    size_t k = TRAJ_NONE, end = isnan(x) ? 0 : first_end(w, 0, 1, x);
    for (size_t i = isnan(x) ? 0 : first_end(w, 1, 0, x); i < end; i++) {
        const traj_segment *g = &w->seg[i];
        if (g->tx <= 0 || x < g->xmin || x > g->xmax)
            continue;
        double u = (x - g->ax) / g->tx;
        double y = g->ay + u * g->ty;
        if (x == g->bx)
            y = g->by;
        if (k == TRAJ_NONE || y > best)
            best = y, k = i;
    }
    if (segment)
        *segment = k;
    return best;
}

static void prepare_segment(const rf_traj_spec *s, size_t i, traj_segment *g)
{
    g->ax = s->px[i], g->ay = s->py[i], g->bx = s->px[i + 1], g->by = s->py[i + 1];
    double dx = g->bx - g->ax, dy = g->by - g->ay;
    g->len = hypot(dx, dy);
    g->tx = dx / g->len, g->ty = dy / g->len;
    if (dx == 0) /* exactly vertical: keep the normal exactly horizontal */
        g->tx = 0, g->ty = dy > 0 ? 1 : -1;
    if (dy == 0)
        g->tx = 1, g->ty = 0;
    g->nx = -g->ty, g->ny = g->tx;
    g->xmin = fmin(g->ax, g->bx), g->xmax = fmax(g->ax, g->bx);
    g->material = s->seg_material ? s->seg_material[i] : 0;
}

rf_status rf_traj_world_create(const rf_traj_spec *s, rf_traj_world **out, rf_error *err)
{
    return traj_world_create_shared(s, NULL, out, err);
}

rf_status traj_world_create_shared(const rf_traj_spec *s, void *table, rf_traj_world **out, rf_error *err)
{
    *out = NULL;
    rf_status st = traj_profile_check(s, err);
    if (st != RF_OK)
        return st;
    rf_traj_world *w = calloc(1, sizeof *w);
    if (!w)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    w->nseg = s->n_points - 1;
    w->seg = calloc(w->nseg, sizeof *w->seg);
    w->ncol = s->n_collectors;
    w->col = calloc(w->ncol ? w->ncol : 1, sizeof *w->col);
    if (!w->seg || !w->col) {
        rf_traj_world_free(w);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    double xmin = s->px[0], xmax = s->px[s->n_points - 1];
    for (size_t i = 0; i < w->nseg; i++)
        prepare_segment(s, i, &w->seg[i]);
    for (size_t c = 0; c < w->ncol; c++) {
        w->col[c].x = s->collectors[c].x;
        w->col[c].ground_y = traj_ground_y(w, w->col[c].x, &w->col[c].segment);
        if (w->col[c].segment == TRAJ_NONE) {
            rf_traj_world_free(w);
            return rf_fail(err, RF_EINVAL, "collectors.%s.x = %g: outside the profile's x-range [%g, %g]",
                           s->collectors[c].name, s->collectors[c].x, xmin, xmax);
        }
    }
    if ((st = traj_release_prepare(s, w, err)) != RF_OK) {
        rf_traj_world_free(w);
        return st;
    }
    w->impact_table = table;
    if (s->law == RF_BOUNCE_IMPACT_MODEL && !table) {
        w->owns_table = 1;
        st = traj_impact_table_build(s, (traj_impact_table **)&w->impact_table, err);
        if (st != RF_OK) {
            rf_traj_world_free(w);
            return st;
        }
    }
    *out = w;
    return RF_OK;
}

void rf_traj_world_free(rf_traj_world *w)
{
    if (!w)
        return;
    if (w->owns_table)
        traj_impact_table_free(w->impact_table);
    traj_release_free(w->release);
    free(w->seg);
    free(w->col);
    free(w);
}
