/* test_fem3d_plastic.c - elasto-plastic bodies and VTK output in the 3D FE
 * model, on coarse meshes (a/h = 2) and short runs: the logic that the
 * sanitizers see.  The linear point law against the matrix-free kernel; no
 * yield at a huge yield stress; a J2 slope, a J2 boulder and a Drucker-Prager
 * slope dissipate where they should and the energy account closes (the
 * elastic energy of the committed stresses against the internal work less the
 * dissipation); thread independence; the VTK files (sizes, fields, plastic
 * strain = the reported output); rf_fem_solve's VTK; the refusals; the model
 * identity.  The comparisons with the axisymmetric and elastic models at the
 * meshes they need are in tests/test_fem3d_plastic_accuracy.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fem_tune.h"
#include "rockfuzz/fem3d.h"
#include "rockfuzz/impact_model.h"
#include "rockfuzz/model.h"
#include "fem3d_plastic_inputs.h"
#include "vtu_reader.h"

/* The linear point law without B-bar is the matrix-free kernel to round-off, and a J2 slope
   (B-bar) of Y = 1e15 Pa never yields: a/h = 2, the loading part (the elastic R_n to 1e-4 at
   a/h = 2.5 is in tests/test_fem3d_plastic_accuracy.c). */
static void test_points_kernel_is_matrix_free(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    rf_fem_options o = coarse(2);
    o.end_time = 1.5e-3;
    rf_impact_output el, pts, j2;
    run3d(&in, &o, &el, NULL, NULL);
    TUNE(o).kernel[0] = TUNE(o).kernel[1] = RF_FEM_KERNEL_POINTS;
    run3d(&in, &o, &pts, NULL, NULL);
    assert_true(fabs(pts.contact_force_max - el.contact_force_max) < 1e-9 * el.contact_force_max);
    assert_true(fabs(pts.penetration_max - el.penetration_max) < 1e-9 * el.penetration_max);
    TUNE(o).kernel[0] = TUNE(o).kernel[1] = RF_FEM_KERNEL_STIFFNESS;
    in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = 1e15;
    run3d(&in, &o, &j2, NULL, NULL);
    assert_true(j2.plastic_work == 0 && j2.equivalent_plastic_strain_max == 0);
}

/* The plastic paths of the accuracy file on a/h = 2 and the loading part of the impact: a J2
   slope (normal impact: its dissipation is the history's, in body 2; both elastic energies are
   recorded; that they agree, to 2e-3 after the impact at a/h = 3, is the accuracy file's; at
   1.5 ms on a/h = 2 they differ by 1.4 %), a J2 boulder on a
   Drucker-Prager slope with a cap at 45 degrees (both dissipate; the energy closes). */
static void test_plastic_paths(void **state)
{
    (void)state;
    rf_impact_input in = granite(0, 0);
    in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = 200e6;
    rf_fem_options o = coarse(2);
    o.end_time = 1.5e-3;
    rf_impact_output out;
    rf_fem_history h = {0};
    run3d(&in, &o, &out, &h, NULL);
    print_message("J2 slope, a/h = 2 to 1.5 ms: W_p %.4f KE0, elastic energy %.5f (stresses) %.5f (work - "
                  "dissipation) of KE0, closure %.2e\n", out.plastic_work, h.elastic_energy_stress / h.ke0,
                  h.elastic_energy_work / h.ke0, out.energy_error);
    assert_true(h.plastic_work_boulder == 0 && h.plastic_work_slope > 0);
    assert_true(fabs(h.plastic_work_slope - out.plastic_work * h.ke0) < 1e-9 * h.ke0);
    assert_true(h.elastic_energy_stress > 0 && h.elastic_energy_work > 0);
    assert_int_equal(h.plastic_strain_max_in, 2);
    assert_true(fabs(out.energy_error) < 5e-3);
    rf_fem_history_free(&h);
    in = granite(45, 0);
    in.boulder_material = RF_MATERIAL_VON_MISES, in.boulder_yield = 200e6;
    in.slope_material = RF_MATERIAL_DRUCKER_PRAGER, in.slope_cohesion = 20e6;
    in.slope_friction_angle = 0.6, in.slope_dilatancy_angle = 0.1;
    in.slope_cap_pressure = 300e6, in.slope_cap_hardening = 5e9;
    run3d(&in, &o, &out, &h, NULL);
    print_message("J2 boulder on DP slope, 45 deg: W_p boulder %.4f slope %.4f KE0, closure %.2e\n",
                  h.plastic_work_boulder / h.ke0, h.plastic_work_slope / h.ke0, out.energy_error);
    assert_true(h.plastic_work_boulder > 0 && h.plastic_work_slope > 0);
    assert_true(fabs(out.energy_error) < 5e-3);
    rf_fem_history_free(&h);
}

