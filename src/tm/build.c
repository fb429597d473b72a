/* build.c - what a TM run evaluates: the inputs' cuts, the per-input point
 * sets of the general, reduced and extended forms (tm_spec s.2.1, 2.5, 3, 4),
 * the three-point grids of the left/right analysis (s.5.4), the extended
 * form's probe lines, and the size of every grid counted analytically so
 * that a study too large for the cap is refused before anything is built.
 *
 * ctx_init decomposes the inputs, refuses cuts that doubles cannot resolve,
 * and registers every value any grid can use (sorted, merged within rtol);
 * the tm_build_* functions then hand per-input value lists to grid.c. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tm/tm_internal.h"

#define MAX_PROBE_CORNERS 64

/* Registration (ctx_init only): add v to values[i] unless a stored value is
 * within rtol.  The values are kept sorted (binary search, insertion): the
 * set stored is the same as with a scan in registration order. */
static int value_add(struct rf_tm_data *d, size_t i, double v)
{
    double tol = d->rtol * d->scale[i], *vals = d->values[i];
    size_t lo = 0, hi = d->nvalues[i];
    while (lo < hi) { /* first stored value >= v - tol */
        size_t mid = lo + (hi - lo) / 2;
        if (vals[mid] < v - tol)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (size_t k = lo; k < d->nvalues[i] && vals[k] <= v + tol; k++)
        if (fabs(vals[k] - v) <= tol)
            return 0;
    if (d->nvalues[i] == d->capvalues[i]) {
        size_t cap = d->capvalues[i] ? 2 * d->capvalues[i] : 16;
        double *nv = realloc(d->values[i], cap * sizeof(double));
        if (!nv)
            return -1;
        d->values[i] = vals = nv;
        d->capvalues[i] = cap;
    }
    size_t at = lo;
    while (at < d->nvalues[i] && vals[at] < v)
        at++;
    memmove(vals + at + 1, vals + at, (d->nvalues[i] - at) * sizeof(double));
    vals[at] = v;
    d->nvalues[i]++;
    return 0;
}

/* Sort ascending and drop values within tol of their predecessor.  The
 * lists are short and nearly sorted (lower bound, midpoints, upper bound):
 * insertion sort. */
size_t tm_sort_unique(double *v, size_t k, double tol)
{
    for (size_t r = 1; r < k; r++) {
        double x = v[r];
        size_t q = r;
        for (; q > 0 && v[q - 1] > x; q--)
            v[q] = v[q - 1];
        v[q] = x;
    }
    size_t w = 0;
    for (size_t r = 0; r < k; r++)
        if (w == 0 || v[r] - v[w - 1] > tol)
            v[w++] = v[r];
    return w;
}

/* General-form points of one input at every level (s.2.1 with the flat-core
 * rule of s.2.5): gen[j] has cnt[j] ascending values.  Returns the first
 * level whose points merged although its cut has a width (doubles cannot
 * resolve them), or SIZE_MAX. */
static size_t general_points(const double *lo, const double *hi, size_t m, double tol, double **gen, size_t *cnt)
{
    size_t merged = SIZE_MAX;
    double *top = gen[m];
    top[0] = lo[m];
    top[1] = hi[m];
    cnt[m] = tm_sort_unique(top, 2, tol);
    for (size_t jj = m; jj-- > 0;) {
        double *c = gen[jj], *up = gen[jj + 1];
        size_t k = 0;
        c[k++] = lo[jj];
        for (size_t l = 0; l + 1 < cnt[jj + 1]; l++)
            c[k++] = 0.5 * (up[l] + up[l + 1]);
        c[k++] = hi[jj];
        size_t want = hi[jj] - lo[jj] > tol ? k : 1;
        cnt[jj] = tm_sort_unique(c, k, tol);
        if (cnt[jj] < want && merged == SIZE_MAX)
            merged = jj;
    }
    return merged;
}

void tm_ctx_free(tm_ctx *c)
{
    for (size_t i = 0; c->gen && i < c->n; i++) {
        for (size_t j = 0; c->gen[i] && j <= c->m; j++)
            free(c->gen[i][j]);
        free(c->gen[i]);
        free(c->gen_cnt[i]);
    }
    free(c->gen);
    free(c->gen_cnt);
    free(c->lo);
    free(c->hi);
    free(c->nominal);
    free(c->cls);
    rf_tm_data_free(c->d);
    c->d = NULL;
}

static rf_status ctx_alloc(tm_ctx *c, size_t n, size_t m, size_t n_out, const rf_tm_options *opt, rf_error *err)
{
    c->lo = malloc(n * (m + 1) * sizeof(double));
    c->hi = malloc(n * (m + 1) * sizeof(double));
    c->nominal = malloc(n * sizeof(double));
    c->gen = calloc(n, sizeof *c->gen);
    c->gen_cnt = calloc(n, sizeof *c->gen_cnt);
    c->cls = calloc(n, sizeof *c->cls);
    c->d = calloc(1, sizeof *c->d);
    if (!c->lo || !c->hi || !c->nominal || !c->gen || !c->gen_cnt || !c->cls || !c->d)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    struct rf_tm_data *d = c->d;
    d->n = n;
    d->m = m;
    d->n_out = n_out;
    d->rtol = opt->cache_rtol > 0 ? opt->cache_rtol : 0;
    d->stop = opt->interrupt;
    d->values = calloc(n, sizeof *d->values);
    d->nvalues = calloc(n, sizeof *d->nvalues);
    d->capvalues = calloc(n, sizeof *d->capvalues);
    d->scale = calloc(n, sizeof *d->scale);
    d->main = calloc(m + 1, sizeof *d->main);
    d->nominal = calloc(1, sizeof *d->nominal);
    if (!d->values || !d->nvalues || !d->capvalues || !d->scale || !d->main || !d->nominal)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; i++) {
        c->gen[i] = calloc(m + 1, sizeof(double *));
        c->gen_cnt[i] = calloc(m + 1, sizeof(size_t));
        if (!c->gen[i] || !c->gen_cnt[i])
            return rf_fail(err, RF_ENOMEM, "out of memory");
        for (size_t j = 0; j <= m; j++)
            if (!(c->gen[i][j] = malloc((m - j + 2) * sizeof(double))))
                return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    return RF_OK;
}

/* Decompose input i, build its general-form points and register its values. */
static rf_status ctx_input(tm_ctx *c, const rf_fuzzy *in, size_t i, rf_error *err)
{
    struct rf_tm_data *d = c->d;
    size_t m = c->m;
    double *lo = c->lo + i * (m + 1), *hi = c->hi + i * (m + 1);
    if (rf_fuzzy_decompose(in, m, lo, hi, err))
        return rf_error_prefix(err, "parameter %zu", i + 1);
    c->nominal[i] = rf_fuzzy_nominal(in);
    double w = hi[0] - lo[0], a = fmax(fabs(lo[0]), fabs(hi[0]));
    d->scale[i] = w > 0 ? w : (a > 0 ? a : 1.0);
    size_t bad = general_points(lo, hi, m, d->rtol * d->scale[i], c->gen[i], c->gen_cnt[i]);
    if (bad != SIZE_MAX)
        return rf_fail(err, RF_EINVAL,
                       "parameter %zu: the %zu general-form grid values at mu = %g, in [%.17g, %.17g], are "
                       "not distinct in double precision (only %zu are): the width is too small for the "
                       "magnitude; lower levels, or shift/rescale the parameter (e.g. give it relative to a "
                       "reference value)",
                       i + 1, m - bad + (c->gen_cnt[i][m]), (double)bad / (double)m, lo[bad], hi[bad],
                       c->gen_cnt[i][bad]);
    /* every value any grid can use, the general-form points first (they
     * hold the reduced form's and the probe's; registering them for every
     * form keeps the merged values, hence the results, independent of the
     * form), then the cut bounds and the nominal */
    int fail = 0;
    for (size_t j = 0; j <= m; j++)
        for (size_t l = 0; l < c->gen_cnt[i][j]; l++)
            fail |= value_add(d, i, c->gen[i][j][l]);
    fail |= value_add(d, i, c->nominal[i]);
    for (size_t j = 0; j <= m; j++)
        fail |= value_add(d, i, lo[j]) | value_add(d, i, hi[j]);
    if (fail)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    c->cls[i] = c->opt->force_class ? c->opt->force_class[i] : RF_MONO_AUTO;
    return RF_OK;
}

rf_status tm_ctx_init(tm_ctx *c, const rf_fuzzy *inputs, size_t n, const rf_tm_options *opt, size_t n_out,
                      rf_error *err)
{
    memset(c, 0, sizeof *c);
    size_t m = opt->levels;
    c->n = n;
    c->m = m;
    c->opt = opt;
    if (n == 0)
        return rf_fail(err, RF_EINVAL, "the study has no parameters");
    if (m < 1)
        return rf_fail(err, RF_EINVAL, "levels = %zu: at least one membership interval is needed", m);
    if (n > 64)
        return rf_fail(err, RF_EINVAL, "%zu parameters: at most 64 are supported", n);
    if (m > 100000)
        return rf_fail(err, RF_EINVAL, "levels = %zu: at most 100000 are supported", m);
    rf_status st = ctx_alloc(c, n, m, n_out, opt, err);
    size_t most = 0;
    for (size_t i = 0; !st && i < n; i++) {
        st = ctx_input(c, &inputs[i], i, err);
        most = c->d->nvalues[i] > most ? c->d->nvalues[i] : most;
    }
    c->d->tw = most <= 256 ? 1 : most <= 65536 ? 2 : 4; /* bytes per value index in a tuple */
    return st;
}

/* -------------------------------------------------------- per-input lists */

static int is_general(const tm_ctx *c, size_t i)
{
    return c->opt->scheme == RF_TM_GENERAL ||
           (c->opt->scheme == RF_TM_EXTENDED && c->cls[i] == RF_MONO_NONMONOTONIC);
}

/* Values of input i at level j for the main grid of the chosen form. */
static size_t main_values(const tm_ctx *c, size_t i, size_t j, double *buf, double **vals)
{
    if (is_general(c, i)) {
        *vals = c->gen[i][j];
        return c->gen_cnt[i][j];
    }
    size_t m = c->m;
    buf[0] = c->lo[i * (m + 1) + j];
    buf[1] = c->hi[i * (m + 1) + j];
    *vals = buf;
    return tm_sort_unique(buf, 2, c->d->rtol * c->d->scale[i]);
}

/* The three-point list {a, nominal, b} of input i at level j. */
static size_t lr_values(const tm_ctx *c, size_t i, size_t j, double *b)
{
    size_t m = c->m;
    b[0] = c->lo[i * (m + 1) + j];
    b[1] = c->nominal[i];
    b[2] = c->hi[i * (m + 1) + j];
    return tm_sort_unique(b, 3, c->d->rtol * c->d->scale[i]);
}

typedef struct {
    double *buf;   /* [3n] */
    double **vals; /* [n] */
    size_t *cnt;   /* [n] */
} lists;

static rf_status lists_alloc(lists *L, size_t n, rf_error *err)
{
    L->buf = malloc(3 * n * sizeof(double));
    L->vals = malloc(n * sizeof(double *));
    L->cnt = malloc(n * sizeof(size_t));
    if (!L->buf || !L->vals || !L->cnt)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    return RF_OK;
}

static void lists_free(lists *L)
{
    free(L->buf);
    free(L->vals);
    free(L->cnt);
}

/* --------------------------------------------------------------- builders */

/* The nominal point, first of all points (id 0: the analysis' reference). */
rf_status tm_build_nominal(tm_ctx *c, int with_ids, rf_error *err)
{
    lists L;
    size_t ignored = 0;
    rf_status st = lists_alloc(&L, c->n, err);
    for (size_t i = 0; !st && i < c->n; i++) {
        L.buf[i] = c->nominal[i];
        L.vals[i] = L.buf + i;
        L.cnt[i] = 1;
    }
    if (!st)
        st = rf_tm_grid_build(c->d, c->d->nominal, L.vals, L.cnt, &ignored, with_ids, err);
    lists_free(&L);
    c->d->nominal_id = 0;
    return st;
}

rf_status tm_build_main(tm_ctx *c, int with_ids, rf_error *err)
{
    lists L;
    tm_grid_sizes s;
    tm_sizes(c, &s);
    rf_status st = lists_alloc(&L, c->n, err);
    if (!st && with_ids && s.floor <= UINT32_MAX) /* room for the whole family at once */
        st = rf_tm_reserve(c->d, s.floor, err);
    for (size_t j = 0; !st && j <= c->m; j++) {
        for (size_t i = 0; i < c->n; i++)
            L.cnt[i] = main_values(c, i, j, L.buf + 3 * i, &L.vals[i]);
        st = rf_tm_grid_build(c->d, &c->d->main[j], L.vals, L.cnt, &c->requested, with_ids, err);
    }
    lists_free(&L);
    return st;
}

/* Three-point grids {a, nominal, b} at levels 0..m (s.5.4).  Level m is the
 * nominal point alone for single-peaked inputs; for flat cores it spans the
 * core, so that the left/right spreads add up to the output width there too. */
rf_status tm_build_lr(tm_ctx *c, int with_ids, rf_error *err)
{
    lists L;
    tm_grid_sizes s;
    tm_sizes(c, &s);
    rf_status st = lists_alloc(&L, c->n, err);
    if (!st && with_ids && s.lr <= UINT32_MAX)
        st = rf_tm_reserve(c->d, s.lr, err);
    if (!st && !(c->d->lr = calloc(c->m + 1, sizeof(rf_grid))))
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t j = 0; !st && j <= c->m; j++) {
        for (size_t i = 0; i < c->n; i++) {
            L.cnt[i] = lr_values(c, i, j, L.buf + 3 * i);
            L.vals[i] = L.buf + 3 * i;
        }
        rf_grid *g = &c->d->lr[j];
        st = rf_tm_grid_build(c->d, g, L.vals, L.cnt, &c->requested, with_ids, err);
        for (size_t i = 0; !st && i < c->n; i++) {
            uint32_t nid = 0;
            rf_tm_value_index(c->d, i, c->nominal[i], &nid);
            for (size_t l = 0; l < g->radix[i]; l++)
                if (g->vidx[i][l] == nid)
                    g->nominal_pos[i] = l;
        }
    }
    lists_free(&L);
    return st;
}

