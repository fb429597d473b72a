/* grid.c - the TM's grids and its point registry (see tm_internal.h).
 *
 * Grid values are registered per input, merged within rtol and then sorted,
 * so that value indices grow with the value and a grid's index list is
 * ascending.  rf_tm_grid_build maps a grid's value lists to index lists and
 * enumerates its points with an odometer, telling new points from repeated
 * ones by the AND of per-position "earlier grids holding this value" sets.
 * A new point gets the next id and its input vector is written once; a
 * repeated point takes the id stored by the first earlier grid holding it
 * (its position there is the rank of each index in that grid's bitsets). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tm/tm_internal.h"

#define WORD_BITS 64
#define SLACK_BYTES 128 /* after the tuples and the input buffer: see new_point */

static size_t words_for(size_t bits) { return (bits + WORD_BITS - 1) / WORD_BITS; }

static int bit_test(const uint64_t *set, size_t words, size_t b)
{
    return b / WORD_BITS < words && ((set[b / WORD_BITS] >> (b % WORD_BITS)) & 1);
}

/* Number of set bits below b: the position of index b in a grid's ascending list. */
static size_t bit_rank(const uint64_t *set, size_t b)
{
    size_t r = 0, w = b / WORD_BITS;
    for (size_t q = 0; q < w; q++)
        r += (size_t)__builtin_popcountll(set[q]);
    uint64_t low = (b % WORD_BITS) ? set[w] & ((UINT64_C(1) << (b % WORD_BITS)) - 1) : 0;
    return r + (size_t)__builtin_popcountll(low);
}

/* Index of the smallest stored value of input i within rtol of v (the
 * values are sorted), or -1 if there is none. */
int rf_tm_value_index(struct rf_tm_data *d, size_t i, double v, uint32_t *out)
{
    const double *vals = d->values[i];
    double tol = d->rtol * d->scale[i];
    size_t lo = 0, hi = d->nvalues[i];
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (vals[mid] < v - tol)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo == d->nvalues[i] || vals[lo] > v + tol)
        return -1;
    *out = (uint32_t)lo;
    return 0;
}

void rf_tm_grid_free(rf_grid *g, size_t n)
{
    if (!g)
        return;
    for (size_t i = 0; i < n; i++) {
        if (g->vidx)
            free(g->vidx[i]);
        if (g->member)
            free(g->member[i]);
    }
    free(g->vidx);
    free(g->member);
    free(g->radix);
    free(g->stride);
    free(g->nominal_pos);
    free(g->ids);
    memset(g, 0, sizeof *g);
}

void rf_tm_data_free(struct rf_tm_data *d)
{
    if (!d)
        return;
    for (size_t i = 0; i < d->n; i++)
        free(d->values ? d->values[i] : NULL);
    free(d->values);
    free(d->nvalues);
    free(d->capvalues);
    free(d->scale);
    free(d->reg);
    free(d->tuples);
    free(d->xbuf);
    free(d->ybuf);
    free(d->y);
    rf_tm_grid_free(d->nominal, d->n);
    free(d->nominal);
    for (size_t j = 0; d->main && j <= d->m; j++)
        rf_tm_grid_free(&d->main[j], d->n);
    free(d->main);
    for (size_t j = 0; d->lr && j <= d->m; j++)
        rf_tm_grid_free(&d->lr[j], d->n);
    free(d->lr);
    for (size_t s = 0; d->probe && s < d->nprobe; s++)
        rf_tm_grid_free(&d->probe[s], d->n);
    free(d->probe);
    free(d);
}

const double *rf_tm_outputs(const struct rf_tm_data *d, const rf_grid *g, size_t k, double *scratch)
{
    const double *col = d->y + k * d->cap_points;
    if (g->consecutive)
        return col + g->first_id;
    for (size_t p = 0; p < g->count; p++)
        scratch[p] = col[g->ids[p]];
    return scratch;
}

