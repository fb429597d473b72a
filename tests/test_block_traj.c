/* test_block_traj.c - rigid blocks in the trajectory engines (issue 30, the
 * wiring; docs/block-shape.md "Wiring"), against independent references:
 *  - a box on a plane DEM below its friction angle stays; above it slides at
 *    g (sin b - mu cos b), read from the engine's barrier crossing (time and
 *    speed; a closed form);
 *  - the energy (kinetic + m g z) never grows over a step in contact and never
 *    exceeds the start's, checked at every step of tumbling runs on a
 *    profile and on terrain (the observer);
 *  - a DEM that extrudes a profile along y gives the profile run of the same
 *    block (the 3D engine against the 2D one with its planar projection);
 *  - a sphere given as an ellipsoid (r, r, r) against the sphere engines
 *    (rigid_sphere law: e_n = R_n, sticking friction) on a profile and on a
 *    plane DEM: the state where it passes a collector;
 *  - the file: shapes, orientation, spin, axis ratios at constant volume,
 *    and messages with file:line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_terrain_util.h"
#include "trajectory/block_traj.h"

/* ---- a profile run from a YAML text ---- */

typedef struct {
    rf_traj_spec spec;
    rf_traj_world *world;
    rf_traj_result res;
    rf_traj_crossing cross[4];
} pcase;

static void pcase_load(pcase *c, const char *yaml)
{
    rf_error err;
    memset(c, 0, sizeof *c);
    if (rf_traj_load_buffer("t.yaml", yaml, strlen(yaml), &c->spec, &err) != RF_OK)
        fail_msg("load: %s", err.msg);
    if (rf_traj_world_create(&c->spec, &c->world, &err) != RF_OK)
        fail_msg("world: %s", err.msg);
    c->res.crossings = c->cross;
    c->res.impacts = malloc(16 * sizeof *c->res.impacts), c->res.impacts_cap = 16;
    c->res.events = malloc(16 * sizeof *c->res.events), c->res.events_cap = 16;
}

static void pcase_run(pcase *c, traj_block_observer obs, void *ctx)
{
    rf_error err;
    rf_status st = c->spec.block_kind ? traj_block_simulate_observed(c->world, &c->spec, 7, 0, &c->res, obs, ctx, &err)
                                      : rf_traj_simulate(c->world, &c->spec, 7, 0, &c->res, &err);
    if (st != RF_OK)
        fail_msg("simulate: %s", err.msg);
}

static void pcase_free(pcase *c)
{
    free(c->res.impacts), free(c->res.events);
    rf_traj_world_free(c->world);
    rf_traj_spec_free(&c->spec);
}

/* ---- the energy observer ---- */

/* The largest energy gain of a contact step, relative to the energy scale
 * |E_0| + m g R: round-off only.  The core's energy cap scales the step's
 * end velocities and its displacement together (block_contact.c); it used
 * to scale the velocities alone, and a block coming to rest was lifted by
 * the uncapped ones (0.1 um for a box, 0.47 um for an EOTA wheel) with its
 * kinetic energy set to 0: that needed an allowance of m g x 1 um here. */
#define CONTACT_GAIN 1e-13

typedef struct {
    double g, e0, prev, worst_gain, worst_above;
    size_t steps;
    int have;
} energy_watch;

static void watch_energy(void *ctx, double t, const rf_block_shape *s, const rf_block_state *st,
                         const rf_block_step_info *info)
{
    energy_watch *w = ctx;
    double e = rf_block_energy(s, st, w->g);
    if (!w->have)
        w->e0 = w->prev = e, w->have = 1;
    double scale = fabs(w->e0) + s->mass * w->g * s->bound_radius;
    if (info->n_contacts > 0 && (e - w->prev) / scale > w->worst_gain)
        w->worst_gain = (e - w->prev) / scale;
    if (getenv("BT_DEBUG") && info->n_contacts > 0 && e > w->prev)
        fprintf(stderr, "t %g gain %g J nc %d cap %g ke %g\n", t, e - w->prev, info->n_contacts, info->energy_cap,
                rf_block_kinetic_energy(s, st, NULL));
    if ((e - w->e0) / scale > w->worst_above)
        w->worst_above = (e - w->e0) / scale;
    w->prev = e;
    w->steps++;
}

