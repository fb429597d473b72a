/* test_terrain_simulate.c - one 3D trajectory (terrain_simulate.c,
 * terrain_barrier.c) against closed forms and the 2D engine:
 *   a bounce series on an inclined plane of any aspect (constant law): each
 *   impact's time, point, normal and tangential velocity from the recurrence
 *   in the plane's frame;
 *   extruded-profile equivalence: 2D profiles of tests/test_trajectory.c
 *   extruded along y, released in the x-z plane, give the 2D engine's impacts
 *   (time, point, velocities, spin) to 1e-9 for constant, velocity_scaled,
 *   rigid_sphere and impact_model (the same table);
 *   a barrier crossed in flight: time, map point, distance along the line,
 *   heights and energy exact, and the capacity rule's cases (collector, held,
 *   broken through with E - C left, over the top);
 *   the end states (exited, step_limit, stopped), runout and reach angle,
 *   rebound height, release by speed/azimuth/dip and at a height above the
 *   ground, the refusals;
 *   roughness on a rough DEM never gains energy over whole trajectories.
 * Contact (terrain_contact.c) is another part: here its stub ends a contact
 * as stopped, so the cases stay in flight and bounce. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_terrain_util.h"
#include "test_traj_util.h"
#include "test_util.h"

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* On the plane z = z0 + sx x + sy y (slope 25 deg, aspect 130 deg) from 10 m
 * above: the first flight's closed form, then per bounce v_n' = R_n |v_n|,
 * v_t' = R_t v_t, the flight T = 2 v_n' / (g n_z) and v_in = v_out + g T. */
static void test_bounce_series_inclined_plane(void **state)
{
    (void)state;
    double beta = 25 * TT_DEG, asp = 130 * TT_DEG;
    tt_plane pl = {300, tan(beta) * sin(asp), tan(beta) * cos(asp), 500, 500};
    rf_terrain *t = tt_dem(201, 201, 0, 0, 5, 5, tt_plane_z, &pl);
    tt_world tw;
    tt_world_init(&tw, t);
    tt_spec ts;
    tt_spec_init(&ts, 0.7, 0.9);
    ts.spec.contact_speed = 0.5;
    ts.spec.vx0 = 2, ts.spec.vy0 = -1, ts.spec.vz0 = 3;
    double start[3] = {500, 500, 310}, nz = 1 / sqrt(1 + pl.sx * pl.sx + pl.sy * pl.sy);
    double n[3] = {-pl.sx * nz, -pl.sy * nz, nz}, gv[3] = {0, 0, -TT_G};
    tt_result r;
    tt_result_init(&r);
    tt_simulate(&tw, &ts, 0, start, &r);
    double B = 3 - pl.sx * 2 - pl.sy * (-1), T = (B + sqrt(B * B + 2 * TT_G * 10)) / TT_G;
    double p[3] = {500 + 2 * T, 500 - T, 0}, v[3] = {2, -1, 3 - TT_G * T}, time = T;
    p[2] = tt_plane_z(&pl, p[0], p[1]);
    size_t K = 0;
    for (;; K++) {
        if (K >= r.res.n_impacts)
            fail_msg("only %zu impacts", r.res.n_impacts);
        const rf_terrain_impact *m = &r.res.impacts[K];
        double vn = dot(v, n), vt[3], out[3];
        for (int q = 0; q < 3; q++)
            vt[q] = v[q] - vn * n[q], out[q] = 0.9 * vt[q] - 0.7 * vn * n[q];
        double sc = 1e-9 * (1 + sqrt(dot(v, v)));
        assert_close(m->t, time, 1e-9);
        assert_near(m->x, p[0], 1e-9 * 600);
        assert_near(m->y, p[1], 1e-9 * 600);
        assert_near(m->z, p[2], 1e-9 * 600);
        for (int q = 0; q < 3; q++) {
            assert_near(m->v_in[q], v[q], sc);
            assert_near(m->v_out[q], out[q], sc);
        }
        if (-0.7 * vn < 0.5)
            break; /* the rebound is slower than contact_speed: contact */
        T = 2 * (-0.7 * vn) / (TT_G * nz);
        for (int q = 0; q < 3; q++)
            p[q] += out[q] * T + 0.5 * gv[q] * T * T, v[q] = out[q] + gv[q] * T;
        time += T;
    }
    assert_int_equal(r.res.n_impacts, K + 1);
    assert_true(K >= 8);
    tt_result_free(&r);
    rf_terrain_free(t);
}

