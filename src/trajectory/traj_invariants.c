/* traj_invariants.c - what every recorded trajectory must satisfy, whatever
 * the input: the block is never inside the ground, and its mechanical energy
 * (kinetic + rotational + potential) never rises from one event to the next
 * beyond round-off.  Used by the tests and the fuzzer.
 *
 * The ground is rebuilt from the spec's points (not from the engine's
 * prepared segments), so an error in the engine's geometry cannot hide here.
 * The motion between two events is a parabola (flight) or a straight stretch
 * on a segment (contact).  A parabola minus a linear ground is concave in x,
 * so its minimum over each segment's x-range lies at an end of that range:
 * checking the flight's end points and every vertex it passes over is
 * exact, not a sampling.  A flight passing over a vertical step must clear
 * the step's top; an event may lie anywhere on a step's face. */
#include "trajectory/traj_internal.h"

#include <math.h>

#define TRAJ_INV_REL 1e-9 /* relative tolerance: round-off accumulated over many events */

/* First point index i with px[i] >= x (n if none). */
static size_t lower_index(const rf_traj_spec *s, double x)
{
    size_t lo = 0, hi = s->n_points;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (s->px[mid] < x)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Lowest and highest point of the column of points at x = px[i]; *end: index after it. */
static void column_at(const rf_traj_spec *s, size_t i, double *lo, double *hi, size_t *end)
{
    double x = s->px[i];
    *lo = *hi = s->py[i];
    for (*end = i + 1; *end < s->n_points && s->px[*end] == x; (*end)++)
        *lo = fmin(*lo, s->py[*end]), *hi = fmax(*hi, s->py[*end]);
}

/* Signed distance of (x, y) from the line of segment i (positive: out of the ground). */
static double above_segment(const rf_traj_spec *s, size_t i, double x, double y)
{
    double dx = s->px[i + 1] - s->px[i], dy = s->py[i + 1] - s->py[i];
    return (dx * (y - s->py[i]) - dy * (x - s->px[i])) / hypot(dx, dy);
}

/* Depth of (x, y) inside the ground (<= tol: not inside; a point on a step's face is not
 * inside); 0 outside the profile's x-range. */
static double depth(const rf_traj_spec *s, double x, double y, double tol)
{
    size_t n = s->n_points;
    if (!(x >= s->px[0] - tol && x <= s->px[n - 1] + tol))
        return 0;
    double best = INFINITY; /* smallest depth over the readings of the ground near x */
    size_t i = lower_index(s, x - tol), end;
    for (; i < n && s->px[i] <= x + tol; i = end) { /* vertex columns within tol of x */
        double lo, hi;
        column_at(s, i, &lo, &hi, &end);
        best = fmin(best, lo - y);
    }
    size_t j = lower_index(s, x);
    for (size_t k = j > 0 ? j - 1 : 0; k <= j && k + 1 < n; k++) /* segments covering x */
        if (s->px[k] <= x && x <= s->px[k + 1] && s->px[k + 1] > s->px[k])
            best = fmin(best, -above_segment(s, k, x, y));
    return isfinite(best) ? best : 0;
}

static double tolerance(double x, double y) { return TRAJ_INV_REL * (1 + fabs(x) + fabs(y)); }

static rf_status check_point(const rf_traj_spec *s, size_t k, double x, double y, const char *what, rf_error *err)
{
    double tol = tolerance(x, y), d = depth(s, x, y, tol);
    if (!isfinite(x) || !isfinite(y) || d > tol)
        return rf_fail(err, RF_EINVAL, "event %zu: %s (%.17g, %.17g) lies %.3g m inside the ground", k, what, x, y,
                       d);
    return RF_OK;
}

/* The flight from event a to event b (same parabola) against every vertex it passes over. */
static rf_status check_flight(const rf_traj_spec *s, const rf_traj_event *a, const rf_traj_event *b)
{
    if (a->vx == 0)
        return RF_OK; /* vertical: y(t) is concave, its ends are checked */
    /* a vertex within round-off of an end (a flight starting at a step's face) is not passed over */
    double x0 = fmin(a->x, b->x), x1 = fmax(a->x, b->x), t0 = tolerance(x0, 0), t1 = tolerance(x1, 0);
    for (size_t i = lower_index(s, x0 + t0); i < s->n_points && s->px[i] < x1 - t1; i++) {
        if (!(s->px[i] > x0 + t0))
            continue;
        double t = (s->px[i] - a->x) / a->vx, y = a->y + a->vy * t - 0.5 * s->gravity * t * t;
        double tol = TRAJ_INV_REL * (1 + fabs(s->px[i]) + fabs(a->y) + fabs(a->vy * t) + s->gravity * t * t);
        double lo, hi;
        size_t end;
        column_at(s, i, &lo, &hi, &end);
        if (y < hi - tol)
            return RF_EINVAL;
    }
    return RF_OK;
}

/* Mechanical energy per unit mass [J/kg]; *size: the magnitude of its terms (for round-off). */
static double energy(const rf_traj_spec *s, const rf_traj_event *e, double *size)
{
    double i_m = s->sphere ? 0.4 * s->radius * s->radius : 0; /* I/m of a solid sphere */
    double kin = 0.5 * (e->vx * e->vx + e->vy * e->vy) + 0.5 * i_m * e->omega * e->omega;
    *size = kin + s->gravity * fabs(e->y);
    return kin + s->gravity * e->y;
}

rf_status traj_check_invariants(const rf_traj_spec *s, const rf_traj_result *res, rf_error *err)
{
    const rf_traj_event *ev = res->events;
    for (size_t k = 0; ev && k < res->n_events; k++) {
        rf_status st = check_point(s, k, ev[k].x, ev[k].y, "the block at", err);
        if (st != RF_OK)
            return st;
        if (k == 0)
            continue;
        if (ev[k - 1].flying && check_flight(s, &ev[k - 1], &ev[k]) != RF_OK)
            return rf_fail(err, RF_EINVAL, "events %zu-%zu: the flight from (%.17g, %.17g) to (%.17g, %.17g) passes "
                           "through the ground", k - 1, k, ev[k - 1].x, ev[k - 1].y, ev[k].x, ev[k].y);
        double s0, s1, e0 = energy(s, &ev[k - 1], &s0), e1 = energy(s, &ev[k], &s1);
        /* round-off of the terms and of the position (as in the ground check) */
        double tol = TRAJ_INV_REL * fmax(s0, s1) + s->gravity * tolerance(ev[k].x, ev[k].y);
        if (!(e1 <= e0 + tol))
            return rf_fail(err, RF_EINVAL, "events %zu-%zu: mechanical energy rises from %.17g to %.17g J/kg", k - 1,
                           k, e0, e1);
    }
    if (res->state == RF_TRAJ_STOPPED)
        return check_point(s, res->n_events, res->x_end, res->y_end, "the rest point", err);
    return RF_OK;
}
