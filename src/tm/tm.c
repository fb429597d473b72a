/* tm.c - the Transformation Method (tm_spec.md s.2-4): per-input point sets
 * of the general, reduced and extended forms, the point cache, evaluation
 * through an rf_evaluator, and the recursive retransformation.
 *
 * Flow of rf_tm_run:
 *   decompose inputs -> register every grid value (merged within rtol) ->
 *   phase 1: nominal point, three-point grid, extended-form probe and (unless
 *            the extended form still has to classify) the main grid ->
 *   evaluate the new distinct points -> classify (extended form) ->
 *   phase 2: main grid of the extended form -> evaluate -> retransform. */
#include "rockfuzz/tm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tm/tm_internal.h"

#define EMPTY_SLOT UINT32_MAX
#define MAX_PROBE_CORNERS 64

void rf_tm_options_default(rf_tm_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->scheme = RF_TM_REDUCED;
    opt->levels = 4;
    opt->left_right = 1;
    opt->cache_rtol = 1e-12;
    opt->probe_rtol = 1e-9;
}

const char *rf_tm_scheme_name(rf_tm_scheme s)
{
    switch (s) {
    case RF_TM_GENERAL: return "general";
    case RF_TM_REDUCED: return "reduced";
    case RF_TM_EXTENDED: return "extended";
    }
    return "?";
}

rf_status rf_tm_scheme_parse(const char *name, rf_tm_scheme *s)
{
    if (!strcmp(name, "general"))
        *s = RF_TM_GENERAL;
    else if (!strcmp(name, "reduced"))
        *s = RF_TM_REDUCED;
    else if (!strcmp(name, "extended"))
        *s = RF_TM_EXTENDED;
    else
        return RF_EINVAL;
    return RF_OK;
}

size_t rf_tm_count_general(size_t n, size_t m)
{
    size_t total = 0;
    for (size_t k = 1; k <= m + 1; k++) {
        size_t p = 1;
        for (size_t i = 0; i < n; i++)
            p *= k;
        total += p;
    }
    return total;
}

size_t rf_tm_count_reduced(size_t n, size_t m) { return m * ((size_t)1 << n) + 1; }

/* ------------------------------------------------------------------ values */

/* Index of v in values[i], adding it if no stored value is within rtol. */
static int value_index(struct rf_tm_data *d, size_t i, double v, uint32_t *out)
{
    double tol = d->rtol * d->scale[i];
    for (size_t k = 0; k < d->nvalues[i]; k++) {
        if (fabs(d->values[i][k] - v) <= tol) {
            *out = (uint32_t)k;
            return 0;
        }
    }
    if (d->nvalues[i] == d->capvalues[i]) {
        size_t cap = d->capvalues[i] ? 2 * d->capvalues[i] : 16;
        double *nv = realloc(d->values[i], cap * sizeof(double));
        if (!nv)
            return -1;
        d->values[i] = nv;
        d->capvalues[i] = cap;
    }
    d->values[i][d->nvalues[i]] = v;
    *out = (uint32_t)d->nvalues[i]++;
    return 0;
}

/* --------------------------------------------------------- per-input sets */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sort ascending and drop values within tol of their predecessor. */
static size_t sort_unique(double *v, size_t k, double tol)
{
    qsort(v, k, sizeof(double), cmp_double);
    size_t w = 0;
    for (size_t r = 0; r < k; r++)
        if (w == 0 || v[r] - v[w - 1] > tol)
            v[w++] = v[r];
    return w;
}

/* General-form points of input i at every level (s.2.1 with the flat-core
 * rule of s.2.5): gen[j] has cnt[j] ascending values. */
static void general_points(const double *lo, const double *hi, size_t m, double tol, double **gen, size_t *cnt)
{
    double *top = gen[m];
    top[0] = lo[m];
    top[1] = hi[m];
    cnt[m] = sort_unique(top, 2, tol);
    for (size_t jj = m; jj-- > 0;) {
        double *c = gen[jj], *up = gen[jj + 1];
        size_t k = 0;
        c[k++] = lo[jj];
        for (size_t l = 0; l + 1 < cnt[jj + 1]; l++)
            c[k++] = 0.5 * (up[l] + up[l + 1]);
        c[k++] = hi[jj];
        cnt[jj] = sort_unique(c, k, tol);
    }
}

/* ------------------------------------------------------------ point table */

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return x;
}

static uint64_t tuple_key(const struct rf_tm_data *d, const uint32_t *t)
{
    uint64_t key = 0;
    if (d->stride64) {
        for (size_t i = 0; i < d->n; i++)
            key += (uint64_t)t[i] * d->stride64[i];
        return key;
    }
    key = 1469598103934665603ULL;
    for (size_t i = 0; i < d->n; i++)
        key = mix64(key ^ t[i]);
    return key;
}

/* Make room for `extra` more points without rehashing or reallocating
 * inside the enumeration loop. */
