/* test_fuzzy_raster.c - fuzzy hazard rasters (docs/fuzzy-hazard.md) on a
 * synthetic valley whose cell statistic is a closed form of the fuzzy inputs
 * p0 (release probability), L (decay length [m]) and c (a shape parameter):
 * a real TM (general form, m = 2) runs a model that writes the valley's
 * raster through the trajectory model's raster sink into the per-point
 * store; the per-cell bounds and the blame map are checked against the
 * closed form, then resume (an interrupted study reuses the stored rasters
 * and gives the same bytes), a deleted raster rebuilt, and the working memory
 * of a 500 x 500 raster with 27 points held to the stated figure.
 *
 * Valley: NX x NY cells of CELL m, d = distance of the row from the axis row.
 *   columns  0- 9  W: f = p0 (1 + col/100)                 p0 only, increasing
 *   columns 10-19  M: f = exp(-d/L)                         L only (constant on the axis)
 *   columns 20-29  E: f = exp(-d/50) ((c - 10)/4)^2         c only, NOT monotonic (min 0 at the peak c = 10)
 *   columns 30-39  X: f = p0 exp(-d/L)                      p0 and L */
#define _GNU_SOURCE
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "rockfuzz/analysis.h"
#include "rockfuzz/fuzzy.h"
#include "rockfuzz/runner.h"
#include "rockfuzz/store.h"
#include "rockfuzz/study.h"
#include "rockfuzz/tm.h"
#include "study/fuzzy_raster.h"
#include "test_util.h"

#define NX 40
#define NY 31
#define AXIS 15
#define CELL 15.0
#define M 2

/* ---- the valley model: writes its raster through the sink, returns its mean */

typedef struct {
    int calls, fail_at; /* fail the evaluation numbered fail_at (1-based), 0 = never */
    size_t nx, ny;      /* raster size (the memory test uses a large one) */
    traj_raster_sink sink; /* where an evaluation hands its rasters, as a terrain trajectory model does */
    void *sink_ctx;
} valley_ctx;

static double valley_cell(const double *x, size_t col, size_t row)
{
    double p0 = x[0], L = x[1], c = x[2], d = fabs((double)row - AXIS) * CELL, q = (c - 10) / 4;
    switch (col / 10 % 4) {
    case 0: return p0 * (1 + (double)col / 100);
    case 1: return exp(-d / L);
    case 2: return exp(-d / 50) * q * q;
    default: return p0 * exp(-d / L);
    }
}

static rf_status valley_eval(void *vctx, const double *x, double *y, rf_error *err)
{
    valley_ctx *v = vctx;
    if (++v->calls == v->fail_at)
        return rf_fail(err, RF_EMODEL, "interrupted on purpose");
    size_t cells = v->nx * v->ny;
    terrain_band b[2] = {{"reach_probability", "", malloc(cells * sizeof(float))},
                         {"energy_p95", "kJ", malloc(cells * sizeof(float))}};
    double sum = 0;
    for (size_t r = 0; r < v->ny; r++)
        for (size_t col = 0; col < v->nx; col++) {
            double f = valley_cell(x, col, r);
            b[0].data[r * v->nx + col] = (float)f;
            b[1].data[r * v->nx + col] = (float)(1000 * f);
            sum += f;
        }
    traj_raster_grid g = {v->nx, v->ny, 600000.0, 5100000.0, CELL, "LOCAL_CS[\"valley\"]"};
    rf_status st = v->sink ? v->sink(v->sink_ctx, x, 3, b, 2, &g, err) : RF_OK;
    free(b[0].data);
    free(b[1].data);
    y[0] = sum / (double)cells;
    return st;
}

static rf_model valley_model(valley_ctx *v)
{
    rf_model m;
    memset(&m, 0, sizeof m);
    const char *names[1] = {"mean"};
    rf_model_init_outputs(&m, 1, names, NULL, NULL);
    rf_model_set_identity(&m, "valley", NULL);
    m.n_inputs = 3;
    m.eval = valley_eval;
    m.ctx = v;
    m.threads_per_eval = 1;
    return m;
}

static void inputs(rf_fuzzy *in)
{
    assert_int_equal(rf_fuzzy_tfn(&in[0], 0.6, 0.3, 0.3, NULL), RF_OK);
    assert_int_equal(rf_fuzzy_tfn(&in[1], 50, 15, 15, NULL), RF_OK);
    /* asymmetric: Hanss's gain is a secant over the cut, blind to an
     * influence symmetric about the cut's centre (docs/fuzzy-hazard.md) */
    assert_int_equal(rf_fuzzy_tfn(&in[2], 10, 2, 6, NULL), RF_OK);
}

