/* terrain_hazard.c - hazard raster accumulators (issue 28 item 5).
 *
 * The output grid: square cells of spec->terrain->raster_cell (0: the DEM's
 * dx) over the DEM's extent from its south-west corner; cell (i, j) covers
 * [x0 + i c, x0 + (i+1) c) x [y0 + j c, y0 + (j+1) c), j to the north (the
 * last row and column may reach past the DEM).
 *
 * A trajectory's pieces are walked over the grid (walk: the cells of a
 * straight map segment in order); each cell it touches keeps, for this
 * trajectory only, the largest total kinetic energy and passing height
 * (the touch list).  At its end every touched cell counts one passage and
 * puts the trajectory's two maxima into the cell's histograms; the cell of
 * a stopped block's end point counts a deposit.
 *
 * Storage: a dense index per grid cell (4 bytes; 0 = never touched) into
 * records of the touched cells only (sizeof(hz_rec) = 72 bytes each) holding
 * passages, deposits, the exact maxima and two sparse histograms; a
 * histogram stores only the bins that were hit, one 64-bit word per bin
 * (bin number << 47 | count), sorted by bin.  The bins are fixed: each
 * octave [2^e, 2^(e+1)) is cut into TERRAIN_HAZARD_BINS_PER_OCTAVE = 64 equal
 * bins [2^e (1 + k/64), 2^e (1 + (k+1)/64)) (log-spaced octaves, as
 * HdrHistogram), from TERRAIN_HAZARD_FLOOR = 2^-20 up, and a zero bin below
 * it.  A value's bin number is the top 17 bits of its IEEE-754 double after
 * the sign (exponent and 6 mantissa bits): no logarithm, and bin edges that
 * are exact doubles.  Every finite double >= the floor has one of
 * (1024 + 20) * 64 = 66 816 bins, so a touched cell costs 72 + 8 (bins hit by
 * the energy + bins hit by the height) bytes (in practice a few hundred
 * bins: the values a cell sees span a few octaves): the memory does not
 * grow with the number of trajectories.  Merging adds counts and takes
 * maxima of maxima: integers and fmax, so the same bits in any order.
 *
 * Pending updates.  The histogram updates of a trajectory's end are not
 * applied at once (each was a cache miss on its cell's bins, a quarter of
 * the run's time): they are kept as keys (record << 18 | histogram << 17 |
 * bin) in a buffer of PEND_MAX and applied when it is full, sorted (LSD
 * radix), so each histogram is visited once per flush for all its updates.
 * Counts are integers: the histograms are the same in any order of
 * application.  Every reader (merge, pack, bands, bytes) applies the
 * pending updates first; these readers take a const accumulator and write
 * its private buffer (the object is never const itself): an accumulator is
 * not read by two threads at once.
 *
 * Percentiles: Hyndman-Fan type 7 as rf_traj_percentiles_at (stats.c),
 * q = v[lo] + f (v[lo+1] - v[lo]) with h = (n - 1) p, lo = floor(h),
 * f = h - lo, v[n - 1] (the exact max) when lo + 1 >= n, where the order
 * statistic v[k] is estimated inside its bin [L, U) by linear interpolation
 * of its rank among the c values of the bin:
 * est = L + (U - L) (k - C + 1/2) / c (C: the values in lower bins), at most
 * the exact max; the zero bin estimates 0.
 * Error bound: v[k] and est both lie in [L, U] (est <= max, v[k] <= max),
 * so |est - v[k]| <= U - L = 2^e / 64 <= L / 64 <= v[k] / 64.  q is a convex
 * combination of two order statistics with v >= 0, so
 * |q_est - q| <= (1 - f) v[lo] / 64 + f v[lo + 1] / 64 = q / 64:
 * TERRAIN_HAZARD_REL_ERROR = 1/64 = 0.0156 (the bound is attained within a
 * bin that starts an octave, see the tests; the float32 bands add 2^-24).
 * Values below the floor (2^-20 = 9.5e-7 J or m) are estimated as 0: an
 * absolute error below the floor on top (exact zeros, such as the height of
 * a block on the ground, are exact). */
#include "trajectory/terrain_internal.h"

#include <stdlib.h>
#include <string.h>