/* Probe line `line` of input i (line 0: the others nominal; line 1+k: corner
 * k of the others, all corners when n - 1 <= 6, else a seeded sample). */
static void probe_line(const tm_ctx *c, size_t i, size_t line, uint64_t *rng, lists *L)
{
    size_t n = c->n, m = c->m, bit = 0;
    uint64_t bits = 0;
    if (line > 0 && n - 1 <= 6) {
        bits = line - 1;
    } else if (line > 0) {
        *rng += 0x9e3779b97f4a7c15ULL; /* splitmix64: fixed seed, reproducible sample */
        uint64_t z = *rng;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        bits = z ^ (z >> 31);
    }
    for (size_t q = 0; q < n; q++) {
        if (q == i) {
            L->vals[q] = c->gen[i][0];
            L->cnt[q] = c->gen_cnt[i][0];
            continue;
        }
        L->buf[q] = line == 0 ? c->nominal[q] : (((bits >> bit) & 1) ? c->hi[q * (m + 1)] : c->lo[q * (m + 1)]);
        bit++;
        L->vals[q] = L->buf + q;
        L->cnt[q] = 1;
    }
}

static size_t probe_corners(size_t n) { return n - 1 <= 6 ? ((size_t)1 << (n - 1)) : MAX_PROBE_CORNERS; }

