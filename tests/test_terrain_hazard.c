/* test_terrain_hazard.c - the hazard raster accumulators (terrain_hazard.c)
 * against brute-force references: random pieces (flights and contact chords,
 * not the simulator) of many random trajectories on a small synthetic DEM.
 * The cells a trajectory touches are found again by clipping each piece's
 * map segment against every cell (Liang-Barsky, positive length) and must
 * contain every cell of a dense sampling of the path; counts and deposits
 * exact; per-cell maxima of energy and height recomputed from the clipped
 * intervals; percentiles within TERRAIN_HAZARD_REL_ERROR of the sorted
 * brute force of the same values (rf_traj_percentiles_at); merges over 1, 2
 * and 3 accumulators in several orders, and packed as MPI ranks would send
 * them, give the same bytes; the memory does
 * not grow with the trajectories.  Plus the walk at corners and along cell
 * lines, the grid, the band names, the apex height of a throw, and the
 * within-bin error near its bound. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "trajectory/terrain_internal.h"

#define G 9.81
#define MAXP 5

typedef struct {
    size_t n;
    terrain_piece pc[MAXP];
    double mass;
    int stopped;
    double end[3];
} traj;

/* ---- small helpers ---- */

static uint64_t rng_state;
static double urand(void) /* splitmix64 -> [0, 1) */
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static rf_terrain *dem_make(size_t nx, size_t ny, double x0, double y0, double d, int hole)
{
    double *z = malloc(nx * ny * sizeof *z);
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++)
            z[j * nx + i] = 0.3 * (double)i * d + 0.1 * (double)j * d + sin(0.7 * (double)i) * cos(0.5 * (double)j);
    if (hole)
        z[(ny - 2) * nx + 1] = NAN; /* a no-data node: four cells off the surface */
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(nx, ny, x0, y0, d, d, z, &t, &err), RF_OK);
    free(z);
    return t;
}

static void spec_make(rf_traj_spec *s, rf_terrain_def *d, double cell, unsigned stats)
{
    memset(s, 0, sizeof *s);
    memset(d, 0, sizeof *d);
    d->raster_cell = cell, d->statistics = stats;
    s->terrain = d;
}

#define ALL_STATS                                                                                                  \
    (RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS | RF_TERRAIN_ENERGY | RF_TERRAIN_HEIGHT)

static void feed(rf_terrain_hazard *h, const rf_terrain *dem, const traj *t)
{
    terrain_hazard_begin(h);
    for (size_t k = 0; k < t->n; k++)
        terrain_hazard_piece(h, dem, t->mass, &t->pc[k]);
    terrain_hazard_end(h, t->stopped, t->end);
}

static const terrain_band *band_named(const terrain_band *b, size_t n, const char *name)
{
    for (size_t k = 0; k < n; k++)
        if (!strcmp(b[k].name, name))
            return &b[k];
    fail_msg("no band %s", name);
    return NULL;
}

/* ---- random trajectories ---- */

static void piece_random(terrain_piece *pc, const rf_terrain *dem, double x, double y)
{
    double zg = 0;
    int on = rf_terrain_height(dem, x, y, &zg, NULL);
    memset(pc, 0, sizeof *pc);
    pc->p[0] = x, pc->p[1] = y, pc->p[2] = (on ? zg : 0) + 4 * urand();
    pc->e_rot = 1e3 * urand();
    double speed = 0.5 + 14 * urand(), az = 6.283185307179586 * urand();
    pc->v[0] = speed * cos(az), pc->v[1] = speed * sin(az);
    if (urand() < 0.6) { /* flight */
        pc->v[2] = -5 + 12 * urand();
        pc->a[2] = -G;
        pc->T = 0.05 + 1.2 * urand();
    } else { /* contact step: chord, accelerated along and down */
        pc->on_ground = urand() < 0.8;
        pc->v[2] = -2 * urand();
        pc->a[0] = -3 + 6 * urand(), pc->a[1] = -3 + 6 * urand(), pc->a[2] = -2 * urand();
        pc->T = 0.4 * urand();
    }
}

static void traj_random(traj *t, const rf_terrain *dem)
{
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    double x = xmin + (xmax - xmin) * urand(), y = ymin + (ymax - ymin) * urand();
    t->n = 1 + (size_t)(urand() * MAXP);
    t->mass = 100 + 5000 * urand();
    for (size_t k = 0; k < t->n; k++) {
        piece_random(&t->pc[k], dem, x, y);
        const terrain_piece *pc = &t->pc[k];
        x = pc->p[0] + pc->v[0] * pc->T + 0.5 * pc->a[0] * pc->T * pc->T;
        y = pc->p[1] + pc->v[1] * pc->T + 0.5 * pc->a[1] * pc->T * pc->T;
    }
    t->stopped = urand() < 0.5;
    t->end[0] = x, t->end[1] = y, t->end[2] = 0;
}

/* ---- the brute-force reference ---- */

typedef struct {
    size_t nx, ny;
    double x0, y0, c;
} grid;

