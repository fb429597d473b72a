/* test_fem.c - the axisymmetric FE impact solver against independent
 * references: Hertz (formulas of impact_refs.md section 1, recomputed here),
 * energy and momentum conservation, exact scale invariance, the spheroid
 * c = d == sphere identity, the time-step bound against a measured
 * instability, thread safety, and refusal of bad input.  Coarse meshes
 * (a/h = 3..5) so that the whole file runs in seconds, also under ASan. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem_tune.h"
#include "rockfuzz/fem.h"
#include "vtu_reader.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static rf_impact_input granite(double v)
{
    rf_impact_input in = {0};
    in.radius = 1;
    in.boulder_density = in.slope_density = 2600;
    in.boulder_E = in.slope_E = 68.2e9;
    in.boulder_poisson = in.slope_poisson = 0.25;
    in.velocity = v;
    return in;
}

typedef struct {
    double delta, force, radius, duration;
} hertz;

/* Hertz sphere (radius R, mass m) on a half-space: impact_refs.md 1.1. */
static hertz hertz_of(const rf_impact_input *in, double R, double m)
{
    double Es = 1 / ((1 - in->boulder_poisson * in->boulder_poisson) / in->boulder_E +
                     (1 - in->slope_poisson * in->slope_poisson) / in->slope_E);
    double V = in->velocity;
    hertz h;
    h.delta = pow(15 * m * V * V / (16 * Es * sqrt(R)), 0.4);
    h.force = 1.25 * m * V * V / h.delta;
    h.radius = sqrt(R * h.delta);
    h.duration = 2.94328 * h.delta / V;
    return h;
}

static double sphere_mass(const rf_impact_input *in)
{
    return 4.0 / 3.0 * M_PI * pow(in->radius, 3) * in->boulder_density;
}

static void run(const rf_impact_input *in, const rf_fem_options *o, rf_impact_output *out, rf_fem_history *h)
{
    rf_error err = {0};
    rf_status st = rf_fem_impact(in, o, out, h, &err);
    if (st != RF_OK)
        fail_msg("rf_fem_impact: %s", err.msg);
}

/* Granite table of impact_refs.md 1.2 reproduced by the local formulas. */
static void test_hertz_reference_numbers(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    hertz h = hertz_of(&in, 1, sphere_mass(&in));
    assert_true(fabs(h.delta / 1.51112e-2 - 1) < 1e-4);
    assert_true(fabs(h.force / 9.0089e7 - 1) < 1e-4);
    assert_true(fabs(h.radius / 0.12293 - 1) < 1e-4);
    assert_true(fabs(h.duration / 4.4477e-3 - 1) < 1e-4);
}

/* Low speed (a/R = 0.049): force, compression and duration near Hertz, with
 * the signs of finite-body stiffening (fem_notes.md); local contact radius
 * within 2 %. */
static void test_low_speed_hertz(void **state)
{
    (void)state;
    rf_impact_input in = granite(1);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 4;
    o.boundary = RF_FEM_BOUNDARY_ABSORBING;
    rf_impact_output out;
    rf_fem_history h;
    run(&in, &o, &out, &h);
    hertz ref = hertz_of(&in, 1, sphere_mass(&in));
    double dF = out.contact_force_max / ref.force - 1, dd = out.compression_max / ref.delta - 1;
    double dt = out.contact_duration / ref.duration - 1, da = out.contact_radius / ref.radius - 1;
    printf("1 m/s a/h=4: dF %+.4f dd %+.4f dt %+.4f da %+.4f\n", dF, dd, dt, da);
    assert_true(dF > 0 && dF < 0.02);
    assert_true(dd < 0 && dd > -0.015);
    assert_true(dt < 0 && dt > -0.015);
    assert_true(fabs(da) < 0.02);
    /* exact multipliers: no penetration */
    assert_true(h.penetration_max < 1e-3 * out.compression_max);
    assert_true(h.warning[0] == 0);
    rf_fem_history_free(&h);
}

/* 10 m/s: contact radius Hertzian, energy closes, energy lost by the boulder
 * = energy left in the half-space + boulder vibration, momentum constant
 * after separation, R_n inside the physical range. */
