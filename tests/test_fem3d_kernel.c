/* test_fem3d_kernel.c - the hexahedron's integration-point kernel
 * (src/fem/fem_kernel_points3d.c) against independent references: with the
 * linear 3D law and no B-bar it reproduces the matrix-free elastic kernel
 * (hex8_kernel.c) to round-off on random distorted elements; with B-bar the
 * linear operator stays symmetric, leaves a constant-strain field unchanged
 * and carries one mean pressure per element; the material point law with a
 * huge yield stress equals the linear one; a J2 point driven into plastic
 * flow reports a dissipation equal to the work sum_q w_q sigma : deps less
 * the stored elastic energy; at the soil's strains under a sunk boulder (a
 * uniform compression 0.7 through the Drucker-Prager cap, with shear) every
 * point carries the stress of one material point driven along the same path,
 * the forces do the virtual work of that stress and the dissipation is the
 * point's times the volume; two laws in one block act element by element. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fem/fem3d_internal.h"
#include "fem/fem_kernel.h"
#include "fem/fem_kernel_points3d.h"
#include "fem/hex8_kernel.h"

enum { NE = 13 };

static double urand(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* ne independent distorted elements (unit cubes stretched, sheared, corners moved). */
static void random_elements(long ne, unsigned long long seed, double *x, int *conn)
{
    static const double XI[8] = {0, 1, 1, 0, 0, 1, 1, 0}, ETA[8] = {0, 0, 1, 1, 0, 0, 1, 1},
                        ZETA[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (long e = 0; e < ne; e++) {
        const double sx = 0.5 + urand(&seed), sy = 0.5 + urand(&seed), sz = 0.5 + urand(&seed);
        const double shear = 0.4 * (urand(&seed) - 0.5);
        for (int a = 0; a < 8; a++) {
            double *p = x + 24 * e + 3 * a;
            p[0] = sx * XI[a] + shear * ZETA[a] + 0.25 * (urand(&seed) - 0.5);
            p[1] = sy * ETA[a] + 0.25 * (urand(&seed) - 0.5);
            p[2] = sz * ZETA[a] + 0.25 * (urand(&seed) - 0.5);
            conn[8 * e + a] = (int)(8 * e + a);
        }
    }
}

static const fem_lame LAME = {27.28e9, 27.28e9}; /* granite: E = 68.2 GPa, nu = 0.25 */

static double max_abs(const double *a, long n)
{
    double m = 0;
    for (long i = 0; i < n; i++)
        m = fmax(m, fabs(a[i]));
    return m;
}

static void field_forces(fem_kernel *k, const double *u, double *fe)
{
    k->ops->forces_field(k, 0, k->units, u, fe);
}

static void test_linear_equals_matfree(void **state)
{
    (void)state;
    double x[24 * NE], u[24 * NE], f1[24 * NE], f2[24 * NE];
    int conn[8 * NE];
    unsigned long long s = 7;
    random_elements(NE, 11, x, conn);
    for (int i = 0; i < 24 * NE; i++)
        u[i] = 1e-4 * (urand(&s) - 0.5);
    fem_kernel km, kp;
    rf_error err;
    assert_int_equal(fem_kernel_hex8_matfree(&km, 0, NE, x, conn, LAME.lam, LAME.mu, 1, &err), RF_OK);
    fem_point_law law = fem_point_law_linear3d(&LAME);
    assert_int_equal(fem_kernel_points_hex(&kp, 0, NE, x, conn, &law, NULL, NULL, 0, &err), RF_OK);
    field_forces(&km, u, f1);
    field_forces(&kp, u, f2);
    double d[24 * NE];
    for (int i = 0; i < 24 * NE; i++)
        d[i] = f1[i] - f2[i];
    assert_true(max_abs(d, 24 * NE) < 1e-12 * max_abs(f1, 24 * NE));
    /* any split of the work units gives the same bits (NE = 13: the last block is padded) */
    double f3[24 * NE];
    assert_true(kp.units == 2);
    kp.ops->forces_field(&kp, 1, 2, u, f3);
    kp.ops->forces_field(&kp, 0, 1, u, f3);
    for (int i = 0; i < 24 * NE; i++)
        assert_true(f3[i] == f2[i]);
    fem_kernel_release(&km);
    fem_kernel_release(&kp);
}

/* u'f(v) = v'f(u) (B-bar keeps the operator symmetric), a constant strain
 * field gives the same forces with and without B-bar, and B-bar lowers the
 * energy of a bending mode (the volumetric locking it removes). */
static void test_bbar(void **state)
{
    (void)state;
    double x[24 * NE], u[24 * NE], v[24 * NE], fu[24 * NE], fv[24 * NE], fa[24 * NE], fb[24 * NE];
    int conn[8 * NE];
    unsigned long long s = 3;
    random_elements(NE, 5, x, conn);
    for (int i = 0; i < 24 * NE; i++)
        u[i] = 1e-4 * (urand(&s) - 0.5), v[i] = 1e-4 * (urand(&s) - 0.5);
    fem_kernel kb, kf;
    rf_error err;
    const fem_lame lame = {1e11, 1e9}; /* nearly incompressible: nu = 0.495 */
    fem_point_law law = fem_point_law_linear3d(&lame);
    assert_int_equal(fem_kernel_points_hex(&kb, 0, NE, x, conn, &law, NULL, NULL, 1, &err), RF_OK);
    assert_int_equal(fem_kernel_points_hex(&kf, 0, NE, x, conn, &law, NULL, NULL, 0, &err), RF_OK);
    field_forces(&kb, u, fu);
    field_forces(&kb, v, fv);
    double uv = 0, vu = 0, sc = 0;
    for (int i = 0; i < 24 * NE; i++)
        uv += u[i] * fv[i], vu += v[i] * fu[i], sc += fabs(u[i] * fv[i]);
    assert_true(fabs(uv - vu) < 1e-12 * sc);
    /* affine field u = A x: constant strain */
    const double A[9] = {1e-4, 2e-5, -3e-5, 4e-5, -2e-4, 1e-5, 0, 3e-5, 5e-5};
    for (int n = 0; n < 8 * NE; n++)
        for (int c = 0; c < 3; c++)
            u[3 * n + c] = A[3 * c] * x[3 * n] + A[3 * c + 1] * x[3 * n + 1] + A[3 * c + 2] * x[3 * n + 2];
    field_forces(&kb, u, fa);
    field_forces(&kf, u, fb);
    double d[24 * NE];
    for (int i = 0; i < 24 * NE; i++)
        d[i] = fa[i] - fb[i];
    assert_true(max_abs(d, 24 * NE) < 1e-10 * max_abs(fb, 24 * NE));
    /* u_x = x (z - z_c), z_c the element's mean z: a field of the trilinear space whose dilatation
       z - z_c averages to 0 over the element; full integration locks on it, B-bar does not */
    for (int n = 0; n < 8 * NE; n++) {
        double zc = 0;
        for (int a = 0; a < 8; a++)
            zc += x[3 * (8 * (n / 8) + a) + 2] / 8;
        u[3 * n] = 1e-4 * x[3 * n] * (x[3 * n + 2] - zc), u[3 * n + 1] = u[3 * n + 2] = 0;
    }
    field_forces(&kb, u, fa);
    field_forces(&kf, u, fb);
    double eb = 0, ef = 0;
    for (int i = 0; i < 24 * NE; i++)
        eb += u[i] * fa[i], ef += u[i] * fb[i];
    assert_true(eb > 0 && eb < 0.5 * ef);
    fem_kernel_release(&kb);
    fem_kernel_release(&kf);
}

/* The material law with a yield stress far above any stress = the linear law; a J2 law in flow
   dissipates the work less the stored energy. */
static void test_material_law(void **state)
{
    (void)state;
    double x[24 * NE], u[24 * NE], f1[24 * NE], f2[24 * NE];
    int conn[8 * NE];
    random_elements(NE, 17, x, conn);
    unsigned long long s = 9;
    for (int i = 0; i < 24 * NE; i++)
        u[i] = 1e-4 * (urand(&s) - 0.5);
    rf_material_params p;
    rf_material_params_default(&p);
    p.model = RF_MATERIAL_VON_MISES, p.yield = 1e15, p.hardening = 0;
    rf_material m;
    rf_error err;
    assert_int_equal(rf_material_init(&m, &p, &err), RF_OK);
    const fem_lame lame = {p.E * p.poisson / ((1 + p.poisson) * (1 - 2 * p.poisson)), p.E / (2 * (1 + p.poisson))};
    fem_point_law ll = fem_point_law_linear3d(&lame), lm = fem_point_law_material3d(&m);
    fem_kernel kl, km;
    assert_int_equal(fem_kernel_points_hex(&kl, 0, NE, x, conn, &ll, NULL, NULL, 1, &err), RF_OK);
    assert_int_equal(fem_kernel_points_hex(&km, 0, NE, x, conn, &lm, NULL, NULL, 1, &err), RF_OK);
    field_forces(&kl, u, f1);
    field_forces(&km, u, f2);
    double d[24 * NE];
    for (int i = 0; i < 24 * NE; i++)
        d[i] = f1[i] - f2[i];
    assert_true(max_abs(d, 24 * NE) < 1e-12 * max_abs(f1, 24 * NE));
    fem_kernel_release(&kl);
    fem_kernel_release(&km);

    /* J2, Y = 50 MPa, H = 1 GPa: 40 increments of the random field (strains ~1e-4 x 40 >> Y/E),
       work by the trapezoidal rule of the linear-in-u path = elastic energy + dissipation */
    p.yield = 50e6, p.hardening = 1e9;
    assert_int_equal(rf_material_init(&m, &p, &err), RF_OK);
    lm = fem_point_law_material3d(&m);
    assert_int_equal(fem_kernel_points_hex(&km, 0, NE, x, conn, &lm, NULL, NULL, 1, &err), RF_OK);
    double W = 0, fold[24 * NE] = {0}, uk[24 * NE];
    for (int step = 1; step <= 200; step++) {
        for (int i = 0; i < 24 * NE; i++)
            uk[i] = u[i] * step / 2.0;
        field_forces(&km, uk, f2);
        km.ops->commit(&km);
        for (int i = 0; i < 24 * NE; i++)
            W += 0.5 * (f2[i] + fold[i]) * u[i] / 2.0;
        memcpy(fold, f2, sizeof fold);
    }
    fem_kernel_report r;
    fem_kernel_report_get(&km, &r);
    const double Ee = fem_kernel_points_hex_energy(&km);
    /* J2 leaves the pressure elastic: about 1/3 of the work is dissipated here */
    assert_true(r.plastic_work > 0.2 * W && r.plastic_strain_max > 0.01 && r.element_max >= 0);
    /* radial return with linear hardening along a straight strain path: the trapezoidal work
       error is second order in the increment */
    assert_true(fabs(W - Ee - r.plastic_work) < 2e-3 * W);
    double sig[6], ep;
    assert_int_equal(fem_kernel_points_hex_cell(&km, r.element_max, sig, &ep), 1);
    assert_true(ep <= r.plastic_strain_max && ep > 0);
    assert_int_equal(fem_kernel_points_hex_cell(&km, NE, sig, &ep), 0);
    fem_kernel_release(&km);
}

/* The S5 colluvium (examples/s5_v10.yaml): Drucker-Prager with a cap. */
static void colluvium(rf_material *m)
{
    rf_material_params p;
    rf_material_params_default(&p);
    p.model = RF_MATERIAL_DRUCKER_PRAGER, p.E = 100e6, p.poisson = 0.3, p.cohesion = 10e3;
    p.friction_angle = 40 * acos(-1.0) / 180, p.dilatancy_angle = 5 * acos(-1.0) / 180;
    p.cap_pressure = 200e3, p.cap_hardening = 40e6;
    rf_error err;
    assert_int_equal(rf_material_init(m, &p, &err), RF_OK);
}

/* At the strains under a boulder sunk into soil (0.6-0.8, docs/validation-plastic.md 9d) the
   small-strain kernel is the material point: an affine field u = t A x (uniform displacement
   gradient, t = 0..1 in equal steps, B-bar on) gives every Gauss point of every distorted
   element the stress of one point driven by rf_material_update along eps = t sym(A); the nodal
   forces do the virtual work V sigma : B of any affine field u = B x; the dissipation is the
   point's times the volume.  Compression 0.7 through the cap with a shear 0.5. */
static void test_homogeneous_large_strain(void **state)
{
    (void)state;
    double x[24 * NE], u[24 * NE], fe[24 * NE];
    int conn[8 * NE];
    random_elements(NE, 29, x, conn);
    rf_material m;
    colluvium(&m);
    const fem_point_law law = fem_point_law_material3d(&m);
    fem_kernel k;
    rf_error err;
    assert_int_equal(fem_kernel_points_hex(&k, 0, NE, x, conn, &law, NULL, NULL, 1, &err), RF_OK);
    const double A[9] = {0, 0, 0.5, 0, 0, 0, 0, 0, -0.7}; /* d u_c / d x_j at 3c + j */
    const double de[6] = {A[0], A[4], A[8], A[1] + A[3], A[5] + A[7], A[2] + A[6]};
    const int nstep = 140;
    double sig[6] = {0}, D = 0, Dsum = 0, V = 0;
    rf_material_state st = {0};
    for (int n = 1; n <= nstep; n++) {
        for (int a = 0; a < 8 * NE; a++)
            for (int c = 0; c < 3; c++)
                u[3 * a + c] = (double)n / nstep * (A[3 * c] * x[3 * a] + A[3 * c + 1] * x[3 * a + 1] +
                                                    A[3 * c + 2] * x[3 * a + 2]);
        field_forces(&k, u, fe);
        k.ops->commit(&k);
        double d[6];
        for (int i = 0; i < 6; i++)
            d[i] = de[i] / nstep;
        rf_material_update(&m, d, sig, &st, &D);
        Dsum += D;
    }
    assert_true(sig[2] < -1e6 && st.compaction > 0.1); /* through the cap, far beyond X0 = 0.2 MPa */
    const double smax = max_abs(sig, 6);
    for (long e = 0; e < NE; e++) {
        double se[6], ep;
        assert_int_equal(fem_kernel_points_hex_cell(&k, e, se, &ep), 1);
        for (int i = 0; i < 6; i++)
            assert_true(fabs(se[i] - sig[i]) < 1e-9 * smax);
        assert_true(fabs(ep - st.plastic_strain_eq) < 1e-9 * st.plastic_strain_eq);
    }
    /* virtual work of u = B x (B[3c + j] = delta_c0 delta_j2 + delta_c1 delta_j1: a shear and a
       stretch): sum F . u = V (sig_xz + sig_yy) per element */
    for (long e = 0; e < NE; e++) {
        double W = 0, Ve = 0;
        for (int a = 0; a < 8; a++)
            W += fe[24 * e + 3 * a] * x[24 * e + 3 * a + 2] + fe[24 * e + 3 * a + 1] * x[24 * e + 3 * a + 1];
        for (int q = 0; q < 8; q++)
            Ve += ((p3_data *)k.data)->w[8 * e + q];
        V += Ve;
        assert_true(fabs(W - Ve * (sig[5] + sig[1])) < 1e-9 * Ve * smax);
    }
    fem_kernel_report r;
    fem_kernel_report_get(&k, &r);
    assert_true(fabs(r.plastic_work - Dsum * V) < 1e-9 * Dsum * V);
    fem_kernel_release(&k);
}

/* Two laws in one block: each element's forces are those of a block with its own law alone. */
static void test_two_laws(void **state)
{
    (void)state;
    double x[24 * NE], u[24 * NE], fa[24 * NE], fb[24 * NE], f2[24 * NE];
    int conn[8 * NE];
    unsigned char use2[NE];
    random_elements(NE, 23, x, conn);
    unsigned long long s = 5;
    for (int i = 0; i < 24 * NE; i++)
        u[i] = 1e-4 * (urand(&s) - 0.5);
    for (int e = 0; e < NE; e++)
        use2[e] = (unsigned char)(e % 3 == 1);
    const fem_lame lb = {1e9, 2e9};
    const fem_point_law la = fem_point_law_linear3d(&LAME), l2 = fem_point_law_linear3d(&lb);
    fem_kernel ka, kb, k2;
    rf_error err;
    assert_int_equal(fem_kernel_points_hex(&ka, 0, NE, x, conn, &la, NULL, NULL, 1, &err), RF_OK);
    assert_int_equal(fem_kernel_points_hex(&kb, 0, NE, x, conn, &l2, NULL, NULL, 1, &err), RF_OK);
    assert_int_equal(fem_kernel_points_hex(&k2, 0, NE, x, conn, &la, &l2, use2, 1, &err), RF_OK);
    field_forces(&ka, u, fa);
    field_forces(&kb, u, fb);
    field_forces(&k2, u, f2);
    for (int e = 0; e < NE; e++)
        for (int r = 0; r < 24; r++)
            assert_true(f2[24 * e + r] == (use2[e] ? fb : fa)[24 * e + r]);
    fem_kernel_release(&ka);
    fem_kernel_release(&kb);
    fem_kernel_release(&k2);
    rf_material_params p;
    rf_material_params_default(&p);
    rf_material m;
    assert_int_equal(rf_material_init(&m, &p, &err), RF_OK);
    const fem_point_law lm = fem_point_law_material3d(&m); /* 4 state variables: not the linear law's shape */
    assert_int_equal(fem_kernel_points_hex(&k2, 0, NE, x, conn, &la, &lm, use2, 1, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "same shape"));
    fem_kernel_release(&k2);
}

static void test_bad_law(void **state)
{
    (void)state;
    double x[24];
    int conn[8];
    random_elements(1, 1, x, conn);
    fem_lame lame = {1, 1};
    fem_point_law law = fem_point_law_linear(&lame); /* 4 components: the quad's */
    fem_kernel k;
    rf_error err;
    assert_int_equal(fem_kernel_points_hex(&k, 0, 1, x, conn, &law, NULL, NULL, 0, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "6"));
    fem_kernel_release(&k);
    for (int a = 0; a < 4; a++) { /* inverted element */
        double t = x[3 * a + 2];
        x[3 * a + 2] = x[3 * (a + 4) + 2], x[3 * (a + 4) + 2] = t;
    }
    law = fem_point_law_linear3d(&lame);
    assert_int_equal(fem_kernel_points_hex(&k, 0, 1, x, conn, &law, NULL, NULL, 0, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "det J"));
    fem_kernel_release(&k);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_equals_matfree),
        cmocka_unit_test(test_bbar),
        cmocka_unit_test(test_material_law),
        cmocka_unit_test(test_homogeneous_large_strain),
        cmocka_unit_test(test_two_laws),
        cmocka_unit_test(test_bad_law),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