static int table_reserve(struct rf_tm_data *d, size_t extra)
{
    size_t need = d->npoints + extra;
    if (need > d->cappoints) {
        uint32_t *nt = realloc(d->tuples, need * d->n * sizeof *nt);
        if (!nt)
            return -1;
        d->tuples = nt;
        d->cappoints = need;
    }
    if (2 * need <= d->nslots)
        return 0;
    size_t ns = d->nslots ? d->nslots : 1024;
    while (ns < 2 * need)
        ns *= 2;
    struct rf_tm_slot *slots = malloc(ns * sizeof *slots);
    if (!slots)
        return -1;
    for (size_t s = 0; s < ns; s++)
        slots[s].id = EMPTY_SLOT;
    for (size_t s = 0; s < d->nslots; s++) {
        if (d->slots[s].id == EMPTY_SLOT)
            continue;
        size_t h = mix64(d->slots[s].key) & (ns - 1);
        while (slots[h].id != EMPTY_SLOT)
            h = (h + 1) & (ns - 1);
        slots[h] = d->slots[s];
    }
    free(d->slots);
    d->slots = slots;
    d->nslots = ns;
    return 0;
}

/* Id of the point with tuple t (key precomputed), adding it if new. */
static int point_id(struct rf_tm_data *d, const uint32_t *t, uint64_t key, uint32_t *out)
{
    if ((d->npoints + 1 > d->cappoints || 2 * (d->npoints + 1) > d->nslots) && table_reserve(d, 1 + d->npoints))
        return -1;
    size_t mask = d->nslots - 1;
    size_t h = mix64(key) & mask;
    while (d->slots[h].id != EMPTY_SLOT) {
        if (d->slots[h].key == key) {
            uint32_t id = d->slots[h].id;
            if (d->stride64 || !memcmp(d->tuples + (size_t)id * d->n, t, d->n * sizeof *t)) {
                *out = id;
                return 0;
            }
        }
        h = (h + 1) & mask;
    }
    memcpy(d->tuples + d->npoints * d->n, t, d->n * sizeof *t);
    d->slots[h].key = key;
    d->slots[h].id = (uint32_t)d->npoints;
    *out = (uint32_t)d->npoints++;
    return 0;
}

/* ------------------------------------------------------------------ grids */

static void grid_free(rf_grid *g, size_t n)
{
    if (!g)
        return;
    if (g->vidx)
        for (size_t i = 0; i < n; i++)
            free(g->vidx[i]);
    free(g->vidx);
    free(g->radix);
    free(g->stride);
    free(g->nominal_pos);
    free(g->ids);
    memset(g, 0, sizeof *g);
}

/* Build grid g from per-input value lists (vals[i], cnt[i] ascending) and
 * register all its points; *requested grows by the grid size. */
static rf_status grid_build(struct rf_tm_data *d, rf_grid *g, double *const *vals, const size_t *cnt,
                            size_t *requested, int with_ids, rf_error *err)
{
    size_t n = d->n;
    g->radix = calloc(n, sizeof *g->radix);
    g->stride = calloc(n, sizeof *g->stride);
    g->vidx = calloc(n, sizeof *g->vidx);
    g->nominal_pos = calloc(n, sizeof *g->nominal_pos);
    if (!g->radix || !g->stride || !g->vidx || !g->nominal_pos)
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
    size_t count = 1;
    for (size_t i = n; i-- > 0;) {
        g->radix[i] = cnt[i];
        g->stride[i] = count;
        if (cnt[i] && count > SIZE_MAX / cnt[i])
            return rf_fail(err, RF_ECAP, "the TM grid is too large to enumerate");
        count *= cnt[i];
        g->vidx[i] = malloc(cnt[i] * sizeof(uint32_t));
        if (!g->vidx[i])
            return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
        for (size_t l = 0; l < cnt[i]; l++)
            if (value_index(d, i, vals[i][l], &g->vidx[i][l]))
                return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
    }
    g->count = count;
    *requested += count;
    if (!with_ids)
        return RF_OK;
    if (count > UINT32_MAX - 1)
        return rf_fail(err, RF_ECAP, "the TM grid has %zu points, more than this build can index", count);
    g->ids = malloc(count * sizeof(uint32_t));
    if (table_reserve(d, count)) {
        free(g->ids);
        g->ids = NULL;
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM point table");
    }
    uint32_t *t = malloc(n * sizeof(uint32_t));
    size_t *digit = calloc(n, sizeof(size_t));
    if (!g->ids || !t || !digit) {
        free(t);
        free(digit);
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
    }
    for (size_t i = 0; i < n; i++)
        t[i] = g->vidx[i][0];
    uint64_t key = d->stride64 ? tuple_key(d, t) : 0;
    rf_status st = RF_OK;
    for (size_t p = 0; p < count; p++) {
        uint64_t k = d->stride64 ? key : tuple_key(d, t);
        if (point_id(d, t, k, &g->ids[p])) {
            st = rf_fail(err, RF_ENOMEM, "out of memory for the TM point table");
            break;
        }
        /* odometer: last input fastest */
        for (size_t i = n; i-- > 0;) {
            if (++digit[i] < g->radix[i]) {
                uint32_t nv = g->vidx[i][digit[i]];
                if (d->stride64)
                    key += ((uint64_t)nv - t[i]) * d->stride64[i];
                t[i] = nv;
                break;
            }
            digit[i] = 0;
            uint32_t nv = g->vidx[i][0];
            if (d->stride64)
                key -= ((uint64_t)t[i] - nv) * d->stride64[i];
            t[i] = nv;
        }
    }
    free(t);
    free(digit);
    return st;
}

