/* terrain_hazard_hist.c - the hazard accumulators' sparse histograms
 * (fixed log-spaced bins, merge, quantiles) and the pending updates of a
 * trajectory's end applied sorted (terrain_hazard_internal.h). */
#include "trajectory/terrain_hazard_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- bins ---- */

#define BIN_BITS_DROPPED 46 /* 52 mantissa bits - 6 (64 = 2^6 bins per octave) */

uint64_t hz_bin_of(double v)
{
    if (!(v >= TERRAIN_HAZARD_FLOOR)) /* and NaN (not stored) */
        return 0;
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    return bits >> BIN_BITS_DROPPED;
}

/* The lower edge of bin b (b > 0); that of b + 1 is its upper edge. */
static double bin_edge(uint64_t b)
{
    uint64_t bits = b << BIN_BITS_DROPPED;
    double v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

static int hist_reserve(hz_hist *hh, uint32_t n)
{
    if (n <= hh->cap)
        return 1;
    uint32_t cap = hh->cap ? hh->cap : 4;
    while (cap < n)
        cap *= 2;
    uint64_t *v = realloc(hh->v, cap * sizeof *v);
    if (!v)
        return 0;
    hh->v = v, hh->cap = cap;
    return 1;
}

/* Add `count` values in bin b, searching from entry `from` (the bins of one
 * flush come in increasing order); the entry it is in, NO_POS if out of memory. */
static uint32_t hist_add_bin(hz_hist *hh, uint64_t b, uint64_t count, uint32_t from)
{
    uint32_t lo = from, hi = hh->n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if ((hh->v[mid] >> BIN_SHIFT) < b)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo < hh->n && (hh->v[lo] >> BIN_SHIFT) == b) {
        hh->v[lo] += count;
        return lo;
    }
    if (!hist_reserve(hh, hh->n + 1))
        return NO_POS;
    memmove(hh->v + lo + 1, hh->v + lo, (hh->n - lo) * sizeof *hh->v);
    hh->v[lo] = b << BIN_SHIFT | count;
    hh->n++;
    return lo;
}

/* into += from, bin by bin. */
int hz_hist_merge(hz_hist *into, const hz_hist *from)
{
    if (!from->n)
        return 1;
    uint32_t cap = 4;
    while (cap < into->n + from->n)
        cap *= 2;
    uint64_t *v = malloc(cap * sizeof *v);
    if (!v)
        return 0;
    uint32_t a = 0, b = 0, n = 0;
    while (a < into->n || b < from->n) {
        uint64_t ba = a < into->n ? into->v[a] >> BIN_SHIFT : UINT64_MAX;
        uint64_t bb = b < from->n ? from->v[b] >> BIN_SHIFT : UINT64_MAX;
        if (ba == bb)
            v[n++] = into->v[a++] + (from->v[b++] & COUNT_MASK);
        else
            v[n++] = ba < bb ? into->v[a++] : from->v[b++];
    }
    free(into->v);
    into->v = v, into->n = n, into->cap = cap;
    return 1;
}

/* The order statistic k (0-based) of the n values of a histogram whose
 * largest value is vmax (see the top of the file). */
static double hist_order(const hz_hist *hh, uint64_t n, double vmax, uint64_t k)
{
    if (k + 1 >= n)
        return vmax;
    uint64_t below = 0;
    for (uint32_t e = 0; e < hh->n; e++) {
        uint64_t c = hh->v[e] & COUNT_MASK;
        if (k < below + c) {
            uint64_t b = hh->v[e] >> BIN_SHIFT;
            if (b == 0)
                return 0;
            double rank = ((double)(k - below) + 0.5) / (double)c, lo = bin_edge(b);
            double est = lo + (bin_edge(b + 1) - lo) * rank;
            return est < vmax ? est : vmax;
        }
        below += c;
    }
    return vmax;
}

static uint64_t hist_total(const hz_hist *hh)
{
    uint64_t n = 0;
    for (uint32_t e = 0; e < hh->n; e++)
        n += hh->v[e] & COUNT_MASK;
    return n;
}

