/* test_terrain_contact.c - sliding and rolling on the terrain surface
 * (terrain_contact.c) against closed forms, a brute-force integration, the
 * 2D engine on extruded profiles and the energy balance.  Each case builds a
 * terrain_run by hand: a surface from nodes, a spec with one material (read
 * from a small profile file, whose profile only the 2D comparisons use), and
 * calls terrain_contact_run from a state on the ground. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/terrain.h"
#include "rockfuzz/trajectory.h"
#include "trajectory/terrain_internal.h"
#include "test_util.h"

#define G 9.81
#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

/* The spec of a trajectory file with the given material and block lines. */
static void load_spec(rf_traj_spec *s, const char *profile, const char *material, const char *block, const char *release)
{
    char yaml[2048];
    snprintf(yaml, sizeof yaml,
             "profile: {points: %s, material: m}\n"
             "materials: {m: {R_n: 0.3, R_t: 0.8, %s}}\n"
             "block: {%s}\n"
             "release: {%s}\n",
             profile, material, block, release);
    rf_error err;
    if (rf_traj_load_buffer("case.yaml", yaml, strlen(yaml), s, &err) != RF_OK)
        fail_msg("load: %s", err.msg);
}

static void simple_spec(rf_traj_spec *s, double phi_deg, double mur, int sphere)
{
    char mat[128];
    snprintf(mat, sizeof mat, "friction_angle: %.17g, rolling_resistance: %.17g", phi_deg, mur);
    load_spec(s, "[[0, 0], [1, 0]]", mat, sphere ? "shape: sphere, radius: 0.5, density: 2600" : "shape: point, mass: 2",
              "x: 0, y: 0");
}

typedef struct {
    rf_terrain_result res;
    struct rf_terrain_world world;  /* no barriers */
    terrain_run r;
} tc_run;

/* run_contact records the events when set. */
static int record_events = 0;

/* Contact from p with velocity v (put into the tangent plane), spin w (NULL: none for a point, rolling for a sphere). */
static void run_contact(tc_run *c, const rf_traj_spec *s, const rf_terrain *dem, const double p[3], const double v[3],
                        const double *w, size_t max_steps)
{
    memset(c, 0, sizeof *c);
    terrain_run *r = &c->r;
    rf_traj_spec *sp = (rf_traj_spec *)s;
    sp->max_steps = max_steps;
    c->world.dem = (rf_terrain *)dem;
    r->w = &c->world, r->dem = dem, r->s = s, r->res = &c->res, r->g = s->gravity;
    r->mass = s->sphere ? 4.0 / 3.0 * PI * pow(s->radius, 3) * s->density : s->mass;
    r->radius = s->sphere ? s->radius : 0;
    r->inertia = s->sphere ? 0.4 * r->mass * s->radius * s->radius : 0;
    memcpy(r->p, p, sizeof r->p);
    memcpy(r->v, v, sizeof r->v);
    if (w)
        memcpy(r->omega, w, sizeof r->omega);
    else if (s->sphere) { /* rolling: omega = n x v / r */
        double z, n[3];
        assert_true(rf_terrain_height(dem, p[0], p[1], &z, n));
        r->omega[0] = (n[1] * v[2] - n[2] * v[1]) / r->radius;
        r->omega[1] = (n[2] * v[0] - n[0] * v[2]) / r->radius;
        r->omega[2] = (n[0] * v[1] - n[1] * v[0]) / r->radius;
    }
    if (record_events) {
        c->res.events_cap = 64;
        assert_non_null(c->res.events = malloc(c->res.events_cap * sizeof *c->res.events));
    }
    r->phase = TERRAIN_CONTACT;
    terrain_contact_run(r);
}

/* Mechanical energy per unit mass of the run's state [J/kg]. */
static double energy_of(const terrain_run *r)
{
    double e = 0.5 * (r->v[0] * r->v[0] + r->v[1] * r->v[1] + r->v[2] * r->v[2]) + r->g * r->p[2];
    if (r->mass > 0)
        e += 0.5 * r->inertia / r->mass *
             (r->omega[0] * r->omega[0] + r->omega[1] * r->omega[1] + r->omega[2] * r->omega[2]);
    return e;
}

static double speed_of(const terrain_run *r) { return sqrt(r->v[0] * r->v[0] + r->v[1] * r->v[1] + r->v[2] * r->v[2]); }

/* A plane falling at slope angle b towards the azimuth direction (cos az, sin az)
 * [az counter-clockwise from east], nodes every h over [0, L]^2. */
static rf_terrain *plane_dem(double b, double az, double L, double h)
{
    size_t n = (size_t)(L / h + 0.5) + 1;
    double *z = malloc(n * n * sizeof *z);
    for (size_t j = 0; j < n; j++)
        for (size_t i = 0; i < n; i++)
            z[j * n + i] = 200 - tan(b) * ((double)i * h * cos(az) + (double)j * h * sin(az));
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(n, n, 0, 0, h, h, z, &t, &err), RF_OK);
    free(z);
    return t;
}

