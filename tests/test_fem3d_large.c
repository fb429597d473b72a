/* test_fem3d_large.c - large deformation (updated Lagrangian) in the 3D FE
 * model (docs/validation-plastic.md section 9c): the hexahedron's
 * updated-Lagrangian point kernel against closed forms (objectivity under a
 * rigid rotation of any size about any axis; the hypoelastic uniaxial
 * compression to lambda = 1/2, second order in the steps), and whole impacts
 * (a rigid boulder on soft Drucker-Prager + cap soil against the axisymmetric
 * large-deformation model; the option, the step check and the model
 * identity).  Finer meshes and the elastic small-velocity check are in
 * tests/test_fem3d_large_accuracy.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem_tune.h"
#include "fem/fem3d_large.h"
#include "fem/fem_core.h"
#include "fem/fem_kernel.h"
#include "fem3d_large_inputs.h"
#include "rockfuzz/impact_model.h"
#include "rockfuzz/model.h"

/* One hexahedron (the unit cube, nodes in fem3d_element.c's order) in a
 * kernel of linear elasticity, updated Lagrangian if large != 0. */
typedef struct {
    double x[24];
    int conn[8];
    fem_lame lame;
    fem_kernel k;
} one_hex;

static void one_hex_init(one_hex *q, double E, double nu, int bbar, int large)
{
    static const double X[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    memcpy(q->x, X, sizeof q->x);
    for (int a = 0; a < 8; a++)
        q->conn[a] = a;
    q->lame = (fem_lame){E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))};
    const fem_point_law law = fem_point_law_linear3d(&q->lame);
    rf_error err = {0};
    assert_int_equal(fem_kernel_points_hex(&q->k, 0, 1, q->x, q->conn, &law, NULL, NULL, bbar, &err), RF_OK);
    if (large)
        assert_int_equal(fem_kernel_points_hex_large(&q->k, q->x, &err), RF_OK);
}

/* One step to the nodal positions xn: forces, commit; the mean stress. */
static void one_hex_move(one_hex *q, const double xn[24], double sig[6])
{
    double u[24], fe[24], ep;
    for (int i = 0; i < 24; i++)
        u[i] = xn[i] - q->x[i];
    q->k.ops->forces_field(&q->k, 0, q->k.units, u, fe);
    q->k.ops->commit(&q->k);
    assert_true(fem_kernel_points_hex_cell(&q->k, 0, sig, &ep));
}

/* Rotation matrix of angle t about the unit axis n (Rodrigues). */
static void rotation(const double n[3], double t, double Q[3][3])
{
    const double c = cos(t), s = sin(t);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            Q[i][j] = (i == j ? c : 0) + (1 - c) * n[i] * n[j];
    Q[0][1] -= s * n[2], Q[1][0] += s * n[2];
    Q[0][2] += s * n[1], Q[2][0] -= s * n[1];
    Q[1][2] -= s * n[0], Q[2][1] += s * n[0];
}

/* A cube strained by a general homogeneous deformation (stretch and shear,
 * 1e-3), then turned rigidly by 80 degrees about the axis (1, 2, 3) / sqrt 14
 * through its centre in 4 steps of 20 degrees.  The mid-step strain increment
 * of a rigid rotation is zero and the Cayley (Hughes-Winget) rotation of its
 * spin is the rotation itself, for any angle: the stress must be Q sigma Q^T
 * to round-off, with and without B-bar.  The small-strain kernel sees a
 * spurious strain of order 1 - cos(80 deg). */
