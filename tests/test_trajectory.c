/* test_trajectory.c - the trajectory engine against closed forms derived by
 * hand (docs/trajectories.md sec. 6): flight off a ledge, a vertical wall,
 * the geometric series of bounces, sliding down an incline onto a floor,
 * sliding to rest, rolling, a convex break that is overflown, leaving the
 * profile, velocity scaling at its reference speed, the rigid sphere against
 * src/impact's rigid model, and energy never gained. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/impact.h"
#include "rockfuzz/trajectory.h"
#include "test_traj_util.h"
#include "test_util.h"

#define G 9.81
#define DEG (3.14159265358979323846 / 180.0)

/* Thrown from (x0, y0) = (-0.5, 20.5) at (5, 2) m/s off a 20 m ledge onto flat
 * ground: T = (vy + sqrt(vy^2 + 2 g y0)) / g, x = x0 + vx T, v_n = sqrt(vy^2 + 2 g y0);
 * after: (R_t vx, R_n v_n); rebound apex R_n^2 v_n^2 / (2 g); collector at
 * x = 6: t = 6.5/5, height y0 + vy t - g t^2/2, KE m (vx^2 + (vy - g t)^2)/2. */
static void test_ledge(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[-10, 20], [0, 20], [0, 0], [100, 0]], materials: [rock, rock, rock]}\n"
                 "materials: {rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}}\n"
                 "block: {shape: point, mass: 1000}\n"
                 "release: {x: -0.5, y: 20.5, vx: 5, vy: 2}\n"
                 "collectors: [{name: barrier, x: 6}]\n");
    double vy = 2, y0 = 20.5, vn = sqrt(vy * vy + 2 * G * y0), T = (vy + vn) / G;
    assert_true(c.res.n_impacts >= 1);
    rf_traj_impact *m = &c.res.impacts[0];
    assert_int_equal(m->segment, 2);
    assert_close(m->t, T, 1e-12);
    assert_close(m->x, -0.5 + 5 * T, 1e-12);
    assert_true(m->y == 0);
    assert_close(m->vy_in, -vn, 1e-12);
    assert_close(m->vx_out, 0.7 * 5, 1e-12);
    assert_close(m->vy_out, 0.4 * vn, 1e-12);
    assert_close(c.res.rebound_height, 0.16 * vn * vn / (2 * G), 1e-12);
    double tc = 6.5 / 5, vyc = vy - G * tc;
    assert_true(c.cross[0].reached);
    assert_close(c.cross[0].t, tc, 1e-12);
    assert_close(c.cross[0].height_lowest, y0 + vy * tc - 0.5 * G * tc * tc, 1e-12);
    assert_close(c.cross[0].normal_height, c.cross[0].height_lowest, 1e-12);
    assert_close(c.cross[0].translational_energy, 500 * (25 + vyc * vyc), 1e-12);
    assert_true(c.cross[0].rotational_energy == 0);
    assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
    traj_case_free(&c);
}

/* A vertical wall at x = 10 (0..5 m): from (2, 1) at (10, 5) it is hit at
 * t = 0.8, y = 1 + 4 - g 0.32; v_n = -10 -> +R_n 10 to the left, v_t along the
 * wall (up) = 5 - 0.8 g -> R_t times it. */
static void test_vertical_wall(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[0, 0], [10, 0], [10, 5], [20, 5]], material: rock}\n"
                 "materials: {rock: {R_n: 0.5, R_t: 0.8, friction_angle: 30}}\n"
                 "block: {shape: point, mass: 1}\n"
                 "release: {x: 2, y: 1, vx: 10, vy: 5}\n");
    rf_traj_impact *m = &c.res.impacts[0];
    assert_int_equal(m->segment, 1);
    assert_close(m->t, 0.8, 1e-12);
    assert_close(m->x, 10, 1e-15);
    assert_close(m->y, 5 - 0.32 * G, 1e-12);
    assert_close(m->vx_out, -5, 1e-12);
    assert_close(m->vy_out, 0.8 * (5 - 0.8 * G), 1e-12);
    traj_case_free(&c);
}

/* Dropped at (0, h) with vx = U on flat ground: impact k (k >= 1) at
 * x_k = U T0 + (2 U v0 / g) sum_{j=1}^{k-1} (R_n R_t)^j, t_k = T0 + (2 v0/g)
 * sum_{j=1}^{k-1} R_n^j, with v0 = sqrt(2 g h), T0 = v0/g; bouncing stops at
 * the first impact K whose rebound R_n^K v0 < contact_speed: from there it
 * slides v^2/(2 mu g) with v = R_t^K U. */