/* Distance from (x, y) along (cx, cy) to the border of [0, L]^2. */
static double to_border(double x, double y, double cx, double cy, double L)
{
    double d = INFINITY;
    if (cx > 0) d = fmin(d, (L - x) / cx);
    if (cx < 0) d = fmin(d, -x / cx);
    if (cy > 0) d = fmin(d, (L - y) / cy);
    if (cy < 0) d = fmin(d, -y / cy);
    return d;
}

/* Down a plane of slope b, aspect az, from (x0, y0) at speed U0 along the fall
 * line: a = g (sin b - mu cos b) (rolling: 5/7 g (sin b - mu_r cos b)), the
 * block leaves the DEM at distance D = horizontal / cos b along the slope,
 * at time t with D = U0 t + a t^2 / 2, speed U0 + a t, on the fall line. */
static void check_plane(double b, double az, double phi, double mur, int sphere, double U0)
{
    rf_traj_spec s;
    simple_spec(&s, phi, mur, sphere);
    double L = 100, x0 = 50 - 30 * cos(az), y0 = 50 - 30 * sin(az);
    rf_terrain *dem = plane_dem(b, az, L, 5);
    double z0, p[3], v[3] = {U0 * cos(b) * cos(az), U0 * cos(b) * sin(az), -U0 * sin(b)};
    assert_true(rf_terrain_height(dem, x0, y0, &z0, NULL));
    p[0] = x0, p[1] = y0, p[2] = z0;
    tc_run c;
    run_contact(&c, &s, dem, p, v, NULL, 100000);
    double a = sphere ? 5.0 / 7.0 * G * (sin(b) - mur * cos(b)) : G * (sin(b) - tan(phi * DEG) * cos(b));
    double Dh = to_border(x0, y0, cos(az), sin(az), L), D = Dh / cos(b);
    double t = 2 * D / (U0 + sqrt(U0 * U0 + 2 * a * D));
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    assert_close(c.res.t_end, t, 1e-9);
    assert_close(c.res.end[0], x0 + Dh * cos(az), 1e-9);
    assert_close(c.res.end[1], y0 + Dh * sin(az), 1e-9);
    assert_close(c.res.end[2], z0 - Dh * tan(b), 1e-9);
    assert_close(speed_of(&c.r), U0 + a * t, 1e-9);
    /* the direction of travel is the fall line */
    double vh = hypot(c.r.v[0], c.r.v[1]);
    assert_true(fabs(c.r.v[0] / vh - cos(az)) < 1e-12 && fabs(c.r.v[1] / vh - sin(az)) < 1e-12);
    if (sphere) { /* rolling: |omega| = v / r, rotational energy m v^2 / 5 */
        double w = sqrt(c.r.omega[0] * c.r.omega[0] + c.r.omega[1] * c.r.omega[1] + c.r.omega[2] * c.r.omega[2]);
        assert_close(w * s.radius, U0 + a * t, 1e-9);
    }
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

static void test_slide_plane_any_aspect(void **state)
{
    (void)state;
    const double slopes[] = {20, 35, 50}, aspects[] = {0, 30, 90, 145, 200, 290};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 6; k++) {
            check_plane(slopes[i] * DEG, aspects[k] * DEG, 15, 0, 0, 0);
            check_plane(slopes[i] * DEG, aspects[k] * DEG, 15, 0, 0, 3.5);
        }
}

/* A sphere rolls at 5/7 g (sin b - mu_r cos b), with and without rolling resistance. */
static void test_roll_plane(void **state)
{
    (void)state;
    check_plane(20 * DEG, 0, 30, 0, 1, 0);
    check_plane(20 * DEG, 60 * DEG, 30, 0.1, 1, 0);
    check_plane(25 * DEG, 250 * DEG, 35, 0.2, 1, 2);
}

/* Thrown down a gentle plane along the fall line: it stops after U0^2 / (2|a|)
 * (sliding, or rolling against mu_r > tan b) and stays. */
static void test_to_rest_on_plane(void **state)
{
    (void)state;
    for (int sphere = 0; sphere < 2; sphere++) {
        rf_traj_spec s;
        double b = 10 * DEG, az = 40 * DEG, U0 = 4, mu = tan(30 * DEG), mur = 0.3;
        simple_spec(&s, 30, mur, sphere);
        rf_terrain *dem = plane_dem(b, az, 100, 5);
        double p[3] = {30, 30, 0}, v[3] = {U0 * cos(b) * cos(az), U0 * cos(b) * sin(az), -U0 * sin(b)};
        assert_true(rf_terrain_height(dem, p[0], p[1], &p[2], NULL));
        tc_run c;
        run_contact(&c, &s, dem, p, v, NULL, 1000);
        double a = sphere ? 5.0 / 7.0 * G * (sin(b) - mur * cos(b)) : G * (sin(b) - mu * cos(b));
        double D = U0 * U0 / (2 * -a);
        assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
        assert_close(c.res.t_end, U0 / -a, 1e-9);
        assert_close(c.res.end[0], 30 + D * cos(b) * cos(az), 1e-9);
        assert_close(c.res.end[1], 30 + D * cos(b) * sin(az), 1e-9);
        assert_true(speed_of(&c.r) == 0);
        rf_terrain_free(dem);
        rf_traj_spec_free(&s);
    }
}

