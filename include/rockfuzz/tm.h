/* tm.h - the Transformation Method of fuzzy arithmetic (tm_spec.md s.2-4).
 *
 * rf_tm_run decomposes the fuzzy inputs, builds the grid of the chosen form
 * (general, reduced or extended), evaluates every DISTINCT point once through
 * an evaluator (points are tuples of grid-value indices, values closer than
 * cache_rtol merged before any evaluation; a point repeated by another grid
 * is recognised from the grids' structure), and retransforms recursively
 * so that the output cuts always nest.  Several outputs share one set of
 * evaluations.  For every output bound the input vector that produced it is
 * kept.  The TM never knows what model it calls.
 *
 * NaN outputs: an output that is NaN at every point is undefined for this
 * study (cuts NaN, output_undefined set); one that is NaN at some points only
 * stops the run with the parameter vector, since its bounds would be wrong.
 *
 * tolerate_failures (off by default): a failed evaluation no longer stops the
 * run; the evaluator gives its point NaN outputs, NaN values are left out of
 * the min/max of every cut, and the count is reported (failed_points, the
 * points whose outputs are all NaN; nan_points[k] per output) so that the
 * caller can warn loudly: such bounds may be too narrow. */
#ifndef ROCKFUZZ_TM_H
#define ROCKFUZZ_TM_H

#include "rockfuzz/fuzzy.h"
#include "rockfuzz/model.h"
#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { RF_TM_GENERAL, RF_TM_REDUCED, RF_TM_EXTENDED } rf_tm_scheme;

/* Monotonicity class of an input (extended form), or a diagnostic verdict. */
typedef enum {
    RF_MONO_AUTO = 0,        /* let the probe decide (option) / not checked (verdict) */
    RF_MONO_MONOTONIC,
    RF_MONO_NONMONOTONIC
} rf_monotonicity;

/* Evaluates count points x[c*n_inputs + i] into y[c*n_outputs + k].  The
 * default (evaluator == NULL) is a serial loop over rf_model_eval.  A failed
 * point returns its status with a message; the TM adds the parameter vector. */
typedef struct {
    rf_status (*evaluate)(void *user, const rf_model *model, size_t count, const double *x, double *y,
                          size_t *failed_index, rf_error *err);
    void *user;
} rf_evaluator;

typedef struct {
    rf_tm_scheme scheme;
    size_t levels;                       /* m >= 1: membership intervals (m+1 levels) */
    size_t max_evaluations;              /* cap on distinct evaluations, 0 = none */
    int left_right;                      /* evaluate the three-point grid for s.5.4 and the monotonicity check */
    const rf_monotonicity *force_class;  /* per input, extended form only; NULL = all auto */
    double cache_rtol;                   /* grid values closer than this (relative) are one value; default 1e-12 */
    double probe_rtol;                   /* extended-form probe: ignore differences below this x output range; 1e-9 */
    const rf_evaluator *evaluator;       /* NULL = serial */
    int tolerate_failures;               /* NaN/failed points are skipped in the bounds (see above) */
    /* Called once with the counts before any evaluation; return non-zero to abort. */
    int (*on_plan)(void *user, size_t requested, size_t distinct);
    void *on_plan_user;
    /* Non-zero *interrupt stops counting and building the grids (a grid of
     * millions of points with the cap off): RF_EINTERRUPTED.  NULL = never. */
    const atomic_int *interrupt;
} rf_tm_options;

void rf_tm_options_default(rf_tm_options *opt);
const char *rf_tm_scheme_name(rf_tm_scheme s);
rf_status rf_tm_scheme_parse(const char *name, rf_tm_scheme *s);

struct rf_tm_data; /* grids and evaluated values, used by the analysis */