/* ---- a block on terrain, in memory ---- */

static void block_spec(tt_spec *ts, int kind, double a, double b, double c, double density)
{
    rf_traj_spec *s = &ts->spec;
    s->block_kind = kind;
    s->block_dims[0] = a, s->block_dims[1] = b, s->block_dims[2] = c;
    s->density = density;
    s->block_ratio_b = s->block_ratio_c = 1;
    s->block_q0[0] = 1;
    s->block_time_step = 1e-3, s->block_max_time = 60, s->block_rest_time = 0.5;
}

/* q of a turn by angle about y. */
static void pitch(tt_spec *ts, double angle)
{
    ts->spec.block_q0[0] = cos(angle / 2), ts->spec.block_q0[2] = sin(angle / 2);
}

static void box_on_incline(double beta_deg, double phi_deg, tt_result *r, rf_terrain **dem, double *x0)
{
    double beta = beta_deg * TT_DEG;
    tt_plane pl = {0, -tan(beta), 0, 0, 0};
    *dem = tt_dem(61, 21, 0, -20, 2, 2, tt_plane_z, &pl);
    tt_world tw;
    tt_world_init(&tw, *dem);
    tt_spec ts;
    tt_spec_init(&ts, 0.3, 0.8);
    ts.mat[0].friction_angle = phi_deg * TT_DEG;
    block_spec(&ts, RF_TRAJ_BLOCK_BOX, 1.0, 0.6, 0.4, 2500);
    pitch(&ts, beta); /* lies flat on the incline (x down the slope) */
    double bx[2] = {60, 60}, by[2] = {-20, 20};
    tt_world_barrier(&tw, &ts, 2, bx, by, 1e9, 0); /* holds it: read the crossing */
    tt_result_init(r);
    rf_error err;
    const double start[3] = {10, 0, NAN};
    if (rf_terrain_simulate(&tw.w, &ts.spec, 7, 0, start, &r->res, &err) != RF_OK)
        fail_msg("simulate: %s", err.msg);
    *x0 = r->res.start[0];
}

static void test_box_stays_below_friction_angle(void **state)
{
    (void)state;
    tt_result r;
    rf_terrain *dem;
    double x0;
    box_on_incline(20, 30, &r, &dem, &x0);
    assert_int_equal(r.res.state, RF_TRAJ_STOPPED);
    assert_false(r.res.crossings[0].reached);
    assert_near(r.res.runout, 0, 1e-6); /* the lowest point has not moved */
    assert_near(r.res.t_end, 0.5, 2e-3); /* at rest from the start: rest_time */
    tt_result_free(&r);
    rf_terrain_free(dem);
}

static void test_box_slides_above_friction_angle(void **state)
{
    (void)state;
    tt_result r;
    rf_terrain *dem;
    double x0, beta = 35 * TT_DEG, mu = tan(30 * TT_DEG);
    box_on_incline(35, 30, &r, &dem, &x0);
    double a = TT_G * (sin(beta) - mu * cos(beta));
    const rf_traj_crossing *c = &r.res.crossings[0];
    assert_true(c->reached);
    assert_true(c->stopped_by_barrier);
    /* The barrier records the centre's crossing (block_traj_terrain.c): the centre starts half the 1 m
     * length uphill of the lowest (downhill bottom) corner at x0 and 0.2 m off the plane. */
    double xc0 = x0 - 0.5 * cos(beta) + 0.2 * sin(beta);
    double d = (60 - xc0) / cos(beta); /* along the slope */
    assert_near(c->speed / c->t / a, 1, 1e-6);           /* v = a t */
    assert_near(2 * d / (c->t * c->t) / a, 1, 1e-6);     /* d = a t^2 / 2 */
    assert_near(c->height_lowest, 0, 1e-12);             /* sliding: on the ground */
    assert_near(c->height_centre, 0.2 / cos(beta), 1e-6); /* centre 0.2 m off the plane, vertically */
    assert_near(c->rotational_energy, 0, 1e-9 * c->total_energy);
    tt_result_free(&r);
    rf_terrain_free(dem);
}