/* Liang-Barsky: the parameters of P0 + s D inside [lo, hi] on one axis. */
static int lb_axis(double p0, double d, double lo, double hi, double *sa, double *sb)
{
    if (d == 0)
        return p0 >= lo && p0 < hi;
    double s0 = (lo - p0) / d, s1 = (hi - p0) / d;
    if (s0 > s1) {
        double t = s0;
        s0 = s1, s1 = t;
    }
    *sa = fmax(*sa, s0), *sb = fmin(*sb, s1);
    return 1;
}

static double ref_energy(const terrain_piece *pc, double mass, double tau)
{
    double v2 = 0;
    for (int k = 0; k < 3; k++)
        v2 += (pc->v[k] + pc->a[k] * tau) * (pc->v[k] + pc->a[k] * tau);
    return 0.5 * mass * v2 + pc->e_rot;
}

static double ref_height_at(const rf_terrain *dem, const terrain_piece *pc, double s, const double D[2])
{
    double tau = s * pc->T, zg;
    if (!rf_terrain_height(dem, pc->p[0] + s * D[0], pc->p[1] + s * D[1], &zg, NULL))
        return NAN;
    return pc->p[2] + pc->v[2] * tau + 0.5 * pc->a[2] * tau * tau - zg;
}

/* Per cell, the trajectory's maxima (NaN: untouched / no height). */
static void ref_traj(const grid *g, const rf_terrain *dem, const traj *t, unsigned char *hit, double *e, double *h)
{
    size_t cells = g->nx * g->ny;
    for (size_t c = 0; c < cells; c++)
        hit[c] = 0, e[c] = h[c] = NAN;
    for (size_t k = 0; k < t->n; k++) {
        const terrain_piece *pc = &t->pc[k];
        double T = pc->T, D[2];
        for (int a = 0; a < 2; a++)
            D[a] = pc->v[a] * T + 0.5 * pc->a[a] * T * T;
        for (size_t j = 0; j < g->ny; j++)
            for (size_t i = 0; i < g->nx; i++) {
                double sa = 0, sb = 1, xl = g->x0 + (double)i * g->c, yl = g->y0 + (double)j * g->c;
                if (!lb_axis(pc->p[0], D[0], xl, xl + g->c, &sa, &sb) ||
                    !lb_axis(pc->p[1], D[1], yl, yl + g->c, &sa, &sb))
                    continue;
                int point = D[0] == 0 && D[1] == 0;
                if (!(sb > sa) && !point)
                    continue;
                size_t c = j * g->nx + i;
                hit[c] = 1;
                e[c] = fmax(e[c], fmax(ref_energy(pc, t->mass, sa * T), ref_energy(pc, t->mass, sb * T)));
                double hh = 0;
                if (!pc->on_ground) {
                    hh = fmax(fmax(ref_height_at(dem, pc, sa, D), ref_height_at(dem, pc, sb, D)),
                              ref_height_at(dem, pc, 0.5 * (sa + sb), D));
                    double sap = T > 0 && pc->a[2] < 0 ? -pc->v[2] / pc->a[2] / T : -1;
                    if (sap > sa && sap < sb)
                        hh = fmax(hh, ref_height_at(dem, pc, sap, D));
                    hh = hh < 0 ? 0 : hh;
                }
                h[c] = fmax(h[c], hh);
            }
    }
}

/* Dense sampling of the path: every sampled cell must be in hit, and no
 * sampled energy above the cell's maximum. */
static void dense_check(const grid *g, const traj *t, const unsigned char *hit, const double *e)
{
    const int N = 2000;
    for (size_t k = 0; k < t->n; k++) {
        const terrain_piece *pc = &t->pc[k];
        double T = pc->T;
        for (int q = 0; q < N; q++) {
            double s = (q + 0.5) / N, tau = s * T;
            double x = pc->p[0] + s * (pc->v[0] * T + 0.5 * pc->a[0] * T * T);
            double y = pc->p[1] + s * (pc->v[1] * T + 0.5 * pc->a[1] * T * T);
            double fi = floor((x - g->x0) / g->c), fj = floor((y - g->y0) / g->c);
            if (fi < 0 || fj < 0 || fi >= (double)g->nx || fj >= (double)g->ny)
                continue;
            size_t c = (size_t)fj * g->nx + (size_t)fi;
            assert_true(hit[c]);
            assert_true(ref_energy(pc, t->mass, tau) <= e[c] * (1 + 1e-12));
        }
    }
}

/* ---- the random run ---- */

#define NTRAJ 1500

typedef struct {
    rf_terrain *dem;
    rf_traj_spec s;
    rf_terrain_def d;
    traj *t;
    grid g;
} run_case;