/* Height of the 2D profile at x (linear between vertices). */
static double profile_z(void *ctx, double x, double y)
{
    (void)y;
    const rf_traj_spec *s = ctx;
    for (size_t k = 0; k + 1 < s->n_points; k++)
        if (x <= s->px[k + 1] || k + 2 == s->n_points)
            return s->py[k] + (s->py[k + 1] - s->py[k]) * (x - s->px[k]) / (s->px[k + 1] - s->px[k]);
    return NAN;
}

/* The collectors the 3D block reached were reached by the 2D block with the
 * same numbers (x = X is the barrier line; 2D has no break-through). */
static void compare_crossings(const traj_case *c, const tt_result *r)
{
    for (size_t k = 0; k < c->spec.n_collectors; k++) {
        const rf_traj_crossing *a = &r->cross[k], *b = &c->cross[k];
        if (!a->reached)
            continue;
        assert_true(b->reached);
        assert_close(a->t, b->t, 1e-9);
        assert_near(a->height_lowest, b->height_lowest, 1e-9 * (1 + fabs(b->height_lowest)));
        assert_near(a->normal_height, b->normal_height, 1e-9 * (1 + fabs(b->height_lowest)));
        assert_close(a->speed, b->speed, 1e-9);
        assert_close(a->total_energy, b->total_energy, 1e-9);
        assert_int_equal(a->stopped_by_barrier, b->stopped_by_barrier);
    }
}

/* The 2D case `yaml` and the same profile extruded along y (node spacing dx,
 * nodes on the vertices), released at y = 0 (a cell line): the 3D impacts
 * equal the 2D ones until the 3D block goes into contact. */