static void test_energy_and_momentum(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 4;
    o.domain_factor = 10; /* the seed paper's model, which reflects (checked below) */
    rf_impact_output out;
    rf_fem_history h;
    run(&in, &o, &out, &h);
    hertz ref = hertz_of(&in, 1, sphere_mass(&in));
    assert_true(fabs(out.contact_radius / ref.radius - 1) < 0.02);
    assert_true(out.energy_error < 1e-3);
    double ke0 = 0.5 * sphere_mass(&in) * 100;
    assert_true(fabs(h.ke0 / ke0 - 1) < 1e-12); /* exact boulder mass */
    /* closure of the account at every sample */
    for (size_t i = 0; i < h.n; i++) {
        double tot = h.kinetic_boulder[i] + h.strain_boulder[i] + h.kinetic_slope[i] + h.strain_slope[i] +
                     h.absorbed[i] - ke0;
        assert_true(fabs(tot - h.closure[i]) < 1e-9 * ke0);
        assert_true(fabs(h.closure[i]) < 1e-3 * ke0);
    }
    double lost = ke0 - 0.5 * h.boulder_mass * out.v_n_after * out.v_n_after;
    assert_true(fabs(lost - (h.slope_energy + h.vibration_energy)) < 1e-3 * ke0);
    assert_true(h.vibration_energy >= 0 && h.vibration_energy < 0.1 * lost);
    /* rigid velocity constant after separation */
    size_t n = h.n;
    assert_true(n > 10);
    assert_true(fabs(h.boulder_velocity[n - 1] - h.boulder_velocity[n - 5]) < 1e-9);
    assert_true(fabs(h.boulder_velocity[n - 1] - out.v_n_after) < 1e-9);
    assert_true(out.R_n > 0.97 && out.R_n < 1);
    assert_true(fabs(out.R_ke - out.R_n * out.R_n) < 1e-12);
    assert_true(isnan(out.R_t));
    assert_true(out.v_n_before == -10);
    /* 2L/c_p = 3.6 ms < 4.4 ms: the fixed boundary warning */
    assert_non_null(strstr(h.warning, "reflected"));
    rf_fem_history_free(&h);
}

/* Absorbing boundary: the dashpots take energy out, R_n within the
 * Hunter-type band widened for the coarse mesh, no reflection warning. */
static void test_absorbing(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 4;
    o.boundary = RF_FEM_BOUNDARY_ABSORBING;
    rf_impact_output out;
    rf_fem_history h;
    run(&in, &o, &out, &h);
    double c0 = sqrt(in.boulder_E / in.boulder_density);
    double lam_lo = 1.04 * pow(10 / c0, 0.6), lam_hi = 1.171 * pow(10 / c0, 0.6);
    printf("absorbing R_n %.5f, Hunter band %.5f..%.5f, absorbed %.3g KE0\n", out.R_n, sqrt(1 - lam_hi),
           sqrt(1 - lam_lo), h.absorbed[h.n - 1] / h.ke0);
    assert_true(out.R_n > sqrt(1 - lam_hi) - 0.002 && out.R_n < sqrt(1 - lam_lo) + 0.002);
    assert_true(h.absorbed[h.n - 1] > 0);
    assert_true(h.warning[0] == 0);
    assert_true(out.energy_error < 1e-3);
    rf_fem_history_free(&h);
}

/* The default domain is sized so that the P wave reflected by the fixed
 * outer surface returns after the contact ends: at 1 m/s (the longest
 * contact, 7.0 ms) 2 L / c_p >= 1.25 t_c with c_p = sqrt(E (1 - nu) /
 * (rho (1 + nu) (1 - 2 nu))) = 5611 m/s computed here, so L >= 24.5 r0; no
 * reflection warning, and the contact closes once. */
static void test_default_domain(void **state)
{
    (void)state;
    rf_impact_input in = granite(1);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3;
    rf_impact_output out;
    rf_fem_history h;
    run(&in, &o, &out, &h);
    const double nu = in.slope_poisson;
    const double c_p = sqrt(in.slope_E * (1 - nu) / (in.slope_density * (1 + nu) * (1 - 2 * nu)));
    hertz ref = hertz_of(&in, 1, sphere_mass(&in));
    const double factor = rf_fem_domain_factor(&o, &in);
    printf("default domain at 1 m/s: %g r0, 2L/c_p = %.4g ms, Hertz t_c = %.4g ms, R_n = %.5f\n", factor,
           2e3 * factor / c_p, 1e3 * ref.duration, out.R_n);
    assert_true(2 * factor * in.radius / c_p >= 1.25 * ref.duration);
    assert_true(factor < 30); /* not grossly oversized either */
    assert_true(fabs(h.reflection_time - 2 * factor / c_p) < 1e-9 * h.reflection_time);
    assert_true(h.warning[0] == 0);
    o.domain_factor = 10; /* the seed paper's model warns */
    assert_true(rf_fem_domain_factor(&o, &in) == 10);
    rf_fem_history_free(&h);
}