/* A sphere spinning forward at twice the rolling rate, thrown down a 50 deg
 * plane (tan b > 3.5 mu: it cannot roll): its slip -U0 is first driven to 0
 * by friction pushing it forward, a1 = g (sin b + mu cos b), in
 * tau1 = U0 / (g sin b + mu g cos b (1 + 1/k)), k = 2/5; then it slides
 * with a2 = g (sin b - mu cos b) and leaves the DEM 30 m down the slope
 * (horizontally) at the time the two stretches give. */
static void test_sliding_sphere_topspin(void **state)
{
    (void)state;
    double b = 50 * DEG, az = 120 * DEG, mu = tan(15 * DEG), U0 = 3;
    rf_traj_spec s;
    simple_spec(&s, 15, 0, 1);
    rf_terrain *dem = plane_dem(b, az, 100, 5);
    double x0 = 50 - 30 * cos(az), y0 = 50 - 30 * sin(az), p[3] = {x0, y0, 0};
    double v[3] = {U0 * cos(b) * cos(az), U0 * cos(b) * sin(az), -U0 * sin(b)}, n[3], w[3];
    assert_true(rf_terrain_height(dem, x0, y0, &p[2], n));
    w[0] = 2 * (n[1] * v[2] - n[2] * v[1]) / s.radius; /* 2 n x v / r */
    w[1] = 2 * (n[2] * v[0] - n[0] * v[2]) / s.radius;
    w[2] = 2 * (n[0] * v[1] - n[1] * v[0]) / s.radius;
    tc_run c;
    run_contact(&c, &s, dem, p, v, w, 1000);
    double a1 = G * (sin(b) + mu * cos(b)), tau1 = U0 / (G * sin(b) + mu * G * cos(b) * 3.5);
    double d1 = U0 * tau1 + 0.5 * a1 * tau1 * tau1, v1 = U0 + a1 * tau1, a2 = G * (sin(b) - mu * cos(b));
    double D = to_border(x0, y0, cos(az), sin(az), 100) / cos(b) - d1;
    double t2 = 2 * D / (v1 + sqrt(v1 * v1 + 2 * a2 * D));
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    assert_close(c.res.t_end, tau1 + t2, 1e-9);
    assert_close(speed_of(&c.r), v1 + a2 * t2, 1e-9);
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

/* Extruded profile: z(x) at nodes every h in x, any y; ny nodes 0..(ny-1) h. */
static rf_terrain *profile_dem(const double *px, const double *pz, size_t np, double h, size_t nx, size_t ny, int along_y)
{
    double *z = malloc(nx * ny * sizeof *z);
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++) {
            double x = (double)(along_y ? j : i) * h, zz = pz[np - 1];
            for (size_t k = 0; k + 1 < np; k++)
                if (x >= px[k] && x <= px[k + 1]) {
                    zz = pz[k] + (pz[k + 1] - pz[k]) * (x - px[k]) / (px[k + 1] - px[k]);
                    break;
                }
            z[j * nx + i] = zz;
        }
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(nx, ny, 0, 0, h, h, z, &t, &err), RF_OK);
    free(z);
    return t;
}

/* Down a plane onto flat ground: at the concave edge the speed is
 * sqrt(2 a D) cos b (the part along the floor), then it stops after
 * (v cos b)^2 / (2 mu g), at t = t_edge + v cos b / (mu g); the profile along
 * x and along y (south to north). */
static void test_plane_to_flat(void **state)
{
    (void)state;
    double b = 30 * DEG, phi = 20;
    double px[3] = {0, 40, 200}, pz[3] = {40 * tan(b), 0, 0};
    for (int along_y = 0; along_y < 2; along_y++) {
        rf_traj_spec s;
        simple_spec(&s, phi, 0, 0);
        rf_terrain *dem = profile_dem(px, pz, 3, 5, along_y ? 5 : 41, along_y ? 41 : 5, along_y);
        double xs = 10, p[3] = {along_y ? 12 : xs, along_y ? xs : 12, (40 - xs) * tan(b)}, v[3] = {0, 0, 0};
        tc_run c;
        run_contact(&c, &s, dem, p, v, NULL, 1000);
        double mu = tan(phi * DEG), a = G * (sin(b) - mu * cos(b)), D = 30 / cos(b);
        double ve = sqrt(2 * a * D) * cos(b), run = ve * ve / (2 * mu * G);
        assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
        assert_close(c.res.end[along_y], 40 + run, 1e-9);
        assert_close(c.res.end[!along_y], 12, 1e-12);
        assert_true(fabs(c.res.end[2]) < 1e-12);
        assert_close(c.res.t_end, sqrt(2 * D / a) + ve / (mu * G), 1e-9);
        rf_terrain_free(dem);
        rf_traj_spec_free(&s);
    }
}

/* A V valley with sides of 45 and 60 deg (and 45/45, 60/60), along y or
 * along x: from rest on a side the block slides down to the valley line
 * and stops there, at t = sqrt(2 L / a) (docs/trajectories.md, the notch). */