/* One study: TM through the runner (and a result store in dir), rasters
 * into dir/rasters, then the fuzzy rasters of both bands. */
typedef struct {
    rf_status st;
    rf_tm_result res;
    terrain_band *bands;
    size_t n_bands, resumed, evaluated;
} study_out;

static const char *const chosen[2] = {"reach_probability", "energy_p95"}, *const units[2] = {"", "kJ"};

static int tolerate_mode; /* run_study with tolerate_failures */

static study_out run_study(const char *dir, valley_ctx *v, int jobs)
{
    study_out o = {0};
    rf_fuzzy in[3];
    inputs(in);
    rf_model m = valley_model(v);
    char path[512], rdir[512];
    snprintf(path, sizeof path, "%s/%s", dir, RF_STORE_FILE);
    snprintf(rdir, sizeof rdir, "%s/rasters", dir);
    const char *in_names[3] = {"p0", "L", "c"}, *out_names[1] = {"mean"};
    rf_store_key key = {"valley", "test", 3, 1, in_names, out_names};
    rf_store *store = NULL;
    fr_store *rs = NULL;
    rf_error err = {0};
    assert_int_equal(rf_store_open(path, &key, 0, &store, &err), RF_OK);
    assert_int_equal(fr_store_open(rdir, &rs, &err), RF_OK);
    v->sink = fr_store_put, v->sink_ctx = rs;
    rf_runner r;
    rf_runner_init(&r);
    r.jobs = jobs;
    r.store = store;
    r.tolerate_failures = tolerate_mode;
    rf_evaluator ev = rf_runner_evaluator(&r);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = RF_TM_GENERAL;
    opt.levels = M;
    opt.left_right = 0;
    opt.evaluator = &ev;
    opt.tolerate_failures = tolerate_mode;
    o.st = rf_tm_run(in, 3, &m, &opt, &o.res, &err);
    o.resumed = r.resumed;
    o.evaluated = r.evaluated;
    if (o.st == RF_OK) {
        fr_store_reader rd;
        assert_int_equal(fr_store_reader_init(&rd, rs, &o.res, 3, NULL, NULL, chosen, 2, &err), RF_OK);
        size_t nx = rd.grid.nx, ny = rd.grid.ny;
        assert_int_equal(nx, v->nx);
        assert_int_equal(ny, v->ny);
        assert_true(rd.grid.x0 == 600000.0 && rd.grid.y0 == 5100000.0 && rd.grid.cell == CELL);
        assert_string_equal(rd.grid.crs_wkt, "LOCAL_CS[\"valley\"]");
        size_t rebuilt = 9;
        assert_int_equal(fr_store_rebuild(&rd, &m, &rebuilt, &err), RF_OK);
        assert_int_equal(rebuilt, 0);
        assert_string_equal(rd.units[1], "kJ"); /* the units the rasters were written with */
        fr_source src = {nx, ny, 2, chosen, rd.units, fr_store_read_point, &rd, 4000 * 8}; /* blocks of a few rows */
        if (fr_retransform(&o.res, &src, &o.bands, &o.n_bands, &err))
            fail_msg("fr_retransform: %s", err.msg);
    }
    fr_store_close(rs);
    rf_store_close(store);
    m.ctx = NULL;
    rf_model_free(&m);
    for (int i = 0; i < 3; i++)
        rf_fuzzy_free(&in[i]);
    return o;
}

static void study_free(study_out *o)
{
    terrain_bands_free(o->bands, o->n_bands);
    rf_tm_result_free(&o->res);
}

static char *temp_dir(void)
{
    char *d = strdup("/tmp/rockfuzz-test-fuzzy-raster-XXXXXX");
    assert_non_null(mkdtemp(d));
    return d;
}

static void remove_tree(const char *dir)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

/* ---- (b) the closed form */

/* Cut of a symmetric triangle (peak, spread) at level a. */
static void cut(double peak, double left, double right, double a, double *lo, double *hi)
{
    *lo = peak - left * (1 - a);
    *hi = peak + right * (1 - a);
}