static void test_rigid_rotation_objective(void **state)
{
    (void)state;
    const double E = 1e9, nu = 0.25, c[3] = {0.5, 0.5, 0.5}, th = 80 * M_PI / 180, r14 = sqrt(14.0);
    const double n[3] = {1 / r14, 2 / r14, 3 / r14};
    const double A[3][3] = {{1e-3, 2e-4, -3e-4}, {1e-4, -5e-4, 4e-4}, {-2e-4, 3e-4, 7e-4}};
    for (int run = 0; run < 3; run++) {
        const int large = run < 2, bbar = run == 1;
        one_hex q;
        one_hex_init(&q, E, nu, bbar, large);
        double xs[24], s0[6], s[6];
        for (int a = 0; a < 8; a++)
            for (int i = 0; i < 3; i++) {
                xs[3 * a + i] = q.x[3 * a + i];
                for (int j = 0; j < 3; j++)
                    xs[3 * a + i] += A[i][j] * (q.x[3 * a + j] - c[j]);
            }
        one_hex_move(&q, xs, s0);
        double Q[3][3];
        for (int k = 1; k <= 4; k++) {
            rotation(n, th * k / 4, Q);
            double xr[24];
            for (int a = 0; a < 8; a++)
                for (int i = 0; i < 3; i++) {
                    xr[3 * a + i] = c[i];
                    for (int j = 0; j < 3; j++)
                        xr[3 * a + i] += Q[i][j] * (xs[3 * a + j] - c[j]);
                }
            one_hex_move(&q, xr, s);
        }
        const double S[3][3] = {{s0[0], s0[3], s0[5]}, {s0[3], s0[1], s0[4]}, {s0[5], s0[4], s0[2]}};
        double R[3][3] = {{0}}, err = 0, smax = 0;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++)
                        R[i][j] += Q[i][a] * S[a][b] * Q[j][b];
                smax = fmax(smax, fabs(S[i][j]));
            }
        const double got[6] = {s[0], s[1], s[2], s[3], s[4], s[5]};
        const double want[6] = {R[0][0], R[1][1], R[2][2], R[0][1], R[1][2], R[2][0]};
        for (int i = 0; i < 6; i++)
            err = fmax(err, fabs(got[i] - want[i]) / smax);
        printf("rigid rotation 80 deg about (1,2,3), %s kernel%s: error %.2e of max |sigma| = %.4g Pa\n",
               large ? "updated-Lagrangian" : "small-strain", bbar ? " (B-bar)" : "", err, smax);
        if (large)
            assert_true(err < 1e-11);
        else
            assert_true(err > 0.1); /* the reference-geometry update is not objective */
        fem_kernel_release(&q.k);
    }
}

/* sigma_zz of a cube compressed homogeneously along z to lambda in N
 * geometric steps (nu = 0: no lateral stress or motion). */
static double compress(int N, double lambda, int bbar, double *lateral)
{
    const double E = 1e9;
    one_hex q;
    one_hex_init(&q, E, 0.0, bbar, 1);
    double s[6] = {0};
    for (int k = 1; k <= N; k++) {
        const double l = pow(lambda, (double)k / N);
        double xn[24];
        memcpy(xn, q.x, sizeof xn);
        for (int a = 0; a < 8; a++)
            xn[3 * a + 2] *= l;
        one_hex_move(&q, xn, s);
    }
    *lateral = fmax(fabs(s[0]), fmax(fabs(s[1]), fmax(fabs(s[3]), fmax(fabs(s[4]), fabs(s[5])))));
    fem_kernel_release(&q.k);
    return s[2];
}

/* Uniaxial compression to lambda = 1/2: the hypoelastic law integrates the
 * rate of deformation to sigma_zz = E ln(lambda) (no spin).  The mid-step
 * increment of a stretch x per step is 2 (x - 1) / (x + 1) = ln x -
 * (ln x)^3 / 12 + ...: over N steps the relative error is
 * -(ln 2)^2 / (12 N^2) to leading order (-1.0e-6 at N = 200), halving the
 * step quarters it.  The small-strain kernel would give E (lambda - 1), 28 % off. */
static void test_uniaxial_large_compression(void **state)
{
    (void)state;
    const double E = 1e9, lambda = 0.5, exact = E * log(lambda);
    for (int bbar = 0; bbar <= 1; bbar++) {
        double lat1, lat2;
        const double s1 = compress(200, lambda, bbar, &lat1), s2 = compress(400, lambda, bbar, &lat2);
        const double e1 = s1 / exact - 1, e2 = s2 / exact - 1, lead = log(2.0) * log(2.0) / (12.0 * 200 * 200);
        printf("uniaxial compression to lambda = 0.5 (B-bar %d): sigma_zz %.9g, E ln(lambda) %.9g; relative error "
               "%.3e at 200 steps (leading term %.3e), %.3e at 400 (ratio %.2f); lateral stress %.2g Pa\n",
               bbar, s1, exact, e1, lead, e2, e1 / e2, fmax(lat1, lat2));
        assert_true(fabs(e1 + lead) < 0.05 * lead); /* |sigma_zz| short of E |ln lambda| */
        assert_true(fabs(e1 / e2 - 4) < 0.1);
        assert_true(fmax(lat1, lat2) < 1e-9 * fabs(exact));
    }
}

/* (d) coarse: a rigid boulder at 5 m/s on soft Drucker-Prager + cap soil
 * (section 9c), 3D and axisymmetric both in large deformation at a/h = 2.
 * The meshes differ (cubes against the axisymmetric quads); at this a/h the
 * small-strain 3D and axisymmetric layer runs of section 9b differ by up to
 * 3 % in R_n: tolerances 5 % in R_n, 3 % in the penetration and W_p / KE; the
 * energy closes to 5e-3 of KE0 in both. */
