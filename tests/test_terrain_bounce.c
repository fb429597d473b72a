/* test_terrain_bounce.c - the bounce laws in 3D (terrain_bounce.c):
 *   constant and velocity_scaled on planes of any aspect against the frame
 *   formula written out here, the soft landing;
 *   rigid_sphere in the plane of a slope's fall line equals the 2D law
 *   (bounce.c's formula: slip v_t - omega r, impulse capped by mu (1 + e) v_n);
 *   no law gains kinetic energy over 10^4 random impacts with random spin
 *   vectors on twisted cells, with and without roughness, and no rebound goes
 *   into the true surface;
 *   roughness: an elastic law reveals the tilted normal, whose angle from the
 *   true normal has the requested SD; the per-cell roughness overrides the
 *   material's. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_terrain_util.h"
#include "test_util.h"

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* A run on dem at point p (on it) with the spec's block. */
static void run_at(terrain_run *r, const tt_world *tw, const tt_spec *ts, const double p[3])
{
    memset(r, 0, sizeof *r);
    r->w = &tw->w, r->dem = tw->w.dem, r->s = &ts->spec;
    r->seed = 3, r->sample = 11, r->g = TT_G;
    const rf_traj_spec *s = &ts->spec;
    r->mass = s->mass, r->radius = s->sphere ? s->radius : 0;
    r->inertia = s->sphere ? 0.4 * s->mass * s->radius * s->radius : 0;
    memcpy(r->p, p, sizeof r->p);
}

static void plane_normal(const tt_plane *pl, double n[3])
{
    double nz = 1 / sqrt(1 + pl->sx * pl->sx + pl->sy * pl->sy);
    n[0] = -pl->sx * nz, n[1] = -pl->sy * nz, n[2] = nz;
}

/* constant and velocity_scaled: v' = R_t v_t - R_n' v_n n. */
static void test_constant_and_scaled_any_aspect(void **state)
{
    (void)state;
    uint64_t seed = 5;
    for (int k = 0; k < 500; k++) {
        double slope = tt_uniform(&seed, 0, 70) * TT_DEG, aspect = tt_uniform(&seed, -180, 180) * TT_DEG;
        tt_plane pl = {10, tan(slope) * sin(aspect), tan(slope) * cos(aspect), 0, 0};
        rf_terrain *t = tt_dem(3, 3, 0, 0, 2, 2, tt_plane_z, &pl);
        tt_spec ts;
        tt_spec_init(&ts, 0.45, 0.8);
        ts.spec.law = k % 2 ? RF_BOUNCE_VELOCITY_SCALED : RF_BOUNCE_CONSTANT;
        tt_world tw;
        tt_world_init(&tw, t);
        double p[3] = {tt_uniform(&seed, 0, 4), tt_uniform(&seed, 0, 4), 0}, n[3];
        p[2] = tt_plane_z(&pl, p[0], p[1]);
        plane_normal(&pl, n);
        double v[3] = {tt_uniform(&seed, -10, 10), tt_uniform(&seed, -10, 10), tt_uniform(&seed, -10, 10)};
        double vn = dot(v, n);
        if (vn > -0.2)
            for (int q = 0; q < 3; q++)
                v[q] -= (vn + 0.2 + tt_uniform(&seed, 0, 10)) * n[q]; /* approaching faster than contact_speed */
        vn = dot(v, n);
        double Rn = 0.45;
        if (k % 2)
            Rn /= 1 + (vn / RF_TRAJ_PFEIFFER_BOWEN_K) * (vn / RF_TRAJ_PFEIFFER_BOWEN_K);
        double expect[3], w[3] = {1, 2, 3};
        for (int q = 0; q < 3; q++)
            expect[q] = 0.8 * (v[q] - vn * n[q]) - Rn * vn * n[q];
        terrain_run r;
        run_at(&r, &tw, &ts, p);
        assert_int_equal(terrain_bounce(&r, (size_t)(p[0] >= 2), (size_t)(p[1] >= 2), v, w), 0);
        for (int q = 0; q < 3; q++) {
            assert_near(v[q], expect[q], 1e-12 * (1 + fabs(expect[q])));
            assert_true(w[q] == 0);
        }
        /* soft landing: normal speed below contact_speed, the tangential part kept */
        double s[3] = {3, -1, 0}, sn = dot(s, n);
        for (int q = 0; q < 3; q++)
            s[q] -= (sn + 0.05) * n[q]; /* v.n = -0.05 */
        double st[3];
        for (int q = 0; q < 3; q++)
            st[q] = s[q] + 0.05 * n[q];
        assert_int_equal(terrain_bounce(&r, 0, 0, s, w), 1);
        for (int q = 0; q < 3; q++)
            assert_near(s[q], st[q], 1e-12);
        rf_terrain_free(t);
    }
}