/* ---------------------------------------------------------------- context */

typedef struct {
    size_t n, m;
    const rf_tm_options *opt;
    double *lo, *hi;        /* [i*(m+1)+j] */
    double *nominal;        /* [i] */
    double ***gen;          /* [i][j] general-form values */
    size_t **gen_cnt;       /* [i][j] */
    struct rf_tm_data *d;
    size_t requested;
    rf_monotonicity *cls;   /* [i] extended-form class in use */
} tm_ctx;

static void ctx_free(tm_ctx *c)
{
    if (c->gen) {
        for (size_t i = 0; i < c->n; i++) {
            if (c->gen[i])
                for (size_t j = 0; j <= c->m; j++)
                    free(c->gen[i][j]);
            free(c->gen[i]);
            free(c->gen_cnt ? c->gen_cnt[i] : NULL);
        }
    }
    free(c->gen);
    free(c->gen_cnt);
    free(c->lo);
    free(c->hi);
    free(c->nominal);
    free(c->cls);
}

static void data_free(struct rf_tm_data *d)
{
    if (!d)
        return;
    for (size_t i = 0; i < d->n; i++)
        free(d->values ? d->values[i] : NULL);
    free(d->values);
    free(d->nvalues);
    free(d->capvalues);
    free(d->scale);
    free(d->tuples);
    free(d->stride64);
    free(d->slots);
    free(d->y);
    if (d->main)
        for (size_t j = 0; j <= d->m; j++)
            grid_free(&d->main[j], d->n);
    free(d->main);
    if (d->lr)
        for (size_t j = 0; j <= d->m; j++)
            grid_free(&d->lr[j], d->n);
    free(d->lr);
    free(d);
}

static rf_status ctx_init(tm_ctx *c, const rf_fuzzy *inputs, size_t n, const rf_tm_options *opt, size_t n_out,
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
    d->values = calloc(n, sizeof *d->values);
    d->nvalues = calloc(n, sizeof *d->nvalues);
    d->capvalues = calloc(n, sizeof *d->capvalues);
    d->scale = calloc(n, sizeof *d->scale);
    d->main = calloc(m + 1, sizeof *d->main);
    if (!d->values || !d->nvalues || !d->capvalues || !d->scale || !d->main)
        return rf_fail(err, RF_ENOMEM, "out of memory");

    for (size_t i = 0; i < n; i++) {
        double *lo = c->lo + i * (m + 1), *hi = c->hi + i * (m + 1);
        rf_status st = rf_fuzzy_decompose(&inputs[i], m, lo, hi, err);
        if (st)
            return rf_error_prefix(err, "parameter %zu", i + 1);
        c->nominal[i] = rf_fuzzy_nominal(&inputs[i]);
        double w = hi[0] - lo[0], a = fmax(fabs(lo[0]), fabs(hi[0]));
        d->scale[i] = w > 0 ? w : (a > 0 ? a : 1.0);
        double tol = d->rtol * d->scale[i];
        c->gen[i] = calloc(m + 1, sizeof(double *));
        c->gen_cnt[i] = calloc(m + 1, sizeof(size_t));
        if (!c->gen[i] || !c->gen_cnt[i])
            return rf_fail(err, RF_ENOMEM, "out of memory");
        for (size_t j = 0; j <= m; j++) {
            c->gen[i][j] = malloc((m - j + 2) * sizeof(double));
            if (!c->gen[i][j])
                return rf_fail(err, RF_ENOMEM, "out of memory");
        }
        general_points(lo, hi, m, tol, c->gen[i], c->gen_cnt[i]);
        /* Register every value any grid can use (general form is a superset
         * of reduced and probe values; plus the nominal) so that the tuple
         * key strides are fixed before any point is enumerated. */
        uint32_t idx;
        for (size_t j = 0; j <= m; j++)
            for (size_t l = 0; l < c->gen_cnt[i][j]; l++)
                if (value_index(d, i, c->gen[i][j][l], &idx))
                    return rf_fail(err, RF_ENOMEM, "out of memory");
        if (value_index(d, i, c->nominal[i], &idx))
            return rf_fail(err, RF_ENOMEM, "out of memory");
        c->cls[i] = opt->force_class ? opt->force_class[i] : RF_MONO_AUTO;
    }
    /* perfect-hash strides when the product of value counts fits in 63 bits */
    d->stride64 = malloc(n * sizeof(uint64_t));
    if (!d->stride64)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    uint64_t s = 1;
    for (size_t i = n; i-- > 0;) {
        d->stride64[i] = s;
        if (s > (UINT64_C(1) << 62) / (d->nvalues[i] + 1)) {
            free(d->stride64);
            d->stride64 = NULL;
            break;
        }
        s *= d->nvalues[i] + 1;
    }
    return RF_OK;
}

