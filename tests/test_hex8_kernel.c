/* test_hex8_kernel.c - the hexahedron force kernels (src/fem/hex8_kernel.c)
 * against the stored-stiffness product K_e u_e of f3_hex_matrices, in double:
 * on random distorted elements and on the real 3D impact mesh built through
 * f3_mesh_build; the same bits for any split of the elements over threads;
 * a caller's point-wise stress routine plugs in; bad elements are refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"
#include "fem/fem3d_internal.h"
#include "fem/fem3d_spec.h"
#include "fem/hex8_kernel.h"
#include "fem/hex8_step.h"
#include "rockfuzz/fem3d.h"

static const f3_material GRANITE = {2600, 68.2e9, 0.25};

static double lame_lambda(const f3_material *m) { return m->E * m->nu / ((1 + m->nu) * (1 - 2 * m->nu)); }
static double lame_mu(const f3_material *m) { return m->E / (2 * (1 + m->nu)); }

static double urand(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* max |fe - K_e u_e| / max |K_e u_e| over the listed elements. */
static double rel_error_vs_stored(const double *x, const int *conn, const int *elem, long n, const double *u,
                                  const double *fe)
{
    double dmax = 0, fmax_ = 0;
    for (long k = 0; k < n; k++) {
        const int *cn = conn + 8 * (long)elem[k];
        double xe[24], ue[24], K[576], m[8], vol;
        for (int a = 0; a < 8; a++)
            for (int d = 0; d < 3; d++)
                xe[3 * a + d] = x[3 * (long)cn[a] + d], ue[3 * a + d] = u[3 * (long)cn[a] + d];
        f3_hex_matrices(xe, &GRANITE, K, m, &vol);
        for (int i = 0; i < 24; i++) {
            double f = 0;
            for (int j = 0; j < 24; j++)
                f += K[24 * i + j] * ue[j];
            dmax = fmax(dmax, fabs(fe[24 * (long)elem[k] + i] - f));
            fmax_ = fmax(fmax_, fabs(f));
        }
    }
    return dmax / fmax_;
}