#define BIN_SHIFT 47
#define COUNT_MASK ((UINT64_C(1) << BIN_SHIFT) - 1)
#define NO_POS UINT32_MAX
/* Two crossings of cell lines closer than this (in the segment's parameter,
 * 0..1) are one crossing of their corner. */
#define CORNER_TIE 1e-12

typedef struct {
    uint64_t *v;                /* bin << 47 | count, sorted by bin */
    uint32_t n, cap;
} hz_hist;

typedef struct {
    uint64_t passages, deposits;
    double e_max, h_max;        /* exact maxima [J], [m]; -INFINITY: none */
    hz_hist e, h;
    uint32_t cell;              /* j nx + i */
    uint32_t pos;               /* its entry in the current trajectory's touch list (if valid) */
} hz_rec;

typedef struct {
    uint32_t rec;
    double e, h;                /* this trajectory's maxima in the cell (NaN: none) */
} hz_touch;

struct rf_terrain_hazard {
    size_t nx, ny;
    double x0, y0, cell;
    unsigned stats;
    int dem_grid;               /* the grid has the DEM's cells (size and count; the origin is checked
                                 * per piece): a piece known to lie in one DEM cell is that cell's alone */
    uint32_t *slot;             /* nx * ny: 0 untouched, else 1 + record */
    hz_rec *rec;
    size_t n_rec, cap_rec;
    hz_touch *touch;
    size_t n_touch, cap_touch;
    uint64_t *pend, *pend_tmp;  /* PEND_MAX pending histogram updates (keys), and the sort's scratch */
    size_t n_pend;
    int nomem;
};

#define PEND_MAX 262144
#define PEND_BIN_BITS 17        /* a bin number has 17 bits (exponent and 6 mantissa bits) */

/* The larger of a and b, NaN only if both are (fmax, inlined: the library
 * call was a tenth of the time of a piece). */
static inline double max_of(double a, double b) { return b > a || a != a ? b : a; }

/* ---- bins ---- */

#define BIN_BITS_DROPPED 46 /* 52 mantissa bits - 6 (64 = 2^6 bins per octave) */

static uint64_t bin_of(double v)
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
static int hist_merge(hz_hist *into, const hz_hist *from)
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
static double hist_quantile(const hz_hist *hh, double vmax, double p)
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

/* Sort n keys (LSD radix, 11-bit digits over the bits in use); tmp: scratch of n. */
static void radix_sort(uint64_t *k, uint64_t *tmp, size_t n)
{
    uint64_t top = 0;
    for (size_t i = 0; i < n; i++)
        top |= k[i];
    for (int shift = 0; shift < 64 && (top >> shift); shift += 11) {
        size_t cnt[2048] = {0};
        for (size_t i = 0; i < n; i++)
            cnt[(k[i] >> shift) & 2047]++;
        for (size_t d = 0, sum = 0; d < 2048; d++) {
            size_t c = cnt[d];
            cnt[d] = sum, sum += c;
        }
        for (size_t i = 0; i < n; i++)
            tmp[cnt[(k[i] >> shift) & 2047]++] = k[i];
        memcpy(k, tmp, n * sizeof *k);
    }
}

/* Apply the pending updates (see the top of the file). */
static void pend_flush(rf_terrain_hazard *h)
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
static void pend_flush_const(const rf_terrain_hazard *h) { pend_flush((rf_terrain_hazard *)h); }

static void pend_add(rf_terrain_hazard *h, uint32_t rec, int height, double value)
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
        pend_flush(h);
    h->pend[h->n_pend++] = ((uint64_t)rec << 1 | (uint64_t)(height != 0)) << PEND_BIN_BITS | bin_of(value);
}

/* ---- records and the touch list ---- */

/* The record of grid cell `cell`, made on first use; NO_POS when out of memory. */
static uint32_t record_at(rf_terrain_hazard *h, size_t cell)
{
    if (h->slot[cell])
        return h->slot[cell] - 1;
    if (h->n_rec == h->cap_rec) {
        size_t cap = h->cap_rec ? 2 * h->cap_rec : 64;
        hz_rec *r = realloc(h->rec, cap * sizeof *r);
        if (!r) {
            h->nomem = 1;
            return NO_POS;
        }
        h->rec = r, h->cap_rec = cap;
    }
    hz_rec *r = &h->rec[h->n_rec];
    memset(r, 0, sizeof *r);
    r->e_max = r->h_max = -INFINITY;
    r->cell = (uint32_t)cell, r->pos = NO_POS;
    h->slot[cell] = (uint32_t)++h->n_rec;
    return (uint32_t)(h->n_rec - 1);
}