/* Values of input i at level j for the main grid of the chosen form. */
static size_t main_values(const tm_ctx *c, size_t i, size_t j, double *buf, const double **vals)
{
    int general = c->opt->scheme == RF_TM_GENERAL ||
                  (c->opt->scheme == RF_TM_EXTENDED && c->cls[i] == RF_MONO_NONMONOTONIC);
    if (general) {
        *vals = c->gen[i][j];
        return c->gen_cnt[i][j];
    }
    size_t m = c->m;
    buf[0] = c->lo[i * (m + 1) + j];
    buf[1] = c->hi[i * (m + 1) + j];
    *vals = buf;
    return sort_unique(buf, 2, c->d->rtol * c->d->scale[i]);
}

static rf_status build_main(tm_ctx *c, int with_ids, rf_error *err)
{
    size_t n = c->n;
    double *buf = malloc(2 * n * sizeof(double));
    double **vals = malloc(n * sizeof(double *));
    size_t *cnt = malloc(n * sizeof(size_t));
    rf_status st = RF_OK;
    if (!buf || !vals || !cnt)
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    /* reserve the point table once for all levels (no rehash while enumerating) */
    size_t total = 0;
    for (size_t j = 0; st == RF_OK && j <= c->m; j++) {
        size_t count = 1;
        for (size_t i = 0; i < n; i++) {
            const double *v;
            size_t k = main_values(c, i, j, buf + 2 * i, &v);
            count = k && count > SIZE_MAX / k ? SIZE_MAX : count * k;
        }
        total = total > SIZE_MAX - count ? SIZE_MAX : total + count;
    }
    if (st == RF_OK && with_ids && total < UINT32_MAX && table_reserve(c->d, total))
        st = rf_fail(err, RF_ENOMEM, "out of memory for the TM point table");
    for (size_t j = 0; st == RF_OK && j <= c->m; j++) {
        for (size_t i = 0; i < n; i++) {
            const double *v;
            cnt[i] = main_values(c, i, j, buf + 2 * i, &v);
            vals[i] = (double *)v;
        }
        st = grid_build(c->d, &c->d->main[j], vals, cnt, &c->requested, with_ids, err);
    }
    free(buf);
    free(vals);
    free(cnt);
    return st;
}

/* Three-point grids {a, nominal, b} at levels 0..m (s.5.4).  Level m is the
 * nominal point alone for single-peaked inputs; for flat cores it spans the
 * core, so that the left/right spreads add up to the output width there too. */
static rf_status build_lr(tm_ctx *c, int with_ids, rf_error *err)
{
    size_t n = c->n, m = c->m;
    c->d->lr = calloc(m + 1, sizeof(rf_grid));
    double *buf = malloc(3 * n * sizeof(double));
    double **vals = malloc(n * sizeof(double *));
    size_t *cnt = malloc(n * sizeof(size_t));
    rf_status st = RF_OK;
    if (!c->d->lr || !buf || !vals || !cnt)
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    size_t bound = m + 1; /* (m + 1) 3^n points at most: reserve once */
    for (size_t i = 0; i < n && bound < UINT32_MAX; i++)
        bound *= 3;
    if (st == RF_OK && with_ids && bound < UINT32_MAX && table_reserve(c->d, bound))
        st = rf_fail(err, RF_ENOMEM, "out of memory for the TM point table");
    for (size_t j = 0; st == RF_OK && j <= m; j++) {
        for (size_t i = 0; i < n; i++) {
            double *b = buf + 3 * i;
            b[0] = c->lo[i * (m + 1) + j];
            b[1] = c->nominal[i];
            b[2] = c->hi[i * (m + 1) + j];
            cnt[i] = sort_unique(b, 3, c->d->rtol * c->d->scale[i]);
            vals[i] = b;
        }
        st = grid_build(c->d, &c->d->lr[j], vals, cnt, &c->requested, with_ids, err);
        for (size_t i = 0; st == RF_OK && i < n; i++) {
            /* locate the nominal in the (merged) list */
            rf_grid *g = &c->d->lr[j];
            uint32_t nid;
            value_index(c->d, i, c->nominal[i], &nid);
            for (size_t l = 0; l < g->radix[i]; l++)
                if (g->vidx[i][l] == nid)
                    g->nominal_pos[i] = l;
        }
    }
    free(buf);
    free(vals);
    free(cnt);
    return st;
}

/* Extended-form probe (s.4 step 1): for each auto input, lines along it at
 * the level-0 general points, the others at nominal and at corner settings. */
typedef struct {
    size_t i;          /* probed input */
    size_t npts;       /* points per line */
    size_t nlines;
    uint32_t *ids;     /* [nlines * npts] */
} probe_set;

