/* simulate.c - one trajectory: the state machine that alternates flights
 * (flight.c) and contact stretches (contact.c), handles impacts (bounce.c),
 * the stopping rules (speed below v_stop after an impact, rest in contact,
 * a barrier), leaving the profile (exited) and the step limit, and records
 * the impacts and events when asked to. */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *rf_traj_state_name(rf_traj_state s)
{
    switch (s) {
    case RF_TRAJ_STOPPED: return "stopped";
    case RF_TRAJ_EXITED: return "exited";
    case RF_TRAJ_STEP_LIMIT: return "step_limit";
    }
    return "?";
}

/* Grow *p (n used, *cap allocated) to hold one more element; 0 if out of memory. */
static int grow(void **p, size_t n, size_t *cap, size_t elem)
{
    if (n < *cap)
        return 1;
    size_t c = *cap ? 2 * *cap : 16;
    void *q = realloc(*p, c * elem);
    if (!q)
        return 0;
    *p = q;
    *cap = c;
    return 1;
}

void traj_event(traj_run *r, rf_traj_event_kind kind, int flying, double ax, double ay)
{
    rf_traj_result *res = r->res;
    if (!res->events || !grow((void **)&res->events, res->n_events, &res->events_cap, sizeof *res->events))
        return;
    res->events[res->n_events++] = (rf_traj_event){kind, flying, r->t, r->x, r->y, r->vx, r->vy, r->omega, ax, ay};
}

void traj_finish(traj_run *r, rf_traj_state state, rf_traj_event_kind kind)
{
    r->phase = TRAJ_DONE;
    r->res->state = state;
    r->res->t_end = r->t, r->res->x_end = r->x, r->res->y_end = r->y;
    r->res->runout_x = r->x;
    traj_event(r, kind, 0, 0, 0);
}

/* The block, on segment k at the current point, moves along it (no normal
 * speed beyond round-off) into the segment rather than off its end, on
 * ground that can carry it: it is in contact, not in flight. */
static int slides_on(const traj_run *r, size_t k)
{
    const traj_segment *g = &r->w->seg[k];
    double vn = g->nx * r->vx + g->ny * r->vy, vt = g->tx * r->vx + g->ty * r->vy;
    if (g->ny <= 0 || fabs(vn) > 1e-9 * hypot(r->vx, r->vy))
        return 0;
    double u = (g->tx * (r->x - g->ax) + g->ty * (r->y - g->ay)) / g->len;
    double d = vt != 0 ? vt : -r->g * g->ty; /* at rest: where gravity takes it */
    return d > 0 ? u < 1 - 1e-9 : d < 0 ? u > 1e-9 : 1;
}

/* A launch exactly along a segment the block is on is no flight: the
 * parabola leaves that segment's line downwards at once (into the ground),
 * and the flight, which never takes the t = 0 root of the segments it starts
 * on, would not find it again (a rebound off a wall at its foot, along the
 * floor, fell through the floor).  Such a launch continues in contact. */
void traj_launch(traj_run *r, size_t a, size_t b, rf_traj_event_kind kind)
{
    size_t on[2] = {a, b};
    for (int i = 0; i < 2; i++)
        if (on[i] != TRAJ_NONE && slides_on(r, on[i])) {
            const traj_segment *g = &r->w->seg[on[i]];
            r->phase = TRAJ_CONTACT;
            r->k = on[i];
            r->u = g->tx * r->vx + g->ty * r->vy;
            traj_event(r, kind, 0, 0, 0);
            return;
        }
    r->phase = TRAJ_FLY;
    r->on[0] = a, r->on[1] = b;
    r->from_impact = kind == RF_EV_IMPACT;
    traj_event(r, kind, 1, 0, -r->g);
}

static void record_impact(traj_run *r, size_t k, double vx_in, double vy_in)
{
    rf_traj_result *res = r->res;
    if (res->impacts && grow((void **)&res->impacts, res->n_impacts, &res->impacts_cap, sizeof *res->impacts))
        res->impacts[res->n_impacts] = (rf_traj_impact){r->t, r->x, r->y, k, vx_in, vy_in, r->vx, r->vy, r->omega};
    res->n_impacts++;
}

/* The other segment sharing the impact point when it is (nearly) a vertex. */
static size_t vertex_neighbour(const traj_run *r, size_t k)
{
    const traj_segment *g = &r->w->seg[k];
    double u = (g->tx * (r->x - g->ax) + g->ty * (r->y - g->ay)) / g->len;
    if (u < 1e-9 && k > 0)
        return k - 1;
    if (u > 1 - 1e-9 && k + 1 < r->w->nseg)
        return k + 1;
    return TRAJ_NONE;
}

