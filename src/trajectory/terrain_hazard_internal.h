/* terrain_hazard_internal.h - the hazard raster accumulators' storage (issue
 * 28 item 5), shared by their three files: terrain_hazard.c (the grid, the
 * walk of each piece and a trajectory's end), terrain_hazard_hist.c (the
 * histograms and the pending updates), terrain_hazard_out.c (merge, pack,
 * bands).  The whole design:
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
#ifndef ROCKFUZZ_TERRAIN_HAZARD_INTERNAL_H
#define ROCKFUZZ_TERRAIN_HAZARD_INTERNAL_H

#include "trajectory/terrain_internal.h"

#include <stdint.h>

#define BIN_SHIFT 47
#define COUNT_MASK ((UINT64_C(1) << BIN_SHIFT) - 1)
#define NO_POS UINT32_MAX

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

/* terrain_hazard_hist.c */
uint64_t hz_bin_of(double v);
int hz_hist_merge(hz_hist *into, const hz_hist *from);
double hz_hist_quantile(const hz_hist *hh, double vmax, double p);
void hz_pend_flush(rf_terrain_hazard *h);
void hz_pend_flush_const(const rf_terrain_hazard *h);
void hz_pend_add(rf_terrain_hazard *h, uint32_t rec, int height, double value);

/* terrain_hazard.c */
uint32_t hz_record_at(rf_terrain_hazard *h, size_t cell);

#endif