/* Closed-form alpha-cut of cell (col, row) at level a. */
static void closed_cut(size_t col, size_t row, double a, double *lo, double *hi)
{
    double p[2], L[2], c[2], d = fabs((double)row - AXIS) * CELL;
    cut(0.6, 0.3, 0.3, a, &p[0], &p[1]);
    cut(50, 15, 15, a, &L[0], &L[1]);
    cut(10, 2, 6, a, &c[0], &c[1]);
    switch (col / 10) {
    case 0: *lo = p[0] * (1 + (double)col / 100), *hi = p[1] * (1 + (double)col / 100); break;
    case 1: *lo = exp(-d / L[0]), *hi = exp(-d / L[1]); break;
    case 2: /* the minimum at c = 10 inside every cut, the maximum at an end */
        *lo = 0, *hi = exp(-d / 50) * fmax(((c[0] - 10) / 4) * ((c[0] - 10) / 4), ((c[1] - 10) / 4) * ((c[1] - 10) / 4));
        break;
    default: *lo = p[0] * exp(-d / L[0]), *hi = p[1] * exp(-d / L[1]); break;
    }
}

/* Region X, Hanss's measures by hand: with m = 2 only level 1 is weighted
 * and its general-form grid is the 2 x 2 x 2 corners, so kappa_p0 = the mean
 * over L of (p0hi - p0lo) exp(-d/L) and kappa_L = mean p0 x (exp(-d/Lhi) -
 * exp(-d/Llo)); rho_L = kappa_L / (kappa_p0 + kappa_L). */
static double rho_L_closed(size_t row)
{
    double d = fabs((double)row - AXIS) * CELL, plo, phi, Llo, Lhi;
    cut(0.6, 0.3, 0.3, 0.5, &plo, &phi);
    cut(50, 15, 15, 0.5, &Llo, &Lhi);
    double kp = (phi - plo) * 0.5 * (exp(-d / Llo) + exp(-d / Lhi)), kL = 0.5 * (plo + phi) * (exp(-d / Lhi) - exp(-d / Llo));
    return kL / (kp + kL);
}

static const terrain_band *band_named(const study_out *o, const char *name)
{
    for (size_t k = 0; k < o->n_bands; k++)
        if (!strcmp(o->bands[k].name, name))
            return &o->bands[k];
    fail_msg("no band %s", name);
    return NULL;
}

static void check_blame(const study_out *o, size_t col, size_t row)
{
    size_t at = row * NX + col;
    float who = band_named(o, "reach_probability_blame")->data[at];
    float rho = band_named(o, "reach_probability_blame_rho")->data[at];
    size_t region = col / 10;
    if (region == 1 && row == AXIS) { /* exp(0) = 1 at every point: no input has influence */
        assert_true(who == 0.0f && isnan(rho));
        return;
    }
    if (region < 3 || row == AXIS) { /* one input alone: rho = 1 exactly */
        assert_true(who == (float)(region == 3 ? 1 : region + 1));
        assert_true(rho == 1.0f);
        return;
    }
    double rl = rho_L_closed(row);
    assert_true(who == (rl > 0.5 ? 2.0f : 1.0f));
    assert_close(rho, rl > 0.5 ? rl : 1 - rl, 1e-6); /* float band */
}

static void test_valley_closed_form(void **state)
{
    (void)state;
    char *dir = temp_dir();
    valley_ctx v = {0, 0, NX, NY, NULL, NULL};
    study_out o = run_study(dir, &v, 2);
    assert_int_equal(o.st, RF_OK);
    assert_int_equal(o.n_bands, 2 * (2 * (M + 1) + 2));
    assert_string_equal(o.bands[0].name, "reach_probability_a0.00_lower");
    assert_string_equal(o.bands[3].name, "reach_probability_a0.50_upper");
    assert_string_equal(o.bands[8].name, "energy_p95_a0.00_lower");
    assert_string_equal(o.bands[9].unit, "kJ");
    size_t per = 2 * (M + 1) + 2, blame_x[2] = {0, 0};
    for (size_t row = 0; row < NY; row++)
        for (size_t col = 0; col < NX; col++) {
            for (size_t j = 0; j <= M; j++) {
                double lo, hi, a = (double)j / M;
                closed_cut(col, row, a, &lo, &hi);
                for (size_t b = 0; b < 2; b++) { /* the bands are float: the bound is the float of the closed form */
                    double s = b ? 1000 : 1;
                    const terrain_band *B = o.bands + b * per;
                    assert_close(B[2 * j].data[row * NX + col], (float)(s * lo), 1e-12);
                    assert_close(B[2 * j + 1].data[row * NX + col], (float)(s * hi), 1e-12);
                }
            }
            check_blame(&o, col, row);
            if (col / 10 == 3)
                blame_x[band_named(&o, "reach_probability_blame")->data[row * NX + col] == 2.0f]++;
        }
    assert_true(blame_x[0] > 0 && blame_x[1] > 0); /* both p0 and L are to blame somewhere in X */
    /* the non-monotonic region really is: its lower bound 0 is not at a corner */
    assert_true(band_named(&o, "reach_probability_a0.00_lower")->data[5 * NX + 25] == 0.0f);
    study_free(&o);
    remove_tree(dir);
    free(dir);
}