/* Hyndman-Fan type 7 at p in [0, 1], as quantile_sorted in stats.c. */
double hz_hist_quantile(const hz_hist *hh, double vmax, double p)
{
    uint64_t n = hist_total(hh);
    double h = (double)(n - 1) * p;
    uint64_t lo = (uint64_t)floor(h);
    if (lo + 1 >= n)
        return vmax;
    double a = hist_order(hh, n, vmax, lo), b = hist_order(hh, n, vmax, lo + 1);
    return a + (h - (double)lo) * (b - a);
}

/* ---- pending updates ---- */

/* Sort n keys (LSD radix over the bits in use, in as few passes of at most
 * 12-bit digits as they need: 3 for the usual 25 to 36 bits; the buffers
 * swap roles each pass, one copy at the end if needed); tmp: scratch of n. */
static void radix_sort(uint64_t *k, uint64_t *tmp, size_t n)
{
    uint64_t top = 0;
    for (size_t i = 0; i < n; i++)
        top |= k[i];
    int bits = 0;
    while (bits < 64 && (top >> bits))
        bits++;
    int passes = (bits + 11) / 12, digit = passes ? (bits + passes - 1) / passes : 0;
    uint64_t mask = (UINT64_C(1) << digit) - 1, *from = k, *to = tmp;
    for (int pass = 0, shift = 0; pass < passes; pass++, shift += digit) {
        size_t cnt[4096] = {0};
        for (size_t i = 0; i < n; i++)
            cnt[(from[i] >> shift) & mask]++;
        for (size_t d = 0, sum = 0; d <= mask; d++) {
            size_t c = cnt[d];
            cnt[d] = sum, sum += c;
        }
        for (size_t i = 0; i < n; i++)
            to[cnt[(from[i] >> shift) & mask]++] = from[i];
        uint64_t *sw = from;
        from = to, to = sw;
    }
    if (from != k)
        memcpy(k, from, n * sizeof *k);
}

/* Apply the pending updates (see the top of the file). */
void hz_pend_flush(rf_terrain_hazard *h)
{
    if (!h->n_pend)
        return;
    radix_sort(h->pend, h->pend_tmp, h->n_pend);
    uint64_t binmask = (UINT64_C(1) << PEND_BIN_BITS) - 1, prev_hist = UINT64_MAX;
    uint32_t from = 0;
    for (size_t i = 0; i < h->n_pend;) {
        uint64_t key = h->pend[i], count = 1;
        while (i + count < h->n_pend && h->pend[i + count] == key)
            count++;
        i += count;
        uint64_t hist = key >> PEND_BIN_BITS;
        hz_rec *r = &h->rec[hist >> 1];
        if (hist != prev_hist)
            from = 0, prev_hist = hist;
        from = hist_add_bin(hist & 1 ? &r->h : &r->e, key & binmask, count, from);
        if (from == NO_POS)
            h->nomem = 1, from = 0;
    }
    h->n_pend = 0;
}

/* The readers' flush (see the top of the file: the buffer is private state). */
void hz_pend_flush_const(const rf_terrain_hazard *h) { hz_pend_flush((rf_terrain_hazard *)h); }

void hz_pend_add(rf_terrain_hazard *h, uint32_t rec, int height, double value)
{
    if (!h->pend) {
        h->pend = malloc(PEND_MAX * sizeof *h->pend), h->pend_tmp = malloc(PEND_MAX * sizeof *h->pend_tmp);
        if (!h->pend || !h->pend_tmp) {
            h->nomem = 1;
            free(h->pend), free(h->pend_tmp), h->pend = h->pend_tmp = NULL;
            return;
        }
    }
    if (h->n_pend == PEND_MAX)
        hz_pend_flush(h);
    h->pend[h->n_pend++] = ((uint64_t)rec << 1 | (uint64_t)(height != 0)) << PEND_BIN_BITS | hz_bin_of(value);
}