/* Index lists of g from ascending value lists; equal indices (values merged
 * within rtol) are kept once.  Sets radix, stride, member and count. */
static rf_status grid_lists(struct rf_tm_data *d, rf_grid *g, double *const *vals, const size_t *cnt,
                            rf_error *err)
{
    size_t n = d->n, count = 1;
    g->radix = calloc(n, sizeof *g->radix);
    g->stride = calloc(n, sizeof *g->stride);
    g->vidx = calloc(n, sizeof *g->vidx);
    g->member = calloc(n, sizeof *g->member);
    g->nominal_pos = calloc(n, sizeof *g->nominal_pos);
    if (!g->radix || !g->stride || !g->vidx || !g->member || !g->nominal_pos)
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
    for (size_t i = n; i-- > 0;) {
        g->vidx[i] = malloc((cnt[i] ? cnt[i] : 1) * sizeof(uint32_t));
        g->member[i] = calloc(words_for(d->nvalues[i]) + 1, sizeof(uint64_t));
        if (!g->vidx[i] || !g->member[i])
            return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
        size_t r = 0;
        for (size_t l = 0; l < cnt[i]; l++) {
            uint32_t v;
            if (rf_tm_value_index(d, i, vals[i][l], &v))
                return rf_fail(err, RF_EINTERNAL, "TM grid value %.17g of input %zu was not registered",
                               vals[i][l], i + 1);
            if (r == 0 || g->vidx[i][r - 1] != v)
                g->vidx[i][r++] = v;
            g->member[i][v / WORD_BITS] |= UINT64_C(1) << (v % WORD_BITS);
        }
        g->radix[i] = r;
        g->stride[i] = count;
        if (r && count > SIZE_MAX / r)
            return rf_fail(err, RF_ECAP, "the TM grid is too large to enumerate");
        count *= r;
    }
    g->count = count;
    return RF_OK;
}

/* The odometer's state while a grid is enumerated. */
typedef struct {
    size_t n, words;      /* words: of a set of earlier grids */
    size_t *digit;        /* [n] */
    uint64_t *mask;       /* [(offset[i] + l) * words]: earlier grids holding value l of input i */
    size_t *offset;       /* [n] */
    uint64_t *prefix;     /* [(n + 1) * words]: AND of the masks of inputs < i */
    double *cur;          /* [n] current input vector (its head part) */
    unsigned char tup[64 * 4]; /* current tuple, tw bytes per input (n <= 64) */
    /* A row sweeps the tail, inputs head..n-1, as one flattened digit t of
     * tail_count values (at least 16 when the grid allows): short radices
     * (2 corners) would otherwise make every row a couple of points. */
    size_t head, tail_count;
    uint64_t *tmask;      /* [t * words]: AND of the tail inputs' masks at tail digit t */
    uint64_t *tany;       /* [words] after tmask: OR of tmask over t (earlier grids holding some tail) */
    double *tx;           /* [t * (n - head)] tail input values */
    unsigned char *ttup;  /* [t * (n - head) * tw] tail tuple bytes */
} odometer;

static void set_tuple(unsigned char *t, size_t tw, size_t i, uint32_t v)
{
    if (tw == 1) {
        t[i] = (unsigned char)v;
    } else if (tw == 2) {
        uint16_t h = (uint16_t)v;
        memcpy(t + 2 * i, &h, 2);
    } else {
        memcpy(t + 4 * i, &v, 4);
    }
}

static void odometer_free(odometer *o)
{
    free(o->tmask);
    free(o->tx);
    free(o->ttup);
    free(o->digit);
    free(o->mask);
    free(o->offset);
    free(o->prefix);
    free(o->cur);
}

static rf_status odometer_tail(odometer *o, const struct rf_tm_data *d, const rf_grid *g, rf_error *err);

