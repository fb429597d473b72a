/* test_fem3d.c - the 3D explicit impact solver on coarse meshes (a/h = 2) and
 * short runs, the logic the sanitizers see: the paths of the accuracy file
 * (normal: energy closure, no spin; frictionless oblique: no friction work;
 * sliding: friction work), determinism across thread counts with a reused
 * workspace, half vs full model, rejected inputs, the rigid-body moments of
 * the lumped boulder masses.  Hertz, the rigid-body formulas and the
 * axisymmetric model at a/h = 3 are in tests/test_fem3d_accuracy.c; the
 * converged figures in docs/validation-3d.md. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fem_tune.h"
#include "rockfuzz/fem3d.h"
#include "fem/fem3d_spec.h"
#include "fem3d_inputs.h"

/* The paths of tests/test_fem3d_accuracy.c at a/h = 2: a normal impact at 2 m/s past its peak
   force (the energy closes, no spin), frictionless 45 degrees (no friction work, the energy
   closes) and sliding at 60 degrees with f = 0.1 (friction work, forward spin), these two over the
   first 1.5 ms (the lumped I_yy, exact before the impact (test_mass_moments), is 1.5e-4 off the
   sphere's at 1.5 ms: the boulder deforms; 7e-7 after the impact at a/h = 3). */
static void test_paths_coarse(void **state)
{
    (void)state;
    rf_impact_input in = granite(2, 0, 0);
    rf_impact_output out;
    rf_fem3d_report rep;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 2, o.end_time = 4e-3; /* past the peak (3 ms) */
    rf_error err = {0};
    assert_int_equal(rf_fem3d_impact_ex(&in, &o, NULL, &out, NULL, &rep, &err), RF_OK);
    printf("# normal 2 m/s a/h = 2 to 4 ms: closure %.2e, omega %.2e\n", out.energy_error, out.omega_after);
    assert_true(out.energy_error < 1e-3 && fabs(out.omega_after) < 1e-6);
    rf_fem3d_report_free(&rep);
    o.end_time = 1.5e-3;
    for (int k = 0; k < 2; k++) {
        in = k == 0 ? granite(10, 45, 0) : granite(10, 60, 0.1);
        assert_int_equal(rf_fem3d_impact_ex(&in, &o, NULL, &out, NULL, &rep, &err), RF_OK);
        printf("# %s a/h = 2 to 1.5 ms: friction work %.3g J, omega %.4f, closure %.2e, I_yy/exact - 1 %.1e\n",
               k ? "60 deg f=0.1" : "45 deg f=0", rep.friction_work, out.omega_after, out.energy_error,
               rep.inertia_lumped / rep.inertia_exact - 1);
        assert_true(k ? rep.friction_work > 0 && out.omega_after > 0 : rep.friction_work == 0);
        assert_true(out.energy_error < 1e-3);
        rf_fem3d_report_free(&rep);
    }
}

/* The same bits for 1 and 2 threads (FNV-1a over the final u and v), in the
 * report and in the history alike.  Both runs share one workspace, so the
 * second also checks that a reused workspace leaves nothing behind. */
static void test_determinism(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 45, 0.6);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 2;
    o.end_time = 1e-3; /* the first part of the contact, sliding and sticking */
    uint64_t h[2];
    double rt[2];
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    assert_non_null(ws);
    for (int t = 0; t < 2; t++) {
        o.threads = t + 1;
        rf_impact_output out;
        rf_fem3d_report rep;
        rf_fem_history hist;
        rf_error err;
        assert_int_equal(rf_fem3d_impact_ws(ws, &in, &o, NULL, &out, &hist, &rep, &err), RF_OK);
        h[t] = rep.state_hash;
        assert_true(hist.state_hash == rep.state_hash);
        rt[t] = out.v_t_after;
        rf_fem3d_report_free(&rep);
        rf_fem_history_free(&hist);
    }
    rf_fem_workspace_free(ws);
    printf("# hash 1 thread %016llx, 2 threads %016llx\n", (unsigned long long)h[0], (unsigned long long)h[1]);
    assert_true(h[0] == h[1]);
    assert_true(rt[0] == rt[1]);
}

/* Half model (symmetry plane) and full model agree (a/h = 2, to 2.5 ms). */
static void test_half_vs_full(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 45, 0.6);
    rf_impact_output a, b;
    rf_fem3d_report ra, rb;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 2, o.end_time = 2.5e-3; /* past the peak force: symmetry holds at every step */
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    rf_error err = {0};
    assert_int_equal(rf_fem3d_impact_ex(&in, &o, &o3, &a, NULL, &ra, &err), RF_OK);
    o3.full_model = 1;
    assert_int_equal(rf_fem3d_impact_ex(&in, &o, &o3, &b, NULL, &rb, &err), RF_OK);
    printf("# half/full: F %.5g/%.5g R_n %.5f/%.5f R_t %.5f/%.5f omega %.4f/%.4f v_y %.2e\n", a.contact_force_max,
           b.contact_force_max, a.R_n, b.R_n, a.R_t, b.R_t, a.omega_after, b.omega_after, rb.v_y_after);
    assert_true(fabs(a.contact_force_max / b.contact_force_max - 1) < 1e-3);
    assert_true(fabs(a.R_n - b.R_n) < 1e-3);
    assert_true(fabs(a.R_t - b.R_t) < 1e-3);
    assert_true(fabs(a.omega_after / b.omega_after - 1) < 1e-3);
    /* v_y = 0 by mirror symmetry: 5e-9 m/s with the C0 master face and the offset centre of mass,
       up to 2.3e-6 with the exact centre on the C0 face (the faceted face amplified the round-off of
       the mirror-asymmetric sweep order), 1.3e-12 with the C1 face */
    assert_true(fabs(rb.v_y_after) < 1e-6);
    assert_true(b.elements > 1.9 * a.elements);
    rf_fem3d_report_free(&ra);
    rf_fem3d_report_free(&rb);
}

