/* block_traj_profile.c - a rigid block on a 2D profile (docs/block-shape.md
 * "Wiring"): the profile's x-y is the block's x-z, the ground the profile
 * extruded along y (rf_block_ground_profile), the motion kept in the plane
 * (traj_block_planar after every step: 3 degrees of freedom).  Records as
 * the point and sphere engines do: impacts, events, collector and barrier
 * crossings, rest, exit, the time limit.  The block's point in the records
 * (x, y of events, impacts, the end) is its lowest point, as the sphere's
 * simulated point is its contact point; velocities are the centre's, omega
 * the spin about y (positive rolls forward to +x). */
#include "trajectory/block_traj.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    block_run b;
    const rf_traj_world *w;
    const rf_traj_spec *s;
    rf_traj_result *res;
    rf_block_profile prof;
    int nomem;
} prof_run;

static double omega_y(const rf_block_state *st)
{
    double w[3];
    traj_block_omega_space(st, w);
    return w[1];
}

static void event(void *eng, rf_traj_event_kind kind, int flying)
{
    prof_run *r = eng;
    rf_traj_result *res = r->res;
    r->b.next_event = r->b.t + BLOCK_TRAJ_EVENT_EVERY;
    if (!res->events)
        return;
    if (!rf_grow((void **)&res->events, res->n_events, &res->events_cap, sizeof *res->events)) {
        r->nomem = r->b.done = 1;
        return;
    }
    const rf_block_state *st = &r->b.st;
    double lp[3];
    block_run_lowest(&r->b, st, lp);
    rf_traj_event *e = &res->events[res->n_events++];
    *e = (rf_traj_event){kind, flying, r->b.t, lp[0], lp[2], st->v[0], st->v[2], omega_y(st), 0,
                         flying ? -r->s->gravity : 0, {st->q[0], st->q[1], st->q[2], st->q[3]}};
}

static void finish(void *eng, rf_traj_state state, rf_traj_event_kind kind)
{
    prof_run *r = eng;
    double lp[3];
    block_run_lowest(&r->b, &r->b.st, lp);
    r->res->state = state;
    r->res->t_end = r->b.t, r->res->x_end = lp[0], r->res->y_end = lp[2], r->res->runout_x = lp[0];
    event(r, kind, 0);
    r->b.done = 1;
}

static void record_impact(void *eng, size_t seg)
{
    prof_run *r = eng;
    rf_traj_result *res = r->res;
    if (res->impacts && !rf_grow((void **)&res->impacts, res->n_impacts, &res->impacts_cap, sizeof *res->impacts)) {
        r->nomem = r->b.done = 1;
        return;
    }
    if (res->impacts) {
        const rf_block_state *a = &r->b.prev, *e = &r->b.st;
        double lp[3], rot[3];
        block_run_lowest(&r->b, e, lp);
        block_run_energy(&r->b, e, rot);
        res->impacts[res->n_impacts] = (rf_traj_impact){r->b.t, lp[0], lp[2], seg, a->v[0], a->v[2], e->v[0], e->v[2],
                                                        omega_y(e), {e->q[0], e->q[1], e->q[2], e->q[3]},
                                                        {rot[0], rot[1], rot[2]}};
    }
    res->n_impacts++;
}

/* Collector c crossed by the centre during the last step, at the fraction f of it. */
static void crossing(prof_run *r, size_t c, double f)
{
    rf_block_state m;
    block_run_state_at(&r->b, f, &m);
    const traj_collector_geo *geo = &r->w->col[c];
    const rf_traj_collector *col = &r->s->collectors[c];
    rf_traj_crossing *cr = &r->res->crossings[c];
    double lp[3], rot[3];
    block_run_lowest(&r->b, &m, lp);
    size_t k;
    double gl = traj_ground_y(r->w, lp[0], &k);
    int contact = r->b.info.n_contacts > 0;
    cr->reached = 1;
    cr->t = r->b.t - (1 - f) * r->b.dt;
    cr->height_lowest = contact || !(lp[2] > gl) ? 0 : lp[2] - gl;
    cr->height_centre = m.x[2] - geo->ground_y;
    const traj_segment *g = k != TRAJ_NONE ? &r->w->seg[k] : &r->w->seg[geo->segment];
    cr->normal_height = contact ? 0 : fmax(0, g->nx * (lp[0] - g->ax) + g->ny * (lp[2] - g->ay));
    cr->speed = hypot(m.v[0], m.v[2]);
    cr->translational_energy = 0.5 * r->b.shape.mass * cr->speed * cr->speed;
    cr->total_energy = block_run_energy(&r->b, &m, rot);
    cr->rotational_energy = cr->total_energy - cr->translational_energy;
    cr->x = geo->x, cr->y = lp[2], cr->along = 0, cr->energy_after = cr->total_energy;
    if (col->capacity > 0 && (col->height <= 0 || cr->height_lowest <= col->height) &&
        cr->total_energy <= col->capacity) { /* held by the barrier: at rest there */
        cr->stopped_by_barrier = 1;
        r->b.st = m;
        memset(r->b.st.v, 0, sizeof r->b.st.v), memset(r->b.st.w, 0, sizeof r->b.st.w);
        r->b.t = cr->t;
        finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
    }
}

