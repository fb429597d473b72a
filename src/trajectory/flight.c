/* flight.c - free flight as the exact parabola p(t) = p0 + v t - (0, g t^2/2):
 * the first impact is the smallest accepted root over all segments of the
 * signed distance s(t) = s0 + (n.v) t - g n_y t^2 / 2 (trajectory_refs.md
 * sec. 2.3), solved with the cancellation-free quadratic formula; and the
 * crossings of collector lines (x = const) inside a flight. */
#include "trajectory/traj_internal.h"

#include <math.h>

/* Smallest root tau > 0 of a tau^2 + b tau + c = 0 at which s decreases
 * (ds/dtau = 2 a tau + b < 0); INFINITY if none. */
static double first_approach_root(double a, double b, double c)
{
    if (a == 0) {
        if (b >= 0)
            return INFINITY;
        double t = -c / b;
        return t > 0 ? t : INFINITY;
    }
    double disc = b * b - 4 * a * c;
    if (disc < 0)
        return INFINITY;
    double q = -0.5 * (b + copysign(sqrt(disc), b));
    double r1 = q / a, r2 = q != 0 ? c / q : r1;
    double lo = fmin(r1, r2), hi = fmax(r1, r2);
    if (lo > 0 && 2 * a * lo + b < 0)
        return lo;
    if (hi > 0 && 2 * a * hi + b < 0)
        return hi;
    return INFINITY;
}

/* Flight time to segment g, or INFINITY.  `on`: the start point lies on g. */
static double segment_root(const traj_segment *g, double x, double y, double vx, double vy, double gr, int on)
{
    double a = -0.5 * gr * g->ny, b = g->nx * vx + g->ny * vy;
    double tau;
    if (on) {
        /* s0 = 0 exactly: the t = 0 root is the point just left, unless the
         * block moves into the segment (a concave corner: hit at once). */
        double speed = hypot(vx, vy);
        if (b < -1e-9 * speed)
            tau = 0;
        else if (a < 0 && b > 1e-9 * speed) /* |b| tiny: grazing along it, no new hit */
            tau = -b / a;
        else
            return INFINITY;
    } else {
        double c = g->nx * (x - g->ax) + g->ny * (y - g->ay);
        tau = first_approach_root(a, b, c);
        if (!isfinite(tau))
            return INFINITY;
    }
    double px = x + vx * tau, py = y + vy * tau - 0.5 * gr * tau * tau;
    double u = (g->tx * (px - g->ax) + g->ty * (py - g->ay)) / g->len;
    const double eps = 1e-12;
    return u >= -eps && u <= 1 + eps ? tau : INFINITY;
}

/* Segments are sorted by x (x non-decreasing) and x moves one way in a
 * flight, so the candidates are scanned from the current x in the direction
 * of motion, and the scan stops at the first segment lying beyond the best
 * hit so far (a later x is a later time).  Equal times go to the lower index. */
size_t traj_first_impact(const rf_traj_world *w, double x, double y, double vx, double vy, double g,
                         const size_t on[2], double *tau)
{
    double best = INFINITY, slack = traj_tol(1e-12, x, 0);
    size_t hit = TRAJ_NONE, n = w->nseg;
    if (vx == 0) {
        for (size_t i = 0; i < n; i++) {
            const traj_segment *s = &w->seg[i];
            if (x < s->xmin - slack || x > s->xmax + slack)
                continue;
            double t = segment_root(s, x, y, vx, vy, g, i == on[0] || i == on[1]);
            if (t < best)
                best = t, hit = i;
        }
        *tau = best;
        return hit;
    }
    size_t lo = 0, hi = n; /* first segment with xmax >= x - slack (vx > 0), last with xmin <= x + slack (vx < 0) */
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (vx > 0 ? w->seg[mid].xmax < x - slack : w->seg[mid].xmin <= x + slack)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (size_t k = 0; k < n; k++) {
        size_t i = vx > 0 ? lo + k : lo - 1 - k;
        if ((vx > 0 && i >= n) || (vx < 0 && k >= lo))
            break;
        const traj_segment *s = &w->seg[i];
        double xhit = x + vx * best;
        if (vx > 0 ? s->xmin > xhit + slack : s->xmax < xhit - slack)
            break;
        double t = segment_root(s, x, y, vx, vy, g, i == on[0] || i == on[1]);
        if (t < best || (t == best && t < INFINITY && i < hit))
            best = t, hit = i;
    }
    *tau = best;
    return hit;
}

size_t traj_next_crossing(const traj_run *r, double (*when)(const traj_run *r, size_t c, const void *ctx),
                          const void *ctx, double *tf)
{
    size_t first = TRAJ_NONE;
    *tf = INFINITY;
    for (size_t c = 0; c < r->w->ncol; c++) {
        if (r->res->crossings[c].reached)
            continue;
        double tc = when(r, c, ctx);
        if (tc < *tf)
            *tf = tc, first = c;
    }
    return first;
}

/* When the flight (straight in x) crosses collector c within [0, *tau_end]; INFINITY if not. */
static double flight_crossing(const traj_run *r, size_t c, const void *tau_end)
{
    double tc = (r->w->col[c].x - r->x) / r->vx;
    return tc >= 0 && tc <= *(const double *)tau_end ? tc : INFINITY;
}

int traj_flight_collectors(traj_run *r, double tau_end)
{
    if (r->vx == 0)
        return 0;
    int stopped = 0;
    /* Crossings in time order, so that a barrier stops the block at the first one. */
    for (;;) {
        double tf;
        size_t first = traj_next_crossing(r, flight_crossing, &tau_end, &tf);
        if (first == TRAJ_NONE)
            return 0;
        double y = r->y + r->vy * tf - 0.5 * r->g * tf * tf;
        traj_record_crossing(r, first, r->t + tf, r->w->col[first].x, y, r->vx, r->vy - r->g * tf, r->omega,
                             &stopped);
        if (stopped)
            return 1;
    }
}

void traj_record_crossing(traj_run *r, size_t c, double t, double x, double y, double vx, double vy,
                          double omega, int *stopped)
{
    const traj_collector_geo *geo = &r->w->col[c];
    const traj_segment *g = &r->w->seg[geo->segment];
    const rf_traj_collector *spec = &r->s->collectors[c];
    rf_traj_crossing *cr = &r->res->crossings[c];
    cr->reached = 1;
    cr->t = t;
    /* The simulated point is the block's lowest point; a sphere's centre is r
     * above it.  In contact the point is on the ground by definition: its
     * height is 0, not the rounding of y along the segment minus the ground. */
    int on_ground = r->phase == TRAJ_CONTACT;
    cr->height_lowest = on_ground ? 0 : y - geo->ground_y;
    cr->height_centre = cr->height_lowest + r->radius;
    cr->normal_height = on_ground ? 0 : g->nx * (x - g->ax) + g->ny * (y - g->ay);
    cr->speed = hypot(vx, vy);
    cr->translational_energy = 0.5 * r->mass * cr->speed * cr->speed;
    cr->rotational_energy = 0.5 * r->inertia * omega * omega;
    cr->total_energy = cr->translational_energy + cr->rotational_energy;
    *stopped = 0;
    if (spec->capacity > 0 && (spec->height <= 0 || cr->height_lowest <= spec->height) &&
        cr->total_energy <= spec->capacity) {
        cr->stopped_by_barrier = 1;
        *stopped = 1;
        r->t = t, r->x = x, r->y = y, r->vx = r->vy = r->omega = 0;
        traj_finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
    }
}