/* ---- (c) resume */

static size_t count_rasters(const char *dir)
{
    char rdir[512];
    snprintf(rdir, sizeof rdir, "%s/rasters", dir);
    DIR *d = opendir(rdir);
    size_t n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        n += strstr(e->d_name, ".f32") && !strstr(e->d_name, ".tmp");
    if (d)
        closedir(d);
    return n;
}

static void same_bands(const study_out *a, const study_out *b)
{
    assert_int_equal(a->n_bands, b->n_bands);
    for (size_t k = 0; k < a->n_bands; k++) {
        assert_string_equal(a->bands[k].name, b->bands[k].name);
        assert_memory_equal(a->bands[k].data, b->bands[k].data, NX * NY * sizeof(float));
    }
}

static void test_resume(void **state)
{
    (void)state;
    char *whole = temp_dir(), *cut_dir = temp_dir();
    valley_ctx v0 = {0, 0, NX, NY, NULL, NULL};
    study_out ref = run_study(whole, &v0, 1);
    assert_int_equal(ref.st, RF_OK);
    size_t np = rf_tm_point_count(&ref.res);
    assert_int_equal(count_rasters(whole), np);

    valley_ctx v1 = {0, 10, NX, NY, NULL, NULL}; /* one thread: the 9 points before the 10th are stored */
    study_out first = run_study(cut_dir, &v1, 1);
    assert_int_not_equal(first.st, RF_OK);
    assert_int_equal(count_rasters(cut_dir), 9);
    char rdir[512];
    snprintf(rdir, sizeof rdir, "%s/rasters", cut_dir);
    struct stat before[64];
    size_t nb = 0;
    char names[64][800];
    DIR *d = opendir(rdir);
    for (struct dirent *e; (e = readdir(d));)
        if (strstr(e->d_name, ".f32")) {
            snprintf(names[nb], sizeof names[nb], "%s/%s", rdir, e->d_name);
            assert_int_equal(stat(names[nb], &before[nb]), 0);
            nb++;
        }
    closedir(d);
    valley_ctx v2 = {0, 0, NX, NY, NULL, NULL};
    study_out second = run_study(cut_dir, &v2, 2);
    assert_int_equal(second.st, RF_OK);
    assert_int_equal(second.resumed, 9);
    assert_int_equal(v2.calls, (int)np - 9); /* the stored points were not evaluated again */
    for (size_t k = 0; k < nb; k++) { /* nor their rasters written again */
        struct stat now;
        assert_int_equal(stat(names[k], &now), 0);
        assert_true(now.st_ino == before[k].st_ino && now.st_mtim.tv_nsec == before[k].st_mtim.tv_nsec &&
                    now.st_mtim.tv_sec == before[k].st_mtim.tv_sec);
    }
    same_bands(&ref, &second);

    /* a stored point whose raster is gone: rebuilt by evaluating it again */
    assert_int_equal(remove(names[0]), 0);
    valley_ctx v3 = {0, 0, NX, NY, NULL, NULL};
    rf_model m = valley_model(&v3);
    fr_store *rs;
    fr_store_reader rd;
    size_t rebuilt = 0;
    assert_int_equal(fr_store_open(rdir, &rs, NULL), RF_OK);
    v3.sink = fr_store_put, v3.sink_ctx = rs;
    rf_error err = {0};
    assert_int_not_equal(fr_store_reader_init(&rd, rs, &second.res, 3, NULL, NULL, chosen, 2, &err) ||
                             fr_retransform(&second.res,
                                            &(fr_source){NX, NY, 2, chosen, NULL, fr_store_read_point, &rd, 0},
                                            &first.bands, &first.n_bands, &err),
                         RF_OK); /* missing: refused, named */
    assert_non_null(strstr(err.msg, "missing"));
    fr_store_reader_init(&rd, rs, &second.res, 3, NULL, NULL, chosen, 2, &err); /* point 0 may be the missing one */
    rd.nx = NX;
    assert_int_equal(fr_store_rebuild(&rd, &m, &rebuilt, &err), RF_OK);
    assert_int_equal(rebuilt, 1);
    assert_int_equal(v3.calls, 1);
    terrain_band *again = NULL;
    size_t n_again = 0;
    fr_source src = {NX, NY, 2, chosen, units, fr_store_read_point, &rd, 0};
    assert_int_equal(fr_store_reader_init(&rd, rs, &second.res, 3, NULL, NULL, chosen, 2, &err), RF_OK);
    assert_int_equal(fr_retransform(&second.res, &src, &again, &n_again, &err), RF_OK);
    study_out o3 = {RF_OK, {0}, again, n_again, 0, 0};
    same_bands(&ref, &o3);
    terrain_bands_free(again, n_again);
    m.ctx = NULL;
    rf_model_free(&m);
    fr_store_close(rs);

    study_free(&ref);
    study_free(&first);
    study_free(&second);
    remove_tree(whole);
    remove_tree(cut_dir);
    free(whole);
    free(cut_dir);
}