static void test_bounce_series(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[-1, 0], [1000, 0]], material: m}\n"
                 "materials: {m: {R_n: 0.6, R_t: 0.9, friction_angle: 45}}\n"
                 "block: {shape: point, mass: 1}\n"
                 "release: {x: 0, y: 5, vx: 3, vy: 0}\n"
                 "bounce: {law: constant, contact_speed: 0.001}\n"
                 "stop: {v_stop: 0}\n");
    double Rn = 0.6, Rt = 0.9, U = 3, v0 = sqrt(2 * G * 5), T0 = v0 / G;
    double x = U * T0, t = T0, vn = v0, vt = U;
    size_t K = 0;
    for (;;) {
        if (K >= c.res.n_impacts)
            fail_msg("only %zu impacts, expected more", c.res.n_impacts);
        rf_traj_impact *m = &c.res.impacts[K];
        assert_close(m->x, x, 1e-9);
        assert_close(m->t, t, 1e-9);
        assert_close(m->vy_out, Rn * vn, 1e-9);
        vn *= Rn, vt *= Rt, K++;
        if (vn < 0.001)
            break; /* rebound slower than contact_speed: it stays on the ground here */
        x += vt * 2 * vn / G, t += 2 * vn / G;
    }
    assert_int_equal(c.res.n_impacts, K);
    /* the limit of the series: x_inf = U T0 + (2 U v0/g) rho/(1 - rho) */
    double rho = Rn * Rt, xinf = U * T0 + 2 * U * v0 / G * rho / (1 - rho);
    assert_true(fabs(x - xinf) < 2 * U * v0 / G * pow(rho, (double)K) / (1 - rho) + 1e-12);
    assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
    assert_close(c.res.x_end, x + vt * vt / (2 * G * 1.0), 1e-9);
    traj_case_free(&c);
}

/* From rest at the top of a 3:4 incline (beta = atan(3/4), D = 5 m) onto a
 * floor: a = g (sin b - mu cos b), v_toe = sqrt(2 a D), t_toe = sqrt(2 D / a);
 * after the concave kink v' = v_toe cos b; runout v'^2 / (2 mu g). */
static void test_slide_incline_floor(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[0, 3], [4, 0], [100, 0]], material: m}\n"
                 "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 20}}\n"
                 "block: {shape: point, mass: 2}\n"
                 "release: {x: 0, y: 3, vx: 0, vy: 0}\n"
                 "collectors: [{name: slope, x: 2}, {name: floor, x: 5}]\n");
    double b = atan2(3, 4), mu = tan(20 * DEG), a = G * (sin(b) - mu * cos(b));
    double vtoe = sqrt(2 * a * 5), ttoe = sqrt(2 * 5 / a), v1 = vtoe * cos(b);
    double run = v1 * v1 / (2 * mu * G);
    assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
    assert_int_equal(c.res.n_impacts, 0);
    assert_close(c.res.x_end, 4 + run, 1e-9);
    assert_close(c.res.t_end, ttoe + v1 / (mu * G), 1e-9);
    assert_true(c.res.y_end == 0);
    assert_close(c.cross[0].speed, sqrt(2 * a * 2.5), 1e-9);   /* x = 2: half way, 2.5 m along */
    assert_true(fabs(c.cross[0].height_lowest) < 1e-12);
    assert_close(c.cross[1].speed, sqrt(v1 * v1 - 2 * mu * G * 1), 1e-9);
    traj_case_free(&c);
}

/* Thrown down a gentle incline (10 deg, mu = tan 30) at 4 m/s along it:
 * a = g (sin b - mu cos b) < 0, rest after v^2/(2|a|), and it stays. */
static void test_slide_to_rest(void **state)
{
    (void)state;
    traj_case c;
    double b = 10 * DEG, v = 4;
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[0, %.17g], [100, 0]], material: m}\n"
             "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30}}\n"
             "block: {shape: point, mass: 2}\n"
             "release: {x: 10, y: %.17g, vx: %.17g, vy: %.17g}\n",
             100 * tan(b), 90 * tan(b), v * cos(b), -v * sin(b));
    traj_case_run(&c, yaml);
    double a = G * (sin(b) - tan(30 * DEG) * cos(b));
    assert_int_equal(c.res.state, RF_TRAJ_STOPPED);
    assert_close(c.res.x_end, 10 + v * v / (2 * -a) * cos(b), 1e-9);
    assert_close(c.res.t_end, v / -a, 1e-9);
    traj_case_free(&c);
}