/* Without gravity the problem is scale free: doubling every length leaves
 * R_n unchanged and doubles the duration (the mesh scales exactly). */
static void test_scale_invariance(void **state)
{
    (void)state;
    rf_impact_input a = granite(10), b = granite(10);
    b.radius = 2;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3;
    rf_impact_output oa, ob;
    run(&a, &o, &oa, NULL);
    run(&b, &o, &ob, NULL);
    assert_true(fabs(oa.R_n - ob.R_n) < 1e-7);
    assert_true(fabs(ob.contact_duration / oa.contact_duration - 2) < 1e-6);
    assert_true(fabs(ob.compression_max / oa.compression_max - 2) < 1e-6);
    assert_true(fabs(ob.contact_force_max / oa.contact_force_max - 4) < 4e-6);
    assert_true(oa.elements == ob.elements);
}

/* A spheroid with c = d is the sphere; c != d agrees locally with Hertz at
 * the pole curvature radius c^2/d. */
static void test_spheroid(void **state)
{
    (void)state;
    rf_impact_input s = granite(10), e = granite(10);
    e.horizontal_axis = 1;
    e.vertical_axis = 1;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3;
    rf_impact_output os, oe;
    run(&s, &o, &os, NULL);
    run(&e, &o, &oe, NULL);
    assert_true(os.R_n == oe.R_n && os.contact_force_max == oe.contact_force_max);

    e.horizontal_axis = 1.1;
    e.vertical_axis = 0; /* volume preserving: d = r0^3 / c^2 */
    o.refinement = 4;
    run(&e, &o, &oe, NULL);
    double c = 1.1, d = 1 / (c * c), m = 4.0 / 3.0 * M_PI * c * c * d * e.boulder_density;
    hertz ref = hertz_of(&e, c * c / d, m);
    printf("spheroid c=1.1: da %+.4f dF %+.4f\n", oe.contact_radius / ref.radius - 1,
           oe.contact_force_max / ref.force - 1);
    assert_true(fabs(oe.contact_radius / ref.radius - 1) < 0.02);
    assert_true(fabs(oe.contact_force_max / ref.force - 1) < 0.05);
}

/* The element eigenvalue bound is rigorous: the step it gives is stable,
 * while 1.5 times it (measured unstable) diverges and is reported. */
static void test_time_step_bound(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3;
    TUNE(o).dt_safety = 1.0;
    rf_impact_output out;
    rf_fem_history h;
    run(&in, &o, &out, &h);
    assert_true(out.energy_error < 1e-3);
    assert_true(h.dt == h.dt_bound);
    rf_fem_history_free(&h);
    TUNE(o).dt_safety = 1.5;
    rf_error err = {0};
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EMODEL);
    assert_non_null(strstr(err.msg, "unstable"));
}

/* Non-matching boulder/slope meshes give the same answer as matching ones. */
static void test_non_matching(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 4;
    rf_impact_output a, b;
    run(&in, &o, &a, NULL);
    TUNE(o).boulder_mesh_ratio = 0.7;
    rf_fem_history h;
    run(&in, &o, &b, &h);
    assert_true(fabs(b.contact_force_max / a.contact_force_max - 1) < 0.01);
    assert_true(fabs(b.compression_max / a.compression_max - 1) < 0.005);
    assert_true(fabs(b.R_n - a.R_n) < 1e-3);
    assert_true(h.penetration_max < 1e-3 * b.compression_max);
    assert_true(h.slip_max < 0.05 * h.h_contact); /* small sliding holds */
    rf_fem_history_free(&h);
}

typedef struct {
    rf_impact_input in;
    rf_fem_options o;
    rf_impact_output out;
    rf_status st;
} job;

static void *worker(void *p)
{
    job *j = p;
    rf_error err = {0};
    j->st = rf_fem_impact(&j->in, &j->o, &j->out, NULL, &err);
    return NULL;
}