/* Extended-form probe (s.4 step 1): for each auto input, lines along it at
 * the level-0 general points, the others at nominal and at corner settings. */
rf_status tm_build_probe(tm_ctx *c, probe_set *ps, size_t *nps, int with_ids, rf_error *err)
{
    size_t n = c->n, nlines = 1 + probe_corners(n), nauto = 0;
    *nps = 0;
    for (size_t i = 0; i < n; i++)
        nauto += c->cls[i] == RF_MONO_AUTO;
    lists L;
    rf_status st = lists_alloc(&L, n, err);
    if (!st && !(c->d->probe = calloc(nauto * nlines, sizeof(rf_grid))))
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    uint64_t rng = 0x9e3779b97f4a7c15ULL;
    for (size_t i = 0; !st && i < n; i++) {
        if (c->cls[i] != RF_MONO_AUTO)
            continue;
        probe_set *p = &ps[(*nps)++];
        p->i = i;
        p->npts = c->gen_cnt[i][0];
        p->nlines = nlines;
        p->lines = c->d->probe + c->d->nprobe;
        for (size_t line = 0; !st && line < nlines; line++) {
            probe_line(c, i, line, &rng, &L);
            st = rf_tm_grid_build(c->d, &c->d->probe[c->d->nprobe++], L.vals, L.cnt, &c->requested, with_ids,
                                  err);
        }
    }
    lists_free(&L);
    return st;
}