/* ne independent elements: unit-cube corners moved by up to 0.25, stretched and sheared. */
static void random_elements(long ne, unsigned long long seed, double *x, int *conn, int *elem)
{
    static const double XI[8] = {0, 1, 1, 0, 0, 1, 1, 0}, ETA[8] = {0, 0, 1, 1, 0, 0, 1, 1},
                        ZETA[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (long e = 0; e < ne; e++) {
        const double sx = 0.5 + urand(&seed), sy = 0.5 + urand(&seed), sz = 0.5 + urand(&seed);
        const double shear = 0.4 * (urand(&seed) - 0.5), off = 100 * urand(&seed);
        for (int a = 0; a < 8; a++) {
            double *p = x + 24 * e + 3 * a;
            p[0] = off + sx * XI[a] + shear * ZETA[a] + 0.25 * (urand(&seed) - 0.5);
            p[1] = -off + sy * ETA[a] + 0.25 * (urand(&seed) - 0.5);
            p[2] = sz * ZETA[a] + 0.25 * (urand(&seed) - 0.5);
            conn[8 * e + a] = (int)(8 * e + a);
        }
        elem[e] = (int)e;
    }
}

static void test_bmat_random_elements(void **state)
{
    (void)state;
    enum { NE = 37 }; /* not a multiple of HEX8_W: the padded lanes are exercised */
    double *x = malloc(24 * NE * sizeof *x), *u = malloc(24 * NE * sizeof *u), *fe = calloc(24 * NE, sizeof *fe);
    int conn[8 * NE], elem[NE];
    double lam[NE], mu[NE];
    random_elements(NE, 7, x, conn, elem);
    unsigned long long s = 11;
    for (int i = 0; i < 24 * NE; i++)
        u[i] = 1e-3 * (urand(&s) - 0.5);
    for (int k = 0; k < NE; k++)
        lam[k] = lame_lambda(&GRANITE), mu[k] = lame_mu(&GRANITE);
    for (int store = 0; store < 2; store++) {
        hex8_bmat B;
        rf_error err = {0};
        assert_int_equal(hex8_bmat_init(&B, x, conn, elem, NE, lam, mu, store, &err), RF_OK);
        assert_int_equal(B.nblk, (NE + HEX8_W - 1) / HEX8_W);
        hex8_bmat_force(&B, 0, B.nblk, u, NULL, fe);
        double e = rel_error_vs_stored(x, conn, elem, NE, u, fe);
        printf("matrix-free (J %s) vs K_e u_e, random elements: %.2e\n", store ? "stored" : "recomputed", e);
        assert_true(e < 1e-12);
        hex8_bmat_free(&B);
    }
    free(x), free(u), free(fe);
}

static void test_shared_random_translations(void **state)
{
    (void)state;
    enum { NE = 20 };
    double xref[24], *x = malloc(24 * NE * sizeof *x), *u = malloc(24 * NE * sizeof *u);
    double *fe = calloc(24 * NE, sizeof *fe);
    int conn[8 * NE], elem[NE], one = 0, found[NE];
    random_elements(1, 3, xref, conn, &one);
    unsigned long long s = 5;
    for (int e = 0; e < NE; e++) {
        double t[3] = {10 * urand(&s), 10 * urand(&s), -10 * urand(&s)};
        for (int a = 0; a < 8; a++)
            for (int d = 0; d < 3; d++)
                x[24 * e + 3 * a + d] = xref[3 * a + d] + t[d];
        for (int a = 0; a < 8; a++)
            conn[8 * e + a] = 8 * e + a;
        elem[e] = e;
    }
    x[24 * 5 + 3 * 6] += 1e-3; /* element 5 is no longer congruent */
    for (int i = 0; i < 24 * NE; i++)
        u[i] = 1e-3 * (urand(&s) - 0.5);
    long m = hex8_find_congruent(x, conn, elem, NE, xref, 1e-9, found);
    assert_int_equal(m, NE - 1);
    for (long k = 0; k < m; k++)
        assert_int_not_equal(found[k], 5);
    double K[576], mass[8], vol;
    f3_hex_matrices(xref, &GRANITE, K, mass, &vol);
    hex8_shared_force(K, conn, found, m, u, fe);
    double e = rel_error_vs_stored(x, conn, found, m, u, fe);
    printf("shared K vs K_e u_e, translated elements: %.2e\n", e);
    assert_true(e < 1e-12);
    free(x), free(u), free(fe);
}

/* The default 45 degree, 10 m/s impact at a coarse a/h. */
static void real_mesh(double refinement, f3_mesh *mesh, f3_mesh_spec *ms)
{
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10,
                          .slope_angle = 45 * RF_PI / 180, .friction = 0.6};
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = refinement;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    double h, a;
    f3_impact_mesh_spec(&in, &o, &o3, ms, &h, &a);
    rf_error err = {0};
    assert_int_equal(f3_mesh_build(ms, mesh, 10000000, &err), RF_OK);
    /* the spec is the solver's: the same element count as a (very short) solver run */
    o.end_time = 1e-7;
    rf_impact_output out;
    assert_int_equal(rf_fem3d_impact_ex(&in, &o, &o3, &out, NULL, NULL, &err), RF_OK);
    assert_int_equal((long)out.elements, mesh->n_elems);
}

static void test_real_mesh(void **state)
{
    (void)state;
    f3_mesh mesh;
    f3_mesh_spec ms;
    real_mesh(2.5, &mesh, &ms);
    const long ne = mesh.n_elems;
    int *all = malloc((size_t)ne * sizeof *all), *cube = malloc((size_t)ne * sizeof *cube);
    double *lam = malloc((size_t)ne * sizeof *lam), *mu = malloc((size_t)ne * sizeof *mu);
    double *u = malloc((size_t)mesh.n_nodes * 3 * sizeof *u), *fe = calloc((size_t)ne * 24, sizeof *fe);
    unsigned long long s = 99;
    for (long i = 0; i < 3 * mesh.n_nodes; i++)
        u[i] = 1e-4 * (urand(&s) - 0.5);
    for (long e = 0; e < ne; e++)
        all[e] = (int)e, lam[e] = lame_lambda(&GRANITE), mu[e] = lame_mu(&GRANITE);
    rf_error err = {0};
    for (int store = 0; store < 2; store++) {
        hex8_bmat B;
        assert_int_equal(hex8_bmat_init(&B, mesh.x, mesh.conn, all, ne, lam, mu, store, &err), RF_OK);
        hex8_bmat_force(&B, 0, B.nblk, u, NULL, fe);
        double e1 = rel_error_vs_stored(mesh.x, mesh.conn, all, ne, u, fe);
        printf("matrix-free (J %s) vs K_e u_e, real mesh (%ld elements): %.2e\n", store ? "stored" : "recomputed",
               ne, e1);
        assert_true(e1 < 1e-12);
        hex8_bmat_free(&B);
    }
    /* the slope's fine box: its first element is a cube of size h; all its cubes share K_e */
    const long first = mesh.boulder_elems, nslope = ne - first;
    const long nbox = (long)(ms.slope.nxm + ms.slope.nxp) * ms.slope.ny * ms.slope.nz;
    double xref[24], K[576], mass[8], vol;
    for (int a = 0; a < 8; a++)
        for (int d = 0; d < 3; d++)
            xref[3 * a + d] = mesh.x[3 * (long)mesh.conn[8 * first + a] + d];
    long m = hex8_find_congruent(mesh.x, mesh.conn, all + first, nslope, xref, 1e-9 * ms.slope.h, cube);
    printf("slope elements congruent to the fine-box cube: %ld of %ld (box %ld)\n", m, nslope, nbox);
    assert_int_equal(m, nbox);
    f3_hex_matrices(xref, &GRANITE, K, mass, &vol);
    memset(fe, 0, (size_t)ne * 24 * sizeof *fe);
    hex8_shared_force(K, mesh.conn, cube, m, u, fe);
    double e2 = rel_error_vs_stored(mesh.x, mesh.conn, cube, m, u, fe);
    printf("shared K vs K_e u_e, slope fine box: %.2e\n", e2);
    assert_true(e2 < 1e-12);
    f3_mesh_free(&mesh);
    free(all), free(cube), free(lam), free(mu), free(u), free(fe);
}