/* A tumbling box on a plane DEM, random orientation and spin: energy watched at every step. */
static void test_energy_never_gained_terrain(void **state)
{
    (void)state;
    tt_plane pl = {0, -0.7, -0.1, 0, 0};
    rf_terrain *dem = tt_dem(61, 41, 0, -40, 2, 2, tt_plane_z, &pl);
    tt_world tw;
    tt_world_init(&tw, dem);
    tt_spec ts;
    tt_spec_init(&ts, 0.4, 0.8);
    block_spec(&ts, RF_TRAJ_BLOCK_BOX, 1.2, 0.8, 0.5, 2600);
    ts.spec.block_random_orientation = 1;
    ts.spec.block_spin_given = 1;
    ts.spec.block_spin0[0] = 2, ts.spec.block_spin0[1] = -3, ts.spec.block_spin0[2] = 1;
    ts.spec.height0 = 2;
    ts.spec.vx0 = 3;
    for (uint64_t k = 0; k < 4; k++) {
        tt_result r;
        tt_result_init(&r);
        energy_watch w = {TT_G, 0, 0, 0, 0, 0, 0};
        rf_error err;
        const double start[3] = {10, 0, NAN};
        if (terrain_block_simulate(&tw.w, &ts.spec, 7, k, start, NULL, &r.res, watch_energy, &w, &err) != RF_OK)
            fail_msg("simulate: %s", err.msg);
        assert_true(w.steps > 100);
        assert_true(r.res.n_impacts >= 1);
        print_message("terrain sample %llu: %zu steps, largest contact-step gain %.3g, largest rise %.3g (of the "
                      "energy scale)\n", (unsigned long long)k, w.steps, w.worst_gain, w.worst_above);
        if (w.worst_gain > CONTACT_GAIN || w.worst_above > 1e-7)
            fail_msg("sample %llu: a contact step gained %.3g, the energy rose %.3g above the start",
                     (unsigned long long)k, w.worst_gain, w.worst_above);
        tt_result_free(&r);
    }
    rf_terrain_free(dem);
}

static const char *profile_yaml =
    "name: p\n"
    "profile: {points: [[0, 30], [30, 10], [60, 5], [100, 5]], material: m}\n"
    "materials: {m: {R_n: 0.4, R_t: 0.8, friction_angle: 35}}\n"
    "block: {%s}\n"
    "release: {x: 2, y: 32, vx: 3}\n"
    "collectors: [{name: c, x: 45}]\n";

static void test_energy_never_gained_profile(void **state)
{
    (void)state;
    char y[1024];
    const char *blocks[3] = {"shape: box, edges: [1.2, 0.8, 0.5], density: 2600, orientation: {pitch: 20}, "
                             "spin: [0, 2, 0]",
                             "shape: ellipsoid, axes: [0.8, 0.5, 0.4], density: 2600, orientation: random",
                             "shape: eota_wheel, volume: 1, density: 2400, orientation: {pitch: 33, roll: 90}"};
    for (int k = 0; k < 3; k++) {
        pcase c;
        snprintf(y, sizeof y, profile_yaml, blocks[k]);
        pcase_load(&c, y);
        energy_watch w = {9.81, 0, 0, 0, 0, 0, 0};
        pcase_run(&c, watch_energy, &w);
        print_message("profile %d: %zu steps, largest contact-step gain %.3g, largest rise %.3g (of the energy "
                      "scale)\n", k, w.steps, w.worst_gain, w.worst_above);
        if (w.worst_gain > CONTACT_GAIN || w.worst_above > 1e-7)
            fail_msg("%s: a contact step gained %.3g, the energy rose %.3g above the start", blocks[k],
                     w.worst_gain, w.worst_above);
        assert_true(c.res.n_impacts >= 1);
        pcase_free(&c);
    }
}

