/* bench_hex8.c - the 3D impact mesh measured for speed (docs/fem-speed.md):
 * elements in the uniform fine boxes vs the graded layers, the spread of the
 * element stable time steps (what multi-time-step subcycling could save),
 * and ns per element-step of the internal-force kernels on 1 and 2 threads:
 *   stored   today's loop (float K_e per element, fem3d_solver.c's element_force)
 *   bmat     hex8_bmat_force on every element (matrix-free, J^-1 stored or recomputed)
 *   hybrid   hex8_shared_force on the slope box cubes + hex8_bmat_force on the rest
 * each with and without the node-ordered gather of element forces that
 * follows in the solver.  The mesh is the real one of the 10 m/s, 45 degree
 * impact (f3_impact_mesh_spec + f3_mesh_build).
 *   bench_hex8 [a/h, default 6] [repetitions, default 40] [max threads, default 2] [count]
 * "count" runs each kernel once (for valgrind --tool=callgrind instruction counts). */
#include <float.h>
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
#include "fem/fem_tuning.h"

typedef struct {
    f3_mesh mesh;
    f3_mesh_spec ms;
    double h, a_hertz, t_hertz;
    double steps; /* predicted steps of the impact (report_steps) */
    long ne, nn, box_b, box_s;
    float *K;           /* 576 per element: today's storage */
    double *elm, *dt_e; /* lumped element masses (8), stable step per element */
    double *dt_g;       /* Gershgorin lower bound of dt_e (rigorous, cheap) */
    long *inc_ptr, *inc;
    double *u, *fe, *f;
} bench;

static const f3_material GRANITE = {2600, 68.2e9, 0.25};

/* ---- today's kernel (a copy of fem3d_solver.c's element_force) ---- */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("default", "arch=x86-64-v3")))
#endif
static void stored_force(const float *restrict k, const double *restrict uel, double *restrict fe)
{
    double acc[24] = {0};
    for (int j = 0; j < 24; j++) {
        const float *kj = k + 24 * j;
        const double uj = uel[j];
        for (int i = 0; i < 24; i++)
            acc[i] += (double)kj[i] * uj;
    }
    memcpy(fe, acc, sizeof acc);
}

static void stored_loop(const bench *B, int threads)
{
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
    for (long e = 0; e < B->ne; e++) {
        const int *cn = B->mesh.conn + 8 * e;
        double uel[24];
        for (int a = 0; a < 8; a++)
            for (int q = 0; q < 3; q++)
                uel[3 * a + q] = B->u[3 * cn[a] + q];
        stored_force(B->K + 576 * e, uel, B->fe + 24 * e);
    }
    (void)threads;
}

static void gather_loop(const bench *B, int threads)
{
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
    for (long n = 0; n < B->nn; n++) {
        double fx = 0, fy = 0, fz = 0;
        for (long p = B->inc_ptr[n]; p < B->inc_ptr[n + 1]; p++) {
            const double *fp = B->fe + 24 * (B->inc[p] >> 3) + 3 * (B->inc[p] & 7);
            fx += fp[0], fy += fp[1], fz += fp[2];
        }
        B->f[3 * n] = fx, B->f[3 * n + 1] = fy, B->f[3 * n + 2] = fz;
    }
    (void)threads;
}