static rf_status odometer_init(odometer *o, const struct rf_tm_data *d, const rf_grid *g, rf_error *err)
{
    size_t n = d->n, total = 0;
    memset(o, 0, sizeof *o);
    o->n = n;
    o->words = words_for(d->nreg) ? words_for(d->nreg) : 1;
    o->offset = malloc(n * sizeof *o->offset);
    for (size_t i = 0; o->offset && i < n; i++) {
        o->offset[i] = total;
        total += g->radix[i];
    }
    o->digit = calloc(n, sizeof *o->digit);
    o->mask = calloc(total * o->words + 1, sizeof *o->mask);
    o->prefix = malloc((n + 1) * o->words * sizeof *o->prefix);
    o->cur = calloc(n < 16 ? 16 : n, sizeof *o->cur); /* slack: new_point copies fixed blocks */
    if (!o->offset || !o->digit || !o->mask || !o->prefix || !o->cur)
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
    for (size_t h = 0; h < d->nreg; h++) {
        const rf_grid *e = d->reg[h];
        for (size_t i = 0; i < n; i++)
            for (size_t l = 0; l < g->radix[i]; l++)
                if (bit_test(e->member[i], words_for(d->nvalues[i]) + 1, g->vidx[i][l]))
                    o->mask[(o->offset[i] + l) * o->words + h / WORD_BITS] |= UINT64_C(1) << (h % WORD_BITS);
    }
    for (size_t w = 0; w < o->words; w++)
        o->prefix[w] = d->nreg ? ~UINT64_C(0) : 0;
    for (size_t i = 0; i < n; i++) {
        o->cur[i] = d->values[i][g->vidx[i][0]];
        set_tuple(o->tup, d->tw, i, g->vidx[i][0]);
    }
    return odometer_tail(o, d, g, err);
}

/* Set the tail digits from the flattened tail digit t (last input fastest). */
static void tail_digits(odometer *o, const rf_grid *g, size_t t)
{
    for (size_t i = o->n; i-- > o->head;) {
        o->digit[i] = t % g->radix[i];
        t /= g->radix[i];
    }
}

/* Choose the tail and tabulate its masks, values and tuple bytes. */
static rf_status odometer_tail(odometer *o, const struct rf_tm_data *d, const rf_grid *g, rf_error *err)
{
    size_t n = o->n, W = o->words, R = 1, head = n, tw = d->tw;
    while (head > 0 && R < 16 && R * g->radix[head - 1] <= 4096)
        R *= g->radix[--head];
    if (head == n) /* a last radix above 4096: sweep it alone */
        R = g->radix[--head];
    size_t L = n - head;
    o->head = head;
    o->tail_count = R;
    o->tmask = malloc((R + 1) * W * sizeof *o->tmask);
    o->tany = o->tmask ? o->tmask + R * W : NULL;
    o->tx = calloc(R * L + 16, sizeof *o->tx); /* slack: rows are copied as fixed blocks */
    o->ttup = calloc(R * L * tw + 128, 1);
    if (!o->tmask || !o->tx || !o->ttup)
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
    memset(o->tany, 0, W * sizeof *o->tany);
    for (size_t t = 0; t < R; t++) {
        tail_digits(o, g, t);
        for (size_t w = 0; w < W; w++)
            o->tmask[t * W + w] = ~UINT64_C(0);
        for (size_t i = head; i < n; i++) {
            uint32_t v = g->vidx[i][o->digit[i]];
            for (size_t w = 0; w < W; w++)
                o->tmask[t * W + w] &= o->mask[(o->offset[i] + o->digit[i]) * W + w];
            o->tx[t * L + (i - head)] = d->values[i][v];
            set_tuple(o->ttup + t * L * tw, tw, i - head, v);
        }
        for (size_t w = 0; w < W; w++)
            o->tany[w] |= o->tmask[t * W + w];
    }
    tail_digits(o, g, 0);
    return RF_OK;
}