/* The profile of profile_yaml as a DEM extruded along y (nodes on its kinks: the bilinear surface is it). */
static double extruded(void *ctx, double x, double y)
{
    (void)ctx, (void)y;
    return x <= 30 ? 30 - x * 20.0 / 30 : x <= 60 ? 10 - (x - 30) * 5.0 / 30 : 5;
}

static void extruded_case(const char *block, double tol_x, double tol_v, double tol_t)
{
    char y[1024];
    pcase c;
    snprintf(y, sizeof y, profile_yaml, block);
    pcase_load(&c, y);
    pcase_run(&c, NULL, NULL);
    rf_terrain *dem = tt_dem(101, 9, 0, -20, 1, 5, extruded, NULL);
    tt_world tw;
    tt_world_init(&tw, dem);
    tt_spec ts;
    tt_spec_init(&ts, 0.4, 0.8);
    rf_traj_spec s3 = c.spec; /* the same block and material on the map */
    s3.terrain = NULL, s3.n_collectors = 0, s3.collectors = ts.col;
    s3.vz0 = c.spec.vy0, s3.vy0 = 0, s3.height0 = 32 - extruded(NULL, 2, 0);
    s3.omega0_xyz[0] = 0, s3.omega0_xyz[1] = c.spec.omega0, s3.omega0_xyz[2] = 0;
    double bx[2] = {45, 45}, by[2] = {-20, 20};
    ts.spec = s3;
    tt_world_barrier(&tw, &ts, 2, bx, by, 0, 0);
    tt_result r;
    tt_result_init(&r);
    rf_error err;
    const double start[3] = {2, 0, NAN};
    if (rf_terrain_simulate(&tw.w, &ts.spec, 7, 0, start, &r.res, &err) != RF_OK)
        fail_msg("simulate: %s", err.msg);
    if (getenv("BT_DEBUG"))
        fprintf(stderr, "%s: end %.9g %.9g vs %.9g; t_end %g vs %g; cross speed %.9g vs %.9g, t %.9g vs %.9g\n", block,
                r.res.end[0], r.res.end[1], c.res.x_end, r.res.t_end, c.res.t_end, r.res.crossings[0].speed,
                c.res.crossings[0].speed, r.res.crossings[0].t, c.res.crossings[0].t);
    assert_int_equal(r.res.state, c.res.state);
    assert_near(r.res.end[0], c.res.x_end, tol_x);
    assert_near(r.res.end[1], 0, tol_x);
    assert_int_equal(r.res.crossings[0].reached, c.res.crossings[0].reached);
    if (c.res.crossings[0].reached) {
        assert_near(r.res.crossings[0].speed / c.res.crossings[0].speed, 1, tol_v);
        assert_near(r.res.crossings[0].t, c.res.crossings[0].t, tol_t);
    }
    tt_result_free(&r);
    rf_terrain_free(dem);
    pcase_free(&c);
}

static void test_extruded_dem_is_the_profile(void **state)
{
    (void)state;
    extruded_case("shape: ellipsoid, axes: [0.8, 0.5, 0.4], density: 2600", 1e-3, 1e-2, 0.05);
    extruded_case("shape: box, edges: [1.2, 0.8, 0.5], density: 2600", 1e-3, 1e-2, 0.05);
}