/* Lumped masses of the boulder mesh as the solver forms them (row sums of the consistent mass,
   density scaled to the spheroid's mass M); their mass, centre (x, z) and I_yy about it. */
static void boulder_moments(const f3_mesh *m, const double *elm, double mom[4])
{
    double M = 0, X = 0, Z = 0, I = 0;
    for (long k = 0; k < 8 * m->boulder_elems; k++) {
        const double *x = m->x + 3 * (long)m->conn[k];
        M += elm[k], X += elm[k] * x[0], Z += elm[k] * x[2];
    }
    X /= M, Z /= M;
    for (long k = 0; k < 8 * m->boulder_elems; k++) {
        const double *x = m->x + 3 * (long)m->conn[k];
        I += elm[k] * ((x[0] - X) * (x[0] - X) + (x[2] - Z) * (x[2] - Z));
    }
    mom[0] = M, mom[1] = X, mom[2] = Z, mom[3] = I;
}

/* f3_boulder_mass_moments gives the lumped masses the spheroid's mass, centre (0, d) and
   I_yy = M (c^2 + d^2) / 5 (half model: half of each), on the elongated, x-asymmetric mesh of the
   45 degree impact (whose lumped centre is 1e-3 r down-slope) and on a spheroid. */
static void check_mass_moments(const rf_impact_input *in, double c, double d, double min_offset)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = 3;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    f3_mesh_spec ms;
    f3_impact_mesh_spec(in, &o, &o3, &ms, NULL, NULL);
    f3_mesh m;
    rf_error err;
    assert_int_equal(f3_mesh_build(&ms, &m, 1000000, &err), RF_OK);
    double *elm = malloc((size_t)m.boulder_elems * 8 * sizeof *elm);
    assert_non_null(elm);
    const f3_material mat = {in->boulder_density, in->boulder_E, in->boulder_poisson};
    for (long e = 0; e < m.boulder_elems; e++) {
        double xe[24], K[576], vol;
        for (int a = 0; a < 8; a++)
            for (int q = 0; q < 3; q++)
                xe[3 * a + q] = m.x[3 * m.conn[8 * e + a] + q];
        f3_hex_matrices(xe, &mat, K, elm + 8 * e, &vol);
    }
    const double M = 4.0 / 3.0 * M_PI * c * c * d * in->boulder_density / 2, I = M * (c * c + d * d) / 5;
    double before[4], after[4];
    boulder_moments(&m, elm, before);
    for (long k = 0; k < 8 * m.boulder_elems; k++)
        elm[k] *= M / before[0];
    boulder_moments(&m, elm, before);
    assert_int_equal(f3_boulder_mass_moments(&m, elm, M, 0, d, I), 1);
    boulder_moments(&m, elm, after);
    printf("# lumped boulder (c %g, d %g): centre x %.2e -> %.2e, z - d %.2e -> %.2e, I_yy/exact - 1 %.2e -> %.2e\n",
           c, d, before[1], after[1], before[2] - d, after[2] - d, before[3] / I - 1, after[3] / I - 1);
    assert_true(fabs(before[1]) >= min_offset);
    assert_true(fabs(after[0] / M - 1) < 1e-12);
    assert_true(fabs(after[1]) < 1e-12 * c && fabs(after[2] - d) < 1e-12 * d);
    assert_true(fabs(after[3] / I - 1) < 1e-12);
    free(elm);
    f3_mesh_free(&m);
}

static void test_mass_moments(void **state)
{
    (void)state;
    rf_impact_input in = granite(10, 45, 0.6);
    check_mass_moments(&in, 1, 1, 1e-4); /* the elongated fine box: lumped centre 9.8e-4 r down-slope */
    in = granite(10, 0, 0);
    in.horizontal_axis = 1.2, in.vertical_axis = 0.8;
    check_mass_moments(&in, 1.2, 0.8, 0); /* symmetric in x: only z and I_yy to correct */
}

static void test_bad_input(void **state)
{
    (void)state;
    rf_impact_output out;
    rf_error err;
    rf_fem_options o;
    rf_fem_options_default(&o);
    rf_impact_input in = granite(10, 45, 0.6);
    in.velocity = -1;
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "velocity"));
    in = granite(10, 90, 0.6);
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "slope_angle"));
    in = granite(10, 45, -0.1);
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "friction"));
    in = granite(10, 45, NAN);
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    in = granite(10, 30, 0.6);
    in.horizontal_axis = 1.1;
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "spheroid"));
    in = granite(10, 45, 0.6);
    o.refinement = 1;
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "refinement"));
    rf_fem_options_default(&o);
    TUNE(o).max_elements = 1000;
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_ECAP);
    assert_int_equal(rf_fem3d_impact(&in, &o, NULL, NULL, &err), RF_EINVAL);
    assert_int_equal(rf_fem3d_impact(NULL, &o, &out, NULL, &err), RF_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_input),    cmocka_unit_test(test_paths_coarse),
        cmocka_unit_test(test_determinism),  cmocka_unit_test(test_half_vs_full),
        cmocka_unit_test(test_mass_moments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