static void test_soft_soil_vs_axisymmetric(void **state)
{
    (void)state;
    const rf_impact_input in = soft_soil_3d(0);
    const rf_fem_options o = large_options(2, RF_FEM_KINEMATICS_AUTO);
    const rf_fem3d_options o3 = large_options3d();
    assert_int_equal(rf_fem_large_deformation(&o, &in), 1); /* auto: a plastic body = large deformation */
    rf_impact_output r3, ax;
    rf_fem_history h3 = {0};
    run3d_ex(&in, &o, &o3, &r3, &h3, NULL);
    rf_error err = {0};
    assert_int_equal(rf_fem_impact(&in, &o, &ax, NULL, &err), RF_OK);
    show("soft soil 3D, large", &r3);
    show("soft soil axisym., large", &ax);
    /* the slope's elastic energy from its committed stresses against its internal work less its
       dissipation (the axisymmetric soft-soil test's closure target, 5e-3 KE0) */
    const double elastic_gap = (h3.elastic_energy_stress - h3.elastic_energy_work) / h3.ke0;
    print_message("elastic energy from stresses - from work: %.1e KE0\n", elastic_gap);
    assert_true(fabs(elastic_gap) < 5e-3);
    rf_fem_history_free(&h3);
    assert_true(fabs(r3.R_n / ax.R_n - 1) < 0.05);
    assert_true(fabs(r3.penetration_max / ax.penetration_max - 1) < 0.03);
    assert_true(fabs(r3.plastic_work / ax.plastic_work - 1) < 0.03);
    assert_true(fabs(r3.energy_error) < 5e-3 && fabs(ax.energy_error) < 5e-3);
    assert_true(r3.penetration_max > 0.04 * in.radius);
}

/* (d) coarse, on a layer (the code path; the comparison with the
 * axisymmetric model is in the accuracy file): section 9b's layer case
 * (rigid boulder, 10 m/s, a 0.1 m DP + cap layer over granite) in large
 * deformation at a/h = 2, its first 1.5 ms (of 5 ms): the layer's law and
 * the bedrock's in one UL block; the energy closes to 5e-3 of KE0, the layer
 * alone dissipates. */
static void test_layer_large(void **state)
{
    (void)state;
    const rf_impact_input in = dp_layer_case();
    rf_fem_options o = large_options(2, RF_FEM_KINEMATICS_AUTO);
    o.end_time = 1.5e-3;
    rf_impact_output l3;
    rf_fem_history h3 = {0};
    run3d_ex(&in, &o, NULL, &l3, &h3, NULL);
    show("DP layer 3D, large, 1.5 ms", &l3);
    assert_true(fabs(l3.energy_error) < 5e-3);
    assert_true(h3.plastic_work_boulder == 0 && h3.plastic_work_slope > 0 && h3.plastic_strain_max_in == 2);
    rf_fem_history_free(&h3);
}

/* The UL kernel writes only its own blocks' state: the soft-soil run gives
 * the same bits with 1 and 2 threads. */
static void test_threads_same_bits(void **state)
{
    (void)state;
    const rf_impact_input in = soft_soil_3d(0);
    rf_fem_options o = large_options(2, RF_FEM_KINEMATICS_AUTO);
    const rf_fem3d_options o3 = large_options3d();
    rf_impact_output a, b;
    uint64_t ha = 0, hb = 1;
    run3d_ex(&in, &o, &o3, &a, NULL, &ha);
    o.threads = 2;
    run3d_ex(&in, &o, &o3, &b, NULL, &hb);
    assert_true(ha == hb && a.R_n == b.R_n);
}

/* Every deformable body on the UL kernel (on): a von Mises boulder (its
 * co-rotated field on the UL kernel) at 10 m/s on elastic granite (the
 * linear law on the UL kernel), a/h = 2, the first 1 ms of the 4.4 ms
 * contact: the energy closes to 5e-3 of KE0 and the boulder yields. */
static void test_all_bodies_updated_lagrangian(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    in.boulder_material = RF_MATERIAL_VON_MISES, in.boulder_yield = 200e6;
    rf_fem_options o = large_options(2, RF_FEM_LARGE_DEFORMATION);
    o.end_time = 1e-3;
    rf_impact_output out;
    rf_fem_history h = {0};
    run3d_ex(&in, &o, NULL, &out, &h, NULL);
    show("J2 boulder, on, first 1 ms", &out);
    assert_true(fabs(out.energy_error) < 5e-3);
    assert_true(h.plastic_work_boulder > 0 && h.plastic_work_slope == 0);
    rf_fem_history_free(&h);
}