static rf_status build_probe(tm_ctx *c, probe_set *ps, size_t *nps, int with_ids, rf_error *err)
{
    size_t n = c->n, m = c->m;
    *nps = 0;
    uint32_t *t = malloc(n * sizeof(uint32_t));
    if (!t)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    size_t ncorner = n - 1 <= 6 ? ((size_t)1 << (n - 1)) : MAX_PROBE_CORNERS;
    uint64_t rng = 0x9e3779b97f4a7c15ULL; /* fixed seed: reproducible sample */
    for (size_t i = 0; i < n; i++) {
        if (c->cls[i] != RF_MONO_AUTO)
            continue;
        probe_set *p = &ps[(*nps)++];
        p->i = i;
        p->npts = c->gen_cnt[i][0];
        p->nlines = 1 + ncorner;
        c->requested += p->nlines * p->npts;
        if (!with_ids) {
            p->ids = NULL;
            continue;
        }
        p->ids = malloc(p->nlines * p->npts * sizeof(uint32_t));
        if (!p->ids) {
            free(t);
            return rf_fail(err, RF_ENOMEM, "out of memory");
        }
        for (size_t line = 0; line < p->nlines; line++) {
            /* line 0: others nominal; line 1+k: corner k of the others */
            uint64_t bits = 0;
            if (line > 0) {
                if (n - 1 <= 6) {
                    bits = line - 1;
                } else {
                    rng = mix64(rng + 0x9e3779b97f4a7c15ULL);
                    bits = rng;
                }
            }
            size_t bit = 0;
            for (size_t q = 0; q < n; q++) {
                if (q == i)
                    continue;
                double v = line == 0 ? c->nominal[q]
                                     : (((bits >> bit) & 1) ? c->hi[q * (m + 1)] : c->lo[q * (m + 1)]);
                bit++;
                value_index(c->d, q, v, &t[q]);
            }
            for (size_t l = 0; l < p->npts; l++) {
                value_index(c->d, i, c->gen[i][0][l], &t[i]);
                if (point_id(c->d, t, tuple_key(c->d, t), &p->ids[line * p->npts + l])) {
                    free(t);
                    return rf_fail(err, RF_ENOMEM, "out of memory");
                }
            }
        }
    }
    free(t);
    return RF_OK;
}

/* ------------------------------------------------------------- evaluation */

static void format_point(const struct rf_tm_data *d, uint32_t id, char *buf, size_t size)
{
    size_t used = 0;
    used += (size_t)snprintf(buf + used, size - used, "(");
    for (size_t i = 0; i < d->n && used < size; i++)
        used += (size_t)snprintf(buf + used, size - used, "%s%.17g", i ? ", " : "",
                                 d->values[i][d->tuples[(size_t)id * d->n + i]]);
    if (used < size)
        snprintf(buf + used, size - used, ")");
}

/* user: the rf_tm_options (tolerate_failures: a failed point gets NaN outputs). */
static rf_status serial_evaluate(void *user, const rf_model *model, size_t count, const double *x, double *y,
                                 size_t *failed, rf_error *err)
{
    const rf_tm_options *opt = user;
    for (size_t p = 0; p < count; p++) {
        rf_status st = rf_model_eval(model, x + p * model->n_inputs, y + p * model->n_outputs, err);
        if (st && opt->tolerate_failures) {
            for (size_t k = 0; k < model->n_outputs; k++)
                y[p * model->n_outputs + k] = NAN;
        } else if (st) {
            *failed = p;
            return st;
        }
    }
    return RF_OK;
}

static rf_status evaluate_pending(tm_ctx *c, const rf_model *model, size_t *already, rf_error *err)
{
    struct rf_tm_data *d = c->d;
    size_t n = d->n, no = d->n_out;
    size_t first = *already, count = d->npoints - first;
    if (count == 0)
        return RF_OK;
    double *y = realloc(d->y, d->npoints * no * sizeof(double));
    if (!y)
        return rf_fail(err, RF_ENOMEM, "out of memory for model outputs");
    d->y = y;
    double *x = malloc(count * n * sizeof(double));
    if (!x)
        return rf_fail(err, RF_ENOMEM, "out of memory for model inputs");
    for (size_t p = 0; p < count; p++)
        for (size_t i = 0; i < n; i++)
            x[p * n + i] = d->values[i][d->tuples[(first + p) * n + i]];
    const rf_evaluator *ev = c->opt->evaluator;
    size_t failed = 0;
    rf_status st = ev ? ev->evaluate(ev->user, model, count, x, d->y + first * no, &failed, err)
                      : serial_evaluate((void *)c->opt, model, count, x, d->y + first * no, &failed, err);
    free(x);
    if (st && failed >= count)
        return st; /* not a model failure (e.g. the result store could not be written) */
    if (st) {
        char pt[512];
        format_point(d, (uint32_t)(first + failed), pt, sizeof pt);
        return rf_error_prefix(err, "model evaluation at parameters %s", pt);
    }
    *already = d->npoints;
    return RF_OK;
}

/* ------------------------------------------------------ classification */

/* Does the sequence z[0..k-1] (stride s) change the sign of its differences? */
static int changes_direction(const double *z, size_t k, size_t s, double tol)
{
    int dir = 0;
    for (size_t l = 1; l < k; l++) {
        double dz = z[l * s] - z[(l - 1) * s];
        if (fabs(dz) <= tol)
            continue;
        int sg = dz > 0 ? 1 : -1;
        if (dir && sg != dir)
            return 1;
        dir = sg;
    }
    return 0;
}

