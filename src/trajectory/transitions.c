/* transitions.c - the changes of state of a trajectory, below the flight,
 * the contact and the state machine that all use them: an event recorded,
 * the end (stopped, exited, step limit), a launch (into flight, or on along a
 * segment), and an impact (bounce.c's law, the stopping rule of v_stop after
 * an impact, the soft landing into contact), recorded when asked to. */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void traj_event(traj_run *r, rf_traj_event_kind kind, int flying, double ax, double ay)
{
    rf_traj_result *res = r->res;
    if (!res->events)
        return;
    if (!rf_grow((void **)&res->events, res->n_events, &res->events_cap, sizeof *res->events)) {
        r->nomem = 1, r->phase = TRAJ_DONE; /* rf_traj_simulate reports it */
        return;
    }
    res->events[res->n_events++] = (rf_traj_event){kind, flying, r->t, r->x, r->y, r->vx, r->vy, r->omega, ax, ay, {0}};
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
    if (res->impacts && !rf_grow((void **)&res->impacts, res->n_impacts, &res->impacts_cap, sizeof *res->impacts))
        r->nomem = 1, r->phase = TRAJ_DONE; /* rf_traj_simulate reports it */
    else if (res->impacts)
        res->impacts[res->n_impacts] = (rf_traj_impact){r->t, r->x, r->y, k, vx_in, vy_in, r->vx, r->vy, r->omega,
                                                        {0}, {0}};
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