static void touch(rf_terrain_hazard *h, size_t cell, double e, double ht)
{
    uint32_t k = record_at(h, cell);
    if (k == NO_POS)
        return;
    uint32_t pos = h->rec[k].pos;
    if (pos < h->n_touch && h->touch[pos].rec == k) {
        hz_touch *t = &h->touch[pos];
        t->e = max_of(t->e, e), t->h = max_of(t->h, ht);
        return;
    }
    if (h->n_touch == h->cap_touch) {
        size_t cap = h->cap_touch ? 2 * h->cap_touch : 64;
        hz_touch *t = realloc(h->touch, cap * sizeof *t);
        if (!t) {
            h->nomem = 1;
            return;
        }
        h->touch = t, h->cap_touch = cap;
    }
    h->rec[k].pos = (uint32_t)h->n_touch;
    h->touch[h->n_touch++] = (hz_touch){k, e, ht};
}

/* ---- the map walk ---- */

typedef struct {
    rf_terrain_hazard *h;
    const rf_terrain *dem;
    const terrain_piece *pc;
    double mass, T;
    double mx0, my0, mdx, mdy;  /* map path: (mx0, my0) + s (mdx, mdy), s in [0, 1], tau = s T */
    double s_last, e_last, h_last;  /* energy and height at s_last, the last cell's exit (its next entry) */
} hz_piece;

static double piece_energy(const hz_piece *q, double tau)
{
    const terrain_piece *pc = q->pc;
    double v2 = 0;
    for (int k = 0; k < 3; k++) {
        double vk = pc->v[k] + pc->a[k] * tau;
        v2 += vk * vk;
    }
    return 0.5 * q->mass * v2 + pc->e_rot;
}

/* Height of the piece over the ground at s (NaN off the surface). */
static double piece_height(const hz_piece *q, double s)
{
    const terrain_piece *pc = q->pc;
    double tau = s * q->T, zg;
    if (!rf_terrain_height(q->dem, q->mx0 + s * q->mdx, q->my0 + s * q->mdy, &zg, NULL))
        return NAN;
    return pc->p[2] + pc->v[2] * tau + 0.5 * pc->a[2] * tau * tau - zg;
}

/* The part s in [sa, sb] of the piece lies in cell (i, j): energy at its
 * ends (convex in tau: exact); height at its ends, its middle and the apex
 * of the path if inside (0 on the ground). */
static void piece_cell(hz_piece *q, size_t i, size_t j, double sa, double sb)
{
    rf_terrain_hazard *h = q->h;
    int energy = h->stats & RF_TERRAIN_ENERGY, height = (h->stats & RF_TERRAIN_HEIGHT) && !q->pc->on_ground;
    int again = sa == q->s_last;
    double e_in = NAN, e_out = NAN, h_in = NAN, h_out = NAN, ht = NAN;
    if (energy) {
        e_in = again ? q->e_last : piece_energy(q, sa * q->T);
        e_out = piece_energy(q, sb * q->T);
    }
    if (height) {
        h_in = again ? q->h_last : piece_height(q, sa);
        h_out = piece_height(q, sb);
        ht = max_of(max_of(h_in, h_out), piece_height(q, 0.5 * (sa + sb)));
        double az = q->pc->a[2], s_apex = az < 0 && q->T > 0 ? -q->pc->v[2] / az / q->T : -1;
        if (s_apex > sa && s_apex < sb)
            ht = max_of(ht, piece_height(q, s_apex));
        if (ht < 0)
            ht = 0;
    } else if (h->stats & RF_TERRAIN_HEIGHT)
        ht = 0; /* on the ground */
    q->s_last = sb, q->e_last = e_out, q->h_last = h_out;
    touch(h, j * h->nx + i, max_of(e_in, e_out), ht);
}

/* The parameters [*sa, *sb] of f0 + s d inside [0, hi]; 0 if none. */
static int clip_axis(double f0, double d, double hi, double *sa, double *sb)
{
    if (d == 0)
        return f0 >= 0 && f0 <= hi;
    double s0 = -f0 / d, s1 = (hi - f0) / d;
    if (s0 > s1) {
        double t = s0;
        s0 = s1, s1 = t;
    }
    *sa = s0 > *sa ? s0 : *sa, *sb = s1 < *sb ? s1 : *sb;
    return *sa <= *sb;
}