/* The element size of the step check against closed forms: a cube of side
 * h gives h / 2, turned rigidly the same, compressed to lambda h along any
 * axis lambda h / 2, inverted 0; and the check itself on that element: the
 * exact bound 2 / sqrt(lambda_max(M^-1 K)) scaled by the size, so that a step
 * just below the bound passes and fails once the element is compressed to
 * half its height. */
static void cube_element(void *ctx, long e, double K[576], double m[8], unsigned char fr[24])
{
    const f3_mesh *mesh = ctx;
    double xe[24], vol;
    for (int i = 0; i < 24; i++)
        xe[i] = mesh->x[3 * mesh->conn[8 * e + i / 3] + i % 3];
    const f3_material granite_mat = {2600, 68.2e9, 0.25};
    f3_hex_matrices(xe, &granite_mat, K, m, &vol);
    memset(fr, 1, 24);
}

static void test_step_check(void **state)
{
    (void)state;
    static const double X[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const double h = 0.2;
    double x[24], u[24] = {0};
    int conn[8];
    for (int i = 0; i < 24; i++)
        x[i] = h * X[i / 3][i % 3];
    for (int a = 0; a < 8; a++)
        conn[a] = a;
    f3_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    mesh.x = x, mesh.conn = conn, mesh.n_nodes = 8, mesh.n_elems = 1;
    assert_true(fabs(f3_element_size(&mesh, 0, NULL) - h / 2) < 1e-15);
    double Q[3][3];
    const double n[3] = {0.6, 0, 0.8};
    rotation(n, 1.0, Q);
    for (int a = 0; a < 8; a++) /* a rigid rotation: the same size */
        for (int i = 0; i < 3; i++) {
            u[3 * a + i] = -x[3 * a + i];
            for (int j = 0; j < 3; j++)
                u[3 * a + i] += Q[i][j] * x[3 * a + j];
        }
    assert_true(fabs(f3_element_size(&mesh, 0, u) - h / 2) < 1e-14);
    for (int axis = 0; axis < 3; axis++) { /* compressed to 0.3 h along each axis */
        memset(u, 0, sizeof u);
        for (int a = 0; a < 8; a++)
            u[3 * a + axis] = -0.7 * x[3 * a + axis];
        assert_true(fabs(f3_element_size(&mesh, 0, u) - 0.3 * h / 2) < 1e-14);
    }
    memset(u, 0, sizeof u);
    for (int a = 0; a < 8; a++) /* turned inside out */
        u[3 * a + 2] = -2 * x[3 * a + 2];
    assert_true(f3_element_size(&mesh, 0, u) == 0);
    double K[576], m[8], lam_upper;
    unsigned char fr[24];
    cube_element(&mesh, 0, K, m, fr);
    const double bound = 2 / sqrt(f3_hex_lambda_max(K, m, fr));
    lam_upper = hex8_gershgorin_bound(K, m, fr);
    f3_step_check c;
    rf_error err = {0};
    assert_int_equal(f3_step_check_init(&c, &mesh, 1, NULL, &lam_upper, cube_element, &mesh, &err), RF_OK);
    memset(u, 0, sizeof u);
    assert_true(f3_step_violation(&c, 0.999 * bound, u) == -1);
    for (int a = 0; a < 8; a++)
        u[3 * a + 2] = -0.5 * x[3 * a + 2];
    assert_true(f3_step_violation(&c, 0.49 * bound, u) == -1);
    assert_true(f3_step_violation(&c, 0.51 * bound, u) == 0);
    printf("step check: cube h = %g m, bound %.4g s, Gershgorin's %.4g s; %ld exact solve(s)\n", h, bound,
           2 / sqrt(lam_upper), c.n_exact);
    assert_true(c.n_exact == 1); /* found once, then kept */
    f3_step_check_free(&c);
}

/* The restart: attempts with the step halved while one is unstable, at most
 * FEM_STEP_HALVINGS times, the last attempt's status returned. */
typedef struct {
    int calls;
    double safety[8], unstable_above;
} halving_log;

static rf_status fake_attempt(void *ctx, const rf_fem_options *o, long *unstable, rf_error *err)
{
    halving_log *h = ctx;
    h->safety[h->calls++] = fem_tuning_of(o)->dt_safety;
    *unstable = fem_tuning_of(o)->dt_safety > h->unstable_above ? 7 : -1;
    return *unstable >= 0 ? rf_fail(err, RF_EMODEL, "unstable") : RF_OK;
}

static void test_step_halving(void **state)
{
    (void)state;
    rf_fem_options o;
    rf_fem_options_default(&o);
    TUNE(o).dt_safety = 0.8;
    rf_error err = {0};
    halving_log h = {0, {0}, 0.25};
    assert_int_equal(fem_run_halving(fake_attempt, &h, &o, &err), RF_OK);
    assert_int_equal(h.calls, 3);
    assert_true(h.safety[0] == 0.8 && h.safety[1] == 0.4 && h.safety[2] == 0.2);
    halving_log never = {0, {0}, 0};
    assert_int_equal(fem_run_halving(fake_attempt, &never, &o, &err), RF_EMODEL);
    assert_int_equal(never.calls, FEM_STEP_HALVINGS + 1);
    assert_true(TUNE(o).dt_safety == 0.8); /* the caller's options untouched */
}

/* The option: on is accepted in 3D; off keeps the small-strain kernel (the
 * earlier results); an elastic run on the UL kernel at small speed is the
 * small-strain one closely (the accuracy file holds the tolerance). */
static void test_kinematics_option_3d(void **state)
{
    (void)state;
    rf_fem_options o;
    rf_fem_options_default(&o);
    rf_error err = {0};
    o.large_deformation = RF_FEM_LARGE_DEFORMATION;
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_OK);
    o.large_deformation = (rf_fem_kinematics)9;
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "large_deformation = 9"));
}