/* A sphere rolling from rest down a 20 deg incline (tan b <= 3.5 mu: no
 * slip): a = (5/7) g (sin b - mu_r cos b); at distance s, v = sqrt(2 a s),
 * omega = v / r, rotational energy (1/5) m v^2. */
static void test_rolling(void **state)
{
    (void)state;
    traj_case c;
    double b = 20 * DEG;
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[0, %.17g], [100, 0]], material: m}\n"
             "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30, rolling_resistance: 0.1}}\n"
             "block: {shape: sphere, radius: 0.5, density: 2600}\n"
             "release: {x: 0, y: %.17g}\n"
             "collectors: [{name: c, x: 50}]\n",
             100 * tan(b), 100 * tan(b));
    traj_case_run(&c, yaml);
    double a = 5.0 / 7.0 * G * (sin(b) - 0.1 * cos(b)), s = 50 / cos(b), v = sqrt(2 * a * s);
    double m = 4.0 / 3.0 * 3.14159265358979323846 * 0.125 * 2600;
    assert_close(c.cross[0].speed, v, 1e-9);
    assert_close(c.cross[0].translational_energy, 0.5 * m * v * v, 1e-9);
    assert_close(c.cross[0].rotational_energy, 0.2 * m * v * v, 1e-9);
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    traj_case_free(&c);
}

/* Sliding without friction at U = 10 m/s off a convex edge at (10, 10) above
 * a 45 deg face down to (20, 0): it overflies the face and lands on the floor
 * at x = 10 + U sqrt(20/g), t = 0.5 + sqrt(20/g) (segment 2). */
static void test_convex_overflown(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[0, 10], [10, 10], [20, 0], [100, 0]], material: m}\n"
                 "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 0}}\n"
                 "block: {shape: point, mass: 1}\n"
                 "release: {x: 5, y: 10, vx: 10, vy: 0}\n"
                 "collectors: [{name: c, x: 15}]\n");
    double T = sqrt(20 / G);
    rf_traj_impact *m = &c.res.impacts[0];
    assert_int_equal(m->segment, 2);
    assert_close(m->x, 10 + 10 * T, 1e-12);
    assert_close(m->t, 0.5 + T, 1e-12);
    assert_close(m->vy_in, -G * T, 1e-12);
    /* at x = 15 the block is g (0.5)^2/2 below the edge, the face is 5 m below */
    assert_close(c.cross[0].height_lowest, 10 - 0.5 * G * 0.25 - 5, 1e-12);
    assert_close(c.cross[0].normal_height, (10 - 0.5 * G * 0.25 - 5) * cos(45 * DEG), 1e-12);
    traj_case_free(&c);
}

/* Thrown fast over a short slope: no root on any segment -> exited at the end of the profile. */
static void test_exit(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[0, 10], [10, 0]], material: m}\n"
                 "materials: {m: {R_n: 0.3, R_t: 0.8, friction_angle: 30}}\n"
                 "block: {shape: point, mass: 1}\n"
                 "release: {x: 5, y: 20, vx: 100, vy: 0}\n");
    assert_int_equal(c.res.state, RF_TRAJ_EXITED);
    assert_int_equal(c.res.n_impacts, 0);
    assert_close(c.res.x_end, 10, 1e-15);
    assert_close(c.res.y_end, 20 - 0.5 * G * 0.05 * 0.05, 1e-12);
    traj_case_free(&c);
}

/* Falling vertically onto flat ground at |v_n| = K = 9.144 m/s: velocity
 * scaling halves R_n, so v_n' = R_n K / 2. */
static void test_velocity_scaling(void **state)
{
    (void)state;
    traj_case c;
    double K = RF_TRAJ_PFEIFFER_BOWEN_K, h = K * K / (2 * G);
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "profile: {points: [[-1, 0], [1, 0]], material: m}\n"
             "materials: {m: {R_n: 0.8, R_t: 0.8, friction_angle: 30}}\n"
             "block: {shape: point, mass: 1}\n"
             "release: {x: 0, y: %.17g}\n"
             "bounce: {law: velocity_scaled}\n", h);
    traj_case_run(&c, yaml);
    assert_close(c.res.impacts[0].vy_in, -K, 1e-12);
    assert_close(c.res.impacts[0].vy_out, 0.8 * K / 2, 1e-12);
    traj_case_free(&c);
}