typedef struct {
    size_t n_inputs, n_outputs, levels;  /* levels = m; arrays have m+1 entries per curve */
    rf_tm_scheme scheme;
    double *in_lo, *in_hi;               /* [i*(m+1) + j] input cuts */
    double *in_nominal;                  /* [i] */
    double *lo, *hi;                     /* [k*(m+1) + j] output cuts (nested) */
    double *x_lo, *x_hi;                 /* [(k*(m+1) + j)*n_inputs + i] inputs giving lo / hi */
    double *nominal;                     /* [k] output at the nominal inputs */
    rf_monotonicity *input_class;        /* [i] extended form: class used (else RF_MONO_AUTO) */
    rf_monotonicity *monotonicity;       /* [k*n_inputs + i] diagnostic verdict (AUTO = not checked) */
    size_t requested;                    /* grid points requested (all grids, before the cache) */
    size_t distinct;                     /* model evaluations actually made */
    size_t probe_evaluations;            /* of which the extended-form probe */
    size_t lr_evaluations;               /* of which only needed by the three-point grid */
    size_t failed_points;                /* tolerate_failures: points with every output NaN (failed) */
    size_t *nan_points;                  /* [k] tolerate_failures: points skipped for output k */
    unsigned char *output_undefined;     /* [k] 1 if the model returned NaN for output k at every
                                          * point (e.g. R_t of a normal impact): its cuts are NaN */
    struct rf_tm_data *data;
} rf_tm_result;

/* Count requested and distinct evaluations without evaluating anything
 * (extended form with auto classes: the probe is counted, the main grid
 * bounded above by the general form).  Every grid's size is counted
 * analytically first: a grid with more points than max_evaluations (or than
 * point ids can index) is refused with RF_ECAP, naming the grid (general- or
 * reduced-form grid at a level, the left/right three-point grid, the
 * extended form's probe) and what to change; then the distinct points are
 * counted without storing any, and a count above max_evaluations is refused
 * too (not for the extended form's upper bound).  Memory does not grow with
 * the grid.  rf_tm_run makes the same checks before it builds anything. */
rf_status rf_tm_count(const rf_fuzzy *inputs, size_t n_inputs, const rf_tm_options *opt,
                      size_t *requested, size_t *distinct, rf_error *err);

rf_status rf_tm_run(const rf_fuzzy *inputs, size_t n_inputs, const rf_model *model,
                    const rf_tm_options *opt, rf_tm_result *res, rf_error *err);

void rf_tm_result_free(rf_tm_result *res);

/* ---- Extra outputs of a finished run (tm_spec s.3-4; docs/fuzzy-hazard.md):
 * values a caller derives at every distinct point, e.g. every cell of a
 * hazard raster, retransformed exactly as rf_tm_run retransforms the model's
 * outputs.  The distinct points have ids 0 .. rf_tm_point_count - 1 (id 0 is
 * the nominal point); rf_tm_point_inputs writes point id's n_inputs values
 * (the very doubles the model was evaluated at).  The TM keeps what this
 * needs anyway (the grids and every point's value indices). */
size_t rf_tm_point_count(const rf_tm_result *res);
rf_status rf_tm_point_inputs(const rf_tm_result *res, size_t id, double *x, rf_error *err);
/* 1 if point id failed (tolerate_failures: every output NaN), else 0. */
int rf_tm_point_failed(const rf_tm_result *res, size_t id);

/* n_cols extra outputs, y[c * rf_tm_point_count(res) + id] (column c, point
 * id), into lo[c*(m+1) + j], hi[c*(m+1) + j] (level j = 0..m, nested).  For
 * a scalar output of the run the cuts are bit-identical to res->lo/hi.  NaN
 * values are left out of the bounds (a raster cell no block reached at some
 * points); a column NaN at every point gets NaN cuts. */
rf_status rf_tm_retransform_values(const rf_tm_result *res, size_t n_cols, const double *y, double *lo, double *hi,
                                   rf_error *err);

/* Closed-form evaluation counts without a cache (tm_spec s.2.3, 3.2). */
size_t rf_tm_count_general(size_t n, size_t m);
size_t rf_tm_count_reduced(size_t n, size_t m);

#ifdef __cplusplus
}
#endif
#endif