/* Concurrent calls share nothing: same results as serial ones. */
static void test_thread_safety(void **state)
{
    (void)state;
    job jobs[3];
    double v[3] = {5, 10, 20};
    for (int i = 0; i < 3; i++) {
        jobs[i].in = granite(v[i]);
        rf_fem_options_default(&jobs[i].o);
        jobs[i].o.refinement = 2; /* bits compared: any mesh shows a race */
    }
    pthread_t th[3];
    for (int i = 0; i < 3; i++)
        assert_int_equal(pthread_create(&th[i], NULL, worker, &jobs[i]), 0);
    for (int i = 0; i < 3; i++)
        pthread_join(th[i], NULL);
    for (int i = 0; i < 3; i++) {
        assert_int_equal(jobs[i].st, RF_OK);
        rf_impact_output serial;
        run(&jobs[i].in, &jobs[i].o, &serial, NULL);
        assert_true(serial.R_n == jobs[i].out.R_n);
        assert_true(serial.contact_force_max == jobs[i].out.contact_force_max);
    }
    /* two OpenMP threads inside one impact: same physics to round-off */
    rf_impact_output one, two;
    rf_fem_options o = jobs[1].o;
    run(&jobs[1].in, &o, &one, NULL);
    o.threads = 2;
    run(&jobs[1].in, &o, &two, NULL);
    assert_true(fabs(one.R_n - two.R_n) < 1e-9);
    assert_true(fabs(one.contact_force_max / two.contact_force_max - 1) < 1e-9);
}

/* Determinism: the same bits (FNV-1a over the final u and v) for 1, 2 and 3
 * threads: element forces are assembled per node in element order. */
static void test_determinism(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3;
    o.end_time = 2e-3;
    uint64_t hash[3];
    double rn[3];
    for (int t = 0; t < 3; t++) {
        o.threads = t + 1;
        rf_impact_output out;
        rf_fem_history h;
        run(&in, &o, &out, &h);
        hash[t] = h.state_hash;
        rn[t] = out.v_n_after;
        rf_fem_history_free(&h);
    }
    printf("# hash 1 thread %016llx, 2 threads %016llx, 3 threads %016llx\n", (unsigned long long)hash[0],
           (unsigned long long)hash[1], (unsigned long long)hash[2]);
    assert_true(hash[0] == hash[1] && hash[0] == hash[2]);
    assert_true(rn[0] == rn[1] && rn[0] == rn[2]);
}

/* A workspace reused across evaluations of different sizes gives the
 * numbers of a fresh one, bit for bit. */
static void test_workspace_reuse(void **state)
{
    (void)state;
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    assert_non_null(ws);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 2; /* bits compared: any mesh shows leftover state */
    const double speeds[3] = {10, 30, 10};
    for (int k = 0; k < 3; k++) {
        rf_impact_input in = granite(speeds[k]);
        rf_impact_output a, b;
        rf_error err = {0};
        assert_int_equal(rf_fem_impact_ws(ws, &in, &o, &a, NULL, &err), RF_OK);
        run(&in, &o, &b, NULL);
        assert_true(a.R_n == b.R_n && a.contact_force_max == b.contact_force_max && a.steps == b.steps);
    }
    rf_fem_workspace_free(ws);
}

/* The material interface: linear elasticity through the integration-point
 * kernel (strain from B u, stress update by a point law, B^T sigma) against
 * the precomputed-stiffness kernel, both bodies, 10 m/s up to peak force.
 * Same physics, different arithmetic: equal to round-off (measured 2e-14 on a
 * whole impact). */
static void test_point_kernel(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3;
    o.domain_factor = 10;
    o.end_time = 2.5e-3;
    rf_impact_output a, b;
    run(&in, &o, &a, NULL);
    TUNE(o).kernel[0] = TUNE(o).kernel[1] = RF_FEM_KERNEL_POINTS;
    run(&in, &o, &b, NULL);
    printf("# point kernel: F %.3g, delta %.3g, v %.3g relative to the stiffness kernel\n",
           b.contact_force_max / a.contact_force_max - 1, b.compression_max / a.compression_max - 1,
           b.v_n_after / a.v_n_after - 1);
    assert_true(a.steps == b.steps);
    assert_true(fabs(b.contact_force_max / a.contact_force_max - 1) < 1e-10);
    assert_true(fabs(b.compression_max / a.compression_max - 1) < 1e-10);
    assert_true(fabs(b.v_n_after / a.v_n_after - 1) < 1e-10);
    assert_true(fabs(b.energy_error - a.energy_error) < 1e-10);
    rf_error err = {0}; /* 3D has the point kernel too (test_fem3d_plastic); an unknown kernel is refused */
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_OK);
    TUNE(o).kernel[0] = (rf_fem_kernel)5;
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "kernel[0]"));
}

