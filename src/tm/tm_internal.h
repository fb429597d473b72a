/* tm_internal.h - the data the TM keeps after a run, shared by tm.c (driver,
 * evaluation, retransformation), grid.c (grid values, grids, the point
 * registry) and analysis.c (influence measures).
 *
 * Every grid value of input i is stored once in values[i] (values closer
 * than cache_rtol are merged); a grid point is a tuple of value indices.  A
 * grid is a Cartesian product of per-input index lists (no index twice),
 * enumerated in mixed radix with input 0 most significant (tm_spec s.2.2).
 *
 * Duplicates are found from the structure, not by hashing: a point of grid g
 * is also a point of an earlier grid h exactly when, for every input i, its
 * value index lies in h's list for i (the intersection of two products is
 * the product of the intersections).  So each grid keeps per input a bitset
 * of the value indices it uses, and while a grid is enumerated each list
 * position carries the set of earlier grids holding that value; the AND of
 * those sets along the odometer says at once whether a point is new.  The
 * id of a repeated point is read from the first earlier grid that holds it.
 * Only new points take memory (their input vector and, later, outputs). */
#ifndef ROCKFUZZ_TM_INTERNAL_H
#define ROCKFUZZ_TM_INTERNAL_H

#include <stdint.h>

#include "rockfuzz/tm.h"

typedef struct {
    size_t *radix;       /* [n] number of values of input i */
    size_t *stride;      /* [n] mixed-radix stride of input i inside the grid */
    uint32_t **vidx;     /* [n][radix[i]] value indices, in ascending value */
    size_t *nominal_pos; /* [n] position of the nominal value in vidx[i] (three-point grid only) */
    uint64_t **member;   /* [n][words of nvalues[i]] bitset of the value indices in vidx[i] */
    uint32_t *ids;       /* [count] point id of every grid point, or NULL (counting only) */
    size_t count;
    uint32_t first_id;   /* consecutive: ids[p] == first_id + p (every point new) */
    int consecutive;
} rf_grid;

struct rf_tm_data {
    size_t n, m, n_out;
    double **values;     /* [n][nvalues[i]] distinct grid values of input i */
    size_t *nvalues, *capvalues;
    double *scale;       /* [n] merge scale of input i (support width or |value|) */
    double rtol;

    /* point registry: every grid built so far, in order (the dedup's "earlier grids") */
    rf_grid **reg;
    size_t nreg, capreg;
    size_t npoints;      /* distinct points so far */
    size_t limit;        /* refuse a new point beyond this many (0 = none) */
    const atomic_int *stop; /* rf_tm_options.interrupt: checked once per grid row, or NULL */
    void *tuples;        /* [npoints * n] value indices of every distinct point, tw bytes each */
    size_t tw;           /* 1, 2 or 4 bytes per index (from the largest nvalues) */
    size_t cap_points;   /* points tuples and y have room for */

    /* New points wait in xbuf (input vectors) until `chunk` of them are
     * there, then flush evaluates them into y: a small buffer that stays in
     * cache for the serial path, all pending points for an evaluator. */
    double *xbuf;        /* [chunk * n] */
    double *ybuf;        /* [chunk * n_out] the evaluator's outputs, before they go into y */
    size_t chunk, xcap;  /* points per flush (0 = no flush while building), room in xbuf */
    size_t xcount, xfirst; /* points waiting in xbuf, id of the first of them */
    rf_status (*flush)(void *user, rf_error *err);
    void *flush_user;

    double *y;           /* [k * cap_points + id] output k of point id (one column per output) */

    rf_grid *nominal;    /* the one-point grid of the nominal inputs; its point is id 0 */
    rf_grid *main;       /* [m+1] grids of the chosen form, level j */
    rf_grid *lr;         /* [m+1] three-point grids (levels 0..m), or NULL */
    rf_grid *probe;      /* [nprobe] extended-form probe lines */
    size_t nprobe;
    uint32_t nominal_id;
};

/* What a run is building (build.c): the inputs' cuts and point sets. */
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
    const rf_model *model;  /* rf_tm_run: the model the flush evaluates */
} tm_ctx;