static void check_valley(double left, double right, int start_right, int along_x, int sphere)
{
    rf_traj_spec s;
    double phi = 10, mu = tan(phi * DEG);
    simple_spec(&s, phi, 0.05, sphere);
    double px[3] = {0, 40, 80}, pz[3] = {40 * tan(left * DEG), 0, 40 * tan(right * DEG)};
    rf_terrain *dem = profile_dem(px, pz, 3, 5, along_x ? 9 : 17, along_x ? 17 : 9, along_x);
    double side = start_right ? right : left, xs = start_right ? 60 : 25, d = fabs(xs - 40);
    double p[3] = {along_x ? 22 : xs, along_x ? xs : 22, d * tan(side * DEG)}, v[3] = {0, 0, 0};
    tc_run c;
    run_contact(&c, &s, dem, p, v, NULL, 1000);
    double sb = sin(side * DEG), cb = cos(side * DEG), L = d / cb;
    int rolling = sphere && tan(side * DEG) <= 3.5 * mu;
    double a = rolling ? 5.0 / 7.0 * G * (sb - 0.05 * cb) : G * (sb - mu * cb);
    assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
    assert_close(c.res.end[along_x], 40, 1e-12);
    assert_close(c.res.end[!along_x], 22, 1e-12);
    assert_true(fabs(c.res.end[2]) < 1e-9);
    assert_close(c.res.t_end, sqrt(2 * L / a), 1e-9); /* a sliding sphere's spin does not change its path */
    assert_true(c.res.n_steps < 10);
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

static void test_valley_stops(void **state)
{
    (void)state;
    for (int along_x = 0; along_x < 2; along_x++)
        for (int right = 0; right < 2; right++) {
            check_valley(45, 60, right, along_x, 0);
            check_valley(45, 45, right, along_x, 0);
            check_valley(60, 60, right, along_x, 0);
            check_valley(45, 60, right, along_x, 1);
        }
}

/* A V valley (sides of slope s = tan 60 deg) whose valley line falls at
 * slope q to the south: from rest on the line the block slides along it
 * pressed into both faces, each with N = g sqrt(1 + s^2 + q^2) / (2 (1 + q^2))
 * (by symmetry), so a = g q / sqrt(1 + q^2) - mu g sqrt(1 + s^2 + q^2) / (1 + q^2)
 * and it leaves the DEM at y = 0 at t = sqrt(2 L / a), L = y0 sqrt(1 + q^2).
 * From rest on a side it reaches the line and leaves the DEM along it. */
static void test_sloping_valley(void **state)
{
    (void)state;
    double sv = tan(60 * DEG), q = tan(25 * DEG), phi = 8, mu = tan(phi * DEG), h = 5;
    size_t nx = 17, ny = 21;
    double *z = malloc(nx * ny * sizeof *z);
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++)
            z[j * nx + i] = fabs((double)i * h - 40) * sv + (double)j * h * q;
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(nx, ny, 0, 0, h, h, z, &dem, &err), RF_OK);
    free(z);
    rf_traj_spec s;
    simple_spec(&s, phi, 0, 0);
    double y0 = 90, p[3] = {40, y0, y0 * q}, v[3] = {0, 0, 0};
    tc_run c;
    run_contact(&c, &s, dem, p, v, NULL, 1000);
    double a = G * q / sqrt(1 + q * q) - mu * G * sqrt(1 + sv * sv + q * q) / (1 + q * q), L = y0 * sqrt(1 + q * q);
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    assert_close(c.res.t_end, sqrt(2 * L / a), 1e-9);
    assert_close(c.res.end[0], 40, 1e-12);
    assert_true(fabs(c.res.end[1]) < 1e-9);
    /* from rest on the west face */
    double p2[3] = {27, 80, 13 * sv + 80 * q};
    run_contact(&c, &s, dem, p2, v, NULL, 1000);
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    assert_close(c.res.end[0], 40, 1e-12);
    assert_true(fabs(c.res.end[1]) < 1e-9);
    assert_true(c.res.n_steps < 100);
    /* a steeper friction angle than the line: it stops on it */
    rf_traj_spec_free(&s);
    simple_spec(&s, 40, 0, 0);
    run_contact(&c, &s, dem, p, v, NULL, 1000);
    assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
    assert_true(c.res.t_end == 0);
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

/* Thrown obliquely into a level V (sides 50 deg): it curves down the face,
 * enters the valley line and slides along it to rest there. */
