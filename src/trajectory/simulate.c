/* simulate.c - one trajectory: the state machine that alternates flights
 * (flight.c) and contact stretches (contact.c), with the impacts, launches,
 * events and the end of transitions.c, leaving the profile (exited) and the
 * step limit. */
#include "trajectory/traj_internal.h"
#include "trajectory/block_traj.h"

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
    double vx, vy;
    traj_release_velocity(s, &vx, &vy);
    r->t = 0, r->x = s->x0, r->y = s->y0, r->vx = vx, r->vy = vy, r->omega = s->omega0;
    size_t k;
    double gy = traj_ground_y(r->w, s->x0, &k);
    r->on[0] = r->on[1] = TRAJ_NONE;
    r->from_impact = 0;
    if (k != TRAJ_NONE && fabs(s->y0 - gy) <= traj_tol(1e-9, s->x0, gy)) {
        const traj_segment *g = &r->w->seg[k];
        r->y = gy;
        r->phase = TRAJ_CONTACT;
        r->k = k;
        r->u = g->tx * vx + g->ty * vy;
        double vn = g->nx * vx + g->ny * vy;
        traj_event(r, RF_EV_RELEASE, 0, 0, 0);
        if (vn > r->s->contact_speed) /* thrown off the ground */
            traj_launch(r, k, TRAJ_NONE, RF_EV_LAUNCH);
        return;
    }
    r->phase = TRAJ_FLY;
    traj_event(r, RF_EV_RELEASE, 1, 0, -r->g);
}

/* The first non-finite result of the trajectory (its name and unit in *what), or 0 if all are finite. */
static int nonfinite_result(const rf_traj_result *res, size_t ncol, const char **what, double *v)
{
    const double q[4] = {res->x_end, res->y_end, res->runout_x, res->rebound_height};
    static const char *const qn[4] = {"x_end [m]", "y_end [m]", "runout_x [m]", "rebound_height [m]"};
    for (int k = 0; k < 4; k++)
        if (!isfinite(q[k]))
            return *what = qn[k], *v = q[k], 1;
    for (size_t c = 0; c < ncol; c++) {
        const rf_traj_crossing *x = &res->crossings[c];
        const double cq[3] = {x->speed, x->total_energy, x->height_lowest};
        static const char *const cn[3] = {"collector speed [m/s]", "collector total_energy [J]",
                                          "collector height_lowest [m]"};
        for (int k = 0; x->reached && k < 3; k++)
            if (!isfinite(cq[k]))
                return *what = cn[k], *v = cq[k], 1;
    }
    return 0;
}

/* A non-finite result is an error naming the inputs that produced it. */
static rf_status check_finite(const traj_run *r, rf_error *err)
{
    const char *what;
    double v;
    if (!nonfinite_result(r->res, r->w->ncol, &what, &v))
        return RF_OK;
    const rf_traj_spec *s = r->s;
    return rf_fail(err, RF_EINVAL, "sample %llu: the result %s = %g is not finite: the inputs exceed what the "
                   "arithmetic holds (gravity = %g m/s^2, block mass = %g kg, release (x, y) = (%g, %g) m, "
                   "(vx, vy) = (%g, %g) m/s, omega = %g rad/s)", (unsigned long long)r->sample, what, v, s->gravity,
                   r->mass, s->x0, s->y0, s->vx0, s->vy0, s->omega0);
}

rf_status rf_traj_simulate(const rf_traj_world *w, const rf_traj_spec *s, uint64_t seed, uint64_t sample,
                           rf_traj_result *res, rf_error *err)
{
    if (s->block_kind != RF_TRAJ_BLOCK_NONE) /* a rigid block: the rigid-body dynamics (block_traj_profile.c) */
        return traj_block_simulate(w, s, seed, sample, res, err);
    traj_run r;
    memset(&r, 0, sizeof r);
    r.w = w, r.s = s, r.res = res, r.seed = seed, r.sample = sample;
    r.g = s->gravity;
    r.mass = traj_spec_mass(s);
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
    if (r.nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory recording trajectory %llu (%zu events, %zu impacts)",
                       (unsigned long long)sample, res->n_events, res->n_impacts);
    return check_finite(&r, err);
}