/* The same bits on 1 and 2 threads with a plastic slope and boulder (f = 0.5). */
static void test_threads(void **state)
{
    (void)state;
    rf_impact_input in = granite(30, 0.5);
    in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = 200e6;
    in.boulder_material = RF_MATERIAL_VON_MISES, in.boulder_yield = 300e6;
    rf_fem_options o = coarse(2);
    o.end_time = 1e-3; /* the first part of the loading: both bodies yield */
    rf_impact_output a, b;
    uint64_t ha, hb;
    run3d(&in, &o, &a, NULL, &ha);
    o.threads = 2;
    run3d(&in, &o, &b, NULL, &hb);
    assert_true(ha == hb);
    assert_true(a.plastic_work == b.plastic_work && a.plastic_work > 0);
}

/* Read a whole file (NULL if absent). */
static char *slurp(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, fp) != (size_t)n)
        n = 0;
    if (s)
        s[n] = 0;
    fclose(fp);
    return s;
}

/* The largest value of the cell array `name` (n values) of a binary .vtu; -1 if absent. */
static double array_max(const vtu_file *f, const char *name, long n)
{
    size_t k;
    int nc;
    double *x = vtu_array(f, name, &k, &nc), m = -HUGE_VAL;
    if (!x || k != (size_t)n || nc != 1) {
        free(x);
        return -1;
    }
    for (size_t i = 0; i < k; i++)
        m = fmax(m, x[i]);
    free(x);
    return m;
}

/* VTK of a 45 degree impact on a J2 slope: a .pvd indexing every frame, each frame with the
   mesh's points and hexahedra, the fields named; the largest plastic strain over the frames is
   the reported output; writing frames changes no result. */
static void test_vtk(void **state)
{
    (void)state;
    char dir[] = "/tmp/rf_fem3d_vtk_XXXXXX";
    assert_non_null(mkdtemp(dir));
    rf_impact_input in = granite(45, 0.3);
    in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = 200e6;
    rf_fem_options o = coarse(2);
    rf_impact_output plain, out;
    uint64_t h0, h1;
    o.end_time = 1.5e-3; /* the loading part of the contact (4.8 ms): the plastic strain is there */
    run3d(&in, &o, &plain, NULL, &h0);
    o.vtk_dir = dir, TUNE(o).vtk_frames = 8;
    run3d(&in, &o, &out, NULL, &h1);
    assert_true(h0 == h1 && plain.R_t == out.R_t);
    char path[512];
    snprintf(path, sizeof path, "%s/fem.pvd", dir);
    char *pvd = slurp(path);
    assert_non_null(pvd);
    int frames = 0;
    for (const char *p = pvd; (p = strstr(p, "<DataSet")); p++)
        frames++;
    assert_true(frames >= 8 && frames <= 4 * (8 + 8));
    double emax = 0;
    for (int f = 0; f < frames; f++) {
        snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, f);
        vtu_file s;
        assert_true(vtu_open(path, &s) && vtu_layout_ok(&s));
        const long np = s.points, nc = s.cells;
        assert_true(np == (long)out.nodes && nc == (long)out.elements);
        static const char *const fields[] = {"displacement", "velocity", "sigma_xx", "sigma_yy", "sigma_zz",
                                             "sigma_xy", "sigma_yz", "sigma_zx", "body"};
        for (size_t k = 0; k < sizeof fields / sizeof *fields; k++) {
            char key[64];
            snprintf(key, sizeof key, "Name=\"%s\"", fields[k]);
            assert_non_null(strstr(s.bytes, key));
        }
        assert_true(array_max(&s, "types", nc) == 12);
        const double e = array_max(&s, "equivalent_plastic_strain", nc);
        assert_true(e >= 0);
        emax = fmax(emax, e);
        if (f == frames - 1) { /* the final state, bit for bit: the solver's state hash */
            size_t nu, nv;
            int c3;
            double *u = vtu_array(&s, "displacement", &nu, &c3), *v = vtu_array(&s, "velocity", &nv, &c3);
            assert_true(u && v && nu == 3 * (size_t)np && nv == nu);
            assert_true(vtu_fnv1a(vtu_fnv1a(VTU_FNV_SEED, u, nu * 8), v, nv * 8) == h1);
            free(u), free(v);
        }
        vtu_close(&s);
        unlink(path);
    }
    assert_true(fabs(emax - out.equivalent_plastic_strain_max) <= 1e-6 * out.equivalent_plastic_strain_max);
    free(pvd);
    snprintf(path, sizeof path, "%s/fem.pvd", dir);
    unlink(path);
    rmdir(dir);
}