/* tolerate_failures: a failed point has no raster; it is not rebuilt and
 * is left out of every cell's bounds (level 0 = min/max over the others). */
static void test_failed_point(void **state)
{
    (void)state;
    char *dir = temp_dir();
    valley_ctx v = {0, 5, NX, NY, NULL, NULL};
    tolerate_mode = 1;
    study_out o = run_study(dir, &v, 1);
    tolerate_mode = 0;
    assert_int_equal(o.st, RF_OK);
    assert_int_equal(o.res.failed_points, 1);
    size_t np = rf_tm_point_count(&o.res), failed = 0;
    assert_int_equal(count_rasters(dir), np - 1);
    for (size_t cell = 0; cell < NX * NY; cell++) {
        double lo = INFINITY, hi = -INFINITY, x[3];
        for (size_t id = 0; id < np; id++) {
            if (rf_tm_point_failed(&o.res, id)) {
                failed += cell == 0;
                continue;
            }
            rf_tm_point_inputs(&o.res, id, x, NULL);
            double f = (float)valley_cell(x, cell % NX, cell / NX);
            lo = fmin(lo, f);
            hi = fmax(hi, f);
        }
        assert_true(o.bands[0].data[cell] == (float)lo && o.bands[1].data[cell] == (float)hi);
    }
    assert_int_equal(failed, 1);
    study_free(&o);
    remove_tree(dir);
    free(dir);
}

/* ---- (d) memory */

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_UNDEFINED__)
#define LIMIT_DATA 1
static size_t vm_data_bytes(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    size_t kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmData: %zu kB", &kb) == 1)
            break;
    if (f)
        fclose(f);
    return kb * 1024;
}
#endif

/* A reader that makes the valley's values at each point on the fly. */
typedef struct {
    const rf_tm_result *res;
    size_t nx;
} gen_reader;

static rf_status gen_read(void *ctx, size_t id, size_t b, size_t row0, size_t nrows, float *out, rf_error *err)
{
    const gen_reader *g = ctx;
    double x[3];
    (void)b;
    rf_status st = rf_tm_point_inputs(g->res, id, x, err);
    for (size_t r = 0; !st && r < nrows; r++)
        for (size_t col = 0; col < g->nx; col++)
            out[r * g->nx + col] = (float)valley_cell(x, col % 40, (row0 + r) % NY);
    return st;
}