static void extruded_case(const char *yaml, double dx, size_t min_impacts)
{
    traj_case c;
    traj_case_run(&c, yaml);
    rf_traj_spec *s = &c.spec;
    double x0 = s->px[0], len = s->px[s->n_points - 1] - x0;
    size_t nx = (size_t)llround(len / dx) + 1;
    for (size_t k = 0; k < s->n_points; k++) /* the nodes sit on the vertices */
        assert_true(fabs((s->px[k] - x0) / dx - round((s->px[k] - x0) / dx)) < 1e-12);
    rf_terrain *t = tt_dem(nx, 3, x0, -4, dx, 4, profile_z, s);
    tt_world tw;
    tt_world_init(&tw, t);
    traj_impact_table *table = NULL; /* impact_model: the same table as the 2D world's (same inputs) */
    rf_error err;
    if (s->law == RF_BOUNCE_IMPACT_MODEL && traj_impact_table_build(s, &table, &err) != RF_OK)
        fail_msg("impact table: %s", err.msg);
    tw.w.impact_table = table;
    tt_spec ts; /* the 2D spec, its release in the x-z plane */
    ts.spec = *s;
    ts.spec.vy0 = 0, ts.spec.vz0 = s->vy0;
    ts.spec.omega0_xyz[0] = 0, ts.spec.omega0_xyz[1] = s->omega0, ts.spec.omega0_xyz[2] = 0;
    for (size_t k = 0; k < s->n_collectors; k++) { /* a collector x = X: the barrier line across the DEM */
        double bx[2] = {s->collectors[k].x, s->collectors[k].x}, by[2] = {-4, 4};
        tt_world_barrier(&tw, &ts, 2, bx, by, s->collectors[k].capacity, s->collectors[k].height);
    }
    ts.spec.collectors = s->collectors;
    double start[3] = {s->x0, 0, s->y0};
    tt_result r;
    tt_result_init(&r);
    tt_simulate(&tw, &ts, 0, start, &r);
    compare_crossings(&c, &r);
    size_t n = r.res.n_impacts;
    if (n < min_impacts || c.res.n_impacts < n)
        fail_msg("3D %zu impacts, 2D %zu, expected at least %zu", n, c.res.n_impacts, min_impacts);
    for (size_t k = 0; k < n; k++) {
        const rf_terrain_impact *a = &r.res.impacts[k];
        const rf_traj_impact *b = &c.res.impacts[k];
        double sc = 1e-9 * (1 + fabs(b->vx_in) + fabs(b->vy_in));
        assert_close(a->t, b->t, 1e-9);
        assert_near(a->x, b->x, 1e-9 * (1 + fabs(b->x)));
        assert_true(a->y == 0);
        assert_near(a->z, b->y, 1e-9 * (1 + fabs(b->y)));
        assert_near(a->v_in[0], b->vx_in, sc);
        assert_near(a->v_in[2], b->vy_in, sc);
        assert_near(a->v_out[0], b->vx_out, sc);
        assert_near(a->v_out[2], b->vy_out, sc);
        assert_true(a->v_in[1] == 0 && a->v_out[1] == 0);
        assert_near(a->omega_out[1], b->omega_out, 1e-9 * (1 + fabs(b->omega_out)));
        assert_true(a->omega_out[0] == 0 && a->omega_out[2] == 0);
    }
    tt_result_free(&r);
    if (table)
        traj_impact_table_free(table);
    rf_terrain_free(t);
    traj_case_free(&c);
}

static void test_extruded_profiles(void **state)
{
    (void)state;
    /* test_trajectory.c's bounce series (constant) */
    extruded_case("profile: {points: [[-1, 0], [1000, 0]], material: m}\n"
                  "materials: {m: {R_n: 0.6, R_t: 0.9, friction_angle: 45}}\n"
                  "block: {shape: point, mass: 1}\n"
                  "release: {x: 0, y: 5, vx: 3, vy: 0}\n"
                  "bounce: {law: constant, contact_speed: 0.001}\n"
                  "stop: {v_stop: 0}\n", 1, 15);
    /* its convex break, released 0.5 m above the ledge (velocity_scaled) */
    extruded_case("profile: {points: [[0, 10], [10, 10], [20, 0], [100, 0]], material: m}\n"
                  "materials: {m: {R_n: 0.5, R_t: 0.8, friction_angle: 30}}\n"
                  "block: {shape: point, mass: 1}\n"
                  "release: {x: 5, y: 10.5, vx: 10, vy: 0}\n"
                  "bounce: {law: velocity_scaled, contact_speed: 0.01}\n"
                  "collectors: [{name: c, x: 15}, {name: d, x: 25}]\n", 2, 4);
    /* the same with a barrier at x = 25 that holds the block */
    extruded_case("profile: {points: [[0, 10], [10, 10], [20, 0], [100, 0]], material: m}\n"
                  "materials: {m: {R_n: 0.5, R_t: 0.8, friction_angle: 30}}\n"
                  "block: {shape: point, mass: 1}\n"
                  "release: {x: 5, y: 10.5, vx: 10, vy: 0}\n"
                  "bounce: {law: velocity_scaled, contact_speed: 0.01}\n"
                  "collectors: [{name: c, x: 15}, {name: d, x: 25, capacity: 1.0e4}]\n", 2, 2);
    /* its energy profile with a spinning sphere, every law, no roughness */
    const char *laws[4] = {"constant", "velocity_scaled", "rigid_sphere",
                           "impact_model, impact: {solver: rigid, tolerance: 0.01}"};
    for (int l = 0; l < 4; l++) {
        char yaml[1024];
        snprintf(yaml, sizeof yaml,
                 "profile: {points: [[0, 60], [20, 45], [30, 44], [45, 20], [50, 19], [70, 5], [80, 6], [120, 0]],\n"
                 "          material: m}\n"
                 "materials: {m: {R_n: 0.55, R_t: 0.85, friction_angle: 25}}\n"
                 "block: {shape: sphere, radius: 0.4, density: 2700}\n"
                 "release: {x: 1, y: 62, vx: 3, vy: 1, omega: 2}\n"
                 "bounce: {law: %s, contact_speed: 0.01}\n", laws[l]);
        extruded_case(yaml, 5, 3);
    }
}

