/* terrain_simulate.c - one 3D trajectory on the terrain: the state machine
 * of simulate.c and transitions.c in 3D.
 *   release: in flight, or in contact when the start lies on the ground and
 *            the velocity does not throw it off (normal speed <= contact_speed);
 *   fly:     (terrain_fly.c) exact first impact (terrain_flight.c), the flight emitted as a
 *            piece (barriers, hazard rasters, rebound height); leaving the DEM
 *            or entering a no-data cell ends it (exited);
 *   impact:  the law (terrain_bounce.c): a soft landing continues in contact;
 *            a rebound slower than v_stop stops; one with normal speed below
 *            contact_speed (or none at all) continues in contact; else a flight;
 *   contact: terrain_contact.c, until it launches, stops or exits;
 * and max_steps events end it (step_limit).  A barrier that holds the block
 * stops it at the crossing; one it breaks through scales its velocity and
 * spin there (an RF_EV_BARRIER event) and the motion goes on.  At the end:
 * runout = horizontal distance from the start, reach angle = atan(drop /
 * runout).  terrain_check_invariants checks what any recorded trajectory
 * must satisfy. */
#include "trajectory/terrain_internal.h"
#include "trajectory/block_traj.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void finish(terrain_run *r, rf_traj_state state, rf_traj_event_kind kind)
{
    r->phase = TERRAIN_DONE;
    r->res->state = state;
    terrain_event(r, kind, 0);
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The release velocity: (vx, vy, vz), or speed at azimuth (clockwise from
 * north) and dip (below the horizontal). */
static void release_velocity(const rf_traj_spec *s, double v[3])
{
    if (!s->release_by_speed) {
        v[0] = s->vx0, v[1] = s->vy0, v[2] = s->vz0;
        return;
    }
    double h = s->speed0 * cos(s->dip0);
    v[0] = h * sin(s->azimuth0), v[1] = h * cos(s->azimuth0), v[2] = -s->speed0 * sin(s->dip0);
}

static rf_status release(terrain_run *r, const double start[3], rf_error *err)
{
    const rf_traj_spec *s = r->s;
    double zg, n[3];
    if (!rf_terrain_height(r->dem, start[0], start[1], &zg, n))
        return rf_fail(err, RF_EINVAL, "sample %llu: the release point (%g, %g) m lies outside the DEM or on a "
                       "no-data cell", (unsigned long long)r->sample, start[0], start[1]);
    double z = isnan(start[2]) ? zg + s->height0 : start[2], tol = 1e-10 * (1 + fabs(zg));
    if (!(z >= zg - tol))
        return rf_fail(err, RF_EINVAL, "sample %llu: the release point (%g, %g, %g) m lies %g m below the ground",
                       (unsigned long long)r->sample, start[0], start[1], z, zg - z);
    r->t = 0, r->p[0] = start[0], r->p[1] = start[1], r->p[2] = z;
    release_velocity(s, r->v);
    memcpy(r->omega, s->omega0_xyz, sizeof r->omega);
    memcpy(r->res->start, r->p, sizeof r->p);
    r->from_impact = 0;
    if (z - zg <= tol && dot3(r->v, n) <= s->contact_speed) { /* on the ground, not thrown off */
        r->p[2] = zg;
        terrain_to_contact(r, n);
        terrain_event(r, RF_EV_RELEASE, 0);
        return RF_OK;
    }
    if (z - zg <= tol)
        r->p[2] = zg;
    r->phase = TERRAIN_FLY;
    terrain_event(r, RF_EV_RELEASE, 1);
    return RF_OK;
}

/* The law's needs that the world or the block must meet. */
static rf_status check_law(const rf_terrain_world *w, const rf_traj_spec *s, rf_error *err)
{
    if ((unsigned)s->law >= RF_BOUNCE_N_LAWS)
        return rf_fail(err, RF_EINVAL, "bounce.law: unknown law %d", (int)s->law);
    if ((s->law == RF_BOUNCE_RIGID_SPHERE || s->law == RF_BOUNCE_IMPACT_MODEL) && !(s->sphere && s->radius > 0))
        return rf_fail(err, RF_EINVAL, "bounce.law = %s: needs block.shape: sphere", rf_traj_bounce_law_names[s->law]);
    if (s->law == RF_BOUNCE_IMPACT_MODEL && !w->impact_table)
        return rf_fail(err, RF_EINVAL, "bounce.law = impact_model: the terrain world has no impact table");
    if (s->n_collectors != w->ncol)
        return rf_fail(err, RF_EINVAL, "terrain: %zu collectors in the spec but %zu barrier lines", s->n_collectors,
                       w->ncol);
    return RF_OK;
}

static void run_init(terrain_run *r, const rf_terrain_world *w, const rf_traj_spec *s, uint64_t seed,
                     uint64_t sample, rf_terrain_hazard *hazard, rf_terrain_result *res)
{
    memset(r, 0, sizeof *r);
    r->w = w, r->dem = w->dem, r->s = s, r->res = res, r->hazard = hazard;
    r->seed = seed, r->sample = sample;
    r->g = s->gravity;
    r->mass = traj_spec_mass(s);
    r->radius = s->sphere ? s->radius : 0;
    r->inertia = s->sphere ? 0.4 * r->mass * s->radius * s->radius : 0;
    res->state = RF_TRAJ_STOPPED;
    res->n_impacts = res->n_steps = res->n_events = 0;
    res->rebound_height = 0;
    if (w->ncol)
        memset(res->crossings, 0, w->ncol * sizeof *res->crossings);
}

/* End point, runout and reach angle. */
static void conclude(terrain_run *r)
{
    rf_terrain_result *res = r->res;
    memcpy(res->end, r->p, sizeof res->end);
    res->t_end = r->t;
    res->runout = hypot(res->end[0] - res->start[0], res->end[1] - res->start[1]);
    res->reach_angle = res->runout > 0 ? atan((res->start[2] - res->end[2]) / res->runout) : NAN;
}

rf_status terrain_simulate_hazard(const rf_terrain_world *w, const rf_traj_spec *s, uint64_t seed, uint64_t sample,
                                  const double start[3], rf_terrain_hazard *hazard, rf_terrain_result *res,
                                  rf_error *err)
{
    if (s->block_kind != RF_TRAJ_BLOCK_NONE) { /* a rigid block: the rigid-body dynamics (block_traj_terrain.c) */
        rf_status st = check_law(w, s, err);
        return st != RF_OK ? st : terrain_block_simulate(w, s, seed, sample, start, hazard, res, NULL, NULL, err);
    }
    terrain_run r;
    run_init(&r, w, s, seed, sample, hazard, res);
    rf_status st = check_law(w, s, err);
    if (st == RF_OK)
        st = release(&r, start, err);
    if (st != RF_OK)
        return st;
    if (hazard)
        terrain_hazard_begin(hazard);
    while (r.phase != TERRAIN_DONE) {
        if (res->n_steps++ >= s->max_steps) {
            finish(&r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
            break;
        }
        size_t ci, cj;
        if (r.phase == TERRAIN_FLY)
            terrain_fly(&r, &ci, &cj);
        else
            terrain_contact_run(&r);
    }
    conclude(&r);
    if (hazard)
        terrain_hazard_end(hazard, res->state == RF_TRAJ_STOPPED, res->end);
    if (r.nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory recording trajectory %llu (%zu events, %zu impacts)",
                       (unsigned long long)sample, res->n_events, res->n_impacts);
    if (!isfinite(res->end[0]) || !isfinite(res->end[1]) || !isfinite(res->end[2]))
        return rf_fail(err, RF_EINVAL, "sample %llu: the end point (%g, %g, %g) m is not finite: the inputs exceed "
                       "what the arithmetic holds", (unsigned long long)sample, res->end[0], res->end[1], res->end[2]);
    return RF_OK;
}

rf_status rf_terrain_simulate(const rf_terrain_world *w, const rf_traj_spec *values, uint64_t seed, uint64_t sample,
                              const double start[3], rf_terrain_result *res, rf_error *err)
{
    return terrain_simulate_hazard(w, values, seed, sample, start, NULL, res, err);
}