/* Recompute the prefix ANDs of inputs from..upto-1. */
static inline void odometer_prefix(odometer *o, size_t from, size_t upto)
{
    size_t W = o->words;
    if (W == 1) {
        for (size_t i = from; i < upto; i++)
            o->prefix[i + 1] = o->prefix[i] & o->mask[o->offset[i] + o->digit[i]];
        return;
    }
    for (size_t i = from; i < upto; i++) {
        const uint64_t *a = o->prefix + i * W, *b = o->mask + (o->offset[i] + o->digit[i]) * W;
        uint64_t *c = o->prefix + (i + 1) * W;
        for (size_t w = 0; w < W; w++)
            c[w] = a[w] & b[w];
    }
}

/* First earlier grid holding the current point, or SIZE_MAX if it is new. */
static size_t odometer_first_holder(const odometer *o)
{
    const uint64_t *acc = o->prefix + o->n * o->words;
    for (size_t w = 0; w < o->words; w++)
        if (acc[w])
            return w * WORD_BITS + (size_t)__builtin_ctzll(acc[w]);
    return SIZE_MAX;
}

/* Advance the head inputs (the tail is swept by the caller); returns the
 * lowest input changed, or SIZE_MAX after the last row. */
static inline size_t odometer_next_row(odometer *o, const struct rf_tm_data *d, const rf_grid *g)
{
    for (size_t i = o->head; i-- > 0;) {
        size_t l = ++o->digit[i] < g->radix[i] ? o->digit[i] : (o->digit[i] = 0);
        o->cur[i] = d->values[i][g->vidx[i][l]];
        set_tuple(o->tup, d->tw, i, g->vidx[i][l]);
        if (l)
            return i;
    }
    return SIZE_MAX;
}

/* Id the earlier grid e gave the current point. */
static uint32_t id_in(const struct rf_tm_data *d, const rf_grid *e, const odometer *o, const rf_grid *g)
{
    size_t pos = 0;
    for (size_t i = 0; i < d->n; i++)
        pos += bit_rank(e->member[i], g->vidx[i][o->digit[i]]) * e->stride[i];
    return e->ids[pos];
}

/* Room for `extra` more points in the tuples and outputs (grown at least
 * geometrically, so that building a family of grids copies little). */
rf_status rf_tm_reserve(struct rf_tm_data *d, size_t extra, rf_error *err)
{
    size_t need = d->npoints + extra;
    if (need <= d->cap_points)
        return RF_OK;
    size_t cap = need > 2 * d->cap_points ? need : 2 * d->cap_points;
    void *t = realloc(d->tuples, cap * d->n * d->tw + SLACK_BYTES);
    if (t)
        d->tuples = t;
    double *y = t ? malloc(cap * d->n_out * sizeof(double)) : NULL;
    if (!t || !y)
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM points (%zu)", need);
    for (size_t k = 0; d->y && k < d->n_out; k++) /* columns move to their new length */
        memcpy(y + k * cap, d->y + k * d->cap_points, d->npoints * sizeof(double));
    free(d->y);
    d->y = y;
    d->cap_points = cap;
    return RF_OK;
}

/* Room for every point of g in the registry, the tuples and the outputs
 * (grown geometrically), and for a full chunk of input vectors. */
static rf_status grid_reserve(struct rf_tm_data *d, const rf_grid *g, int with_ids, rf_error *err)
{
    if (d->nreg == d->capreg) {
        size_t cap = d->capreg ? 2 * d->capreg : 32;
        rf_grid **r = realloc(d->reg, cap * sizeof *r);
        if (!r)
            return rf_fail(err, RF_ENOMEM, "out of memory for the TM grid");
        d->reg = r;
        d->capreg = cap;
    }
    if (!with_ids)
        return RF_OK;
    if (g->count > UINT32_MAX - 1 - d->npoints)
        return rf_fail(err, RF_ECAP, "the TM grids have more points than this build can index");
    size_t need = d->npoints + g->count;
    rf_status st = rf_tm_reserve(d, g->count, err);
    if (st)
        return st;
    size_t chunk = d->chunk ? d->chunk : need - d->xfirst;
    if (chunk > d->xcap) {
        double *x = realloc(d->xbuf, chunk * d->n * sizeof(double) + SLACK_BYTES);
        if (x)
            d->xbuf = x;
        double *yb = x ? realloc(d->ybuf, chunk * d->n_out * sizeof(double)) : NULL;
        if (!x || !yb)
            return rf_fail(err, RF_ENOMEM, "out of memory for the TM points (%zu)", chunk);
        d->ybuf = yb;
        d->xcap = chunk;
    }
    return RF_OK;
}