/* A flight over flat ground (z = 0) from (10, 50, 40) at (12, 3, 4) m/s
 * crosses the fence (30, 0) - (40, 60) - (45, 100) on its first segment:
 * with the line a x + b y = c, t = (c - a px - b py) / (a vx + b vy). */
typedef struct {
    double t, x, y, z, along, E, v[3];
} crossing_ref;

static crossing_ref fence_reference(double mass)
{
    double a = 60, b = -10, c = a * 30 + b * 0; /* normal of (10, 60) */
    crossing_ref f;
    f.t = (c - a * 10 - b * 50) / (a * 12 + b * 3);
    f.x = 10 + 12 * f.t, f.y = 50 + 3 * f.t, f.z = 40 + 4 * f.t - 0.5 * TT_G * f.t * f.t;
    f.along = hypot(f.x - 30, f.y - 0);
    f.v[0] = 12, f.v[1] = 3, f.v[2] = 4 - TT_G * f.t;
    f.E = 0.5 * mass * dot(f.v, f.v);
    return f;
}

static void fence_run(double capacity, double height, tt_result *r, tt_spec *ts)
{
    static double zero_z[4] = {0, 0, 0, 0};
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(2, 2, 0, 0, 200, 200, zero_z, &t, &err), RF_OK);
    tt_world tw;
    tt_world_init(&tw, t);
    tt_spec_init(ts, 0.5, 0.8);
    ts->spec.vx0 = 12, ts->spec.vy0 = 3, ts->spec.vz0 = 4;
    double bx[3] = {30, 40, 45}, by[3] = {0, 60, 100};
    tt_world_barrier(&tw, ts, 3, bx, by, capacity, height);
    double start[3] = {10, 50, 40};
    tt_result_init(r);
    tt_simulate(&tw, ts, 0, start, r);
    rf_terrain_free(t);
}

static void check_crossing(const rf_traj_crossing *cr, const crossing_ref *f)
{
    assert_true(cr->reached);
    assert_close(cr->t, f->t, 1e-12);
    assert_close(cr->x, f->x, 1e-12);
    assert_close(cr->y, f->y, 1e-12);
    assert_close(cr->along, f->along, 1e-12);
    assert_close(cr->height_lowest, f->z, 1e-12);
    assert_close(cr->height_centre, f->z, 1e-12);
    assert_close(cr->normal_height, f->z, 1e-12);
    assert_close(cr->speed, sqrt(dot(f->v, f->v)), 1e-12);
    assert_close(cr->translational_energy, f->E, 1e-12);
    assert_true(cr->rotational_energy == 0);
    assert_close(cr->total_energy, f->E, 1e-12);
}