/* ---- set-up: mesh, matrices, incidence, element time steps ---- */
static int setup(bench *B, double refinement)
{
    memset(B, 0, sizeof *B);
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10,
                          .slope_angle = 45 * RF_PI / 180, .friction = 0.6};
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = refinement;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    f3_impact_mesh_spec(&in, &o, &o3, &B->ms, &B->h, &B->a_hertz);
    const double Vn = 10 * cos(45 * RF_PI / 180), delta = B->a_hertz * B->a_hertz / in.radius;
    B->t_hertz = 2.94328 * delta / Vn;
    rf_error err = {0};
    if (f3_mesh_build(&B->ms, &B->mesh, 50000000, &err) != RF_OK) {
        fprintf(stderr, "bench_hex8: %s\n", err.msg);
        return -1;
    }
    B->ne = B->mesh.n_elems, B->nn = B->mesh.n_nodes;
    const f3_box *bb = &B->ms.boulder, *bs = &B->ms.slope;
    B->box_b = (long)(bb->nxm + bb->nxp) * bb->ny * bb->nz;
    B->box_s = (long)(bs->nxm + bs->nxp) * bs->ny * bs->nz;
    B->K = malloc((size_t)B->ne * 576 * sizeof *B->K);
    B->elm = malloc((size_t)B->ne * 8 * sizeof *B->elm);
    B->dt_e = malloc((size_t)B->ne * sizeof *B->dt_e);
    B->dt_g = malloc((size_t)B->ne * sizeof *B->dt_g);
    B->inc_ptr = calloc((size_t)B->nn + 1, sizeof *B->inc_ptr);
    B->inc = malloc((size_t)B->ne * 8 * sizeof *B->inc);
    B->u = malloc((size_t)B->nn * 3 * sizeof *B->u);
    B->fe = calloc((size_t)B->ne * 24, sizeof *B->fe);
    B->f = calloc((size_t)B->nn * 3, sizeof *B->f);
    if (!B->K || !B->elm || !B->dt_e || !B->dt_g || !B->inc_ptr || !B->inc || !B->u || !B->fe || !B->f)
        return -1;
    for (long i = 0; i < 3 * B->nn; i++)
        B->u[i] = 1e-5 * sin(0.37 * (double)i);
    for (long e = 0; e < B->ne; e++)
        for (int a = 0; a < 8; a++)
            B->inc_ptr[B->mesh.conn[8 * e + a] + 1]++;
    for (long n = 0; n < B->nn; n++)
        B->inc_ptr[n + 1] += B->inc_ptr[n];
    long *fill = malloc((size_t)B->nn * sizeof *fill);
    if (!fill)
        return -1;
    memcpy(fill, B->inc_ptr, (size_t)B->nn * sizeof *fill);
    for (long e = 0; e < B->ne; e++)
        for (int a = 0; a < 8; a++)
            B->inc[fill[B->mesh.conn[8 * e + a]]++] = e * 8 + a;
    free(fill);
    return 0;
}

/* Element matrices (today's float K_e) and lumped masses; returns the boulder mesh mass. */
static double element_matrices(bench *B)
{
    double mesh_mass_b = 0;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 256) num_threads(2) reduction(+ : mesh_mass_b)
#endif
    for (long e = 0; e < B->ne; e++) {
        const int *cn = B->mesh.conn + 8 * e;
        double xe[24], Kd[576], vol;
        for (int a = 0; a < 8; a++)
            for (int q = 0; q < 3; q++)
                xe[3 * a + q] = B->mesh.x[3 * cn[a] + q];
        f3_hex_matrices(xe, &GRANITE, Kd, B->elm + 8 * e, &vol);
        for (int q = 0; q < 576; q++)
            B->K[576 * e + q] = (float)Kd[q];
        if (e < B->mesh.boulder_elems)
            for (int a = 0; a < 8; a++)
                mesh_mass_b += B->elm[8 * e + a];
    }
    return mesh_mass_b;
}

/* The eigenvalue bound 2/sqrt(max lambda(M_e^-1 K_e)) with the solver's constraints (symmetry
   plane u_y = 0, fixed outer surface) and boulder mass scaling. */
static void element_steps(bench *B, double mesh_mass_b)
{
    const double mscale = 4.0 / 3.0 * RF_PI * 2600 / 2 / mesh_mass_b;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 256) num_threads(2)
#endif
    for (long e = 0; e < B->ne; e++) {
        const int *cn = B->mesh.conn + 8 * e;
        unsigned char fr[24];
        double Kd[576], m[8];
        for (int a = 0; a < 8; a++) {
            const unsigned char fl = B->mesh.flags[cn[a]];
            const int outer = cn[a] >= B->mesh.boulder_nodes && (fl & F3_OUTER);
            fr[3 * a] = fr[3 * a + 2] = !outer;
            fr[3 * a + 1] = !outer && !(fl & F3_SYM);
            m[a] = B->elm[8 * e + a] * (e < B->mesh.boulder_elems ? mscale : 1);
        }
        for (int q = 0; q < 576; q++)
            Kd[q] = B->K[576 * e + q];
        B->dt_e[e] = 2 / sqrt(f3_hex_lambda_max(Kd, m, fr));
        B->dt_g[e] = 2 / sqrt(hex8_gershgorin_bound(Kd, m, fr));
    }
}

/* ---- measurements ---- */
static void report_zones(const bench *B)
{
    const long nb = B->mesh.boulder_elems, ns = B->ne - nb;
    printf("mesh: a/h = %.3g, h = %.4g m, Hertz radius %.4g m, duration %.3g ms; %ld elements, %ld nodes\n",
           B->a_hertz / B->h, B->h, B->a_hertz, 1e3 * B->t_hertz, B->ne, B->nn);
    printf("  boulder: %ld elements, fine box %ld (%.1f %%), graded %ld\n", nb, B->box_b, 100.0 * B->box_b / nb,
           nb - B->box_b);
    printf("  slope:   %ld elements, fine box %ld (%.1f %%), graded %ld\n", ns, B->box_s, 100.0 * B->box_s / ns,
           ns - B->box_s);
    printf("  fine boxes together: %.1f %% of the elements\n", 100.0 * (B->box_b + B->box_s) / B->ne);
}

