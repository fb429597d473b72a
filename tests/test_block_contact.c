/* test_block_contact.c - non-smooth contact of a rigid block
 * (block_contact.c) against closed forms: a box resting on an incline below
 * its friction angle and sliding above it at g (sin b - mu cos b); a
 * slender box tipping over its edge just past the angle its geometry gives; a sphere
 * rolling at 5/7 g sin b, and sliding and spinning up when friction is too
 * small; a dropped sphere's rebound (Newton); an oblique sphere impact
 * against the 2D engine's rigid_sphere law (src/trajectory/bounce.c); a box
 * dropped flat with e_n = 0 at rest at once; a tumbling block on a profile.
 * Every step of every case checks that the energy (kinetic + m g z) never
 * grows in a contact step by more than round-off, nor in flight by more than
 * the free rotor's bounded oscillation.  Also: a sphere rolling in a V-groove
 * (two planes) at g sin b / 1.8, an ellipsoid resting, rebounding and
 * tumbling on its support point. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rockfuzz/block.h"
#include "rockfuzz/terrain.h"

#define G 9.81
#define PI 3.14159265358979323846
#define DEG (PI / 180)

static void assert_rel(double got, double want, double tol, const char *what)
{
    double err = fabs(got - want) / fmax(fabs(want), 1e-300);
    if (!(err <= tol))
        fail_msg("%s: got %.17g, want %.17g (relative error %.3g > %.3g)", what, got, want, err, tol);
}

/* An incline through the origin falling towards +x at beta. */
static rf_block_plane incline(double beta)
{
    rf_block_plane p = {{0, 0, 0}, {sin(beta), 0, cos(beta)}};
    return p;
}

static rf_block_world world(const rf_block_plane *p, double mu, double e_n, double h)
{
    rf_block_world w = {.e_n = e_n, .e_t = 0, .mu = mu, .g = G, .h = h, .tol = 1e-13, .max_iter = 2000,
                        .n_planes = p ? 1 : 0, .planes = p};
    return w;
}

/* Runs n steps; fails if a prox iteration does not converge, if a step with
 * contacts ends with more energy than tol [J] above its start (the step caps
 * it: only round-off may show), or if a flight step gains more than the free
 * rotor's bounded O(h^2) oscillation allows (1e-6 of the kinetic energy:
 * test_block_flight measures 8e-8 at 1 ms for an asymmetric top).  Returns
 * the largest growth in a contact step. */
static double run(const rf_block_shape *s, const rf_block_world *w, rf_block_state *st, long n, double tol)
{
    double e = rf_block_energy(s, st, w->g), worst = -INFINITY;
    for (long k = 0; k < n; k++) {
        rf_block_step_info info;
        double ke = rf_block_kinetic_energy(s, st, NULL);
        rf_block_step(s, w, st, &info);
        if (!info.converged)
            fail_msg("step %ld: the prox iteration did not converge in %d sweeps (%d contacts)", k, info.iterations,
                     info.n_contacts);
        double e2 = rf_block_energy(s, st, w->g);
        if (info.n_contacts) {
            worst = fmax(worst, e2 - e);
            if (e2 - e > tol)
                fail_msg("step %ld: the energy grew by %.3e J (> %.3e) in a contact step", k, e2 - e, tol);
        } else if (e2 - e > 1e-6 * ke + tol) {
            fail_msg("step %ld: the energy grew by %.3e J in flight (kinetic %.3e J)", k, e2 - e, ke);
        }
        e = e2;
    }
    return worst;
}