void traj_impact(traj_run *r, size_t k)
{
    const traj_segment *g = &r->w->seg[k];
    double vx_in = r->vx, vy_in = r->vy;
    if (traj_bounce(r, k, &r->vx, &r->vy, &r->omega)) { /* soft landing */
        r->phase = TRAJ_CONTACT;
        r->k = k;
        r->u = g->tx * r->vx + g->ty * r->vy;
        return;
    }
    record_impact(r, k, vx_in, vy_in);
    if (hypot(r->vx, r->vy) < r->s->v_stop || (r->vx == 0 && r->vy == 0)) {
        r->vx = r->vy = r->omega = 0;
        traj_event(r, RF_EV_IMPACT, 0, 0, 0);
        traj_finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
        return;
    }
    double vn = g->nx * r->vx + g->ny * r->vy;
    /* (a rebound of no normal speed at all stays on the ground even with contact_speed = 0:
     * a flight grazing the segment it starts on would not find it again) */
    if ((vn < r->s->contact_speed || vn <= 1e-9 * hypot(r->vx, r->vy)) && g->ny > 0) {
        r->phase = TRAJ_CONTACT;
        r->k = k;
        r->u = g->tx * r->vx + g->ty * r->vy;
        traj_event(r, RF_EV_IMPACT, 0, 0, 0);
        return;
    }
    traj_launch(r, k, vertex_neighbour(r, k), RF_EV_IMPACT);
}

/* Largest height of the flight above its start over [0, tau]. */
static double flight_rise(const traj_run *r, double tau)
{
    double ta = r->vy / r->g;
    if (ta <= 0)
        return 0;
    if (ta <= tau)
        return r->vy * r->vy / (2 * r->g);
    return r->vy * tau - 0.5 * r->g * tau * tau;
}

static void advance(traj_run *r, double tau)
{
    r->t += tau;
    r->x += r->vx * tau;
    r->y += r->vy * tau - 0.5 * r->g * tau * tau;
    r->vy -= r->g * tau;
}

static void fly_step(traj_run *r)
{
    double tau;
    size_t k = traj_first_impact(r->w, r->x, r->y, r->vx, r->vy, r->g, r->on, &tau);
    if (r->from_impact) {
        double rise = flight_rise(r, tau);
        if (rise > r->res->rebound_height)
            r->res->rebound_height = rise;
    }
    if (traj_flight_collectors(r, tau))
        return;
    if (k == TRAJ_NONE) { /* report the state where it passes the end of the profile */
        const traj_segment *end = r->vx > 0 ? &r->w->seg[r->w->nseg - 1] : &r->w->seg[0];
        double xe = r->vx > 0 ? end->bx : end->ax, te = r->vx != 0 ? (xe - r->x) / r->vx : 0;
        if (te > 0)
            advance(r, te);
        traj_finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
        return;
    }
    advance(r, tau);
    const traj_segment *g = &r->w->seg[k]; /* put the point exactly on the segment's line */
    double s = g->nx * (r->x - g->ax) + g->ny * (r->y - g->ay);
    r->x -= s * g->nx, r->y -= s * g->ny;
    traj_impact(r, k);
}

/* Start: in flight, or in contact when the release point lies on the ground. */
static void release(traj_run *r)
{
    const rf_traj_spec *s = r->s;
    r->t = 0, r->x = s->x0, r->y = s->y0, r->vx = s->vx0, r->vy = s->vy0, r->omega = s->omega0;
    size_t k;
    double gy = traj_ground_y(r->w, s->x0, &k);
    r->on[0] = r->on[1] = TRAJ_NONE;
    r->from_impact = 0;
    if (k != TRAJ_NONE && fabs(s->y0 - gy) <= traj_tol(1e-9, s->x0, gy)) {
        const traj_segment *g = &r->w->seg[k];
        r->y = gy;
        r->phase = TRAJ_CONTACT;
        r->k = k;
        r->u = g->tx * s->vx0 + g->ty * s->vy0;
        double vn = g->nx * s->vx0 + g->ny * s->vy0;
        traj_event(r, RF_EV_RELEASE, 0, 0, 0);
        if (vn > r->s->contact_speed) /* thrown off the ground */
            traj_launch(r, k, TRAJ_NONE, RF_EV_LAUNCH);
        return;
    }
    r->phase = TRAJ_FLY;
    traj_event(r, RF_EV_RELEASE, 1, 0, -r->g);
}

rf_status rf_traj_simulate(const rf_traj_world *w, const rf_traj_spec *s, uint64_t seed, uint64_t sample,
                           rf_traj_result *res, rf_error *err)
{
    (void)err;
    traj_run r;
    memset(&r, 0, sizeof r);
    r.w = w, r.s = s, r.res = res, r.seed = seed, r.sample = sample;
    r.g = s->gravity;
    r.mass = s->sphere ? 4.0 / 3.0 * RF_PI * s->radius * s->radius * s->radius * s->density : s->mass;
    r.radius = s->sphere ? s->radius : 0;
    r.inertia = s->sphere ? 0.4 * r.mass * s->radius * s->radius : 0;
    res->state = RF_TRAJ_STOPPED;
    res->n_impacts = res->n_steps = res->n_events = 0;
    res->rebound_height = 0;
    if (w->ncol)
        memset(res->crossings, 0, w->ncol * sizeof *res->crossings);
    release(&r);
    while (r.phase != TRAJ_DONE) {
        if (res->n_steps++ >= s->max_steps) {
            traj_finish(&r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
            break;
        }
        if (r.phase == TRAJ_FLY)
            fly_step(&r);
        else
            traj_contact_step(&r);
    }
    return RF_OK;
}