/* Start cell index along one axis at f going in direction d: a start on a
 * cell line going down belongs to the cell below. */
static long long start_index(double f, double d)
{
    double fl = floor(f);
    return (long long)fl - (d < 0 && f == fl);
}

/* Next line crossed along one axis from cell index c (INFINITY: none). */
static double next_crossing(long long c, double f0, double d)
{
    if (d > 0)
        return ((double)(c + 1) - f0) / d;
    if (d < 0)
        return ((double)c - f0) / d;
    return INFINITY;
}

/* The cells of the map segment in grid units (fx0, fy0) + s (gdx, gdy),
 * s in [0, 1], in order, each with its parameter interval; two crossings at
 * a corner (to CORNER_TIE) step diagonally; a segment along a cell line
 * lies in the cells to its north / east (half-open cells). */
static void walk(hz_piece *q, double fx0, double fy0, double gdx, double gdy)
{
    const rf_terrain_hazard *h = q->h;
    double sa = 0, sb = 1;
    if (!clip_axis(fx0, gdx, (double)h->nx, &sa, &sb) || !clip_axis(fy0, gdy, (double)h->ny, &sa, &sb))
        return;
    long long i = start_index(fx0 + sa * gdx, gdx), j = start_index(fy0 + sa * gdy, gdy);
    long long di = gdx > 0 ? 1 : -1, dj = gdy > 0 ? 1 : -1;
    size_t steps = 2 * (h->nx + h->ny) + 8; /* more than the lines a segment in the grid crosses */
    double s = sa;
    for (size_t k = 0; k < steps; k++) {
        double sx = next_crossing(i, fx0, gdx), sy = next_crossing(j, fy0, gdy);
        double sn = sx < sy ? sx : sy;
        int last = !(sn < sb);
        if (i >= 0 && j >= 0 && i < (long long)h->nx && j < (long long)h->ny)
            piece_cell(q, (size_t)i, (size_t)j, s, last ? sb : sn);
        if (last)
            break;
        int corner = fabs(sx - sy) <= CORNER_TIE;
        if (sx <= sy || corner)
            i += di;
        if (sy <= sx || corner)
            j += dj;
        s = sn;
    }
}

/* ---- the interface ---- */

static size_t cells_over(double width, double cell)
{
    double n = ceil(width / cell - 1e-9);
    return n < 1 ? 1 : (size_t)n;
}

rf_terrain_hazard *terrain_hazard_create(const rf_traj_spec *s, const rf_terrain *dem)
{
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    const rf_terrain_def *d = s ? s->terrain : NULL;
    double cell = d && d->raster_cell > 0 ? d->raster_cell : dx;
    if (!(cell > 0) || !((xmax - xmin) / cell < 1e9) || !((ymax - ymin) / cell < 1e9))
        return NULL;
    size_t nx = cells_over(xmax - xmin, cell), ny = cells_over(ymax - ymin, cell);
    if (nx * ny >= UINT32_MAX)
        return NULL;
    rf_terrain_hazard *h = calloc(1, sizeof *h);
    if (!h)
        return NULL;
    h->slot = calloc(nx * ny, sizeof *h->slot);
    if (!h->slot) {
        free(h);
        return NULL;
    }
    h->nx = nx, h->ny = ny, h->x0 = xmin, h->y0 = ymin, h->cell = cell;
    h->dem_grid = cell == dx && cell == dy && nx == dem->nx - 1 && ny == dem->ny - 1;
    h->stats = d ? d->statistics
                 : RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS | RF_TERRAIN_ENERGY |
                       RF_TERRAIN_HEIGHT;
    return h;
}

void terrain_hazard_begin(rf_terrain_hazard *h)
{
    if (h)
        h->n_touch = 0;
}

/* The walk's state for piece pc. */
static hz_piece piece_of(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc)
{
    hz_piece q = {h, dem, pc, mass, pc->T > 0 ? pc->T : 0, pc->p[0], pc->p[1], 0, 0, -1, NAN, NAN};
    for (int k = 0; k < 2; k++) {
        double end = pc->p[k] + pc->v[k] * q.T + 0.5 * pc->a[k] * q.T * q.T;
        *(k ? &q.mdy : &q.mdx) = end - pc->p[k];
    }
    return q;
}

