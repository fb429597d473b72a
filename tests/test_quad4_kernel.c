/* test_quad4_kernel.c - the axisymmetric quad force kernel
 * (src/fem/quad4_kernel.c) against the stored-stiffness product that
 * fem_solver.c computes today: on random symmetric matrices, and on the real
 * 10 m/s impact mesh (built through fem_mesh_build from fem_impact_mesh_spec)
 * where elements of one shape share K_e; and the packed table (36 entries
 * per element, 8 elements per vector) against the per-element one, byte for
 * byte. */
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
#include "fem/fem_internal.h"
#include "fem/fem_spec.h"
#include "fem/quad4_kernel.h"
#include "rockfuzz/fem.h"

static double urand(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* Today's loop (fem_solver.c force_kernel): f += K_e u_e, row by row. */
static void reference_force(const double *K, const int *conn, long ne, const double *u, double *f)
{
    for (long e = 0; e < ne; e++) {
        const int *c = conn + 4 * e;
        double ue[8];
        for (int a = 0; a < 4; a++)
            ue[2 * a] = u[2 * c[a]], ue[2 * a + 1] = u[2 * c[a] + 1];
        for (int i = 0; i < 8; i++) {
            double s = 0;
            for (int j = 0; j < 8; j++)
                s += K[64 * e + 8 * i + j] * ue[j];
            f[2 * c[i / 2] + i % 2] += s;
        }
    }
}

static double rel_diff(const double *a, const double *b, long n)
{
    double d = 0, m = 0;
    for (long i = 0; i < n; i++)
        d = fmax(d, fabs(a[i] - b[i])), m = fmax(m, fabs(b[i]));
    return d / m;
}

static void test_random_matrices(void **state)
{
    (void)state;
    enum { NE = 57, NN = 40 };
    double *K = malloc(64 * NE * sizeof *K), u[2 * NN], f[2 * NN] = {0}, g[2 * NN] = {0};
    int conn[4 * NE];
    unsigned long long s = 3;
    for (long e = 0; e < NE; e++) {
        for (int i = 0; i < 8; i++)
            for (int j = 0; j <= i; j++)
                K[64 * e + 8 * i + j] = K[64 * e + 8 * j + i] = urand(&s) - 0.5;
        for (int a = 0; a < 4; a++)
            conn[4 * e + a] = (int)(urand(&s) * NN);
    }
    for (int i = 0; i < 2 * NN; i++)
        u[i] = urand(&s) - 0.5;
    reference_force(K, conn, NE, u, f);
    quad4_force(K, NULL, conn, 0, 20, u, g); /* in two calls, as two threads' ranges would be */
    quad4_force(K, NULL, conn, 20, NE, u, g);
    double d = rel_diff(g, f, 2 * NN);
    printf("quad4_force vs row-by-row product, random K: %.2e\n", d);
    assert_true(d < 1e-14);
    free(K);
}

/* The default axisymmetric impact (10 m/s, a/h = 10). */
static void real_mesh(fem_mesh *mesh, fem_material *mat)
{
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10};
    rf_fem_options o;
    rf_fem_options_default(&o);
    fem_body_spec bs, ss;
    rf_error err = {0};
    assert_int_equal(fem_impact_mesh_spec(&in, &o, &bs, &ss, &err), RF_OK);
    assert_int_equal(fem_mesh_build(&bs, &ss, mesh, TUNE(o).max_elements, &err), RF_OK);
    o.end_time = 1e-7; /* the spec is the solver's: the same element count */
    rf_impact_output out;
    assert_int_equal(rf_fem_impact(&in, &o, &out, NULL, &err), RF_OK);
    assert_int_equal((long)out.elements, mesh->n_elems);
    *mat = (fem_material){2600, 68.2e9, 0.25};
}