/* ------------------------------------------------- sizes before building */

static size_t sat_mul(size_t a, size_t b) { return a && b > SIZE_MAX / a ? SIZE_MAX : a * b; }
static size_t sat_add(size_t a, size_t b) { return a > SIZE_MAX - b ? SIZE_MAX : a + b; }

/* Points of the main grids (every level) if the auto inputs of the extended
 * form are taken as `auto_as`; the largest level grid in *largest at *level. */
static size_t size_main(const tm_ctx *c, rf_monotonicity auto_as, size_t *largest, size_t *level)
{
    size_t total = 0;
    *largest = 0;
    *level = 0;
    for (size_t j = 0; j <= c->m; j++) {
        size_t count = 1;
        for (size_t i = 0; i < c->n; i++) {
            size_t m = c->m, k;
            int general = c->opt->scheme == RF_TM_GENERAL ||
                          (c->opt->scheme == RF_TM_EXTENDED &&
                           (c->cls[i] == RF_MONO_AUTO ? auto_as : c->cls[i]) == RF_MONO_NONMONOTONIC);
            if (general)
                k = c->gen_cnt[i][j];
            else
                k = c->hi[i * (m + 1) + j] - c->lo[i * (m + 1) + j] > c->d->rtol * c->d->scale[i] ? 2 : 1;
            count = sat_mul(count, k);
        }
        if (count > *largest) {
            *largest = count;
            *level = j;
        }
        total = sat_add(total, count);
    }
    return total;
}