/* The 2D rigid sphere (bounce.c) on a segment of tangent t, normal n. */
static void rigid_2d(double vn, double vt, double om, double e, double mu, double k, double r, double *vn_o,
                     double *vt_o, double *om_o)
{
    double slip = vt - om * r, p = fmin(fabs(slip) / (1 + 1 / k), mu * (1 + e) * fabs(vn));
    p = copysign(p, slip);
    *vn_o = e * fabs(vn), *vt_o = vt - p, *om_o = om + p / (k * r);
}

static void test_rigid_sphere_in_plane_is_2d(void **state)
{
    (void)state;
    uint64_t seed = 17;
    int sliding = 0, sticking = 0;
    for (int k = 0; k < 2000; k++) {
        double beta = tt_uniform(&seed, -60, 60) * TT_DEG; /* the slope rises to the east at beta */
        tt_plane pl = {50, tan(beta), 0, 0, 0};
        rf_terrain *t = tt_dem(3, 3, 0, 0, 1, 1, tt_plane_z, &pl);
        tt_spec ts;
        tt_spec_init(&ts, tt_uniform(&seed, 0.1, 0.9), 0.8);
        ts.mat[0].friction_angle = tt_uniform(&seed, 5, 45) * TT_DEG;
        tt_sphere(&ts, tt_uniform(&seed, 0.1, 2), 2600);
        ts.spec.law = RF_BOUNCE_RIGID_SPHERE;
        tt_world tw;
        tt_world_init(&tw, t);
        double tx = cos(beta), tz = sin(beta), nx = -tz, nz = tx; /* 2D: t = (tx, tz), n = (-tz, tx) */
        double vn = -tt_uniform(&seed, 0.5, 15), vt = tt_uniform(&seed, -15, 15), om = tt_uniform(&seed, -20, 20);
        double v[3] = {vn * nx + vt * tx, 0, vn * nz + vt * tz}, w[3] = {0, om, 0}, p[3] = {1, 1, 0};
        p[2] = tt_plane_z(&pl, 1, 1);
        terrain_run r;
        run_at(&r, &tw, &ts, p);
        assert_int_equal(terrain_bounce(&r, 0, 0, v, w), 0);
        double vn2, vt2, om2, kk = 0.4;
        rigid_2d(vn, vt, om, ts.mat[0].R_n, tan(ts.mat[0].friction_angle), kk, ts.spec.radius, &vn2, &vt2, &om2);
        double scale = 1 + fabs(vn) + fabs(vt) + fabs(om);
        assert_near(v[0], vn2 * nx + vt2 * tx, 1e-12 * scale);
        assert_near(v[1], 0, 1e-12 * scale);
        assert_near(v[2], vn2 * nz + vt2 * tz, 1e-12 * scale);
        assert_near(w[0], 0, 1e-12 * scale);
        assert_near(w[1], om2, 1e-12 * scale);
        assert_near(w[2], 0, 1e-12 * scale);
        double slip = vt - om * ts.spec.radius;
        if (fabs(slip) / (1 + 1 / kk) > tan(ts.mat[0].friction_angle) * (1 + ts.mat[0].R_n) * fabs(vn))
            sliding++;
        else
            sticking++;
        rf_terrain_free(t);
    }
    assert_true(sliding > 200 && sticking > 200); /* both branches of the law */
}

/* Random node heights: twisted cells (d != 0) of every slope. */
static double random_height(void *ctx, double x, double y)
{
    (void)x, (void)y;
    return tt_uniform(ctx, -3, 3);
}

/* Kinetic energy (per unit mass, times 2). */
static double ke2(const double v[3], const double w[3], double i_m) { return dot(v, v) + i_m * dot(w, w); }

static void test_energy_never_gained(void **state)
{
    (void)state;
    uint64_t seed = 2026, zs = 8;
    rf_terrain *t = tt_dem(9, 9, 0, 0, 1.5, 1, random_height, &zs);
    tt_world tw;
    tt_world_init(&tw, t);
    int tilted_away = 0;
    for (int k = 0; k < 10000; k++) {
        tt_spec ts;
        tt_spec_init(&ts, tt_uniform(&seed, 0, 1), tt_uniform(&seed, 0, 1));
        ts.mat[0].friction_angle = tt_uniform(&seed, 0, 60) * TT_DEG;
        ts.mat[0].roughness = k % 2 ? tt_uniform(&seed, 0, 30) * TT_DEG : 0;
        ts.spec.contact_speed = 0;
        tt_sphere(&ts, tt_uniform(&seed, 0.05, 2), 2600);
        ts.spec.law = (rf_bounce_law)(k % 3); /* constant, velocity_scaled, rigid_sphere */
        size_t ci = (size_t)(tt_rand(&seed) * 8), cj = (size_t)(tt_rand(&seed) * 8);
        double p[3] = {(ci + tt_rand(&seed)) * 1.5, cj + tt_rand(&seed), 0}, n[3];
        assert_true(rf_terrain_height(t, p[0], p[1], &p[2], n));
        terrain_surface_normal(t, ci, cj, p[0], p[1], n);
        double v[3] = {tt_uniform(&seed, -20, 20), tt_uniform(&seed, -20, 20), tt_uniform(&seed, -20, 5)};
        double vn = dot(v, n);
        if (vn >= 0)
            for (int q = 0; q < 3; q++)
                v[q] -= (2 * vn + 0.01) * n[q];
        double w[3] = {tt_uniform(&seed, -30, 30), tt_uniform(&seed, -30, 30), tt_uniform(&seed, -30, 30)};
        double i_m = 0.4 * ts.spec.radius * ts.spec.radius, e0 = ke2(v, w, i_m);
        terrain_run r;
        run_at(&r, &tw, &ts, p);
        r.sample = (uint64_t)k;
        assert_int_equal(terrain_bounce(&r, ci, cj, v, w), 0);
        double e1 = ke2(v, w, i_m);
        if (!(e1 <= e0 * (1 + 1e-12)))
            fail_msg("impact %d (law %d): kinetic energy %.17g -> %.17g", k, (int)ts.spec.law, e0, e1);
        assert_true(dot(v, n) >= -1e-12 * sqrt(dot(v, v))); /* never into the true surface */
        tilted_away += dot(v, n) < 0.2 * sqrt(dot(v, v)) && ts.mat[0].roughness > 0;
    }
    assert_true(tilted_away > 0); /* grazing rebounds were produced (the guard was exercised) */
    rf_terrain_free(t);
}