static void test_valley_oblique(void **state)
{
    (void)state;
    rf_traj_spec s;
    simple_spec(&s, 20, 0, 0);
    double px[3] = {0, 40, 80}, pz[3] = {40 * tan(50 * DEG), 0, 40 * tan(50 * DEG)};
    rf_terrain *dem = profile_dem(px, pz, 3, 5, 17, 41, 0);
    double p[3] = {30, 30, 10 * tan(50 * DEG)}, v[3] = {0, 6, 0};
    tc_run c;
    run_contact(&c, &s, dem, p, v, NULL, 10000);
    assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
    assert_close(c.res.end[0], 40, 1e-12);
    assert_true(c.res.end[1] > 30 && fabs(c.res.end[2]) < 1e-9);
    assert_true(c.res.n_steps < 2000);
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

/* A V valley (sides of slope 1.2, valley line level or falling at 0.3)
 * turned 30 and 45 deg to the grid: its bottom runs through curved cells and
 * across nodes where the cells' fall lines meet.  From 60 starts on its
 * sides, points and spheres never end in the step limit (issue 31 item 2 in
 * 2D): each stops, leaves the DEM or is launched, and no energy is gained. */
static void test_rotated_valley(void **state)
{
    (void)state;
    const double rots[2] = {30, 45}, slopes[2] = {0, 0.3};
    size_t n = 101;
    double h = 2, *z = malloc(n * n * sizeof *z);
    uint64_t seed = 7;
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) {
            double rot = rots[a] * DEG;
            for (size_t j = 0; j < n; j++)
                for (size_t i = 0; i < n; i++) {
                    double x = (double)i * h - 100, y = (double)j * h - 100;
                    z[j * n + i] = 300 + 1.2 * fabs(x * cos(rot) + y * sin(rot)) + slopes[b] * (y * cos(rot) - x * sin(rot));
                }
            rf_terrain *dem;
            rf_error err;
            assert_int_equal(rf_terrain_from_nodes(n, n, 0, 0, h, h, z, &dem, &err), RF_OK);
            for (int sphere = 0; sphere < 2; sphere++) {
                rf_traj_spec s;
                simple_spec(&s, 25, 0.1, sphere);
                for (int k = 0; k < 15; k++) {
                    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
                    double u1 = (double)(seed >> 11) / 9007199254740992.0;
                    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
                    double u2 = (double)(seed >> 11) / 9007199254740992.0;
                    double p[3] = {30 + 140 * u1, 30 + 140 * u2, 0}, v[3] = {0, 0, 0};
                    assert_true(rf_terrain_height(dem, p[0], p[1], &p[2], NULL));
                    tc_run c;
                    run_contact(&c, &s, dem, p, v, NULL, 20000);
                    if (c.r.phase != TERRAIN_FLY && c.res.state == RF_TRAJ_STEP_LIMIT)
                        fail_msg("rot %g slope %g sphere %d: from (%g, %g) the step limit", rots[a], slopes[b], sphere,
                                 p[0], p[1]);
                    assert_true(energy_of(&c.r) <= G * p[2] * (1 + 1e-12));
                }
                rf_traj_spec_free(&s);
            }
            rf_terrain_free(dem);
        }
    free(z);
}

/* The law on a plane of normal n (a second, brute-force method): the
 * derivative of the state (p, v, omega) for a point or sliding sphere
 * (friction against the slip v + r n x omega, spin rate mu N m r (n x s^)/I)
 * or a rolling sphere ((g_t - mu_r N v^) / (1 + k)). */
static void plane_law(const double n[3], double mu, double mur, int sphere, int rolling, double r, const double y[9],
                      double dy[9])
{
    double N = G * n[2], gt[3] = {G * n[2] * n[0], G * n[2] * n[1], -G + G * n[2] * n[2]}, e[3];
    const double *v = y + 3, *w = y + 6;
    double sp = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    memcpy(dy, v, 3 * sizeof *dy);
    memset(dy + 6, 0, 3 * sizeof *dy);
    if (rolling) {
        for (int q = 0; q < 3; q++)
            dy[3 + q] = (gt[q] - mur * N * v[q] / sp) / 1.4;
        return;
    }
    double s[3] = {v[0], v[1], v[2]};
    if (sphere) {
        s[0] += r * (n[1] * w[2] - n[2] * w[1]);
        s[1] += r * (n[2] * w[0] - n[0] * w[2]);
        s[2] += r * (n[0] * w[1] - n[1] * w[0]);
    }
    double ss = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int q = 0; q < 3; q++)
        e[q] = s[q] / ss, dy[3 + q] = gt[q] - mu * N * e[q];
    if (sphere) { /* m r / I = 1 / (0.4 r) */
        double f = mu * N / (0.4 * r);
        dy[6] = f * (n[1] * e[2] - n[2] * e[1]);
        dy[7] = f * (n[2] * e[0] - n[0] * e[2]);
        dy[8] = f * (n[0] * e[1] - n[1] * e[0]);
    }
}

/* Thrown across the fall line of a plane falling to the south, the block
 * curves towards the fall line: against a fine fixed-step RK4 integration of
 * the same law (plane_law), where it leaves the DEM (y = 0). */