static size_t size_lr(const tm_ctx *c, size_t *largest, size_t *level)
{
    double b[3];
    size_t total = 0;
    *largest = 0;
    *level = 0;
    for (size_t j = 0; j <= c->m; j++) {
        size_t count = 1;
        for (size_t i = 0; i < c->n; i++)
            count = sat_mul(count, lr_values(c, i, j, b));
        if (count > *largest) {
            *largest = count;
            *level = j;
        }
        total = sat_add(total, count);
    }
    return total;
}

static size_t size_probe(const tm_ctx *c)
{
    size_t total = 0;
    for (size_t i = 0; i < c->n; i++)
        if (c->opt->scheme == RF_TM_EXTENDED && c->cls[i] == RF_MONO_AUTO)
            total = sat_add(total, sat_mul(1 + probe_corners(c->n), c->gen_cnt[i][0]));
    return total;
}

void tm_sizes(const tm_ctx *c, tm_grid_sizes *s)
{
    memset(s, 0, sizeof *s);
    s->main = size_main(c, RF_MONO_NONMONOTONIC, &s->main_largest, &s->main_level);
    s->floor = size_main(c, RF_MONO_MONOTONIC, &s->floor_largest, &s->floor_level);
    s->probe = size_probe(c);
    if (c->opt->left_right)
        s->lr = size_lr(c, &s->lr_largest, &s->lr_level);
    s->requested = sat_add(sat_add(s->main, s->probe), s->lr);
}