static void run_case_make(run_case *rc, double cell, uint64_t seed)
{
    rng_state = seed;
    rc->dem = dem_make(13, 10, 1000.25, -50.5, 2.0, 1);
    spec_make(&rc->s, &rc->d, cell, ALL_STATS);
    rc->s.outputs.n_percentiles = 4;
    double lv[4] = {10, 50, 95, 99};
    memcpy(rc->s.outputs.percentiles, lv, sizeof lv);
    rc->t = malloc(NTRAJ * sizeof *rc->t);
    for (size_t k = 0; k < NTRAJ; k++)
        traj_random(&rc->t[k], rc->dem);
}

static void run_case_free(run_case *rc)
{
    free(rc->t);
    rf_terrain_free(rc->dem);
}

/* The accumulator's grid against the definition. */
static void check_grid(run_case *rc, const rf_terrain_hazard *h, double cell)
{
    terrain_hazard_grid(h, &rc->g.nx, &rc->g.ny, &rc->g.x0, &rc->g.y0, &rc->g.c);
    double c = cell > 0 ? cell : 2.0;
    assert_true(rc->g.c == c && rc->g.x0 == 1000.25 && rc->g.y0 == -50.5);
    assert_int_equal(rc->g.nx, (size_t)ceil(24 / c - 1e-9));
    assert_int_equal(rc->g.ny, (size_t)ceil(18 / c - 1e-9));
}

typedef struct {
    double *e, *h;              /* cells x NTRAJ per-trajectory maxima (NaN: none) */
    double *pass, *dep;
} reference;

static void reference_make(run_case *rc, reference *r)
{
    size_t cells = rc->g.nx * rc->g.ny;
    r->e = malloc(cells * NTRAJ * sizeof *r->e), r->h = malloc(cells * NTRAJ * sizeof *r->h);
    r->pass = calloc(cells, sizeof *r->pass), r->dep = calloc(cells, sizeof *r->dep);
    unsigned char *hit = malloc(cells);
    double *e = malloc(cells * sizeof *e), *h = malloc(cells * sizeof *h);
    for (size_t k = 0; k < NTRAJ; k++) {
        ref_traj(&rc->g, rc->dem, &rc->t[k], hit, e, h);
        dense_check(&rc->g, &rc->t[k], hit, e);
        for (size_t c = 0; c < cells; c++) {
            r->pass[c] += hit[c];
            r->e[c * NTRAJ + k] = e[c], r->h[c * NTRAJ + k] = h[c];
        }
        double fi = floor((rc->t[k].end[0] - rc->g.x0) / rc->g.c), fj = floor((rc->t[k].end[1] - rc->g.y0) / rc->g.c);
        if (rc->t[k].stopped && fi >= 0 && fj >= 0 && fi < (double)rc->g.nx && fj < (double)rc->g.ny)
            r->dep[(size_t)fj * rc->g.nx + (size_t)fi]++;
    }
    free(hit), free(e), free(h);
}

static void reference_free(reference *r) { free(r->e), free(r->h), free(r->pass), free(r->dep); }

/* One statistic (energy or height) of one cell against the reference. */
static void check_cell_stat(const terrain_band *b, size_t nb, const char *what, size_t c, const double *vals,
                            const rf_traj_spec *s, double *worst)
{
    char name[48];
    snprintf(name, sizeof name, "%s_max", what);
    float got_max = band_named(b, nb, name)->data[c];
    rf_traj_percentiles ex = rf_traj_percentiles_at(vals, NTRAJ, s->outputs.percentiles, s->outputs.n_percentiles);
    if (isnan(ex.max)) {
        assert_true(isnan(got_max));
        return;
    }
    assert_true(fabs(got_max - (float)ex.max) <= 0x1.0p-23 * fabs(ex.max));
    for (size_t l = 0; l < ex.n; l++) {
        char p[24];
        rf_traj_percentile_name(ex.level[l], p, sizeof p);
        snprintf(name, sizeof name, "%s_%s", what, p);
        double got = band_named(b, nb, name)->data[c], want = ex.value[l];
        /* the stated bound, the floor, and float32 output */
        double tol = TERRAIN_HAZARD_REL_ERROR * fabs(want) + TERRAIN_HAZARD_FLOOR + 1e-6 * fabs(want);
        if (!(fabs(got - want) <= tol))
            fail_msg("cell %zu %s: %.9g against %.9g", c, name, got, want);
        if (want > 1e-3)
            *worst = fmax(*worst, fabs(got - want) / want);
    }
}

static void check_against_reference(run_case *rc, const reference *r, const terrain_band *b, size_t nb)
{
    size_t cells = rc->g.nx * rc->g.ny, touched = 0, deposits = 0;
    double worst_e = 0, worst_h = 0;
    for (size_t c = 0; c < cells; c++) {
        assert_true(band_named(b, nb, "passages")->data[c] == (float)r->pass[c]);
        assert_true(band_named(b, nb, "reach_probability")->data[c] == (float)(r->pass[c] / NTRAJ));
        assert_true(band_named(b, nb, "deposits")->data[c] == (float)r->dep[c]);
        check_cell_stat(b, nb, "energy", c, r->e + c * NTRAJ, &rc->s, &worst_e);
        check_cell_stat(b, nb, "height", c, r->h + c * NTRAJ, &rc->s, &worst_h);
        touched += r->pass[c] > 0, deposits += (size_t)r->dep[c];
    }
    /* the run exercised what it checks */
    assert_true(touched > cells / 2 && deposits > NTRAJ / 5);
    assert_true(worst_e > 1e-4 && worst_e <= TERRAIN_HAZARD_REL_ERROR);
    printf("cells %zu (touched %zu), worst relative error of a percentile: energy %.4f, height %.4f\n", cells,
           touched, worst_e, worst_h);
}