static void check_across(double bdeg, double phi, double mur, int sphere, int rolling)
{
    double b = bdeg * DEG, mu = tan(phi * DEG), U0 = 8;
    rf_traj_spec s;
    simple_spec(&s, phi, mur, sphere);
    rf_terrain *dem = plane_dem(b, -PI / 2, 100, 5); /* z = 200 + tan b y */
    double p[3] = {20, 90, 200 + 90 * tan(b)}, v[3] = {U0, 0, 0}, w0[3] = {0, 0, 0};
    tc_run c;
    run_contact(&c, &s, dem, p, v, rolling ? NULL : w0, 100000);
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    double n[3] = {0, -sin(b), cos(b)}, y[9] = {20, 90, 0, U0, 0, 0, 0, 0, 0}, t = 0, dt = 1e-5;
    if (rolling)
        y[6] = 0, y[7] = n[2] * U0 / s.radius, y[8] = -n[1] * U0 / s.radius;
    for (;;) {
        double k[4][9], z[9];
        plane_law(n, mu, mur, sphere, rolling, s.radius, y, k[0]);
        for (int m = 1; m < 4; m++) {
            for (int q = 0; q < 9; q++)
                z[q] = y[q] + (m == 3 ? 1 : 0.5) * dt * k[m - 1][q];
            plane_law(n, mu, mur, sphere, rolling, s.radius, z, k[m]);
        }
        double yn[9];
        for (int q = 0; q < 9; q++)
            yn[q] = y[q] + dt / 6 * (k[0][q] + 2 * k[1][q] + 2 * k[2][q] + k[3][q]);
        if (yn[1] <= 0) { /* linear to the border */
            double f = y[1] / (y[1] - yn[1]);
            y[0] += f * (yn[0] - y[0]), t += f * dt;
            break;
        }
        memcpy(y, yn, sizeof y);
        t += dt;
    }
    /* the steps' error control targets CC_TOL = 1e-3 of the velocity per step */
    assert_close(c.res.t_end, t, 2e-3);
    assert_close(c.res.end[0], y[0], 2e-3);
    assert_true(fabs(c.res.end[0] - y[0]) < 0.01 * (y[0] - 20));
    /* curving towards the fall line: at the end within 45 deg of it */
    assert_true(atan2(fabs(c.r.v[0]), -c.r.v[1]) < 45 * DEG);
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

static void test_across_fall_line(void **state)
{
    (void)state;
    check_across(30, 15, 0, 0, 0);   /* a sliding point */
    check_across(20, 30, 0.1, 1, 1); /* a rolling sphere */
    check_across(50, 15, 0, 1, 0);   /* a sliding sphere spun up by friction (tan b > 3.5 mu) */
}

/* Mechanical energy after k steps never exceeds that after k - 1 (the run is
 * deterministic, so max_steps = k gives the state after k steps). */
static void check_energy_steps(const rf_traj_spec *s, const rf_terrain *dem, const double p[3], const double v[3],
                               const double *w, size_t kmax)
{
    tc_run c;
    run_contact(&c, s, dem, p, v, w, 0); /* the state put on the surface, before any step */
    double prev = energy_of(&c.r);
    for (size_t k = 1; k <= kmax; k++) {
        run_contact(&c, s, dem, p, v, w, k);
        double e = energy_of(&c.r);
        if (!(e <= prev + 1e-9 * (fabs(prev) + 1)))
            fail_msg("step %zu: energy rises from %.17g to %.17g J/kg", k, prev, e);
        prev = e;
        if (c.res.state != RF_TRAJ_STEP_LIMIT)
            break;
    }
}

/* Random bilinear terrain, random starts, a point and a sphere: no energy gained. */
static void test_energy_random_terrain(void **state)
{
    (void)state;
    uint64_t seed = 12345;
#define RND() ((double)((seed = seed * 6364136223846793005ULL + 1442695040888963407ULL) >> 11) / 9007199254740992.0)
    size_t n = 12;
    double h = 4, z[144];
    for (size_t j = 0; j < n; j++)
        for (size_t i = 0; i < n; i++)
            z[j * n + i] = 60 - 0.6 * (double)i * h - 0.2 * (double)j * h + 3 * RND();
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(n, n, 0, 0, h, h, z, &dem, &err), RF_OK);
    for (int sphere = 0; sphere < 2; sphere++) {
        rf_traj_spec s;
        simple_spec(&s, 5 + 20 * RND(), 0.05, sphere);
        for (int k = 0; k < 12; k++) {
            double p[3] = {2 + 20 * RND(), 2 + 40 * RND(), 0}, v[3] = {8 * RND() - 2, 8 * RND() - 4, 0};
            assert_true(rf_terrain_height(dem, p[0], p[1], &p[2], NULL));
            double w[3] = {20 * RND() - 10, 20 * RND() - 10, 20 * RND() - 10};
            check_energy_steps(&s, dem, p, v, sphere ? w : NULL, 300);
        }
        rf_traj_spec_free(&s);
    }
    rf_terrain_free(dem);
#undef RND
}

/* A convex edge (10 deg onto 40 deg) launches the block at any speed with
 * its velocity along the old slope (the 2D rule); the launch is flown inside
 * the contact phase (terrain_contact.c hop) and lands on the 40 deg face
 * where the parabola meets its plane: from (40, z40) with velocity (U, W),
 * z40 + W t - g t^2 / 2 = z40 - tan(40 deg) U t, t = 2 (W + U tan 40) / g. */