/* A repeated point at tail digit t of the current row: its id from the
 * first earlier grid holding it. */
static uint32_t repeated_id(struct rf_tm_data *d, const rf_grid *g, odometer *o, size_t t)
{
    tail_digits(o, g, t);
    odometer_prefix(o, o->head, o->n);
    uint32_t id = id_in(d, d->reg[odometer_first_holder(o)], o, g);
    tail_digits(o, g, 0);
    return id;
}

/* Copy a short vector as fixed blocks (the buffers have SLACK_BYTES to
 * spare), which the compiler inlines: a call to memcpy per point would cost
 * more than the copy. */
static inline void copy_head(void *restrict dst, const void *restrict src, size_t bytes)
{
    if (bytes <= 16) {
        memcpy(dst, src, 16);
    } else if (bytes <= 128) {
        memcpy(dst, src, 64);
        if (bytes > 64)
            memcpy((char *)dst + 64, (const char *)src + 64, 64);
    } else {
        memcpy(dst, src, bytes);
    }
}

/* Is the point at position l of the row in an earlier grid? */
static inline int in_earlier(size_t W, const uint64_t *pre, const uint64_t *mask, size_t l)
{
    if (W == 1)
        return (pre[0] & mask[l]) != 0;
    uint64_t any = 0;
    for (size_t w = 0; w < W; w++)
        any |= pre[w] & mask[l * W + w];
    return any != 0;
}

/* A row none of whose points an earlier grid holds, written at once: the
 * ids, tuples and input vectors of R new points (room checked by the caller). */
static void new_row(struct rf_tm_data *d, const odometer *o, uint32_t *ids)
{
    const size_t n = d->n, head = o->head, L = n - head, R = o->tail_count, tw = d->tw, rowlen = n * tw;
    const double *cur = o->cur, *tx = o->tx;
    const unsigned char *tup = o->tup, *ttup = o->ttup;
    const size_t np = d->npoints;
    double *x = d->xbuf + d->xcount * n;
    unsigned char *tp = (unsigned char *)d->tuples + np * rowlen;
    for (size_t t = 0; t < R; t++, x += n, tp += rowlen) {
        copy_head(x, cur, head * sizeof(double)); /* the head, then the tail over what spills */
        copy_head(x + head, tx + t * L, L * sizeof(double));
        copy_head(tp, tup, head * tw);
        copy_head(tp + head * tw, ttup + t * L * tw, L * tw);
        ids[t] = (uint32_t)(np + t);
    }
    d->npoints = np + R;
    d->xcount += R;
}

/* One row of the grid: the tail sweeps its tail_count values, the head is
 * fixed (its AND of earlier-grid sets is o->prefix[head]).  *p is the
 * position of the row's first point in the grid.  A new point gets the next
 * id, its tuple, and its input vector in the buffer, which is evaluated
 * (flushed) when full.  The state lives in locals while the row is swept:
 * the byte stores of the tuples could alias any field of d or o. */