static void test_barrier_flight_and_capacity(void **state)
{
    (void)state;
    crossing_ref f = fence_reference(1000);
    double T1 = (4 + sqrt(16 + 2 * TT_G * 40)) / TT_G; /* the impact without a barrier */
    assert_true(f.z > 15 && f.z < 25 && f.t < T1);
    tt_result r;
    tt_spec ts;
    /* a pure collector: recorded, the flight untouched */
    fence_run(0, 0, &r, &ts);
    check_crossing(&r.cross[0], &f);
    assert_close(r.cross[0].energy_after, f.E, 1e-12);
    assert_false(r.cross[0].stopped_by_barrier);
    assert_close(r.res.impacts[0].t, T1, 1e-12);
    tt_result_free(&r);
    /* held: E <= C, unlimited height: stops at the crossing */
    fence_run(2 * f.E, 0, &r, &ts);
    check_crossing(&r.cross[0], &f);
    assert_true(r.cross[0].stopped_by_barrier);
    assert_true(r.cross[0].energy_after == 0);
    assert_int_equal(r.res.state, RF_TRAJ_STOPPED);
    assert_int_equal(r.res.n_impacts, 0);
    assert_close(r.res.t_end, f.t, 1e-12);
    assert_close(r.res.end[0], f.x, 1e-12);
    assert_close(r.res.end[1], f.y, 1e-12);
    tt_result_free(&r);
    /* held below a 30 m top as well */
    fence_run(2 * f.E, 30, &r, &ts);
    assert_true(r.cross[0].stopped_by_barrier);
    tt_result_free(&r);
    /* broken through: E > C, goes on with E - C (velocity scaled by sqrt((E - C) / E)) */
    fence_run(0.5 * f.E, 0, &r, &ts);
    check_crossing(&r.cross[0], &f);
    assert_false(r.cross[0].stopped_by_barrier);
    assert_close(r.cross[0].energy_after, 0.5 * f.E, 1e-12);
    const rf_terrain_event *ev = NULL;
    for (size_t k = 0; k < r.res.n_events; k++)
        if (r.res.events[k].kind == RF_EV_BARRIER)
            ev = &r.res.events[k];
    assert_non_null(ev);
    double sc = sqrt(0.5), vs[3] = {f.v[0] * sc, f.v[1] * sc, f.v[2] * sc};
    for (int q = 0; q < 3; q++)
        assert_near(ev->v[q], vs[q], 1e-12 * 20);
    assert_close(0.5 * 1000 * dot(ev->v, ev->v), 0.5 * f.E, 1e-12);
    double T2 = f.t + (vs[2] + sqrt(vs[2] * vs[2] + 2 * TT_G * f.z)) / TT_G;
    assert_close(r.res.impacts[0].t, T2, 1e-12);
    assert_close(r.res.impacts[0].x, f.x + vs[0] * (T2 - f.t), 1e-12);
    tt_result_free(&r);
    /* over the top of a 10 m fence: passes untouched */
    fence_run(0.5 * f.E, 10, &r, &ts);
    check_crossing(&r.cross[0], &f);
    assert_false(r.cross[0].stopped_by_barrier);
    assert_close(r.cross[0].energy_after, f.E, 1e-12);
    assert_close(r.res.impacts[0].t, T1, 1e-12);
    tt_result_free(&r);
}

/* A contact piece (on the ground, accelerating along its straight path):
 * the crossing of the line x = 5 from the distance along the chord,
 * 2 tau + tau^2 / 2 = 5, speed |v + a tau|, heights 0; a piece ending
 * before the line records nothing. */