/* Extended-form probe lines of one input. */
typedef struct {
    size_t i;              /* probed input */
    size_t npts;           /* points per line */
    size_t nlines;
    const rf_grid *lines;  /* [nlines] one-dimensional grids along input i */
} probe_set;

/* Grid sizes counted analytically (saturating at SIZE_MAX). */
typedef struct {
    size_t main, main_largest, main_level;    /* main grids; extended: every auto input nonmonotonic */
    size_t floor, floor_largest, floor_level; /* extended: every auto input monotonic (= main otherwise) */
    size_t probe;                             /* extended-form probe */
    size_t lr, lr_largest, lr_level;          /* three-point grids (0 if left_right is off) */
    size_t requested;                         /* main + probe + lr */
} tm_grid_sizes;

/* build.c */
rf_status tm_ctx_init(tm_ctx *c, const rf_fuzzy *inputs, size_t n, const rf_tm_options *opt, size_t n_out,
                      rf_error *err);
void tm_ctx_free(tm_ctx *c);
size_t tm_sort_unique(double *v, size_t k, double tol);
rf_status tm_build_nominal(tm_ctx *c, int with_ids, rf_error *err);
rf_status tm_build_main(tm_ctx *c, int with_ids, rf_error *err);
rf_status tm_build_lr(tm_ctx *c, int with_ids, rf_error *err);
rf_status tm_build_probe(tm_ctx *c, probe_set *ps, size_t *nps, int with_ids, rf_error *err);
void tm_sizes(const tm_ctx *c, tm_grid_sizes *s);
rf_status tm_check_sizes(const tm_ctx *c, const tm_grid_sizes *s, rf_error *err);

/* tm.c: the recursive retransformation of the outputs held in d->y (d->n_out
 * columns) into res (lo, hi, x_lo, x_hi; reads res->output_undefined);
 * -1 without memory. */
int tm_retransform(const struct rf_tm_data *d, rf_tm_result *res);

/* values.c: a result for extra outputs y[c * npoints + id] (n_cols columns, in
 * the point order of res) as rf_tm_run would have made it for them: its data
 * a view of res->data (grids shared, y the caller's columns: keep them alive),
 * cuts retransformed, NaN values left out of the bounds (an all-NaN column is
 * output_undefined, its cuts NaN).  lo, hi: the caller's arrays for the
 * cuts ((m+1) per column) or NULL (owned).  Free with tm_values_result_free. */
rf_status tm_values_result(const rf_tm_result *res, size_t n_cols, const double *y, double *lo, double *hi,
                           rf_tm_result *out, rf_error *err);
void tm_values_result_free(rf_tm_result *out);

/* grid.c */
/* Value index of input i of point id. */
static inline uint32_t rf_tm_tuple(const struct rf_tm_data *d, size_t id, size_t i)
{
    size_t at = id * d->n + i;
    return d->tw == 1 ? ((const uint8_t *)d->tuples)[at]
           : d->tw == 2 ? ((const uint16_t *)d->tuples)[at]
                        : ((const uint32_t *)d->tuples)[at];
}
rf_status rf_tm_reserve(struct rf_tm_data *d, size_t extra, rf_error *err);
int rf_tm_value_index(struct rf_tm_data *d, size_t i, double v, uint32_t *out);
rf_status rf_tm_grid_build(struct rf_tm_data *d, rf_grid *g, double *const *vals, const size_t *cnt,
                           size_t *requested, int with_ids, rf_error *err);
void rf_tm_grid_free(rf_grid *g, size_t n);
void rf_tm_data_free(struct rf_tm_data *d);

/* Output k of every point of g in grid order: the column itself when the
 * grid's ids are consecutive, else gathered into scratch[g->count]. */
const double *rf_tm_outputs(const struct rf_tm_data *d, const rf_grid *g, size_t k, double *scratch);

/* Output k of point id. */
static inline double rf_tm_y(const struct rf_tm_data *d, size_t id, size_t k) { return d->y[k * d->cap_points + id]; }

#endif
