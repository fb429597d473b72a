/* test_fem_points_block.c - the axisymmetric integration-point kernel, which
 * runs in SIMD blocks of 8 elements (src/fem/fem_points_block.c), against a
 * plain scalar reference written here from the formulas (fem_element.c's B
 * and weights per element, the mean-dilatation B-bar, strain B u, the law,
 * sum_q w_q B_q^T sigma_q; in the updated Lagrangian form B of the mid-step
 * geometry for the increment, the Hughes-Winget rotation of the spin, B and
 * w of the current geometry for the force).  13 elements (not a multiple of
 * 8: a padded last block), a block that starts at element 2, and calls on
 * ranges that cut blocks (partial lanes); a von Mises law driven well past
 * yield, two steps.  The vector code does the scalar operations in the same
 * order, so the forces must agree to the last bit. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fem/fem_internal.h"
#include "fem/fem_kernel.h"
#include "rockfuzz/material.h"

enum { NI = 5, NJ = 3, NE = NI * NJ, FIRST = 2, COUNT = NE - FIRST, NN = (NI + 1) * (NJ + 1) };

typedef struct {
    double r[NN], z[NN];
    int conn[4 * NE];
    rf_material mat;
    fem_point_law law;
    /* the reference's committed state, per point of the block */
    double eps[4 * COUNT][4], sig[4 * COUNT][4], var[4 * COUNT][4], uc[COUNT][8];
} mesh;

static void mesh_init(mesh *m)
{
    for (int j = 0; j <= NJ; j++)
        for (int i = 0; i <= NI; i++) {
            const int n = j * (NI + 1) + i;
            m->r[n] = (i == 0 ? 0.05 : 0.05 + 0.2 * i + 0.03 * sin(1.7 * i + 2.3 * j));
            m->z[n] = 0.2 * j + 0.04 * cos(2.1 * i - 0.7 * j);
        }
    for (int j = 0; j < NJ; j++)
        for (int i = 0; i < NI; i++) {
            int *c = m->conn + 4 * (j * NI + i);
            c[0] = j * (NI + 1) + i, c[1] = c[0] + 1, c[2] = c[1] + NI + 1, c[3] = c[0] + NI + 1;
        }
    rf_material_params p;
    rf_material_params_default(&p);
    p.model = RF_MATERIAL_VON_MISES, p.yield = 100e6, p.hardening = 2e9; /* yield strain ~1.5e-3 */
    rf_error err = {0};
    assert_int_equal(rf_material_init(&m->mat, &p, &err), RF_OK);
    m->law = fem_point_law_material(&m->mat);
    memset(m->eps, 0, sizeof m->eps), memset(m->sig, 0, sizeof m->sig), memset(m->var, 0, sizeof m->var);
    memset(m->uc, 0, sizeof m->uc);
}

/* Element displacements of step s: a non-uniform stretch of ~1 % and, from step 2, a rotation of 0.05 rad
 * about the origin (r stays > 0; not rigid in axisymmetry: its hoop strain near the axis reaches 25 %, so the
 * return map works hard). */
static void displacements(const mesh *m, int s, double ue[COUNT][8])
{
    const double th = s > 1 ? 0.05 : 0, c = cos(th), sn = sin(th);
    for (int e = 0; e < COUNT; e++)
        for (int a = 0; a < 4; a++) {
            const int n = m->conn[4 * (FIRST + e) + a];
            const double r = m->r[n] * (1 + 0.01 * s * (1 + m->z[n]));
            const double z = m->z[n] * (1 - 0.008 * s) + 0.002 * s * m->r[n];
            ue[e][2 * a] = c * r - sn * z - m->r[n], ue[e][2 * a + 1] = sn * r + c * z - m->z[n];
        }
}

/* The scalar mean dilatation (the kernel's former code). */
static void mean_dilatation(double B[4][32], const double w[4])
{
    double bbar[8] = {0}, W = 0;
    for (int q = 0; q < 4; q++) {
        W += w[q];
        for (int j = 0; j < 8; j++)
            bbar[j] += w[q] * (B[q][j] + B[q][8 + j] + B[q][16 + j]);
    }
    for (int q = 0; q < 4; q++)
        for (int j = 0; j < 8; j++) {
            const double c = (bbar[j] / W - (B[q][j] + B[q][8 + j] + B[q][16 + j])) / 3;
            B[q][j] += c, B[q][8 + j] += c, B[q][16 + j] += c;
        }
}

static void element_geometry(const mesh *m, int e, const double *u, double f, int bbar, double B[4][32], double w[4])
{
    double r[4], z[4];
    for (int a = 0; a < 4; a++) {
        const int n = m->conn[4 * (FIRST + e) + a];
        r[a] = m->r[n] + f * u[2 * a], z[a] = m->z[n] + f * u[2 * a + 1];
    }
    fem_element_points(r, z, B, w);
    if (bbar)
        mean_dilatation(B, w);
}