static void test_random_against_brute_force(double cell)
{
    run_case rc;
    run_case_make(&rc, cell, 42 + (uint64_t)(cell * 10));
    rf_terrain_hazard *h = terrain_hazard_create(&rc.s, rc.dem);
    assert_non_null(h);
    check_grid(&rc, h, cell);
    for (size_t k = 0; k < NTRAJ; k++)
        feed(h, rc.dem, &rc.t[k]);
    reference r;
    reference_make(&rc, &r);
    terrain_band *b;
    size_t nb;
    rf_error err;
    assert_int_equal(terrain_hazard_bands(h, &rc.s, NTRAJ, &b, &nb, &err), RF_OK);
    assert_int_equal(nb, 3 + 2 * 5);
    check_against_reference(&rc, &r, b, nb);
    terrain_bands_free(b, nb);
    reference_free(&r);
    terrain_hazard_free(h);
    run_case_free(&rc);
}

static void test_random_dem_cells(void **state)
{
    (void)state;
    test_random_against_brute_force(0); /* the DEM's cells: 12 x 9 */
}

static void test_random_coarse_cells(void **state)
{
    (void)state;
    test_random_against_brute_force(3.0); /* 8 x 6, not aligned with the DEM's cells */
}

static void test_random_fine_cells(void **state)
{
    (void)state;
    test_random_against_brute_force(0.7); /* 35 x 26, past the DEM's north and east edges */
}

/* ---- merging ---- */

static void bands_of(const rf_terrain_hazard *h, const rf_traj_spec *s, terrain_band **b, size_t *nb)
{
    rf_error err;
    assert_int_equal(terrain_hazard_bands(h, s, NTRAJ, b, nb, &err), RF_OK);
}

static void assert_same_bands(const terrain_band *a, const terrain_band *b, size_t n, size_t cells)
{
    for (size_t k = 0; k < n; k++) {
        assert_string_equal(a[k].name, b[k].name);
        assert_memory_equal(a[k].data, b[k].data, cells * sizeof(float));
    }
}

/* Trajectory k goes to accumulator part(k, parts). */
static size_t part_rr(size_t k, size_t parts) { return k % parts; }
static size_t part_block(size_t k, size_t parts) { return k * parts / NTRAJ; }

static void test_merge_deterministic(void **state)
{
    (void)state;
    run_case rc;
    run_case_make(&rc, 1.5, 7);
    rf_terrain_hazard *one = terrain_hazard_create(&rc.s, rc.dem);
    for (size_t k = 0; k < NTRAJ; k++)
        feed(one, rc.dem, &rc.t[k]);
    terrain_band *ref;
    size_t nb;
    bands_of(one, &rc.s, &ref, &nb);
    terrain_hazard_grid(one, &rc.g.nx, &rc.g.ny, &rc.g.x0, &rc.g.y0, &rc.g.c);
    size_t cells = rc.g.nx * rc.g.ny;
    /* orders[parts][order]: the sequence merged into the first listed */
    static const size_t orders[][3] = {{0, 1, 9}, {1, 0, 9}, {0, 1, 2}, {2, 1, 0}, {1, 2, 0}};
    static const size_t parts_of[] = {2, 2, 3, 3, 3};
    size_t (*split[2])(size_t, size_t) = {part_rr, part_block};
    for (size_t o = 0; o < 5; o++)
        for (int sp = 0; sp < 2; sp++) {
            size_t parts = parts_of[o];
            rf_terrain_hazard *acc[3];
            for (size_t p = 0; p < parts; p++)
                acc[p] = terrain_hazard_create(&rc.s, rc.dem);
            for (size_t k = 0; k < NTRAJ; k++)
                feed(acc[split[sp](k, parts)], rc.dem, &rc.t[k]);
            for (size_t p = 1; p < parts; p++)
                terrain_hazard_merge(acc[orders[o][0]], acc[orders[o][p]]);
            terrain_band *b;
            size_t n;
            bands_of(acc[orders[o][0]], &rc.s, &b, &n);
            assert_int_equal(n, nb);
            assert_same_bands(ref, b, n, cells);
            terrain_bands_free(b, n);
            for (size_t p = 0; p < parts; p++)
                terrain_hazard_free(acc[p]);
        }
    /* a tree: (a <- b) and (c <- d) then (c <- a) */
    rf_terrain_hazard *acc[4];
    for (size_t p = 0; p < 4; p++)
        acc[p] = terrain_hazard_create(&rc.s, rc.dem);
    for (size_t k = 0; k < NTRAJ; k++)
        feed(acc[(k * 7) % 4], rc.dem, &rc.t[k]);
    terrain_hazard_merge(acc[0], acc[1]);
    terrain_hazard_merge(acc[2], acc[3]);
    terrain_hazard_merge(acc[2], acc[0]);
    terrain_band *b;
    size_t n;
    bands_of(acc[2], &rc.s, &b, &n);
    assert_same_bands(ref, b, n, cells);
    terrain_bands_free(b, n);
    for (size_t p = 0; p < 4; p++)
        terrain_hazard_free(acc[p]);
    terrain_bands_free(ref, nb);
    terrain_hazard_free(one);
    run_case_free(&rc);
}