/* A sphere given as an ellipsoid (r, r, r) against the profile engine's
 * sphere with the rigid_sphere law (e_n = R_n, sticking friction with mu =
 * tan(friction_angle): the rigid-body law of docs/block-shape.md with e_t =
 * 0, which R_t = 0.8 > 5/7 maps to).  The methods differ: the 2D engine takes
 * the sphere's lowest point as its contact point (on a slope of b the true
 * contact, along the normal, comes r (1/cos b - 1) earlier), its flights are
 * exact and its contact phases closed-form; the block engine steps at h with
 * the midpoint rule (an impact's normal impulse carries m g h).  So the paths
 * agree to a few per cent, not to round-off. */
static void test_sphere_as_ellipsoid_profile(void **state)
{
    (void)state;
    char y[1024];
    pcase a, b;
    snprintf(y, sizeof y, profile_yaml, "shape: sphere, radius: 0.5, density: 2600");
    strcat(y, "bounce: {law: rigid_sphere}\n");
    pcase_load(&a, y);
    pcase_run(&a, NULL, NULL);
    snprintf(y, sizeof y, profile_yaml, "shape: ellipsoid, axes: [0.5, 0.5, 0.5], density: 2600, time_step: 2e-4");
    pcase_load(&b, y);
    pcase_run(&b, NULL, NULL);
    const rf_traj_crossing *ca = &a.res.crossings[0], *cb = &b.res.crossings[0];
    if (getenv("BT_DEBUG"))
        fprintf(stderr, "sphere: %s x %g t %g | cross t %.6g v %.6g rot %.6g h %.4g | impacts %zu\n"
                        "ellipsoid: %s x %g t %g | cross t %.6g v %.6g rot %.6g h %.4g | impacts %zu\n",
                rf_traj_state_name(a.res.state), a.res.x_end, a.res.t_end, ca->t, ca->speed, ca->rotational_energy,
                ca->height_centre, a.res.n_impacts, rf_traj_state_name(b.res.state), b.res.x_end, b.res.t_end,
                cb->t, cb->speed, cb->rotational_energy, cb->height_centre, b.res.n_impacts);
    assert_true(ca->reached && cb->reached);
    /* measured: 0.05 %, 0.1 %, 0.1 %; the centre 0.507 m above the ground at x = 45 m (r / cos b on the
       1:6 slope) where the 2D engine puts it r = 0.5 m above its lowest point */
    assert_near(cb->speed / ca->speed, 1, 0.01);
    assert_near(cb->t / ca->t, 1, 0.01);
    assert_near(cb->rotational_energy / ca->rotational_energy, 1, 0.01);
    assert_near(cb->height_centre, 0.5 / cos(atan(5.0 / 30)), 0.01);
    pcase_free(&a);
    pcase_free(&b);
}

/* The same on a plane DEM (25 deg down x) against the terrain engine's sphere: thrown, bouncing, rolling. */
static void sphere_on_plane(int block, tt_result *r, rf_terrain **dem)
{
    tt_plane pl = {0, -tan(25 * TT_DEG), 0, 0, 0};
    *dem = tt_dem(61, 21, 0, -20, 2, 2, tt_plane_z, &pl);
    tt_world tw;
    tt_world_init(&tw, *dem);
    tt_spec ts;
    tt_spec_init(&ts, 0.4, 0.8);
    ts.spec.law = block ? RF_BOUNCE_CONSTANT : RF_BOUNCE_RIGID_SPHERE; /* a block has its own law */
    ts.mat[0].rolling_resistance = 0;
    if (block) {
        block_spec(&ts, RF_TRAJ_BLOCK_ELLIPSOID, 0.5, 0.5, 0.5, 2600);
        ts.spec.block_time_step = 2e-4;
    } else
        tt_sphere(&ts, 0.5, 2600);
    ts.spec.height0 = 3, ts.spec.vx0 = 2, ts.spec.vy0 = 0.5;
    double bx[2] = {80, 80}, by[2] = {-20, 20};
    tt_world_barrier(&tw, &ts, 2, bx, by, 0, 0);
    tt_result_init(r);
    rf_error err;
    const double start[3] = {10, 0, NAN};
    if (rf_terrain_simulate(&tw.w, &ts.spec, 7, 0, start, &r->res, &err) != RF_OK)
        fail_msg("simulate: %s", err.msg);
}