static void output_range(const struct rf_tm_data *d, double *range)
{
    for (size_t k = 0; k < d->n_out; k++) {
        double lo = INFINITY, hi = -INFINITY;
        for (size_t p = 0; p < d->npoints; p++) {
            double v = d->y[p * d->n_out + k];
            if (v < lo)
                lo = v;
            if (v > hi)
                hi = v;
        }
        range[k] = hi > lo ? hi - lo : 0;
    }
}

static void classify(tm_ctx *c, const probe_set *ps, size_t nps, rf_monotonicity *verdict)
{
    struct rf_tm_data *d = c->d;
    size_t no = d->n_out;
    double range[no ? no : 1];
    output_range(d, range);
    size_t maxpts = 1;
    for (size_t s = 0; s < nps; s++)
        if (ps[s].npts > maxpts)
            maxpts = ps[s].npts;
    double *z = malloc(maxpts * sizeof(double));
    if (!z) { /* without memory, be conservative: general form for every probed input */
        for (size_t s = 0; s < nps; s++)
            c->cls[ps[s].i] = RF_MONO_NONMONOTONIC;
        return;
    }
    for (size_t s = 0; s < nps; s++) {
        const probe_set *p = &ps[s];
        int nonmono = 0;
        for (size_t k = 0; k < no; k++) {
            int nm_k = 0;
            for (size_t line = 0; line < p->nlines && !nm_k; line++) {
                for (size_t l = 0; l < p->npts; l++)
                    z[l] = d->y[(size_t)p->ids[line * p->npts + l] * no + k];
                nm_k = changes_direction(z, p->npts, 1, c->opt->probe_rtol * range[k]);
            }
            verdict[k * c->n + p->i] = nm_k ? RF_MONO_NONMONOTONIC : RF_MONO_MONOTONIC;
            nonmono |= nm_k;
        }
        c->cls[p->i] = nonmono ? RF_MONO_NONMONOTONIC : RF_MONO_MONOTONIC;
    }
    free(z);
}

/* Monotonicity diagnostic on a grid: every line parallel to axis i. */
static void diagnose_grid(const struct rf_tm_data *d, const rf_grid *g, const double *range, double rtol,
                          rf_monotonicity *verdict)
{
    size_t n = d->n, no = d->n_out;
    int any = 0;
    for (size_t i = 0; i < n; i++)
        any |= g->radix[i] >= 3;
    if (!any)
        return;
    /* gather the grid's outputs once per output (one pass of random reads),
     * then scan the lines with strides over a contiguous array */
    double *z = malloc(g->count * sizeof(double));
    if (!z)
        return; /* the diagnostic stays "not checked" */
    for (size_t k = 0; k < no; k++) {
        for (size_t p = 0; p < g->count; p++)
            z[p] = d->y[(size_t)g->ids[p] * no + k];
        double tol = rtol * range[k];
        for (size_t i = 0; i < n; i++) {
            size_t r = g->radix[i], s = g->stride[i];
            rf_monotonicity *v = &verdict[k * n + i];
            if (r < 3 || *v == RF_MONO_NONMONOTONIC)
                continue;
            int nm = 0;
            for (size_t outer = 0; outer < g->count && !nm; outer += r * s)
                for (size_t inner = 0; inner < s && !nm; inner++)
                    nm = changes_direction(z + outer + inner, r, s, tol);
            *v = nm ? RF_MONO_NONMONOTONIC : RF_MONO_MONOTONIC;
        }
    }
    free(z);
}

/* ------------------------------------------------------- retransformation */

/* Outputs NaN everywhere are undefined; NaN somewhere is an error. */
static rf_status check_nan_outputs(const tm_ctx *c, const rf_model *model, rf_tm_result *res, rf_error *err)
{
    const struct rf_tm_data *d = c->d;
    size_t no = d->n_out;
    for (size_t k = 0; k < no; k++) {
        size_t nan = 0, first_nan = 0;
        for (size_t p = 0; p < d->npoints; p++)
            if (isnan(d->y[p * no + k]) && !nan++)
                first_nan = p;
        if (nan == d->npoints) {
            res->output_undefined[k] = 1;
        } else if (nan > 0 && c->opt->tolerate_failures) {
            res->nan_points[k] = nan; /* left out of the bounds; the caller warns */
        } else if (nan > 0) {
            char pt[512];
            format_point(d, (uint32_t)first_nan, pt, sizeof pt);
            return rf_fail(err, RF_EMODEL,
                           "output '%s' is NaN at parameters %s (and %zu other points) but defined at others: "
                           "its bounds would be wrong",
                           model->output_names[k], pt, nan - 1);
        }
    }
    return RF_OK;
}