static void test_barrier_contact_piece(void **state)
{
    (void)state;
    double zero[4] = {0, 0, 0, 0};
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(2, 2, -20, -20, 40, 40, zero, &t, &err), RF_OK);
    tt_world tw;
    tt_world_init(&tw, t);
    tt_spec ts;
    tt_spec_init(&ts, 0.5, 0.8);
    tt_sphere(&ts, 0.5, 2600);
    double bx[2] = {5, 5}, by[2] = {-10, 10};
    tt_world_barrier(&tw, &ts, 2, bx, by, 0, 0);
    tt_result r;
    tt_result_init(&r);
    terrain_run run;
    memset(&run, 0, sizeof run);
    run.w = &tw.w, run.dem = t, run.s = &ts.spec, run.res = &r.res, run.g = TT_G;
    run.mass = ts.spec.mass, run.radius = 0.5;
    terrain_piece pc = {3, 5, {0, 0, 0}, {2, 1, 0}, {1, 0.5, 0}, 123, 1};
    double cut, scale;
    assert_int_equal(terrain_barrier_piece(&run, &pc, &cut, &scale), TERRAIN_PIECE_FREE);
    double tau = -2 + sqrt(4 + 10), v[3] = {2 + tau, 1 + 0.5 * tau, 0};
    const rf_traj_crossing *cr = &r.cross[0];
    assert_true(cr->reached);
    assert_close(cr->t, 3 + tau, 1e-12);
    assert_close(cr->x, 5, 1e-12);
    assert_close(cr->y, 2.5, 1e-12);
    assert_close(cr->along, 12.5, 1e-12);
    assert_true(cr->height_lowest == 0 && cr->normal_height == 0);
    assert_close(cr->height_centre, 0.5, 1e-15);
    assert_close(cr->speed, sqrt(dot(v, v)), 1e-12);
    assert_close(cr->total_energy, 0.5 * ts.spec.mass * dot(v, v) + 123, 1e-12);
    memset(r.cross, 0, sizeof r.cross);
    pc.T = 1.5; /* ends at x = 4.125 */
    assert_int_equal(terrain_barrier_piece(&run, &pc, &cut, &scale), TERRAIN_PIECE_FREE);
    assert_false(r.cross[0].reached);
    tt_result_free(&r);
    rf_terrain_free(t);
}

/* The same sample gives the same bits; roughness draws differ by sample. */
static void test_same_sample_same_bits(void **state)
{
    (void)state;
    tt_plane pl = {0, -0.5, 0.1, 0, 0};
    rf_terrain *t = tt_dem(101, 41, 0, 0, 2, 2, tt_plane_z, &pl);
    tt_world tw;
    tt_world_init(&tw, t);
    tt_spec ts;
    tt_spec_init(&ts, 0.7, 0.9);
    ts.mat[0].roughness = 10 * TT_DEG;
    ts.spec.vx0 = 3;
    double start[3] = {4, 40, NAN};
    ts.spec.height0 = 2;
    tt_result a, b;
    tt_result_init(&a);
    tt_result_init(&b);
    tt_simulate(&tw, &ts, 5, start, &a);
    tt_simulate(&tw, &ts, 5, start, &b);
    assert_true(a.res.n_events == b.res.n_events && a.res.n_events > 3);
    assert_memory_equal(a.res.events, b.res.events, a.res.n_events * sizeof *a.res.events);
    tt_simulate(&tw, &ts, 6, start, &b);
    assert_true(b.res.end[0] != a.res.end[0] || b.res.end[1] != a.res.end[1]);
    tt_result_free(&a);
    tt_result_free(&b);
    rf_terrain_free(t);
}

/* Flat ground tilted down to the east (z = -0.1 x): thrown east fast from
 * (5, 5, 1) it leaves through x = 100 at t = 95 / 60; runout and reach angle
 * from the exit point. */
static void test_exit_runout_reach(void **state)
{
    (void)state;
    tt_plane pl = {0, -0.1, 0, 0, 0};
    rf_terrain *t = tt_dem(11, 11, 0, 0, 10, 10, tt_plane_z, &pl);
    tt_world tw;
    tt_world_init(&tw, t);
    tt_spec ts;
    tt_spec_init(&ts, 0.5, 0.8);
    ts.spec.vx0 = 60, ts.spec.vy0 = 0, ts.spec.vz0 = 5;
    double start[3] = {5, 5, 1};
    tt_result r;
    tt_result_init(&r);
    tt_simulate(&tw, &ts, 0, start, &r);
    double te = 95.0 / 60, ze = 1 + 5 * te - 0.5 * TT_G * te * te;
    assert_int_equal(r.res.state, RF_TRAJ_EXITED);
    assert_int_equal(r.res.n_impacts, 0);
    assert_close(r.res.t_end, te, 1e-12);
    assert_close(r.res.end[0], 100, 1e-12);
    assert_close(r.res.end[2], ze, 1e-12);
    assert_close(r.res.runout, 95, 1e-12);
    assert_close(r.res.reach_angle, atan((1 - ze) / 95), 1e-12);
    assert_close(r.res.rebound_height, 0, 1);
    assert_int_equal(r.res.events[r.res.n_events - 1].kind, RF_EV_EXIT);
    tt_result_free(&r);
    rf_terrain_free(t);
}