static void test_convex_edge_launch(void **state)
{
    (void)state;
    rf_traj_spec s;
    simple_spec(&s, 5, 0, 0);
    double px[3] = {0, 40, 100}, pz[3] = {60, 60 - 40 * tan(10 * DEG), 60 - 40 * tan(10 * DEG) - 60 * tan(40 * DEG)};
    rf_terrain *dem = profile_dem(px, pz, 3, 5, 21, 5, 0);
    double U = 0.5, p[3] = {30, 10, 60 - 30 * tan(10 * DEG)}, v[3] = {U * cos(10 * DEG), 0, -U * sin(10 * DEG)};
    tc_run c;
    record_events = 1;
    run_contact(&c, &s, dem, p, v, NULL, 1000);
    record_events = 0;
    const rf_terrain_event *e = c.res.events, *end = e + c.res.n_events;
    while (e < end && e->kind != RF_EV_LAUNCH)
        e++;
    assert_true(e < end && e->flying);
    assert_close(e->p[0], 40, 1e-12);
    assert_close(-e->v[2] / e->v[0], tan(10 * DEG), 1e-9);
    double a = G * (sin(10 * DEG) - tan(5 * DEG) * cos(10 * DEG));
    double V = sqrt(e->v[0] * e->v[0] + e->v[2] * e->v[2]);
    assert_close(V, sqrt(U * U + 2 * a * 10 / cos(10 * DEG)), 1e-9);
    /* the landing: the next event, at the parabola's meeting with the 40 deg plane */
    assert_true(e + 1 < end);
    double tf = 2 * (e->v[2] + tan(40 * DEG) * e->v[0]) / G;
    assert_true(tf > 0);
    assert_close(e[1].t - e->t, tf, 1e-9);
    assert_close(e[1].p[0], 40 + e->v[0] * tf, 1e-9);
    assert_close(e[1].p[2], pz[1] - tan(40 * DEG) * e->v[0] * tf, 1e-9);
    assert_close(e[1].p[1], 10, 1e-12);
    assert_true(c.res.n_steps >= 2); /* the flight and the landing are counted as the state machine counts phases */
    free(c.res.events);
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

/* The ridge z = d X Y (d < 0) of one cell: along its diagonal the ground is
 * the parabola z = d s^2 / 2, and N = (g + d v_h^2) / |grad F| (v_h the
 * horizontal speed) is positive everywhere on the way down iff it is at the
 * start (on a parabola the sign of N does not change: g > |d| v_h^2 <=>
 * g > |d| v_0^2, v_0 the speed at the top).  Faster than sqrt(g / |d|): it
 * is launched at once; slower: it slides to the far corner and leaves the
 * DEM without a launch. */
static void test_ridge_launch(void **state)
{
    (void)state;
    double d = -0.05, L = 20, vc = sqrt(G / -d);
    double z[4] = {0, 0, 0, d * L * L};
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(2, 2, 0, 0, L, L, z, &dem, &err), RF_OK);
    rf_traj_spec s;
    simple_spec(&s, 0, 0, 0);
    const double s0[2] = {0, 5}, f[2] = {0.98, 1.02};
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 2; k++) {
            double X = s0[i] / sqrt(2), vh = sqrt(f[k]) * vc, vx = vh / sqrt(2);
            double p[3] = {X, X, d * X * X}, v[3] = {vx, vx, 2 * d * X * vx};
            tc_run c;
            run_contact(&c, &s, dem, p, v, NULL, 100000);
            if (f[k] > 1) {
                assert_int_equal(c.r.phase, TERRAIN_FLY);
                assert_true(c.r.t == 0);
            } else {
                assert_int_equal(c.r.phase, TERRAIN_DONE);
                assert_int_equal(c.res.state, RF_TRAJ_EXITED);
                assert_close(c.res.end[0], L, 1e-9);
                assert_close(c.res.end[1], L, 1e-6); /* the diagonal, to the steps' accuracy */
            }
        }
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

/* Leaving the DEM, entering a no-data cell, the step limit. */
static void test_exit_nodata_steplimit(void **state)
{
    (void)state;
    rf_traj_spec s;
    simple_spec(&s, 10, 0, 0);
    double z[25];
    for (int j = 0; j < 5; j++)
        for (int i = 0; i < 5; i++)
            z[j * 5 + i] = 40 - 5.0 * i;
    z[2 * 5 + 3] = NAN; /* node (3, 2): cells (2..3, 1..2) have no data */
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(5, 5, 0, 0, 10, 10, z, &dem, &err), RF_OK);
    double p[3] = {5, 15, 37.5}, v[3] = {0, 0, 0};
    tc_run c;
    run_contact(&c, &s, dem, p, v, NULL, 1000);
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    assert_close(c.res.end[0], 20, 1e-12); /* the edge of the no-data cell */
    double p2[3] = {5, 35, 37.5};
    run_contact(&c, &s, dem, p2, v, NULL, 1000);
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    assert_close(c.res.end[0], 40, 1e-12); /* the DEM's border */
    run_contact(&c, &s, dem, p2, v, NULL, 2);
    assert_int_equal(c.res.state, RF_TRAJ_STEP_LIMIT);
    assert_int_equal(c.res.n_steps, 3);
    rf_terrain_free(dem);
    rf_traj_spec_free(&s);
}