/* One rule table checks the options; each message names the setting and
 * its value, and the 3D limits differ where the table says so. */
static void test_options_validate(void **state)
{
    (void)state;
    rf_fem_options o;
    rf_fem_options_default(&o);
    rf_error err = {0};
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_OK);
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_OK);
    o.refinement = 200; /* fine for the axisymmetric model, not for 3D */
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_OK);
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "refinement = 200"));
    rf_fem_options_default(&o);
    o.domain_factor = 2;
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "domain_factor = 2"));
    rf_fem_options_default(&o);
    TUNE(o).dt_safety = NAN;
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "dt_safety"));
    rf_fem_options_default(&o);
    o.end_time = INFINITY;
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "end_time"));
    rf_fem_options_default(&o);
    o.boundary = (rf_fem_boundary)7;
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_EINVAL);
    rf_fem_options_default(&o);
    o.threads = -1;
    assert_int_equal(rf_fem_options_validate(&o, 0, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "threads = -1"));
    /* defaults resolve: 10 axisymmetric, 6 in 3D; an explicit domain is kept */
    rf_fem_options_default(&o);
    assert_true(rf_fem_refinement(&o, 0) == 10 && rf_fem_refinement(&o, 1) == 3);
    rf_impact_input in = granite(10);
    o.domain_factor = 12;
    assert_true(rf_fem_domain_factor(&o, &in) == 12);
    rf_fem_boundary b;
    assert_int_equal(rf_fem_boundary_parse("absorbing", &b, &err), RF_OK);
    assert_int_equal(b, RF_FEM_BOUNDARY_ABSORBING);
    assert_string_equal(rf_fem_boundary_name(RF_FEM_BOUNDARY_FIXED), "fixed");
}

static void test_bad_input(void **state)
{
    (void)state;
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    rf_impact_output out;
    rf_error err = {0};
    in.slope_angle = 0.5;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "normal impact"));
    in = granite(10);
    o.refinement = 1.5;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "refinement = 1.5"));
    rf_fem_options_default(&o);
    in.velocity = 0;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    in = granite(10);
    in.boulder_poisson = 0.5;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    in = granite(10);
    in.slope_E = NAN;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    in = granite(10);
    o.domain_factor = 1;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    rf_fem_options_default(&o);
    TUNE(o).boulder_mesh_ratio = 2; /* slave side coarser than the master: refused */
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    rf_fem_options_default(&o);
    TUNE(o).max_elements = 100;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_ECAP);
    rf_fem_options_default(&o);
    in.velocity = 2000; /* contact zone larger than the boulder */
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    in = granite(10);
    assert_int_equal(rf_fem_impact(&in, &o, NULL, NULL, &err), RF_EINVAL);
}

/* The nodal 3-vectors of array name with the third component dropped (the
 * axisymmetric model's (r, z) pairs), NULL if absent or not n x 3. */
static double *planar(const vtu_file *f, const char *name, long nodes)
{
    size_t n;
    int nc;
    double *x = vtu_array(f, name, &n, &nc);
    if (!x || nc != 3 || n != 3 * (size_t)nodes) {
        free(x);
        return NULL;
    }
    for (long i = 0; i < nodes; i++) {
        assert_true(x[3 * i + 2] == 0);
        x[2 * i] = x[3 * i], x[2 * i + 1] = x[3 * i + 1];
    }
    return x;
}

/* One binary frame against the mesh: counts, quads, offsets, node ids, bodies; the
 * nodal displacement and velocity as the solver's (r, z) pairs into u, v. */