static void test_memory_500(void **state)
{
    (void)state;
    rf_fuzzy in[3];
    inputs(in);
    valley_ctx v = {0, 0, 1, 1, NULL, NULL};
    rf_model m = valley_model(&v);
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = RF_TM_GENERAL;
    opt.levels = M;
    opt.left_right = 0;
    rf_tm_result res;
    assert_int_equal(rf_tm_run(in, 3, &m, &opt, &res, NULL), RF_OK);
    size_t np = rf_tm_point_count(&res);
    assert_int_equal(np, 36); /* 27 level-0 points, 8 level-1 corners, the peak (c's 10 is no level-0 value) */
    /* the stated figures (docs/fuzzy-hazard.md): 917 bytes per cell at 27 points, n = 3, m = 2 */
    assert_int_equal(fr_bytes_per_cell(27, 3, 2), 917);
    size_t bytes = 0, rows = fr_block_rows(&res, 500, 500, FR_DEFAULT_BUDGET, &bytes);
    assert_true(bytes <= FR_DEFAULT_BUDGET);
    assert_int_equal(rows, (FR_DEFAULT_BUDGET - fr_bytes_fixed(&res)) / (500 * fr_bytes_per_cell(np, 3, 2)));
    /* a budget of 4 MiB: the retransformation must live in it (plus the
     * output bands and 1 MiB of allocator slack), under an address-space
     * limit on the process's data (not with a sanitizer, which maps its own) */
    size_t budget = (size_t)4 << 20, work = 0;
    fr_block_rows(&res, 500, 500, budget, &work);
    assert_true(work <= budget);
    gen_reader g = {&res, 500};
    const char *name[1] = {"reach_probability"};
    fr_source src = {500, 500, 1, name, NULL, gen_read, &g, budget};
    terrain_band *out = NULL;
    size_t n_out = 0;
    struct rlimit old;
    getrlimit(RLIMIT_DATA, &old);
    int limited = 0;
#ifdef LIMIT_DATA
    size_t out_bytes = 8 * 500 * 500 * sizeof(float);
    struct rlimit lim = {vm_data_bytes() + out_bytes + work + ((size_t)1 << 20), old.rlim_max};
    limited = setrlimit(RLIMIT_DATA, &lim) == 0;
#endif
    rf_error err = {0};
    rf_status st = fr_retransform(&res, &src, &out, &n_out, &err);
    if (limited)
        setrlimit(RLIMIT_DATA, &old);
    if (st)
        fail_msg("fr_retransform within %zu bytes of working memory: %s", work, err.msg);
    assert_int_equal(n_out, 8);
    /* spot check: cell (col 5, row 0) of W: alpha-0 bounds 0.3 and 0.9 times 1.05 */
    assert_close(out[0].data[5], (float)(0.3 * 1.05), 1e-12);
    assert_close(out[1].data[5], (float)(0.9 * 1.05), 1e-12);
    terrain_bands_free(out, n_out);
    rf_tm_result_free(&res);
    m.ctx = NULL;
    rf_model_free(&m);
    for (int i = 0; i < 3; i++)
        rf_fuzzy_free(&in[i]);
}


/* ---- the study key: model.trajectory.rasters.fuzzy */

static const char *drop_yaml =
    "name: drop\n"
    "profile: {points: [[-1, 0], [1, 0]], material: ground}\n"
    "materials: {ground: {R_n: 0.5, R_t: 0.8, friction_angle: 30}}\n"
    "block: {shape: point, mass: 100}\n"
    "release: {x: 0, y: {uniform: [2, 12]}}\n"
    "bounce: {contact_speed: 1}\n"
    "samples: 100\nseed: 11\n";

static rf_status load_study(const char *dir, const char *rasters, rf_study *s, rf_error *err)
{
    char path[600], text[600];
    snprintf(path, sizeof path, "%s/drop.yaml", dir);
    FILE *f = fopen(path, "w");
    fputs(drop_yaml, f);
    fclose(f);
    snprintf(text, sizeof text,
             "parameters: {Rn: {tfn: [0.5, 0.2, 0.2]}}\n"
             "model: {trajectory: {file: drop.yaml, bind: {Rn: materials.ground.R_n}%s}}\n", rasters);
    snprintf(path, sizeof path, "%s/study.yaml", dir);
    f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    return rf_study_load(path, s, err);
}

static void test_study_key(void **state)
{
    (void)state;
    char *dir = temp_dir();
    rf_study s;
    rf_error err = {0};
    if (load_study(dir, "", &s, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(s.n_fuzzy_rasters, 0); /* a profile: no rasters, none by default */
    rf_study_free(&s);
    assert_int_equal(load_study(dir, ", rasters: {fuzzy: [reach_probability]}", &s, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "model.trajectory.rasters"));
    assert_non_null(strstr(err.msg, "terrain file"));
    remove_tree(dir);
    free(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_valley_closed_form),
        cmocka_unit_test(test_resume),
        cmocka_unit_test(test_failed_point),
        cmocka_unit_test(test_memory_500),
        cmocka_unit_test(test_study_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
