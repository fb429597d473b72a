/* bench_quad4.c - ns per element-step of the axisymmetric internal force on
 * the real 10 m/s impact mesh (fem_impact_mesh_spec + fem_mesh_build):
 *   today    fem_solver.c's force_kernel (64 scalar products per element)
 *   quad4    quad4_force with per-element K_e (column updates, FMA, clones)
 *   shared   quad4_force with K_e shared by shape (quad4_group_by_shape)
 *   packed   quad4_force_packed: the 36 entries of each symmetric K_e, 8
 *            elements per vector (the solver's path; the same bits as quad4)
 * one thread (the solver's 2-thread scheme adds per-thread force buffers).
 *   bench_quad4 [a/h, default 10] [repetitions, default 200] [count]
 * "count" runs each loop once, for valgrind --tool=callgrind. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"
#include "fem/fem_internal.h"
#include "fem/fem_spec.h"
#include "fem/quad4_kernel.h"
#include "rockfuzz/fem.h"

typedef struct {
    fem_mesh mesh;
    double *K, *Kg, *u, *f, *pk;
    int *kidx, *rep;
    long ng;
} bench;

/* A copy of fem_solver.c's force_kernel. */
static void today_force(const bench *B)
{
    const int *conn = B->mesh.conn;
    for (long e = 0; e < B->mesh.n_elems; e++) {
        const int *c = conn + 4 * e;
        const double *k = B->K + 64 * e;
        double ue[8], fe[8];
        for (int a = 0; a < 4; a++)
            ue[2 * a] = B->u[2 * c[a]], ue[2 * a + 1] = B->u[2 * c[a] + 1];
        for (int a = 0; a < 8; a++) {
            const double *ka = k + 8 * a;
            fe[a] = ka[0] * ue[0] + ka[1] * ue[1] + ka[2] * ue[2] + ka[3] * ue[3] + ka[4] * ue[4] + ka[5] * ue[5] +
                    ka[6] * ue[6] + ka[7] * ue[7];
        }
        for (int a = 0; a < 4; a++)
            B->f[2 * c[a]] += fe[2 * a], B->f[2 * c[a] + 1] += fe[2 * a + 1];
    }
}

static int setup(bench *B, double refinement)
{
    memset(B, 0, sizeof *B);
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10};
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = refinement;
    fem_body_spec bs, ss;
    rf_error err = {0};
    if (fem_impact_mesh_spec(&in, &o, &bs, &ss, &err) != RF_OK || fem_mesh_build(&bs, &ss, &B->mesh, 10000000, &err)) {
        fprintf(stderr, "bench_quad4: %s\n", err.msg);
        return -1;
    }
    const long ne = B->mesh.n_elems, nn = B->mesh.n_nodes;
    B->K = malloc((size_t)ne * 64 * sizeof *B->K);
    B->Kg = malloc((size_t)ne * 64 * sizeof *B->Kg);
    B->u = malloc((size_t)nn * 2 * sizeof *B->u);
    B->f = calloc((size_t)nn * 2, sizeof *B->f);
    B->kidx = malloc((size_t)ne * sizeof *B->kidx);
    B->rep = malloc((size_t)ne * sizeof *B->rep);
    B->pk = malloc((size_t)quad4_packed_size(ne) * sizeof *B->pk);
    if (!B->K || !B->Kg || !B->u || !B->f || !B->kidx || !B->rep || !B->pk)
        return -1;
    const fem_material mat = {2600, 68.2e9, 0.25};
    for (long e = 0; e < ne; e++) {
        double r[4], z[4], m[4], mass, area;
        for (int a = 0; a < 4; a++)
            r[a] = B->mesh.r[B->mesh.conn[4 * e + a]], z[a] = B->mesh.z[B->mesh.conn[4 * e + a]];
        fem_element_matrices(r, z, &mat, B->K + 64 * e, m, &mass, &area);
    }
    for (long i = 0; i < 2 * nn; i++)
        B->u[i] = 1e-5 * sin(0.37 * (double)i);
    B->ng = quad4_group_by_shape(B->mesh.r, B->mesh.z, B->mesh.conn, ne, 1e-12, B->kidx, B->rep);
    if (B->ng < 0 || quad4_pack(B->K, ne, B->pk) != 0)
        return -1;
    for (long g = 0; g < B->ng; g++)
        memcpy(B->Kg + 64 * g, B->K + 64 * (long)B->rep[g], 64 * sizeof *B->Kg);
    return 0;
}

static void run(const bench *B, int v)
{
    memset(B->f, 0, (size_t)B->mesh.n_nodes * 2 * sizeof *B->f); /* as the solver does every step */
    if (v == 0)
        today_force(B);
    else if (v == 1)
        quad4_force(B->K, NULL, B->mesh.conn, 0, B->mesh.n_elems, B->u, B->f);
    else if (v == 2)
        quad4_force(B->Kg, B->kidx, B->mesh.conn, 0, B->mesh.n_elems, B->u, B->f);
    else
        quad4_force_packed(B->pk, B->mesh.conn, 0, B->mesh.n_elems, B->u, B->f);
}

__attribute__((noinline)) static void count_today(const bench *B) { run(B, 0); }
__attribute__((noinline)) static void count_quad4(const bench *B) { run(B, 1); }
__attribute__((noinline)) static void count_shared(const bench *B) { run(B, 2); }
__attribute__((noinline)) static void count_packed(const bench *B) { run(B, 3); }

int main(int argc, char **argv)
{
    const double ref = argc > 1 ? atof(argv[1]) : 10;
    const int reps = argc > 2 ? atoi(argv[2]) : 200, count = argc > 3 && strcmp(argv[3], "count") == 0;
    bench B;
    if (setup(&B, ref) != 0)
        return 1;
    const long ne = B.mesh.n_elems;
    printf("axisymmetric mesh a/h = %g: %ld elements, %ld distinct shapes (K table %.2f MB by shape, %.2f MB per "
           "element, %.2f MB packed)\n",
           ref, ne, B.ng, B.ng * 512e-6, ne * 512e-6, (double)quad4_packed_size(ne) * 8e-6);
    if (count) {
        count_today(&B), count_quad4(&B), count_shared(&B), count_packed(&B);
    } else {
        static const char *names[4] = {"today (scalar rows)", "quad4_force, K per element", "quad4_force, K by shape",
                                       "quad4_force_packed"};
        double best[4] = {1e30, 1e30, 1e30, 1e30};
        for (int r = 0; r <= reps; r++)
            for (int v = 0; v < 4; v++) {
                const double t0 = rf_monotonic_seconds();
                run(&B, v);
                const double ns = 1e9 * (rf_monotonic_seconds() - t0) / (double)ne;
                if (r > 0 && ns < best[v])
                    best[v] = ns;
            }
        for (int v = 0; v < 4; v++)
            printf("  %-28s %6.1f ns per element-step (best of %d, incl. zeroing f)\n", names[v], best[v], reps);
    }
    fem_mesh_free(&B.mesh);
    free(B.K), free(B.Kg), free(B.u), free(B.f), free(B.kidx), free(B.rep), free(B.pk);
    return 0;
}