/* Ranks: three accumulators packed to words and merged (as MPI would carry
 * them) into an empty one, in two orders, against one accumulator of all;
 * a packed accumulator of another grid is refused. */
static void test_packed_merge(void **state)
{
    (void)state;
    run_case rc;
    run_case_make(&rc, 2.5, 5);
    rf_terrain_hazard *one = terrain_hazard_create(&rc.s, rc.dem), *part[3];
    for (size_t p = 0; p < 3; p++)
        part[p] = terrain_hazard_create(&rc.s, rc.dem);
    for (size_t k = 0; k < NTRAJ; k++) {
        feed(one, rc.dem, &rc.t[k]);
        feed(part[part_block(k, 3)], rc.dem, &rc.t[k]);
    }
    uint64_t *buf[3];
    size_t words[3];
    rf_error err;
    for (size_t p = 0; p < 3; p++)
        assert_int_equal(terrain_hazard_pack(part[p], &buf[p], &words[p], &err), RF_OK);
    terrain_band *ref, *b;
    size_t nb, n;
    bands_of(one, &rc.s, &ref, &nb);
    terrain_hazard_grid(one, &rc.g.nx, &rc.g.ny, &rc.g.x0, &rc.g.y0, &rc.g.c);
    static const size_t order[2][3] = {{0, 1, 2}, {2, 0, 1}};
    for (int o = 0; o < 2; o++) {
        rf_terrain_hazard *root = terrain_hazard_create(&rc.s, rc.dem);
        for (size_t p = 0; p < 3; p++)
            assert_int_equal(terrain_hazard_merge_packed(root, buf[order[o][p]], words[order[o][p]], &err), RF_OK);
        bands_of(root, &rc.s, &b, &n);
        assert_int_equal(n, nb);
        assert_same_bands(ref, b, n, rc.g.nx * rc.g.ny);
        terrain_bands_free(b, n);
        terrain_hazard_free(root);
    }
    rf_terrain_def d2 = rc.d;
    rf_traj_spec s2 = rc.s;
    d2.raster_cell = 2.0, s2.terrain = &d2;
    rf_terrain_hazard *other = terrain_hazard_create(&s2, rc.dem);
    assert_int_equal(terrain_hazard_merge_packed(other, buf[0], words[0], &err), RF_EINVAL);
    assert_int_equal(terrain_hazard_merge_packed(other, buf[0], 3, &err), RF_EINVAL);
    terrain_hazard_free(other);
    other = terrain_hazard_create(&rc.s, rc.dem);
    assert_int_equal(terrain_hazard_merge_packed(other, buf[0], words[0] - 1, &err), RF_EINVAL); /* cut */
    terrain_hazard_free(other);
    terrain_bands_free(ref, nb);
    for (size_t p = 0; p < 3; p++)
        free(buf[p]), terrain_hazard_free(part[p]);
    terrain_hazard_free(one);
    run_case_free(&rc);
}

/* ---- memory ---- */

static void test_memory_bounded(void **state)
{
    (void)state;
    run_case rc;
    run_case_make(&rc, 1.0, 11);
    rf_terrain_hazard *h = terrain_hazard_create(&rc.s, rc.dem);
    size_t n1 = 1000, n2 = 100000;
    for (size_t k = 0; k < n1; k++)
        feed(h, rc.dem, &rc.t[k]);
    size_t b1 = terrain_hazard_bytes(h);
    terrain_band *b;
    size_t nb;
    rf_error err;
    assert_int_equal(terrain_hazard_bands(h, &rc.s, n1, &b, &nb, &err), RF_OK);
    double pass1 = 0;
    for (size_t c = 0; c < 24 * 18; c++)
        pass1 += band_named(b, nb, "passages")->data[c];
    terrain_bands_free(b, nb);
    for (size_t k = n1; k < n2; k++)
        feed(h, rc.dem, &rc.t[k % n1]); /* the same cells and values again */
    size_t b2 = terrain_hazard_bytes(h);
    assert_int_equal(b1, b2);
    assert_int_equal(terrain_hazard_bands(h, &rc.s, n2, &b, &nb, &err), RF_OK);
    /* the counts did grow: 100 times those after 1000 */
    double pass = 0;
    for (size_t c = 0; c < 24 * 18; c++)
        pass += band_named(b, nb, "passages")->data[c];
    printf("accumulator: %zu bytes after %zu and after %zu trajectories, %.0f passages\n", b1, n1, n2, pass);
    assert_true(pass1 > 1000 && pass == 100 * pass1);
    terrain_bands_free(b, nb);
    terrain_hazard_free(h);
    run_case_free(&rc);
}