static rf_status grid_row(struct rf_tm_data *d, rf_grid *g, odometer *o, size_t *p, int with_ids, rf_error *err)
{
    const size_t W = o->words, n = d->n, head = o->head, L = n - head, R = o->tail_count, tw = d->tw;
    const size_t rowlen = n * tw;
    const uint64_t *pre = o->prefix + head * W, *tmask = o->tmask;
    const double *cur = o->cur, *tx = o->tx;
    const unsigned char *tup = o->tup, *ttup = o->ttup;
    uint32_t *ids = with_ids ? g->ids + *p : NULL;
    const size_t limit = d->limit ? d->limit : SIZE_MAX, xcap = d->xcap, chunked = d->chunk != 0;
    size_t np = d->npoints, xc = d->xcount;
    double *xb = d->xbuf;
    unsigned char *tb = d->tuples;
    rf_status st = RF_OK;
    if (with_ids && !in_earlier(W, pre, o->tany, 0) && np + R <= limit && xc + R <= xcap) {
        new_row(d, o, ids); /* the common case: every point new, no test per point */
        *p += R;
        return chunked && d->xcount == xcap ? d->flush(d->flush_user, err) : RF_OK;
    }
    for (size_t t = 0; t < R; t++) {
        if (in_earlier(W, pre, tmask, t)) {
            if (with_ids)
                ids[t] = repeated_id(d, g, o, t);
            continue;
        }
        if (np >= limit) {
            st = rf_fail(err, RF_ECAP, "more than %zu distinct points", d->limit);
            break;
        }
        if (!with_ids) {
            np++;
            continue;
        }
        double *x = xb + xc * n;
        unsigned char *tp = tb + np * rowlen;
        copy_head(x, cur, head * sizeof(double)); /* the head, then the tail over what spills */
        copy_head(x + head, tx + t * L, L * sizeof(double));
        copy_head(tp, tup, head * tw);
        copy_head(tp + head * tw, ttup + t * L * tw, L * tw);
        ids[t] = (uint32_t)np++;
        if (++xc == xcap && chunked) {
            d->npoints = np;
            d->xcount = xc;
            if ((st = d->flush(d->flush_user, err)))
                break;
            xc = d->xcount;
            xb = d->xbuf;
        }
    }
    d->npoints = np;
    d->xcount = xc;
    *p += R;
    return st;
}

static rf_status grid_enumerate(struct rf_tm_data *d, rf_grid *g, int with_ids, rf_error *err)
{
    size_t first = d->npoints;
    odometer o;
    rf_status st = odometer_init(&o, d, g, err);
    if (!st && with_ids && !(g->ids = malloc((g->count ? g->count : 1) * sizeof(uint32_t))))
        st = rf_fail(err, RF_ENOMEM, "out of memory for the TM grid (%zu points)", g->count);
    if (!st && g->count > 0) {
        odometer_prefix(&o, 0, o.head);
        size_t p = 0, changed = 0;
        while (!st && changed != SIZE_MAX) {
            if (d->stop && atomic_load_explicit(d->stop, memory_order_relaxed)) {
                st = rf_fail(err, RF_EINTERRUPTED, "interrupted while enumerating the TM's grid points (%zu of "
                             "the %zu of a grid)", p, g->count);
                break;
            }
            st = grid_row(d, g, &o, &p, with_ids, err);
            changed = odometer_next_row(&o, d, g);
            if (changed != SIZE_MAX)
                odometer_prefix(&o, changed, o.head);
        }
    }
    odometer_free(&o);
    g->first_id = (uint32_t)first;
    g->consecutive = with_ids && !st && d->npoints - first == g->count; /* new points get consecutive ids */
    return st;
}

/* Build grid g from per-input value lists (vals[i], cnt[i] ascending),
 * register its points (ids only if with_ids; otherwise they are counted) and
 * the grid itself; *requested grows by the grid size. */
rf_status rf_tm_grid_build(struct rf_tm_data *d, rf_grid *g, double *const *vals, const size_t *cnt,
                           size_t *requested, int with_ids, rf_error *err)
{
    rf_status st = grid_lists(d, g, vals, cnt, err);
    if (!st)
        st = grid_reserve(d, g, with_ids, err);
    if (!st)
        st = grid_enumerate(d, g, with_ids, err);
    if (st)
        return st;
    *requested += g->count;
    d->reg[d->nreg++] = g;
    return RF_OK;
}