static void test_sphere_as_ellipsoid_terrain(void **state)
{
    (void)state;
    tt_result a, b;
    rf_terrain *da, *db;
    sphere_on_plane(0, &a, &da);
    sphere_on_plane(1, &b, &db);
    const rf_traj_crossing *ca = &a.res.crossings[0], *cb = &b.res.crossings[0];
    if (getenv("BT_DEBUG"))
        fprintf(stderr, "sphere: cross t %.6g v %.6g rot %.6g y %.6g | ellipsoid: t %.6g v %.6g rot %.6g y %.6g\n",
                ca->t, ca->speed, ca->rotational_energy, ca->along, cb->t, cb->speed, cb->rotational_energy, cb->along);
    assert_true(ca->reached && cb->reached);
    assert_near(cb->speed / ca->speed, 1, 0.01);
    assert_near(cb->t / ca->t, 1, 0.01);
    /* Measured: speed 4e-5, time 5e-5 apart.  The block rolls there (w r = v: rotational energy 2/5 of the
       translational, a closed form); the terrain engine's sphere carries 2.8 % less rotational energy at the
       same speed (its spin lags v / r by 1.4 %: a point for its contact phase, not for the block). */
    assert_near(cb->rotational_energy / (0.4 * cb->translational_energy), 1, 1e-3);
    assert_near(cb->rotational_energy / ca->rotational_energy, 1, 0.05);
    assert_near(cb->along, ca->along, 0.01); /* where it meets the barrier line */
    tt_result_free(&a), tt_result_free(&b);
    rf_terrain_free(da), rf_terrain_free(db);
}

/* ---- the ground adapters' bounds (block_traj_ground.c) against brute force ---- */

static double bumpy_z(void *ctx, double x, double y)
{
    (void)ctx;
    return 0.6 * x - 0.2 * y + 1.5 * sin(x / 3.0) * cos(y / 4.0) + 0.3 * sin(1.7 * x + 0.9 * y);
}

/* The largest ground - plane over an n x n sampling of the rectangle
 * (edges included) through the ground callback; -inf if no ground. */
static double sampled_max(rf_block_ground_fn ground, void *ctx, const double r[4], const double p[3], int n)
{
    double m = -INFINITY, z, nn[3];
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            double x = r[0] + (r[2] - r[0]) * i / n, y = r[1] + (r[3] - r[1]) * j / n;
            if (ground(ctx, x, y, &z, nn))
                m = fmax(m, z - p[0] - p[1] * x - p[2] * y);
        }
    return m;
}

/* Random rectangles (some reaching past the edges) and planes: the bound is
 * never below a sample of the ground (it is a bound) and exceeds the largest
 * of 400^2 samples by less than the ground's slope times the samples'
 * spacing (it is tight); a rectangle off the ground has no bound. */
static void check_bound(rf_block_ground_fn ground, rf_block_ground_bound_fn bound, void *ctx, const double ext[4],
                        double slope, int planar)
{
    uint64_t seed = 11;
    double worst = 0;
    for (int k = 0; k < 200; k++) {
        double cx = tt_uniform(&seed, ext[0] - 2, ext[2] + 2), cy = tt_uniform(&seed, ext[1] - 2, ext[3] + 2);
        double wx = tt_uniform(&seed, 0.01, 6), wy = tt_uniform(&seed, 0.01, 6), dz;
        double r[4] = {cx - wx, cy - wy, cx + wx, cy + wy};
        double p[3] = {tt_uniform(&seed, -5, 5), tt_uniform(&seed, -1, 1), planar ? 0 : tt_uniform(&seed, -1, 1)};
        double m = sampled_max(ground, ctx, r, p, 400);
        if (!bound(ctx, r[0], r[1], r[2], r[3], p, &dz)) {
            assert_true(m == -INFINITY);
            continue;
        }
        assert_true(m > -INFINITY);
        assert_true(dz >= m - 1e-12);
        double spacing = hypot(r[2] - r[0], r[3] - r[1]) / 400;
        assert_true(dz - m <= (slope + 1.5) * spacing); /* plane slopes <= 1.5 */
        worst = fmax(worst, (dz - m) / spacing);
    }
    print_message("bound - largest sample: at most %.3f sample spacings\n", worst);
}