/* Blocks split over 1 or 2 threads, or in uneven chunks: the same bits. */
static void test_thread_invariance(void **state)
{
    (void)state;
    enum { NE = 203 };
    double *x = malloc(24 * NE * sizeof *x), *u = malloc(24 * NE * sizeof *u);
    double *f1 = calloc(24 * NE, sizeof *f1), *f2 = calloc(24 * NE, sizeof *f2), *f3 = calloc(24 * NE, sizeof *f3);
    int conn[8 * NE], elem[NE];
    double lam[NE], mu[NE];
    random_elements(NE, 21, x, conn, elem);
    unsigned long long s = 1;
    for (int i = 0; i < 24 * NE; i++)
        u[i] = urand(&s) - 0.5;
    for (int k = 0; k < NE; k++)
        lam[k] = lame_lambda(&GRANITE) * (1 + k % 3), mu[k] = lame_mu(&GRANITE);
    for (int store = 0; store < 2; store++) {
        hex8_bmat B;
        rf_error err = {0};
        assert_int_equal(hex8_bmat_init(&B, x, conn, elem, NE, lam, mu, store, &err), RF_OK);
        hex8_bmat_force(&B, 0, B.nblk, u, NULL, f1);
        hex8_bmat_force(&B, 0, 5, u, NULL, f2);
        hex8_bmat_force(&B, 5, B.nblk, u, NULL, f2);
#ifdef _OPENMP
#pragma omp parallel for schedule(static, 3) num_threads(2)
#endif
        for (long b = 0; b < B.nblk; b++)
            hex8_bmat_force(&B, b, b + 1, u, NULL, f3);
        assert_memory_equal(f1, f2, 24 * NE * sizeof *f1);
        assert_memory_equal(f1, f3, 24 * NE * sizeof *f1);
        hex8_bmat_free(&B);
    }
    double K[576], mass[8], vol;
    f3_hex_matrices(x, &GRANITE, K, mass, &vol);
    memset(f2, 0, 24 * NE * sizeof *f2), memset(f3, 0, 24 * NE * sizeof *f3);
    hex8_shared_force(K, conn, elem, NE, u, f2);
#ifdef _OPENMP
#pragma omp parallel for schedule(static, 7) num_threads(2)
#endif
    for (long k = 0; k < NE; k++)
        hex8_shared_force(K, conn, elem + k, 1, u, f3);
    assert_memory_equal(f2, f3, 24 * NE * sizeof *f2);
    free(x), free(u), free(f1), free(f2), free(f3);
}

/* A caller's point-wise routine: elasticity with its own constants; counts the points it sees. */
typedef struct {
    double lam, mu;
    long calls, npoints;
    int bad_index;
} elastic_ctx;

static void elastic_point(void *ctx, long point, const double eps[6], double sig[6])
{
    elastic_ctx *c = ctx;
    c->calls++;
    if (point < 0 || point >= c->npoints)
        c->bad_index = 1;
    const double tr = c->lam * (eps[0] + eps[1] + eps[2]);
    for (int i = 0; i < 3; i++)
        sig[i] = tr + 2 * c->mu * eps[i], sig[3 + i] = 2 * c->mu * eps[3 + i];
}