void terrain_hazard_piece(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc)
{
    if (!h)
        return;
    hz_piece q = piece_of(h, dem, mass, pc);
    double fx0 = (q.mx0 - h->x0) / h->cell, fy0 = (q.my0 - h->y0) / h->cell;
    double gdx = q.mdx / h->cell, gdy = q.mdy / h->cell;
    if (isfinite(fx0) && isfinite(fy0) && isfinite(gdx) && isfinite(gdy))
        walk(&q, fx0, fy0, gdx, gdy);
}

void terrain_hazard_piece_in(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc,
                             size_t ci, size_t cj)
{
    if (!h)
        return;
    if (!h->dem_grid || h->x0 != dem->x0 || h->y0 != dem->y0 || h->cell != dem->dx || ci >= h->nx || cj >= h->ny) {
        terrain_hazard_piece(h, dem, mass, pc);
        return;
    }
    hz_piece q = piece_of(h, dem, mass, pc);
    piece_cell(&q, ci, cj, 0, 1);
}

void terrain_hazard_end(rf_terrain_hazard *h, int stopped, const double end[3])
{
    if (!h)
        return;
    for (size_t k = 0; k < h->n_touch; k++) {
        const hz_touch *t = &h->touch[k];
        hz_rec *r = &h->rec[t->rec];
        r->passages++;
        if ((h->stats & RF_TERRAIN_ENERGY) && isfinite(t->e)) {
            r->e_max = max_of(r->e_max, t->e);
            pend_add(h, t->rec, 0, t->e);
        }
        if ((h->stats & RF_TERRAIN_HEIGHT) && isfinite(t->h)) {
            r->h_max = max_of(r->h_max, t->h);
            pend_add(h, t->rec, 1, t->h);
        }
    }
    h->n_touch = 0;
    if (!stopped || !end)
        return;
    /* the cell of the end point (on the grid's last line: the last cell) */
    double fx = (end[0] - h->x0) / h->cell, fy = (end[1] - h->y0) / h->cell;
    if (!(fx >= 0 && fy >= 0 && fx <= (double)h->nx && fy <= (double)h->ny))
        return;
    size_t i = (size_t)fx < h->nx ? (size_t)fx : h->nx - 1, j = (size_t)fy < h->ny ? (size_t)fy : h->ny - 1;
    uint32_t k = record_at(h, j * h->nx + i);
    if (k != NO_POS)
        h->rec[k].deposits++;
}

void terrain_hazard_merge(rf_terrain_hazard *into, const rf_terrain_hazard *from)
{
    if (!into || !from)
        return;
    pend_flush(into), pend_flush_const(from);
    if (into->nx != from->nx || into->ny != from->ny || from->nomem) {
        into->nomem = 1; /* not the same grid (a bug) or an incomplete part: refuse the bands */
        return;
    }
    for (size_t k = 0; k < from->n_rec; k++) {
        const hz_rec *f = &from->rec[k];
        uint32_t m = record_at(into, f->cell);
        if (m == NO_POS)
            return;
        hz_rec *r = &into->rec[m];
        r->passages += f->passages, r->deposits += f->deposits;
        r->e_max = max_of(r->e_max, f->e_max), r->h_max = max_of(r->h_max, f->h_max);
        into->nomem |= !hist_merge(&r->e, &f->e) || !hist_merge(&r->h, &f->h);
    }
}

/* ---- packed accumulators (MPI) ---- */

/* Layout, 64-bit words in the machine's byte order: magic, nx, ny, n_rec;
 * per record: cell | n_e << 32, n_h, passages, deposits, e_max, h_max (the
 * doubles' bits), then the n_e + n_h histogram words. */
#define PACK_MAGIC UINT64_C(0x31465a4852525446) /* "FTRRHZF1" */

static size_t pack_words(const rf_terrain_hazard *h)
{
    size_t n = 4;
    for (size_t k = 0; k < h->n_rec; k++)
        n += 6 + (size_t)h->rec[k].e.n + h->rec[k].h.n;
    return n;
}

