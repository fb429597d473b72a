/* block_traj_terrain.c - a rigid block on the terrain (docs/block-shape.md
 * "Wiring"): 6 degrees of freedom against the bilinear DEM surface
 * (rf_terrain_height as the ground callback), the material of the cell under
 * the block's lowest point.  Every step is emitted as a terrain piece
 * (terrain_emit: barriers, hazard rasters) of the lowest point moving with
 * the centre's velocity, so barrier crossings and raster heights are those
 * of the lowest point; a crossing's centre height is the lowest point's plus
 * the centre's height above it.  Records as the sphere engine: impacts,
 * events, rest, exit, the time limit; points are the lowest point (the
 * runout: the centre's horizontal travel),
 * velocities the centre's, omega the space angular velocity. */
#include "trajectory/block_traj.h"
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    block_run b;
    terrain_run r;        /* what terrain_emit and terrain_event use: p the lowest point, v the centre's */
    double c0[2];         /* the centre's horizontal position after placement [m]: the runout's origin */
} ter_run;

/* Mirror the block into the terrain run's state (lowest point, centre velocity, space spin). */
static void sync(ter_run *q)
{
    block_run_lowest(&q->b, &q->b.st, q->r.p);
    memcpy(q->r.v, q->b.st.v, sizeof q->r.v);
    traj_block_omega_space(&q->b.st, q->r.omega);
    q->r.t = q->b.t;
}

static void event(void *eng, rf_traj_event_kind kind, int flying)
{
    ter_run *q = eng;
    sync(q);
    q->b.next_event = q->b.t + BLOCK_TRAJ_EVENT_EVERY;
    size_t n = q->r.res->n_events;
    terrain_event(&q->r, kind, flying);
    if (q->r.res->events && q->r.res->n_events > n)
        memcpy(q->r.res->events[n].q, q->b.st.q, sizeof q->b.st.q);
    if (q->r.nomem)
        q->b.done = 1;
}

static void finish(void *eng, rf_traj_state state, rf_traj_event_kind kind)
{
    ter_run *q = eng;
    q->r.res->state = state;
    event(q, kind, 0);
    q->b.done = 1;
}

static void record_impact(void *eng, size_t material)
{
    ter_run *q = eng;
    rf_terrain_result *res = q->r.res;
    if (res->impacts && !rf_grow((void **)&res->impacts, res->n_impacts, &res->impacts_cap, sizeof *res->impacts)) {
        q->r.nomem = q->b.done = 1;
        return;
    }
    if (res->impacts) {
        rf_terrain_impact *m = &res->impacts[res->n_impacts];
        sync(q);
        m->t = q->b.t, m->x = q->r.p[0], m->y = q->r.p[1], m->z = q->r.p[2];
        memcpy(m->v_in, q->b.prev.v, sizeof m->v_in), memcpy(m->v_out, q->b.st.v, sizeof m->v_out);
        memcpy(m->omega_out, q->r.omega, sizeof m->omega_out);
        m->material = material;
        memcpy(m->q, q->b.st.q, sizeof m->q);
        block_run_energy(&q->b, &q->b.st, m->rot_energy);
    }
    res->n_impacts++;
}

/* The last step as a piece of the lowest point (from the state before it). */
static void emit(void *eng)
{
    ter_run *q = eng;
    const rf_block_state *a = &q->b.prev, *e = &q->b.st;
    double h = q->b.dt, lp[3], rot[3];
    terrain_piece pc = {q->b.t - h, h, {0}, {a->v[0], a->v[1], a->v[2]}, {0}, 0, q->b.info.n_contacts > 0};
    block_run_lowest(&q->b, a, lp);
    /* On the map the piece is the centre's path, at the lowest point's height.  The lowest point itself
     * jumps from vertex to vertex as the block turns: pieces of it moving with the centre's velocity left
     * gaps, and a barrier line in a gap was never crossed (a tumbling box crossed a line across the whole
     * DEM in 1 run of 13 that passed it).  The centre's pieces chain exactly (midpoint rule:
     * x_E = x_A + h (v_A + v_E) / 2 = p + v h + a h^2 / 2). */
    pc.p[0] = a->x[0], pc.p[1] = a->x[1], pc.p[2] = lp[2];
    for (int k = 0; k < 3; k++)
        pc.a[k] = pc.on_ground ? (e->v[k] - a->v[k]) / h : k == 2 ? -q->r.g : 0;
    double ke = block_run_energy(&q->b, a, rot);
    pc.e_rot = ke - 0.5 * q->b.shape.mass * (a->v[0] * a->v[0] + a->v[1] * a->v[1] + a->v[2] * a->v[2]);
    unsigned char before[64] = {0};
    size_t nc = q->r.w->ncol < 64 ? q->r.w->ncol : 64;
    for (size_t c = 0; c < nc; c++)
        before[c] = (unsigned char)q->r.res->crossings[c].reached;
    double cut, scale;
    terrain_piece_outcome o = terrain_emit(&q->r, &pc, &cut, &scale);
    for (size_t c = 0; c < nc; c++) /* the centre's height above the ground under it, at the crossing */
        if (!before[c] && q->r.res->crossings[c].reached) {
            double zg;
            rf_block_state m;
            block_run_state_at(&q->b, (q->r.res->crossings[c].t - pc.t) / h, &m);
            if (rf_terrain_height(q->r.dem, m.x[0], m.x[1], &zg, NULL))
                q->r.res->crossings[c].height_centre = m.x[2] - zg;
        }
    if (o == TERRAIN_PIECE_STOPPED) {
        q->b.t = q->b.t - h + cut;
        memset(q->b.st.v, 0, sizeof q->b.st.v), memset(q->b.st.w, 0, sizeof q->b.st.w);
        finish(q, RF_TRAJ_STOPPED, RF_EV_REST);
    } else if (o == TERRAIN_PIECE_SLOWED) {
        for (int k = 0; k < 3; k++)
            q->b.st.v[k] *= scale, q->b.st.w[k] *= scale;
        event(q, RF_EV_BARRIER, q->b.info.n_contacts == 0);
    }
}