static void check_frame(const char *path, const rf_impact_output *out, const rf_fem_history *h, double **u,
                        double **v)
{
    vtu_file f;
    assert_true(vtu_open(path, &f));
    assert_true(vtu_layout_ok(&f));
    assert_int_equal(f.points, (long)out->nodes);
    assert_int_equal(f.cells, (long)out->elements);
    size_t n, nt, no, nb;
    int nc;
    double *conn = vtu_array(&f, "connectivity", &n, &nc), *types = vtu_array(&f, "types", &nt, &nc);
    double *off = vtu_array(&f, "offsets", &no, &nc), *body = vtu_array(&f, "body", &nb, &nc);
    double *szz = vtu_array(&f, "sigma_zz", &n, &nc);
    assert_true(conn && types && off && body && szz && n == (size_t)f.cells);
    assert_true(nt == (size_t)f.cells && no == (size_t)f.cells && nb == (size_t)f.cells);
    long boulder = 0;
    for (long e = 0; e < f.cells; e++) {
        assert_true(types[e] == 9 && off[e] == 4.0 * (double)(e + 1) && (body[e] == 0 || body[e] == 1));
        boulder += body[e] == 0;
        for (int a = 0; a < 4; a++)
            assert_true(conn[4 * e + a] >= 0 && conn[4 * e + a] < (double)f.points);
    }
    assert_int_equal(boulder, h->boulder_elements);
    *u = planar(&f, "displacement", f.points), *v = planar(&f, "velocity", f.points);
    assert_true(*u && *v);
    free(conn), free(types), free(off), free(body), free(szz);
    vtu_close(&f);
}

/* VTK output: a .pvd index and binary .vtu frames (appended raw arrays),
 * decoded by an independent reader: the first frame holds the initial state
 * (no displacement; the boulder's nodes at -V, the slope's at rest), the last
 * one the final state, bit for bit (its hash is the solver's state_hash). */
static void test_vtk(void **state)
{
    (void)state;
    char dir[] = "/tmp/rockfuzz_fem_vtkXXXXXX";
    assert_non_null(mkdtemp(dir));
    rf_impact_input in = granite(10);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 2;
    o.vtk_dir = dir;
    TUNE(o).vtk_frames = 3;
    rf_impact_output out;
    rf_fem_history h = {0};
    run(&in, &o, &out, &h);
    char path[512], line[512];
    snprintf(path, sizeof path, "%s/fem.pvd", dir);
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    int frames = 0;
    while (fgets(line, sizeof line, fp))
        frames += strstr(line, "<DataSet") != NULL;
    fclose(fp);
    assert_true(frames >= 4); /* about 3, and the final state */
    for (int i = 0; i < frames; i++) {
        snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, i);
        double *u, *v;
        check_frame(path, &out, &h, &u, &v);
        const long nn = (long)out.nodes;
        if (i == 0) {
            long moving = 0;
            for (long k = 0; k < 2 * nn; k++)
                assert_true(u[k] == 0);
            for (long k = 0; k < nn; k++) {
                assert_true(v[2 * k] == 0 && (v[2 * k + 1] == 0 || v[2 * k + 1] == -in.velocity));
                moving += v[2 * k + 1] != 0;
            }
            assert_int_equal(moving, h.boulder_nodes);
        }
        if (i == frames - 1) {
            const size_t bytes = (size_t)(2 * nn) * sizeof(double);
            assert_true(vtu_fnv1a(vtu_fnv1a(VTU_FNV_SEED, u, bytes), v, bytes) == h.state_hash);
        }
        free(u), free(v);
        unlink(path);
    }
    rf_fem_history_free(&h);
    snprintf(path, sizeof path, "%s/fem.pvd", dir);
    unlink(path);
    rmdir(dir);
    /* an unwritable directory is an I/O error, not a crash */
    o.vtk_dir = "/nonexistent/rockfuzz";
    rf_error err = {0};
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_EIO);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hertz_reference_numbers),
        cmocka_unit_test(test_low_speed_hertz),
        cmocka_unit_test(test_energy_and_momentum),
        cmocka_unit_test(test_absorbing),
        cmocka_unit_test(test_default_domain),
        cmocka_unit_test(test_scale_invariance),
        cmocka_unit_test(test_spheroid),
        cmocka_unit_test(test_time_step_bound),
        cmocka_unit_test(test_non_matching),
        cmocka_unit_test(test_thread_safety),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_workspace_reuse),
        cmocka_unit_test(test_point_kernel),
        cmocka_unit_test(test_options_validate),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_vtk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