/* Dropped from 5 m onto flat ground, with vx = 3: the first rebound rises
 * (R_n v0)^2 / (2 g); with max_steps 3 the run ends at the step limit; a
 * release by speed 10, azimuth 90 (east), dip 30 from 2 m above the ground
 * (z NaN: ground + height0) lands at the closed form. */
static void test_states_and_release(void **state)
{
    (void)state;
    double zero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(3, 3, -100, -100, 100, 100, zero, &t, &err), RF_OK);
    tt_world tw;
    tt_world_init(&tw, t);
    tt_spec ts;
    tt_spec_init(&ts, 0.6, 0.9);
    ts.spec.vx0 = 3;
    double start[3] = {0, 0, 5}, v0 = sqrt(2 * TT_G * 5);
    tt_result r;
    tt_result_init(&r);
    tt_simulate(&tw, &ts, 0, start, &r);
    assert_close(r.res.rebound_height, 0.36 * v0 * v0 / (2 * TT_G), 1e-12);
    assert_true(r.res.n_impacts > 5);
    assert_int_equal(r.res.state, RF_TRAJ_STOPPED); /* into contact: the contact stub stops it */
    assert_close(r.res.reach_angle, atan(5 / r.res.runout), 1e-12);
    ts.spec.max_steps = 3;
    tt_simulate(&tw, &ts, 0, start, &r);
    assert_int_equal(r.res.state, RF_TRAJ_STEP_LIMIT);
    assert_int_equal(r.res.n_impacts, 3);
    assert_int_equal(r.res.events[r.res.n_events - 1].kind, RF_EV_STEP_LIMIT);
    ts.spec.max_steps = 10000;
    ts.spec.release_by_speed = 1, ts.spec.speed0 = 10, ts.spec.azimuth0 = 90 * TT_DEG, ts.spec.dip0 = 30 * TT_DEG;
    ts.spec.height0 = 2;
    double at[3] = {1, 2, NAN};
    tt_simulate(&tw, &ts, 0, at, &r);
    double vz = -5, T = (vz + sqrt(vz * vz + 2 * TT_G * 2)) / TT_G;
    assert_close(r.res.start[2], 2, 1e-15);
    assert_close(r.res.impacts[0].t, T, 1e-12);
    assert_close(r.res.impacts[0].x, 1 + 10 * cos(30 * TT_DEG) * T, 1e-12);
    assert_near(r.res.impacts[0].y, 2, 1e-12);
    /* on the ground at rest: contact at once (events: release on the ground) */
    ts.spec.height0 = 0, ts.spec.speed0 = 0;
    tt_simulate(&tw, &ts, 0, at, &r);
    assert_int_equal(r.res.events[0].kind, RF_EV_RELEASE);
    assert_false(r.res.events[0].flying);
    assert_int_equal(r.res.n_impacts, 0);
    /* refusals: outside the DEM; rigid_sphere for a point block; impact_model without a table */
    double off[3] = {500, 0, 1};
    assert_int_equal(rf_terrain_simulate(&tw.w, &ts.spec, 1, 0, off, &r.res, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "outside the DEM"));
    ts.spec.law = RF_BOUNCE_RIGID_SPHERE;
    assert_int_equal(rf_terrain_simulate(&tw.w, &ts.spec, 1, 0, start, &r.res, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "sphere"));
    tt_sphere(&ts, 0.5, 2600);
    ts.spec.law = RF_BOUNCE_IMPACT_MODEL;
    assert_int_equal(rf_terrain_simulate(&tw.w, &ts.spec, 1, 0, start, &r.res, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "impact table"));
    tt_result_free(&r);
    rf_terrain_free(t);
}