rf_status terrain_hazard_pack(const rf_terrain_hazard *h, uint64_t **buf, size_t *words, rf_error *err)
{
    *buf = NULL, *words = 0;
    pend_flush_const(h);
    if (h->nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory while accumulating the hazard rasters");
    size_t n = pack_words(h), w = 0;
    uint64_t *b = malloc(n * sizeof *b);
    if (!b)
        return rf_fail(err, RF_ENOMEM, "out of memory packing the hazard rasters (%zu bytes)", n * sizeof *b);
    b[w++] = PACK_MAGIC, b[w++] = h->nx, b[w++] = h->ny, b[w++] = h->n_rec;
    for (size_t k = 0; k < h->n_rec; k++) {
        const hz_rec *r = &h->rec[k];
        b[w++] = r->cell | (uint64_t)r->e.n << 32, b[w++] = r->h.n;
        b[w++] = r->passages, b[w++] = r->deposits;
        memcpy(&b[w++], &r->e_max, sizeof r->e_max), memcpy(&b[w++], &r->h_max, sizeof r->h_max);
        for (uint32_t e = 0; e < r->e.n; e++)
            b[w++] = r->e.v[e];
        for (uint32_t e = 0; e < r->h.n; e++)
            b[w++] = r->h.v[e];
    }
    *buf = b, *words = n;
    return RF_OK;
}

rf_status terrain_hazard_merge_packed(rf_terrain_hazard *into, const uint64_t *b, size_t words, rf_error *err)
{
    if (words < 4 || b[0] != PACK_MAGIC || b[1] != into->nx || b[2] != into->ny)
        return rf_fail(err, RF_EINVAL, "packed hazard rasters: not a %zu x %zu grid's accumulator", into->nx,
                       into->ny);
    size_t w = 4;
    pend_flush(into);
    rf_terrain_hazard one = *into; /* a one-record accumulator over the packed words */
    one.pend = one.pend_tmp = NULL, one.n_pend = 0;
    for (uint64_t k = 0; k < b[3]; k++) {
        if (words - w < 6 || (b[w] & 0xffffffffu) >= into->nx * into->ny ||
            (b[w] >> 32) + b[w + 1] > words - w - 6)
            return rf_fail(err, RF_EINVAL, "packed hazard rasters: record %llu is cut or out of the grid",
                           (unsigned long long)k);
        hz_rec r = {b[w + 2], b[w + 3], 0, 0, {NULL, 0, 0}, {NULL, 0, 0}, (uint32_t)(b[w] & 0xffffffffu), NO_POS};
        memcpy(&r.e_max, &b[w + 4], sizeof r.e_max), memcpy(&r.h_max, &b[w + 5], sizeof r.h_max);
        r.e.n = (uint32_t)(b[w] >> 32), r.h.n = (uint32_t)b[w + 1];
        r.e.v = (uint64_t *)(b + w + 6), r.h.v = (uint64_t *)(b + w + 6 + r.e.n);
        w += 6 + (size_t)r.e.n + r.h.n;
        one.rec = &r, one.n_rec = 1, one.nomem = 0;
        terrain_hazard_merge(into, &one);
    }
    if (into->nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory merging packed hazard rasters");
    return RF_OK;
}

void terrain_hazard_free(rf_terrain_hazard *h)
{
    if (!h)
        return;
    for (size_t k = 0; k < h->n_rec; k++)
        free(h->rec[k].e.v), free(h->rec[k].h.v);
    free(h->rec), free(h->touch), free(h->slot), free(h->pend), free(h->pend_tmp), free(h);
}

size_t terrain_hazard_bytes(const rf_terrain_hazard *h)
{
    pend_flush_const(h);
    size_t n = sizeof *h + h->nx * h->ny * sizeof *h->slot + h->cap_rec * sizeof *h->rec +
               h->cap_touch * sizeof *h->touch + (h->pend ? 2 * PEND_MAX * sizeof *h->pend : 0);
    for (size_t k = 0; k < h->n_rec; k++)
        n += ((size_t)h->rec[k].e.cap + h->rec[k].h.cap) * sizeof(uint64_t);
    return n;
}

void terrain_hazard_grid(const rf_terrain_hazard *h, size_t *nx, size_t *ny, double *x0, double *y0, double *cell)
{
    *nx = h->nx, *ny = h->ny, *x0 = h->x0, *y0 = h->y0, *cell = h->cell;
}

/* ---- bands ---- */

enum { B_PASSAGES, B_REACH, B_DEPOSITS, B_MAX, B_PERCENTILE };

typedef struct {
    int kind;                   /* B_* */
    int height;                 /* energy (0) or height (1) statistics */
    double level;               /* [%] for B_PERCENTILE */
} hz_band_def;

static float band_value(const hz_rec *r, const hz_band_def *b, size_t samples)
{
    const hz_hist *hh = b->height ? &r->h : &r->e;
    double vmax = b->height ? r->h_max : r->e_max;
    switch (b->kind) {
    case B_PASSAGES:
        return (float)r->passages;
    case B_REACH:
        return samples ? (float)((double)r->passages / (double)samples) : 0.0f;
    case B_DEPOSITS:
        return (float)r->deposits;
    case B_MAX:
        return hh->n ? (float)vmax : NAN;
    default:
        return hh->n ? (float)hist_quantile(hh, vmax, b->level / 100) : NAN;
    }
}

/* The list of bands the spec asks for, with their names. */
static size_t band_defs(unsigned stats, const rf_traj_spec *s, hz_band_def *def, char (*name)[48])
{
    static const double dflt[3] = {50, 95, 99};
    size_t nl = s && s->outputs.n_percentiles ? s->outputs.n_percentiles : 3;
    const double *lv = s && s->outputs.n_percentiles ? s->outputs.percentiles : dflt;
    size_t n = 0;
    static const char *simple[3] = {"passages", "reach_probability", "deposits"};
    static const unsigned bit[3] = {RF_TERRAIN_PASSAGES, RF_TERRAIN_REACH_PROBABILITY, RF_TERRAIN_DEPOSITS};
    for (int k = 0; k < 3; k++)
        if (stats & bit[k]) {
            def[n] = (hz_band_def){k, 0, 0};
            snprintf(name[n++], 48, "%s", simple[k]);
        }
    for (int ht = 0; ht < 2; ht++) {
        if (!(stats & (ht ? RF_TERRAIN_HEIGHT : RF_TERRAIN_ENERGY)))
            continue;
        const char *what = ht ? "height" : "energy";
        def[n] = (hz_band_def){B_MAX, ht, 0};
        snprintf(name[n++], 48, "%s_max", what);
        for (size_t l = 0; l < nl; l++) {
            char p[24];
            rf_traj_percentile_name(lv[l], p, sizeof p);
            def[n] = (hz_band_def){B_PERCENTILE, ht, lv[l]};
            snprintf(name[n++], 48, "%s_%s", what, p);
        }
    }
    return n;
}

rf_status terrain_hazard_bands(const rf_terrain_hazard *h, const rf_traj_spec *s, size_t samples, terrain_band **bands,
                               size_t *n, rf_error *err)
{
    *bands = NULL, *n = 0;
    pend_flush_const(h);
    if (h->nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory while accumulating the hazard rasters");
    hz_band_def def[3 + 2 * (1 + RF_TRAJ_MAX_PERCENTILES)];
    char name[3 + 2 * (1 + RF_TRAJ_MAX_PERCENTILES)][48];
    size_t nb = band_defs(h->stats, s, def, name), cells = h->nx * h->ny;
    terrain_band *b = calloc(nb ? nb : 1, sizeof *b);
    if (!b)
        return rf_fail(err, RF_ENOMEM, "out of memory for the hazard raster bands");
    for (size_t k = 0; k < nb; k++) {
        memcpy(b[k].name, name[k], sizeof b[k].name);
        b[k].unit = def[k].kind < B_MAX ? "" : def[k].height ? "m" : "J";
        b[k].data = malloc(cells * sizeof *b[k].data);
        if (!b[k].data) {
            terrain_bands_free(b, nb);
            return rf_fail(err, RF_ENOMEM, "out of memory for the hazard raster bands (%zu cells)", cells);
        }
        float none = def[k].kind < B_MAX ? 0.0f : NAN;
        for (size_t c = 0; c < cells; c++)
            b[k].data[c] = none;
        for (size_t r = 0; r < h->n_rec; r++)
            b[k].data[h->rec[r].cell] = band_value(&h->rec[r], &def[k], samples);
    }
    *bands = b, *n = nb;
    return RF_OK;
}

void terrain_bands_free(terrain_band *b, size_t n)
{
    for (size_t k = 0; b && k < n; k++)
        free(b[k].data);
    free(b);
}