static void test_terrain_bound(void **state)
{
    (void)state;
    rf_terrain *dem = tt_dem(31, 21, -10, 5, 1.5, 2.0, bumpy_z, NULL);
    const double ext[4] = {-10, 5, 35, 45};
    check_bound(traj_block_terrain_ground, traj_block_terrain_bound, dem, ext, 3.5, 0);
    rf_terrain_free(dem);
}

static void test_profile_bound(void **state)
{
    (void)state;
    double x[40], z[40];
    for (int i = 0; i < 40; i++)
        x[i] = -10 + 1.3 * i + 0.4 * sin(i), z[i] = bumpy_z(NULL, x[i], 0);
    rf_block_profile prof = {40, x, z};
    const double ext[4] = {x[0], -30, x[39], 30};
    check_bound(rf_block_ground_profile, traj_block_profile_bound, &prof, ext, 3.5, 1);
}

/* A block flying over a collector (the flight taken in steps of up to 64 ms):
 * the crossing is the exact parabola's, t = dx / v_x, centre height
 * z_0 - g t^2 / 2, speed sqrt(v_x^2 + (g t)^2), whatever the spin
 * (block_run_state_at; interpolating a 64 ms step linearly would miss the
 * height by g tau^2 / 8, 5 mm). */
static void test_flight_crossing_exact(void **state)
{
    (void)state;
    pcase c;
    pcase_load(&c, "name: f\n"
                   "profile: {points: [[0, 0], [100, 0]], material: m}\n"
                   "materials: {m: {R_n: 0.4, R_t: 0.8, friction_angle: 35}}\n"
                   "block: {shape: ellipsoid, axes: [0.5, 0.4, 0.3], density: 2600, spin: [0, 3, 0], max_time: 2.5}\n"
                   "release: {x: 2, y: 40, vx: 5}\n"
                   "collectors: [{name: c, x: 12}]\n");
    pcase_run(&c, NULL, NULL);
    const rf_traj_crossing *cr = &c.res.crossings[0];
    double g = c.spec.gravity, t = 10.0 / 5.0, z = 40.3 - 0.5 * g * t * t;
    print_message("flight crossing: t %.15g (%.15g), centre %.15g m (%.15g), speed %.15g m/s\n", cr->t, t,
                  cr->height_centre, z, cr->speed);
    assert_true(cr->reached);
    assert_true(c.res.n_steps < 100); /* long flight steps (2.5 s in the air) */
    assert_near(cr->t, t, 1e-12);
    assert_near(cr->height_centre, z, 1e-9);
    assert_near(cr->speed, hypot(5, g * t), 1e-9);
    pcase_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box_stays_below_friction_angle),
        cmocka_unit_test(test_box_slides_above_friction_angle),
        cmocka_unit_test(test_energy_never_gained_terrain),
        cmocka_unit_test(test_energy_never_gained_profile),
        cmocka_unit_test(test_extruded_dem_is_the_profile),
        cmocka_unit_test(test_sphere_as_ellipsoid_profile),
        cmocka_unit_test(test_sphere_as_ellipsoid_terrain),
        cmocka_unit_test(test_terrain_bound),
        cmocka_unit_test(test_profile_bound),
        cmocka_unit_test(test_flight_crossing_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