static double rough_slope(void *ctx, double x, double y)
{
    uint64_t *s = ctx;
    return -0.6 * x - 0.1 * y + tt_uniform(s, 0, 1.5);
}

/* Every flight between two recorded events stays above the ground at 400
 * samples (a second method beside the cell walk). */
static void check_flights_above(const rf_terrain *t, const rf_terrain_result *res)
{
    for (size_t k = 0; k + 1 < res->n_events; k++) {
        const rf_terrain_event *a = &res->events[k], *b = &res->events[k + 1];
        if (!a->flying)
            continue;
        double T = b->t - a->t;
        for (int i = 1; i < 400; i++) {
            double s = T * i / 400, x = a->p[0] + a->v[0] * s, y = a->p[1] + a->v[1] * s, zg;
            double z = a->p[2] + a->v[2] * s - 0.5 * TT_G * s * s;
            if (rf_terrain_height(t, x, y, &zg, NULL) && z < zg - 1e-9 * (1 + fabs(z)))
                fail_msg("events %zu-%zu: the flight is %g m below the ground at s = %g", k, k + 1, zg - z, s);
        }
    }
}

/* Whole trajectories down a rough 31 deg slope with roughness 20 deg: the
 * invariants (never below the ground, never more mechanical energy, spin
 * included) hold at every event, every flight stays above the ground, and
 * no impact of a lumped-mass law returns more speed than it received. */
static void test_roughness_never_gains_energy(void **state)
{
    (void)state;
    uint64_t zs = 31;
    rf_terrain *t = tt_dem(61, 31, 0, 0, 2, 2, rough_slope, &zs);
    tt_world tw;
    tt_world_init(&tw, t);
    size_t impacts = 0;
    for (int law = 0; law < 3; law++) {
        tt_spec ts;
        tt_spec_init(&ts, 0.6, 0.85);
        tt_sphere(&ts, 0.3, 2600);
        ts.spec.law = (rf_bounce_law)law;
        ts.mat[0].roughness = 20 * TT_DEG;
        ts.spec.contact_speed = 0.05;
        ts.spec.omega0_xyz[0] = 1, ts.spec.omega0_xyz[1] = -2; /* rigid_sphere: spin in the event energies */
        for (uint64_t k = 0; k < 200; k++) {
            ts.spec.vx0 = 2 + (double)(k % 7), ts.spec.vy0 = (double)(k % 5) - 2, ts.spec.vz0 = 1;
            double start[3] = {4 + (double)(k % 3), 10 + (double)(k % 11), NAN};
            ts.spec.height0 = 0.5 + 0.1 * (double)(k % 4);
            tt_result r;
            tt_result_init(&r);
            tt_simulate(&tw, &ts, k, start, &r);
            check_flights_above(t, &r.res);
            for (size_t m = 0; m < r.res.n_impacts && law != RF_BOUNCE_RIGID_SPHERE; m++) {
                const rf_terrain_impact *im = &r.res.impacts[m]; /* lumped mass: translation only */
                assert_true(dot(im->v_out, im->v_out) <= dot(im->v_in, im->v_in) * (1 + 1e-12));
            }
            impacts += r.res.n_impacts;
            tt_result_free(&r);
        }
    }
    assert_true(impacts > 1000);
    rf_terrain_free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bounce_series_inclined_plane),
        cmocka_unit_test(test_extruded_profiles),
        cmocka_unit_test(test_barrier_flight_and_capacity),
        cmocka_unit_test(test_barrier_contact_piece),
        cmocka_unit_test(test_same_sample_same_bits),
        cmocka_unit_test(test_exit_runout_reach),
        cmocka_unit_test(test_states_and_release),
        cmocka_unit_test(test_roughness_never_gains_energy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