/* The buffered histogram updates (flushed when 262 144 are pending, in the
 * middle of a trajectory's end as well): one accumulator fed the trajectories
 * R times, with several flushes on the way, against R accumulators fed them
 * once each (flushed only when read) and merged one by one into another:
 * the same bands, to the byte. */
static void test_pending_flushes(void **state)
{
    (void)state;
    run_case rc;
    run_case_make(&rc, 1.0, 5);
    rf_terrain_hazard *one = terrain_hazard_create(&rc.s, rc.dem), *merged = terrain_hazard_create(&rc.s, rc.dem);
    for (size_t k = 0; k < NTRAJ; k++)
        feed(one, rc.dem, &rc.t[k]);
    terrain_band *b;
    size_t nb;
    bands_of(one, &rc.s, &b, &nb);
    terrain_hazard_grid(one, &rc.g.nx, &rc.g.ny, &rc.g.x0, &rc.g.y0, &rc.g.c);
    size_t cells = rc.g.nx * rc.g.ny;
    double per_round = 0; /* histogram updates per round: two per passage (energy, height) */
    for (size_t c = 0; c < cells; c++)
        per_round += 2 * band_named(b, nb, "passages")->data[c];
    terrain_bands_free(b, nb);
    size_t rounds = (size_t)(3 * 262144 / per_round) + 2;
    printf("%.0f updates per round, %zu rounds\n", per_round, rounds);
    assert_true(rounds >= 2 && (double)rounds * per_round > 3 * 262144);
    for (size_t r = 0; r < rounds; r++) {
        if (r > 0)
            for (size_t k = 0; k < NTRAJ; k++)
                feed(one, rc.dem, &rc.t[k]);
        rf_terrain_hazard *part = terrain_hazard_create(&rc.s, rc.dem);
        for (size_t k = 0; k < NTRAJ; k++)
            feed(part, rc.dem, &rc.t[k]);
        terrain_hazard_merge(merged, part);
        terrain_hazard_free(part);
    }
    terrain_band *b1, *b2;
    size_t n1, n2;
    bands_of(one, &rc.s, &b1, &n1);
    bands_of(merged, &rc.s, &b2, &n2);
    assert_int_equal(n1, n2);
    assert_same_bands(b1, b2, n1, cells);
    terrain_bands_free(b1, n1);
    terrain_bands_free(b2, n2);
    terrain_hazard_free(one);
    terrain_hazard_free(merged);
    run_case_free(&rc);
}

/* ---- the walk, exactly ---- */

/* One straight flight on a flat 10 x 10 m DEM of 1 m cells, from (xa, ya)
 * to (xb, yb) in 1 s; the cells it passes, as a list of (i, j). */
static void walk_case(double xa, double ya, double xb, double yb, const int *want, size_t n_want)
{
    double z[121] = {0};
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(11, 11, 0, 0, 1, 1, z, &dem, &err), RF_OK);
    rf_traj_spec s;
    rf_terrain_def d;
    spec_make(&s, &d, 0, RF_TERRAIN_PASSAGES);
    rf_terrain_hazard *h = terrain_hazard_create(&s, dem);
    terrain_piece pc = {0, 1, {xa, ya, 1}, {xb - xa, yb - ya, 0}, {0, 0, -G}, 0, 0};
    feed(h, dem, &(traj){1, {pc}, 1, 0, {0}});
    terrain_band *b;
    size_t nb;
    assert_int_equal(terrain_hazard_bands(h, &s, 1, &b, &nb, &err), RF_OK);
    assert_int_equal(nb, 1);
    float expect[100] = {0};
    for (size_t k = 0; k < n_want; k++)
        expect[want[2 * k + 1] * 10 + want[2 * k]] = 1;
    for (int c = 0; c < 100; c++)
        if (b[0].data[c] != expect[c])
            fail_msg("(%g, %g) -> (%g, %g): cell (%d, %d) has %g, want %g", xa, ya, xb, yb, c % 10, c / 10,
                     b[0].data[c], expect[c]);
    terrain_bands_free(b, nb);
    terrain_hazard_free(h);
    rf_terrain_free(dem);
}