/* Multi-time-step potential: the work relative to one global step dt_min, (i) ideal (every element
   at its own step), (ii) power-of-two levels where an element runs at the finest level of the
   elements it shares a node with (the halo a subcycling scheme must update with the fine side). */
static void report_steps(bench *B)
{
    double dmin = DBL_MAX, ideal = 0;
    for (long e = 0; e < B->ne; e++)
        dmin = fmin(dmin, B->dt_e[e]);
    int *lev = malloc((size_t)B->ne * sizeof *lev), *nlev = malloc((size_t)B->nn * sizeof *nlev);
    long hist[2][12] = {{0}};
    for (long e = 0; e < B->ne; e++) {
        ideal += dmin / B->dt_e[e];
        int k = (int)floor(log2(B->dt_e[e] / dmin) + 1e-12);
        lev[e] = k > 11 ? 11 : k;
        const int zone = (e < B->box_b) || (e >= B->mesh.boulder_elems && e < B->mesh.boulder_elems + B->box_s);
        hist[zone ? 0 : 1][lev[e]]++;
    }
    for (long n = 0; n < B->nn; n++)
        nlev[n] = 11;
    for (long e = 0; e < B->ne; e++)
        for (int a = 0; a < 8; a++)
            if (lev[e] < nlev[B->mesh.conn[8 * e + a]])
                nlev[B->mesh.conn[8 * e + a]] = lev[e];
    double binned = 0;
    for (long e = 0; e < B->ne; e++) {
        int k = lev[e];
        for (int a = 0; a < 8; a++)
            if (nlev[B->mesh.conn[8 * e + a]] < k)
                k = nlev[B->mesh.conn[8 * e + a]];
        binned += ldexp(1.0, -k);
    }
    const double steps = ceil(1.3 * B->t_hertz / (0.9 * dmin));
    B->steps = steps;
    printf("time steps: smallest element bound %.4g us, step 0.9 x that; %.0f steps to 1.3 Hertz durations "
           "(the solver's shortest run)\n",
           1e6 * dmin, steps);
    printf("  dt_e / dt_min in [2^k, 2^(k+1)):  k    fine-box   graded\n");
    for (int k = 0; k < 12; k++)
        if (hist[0][k] || hist[1][k])
            printf("                                   %2d  %9ld %8ld\n", k, hist[0][k], hist[1][k]);
    printf("  subcycling work / one global step: ideal %.3f, power-of-two levels with node halo %.3f\n",
           ideal / B->ne, binned / B->ne);
    long need = 0;
    double gmin = DBL_MAX, ratio = 0;
    for (long e = 0; e < B->ne; e++) {
        need += B->dt_g[e] < dmin * (1 + 1e-12);
        gmin = fmin(gmin, B->dt_g[e]);
        ratio += B->dt_g[e] / B->dt_e[e];
    }
    printf("  Gershgorin bound: dt_G / dt_e = %.3f on average; exact eigen-solves needed for the minimum: %ld of %ld "
           "(dt_G < dt_min)\n",
           ratio / B->ne, need, B->ne);
    free(lev), free(nlev);
}

typedef struct {
    hex8_bmat all, rest, lean, lean_rest; /* J stored / J recomputed from x */
    int *cubes;
    long ncubes;
    double Kcube[576];
} kernels;