static void retransform(const tm_ctx *c, rf_tm_result *res)
{
    const struct rf_tm_data *d = c->d;
    size_t n = d->n, m = d->m, no = d->n_out;
    for (size_t k = 0; k < no; k++) {
        if (res->output_undefined[k]) {
            for (size_t at = k * (m + 1); at < (k + 1) * (m + 1); at++) {
                res->lo[at] = res->hi[at] = NAN;
                for (size_t i = 0; i < n; i++)
                    res->x_lo[at * n + i] = res->x_hi[at * n + i] = NAN;
            }
            continue;
        }
        uint32_t amin = 0, amax = 0;
        double zmin = INFINITY, zmax = -INFINITY;
        for (size_t jj = m + 1; jj-- > 0;) {
            /* recursion (s.2.4): start from the bounds of level j+1 */
            const rf_grid *g = &d->main[jj];
            for (size_t p = 0; p < g->count; p++) {
                uint32_t id = g->ids[p];
                double z = d->y[(size_t)id * no + k];
                if (z < zmin) {
                    zmin = z;
                    amin = id;
                }
                if (z > zmax) {
                    zmax = z;
                    amax = id;
                }
            }
            size_t at = k * (m + 1) + jj;
            int none = zmin > zmax; /* tolerate_failures: every point of the cut was NaN so far */
            res->lo[at] = none ? NAN : zmin;
            res->hi[at] = none ? NAN : zmax;
            for (size_t i = 0; i < n; i++) {
                res->x_lo[at * n + i] = none ? NAN : d->values[i][d->tuples[(size_t)amin * n + i]];
                res->x_hi[at * n + i] = none ? NAN : d->values[i][d->tuples[(size_t)amax * n + i]];
            }
        }
    }
}

/* ------------------------------------------------------------------ driver */