static rf_status too_large(rf_error *err, const char *grid, double mu, size_t points, size_t limit, int is_cap,
                           const char *advice)
{
    char count[48];
    if (points == SIZE_MAX)
        snprintf(count, sizeof count, "more than %zu", SIZE_MAX);
    else
        snprintf(count, sizeof count, "%zu", points);
    if (is_cap)
        return rf_fail(err, RF_ECAP,
                       "the %s at mu = %g has %s points, more than the cap of %zu (max_evaluations = %zu): %s", grid,
                       mu, count, limit, limit, advice);
    return rf_fail(err, RF_ECAP, "the %s at mu = %g has %s points, more than this build can index (%zu): %s", grid, mu,
                   count, limit, advice);
}

/* Refuse, before anything is built, a grid with more points than the cap (a
 * grid's points are distinct, so the study would need at least that many
 * evaluations) or than the point ids can index.  For the extended form the
 * main grid is judged by its smallest possible size (every auto input
 * monotonic): the probe decides, and the grid is checked again after it. */
rf_status tm_check_sizes(const tm_ctx *c, const tm_grid_sizes *s, rf_error *err)
{
    size_t cap = c->opt->max_evaluations, index = UINT32_MAX - 1, m = c->m;
    int use_cap = cap > 0 && cap < index;
    size_t limit = use_cap ? cap : index;
    const char *more = use_cap ? "; or raise max_evaluations" : "";
    char advice[400];
    if (s->lr_largest > limit) {
        snprintf(advice, sizeof advice,
                 "it has 3 values per parameter (%zu parameters); turn off the left/right influence "
                 "(options.left_right: false), which the main grid does not need%s", c->n, more);
        return too_large(err, "three-point grid of the left/right influence", (double)s->lr_level / (double)m,
                         s->lr_largest, limit, use_cap, advice);
    }
    if (s->probe > limit) {
        snprintf(advice, sizeof advice,
                 "give the parameters their class (monotonic or nonmonotonic) so that the probe is not needed, "
                 "or lower levels%s", more);
        return too_large(err, "extended form's monotonicity probe", 0.0, s->probe, limit, use_cap, advice);
    }
    if (s->floor_largest > limit) {
        const char *form = c->opt->scheme == RF_TM_GENERAL ? "general-form grid"
                           : c->opt->scheme == RF_TM_REDUCED ? "reduced-form grid (corners of the level box)"
                                                             : "extended-form grid";
        if (c->opt->scheme == RF_TM_GENERAL)
            snprintf(advice, sizeof advice,
                     "it has m - j + 1 values per parameter (%zu parameters); lower levels, or use scheme: "
                     "reduced (exact for models monotonic in each parameter) or scheme: extended%s", c->n, more);
        else
            snprintf(advice, sizeof advice,
                     "it has 2 values per fuzzy parameter%s (%zu parameters); make some parameters crisp%s%s",
                     c->opt->scheme == RF_TM_EXTENDED ? " and m - j + 1 per nonmonotonic one" : "", c->n,
                     c->opt->scheme == RF_TM_EXTENDED ? " or declare fewer of them nonmonotonic" : "", more);
        return too_large(err, form, (double)s->floor_level / (double)m, s->floor_largest, limit, use_cap, advice);
    }
    if (s->requested >= index)
        return rf_fail(err, RF_ECAP, "the TM grids request %zu points in all, more than this build can index (%zu)",
                       s->requested, index);
    return RF_OK;
}