/* The 2D engine on a profile and the contact on the same profile extruded
 * across y (release in the x-z plane): same rest point and time to 1e-9. */
static void check_extruded(const char *points, const double *px, const double *pz, size_t np, double x0,
                           const char *material, const char *block, double vx0)
{
    char rel[128];
    double z0 = pz[0];
    for (size_t k = 0; k + 1 < np; k++)
        if (x0 >= px[k] && x0 <= px[k + 1])
            z0 = pz[k] + (pz[k + 1] - pz[k]) * (x0 - px[k]) / (px[k + 1] - px[k]);
    double slope = 0;
    for (size_t k = 0; k + 1 < np; k++)
        if (x0 >= px[k] && x0 < px[k + 1])
            slope = (pz[k + 1] - pz[k]) / (px[k + 1] - px[k]);
    snprintf(rel, sizeof rel, "x: %.17g, y: %.17g, vx: %.17g, vy: %.17g", x0, z0, vx0, vx0 * slope);
    rf_traj_spec s;
    load_spec(&s, points, material, block, rel);
    rf_traj_world *w;
    rf_error err;
    assert_int_equal(rf_traj_world_create(&s, &w, &err), RF_OK);
    rf_traj_result r2;
    memset(&r2, 0, sizeof r2);
    assert_int_equal(rf_traj_simulate(w, &s, 1, 0, &r2, &err), RF_OK);
    rf_terrain *dem = profile_dem(px, pz, np, 5, (size_t)(px[np - 1] / 5 + 1.5), 5, 0);
    double p[3] = {x0, 10, z0}, v[3] = {vx0, 0, vx0 * slope};
    tc_run c;
    run_contact(&c, &s, dem, p, v, NULL, 10000);
    assert_int_equal(c.res.state, r2.state);
    assert_close(c.res.end[0], r2.x_end, 1e-9);
    assert_close(c.res.end[2], r2.y_end, 1e-9);
    assert_close(c.res.t_end, r2.t_end, 1e-9);
    assert_close(c.res.end[1], 10, 1e-12);
    rf_terrain_free(dem);
    rf_traj_world_free(w);
    rf_traj_spec_free(&s);
}

static void test_extruded_2d(void **state)
{
    (void)state;
    const double px1[4] = {0, 40, 60, 100}, pz1[4] = {40, 20, 15, 15};
    const char *p1 = "[[0, 40], [40, 20], [60, 15], [100, 15]]";
    check_extruded(p1, px1, pz1, 4, 2, "friction_angle: 12", "shape: point, mass: 2", 0);
    check_extruded(p1, px1, pz1, 4, 7, "friction_angle: 20", "shape: point, mass: 2", 3);
    check_extruded(p1, px1, pz1, 4, 2, "friction_angle: 30, rolling_resistance: 0.15",
                   "shape: sphere, radius: 0.4, density: 2700", 0);
    /* down, across a floor, up a rise it cannot climb, back: rest on the floor */
    const double px2[5] = {0, 20, 40, 60, 100}, pz2[5] = {20, 0, 0, 10, 10};
    const char *p2 = "[[0, 20], [20, 0], [40, 0], [60, 10], [100, 10]]";
    check_extruded(p2, px2, pz2, 5, 3, "friction_angle: 14", "shape: point, mass: 2", 0);
    check_extruded(p2, px2, pz2, 5, 3, "friction_angle: 30, rolling_resistance: 0.05",
                   "shape: sphere, radius: 0.5, density: 2600", 0);
    /* a V notch (45 / 60 deg): rest at the vertex; a sliding sphere (tan 60 > 3.5 mu) */
    const double px3[3] = {0, 40, 80}, pz3[3] = {40, 0, 40 * 1.7320508075688772};
    const char *p3 = "[[0, 40], [40, 0], [80, 69.282032302755088]]";
    check_extruded(p3, px3, pz3, 3, 10, "friction_angle: 10", "shape: point, mass: 2", 0);
    check_extruded(p3, px3, pz3, 3, 70, "friction_angle: 10", "shape: sphere, radius: 0.5, density: 2600", 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slide_plane_any_aspect),
        cmocka_unit_test(test_roll_plane),
        cmocka_unit_test(test_to_rest_on_plane),
        cmocka_unit_test(test_sliding_sphere_topspin),
        cmocka_unit_test(test_plane_to_flat),
        cmocka_unit_test(test_valley_stops),
        cmocka_unit_test(test_sloping_valley),
        cmocka_unit_test(test_valley_oblique),
        cmocka_unit_test(test_rotated_valley),
        cmocka_unit_test(test_across_fall_line),
        cmocka_unit_test(test_energy_random_terrain),
        cmocka_unit_test(test_convex_edge_launch),
        cmocka_unit_test(test_ridge_launch),
        cmocka_unit_test(test_exit_nodata_steplimit),
        cmocka_unit_test(test_extruded_2d),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