/* rigid_sphere without spin = src/impact's rf_impact_rigid (vertical fall onto a 30 deg slope). */
static void test_rigid_sphere_matches_impact(void **state)
{
    (void)state;
    double fr[2] = {10, 0.2}; /* sticking, sliding */
    for (int k = 0; k < 2; k++) {
        traj_case c;
        char yaml[1024];
        double b = 30 * DEG, V = 10, h = V * V / (2 * G);
        snprintf(yaml, sizeof yaml,
                 "profile: {points: [[-10, %.17g], [10, %.17g]], material: m}\n"
                 "materials: {m: {R_n: 0.5, R_t: 1, friction_angle: %.17g}}\n"
                 "block: {shape: sphere, radius: 1, density: 2600}\n"
                 "release: {x: 0, y: %.17g}\n"
                 "bounce: {law: rigid_sphere}\n", 10 * tan(b), -10 * tan(b), atan(fr[k]) / DEG, h);
        traj_case_run(&c, yaml);
        rf_impact_input in;
        rf_impact_input_default(&in);
        in.velocity = V, in.slope_angle = b, in.friction = fr[k];
        rf_impact_output out;
        rf_error err;
        assert_int_equal(rf_impact_rigid(&in, 0.5, &out, &err), RF_OK);
        rf_traj_impact *m = &c.res.impacts[0];
        double tx = cos(b), ty = -sin(b), nx = sin(b), ny = cos(b);
        assert_close(m->vx_out * nx + m->vy_out * ny, out.v_n_after, 1e-12);
        assert_close(m->vx_out * tx + m->vy_out * ty, out.v_t_after, 1e-12);
        assert_close(m->omega_out, out.omega_after, 1e-12);
        traj_case_free(&c);
    }
}

static double energy(const rf_traj_event *e, double m, double I, double g)
{
    return 0.5 * m * (e->vx * e->vx + e->vy * e->vy) + 0.5 * I * e->omega * e->omega + m * g * e->y;
}

/* Roughness, spin, kinks: kinetic energy never rises at an impact, the
 * total energy never rises from one event to the next, every impact point
 * lies on its segment and every rest point on the ground. */
static void test_energy_never_gained(void **state)
{
    (void)state;
    const char *laws[4] = {"constant", "velocity_scaled", "rigid_sphere", "impact_model"};
    for (int l = 0; l < 4; l++) {
        char yaml[2048];
        snprintf(yaml, sizeof yaml,
                 "profile: {points: [[0, 60], [20, 45], [30, 44], [45, 20], [50, 19], [70, 5], [80, 6], [120, 0]],\n"
                 "          material: m}\n"
                 "materials: {m: {R_n: {uniform: [0.2, 0.9]}, R_t: {uniform: [0.5, 1]}, friction_angle: 25,\n"
                 "                roughness: 15, rolling_resistance: 0.05}}\n"
                 "block: {shape: sphere, radius: 0.4, density: 2700}\n"
                 "release: {x: 1, y: 62, vx: {uniform: [0, 5]}, vy: 0, omega: {uniform: [-3, 3]}}\n"
                 "bounce: {law: %s}\n"
                 "samples: 200\nrecord: 200\nseed: 7\n", laws[l]);
        rf_traj_spec s;
        rf_error err;
        if (rf_traj_load_buffer("energy.yaml", yaml, strlen(yaml), &s, &err) != RF_OK)
            fail_msg("%s", err.msg);
        rf_traj_ensemble e;
        assert_int_equal(rf_traj_run(&s, 2, &e, &err), RF_OK);
        assert_ensemble_invariants(&s, &e);
        double m = 4.0 / 3.0 * 3.14159265358979323846 * 0.064 * 2700, I = 0.4 * m * 0.16;
        for (size_t i = 0; i < e.n_recorded; i++) {
            const rf_traj_result *r = &e.recorded[i];
            for (size_t k = 0; k < r->n_impacts; k++) {
                const rf_traj_impact *q = &r->impacts[k];
                double in = q->vx_in * q->vx_in + q->vy_in * q->vy_in, out = q->vx_out * q->vx_out + q->vy_out * q->vy_out;
                assert_true(out <= in * (1 + 1e-12) + 1e-12 || l >= 2); /* with spin: total energy below */
            }
            for (size_t k = 1; k < r->n_events; k++) {
                double e0 = energy(&r->events[k - 1], m, I, G), e1 = energy(&r->events[k], m, I, G);
                if (e1 > e0 + 1e-9 * fabs(e0) + 1e-9)
                    fail_msg("%s sample %zu event %zu: energy %.12g -> %.12g", laws[l], i, k, e0, e1);
            }
            for (size_t k = 0; k < r->n_impacts; k++) { /* every impact point lies on its segment */
                const rf_traj_impact *q = &r->impacts[k];
                double ax = s.px[q->segment], ay = s.py[q->segment], bx = s.px[q->segment + 1], by = s.py[q->segment + 1];
                double cross = (bx - ax) * (q->y - ay) - (by - ay) * (q->x - ax);
                assert_true(fabs(cross) / hypot(bx - ax, by - ay) < 1e-9);
                assert_true(q->x >= fmin(ax, bx) - 1e-9 && q->x <= fmax(ax, bx) + 1e-9);
            }
            if (r->state == RF_TRAJ_STOPPED) { /* at rest on the ground, not under it */
                double gy = NAN;
                for (size_t k = 0; k + 1 < s.n_points; k++)
                    if (r->x_end >= s.px[k] && r->x_end <= s.px[k + 1] && s.px[k + 1] > s.px[k])
                        gy = fmax(isnan(gy) ? -INFINITY : gy,
                                  s.py[k] + (s.py[k + 1] - s.py[k]) * (r->x_end - s.px[k]) / (s.px[k + 1] - s.px[k]));
                if (!(fabs(r->y_end - gy) < 1e-9))
                    fail_msg("%s sample %zu: rest at (%g, %g), ground %g", laws[l], i, r->x_end, r->y_end, gy);
            }
        }
        rf_traj_ensemble_free(&e);
        rf_traj_spec_free(&s);
    }
}