static void test_stress_callback(void **state)
{
    (void)state;
    enum { NE = 13 };
    double x[24 * NE], u[24 * NE], f1[24 * NE], f2[24 * NE];
    int conn[8 * NE], elem[NE];
    double lam[NE], mu[NE];
    random_elements(NE, 4, x, conn, elem);
    unsigned long long s = 8;
    for (int i = 0; i < 24 * NE; i++)
        u[i] = urand(&s) - 0.5;
    for (int k = 0; k < NE; k++)
        lam[k] = lame_lambda(&GRANITE), mu[k] = lame_mu(&GRANITE);
    hex8_bmat B;
    rf_error err = {0};
    assert_int_equal(hex8_bmat_init(&B, x, conn, elem, NE, lam, mu, 1, &err), RF_OK);
    hex8_bmat_force(&B, 0, B.nblk, u, NULL, f1);
    elastic_ctx c = {lame_lambda(&GRANITE), lame_mu(&GRANITE), 0, 8 * NE, 0};
    hex8_stress st = {elastic_point, &c};
    hex8_bmat_force(&B, 0, B.nblk, u, &st, f2);
    assert_int_equal(c.calls, 8 * NE);
    assert_int_equal(c.bad_index, 0);
    double d = 0, m = 0;
    for (int i = 0; i < 24 * NE; i++)
        d = fmax(d, fabs(f1[i] - f2[i])), m = fmax(m, fabs(f1[i]));
    printf("point-wise elastic routine vs the built-in: %.2e\n", d / m);
    assert_true(d <= 1e-13 * m);
    hex8_bmat_free(&B);
}

static void test_bad_element(void **state)
{
    (void)state;
    double x[24];
    int conn[8], elem = 0;
    random_elements(1, 2, x, conn, &elem);
    for (int a = 0; a < 4; a++) { /* swap top and bottom: negative Jacobian */
        int t = conn[a];
        conn[a] = conn[a + 4], conn[a + 4] = t;
    }
    double lam = 1, mu = 1;
    hex8_bmat B;
    rf_error err = {0};
    assert_int_equal(hex8_bmat_init(&B, x, conn, &elem, 1, &lam, &mu, 0, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "det J"));
}

/* Element data for the step: K, lumped masses, free dofs (u_y fixed on the symmetry plane, all
   fixed on the slope's outer surface), as the solver forms them (without its boulder mass scale). */
typedef struct {
    const f3_mesh *mesh;
} step_ctx;

static void step_element(void *ctx, long e, double K[576], double m[8], unsigned char fr[24])
{
    const f3_mesh *mesh = ((step_ctx *)ctx)->mesh;
    const int *cn = mesh->conn + 8 * e;
    double xe[24], vol;
    for (int a = 0; a < 8; a++) {
        for (int d = 0; d < 3; d++)
            xe[3 * a + d] = mesh->x[3 * (long)cn[a] + d];
        const unsigned char fl = mesh->flags[cn[a]];
        const int outer = cn[a] >= mesh->boulder_nodes && (fl & F3_OUTER);
        fr[3 * a] = fr[3 * a + 2] = !outer;
        fr[3 * a + 1] = !outer && !(fl & F3_SYM);
    }
    f3_hex_matrices(xe, &GRANITE, K, m, &vol);
}

/* The pruned minimum equals the brute-force one bit for bit, with far fewer eigen-solves, and
   the Gershgorin steps are lower bounds of every element's exact step. */
static void test_min_stable_step(void **state)
{
    (void)state;
    f3_mesh mesh;
    f3_mesh_spec ms;
    real_mesh(2.5, &mesh, &ms);
    step_ctx c = {&mesh};
    const long ne = mesh.n_elems;
    double *lower = malloc((size_t)ne * sizeof *lower), brute = 1e300;
    int below = 0;
    for (long e = 0; e < ne; e++) {
        double K[576], m[8];
        unsigned char fr[24];
        step_element(&c, e, K, m, fr);
        const double lam = f3_hex_lambda_max(K, m, fr);
        if (lam > 0)
            brute = fmin(brute, 2 / sqrt(lam));
    }
    long n_exact = 0;
    const double dt = hex8_min_stable_step(ne, step_element, &c, lower, &n_exact);
    for (long e = 0; e < ne; e++) {
        double K[576], m[8];
        unsigned char fr[24];
        step_element(&c, e, K, m, fr);
        const double lam = f3_hex_lambda_max(K, m, fr);
        if (lam > 0 && lower[e] > 2 / sqrt(lam))
            below = 1;
    }
    printf("smallest stable step %.6g s: %ld eigen-solves instead of %ld\n", dt, n_exact, ne);
    assert_true(dt == brute);
    assert_true(n_exact > 0 && n_exact < ne / 10);
    assert_int_equal(below, 0);
    free(lower);
    f3_mesh_free(&mesh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bmat_random_elements), cmocka_unit_test(test_shared_random_translations),
        cmocka_unit_test(test_real_mesh),            cmocka_unit_test(test_thread_invariance),
        cmocka_unit_test(test_stress_callback),      cmocka_unit_test(test_bad_element),
        cmocka_unit_test(test_min_stable_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