static int kernels_init(const bench *B, kernels *k)
{
    const long ne = B->ne;
    int *ids = malloc((size_t)ne * sizeof *ids), *rest = malloc((size_t)ne * sizeof *rest);
    double *lam = malloc((size_t)ne * sizeof *lam), *mu = malloc((size_t)ne * sizeof *mu);
    k->cubes = malloc((size_t)ne * sizeof *k->cubes);
    unsigned char *is_cube = calloc((size_t)ne, 1);
    if (!ids || !rest || !lam || !mu || !k->cubes || !is_cube)
        return -1;
    for (long e = 0; e < ne; e++)
        ids[e] = (int)e, lam[e] = GRANITE.E * GRANITE.nu / ((1 + GRANITE.nu) * (1 - 2 * GRANITE.nu)),
        mu[e] = GRANITE.E / (2 * (1 + GRANITE.nu));
    const long first = B->mesh.boulder_elems;
    double xref[24], m[8], vol;
    for (int a = 0; a < 8; a++)
        for (int d = 0; d < 3; d++)
            xref[3 * a + d] = B->mesh.x[3 * (long)B->mesh.conn[8 * first + a] + d];
    k->ncubes = hex8_find_congruent(B->mesh.x, B->mesh.conn, ids + first, ne - first, xref, 1e-9 * B->h, k->cubes);
    f3_hex_matrices(xref, &GRANITE, k->Kcube, m, &vol);
    for (long c = 0; c < k->ncubes; c++)
        is_cube[k->cubes[c]] = 1;
    long nr = 0;
    for (long e = 0; e < ne; e++)
        if (!is_cube[e])
            rest[nr++] = (int)e;
    /* the boulder's box is the inversion image of cubes: how far are its K_e from one shared K? */
    double dK = 0, K0 = 0;
    for (long e = 0; e < B->box_b; e++)
        for (int q = 0; q < 576; q++) {
            dK = fmax(dK, fabs(B->K[576 * e + q] - B->K[q]));
            K0 = fmax(K0, fabs(B->K[q]));
        }
    printf("congruent to the slope cube (1e-9 h): %ld slope elements; boulder box: max |K_e - K_0| / max |K_0| = %.2g\n",
           k->ncubes, dK / K0);
    rf_error err = {0};
    int rc = hex8_bmat_init(&k->all, B->mesh.x, B->mesh.conn, ids, ne, lam, mu, 1, &err) != RF_OK ||
             hex8_bmat_init(&k->rest, B->mesh.x, B->mesh.conn, rest, nr, lam, mu, 1, &err) != RF_OK ||
             hex8_bmat_init(&k->lean, B->mesh.x, B->mesh.conn, ids, ne, lam, mu, 0, &err) != RF_OK ||
             hex8_bmat_init(&k->lean_rest, B->mesh.x, B->mesh.conn, rest, nr, lam, mu, 0, &err) != RF_OK;
    free(ids), free(rest), free(lam), free(mu), free(is_cube);
    return rc ? -1 : 0;
}

static void bmat_loop(const hex8_bmat *M, const bench *B, int threads)
{
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
    for (long b = 0; b < M->nblk; b++)
        hex8_bmat_force(M, b, b + 1, B->u, NULL, B->fe);
    (void)threads;
}

static void shared_loop(const kernels *k, const bench *B, int threads)
{
    const long chunk = 64, nch = (k->ncubes + chunk - 1) / chunk;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
    for (long c = 0; c < nch; c++) {
        const long n = c + 1 < nch ? chunk : k->ncubes - c * chunk;
        hex8_shared_force(k->Kcube, B->mesh.conn, k->cubes + c * chunk, n, B->u, B->fe);
    }
    (void)threads;
}

static void run_variant(const bench *B, const kernels *k, int variant, int threads, int gather)
{
    if (variant == 0)
        stored_loop(B, threads);
    else if (variant == 1 || variant == 3)
        bmat_loop(variant == 1 ? &k->all : &k->lean, B, threads);
    else {
        shared_loop(k, B, threads);
        bmat_loop(variant == 2 ? &k->rest : &k->lean_rest, B, threads);
    }
    if (gather)
        gather_loop(B, threads);
}

enum { NVAR = 5, NTHR = 4 };

/* Bytes each loop moves per element-step if every array streams once per step (a model: u is
   re-read from cache by neighbouring elements; a written line is read first, so writes count
   twice).  The bandwidth floor is these bytes over bench_stream's triad rate. */
static void report_bytes(const bench *B, const kernels *k)
{
    const double per_node = (double)B->nn / (double)B->ne;
    const double u_rd = 24 * per_node, fe_wr = 2 * 24 * 8.0;
    const double stored = 576 * 4 + 8 * 4 + u_rd + fe_wr;
    const double bm = (72 + 8 + 2) * 8 + 8 * 4 + 4 + u_rd + fe_wr;
    const double cube = 8 * 4 + 4 + u_rd + fe_wr, fc = (double)k->ncubes / (double)B->ne;
    const double lean = 8 * 4 + 4 + 2 * 8 + 2 * u_rd + fe_wr; /* x is gathered like u */
    const double gather = 8 * 8 + 8 * per_node + 24 * 8 + 2 * 24 * per_node;
    printf("bytes per element-step (model): stored K_e %.0f; J stored %.0f, with shared K %.0f; J recomputed %.0f, "
           "with shared K %.0f; node gather %.0f more\n",
           stored, bm, fc * cube + (1 - fc) * bm, lean, fc * cube + (1 - fc) * lean, gather);
}