/* Reference forces of element e and its trial state (committed into m). */
static void reference_element(mesh *m, int e, const double ue[8], int bbar, int large, double y[8])
{
    double Bm[4][32], wm[4], Bc[4][32], wc[4], Bp[4][32], du[8], um[8];
    for (int j = 0; j < 8; j++)
        du[j] = ue[j] - m->uc[e][j], um[j] = 0.5 * (ue[j] + m->uc[e][j]);
    element_geometry(m, e, large ? um : ue, large ? 1 : 0, bbar, Bm, wm);
    element_geometry(m, e, ue, large ? 1 : 0, bbar, Bc, wc);
    element_geometry(m, e, um, large ? 1 : 0, 0, Bp, wm); /* plain B for the spin */
    memset(y, 0, 8 * sizeof *y);
    for (int q = 0; q < 4; q++) {
        const int p = 4 * e + q;
        double deps[4], s6[6] = {m->sig[p][0], m->sig[p][1], m->sig[p][2], m->sig[p][3], 0, 0}, sig[4], var[4];
        for (int i = 0; i < 4; i++) {
            double s = 0;
            for (int j = 0; j < 8; j++)
                s += Bm[q][8 * i + j] * (large ? du[j] : ue[j]);
            deps[i] = large ? s : s - m->eps[p][i];
            m->eps[p][i] = large ? m->eps[p][i] + s : s;
        }
        if (large) {
            double sp = 0;
            for (int a = 0; a < 4; a++)
                sp += Bp[q][2 * a] * du[2 * a + 1] - Bp[q][8 + 2 * a + 1] * du[2 * a];
            rf_material_rotate(s6, (const double[3]){0, 0, 0.5 * sp});
        }
        m->law.update(m->law.params, deps, s6, m->var[p], sig, var);
        memcpy(m->sig[p], sig, sizeof sig), memcpy(m->var[p], var, sizeof var);
        for (int j = 0; j < 8; j++)
            y[j] += wc[q] * (Bc[q][j] * sig[0] + Bc[q][8 + j] * sig[1] + Bc[q][16 + j] * sig[2] +
                             Bc[q][24 + j] * sig[3]);
    }
    memcpy(m->uc[e], ue, sizeof m->uc[e]);
}

static void check_kernel(int bbar, int large)
{
    static mesh m;
    mesh_init(&m);
    fem_kernel k = {0};
    rf_error err = {0};
    assert_int_equal(fem_kernel_points_axi_ex(&k, FIRST, COUNT, m.r, m.z, m.conn, &m.law, bbar, &err), RF_OK);
    if (large)
        assert_int_equal(fem_kernel_points_axi_large(&k, m.r, m.z, m.conn, &err), RF_OK);
    static const long cut[3] = {5, 11, 3}; /* a range boundary inside a block, per step */
    for (int s = 1; s <= 3; s++) {
        double ue[COUNT][8], fe[COUNT][8], y[8];
        displacements(&m, s, ue);
        const long c = cut[s - 1] + FIRST;
        k.ops->forces(&k, FIRST, c, ue[0], fe[0]);
        k.ops->forces(&k, c, FIRST + COUNT, ue[c - FIRST], fe[c - FIRST]);
        k.ops->commit(&k);
        double scale = 0, dmax = 0;
        for (int e = 0; e < COUNT; e++) {
            reference_element(&m, e, ue[e], bbar, large, y);
            for (int j = 0; j < 8; j++)
                scale = fmax(scale, fabs(y[j])), dmax = fmax(dmax, fabs(fe[e][j] - y[j]));
        }
        printf("bbar %d large %d step %d: |f| max %.3e, |f - reference| max %.3e\n", bbar, large, s, scale, dmax);
        assert_true(scale > 0);
        assert_true(dmax == 0);
    }
    fem_kernel_report r;
    fem_kernel_report_get(&k, &r);
    printf("  plastic strain max %.3e, plastic work %.3e J\n", r.plastic_strain_max, r.plastic_work);
    assert_true(r.plastic_strain_max > 1e-3 && r.plastic_work > 0); /* the return map ran */
    fem_kernel_release(&k);
}

static void test_small_strain(void **state)
{
    (void)state;
    check_kernel(0, 0);
    check_kernel(1, 0);
}

static void test_updated_lagrangian(void **state)
{
    (void)state;
    check_kernel(0, 1);
    check_kernel(1, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_strain),
        cmocka_unit_test(test_updated_lagrangian),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