static void test_walk_corners_and_lines(void **state)
{
    (void)state;
    /* through the corners (1, 1), (2, 2): only the diagonal cells */
    walk_case(0.5, 0.5, 2.5, 2.5, (int[]){0, 0, 1, 1, 2, 2}, 3);
    walk_case(2.5, 2.5, 0.5, 0.5, (int[]){0, 0, 1, 1, 2, 2}, 3);
    walk_case(0.5, 2.5, 2.5, 0.5, (int[]){0, 2, 1, 1, 2, 0}, 3);
    walk_case(2.5, 0.5, 0.5, 2.5, (int[]){0, 2, 1, 1, 2, 0}, 3);
    /* along the line y = 1, either way: the cells north of it */
    walk_case(0.5, 1, 2.5, 1, (int[]){0, 1, 1, 1, 2, 1}, 3);
    walk_case(2.5, 1, 0.5, 1, (int[]){0, 1, 1, 1, 2, 1}, 3);
    walk_case(3, 0.5, 3, 2.5, (int[]){3, 0, 3, 1, 3, 2}, 3);
    /* starting on a line going west, ending on a line going east: not the cell beyond */
    walk_case(2, 0.5, 0.5, 0.5, (int[]){0, 0, 1, 0}, 2);
    walk_case(0.5, 0.5, 2, 0.5, (int[]){0, 0, 1, 0}, 2);
    /* a shallow line: (0.2, 0.1) -> (3.8, 1.3): y = 1 at x = 2.9 */
    walk_case(0.2, 0.1, 3.8, 1.3, (int[]){0, 0, 1, 0, 2, 0, 2, 1, 3, 1}, 5);
    /* partly off the grid: from (-3, 5.5) to (1.5, 5.5), and wholly off */
    walk_case(-3, 5.5, 1.5, 5.5, (int[]){0, 5, 1, 5}, 2);
    walk_case(-3, 5.5, -1, 7.5, NULL, 0);
    /* a vertical drop (no map motion): its cell */
    walk_case(4.5, 4.5, 4.5, 4.5, (int[]){4, 4}, 1);
}

/* ---- closed forms ---- */

/* A throw straight up from 2 m over flat ground at 5 m/s: apex height
 * 2 + 25 / (2 g) in the cell, energy max at the start or the end (the end:
 * 1.2 s later, speed |5 - 1.2 g|); then across cells at 3 m/s east: the
 * cell of the apex (x = 3 vz / g from 0.5) has the apex height. */
static void test_throw_closed_form(void **state)
{
    (void)state;
    double z[121] = {0};
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(11, 11, 0, 0, 1, 1, z, &dem, &err), RF_OK);
    rf_traj_spec s;
    rf_terrain_def d;
    spec_make(&s, &d, 0, RF_TERRAIN_ENERGY | RF_TERRAIN_HEIGHT);
    rf_terrain_hazard *h = terrain_hazard_create(&s, dem);
    double m = 10, T = 1.2, vz = 5;
    terrain_piece up = {0, T, {5.5, 5.5, 2}, {0, 0, vz}, {0, 0, -G}, 7, 0};
    feed(h, dem, &(traj){1, {up}, m, 1, {5.5, 5.5, 0}});
    terrain_piece across = {0, T, {0.5, 1.5, 2}, {3, 0, vz}, {0, 0, -G}, 0, 0};
    feed(h, dem, &(traj){1, {across}, m, 0, {0}});
    terrain_band *b;
    size_t nb;
    assert_int_equal(terrain_hazard_bands(h, &s, 2, &b, &nb, &err), RF_OK);
    const float *emax = band_named(b, nb, "energy_max")->data, *hmax = band_named(b, nb, "height_max")->data;
    double apex = 2 + vz * vz / (2 * G), vend = vz - G * T;
    const double f32 = 0x1.0p-23; /* the bands are float32 */
    assert_true(fabs(hmax[55] - apex) <= f32 * apex);
    double e_end = 0.5 * m * vend * vend + 7;
    assert_true(vend * vend > vz * vz && fabs(emax[55] - e_end) <= f32 * e_end);
    double xa = 0.5 + 3 * vz / G; /* 2.029: cell (2, 1) */
    assert_true(fabs(hmax[1 * 10 + (size_t)xa] - apex) <= f32 * apex);
    /* cell (1, 1) is left at x = 2 (tau = 0.5): the height there */
    double tau = 0.5;
    assert_true(fabs(hmax[11] - (2 + vz * tau - G * tau * tau / 2)) <= 1e-6);
    /* cells not passed: NaN; the cell (0, 1) entered at the start */
    assert_true(isnan(emax[0]) && isnan(hmax[99]) && !isnan(hmax[10]));
    terrain_bands_free(b, nb);
    terrain_hazard_free(h);
    rf_terrain_free(dem);
}

/* 1000 equal values just above the lower edge of the bin [1024, 1040) that
 * starts an octave (the widest bin relative to its values) and one just
 * below its upper edge (the max, so the estimates are not clamped to it):
 * the worst case of the within-bin interpolation; estimates at
 * 1024 + 16 (k + 1/2) / 1001; the p99 error is close to (not above) the
 * bound, the max exact. */