static rf_status plan(tm_ctx *c, int with_ids, probe_set *ps, size_t *nps, int *deferred, rf_error *err)
{
    rf_status st;
    /* nominal point first: its id is the reference of the analysis */
    if (with_ids) {
        uint32_t *t = malloc(c->n * sizeof(uint32_t));
        if (!t)
            return rf_fail(err, RF_ENOMEM, "out of memory");
        for (size_t i = 0; i < c->n; i++)
            value_index(c->d, i, c->nominal[i], &t[i]);
        int bad = point_id(c->d, t, tuple_key(c->d, t), &c->d->nominal_id);
        free(t);
        if (bad)
            return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    if (c->opt->left_right && (st = build_lr(c, with_ids, err)))
        return st;
    *nps = 0;
    *deferred = 0;
    if (c->opt->scheme == RF_TM_EXTENDED) {
        int any_auto = 0;
        for (size_t i = 0; i < c->n; i++)
            any_auto |= c->cls[i] == RF_MONO_AUTO;
        if (any_auto) {
            if ((st = build_probe(c, ps, nps, with_ids, err)))
                return st;
            *deferred = 1;
            return RF_OK;
        }
    }
    return build_main(c, with_ids, err);
}

rf_status rf_tm_count(const rf_fuzzy *inputs, size_t n_inputs, const rf_tm_options *opt, size_t *requested,
                      size_t *distinct, rf_error *err)
{
    tm_ctx c;
    rf_status st = ctx_init(&c, inputs, n_inputs, opt, 1, err);
    probe_set *ps = st ? NULL : calloc(n_inputs, sizeof *ps);
    size_t nps = 0;
    int deferred = 0;
    if (!st && !ps)
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (!st)
        st = plan(&c, 1, ps, &nps, &deferred, err);
    if (!st && deferred) {
        /* upper bound: every auto input non-monotonic (general form) */
        for (size_t i = 0; i < n_inputs; i++)
            if (c.cls[i] == RF_MONO_AUTO)
                c.cls[i] = RF_MONO_NONMONOTONIC;
        st = build_main(&c, 1, err);
    }
    if (!st) {
        *requested = c.requested;
        *distinct = c.d->npoints;
    }
    for (size_t s = 0; ps && s < nps; s++)
        free(ps[s].ids);
    free(ps);
    data_free(c.d);
    ctx_free(&c);
    return st;
}

void rf_tm_result_free(rf_tm_result *res)
{
    if (!res)
        return;
    free(res->in_lo);
    free(res->in_hi);
    free(res->in_nominal);
    free(res->lo);
    free(res->hi);
    free(res->x_lo);
    free(res->x_hi);
    free(res->nominal);
    free(res->input_class);
    free(res->monotonicity);
    free(res->output_undefined);
    free(res->nan_points);
    data_free(res->data);
    memset(res, 0, sizeof *res);
}

static rf_status result_alloc(rf_tm_result *res, size_t n, size_t no, size_t m, rf_error *err)
{
    memset(res, 0, sizeof *res);
    res->n_inputs = n;
    res->n_outputs = no;
    res->levels = m;
    res->in_lo = malloc(n * (m + 1) * sizeof(double));
    res->in_hi = malloc(n * (m + 1) * sizeof(double));
    res->in_nominal = malloc(n * sizeof(double));
    res->lo = malloc(no * (m + 1) * sizeof(double));
    res->hi = malloc(no * (m + 1) * sizeof(double));
    res->x_lo = malloc(no * (m + 1) * n * sizeof(double));
    res->x_hi = malloc(no * (m + 1) * n * sizeof(double));
    res->nominal = malloc(no * sizeof(double));
    res->input_class = calloc(n, sizeof *res->input_class);
    res->monotonicity = calloc(no * n, sizeof *res->monotonicity);
    res->output_undefined = calloc(no, 1);
    res->nan_points = calloc(no, sizeof *res->nan_points);
    if (!res->output_undefined || !res->nan_points ||!res->in_lo || !res->in_hi || !res->in_nominal || !res->lo || !res->hi || !res->x_lo || !res->x_hi ||
        !res->nominal || !res->input_class || !res->monotonicity)
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM result");
    return RF_OK;
}

rf_status rf_tm_run(const rf_fuzzy *inputs, size_t n_inputs, const rf_model *model, const rf_tm_options *opt,
                    rf_tm_result *res, rf_error *err)
{
    memset(res, 0, sizeof *res);
    if (!model || model->n_inputs != n_inputs)
        return rf_fail(err, RF_EINVAL, "the model takes %zu inputs but %zu parameters were given",
                       model ? model->n_inputs : 0, n_inputs);
    if (model->n_outputs == 0)
        return rf_fail(err, RF_EINVAL, "the model has no outputs");
    size_t no = model->n_outputs, m = opt->levels;
    tm_ctx c;
    probe_set *ps = NULL;
    size_t nps = 0, evaluated = 0;
    int deferred = 0;
    rf_status st = ctx_init(&c, inputs, n_inputs, opt, no, err);
    if (!st)
        st = result_alloc(res, n_inputs, no, m, err);
    if (!st && !(ps = calloc(n_inputs, sizeof *ps)))
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (!st && opt->on_plan) {
        size_t rq = 0, ds = 0;
        st = rf_tm_count(inputs, n_inputs, opt, &rq, &ds, err);
        if (!st && opt->on_plan(opt->on_plan_user, rq, ds))
            st = rf_fail(err, RF_ECAP, "the run was cancelled before any evaluation");
    }
    if (!st)
        st = plan(&c, 1, ps, &nps, &deferred, err);
    if (!st && opt->max_evaluations && c.d->npoints > opt->max_evaluations)
        st = rf_fail(err, RF_ECAP, "%zu distinct evaluations needed, more than max_evaluations = %zu",
                     c.d->npoints, opt->max_evaluations);
    if (!st)
        st = evaluate_pending(&c, model, &evaluated, err);
    size_t before_main = c.d ? c.d->npoints : 0;
    if (!st && deferred) {
        classify(&c, ps, nps, res->monotonicity);
        res->probe_evaluations = c.d->npoints;
        st = build_main(&c, 1, err);
        if (!st && opt->max_evaluations && c.d->npoints > opt->max_evaluations)
            st = rf_fail(err, RF_ECAP, "%zu distinct evaluations needed, more than max_evaluations = %zu",
                         c.d->npoints, opt->max_evaluations);
        if (!st)
            st = evaluate_pending(&c, model, &evaluated, err);
    }
    (void)before_main;
    if (!st)
        st = check_nan_outputs(&c, model, res, err);
    if (!st && opt->tolerate_failures) {
        const struct rf_tm_data *d = c.d;
        for (size_t p = 0; p < d->npoints; p++) {
            size_t k = 0;
            while (k < no && isnan(d->y[p * no + k]))
                k++;
            res->failed_points += k == no;
        }
    }
    if (!st) {
        struct rf_tm_data *d = c.d;
        res->scheme = opt->scheme;
        memcpy(res->in_lo, c.lo, n_inputs * (m + 1) * sizeof(double));
        memcpy(res->in_hi, c.hi, n_inputs * (m + 1) * sizeof(double));
        memcpy(res->in_nominal, c.nominal, n_inputs * sizeof(double));
        for (size_t k = 0; k < no; k++)
            res->nominal[k] = d->y[(size_t)d->nominal_id * no + k];
        if (opt->scheme == RF_TM_EXTENDED)
            memcpy(res->input_class, c.cls, n_inputs * sizeof *c.cls);
        /* diagnostic on whatever grids have interior points */
        double range[no];
        output_range(d, range);
        if (d->lr)
            for (size_t j = 0; j <= m; j++)
                diagnose_grid(d, &d->lr[j], range, opt->probe_rtol, res->monotonicity);
        if (opt->scheme != RF_TM_REDUCED)
            for (size_t j = 0; j <= m; j++)
                diagnose_grid(d, &d->main[j], range, opt->probe_rtol, res->monotonicity);
        retransform(&c, res);
        res->requested = c.requested;
        res->distinct = d->npoints;
        if (d->lr) {
            /* evaluations only the three-point grid needed */
            unsigned char *used = calloc(d->npoints, 1);
            if (used) {
                for (size_t j = 0; j <= m; j++)
                    for (size_t p = 0; p < d->main[j].count; p++)
                        used[d->main[j].ids[p]] = 1;
                used[d->nominal_id] = 1;
                size_t lr_only = 0;
                for (size_t j = 0; j <= m; j++)
                    for (size_t p = 0; p < d->lr[j].count; p++)
                        if (!used[d->lr[j].ids[p]]) {
                            used[d->lr[j].ids[p]] = 2;
                            lr_only++;
                        }
                res->lr_evaluations = lr_only;
                free(used);
            }
        }
        res->data = c.d;
        c.d = NULL;
    }
    for (size_t s = 0; ps && s < nps; s++)
        free(ps[s].ids);
    free(ps);
    data_free(c.d);
    ctx_free(&c);
    if (st) {
        rf_tm_result_free(res);
    }
    return st;
}