static void test_real_mesh_shared(void **state)
{
    (void)state;
    fem_mesh mesh;
    fem_material mat;
    real_mesh(&mesh, &mat);
    const long ne = mesh.n_elems, nn = mesh.n_nodes;
    double *K = malloc((size_t)ne * 64 * sizeof *K), *u = malloc((size_t)nn * 2 * sizeof *u);
    double *f = calloc((size_t)nn * 2, sizeof *f), *g = calloc((size_t)nn * 2, sizeof *g);
    int *kidx = malloc((size_t)ne * sizeof *kidx), *rep = malloc((size_t)ne * sizeof *rep);
    for (long e = 0; e < ne; e++) {
        double r[4], z[4], m[4], mass, area;
        for (int a = 0; a < 4; a++)
            r[a] = mesh.r[mesh.conn[4 * e + a]], z[a] = mesh.z[mesh.conn[4 * e + a]];
        fem_element_matrices(r, z, &mat, K + 64 * e, m, &mass, &area);
    }
    long ng = quad4_group_by_shape(mesh.r, mesh.z, mesh.conn, ne, 1e-12, kidx, rep);
    printf("axisymmetric mesh: %ld elements, %ld distinct shapes\n", ne, ng);
    assert_true(ng > 0 && ng < ne);
    double *Kg = malloc((size_t)ng * 64 * sizeof *Kg), dK = 0, Km = 0;
    for (long g2 = 0; g2 < ng; g2++)
        memcpy(Kg + 64 * g2, K + 64 * (long)rep[g2], 64 * sizeof *Kg);
    for (long e = 0; e < ne; e++) /* every member's own K equals its group's */
        for (int i = 0; i < 64; i++)
            dK = fmax(dK, fabs(K[64 * e + i] - Kg[64 * (long)kidx[e] + i])), Km = fmax(Km, fabs(K[64 * e + i]));
    printf("max |K_e - K_group| / max |K|: %.2e\n", dK / Km);
    assert_true(dK <= 1e-12 * Km);
    unsigned long long s = 17;
    for (long i = 0; i < 2 * nn; i++)
        u[i] = 1e-4 * (urand(&s) - 0.5);
    reference_force(K, mesh.conn, ne, u, f);
    quad4_force(Kg, kidx, mesh.conn, 0, ne, u, g);
    double d = rel_diff(g, f, 2 * nn);
    printf("shared-K force vs per-element product, real mesh: %.2e\n", d);
    assert_true(d < 1e-12);
    free(K), free(u), free(f), free(g), free(kidx), free(rep), free(Kg);
    fem_mesh_free(&mesh);
}

/* The packed table (36 entries per element, 8 elements per vector) gives the same bits as the
 * per-element table, in one call and in ranges that start and end inside a group of 8 (the
 * threads' ranges), through the fused path and the element-vector path; an asymmetric K is
 * refused. */
static void test_packed_same_bits(void **state)
{
    (void)state;
    fem_mesh mesh;
    fem_material mat;
    real_mesh(&mesh, &mat);
    const long ne = mesh.n_elems, nn = mesh.n_nodes;
    double *K = malloc((size_t)ne * 64 * sizeof *K), *u = malloc((size_t)nn * 2 * sizeof *u);
    double *f = calloc((size_t)nn * 2, sizeof *f), *g = calloc((size_t)nn * 2, sizeof *g);
    double *pk = malloc((size_t)quad4_packed_size(ne) * sizeof *pk);
    double *ue = malloc((size_t)ne * 8 * sizeof *ue), *fa = malloc((size_t)ne * 8 * sizeof *fa);
    double *fb = malloc((size_t)ne * 8 * sizeof *fb);
    for (long e = 0; e < ne; e++) {
        double r[4], z[4], m[4], mass, area;
        for (int a = 0; a < 4; a++)
            r[a] = mesh.r[mesh.conn[4 * e + a]], z[a] = mesh.z[mesh.conn[4 * e + a]];
        fem_element_matrices(r, z, &mat, K + 64 * e, m, &mass, &area);
    }
    assert_true(quad4_packed_size(ne) == 288 * ((ne + 7) / 8));
    assert_int_equal(quad4_pack(K, ne, pk), 0);
    unsigned long long s = 29;
    for (long i = 0; i < 2 * nn; i++)
        u[i] = 1e-4 * (urand(&s) - 0.5);
    for (long i = 0; i < 8 * ne; i++)
        ue[i] = urand(&s) - 0.5;
    const long cut[] = {0, 3, 8, 13, 21, 1000, ne - 5, ne}; /* ranges inside and across groups */
    for (int c = 0; c + 1 < (int)(sizeof cut / sizeof *cut); c++) {
        quad4_force(K, NULL, mesh.conn, cut[c], cut[c + 1], u, f);
        quad4_force_packed(pk, mesh.conn, cut[c], cut[c + 1], u, g);
        quad4_force_elements(K, cut[c], cut[c + 1], ue + 8 * cut[c], fa + 8 * cut[c]);
        quad4_force_packed_elements(pk, cut[c], cut[c + 1], ue + 8 * cut[c], fb + 8 * cut[c]);
    }
    assert_memory_equal(f, g, (size_t)nn * 2 * sizeof *f);
    assert_memory_equal(fa, fb, (size_t)ne * 8 * sizeof *fa);
    double fmaxabs = 0;
    for (long i = 0; i < 2 * nn; i++)
        fmaxabs = fmax(fmaxabs, fabs(f[i]));
    assert_true(fmaxabs > 0); /* a real product, not zeros compared with zeros */
    K[64 * 5 + 8 * 1 + 6] = nextafter(K[64 * 5 + 8 * 1 + 6], 1e300);
    assert_int_equal(quad4_pack(K, ne, pk), -1);
    printf("packed K: %ld elements, same bits as the per-element table (fused and element paths)\n", ne);
    free(K), free(u), free(f), free(g), free(pk), free(ue), free(fa), free(fb);
    fem_mesh_free(&mesh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_matrices),
        cmocka_unit_test(test_real_mesh_shared),
        cmocka_unit_test(test_packed_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