/* rf_fem_solve (the CLI's and the impact model's entry) passes vtk_dir on to the 3D model. */
static void test_solve_vtk(void **state)
{
    (void)state;
    char dir[] = "/tmp/rf_fem3d_solve_XXXXXX", path[512];
    assert_non_null(mkdtemp(dir));
    rf_impact_input in = granite(45, 0);
    in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = 200e6;
    rf_fem_options o = coarse(2.5);
    o.end_time = 5e-4, o.vtk_dir = dir, TUNE(o).vtk_frames = 2;
    rf_impact_output out;
    rf_error err = {0};
    int three_d = 0;
    assert_int_equal(rf_fem_solve(&in, &o, &out, NULL, NULL, &three_d, &err), RF_OK);
    assert_int_equal(three_d, 1);
    snprintf(path, sizeof path, "%s/fem.pvd", dir);
    char *pvd = slurp(path);
    assert_non_null(pvd);
    int frames = 0;
    for (const char *p = pvd; (p = strstr(p, "<DataSet")); p++)
        frames++;
    free(pvd);
    assert_true(frames >= 2);
    unlink(path);
    for (int f = 0; f < frames; f++) {
        snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, f);
        assert_int_equal(unlink(path), 0);
    }
    rmdir(dir);
}

static void test_refusals(void **state)
{
    (void)state;
    rf_impact_input in = granite(30, 0);
    rf_fem_options o = coarse(2.5);
    rf_impact_output out;
    rf_error err = {0};
    /* (a rigid boulder and a layer run in 3D now: test_fem3d_layer) */
    TUNE(o).kernel[1] = (rf_fem_kernel)7;
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "kernel[1] = 7"));
    TUNE(o).kernel[1] = RF_FEM_KERNEL_STIFFNESS;
    o.vtk_dir = "/nonexistent/rockfuzz";
    assert_int_equal(rf_fem3d_impact(&in, &o, &out, NULL, &err), RF_EIO);
    assert_non_null(strstr(err.msg, "/nonexistent/rockfuzz/fem_0000.vtu"));
}

/* The model identity (result stores) tells a model that may run the 3D solver, which now takes
   plastic bodies and measures the crater, from the older one; the axisymmetric identity keeps. */
static void test_identity(void **state)
{
    (void)state;
    const char *names[1] = {"slope_angle"};
    for (int k = 0; k < 3; k++) {
        rf_impact_model_spec spec;
        rf_impact_model_spec_default(&spec);
        spec.solver = RF_IMPACT_FEM;
        if (k == 1)
            spec.base.slope_angle = 30 * DEG;
        rf_model m;
        rf_error err = {0};
        assert_int_equal(rf_impact_model_create(&spec, names, k == 2 ? 1 : 0, &m, &err), RF_OK);
        const int tagged = strstr(m.identity, "fem3d_materials=plastic_b_bar") != NULL;
        assert_int_equal(tagged, k > 0);
        rf_model_free(&m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refusals),       cmocka_unit_test(test_points_kernel_is_matrix_free),
        cmocka_unit_test(test_plastic_paths),  cmocka_unit_test(test_threads),
        cmocka_unit_test(test_vtk),            cmocka_unit_test(test_solve_vtk),
        cmocka_unit_test(test_identity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