/* The 3D identity names its kinematics: 3D results from before (small strain
 * in every case) and after never mix in a store. */
static int identity_has(const rf_impact_model_spec *spec, const char *what)
{
    rf_model model;
    rf_error err = {0};
    const char *names[2] = {"velocity", "slope_angle"};
    if (rf_impact_model_create(spec, names, 2, &model, &err) != RF_OK)
        fail_msg("%s", err.msg);
    const int has = strstr(model.identity, what) != NULL;
    rf_model_free(&model);
    return has;
}

static void test_identity_names_3d_kinematics(void **state)
{
    (void)state;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = RF_IMPACT_FEM;
    assert_false(identity_has(&spec, "fem3d_kinematics")); /* elastic: small strain, as before */
    spec.base.slope_material = RF_MATERIAL_VON_MISES, spec.base.slope_yield = 2e8;
    assert_true(identity_has(&spec, "fem3d_kinematics=updated_lagrangian"));
    spec.fem.large_deformation = RF_FEM_SMALL_STRAIN;
    assert_false(identity_has(&spec, "fem3d_kinematics")); /* off: the earlier 3D plastic identity */
}

/* The 3D mass redistribution (docs/validation-plastic.md 9e) is on by default, and named in the identity
 * where a soil may run in 3D (granite stores keep their identity); its off (the lumped face) is a second
 * method of the tests only, checked as a switch. */
static void test_surface_mass_3d_switch(void **state)
{
    (void)state;
    rf_error err = {0};
    rf_fem_options o;
    rf_fem_options_default(&o);
    assert_int_equal(TUNE(o).surface_mass_3d, 1); /* on by default (section 9e) */
    TUNE(o).surface_mass_3d = 2;
    assert_int_equal(rf_fem_options_validate(&o, 1, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "surface_mass_3d = 2"));
    assert_null(rf_fem_option_find("surface_mass_3d")); /* not a user's option */
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    spec.solver = RF_IMPACT_FEM;
    assert_false(identity_has(&spec, "fem3d_surface_mass")); /* granite: nothing is redistributed */
    spec.base.slope_material = RF_MATERIAL_VON_MISES, spec.base.slope_yield = 2e8;
    assert_true(identity_has(&spec, "fem3d_surface_mass=on"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rigid_rotation_objective),
        cmocka_unit_test(test_uniaxial_large_compression),
        cmocka_unit_test(test_kinematics_option_3d),
        cmocka_unit_test(test_identity_names_3d_kinematics),
        cmocka_unit_test(test_surface_mass_3d_switch),
        cmocka_unit_test(test_soft_soil_vs_axisymmetric),
        cmocka_unit_test(test_layer_large),
        cmocka_unit_test(test_all_bodies_updated_lagrangian),
        cmocka_unit_test(test_threads_same_bits),
        cmocka_unit_test(test_step_check),
        cmocka_unit_test(test_step_halving),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