/* The ground adapter: the DEM cell under the lowest point and its material. */
static const rf_traj_material *locate(void *eng, const double p[3], size_t *mat)
{
    ter_run *q = eng;
    double z, u, v;
    size_t ci, cj;
    if (!rf_terrain_height(q->r.dem, p[0], p[1], &z, NULL) || !terrain_cell_of(q->r.dem, p[0], p[1], &ci, &cj, &u, &v))
        return NULL;
    *mat = terrain_material_of(q->r.dem, ci, cj);
    return &q->r.s->materials[*mat];
}

static const block_engine terrain_engine = {locate, emit, record_impact, event, finish};

static rf_status start(ter_run *q, const double start[3], rf_error *err)
{
    const rf_traj_spec *s = q->r.s;
    double w[3], zg, n[3];
    memcpy(w, s->block_spin_given ? s->block_spin0 : s->omega0_xyz, sizeof w);
    rf_status st = block_run_init(&q->b, s, q->r.seed, q->r.sample, 0, w, err);
    if (st != RF_OK)
        return st;
    q->b.bw.ground = traj_block_terrain_ground, q->b.bw.ground_ctx = (void *)q->r.dem;
    q->b.bw.ground_bound = traj_block_terrain_bound;
    q->b.n_steps = &q->r.res->n_steps, q->b.rebound_height = &q->r.res->rebound_height;
    if (!rf_terrain_height(q->r.dem, start[0], start[1], &zg, n))
        return rf_fail(err, RF_EINVAL, "sample %llu: the release point (%g, %g) m lies outside the DEM or on a "
                       "no-data cell", (unsigned long long)q->r.sample, start[0], start[1]);
    double p[3] = {start[0], start[1], isnan(start[2]) ? zg + s->height0 : fmax(start[2], zg)};
    if (!traj_block_place(&q->b.shape, traj_block_terrain_ground, (void *)q->r.dem, p, &q->b.st))
        return rf_fail(err, RF_EINVAL, "sample %llu: no ground under the release point",
                       (unsigned long long)q->r.sample);
    if (!s->release_by_speed)
        q->b.st.v[0] = s->vx0, q->b.st.v[1] = s->vy0, q->b.st.v[2] = s->vz0;
    else {
        double hs = s->speed0 * cos(s->dip0);
        q->b.st.v[0] = hs * sin(s->azimuth0), q->b.st.v[1] = hs * cos(s->azimuth0);
        q->b.st.v[2] = -s->speed0 * sin(s->dip0);
    }
    memcpy(q->r.res->start, p, sizeof p);
    q->c0[0] = q->b.st.x[0], q->c0[1] = q->b.st.x[1];
    event(q, RF_EV_RELEASE, 1);
    return RF_OK;
}

rf_status terrain_block_simulate(const rf_terrain_world *w, const rf_traj_spec *s, uint64_t seed, uint64_t sample,
                                 const double start_p[3], struct rf_terrain_hazard *hazard, rf_terrain_result *res,
                                 traj_block_observer obs, void *ctx, rf_error *err)
{
    ter_run q;
    memset(&q, 0, sizeof q);
    terrain_run *r = &q.r;
    r->w = w, r->dem = w->dem, r->s = s, r->res = res, r->hazard = hazard, r->seed = seed, r->sample = sample;
    r->g = s->gravity;
    res->state = RF_TRAJ_STOPPED;
    res->n_impacts = res->n_steps = res->n_events = 0;
    res->rebound_height = 0;
    if (w->ncol)
        memset(res->crossings, 0, w->ncol * sizeof *res->crossings);
    rf_status st = start(&q, start_p, err);
    r->mass = q.b.shape.mass; /* the rasters' energies; radius 0: the piece is the lowest point */
    q.b.obs = obs, q.b.obs_ctx = ctx;
    if (st == RF_OK && hazard)
        terrain_hazard_begin(hazard);
    if (st == RF_OK)
        block_run_loop(&q.b, &terrain_engine, &q);
    if (st == RF_OK)
        sync(&q);
    rf_block_shape_free(&q.b.shape);
    if (st != RF_OK)
        return st;
    memcpy(res->end, r->p, sizeof res->end);
    res->t_end = q.b.t;
    /* The runout is the centre's horizontal travel: a block at rest on a face has no single lowest point
     * (its vertices tie, and round-off picks any of them), so the lowest point's travel of a box that never
     * moved can be an edge's length. */
    res->runout = hypot(q.b.st.x[0] - q.c0[0], q.b.st.x[1] - q.c0[1]);
    res->reach_angle = res->runout > 0 ? atan((res->start[2] - res->end[2]) / res->runout) : NAN;
    if (hazard)
        terrain_hazard_end(hazard, res->state == RF_TRAJ_STOPPED, res->end);
    if (r->nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory recording trajectory %llu (%zu events, %zu impacts)",
                       (unsigned long long)sample, res->n_events, res->n_impacts);
    if (!isfinite(res->end[0]) || !isfinite(res->end[1]) || !isfinite(res->end[2]))
        return rf_fail(err, RF_EINVAL, "sample %llu: the end point is not finite", (unsigned long long)sample);
    return RF_OK;
}