static void test_bin_error_near_bound(void **state)
{
    (void)state;
    double z[4] = {0};
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(2, 2, 0, 0, 1, 1, z, &dem, &err), RF_OK);
    rf_traj_spec s;
    rf_terrain_def d;
    spec_make(&s, &d, 0, RF_TERRAIN_ENERGY);
    s.outputs.n_percentiles = 2, s.outputs.percentiles[0] = 50, s.outputs.percentiles[1] = 99;
    rf_terrain_hazard *h = terrain_hazard_create(&s, dem);
    /* a bin edge: FLOOR 10^(k / 128) with k = 128 * 9 + 5 (1e3 J and a bit) */
    double v = 1024 * (1 + 1e-9), top = 1040 * (1 - 1e-9);
    terrain_piece still = {0, 0, {0.5, 0.5, 0}, {0, 0, 0}, {0, 0, 0}, v, 1};
    for (int k = 0; k < 1000; k++)
        feed(h, dem, &(traj){1, {still}, 1, 0, {0}});
    still.e_rot = top;
    feed(h, dem, &(traj){1, {still}, 1, 0, {0}});
    terrain_band *b;
    size_t nb;
    assert_int_equal(terrain_hazard_bands(h, &s, 1001, &b, &nb, &err), RF_OK);
    double e50 = band_named(b, nb, "energy_p50")->data[0], e99 = band_named(b, nb, "energy_p99")->data[0];
    assert_true(band_named(b, nb, "energy_max")->data[0] == (float)top);
    assert_true(fabs(e50 - (1024 + 16 * 500.5 / 1001)) < 1e-4);
    assert_true(fabs(e99 - (1024 + 16 * 990.5 / 1001)) < 1e-4);
    assert_true(e99 / v - 1 > 0.015 && e99 / v - 1 <= TERRAIN_HAZARD_REL_ERROR);
    terrain_bands_free(b, nb);
    terrain_hazard_free(h);
    rf_terrain_free(dem);
}

/* ---- grid and bands ---- */

static void test_grid_and_band_names(void **state)
{
    (void)state;
    double z[11 * 8] = {0};
    rf_terrain *dem;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(11, 8, -3, 4, 1, 1, z, &dem, &err), RF_OK);
    rf_traj_spec s;
    rf_terrain_def d;
    spec_make(&s, &d, 2.5, ALL_STATS);
    s.outputs.n_percentiles = 2, s.outputs.percentiles[0] = 95, s.outputs.percentiles[1] = 99.9;
    rf_terrain_hazard *h = terrain_hazard_create(&s, dem);
    size_t nx, ny;
    double x0, y0, c;
    terrain_hazard_grid(h, &nx, &ny, &x0, &y0, &c);
    assert_true(nx == 4 && ny == 3 && x0 == -3 && y0 == 4 && c == 2.5); /* 10 x 7 m */
    terrain_band *b;
    size_t nb;
    assert_int_equal(terrain_hazard_bands(h, &s, 0, &b, &nb, &err), RF_OK);
    const char *names[] = {"passages",   "reach_probability", "deposits",   "energy_max",   "energy_p95",
                           "energy_p99_9", "height_max",      "height_p95", "height_p99_9"};
    const char *units[] = {"", "", "", "J", "J", "J", "m", "m", "m"};
    assert_int_equal(nb, 9);
    for (size_t k = 0; k < nb; k++) {
        assert_string_equal(b[k].name, names[k]);
        assert_string_equal(b[k].unit, units[k]);
        assert_true(k < 3 ? b[k].data[5] == 0 : isnan(b[k].data[5])); /* nothing passed */
    }
    terrain_bands_free(b, nb);
    terrain_hazard_free(h);
    /* some statistics, default percentiles */
    spec_make(&s, &d, 0, RF_TERRAIN_DEPOSITS | RF_TERRAIN_HEIGHT);
    h = terrain_hazard_create(&s, dem);
    terrain_hazard_grid(h, &nx, &ny, &x0, &y0, &c);
    assert_true(nx == 10 && ny == 7 && c == 1);
    assert_int_equal(terrain_hazard_bands(h, &s, 0, &b, &nb, &err), RF_OK);
    const char *names2[] = {"deposits", "height_max", "height_p50", "height_p95", "height_p99"};
    assert_int_equal(nb, 5);
    for (size_t k = 0; k < nb; k++)
        assert_string_equal(b[k].name, names2[k]);
    terrain_bands_free(b, nb);
    terrain_hazard_free(h);
    rf_terrain_free(dem);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_and_band_names),    cmocka_unit_test(test_walk_corners_and_lines),
        cmocka_unit_test(test_throw_closed_form),      cmocka_unit_test(test_bin_error_near_bound),
        cmocka_unit_test(test_random_dem_cells),       cmocka_unit_test(test_random_coarse_cells),
        cmocka_unit_test(test_random_fine_cells),      cmocka_unit_test(test_merge_deterministic),
        cmocka_unit_test(test_packed_merge),           cmocka_unit_test(test_memory_bounded),
        cmocka_unit_test(test_pending_flushes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