/* ns per element-step, best of reps, the variants interleaved so that a burst of load from
   other processes hits them alike: best[v][t - 1][gather]. */
static void time_variants(const bench *B, const kernels *k, int tmax, int reps, double best[NVAR][NTHR][2])
{
    for (int v = 0; v < NVAR; v++)
        for (int t = 0; t < NTHR; t++)
            best[v][t][0] = best[v][t][1] = 1e30;
    for (int r = 0; r <= reps; r++)
        for (int v = 0; v < NVAR; v++)
            for (int t = 1; t <= tmax; t++)
                for (int g = 0; g < 2; g++) {
                    const double t0 = rf_monotonic_seconds();
                    run_variant(B, k, v, t, g);
                    const double ns = 1e9 * (rf_monotonic_seconds() - t0) / (double)B->ne;
                    if (r > 0 && ns < best[v][t - 1][g]) /* r = 0 warms the caches */
                        best[v][t - 1][g] = ns;
                }
}

/* One pass of each variant in its own function, for instruction counts:
   valgrind --tool=callgrind bench_hex8 A 0 1 count, then callgrind_annotate --inclusive=yes. */
__attribute__((noinline)) static void count_stored(const bench *B, const kernels *k) { run_variant(B, k, 0, 1, 0); }
__attribute__((noinline)) static void count_bmat(const bench *B, const kernels *k) { run_variant(B, k, 1, 1, 0); }
__attribute__((noinline)) static void count_hybrid(const bench *B, const kernels *k) { run_variant(B, k, 2, 1, 0); }
__attribute__((noinline)) static void count_lean(const bench *B, const kernels *k) { run_variant(B, k, 3, 1, 0); }
__attribute__((noinline)) static void count_lean_hybrid(const bench *B, const kernels *k) { run_variant(B, k, 4, 1, 0); }
__attribute__((noinline)) static void count_gather(const bench *B) { gather_loop(B, 1); }

static void release(bench *B, kernels *k)
{
    hex8_bmat_free(&k->all), hex8_bmat_free(&k->rest), hex8_bmat_free(&k->lean), hex8_bmat_free(&k->lean_rest);
    free(k->cubes);
    f3_mesh_free(&B->mesh);
    free(B->K), free(B->elm), free(B->dt_e), free(B->dt_g), free(B->inc_ptr), free(B->inc), free(B->u), free(B->fe), free(B->f);
}

int main(int argc, char **argv)
{
    const double ref = argc > 1 ? atof(argv[1]) : 6;
    const int reps = argc > 2 ? atoi(argv[2]) : 40, tmax = argc > 3 ? atoi(argv[3]) : 2;
    const int count = argc > 4 && strcmp(argv[4], "count") == 0;
    bench B;
    kernels k;
    memset(&k, 0, sizeof k);
    if (setup(&B, ref) != 0)
        return 1;
    const double mesh_mass_b = element_matrices(&B);
    report_zones(&B);
    if (!count) {
        element_steps(&B, mesh_mass_b);
        report_steps(&B);
    }
    if (kernels_init(&B, &k) != 0)
        return 1;
    report_bytes(&B, &k);
    if (count) {
        count_stored(&B, &k), count_bmat(&B, &k), count_hybrid(&B, &k), count_gather(&B);
        count_lean(&B, &k), count_lean_hybrid(&B, &k);
        printf("counted one pass of each kernel over %ld elements\n", B.ne);
        release(&B, &k);
        return 0;
    }
    static const char *names[NVAR] = {"stored float K_e (today)", "matrix-free, J stored", "shared K + J stored",
                                      "matrix-free, J recomputed", "shared K + J recomputed"};
    double best[NVAR][NTHR][2];
    const int tm = tmax < NTHR ? tmax : NTHR;
    time_variants(&B, &k, tm, reps, best);
    printf("ns per element-step, best of %d (kernel only / kernel + node gather)\n", reps);
    for (int v = 0; v < NVAR; v++) {
        printf("  %-28s", names[v]);
        for (int t = 1; t <= tm; t++)
            printf("  %d thr: %6.1f / %6.1f", t, best[v][t - 1][0], best[v][t - 1][1]);
        printf("\n");
    }
    printf("force loop (kernel + gather) of the whole impact, %.0f steps x %ld elements: ", B.steps, B.ne);
    for (int v = 0; v < NVAR; v++)
        printf("%s%.1f s", v ? ", " : "", best[v][0][1] * 1e-9 * B.steps * (double)B.ne);
    printf(" on 1 thread (same order as above)\n");
    release(&B, &k);
    return 0;
}