/* Barriers on the ledge case: the crossing at x = 6 has KE = m (vx^2 + vy^2)/2 = E
 * at height H.  capacity > E and height > H: held there; capacity < E: passes;
 * height < H: flies over. */
static void test_barrier(void **state)
{
    (void)state;
    double tc = 6.5 / 5, vyc = 2 - G * tc, E = 500 * (25 + vyc * vyc), H = 20.5 + 2 * tc - 0.5 * G * tc * tc;
    struct { double cap, height; int held; } c[3] = {{E * 1.01, H + 1, 1}, {E * 0.99, 0, 0}, {E * 2, H - 1, 0}};
    for (int k = 0; k < 3; k++) {
        char yaml[1024];
        snprintf(yaml, sizeof yaml,
                 "profile: {points: [[-10, 20], [0, 20], [0, 0], [100, 0]], material: rock}\n"
                 "materials: {rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30}}\n"
                 "block: {shape: point, mass: 1000}\n"
                 "release: {x: -0.5, y: 20.5, vx: 5, vy: 2}\n"
                 "collectors: [{name: net, x: 6, capacity: %.17g, height: %.17g}]\n", c[k].cap, c[k].height);
        traj_case t;
        traj_case_run(&t, yaml);
        assert_int_equal(t.cross[0].stopped_by_barrier, c[k].held);
        assert_close(t.cross[0].translational_energy, E, 1e-12);
        if (c[k].held) {
            assert_int_equal(t.res.state, RF_TRAJ_STOPPED);
            assert_close(t.res.x_end, 6, 1e-15);
            assert_close(t.res.t_end, tc, 1e-12);
            assert_int_equal(t.res.n_impacts, 0);
        } else {
            assert_true(t.res.n_impacts > 0 && t.res.x_end > 6);
        }
        traj_case_free(&t);
    }
}

/* A block that bounces for ever (R_n = 1, no friction loss) ends on the step limit. */
static void test_step_limit(void **state)
{
    (void)state;
    traj_case c;
    traj_case_run(&c, "profile: {points: [[-1, 0], [1, 0]], material: m}\n"
                 "materials: {m: {R_n: 1, R_t: 1, friction_angle: 30}}\n"
                 "block: {shape: point, mass: 1}\n"
                 "release: {x: 0, y: 1}\n"
                 "stop: {max_steps: 50}\n");
    assert_int_equal(c.res.state, RF_TRAJ_STEP_LIMIT);
    assert_int_equal(c.res.n_steps, 51);
    assert_int_equal(c.res.n_impacts, 50);
    assert_close(c.res.t_end, sqrt(2 / G) * 99, 1e-9); /* 1 fall + 49 round trips of 2 sqrt(2 h / g) */
    traj_case_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ledge),
        cmocka_unit_test(test_vertical_wall),
        cmocka_unit_test(test_bounce_series),
        cmocka_unit_test(test_slide_incline_floor),
        cmocka_unit_test(test_slide_to_rest),
        cmocka_unit_test(test_rolling),
        cmocka_unit_test(test_convex_overflown),
        cmocka_unit_test(test_exit),
        cmocka_unit_test(test_velocity_scaling),
        cmocka_unit_test(test_rigid_sphere_matches_impact),
        cmocka_unit_test(test_energy_never_gained),
        cmocka_unit_test(test_barrier),
        cmocka_unit_test(test_step_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