/* After a step: the collectors the centre crossed (in flight x is linear in
 * time, so the fraction of x is the fraction of the step). */
static void crossings(void *eng)
{
    prof_run *r = eng;
    double x0 = r->b.prev.x[0], x1 = r->b.st.x[0];
    for (size_t c = 0; c < r->w->ncol && !r->b.done; c++) {
        double xc = r->w->col[c].x;
        if (!r->res->crossings[c].reached && x0 != x1 && (xc - x0) * (xc - x1) <= 0 && xc != x0)
            crossing(r, c, (xc - x0) / (x1 - x0));
    }
}

/* The ground adapter: the segment under the lowest point and its material. */
static const rf_traj_material *locate(void *eng, const double p[3], size_t *seg)
{
    prof_run *r = eng;
    traj_ground_y(r->w, p[0], seg);
    return *seg == TRAJ_NONE ? NULL : &r->s->materials[r->w->seg[*seg].material];
}

static const block_engine profile_engine = {locate, crossings, record_impact, event, finish};

static rf_status start(prof_run *r, uint64_t seed, uint64_t sample, rf_error *err)
{
    const rf_traj_spec *s = r->s;
    double vx, vy, w[3] = {0, s->omega0, 0};
    if (s->block_spin_given)
        memcpy(w, s->block_spin0, sizeof w);
    rf_status st = block_run_init(&r->b, s, seed, sample, 1, w, err);
    if (st != RF_OK)
        return st;
    r->prof = (rf_block_profile){s->n_points, s->px, s->py};
    r->b.bw.ground = rf_block_ground_profile, r->b.bw.ground_ctx = &r->prof;
    r->b.bw.ground_bound = traj_block_profile_bound;
    r->b.n_steps = &r->res->n_steps, r->b.rebound_height = &r->res->rebound_height;
    traj_release_velocity(s, &vx, &vy);
    const double p[3] = {s->x0, 0, s->y0};
    if (!traj_block_place(&r->b.shape, rf_block_ground_profile, &r->prof, p, &r->b.st))
        return rf_fail(err, RF_EINVAL, "sample %llu: the release x = %g m lies outside the profile",
                       (unsigned long long)sample, s->x0);
    r->b.st.v[0] = vx, r->b.st.v[1] = 0, r->b.st.v[2] = vy;
    event(r, RF_EV_RELEASE, 1);
    return RF_OK;
}

rf_status traj_block_simulate_observed(const rf_traj_world *w, const rf_traj_spec *s, uint64_t seed,
                                       uint64_t sample, rf_traj_result *res, traj_block_observer obs, void *ctx,
                                       rf_error *err)
{
    prof_run r;
    memset(&r, 0, sizeof r);
    r.w = w, r.s = s, r.res = res;
    res->state = RF_TRAJ_STOPPED;
    res->n_impacts = res->n_steps = res->n_events = 0;
    res->rebound_height = 0;
    if (w->ncol)
        memset(res->crossings, 0, w->ncol * sizeof *res->crossings);
    rf_status st = start(&r, seed, sample, err);
    r.b.obs = obs, r.b.obs_ctx = ctx;
    if (st == RF_OK)
        block_run_loop(&r.b, &profile_engine, &r);
    rf_block_shape_free(&r.b.shape);
    if (st == RF_OK && r.nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory recording trajectory %llu (%zu events, %zu impacts)",
                       (unsigned long long)sample, res->n_events, res->n_impacts);
    if (st == RF_OK && !(isfinite(res->x_end) && isfinite(res->y_end)))
        return rf_fail(err, RF_EINVAL, "sample %llu: the end point (%g, %g) m is not finite",
                       (unsigned long long)sample, res->x_end, res->y_end);
    return st;
}

rf_status traj_block_simulate(const rf_traj_world *w, const rf_traj_spec *s, uint64_t seed, uint64_t sample,
                              rf_traj_result *res, rf_error *err)
{
    return traj_block_simulate_observed(w, s, seed, sample, res, NULL, NULL, err);
}