/* A box of edges lx (downhill), ly, lz (up) lying on the incline. */
static void box_edges_on_incline(double beta, double lx, double ly, double lz, rf_block_shape *s, rf_block_state *st)
{
    rf_error err;
    if (rf_block_box(lx, ly, lz, 2650, s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    double c = cos(beta), sn = sin(beta), ry[9] = {c, 0, sn, 0, 1, 0, -sn, 0, c}, m[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m[3 * i + j] = ry[3 * i] * s->axes[j] + ry[3 * i + 1] * s->axes[3 + j] + ry[3 * i + 2] * s->axes[6 + j];
    memset(st, 0, sizeof *st);
    rf_block_quat_from_matrix(m, st->q);
    for (int i = 0; i < 3; i++)
        st->x[i] = lz / 2 * (i == 0 ? sn : i == 2 ? c : 0);
}

static void box_on_incline(double beta, rf_block_shape *s, rf_block_state *st)
{
    box_edges_on_incline(beta, 1.0, 0.6, 0.4, s, st);
}

/* The angle [rad] between the box's up edge and the incline's normal. */
static double tilt(const rf_block_shape *s, const rf_block_state *st, double beta)
{
    double up[3] = {0, 0, 0}, b[3];
    for (int i = 0; i < 3; i++)
        up[i] = s->axes[6 + i]; /* the given z axis in the body frame */
    rf_block_to_space(st->q, up, b);
    return acos(fmin(1, b[0] * sin(beta) + b[2] * cos(beta)));
}

/* A slender box (0.4 downhill, 1.0 high) with friction enough not to slide
 * (mu = 1) tips over its lower edge when its centre passes over that edge:
 * tan(beta) > 0.4 / 1.0, beta > 21.8 deg. */
static void test_box_tips(void **state)
{
    (void)state;
    double tip = atan(0.4 / 1.0);
    for (int k = 0; k < 2; k++) {
        double beta = tip + (k ? 1 : -1) * DEG;
        rf_block_plane p = incline(beta);
        rf_block_world w = world(&p, 1.0, 0, 1e-3);
        rf_block_shape s;
        rf_block_state st;
        box_edges_on_incline(beta, 0.4, 0.6, 1.0, &s, &st);
        double capped = 0, e0 = rf_block_energy(&s, &st, G);
        for (int n = 0; n < 3000; n++) {
            rf_block_step_info info;
            double e = rf_block_energy(&s, &st, G);
            rf_block_step(&s, &w, &st, &info);
            assert_true(rf_block_energy(&s, &st, G) <= e + 1e-12 * s.mass * G);
            capped += info.energy_cap;
        }
        double a = tilt(&s, &st, beta), lost = e0 - rf_block_energy(&s, &st, G);
        print_message("slender box at %.2f deg (tipping angle %.2f): tilt after 3 s %.3e deg; energy lost %.1f J, "
                      "of it capped %.3f J\n", beta / DEG, tip / DEG, a / DEG, lost, capped);
        assert_true(capped <= 1e-3 * lost + 1e-9); /* the cap: a small part of the dissipation */
        if (k)
            assert_true(a > 30 * DEG);
        else
            assert_true(a < 1e-9);
        rf_block_shape_free(&s);
    }
}

static void test_box_sticks(void **state)
{
    (void)state;
    double beta = 20 * DEG, mu = 0.5; /* friction angle 26.6 deg */
    rf_block_plane p = incline(beta);
    rf_block_world w = world(&p, mu, 0, 1e-3);
    rf_block_shape s;
    rf_block_state st;
    box_on_incline(beta, &s, &st);
    double x0[3] = {st.x[0], st.x[1], st.x[2]}, scale = s.mass * G * 1.0;
    double grow = run(&s, &w, &st, 10000, 1e-12 * scale);
    double drift = sqrt(pow(st.x[0] - x0[0], 2) + pow(st.x[1] - x0[1], 2) + pow(st.x[2] - x0[2], 2));
    print_message("box below its friction angle, 10 s: drift %.3e m, speed %.3e m/s, largest energy step %+.3e J\n",
                  drift, sqrt(st.v[0] * st.v[0] + st.v[1] * st.v[1] + st.v[2] * st.v[2]), grow);
    assert_true(drift < 1e-12);
    rf_block_shape_free(&s);
}

static void test_box_slides(void **state)
{
    (void)state;
    double beta = 30 * DEG, mu = 0.3;
    rf_block_plane p = incline(beta);
    rf_block_world w = world(&p, mu, 0, 1e-3);
    rf_block_shape s;
    rf_block_state st;
    box_on_incline(beta, &s, &st);
    double x0[3] = {st.x[0], st.x[1], st.x[2]}, down[3] = {cos(beta), 0, -sin(beta)};
    run(&s, &w, &st, 2000, 1e-12 * s.mass * G);
    double T = 2.0, a = G * (sin(beta) - mu * cos(beta));
    double v = st.v[0] * down[0] + st.v[2] * down[2], d = (st.x[0] - x0[0]) * down[0] + (st.x[2] - x0[2]) * down[2];
    print_message("box above its friction angle: a = %.12f from v, %.12f from the distance, %.12f closed form\n",
                  v / T, 2 * d / (T * T), a);
    assert_rel(v / T, a, 1e-6, "sliding acceleration (velocity)");
    assert_rel(2 * d / (T * T), a, 1e-6, "sliding acceleration (distance)");
    assert_true(fabs(st.w[0]) + fabs(st.w[1]) + fabs(st.w[2]) < 1e-9);
    rf_block_shape_free(&s);
}

static void sphere_on_incline(double beta, double r, rf_block_shape *s, rf_block_state *st)
{
    rf_error err;
    if (rf_block_sphere(r, 2650, s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    rf_block_state z = {{r * sin(beta), 0, r * cos(beta)}, {1, 0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    *st = z;
}

static void test_sphere_rolls(void **state)
{
    (void)state;
    double beta = 20 * DEG, r = 0.5, T = 3;
    rf_block_plane p = incline(beta);
    rf_block_shape s;
    rf_block_state st;
    /* mu = 0.5 >= 2/7 tan(beta): rolls */
    rf_block_world w = world(&p, 0.5, 0, 1e-3);
    sphere_on_incline(beta, r, &s, &st);
    run(&s, &w, &st, 3000, 1e-12 * s.mass * G);
    double down[3] = {cos(beta), 0, -sin(beta)}, v = st.v[0] * down[0] + st.v[2] * down[2];
    assert_rel(v / T, 5.0 / 7.0 * G * sin(beta), 1e-6, "rolling acceleration 5/7 g sin b");
    assert_rel(st.w[1] * r, v, 1e-9, "rolling: omega r = v");
    /* mu = 0.05 < 2/7 tan(beta): slides at g (sin b - mu cos b) and spins up at 5 mu g cos b / (2 r) */
    double mu = 0.05;
    w = world(&p, mu, 0, 1e-3);
    sphere_on_incline(beta, r, &s, &st);
    run(&s, &w, &st, 3000, 1e-12 * s.mass * G);
    v = st.v[0] * down[0] + st.v[2] * down[2];
    double wy;
    rf_block_to_space(st.q, st.w, down); /* the spin in space (about +y rolls forward) */
    wy = down[1];
    assert_rel(v / T, G * (sin(beta) - mu * cos(beta)), 1e-6, "sliding sphere's acceleration");
    assert_rel(wy / T, 2.5 * mu * G * cos(beta) / r, 1e-6, "sliding sphere's spin-up");
}

/* A sphere dropped from rest, its lowest point H above the plane. */
static void test_sphere_rebound(void **state)
{
    (void)state;
    double r = 0.5, H = 2.0, e = 0.6, h = 1e-4;
    rf_block_plane p = incline(0);
    rf_block_world w = world(&p, 0.5, e, h);
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_sphere(r, 2650, &s, &err), RF_OK);
    rf_block_state st = {{0, 0, r + H}, {1, 0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    double e0 = rf_block_energy(&s, &st, G), v_before = 0, v_after = 0, apex = 0;
    int hit = 0;
    for (long k = 0; k < 20000; k++) {
        double v = st.v[2];
        rf_block_step_info info;
        rf_block_step(&s, &w, &st, &info);
        assert_true(rf_block_energy(&s, &st, G) <= e0 + 1e-12 * e0);
        e0 = rf_block_energy(&s, &st, G);
        if (info.n_contacts && !hit)
            hit = 1, v_before = v, v_after = st.v[2];
        if (hit)
            apex = fmax(apex, st.x[2] - r);
        if (hit && st.v[2] < 0)
            break;
    }
    double v_imp = sqrt(2 * G * H);
    print_message("rebound: v before %.6f (free fall %.6f), after %.6f, ratio %.15f; apex %.6f m (e^2 H = %.6f)\n",
                  v_before, -v_imp, v_after, -v_after / v_before, apex, e * e * H);
    assert_rel(-v_after / v_before, e, 1e-13, "Newton: v+ = -e v-");
    /* the impact lands within one step: position off by v h, speed by g h */
    assert_true(fabs(v_before + v_imp) < G * h + 1e-12);
    assert_true(fabs(apex - e * e * H) < 2 * v_imp * h);
    rf_block_shape_free(&s);
}

/* bounce.c's rigid_sphere law (its equations, restated): slip s = v_t -
 * omega r, P = sign(s) min(|s| / (1 + 1/k), mu (1 + e) |v_n|), v_n' = e |v_n|,
 * v_t' = v_t - P, omega' = omega + P / (k r), k = I / (m r^2) = 2/5. */
static void rigid_sphere_ref(double vn, double vt, double om, double e, double mu, double r, double out[3])
{
    double k = 0.4, slip = vt - om * r;
    double p = copysign(fmin(fabs(slip) / (1 + 1 / k), mu * (1 + e) * fabs(vn)), slip);
    out[0] = e * fabs(vn), out[1] = vt - p, out[2] = om + p / (k * r);
}

/* One impact of a sphere on the horizontal plane (the spin about +y rolls
 * it forward along +x); out = (v_z, v_x, omega_y) after it. */
static void sphere_impact(double vn, double vt, double om, double e, double mu, double g, double out[3])
{
    double r = 0.4, h = 1e-4;
    rf_block_plane p = incline(0);
    rf_block_world w = world(&p, mu, e, h);
    w.g = g;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_sphere(r, 2650, &s, &err), RF_OK);
    rf_block_state st = {{0, 0, r + 0.3 * vn * h}, {1, 0, 0, 0}, {vt, 0, -vn}, {0, om, 0}};
    for (int k = 0; k < 3; k++) {
        rf_block_step_info info;
        rf_block_step(&s, &w, &st, &info);
        if (info.n_contacts)
            break;
    }
    double ws[3];
    rf_block_to_space(st.q, st.w, ws);
    out[0] = st.v[2], out[1] = st.v[0], out[2] = ws[1];
}

static void test_oblique_impact(void **state)
{
    (void)state;
    /* (v_n, v_t, omega): sliding throughout, sticking, backspin, topspin faster than rolling */
    double cases[4][3] = {{5, 8, 0}, {5, 1, 0}, {4, 3, -10}, {3, 1, 12}};
    double e = 0.4, mu = 0.2, h = 1e-4; /* cases 0, 2, 3 slide throughout, 1 sticks */
    for (int c = 0; c < 4; c++) {
        double ref[3], got[3], got_g[3];
        rigid_sphere_ref(cases[c][0], cases[c][1], cases[c][2], e, mu, 0.4, ref);
        sphere_impact(cases[c][0], cases[c][1], cases[c][2], e, mu, 0, got);
        sphere_impact(cases[c][0], cases[c][1], cases[c][2], e, mu, G, got_g);
        print_message("impact %d: rigid_sphere (%.9f %.9f %.9f), block g=0 (%.9f %.9f %.9f), g=9.81 (%.9f %.9f %.9f)\n",
                      c, ref[0], ref[1], ref[2], got[0], got[1], got[2], got_g[0], got_g[1], got_g[2]);
        for (int i = 0; i < 3; i++)
            assert_true(fabs(got[i] - ref[i]) < 1e-12 * (1 + fabs(ref[i])));
        /* with gravity the step's normal impulse carries g h more (and friction mu g h):
         * v_n' is e |v_n| of the step's start, the rest within mu g h (x 1/(k r) for the spin) */
        assert_true(fabs(got_g[0] - ref[0]) < 1e-12 * (1 + ref[0]));
        assert_true(fabs(got_g[1] - ref[1]) <= mu * G * h * (1 + 1e-9));
        assert_true(fabs(got_g[2] - ref[2]) <= mu * G * h / (0.4 * 0.4) * (1 + 1e-9));
    }
}

/* A box dropped flat with e_n = 0 is at rest after the impact step; an
 * EOTA cube thrown spinning onto a profile tumbles down and loses energy. */
static void test_flat_drop_and_tumble(void **state)
{
    (void)state;
    rf_block_shape s;
    rf_error err;
    rf_block_plane p = incline(0);
    rf_block_world w = world(&p, 0.6, 0, 1e-3);
    assert_int_equal(rf_block_box(1.0, 0.8, 0.5, 2650, &s, &err), RF_OK);
    rf_block_state st = {{0, 0, 1.25}, {1, 0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    rf_block_quat_from_matrix(s.axes, st.q);
    int rest = -1;
    for (int k = 0; k < 2000 && rest < 0; k++) {
        rf_block_step_info info;
        rf_block_step(&s, &w, &st, &info);
        if (info.n_contacts)
            rest = k;
    }
    assert_true(rest > 0);
    double speed = fabs(st.v[0]) + fabs(st.v[1]) + fabs(st.v[2]) + fabs(st.w[0]) + fabs(st.w[1]) + fabs(st.w[2]);
    assert_true(speed < 1e-12);
    run(&s, &w, &st, 1000, 1e-12 * s.mass * G);
    speed = fabs(st.v[0]) + fabs(st.v[1]) + fabs(st.v[2]) + fabs(st.w[0]) + fabs(st.w[1]) + fabs(st.w[2]);
    assert_true(speed < 1e-12);
    rf_block_shape_free(&s);

    double px[4] = {-5, 10, 25, 200}, pz[4] = {10, 0, -8, -10};
    rf_block_profile prof = {4, px, pz};
    rf_block_world tw = world(NULL, 0.6, 0.3, 1e-3);
    tw.ground = rf_block_ground_profile, tw.ground_ctx = &prof;
    assert_int_equal(rf_block_eota_cube(0.5, 2650, &s, &err), RF_OK);
    rf_block_state t = {{0, 0, 8.5}, {0.9, 0.1, 0.3, 0.2}, {4, 0.5, 0}, {1, -3, 2}};
    double n = sqrt(0.9 * 0.9 + 0.01 + 0.09 + 0.04);
    for (int i = 0; i < 4; i++)
        t.q[i] /= n;
    double e0 = rf_block_energy(&s, &t, G);
    double grow = run(&s, &tw, &t, 8000, 1e-12 * e0);
    print_message("EOTA cube: largest energy change in a step %+.3e J\n", grow);
    print_message("EOTA cube on a profile: after 8 s at x = %.2f m, z = %.2f m, energy %.1f of %.1f kJ\n", t.x[0],
                  t.x[2], rf_block_energy(&s, &t, G) / 1e3, e0 / 1e3);
    assert_true(t.x[0] > 25); /* it went down the slope */
    double zg, ng[3];
    assert_true(rf_block_ground_profile(&prof, t.x[0], 0, &zg, ng));
    assert_true(t.x[2] > zg); /* and stayed above the ground */
    rf_block_shape_free(&s);
}

/* A sphere rolling down a 90 deg V-groove (two planes) whose axis falls at
 * beta: it rolls about the line through its two contacts, r / sqrt(2) below
 * its centre, so a = g sin b / (1 + (2/5) r^2 / (r^2 / 2)) = g sin b / 1.8. */
static void test_sphere_in_groove(void **state)
{
    (void)state;
    double beta = 20 * DEG, r = 0.5, c = cos(beta), sn = sin(beta), q = sqrt(0.5), T = 2;
    rf_block_plane p[2] = {{{0, 0, 0}, {c * 0 + sn * q, -q, -sn * 0 + c * q}},
                           {{0, 0, 0}, {sn * q, q, c * q}}};
    rf_block_world w = world(p, 0.8, 0, 1e-3);
    w.n_planes = 2;
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_sphere(r, 2650, &s, &err), RF_OK);
    double z0 = r * sqrt(2.0);
    rf_block_state st = {{sn * z0, 0, c * z0}, {1, 0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    run(&s, &w, &st, 2000, 1e-12 * s.mass * G);
    double v = st.v[0] * c - st.v[2] * sn;
    print_message("sphere in a V-groove: a = %.12f, closed form %.12f; lateral v %.1e\n", v / T, G * sn / 1.8, st.v[1]);
    assert_rel(v / T, G * sn / 1.8, 1e-6, "rolling in a V-groove");
    assert_true(fabs(st.v[1]) < 1e-12);
}

/* An ellipsoid lying on its flat side rests at its shortest semi-axis and,
 * dropped flat, rebounds at -e v; dropped tilted it tumbles without ever
 * gaining energy (its support point is the contact). */
static void test_ellipsoid_contact(void **state)
{
    (void)state;
    rf_block_plane p = incline(0);
    rf_block_world w = world(&p, 0.5, 0.5, 1e-4);
    rf_block_shape s;
    rf_error err;
    assert_int_equal(rf_block_ellipsoid(1.0, 0.6, 0.3, 2650, &s, &err), RF_OK);
    rf_block_state st = {{0, 0, 0.3}, {1, 0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    w.e_n = 0;
    run(&s, &w, &st, 10000, 1e-12 * s.mass * G);
    assert_true(fabs(st.x[2] - 0.3) < 1e-12 && fabs(st.x[0]) < 1e-12);
    w.e_n = 0.5;
    st.x[2] = 1.3;
    double v_before = 0, v_after = 0;
    for (int k = 0; k < 10000 && v_after == 0; k++) {
        rf_block_step_info info;
        double v = st.v[2];
        rf_block_step(&s, &w, &st, &info);
        if (info.n_contacts)
            v_before = v, v_after = st.v[2];
    }
    assert_rel(-v_after / v_before, 0.5, 1e-13, "ellipsoid rebound");
    rf_block_state t = {{0, 0, 1.5}, {cos(0.3), sin(0.3), 0, 0}, {1, 0, 0}, {0, 2, 1}};
    w.h = 1e-3;
    double e0 = rf_block_energy(&s, &t, G);
    run(&s, &w, &t, 3000, 1e-12 * e0);
    double up[3] = {0, 0, 1}, low[3];
    assert_true(rf_block_lowest_point(&s, &t, up, low) > -0.01); /* never sank: at most a step's travel */
}

/* The terrain plugs in through the ground callback: a DEM of an inclined
 * plane (rf_terrain_from_nodes, bilinear) gives a sphere the rolling
 * acceleration of the plane, 5/7 g sin b, and a box the sliding one. */
static int terrain_ground(void *t, double x, double y, double *z, double n[3])
{
    return rf_terrain_height(t, x, y, z, n);
}

static void test_terrain_ground(void **state)
{
    (void)state;
    double beta = 25 * DEG, zs[40 * 8];
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 40; i++)
            zs[j * 40 + i] = -tan(beta) * (-10 + 2.0 * i);
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(40, 8, -10, -7, 2, 2, zs, &t, &err), RF_OK);
    rf_block_world w = world(NULL, 0.6, 0, 1e-3);
    w.ground = terrain_ground, w.ground_ctx = t;
    rf_block_shape s;
    rf_block_state st;
    sphere_on_incline(beta, 0.5, &s, &st);
    run(&s, &w, &st, 2000, 1e-12 * s.mass * G);
    double down[3] = {cos(beta), 0, -sin(beta)}, v = st.v[0] * down[0] + st.v[2] * down[2];
    assert_rel(v / 2.0, 5.0 / 7.0 * G * sin(beta), 1e-6, "rolling on a terrain plane");
    w.mu = 0.3;
    box_on_incline(beta, &s, &st);
    run(&s, &w, &st, 2000, 1e-12 * s.mass * G);
    v = st.v[0] * down[0] + st.v[2] * down[2];
    assert_rel(v / 2.0, G * (sin(beta) - 0.3 * cos(beta)), 1e-6, "sliding on a terrain plane");
    rf_block_shape_free(&s);
    rf_terrain_free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box_sticks),      cmocka_unit_test(test_box_slides), cmocka_unit_test(test_box_tips),
        cmocka_unit_test(test_sphere_rolls),    cmocka_unit_test(test_sphere_rebound),
        cmocka_unit_test(test_oblique_impact),  cmocka_unit_test(test_flat_drop_and_tumble),
        cmocka_unit_test(test_sphere_in_groove), cmocka_unit_test(test_ellipsoid_contact),
        cmocka_unit_test(test_terrain_ground),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