/* An elastic law (R_n = R_t = 1) reflects about the tilted normal n', so
 * n' is along v_in - v_out: its angle from n has SD equal to the roughness
 * (1e4 impacts steeply from above, where no tilt is refused). */
static void test_roughness_tilt(void **state)
{
    (void)state;
    tt_plane pl = {0, 0.3, -0.2, 0, 0};
    rf_terrain *t = tt_dem(3, 3, 0, 0, 1, 1, tt_plane_z, &pl);
    tt_world tw;
    tt_world_init(&tw, t);
    tt_spec ts;
    tt_spec_init(&ts, 1, 1);
    ts.mat[0].roughness = 6 * TT_DEG;
    double n[3], p[3] = {1, 1, tt_plane_z(&pl, 1, 1)}, sum2 = 0, axis[3] = {0, 0, 0}, axis_len = 0;
    plane_normal(&pl, n);
    terrain_run r;
    run_at(&r, &tw, &ts, p);
    const int N = 10000;
    for (int k = 0; k < N; k++) {
        double v[3] = {-8 * n[0], -8 * n[1], -8 * n[2]}, v0[3], w[3] = {0, 0, 0}, d[3];
        memcpy(v0, v, sizeof v);
        uint64_t before = r.n_rough;
        assert_int_equal(terrain_bounce(&r, 0, 0, v, w), 0);
        assert_int_equal(r.n_rough, before + 2); /* two draws per impact */
        assert_close(sqrt(dot(v, v)), 8, 1e-12);
        for (int q = 0; q < 3; q++)
            d[q] = v0[q] - v[q];
        double c = -dot(d, n) / sqrt(dot(d, d)), ang = acos(fmin(1, c));
        sum2 += ang * ang;
        double dn = dot(d, n), m[3]; /* the tilt's direction in the tangent plane */
        for (int q = 0; q < 3; q++)
            m[q] = (d[q] - dn * n[q]) / sqrt(dot(d, d));
        for (int q = 0; q < 3; q++)
            axis[q] += m[q];
        axis_len += sqrt(dot(m, m));
    }
    /* the axis is uniform: the mean tilt direction ~ 0 (SE ~ 0.7% of the mean length) */
    assert_true(sqrt(dot(axis, axis)) < 0.05 * axis_len);
    double sd = sqrt(sum2 / N); /* |delta| of N(0, sd): RMS sd, its SE sd / sqrt(2N) = 0.7% */
    assert_close(sd, 6 * TT_DEG, 0.03);
    /* per-cell roughness overrides the material's */
    t->roughness = calloc(4, sizeof *t->roughness);
    for (int c = 0; c < 4; c++)
        t->roughness[c] = (float)(12 * TT_DEG);
    sum2 = 0;
    for (int k = 0; k < N; k++) {
        double v[3] = {-8 * n[0], -8 * n[1], -8 * n[2]}, v0[3], w[3] = {0, 0, 0}, d[3];
        memcpy(v0, v, sizeof v);
        terrain_bounce(&r, 0, 0, v, w);
        for (int q = 0; q < 3; q++)
            d[q] = v0[q] - v[q];
        double ang = acos(fmin(1, -dot(d, n) / sqrt(dot(d, d))));
        sum2 += ang * ang;
    }
    assert_close(sqrt(sum2 / N), 12 * TT_DEG, 0.03);
    rf_terrain_free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constant_and_scaled_any_aspect),
        cmocka_unit_test(test_rigid_sphere_in_plane_is_2d),
        cmocka_unit_test(test_energy_never_gained),
        cmocka_unit_test(test_roughness_tilt),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
