/* tm.c - the Transformation Method (tm_spec.md s.2-4): the run's driver,
 * evaluation through an rf_evaluator, the extended form's classification,
 * the monotonicity diagnostic and the recursive retransformation.  What is
 * evaluated is built in build.c and grid.c.
 *
 * Flow of rf_tm_run:
 *   decompose inputs, register every grid value (build.c) -> count every
 *   grid analytically and refuse one beyond the cap (nothing built yet) ->
 *   with a cap: count the distinct points exactly (no storage) and refuse ->
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

#define SERIAL_CHUNK 256 /* points evaluated at a time without an evaluator */


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


/* ------------------------------------------------------------- evaluation */

static void format_point(const struct rf_tm_data *d, uint32_t id, char *buf, size_t size)
{
    size_t used = 0;
    used += (size_t)snprintf(buf + used, size - used, "(");
    for (size_t i = 0; i < d->n && used < size; i++)
        used += (size_t)snprintf(buf + used, size - used, "%s%.17g", i ? ", " : "",
                                 d->values[i][rf_tm_tuple(d, id, i)]);
    if (used < size)
        snprintf(buf + used, size - used, ")");
}

/* user: the rf_tm_options (tolerate_failures: a failed point gets NaN
 * outputs and the evaluation goes on after it). */
static rf_status serial_evaluate(void *user, const rf_model *model, size_t count, const double *x, double *y,
                                 size_t *failed, rf_error *err)
{
    const rf_tm_options *opt = user;
    size_t done = 0, nin = model->n_inputs, nout = model->n_outputs;
    while (done < count) {
        size_t at = 0;
        rf_status st = rf_model_eval_many(model, count - done, x + done * nin, y + done * nout, &at, err);
        if (st == RF_OK)
            return RF_OK;
        if (!opt->tolerate_failures || !model->eval) {
            *failed = done + at;
            return st;
        }
        for (size_t k = 0; k < nout; k++)
            y[(done + at) * nout + k] = NAN;
        done += at + 1;
    }
    return RF_OK;
}

/* Evaluate the points waiting in the buffer (ids xfirst ..) into y. */
static rf_status flush_points(void *user, rf_error *err)
{
    tm_ctx *c = user;
    struct rf_tm_data *d = c->d;
    size_t no = d->n_out, first = d->xfirst, count = d->xcount;
    if (count == 0)
        return RF_OK;
    const rf_evaluator *ev = c->opt->evaluator;
    const rf_model *model = c->model;
    size_t failed = 0;
    double *yb = d->ybuf;
    rf_status st = ev ? ev->evaluate(ev->user, model, count, d->xbuf, yb, &failed, err)
                      : serial_evaluate((void *)c->opt, model, count, d->xbuf, yb, &failed, err);
    for (size_t k = 0; !st && k < no; k++) { /* into the output columns */
        double *col = d->y + k * d->cap_points + first;
        for (size_t p = 0; p < count; p++)
            col[p] = yb[p * no + k];
    }
    if (st && failed >= count)
        return st; /* not a model failure (e.g. the result store could not be written) */
    if (st) {
        char pt[512];
        format_point(d, (uint32_t)(first + failed), pt, sizeof pt);
        return rf_error_prefix(err, "model evaluation at parameters %s", pt);
    }
    d->xfirst += count;
    d->xcount = 0;
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
            double v = rf_tm_y(d, p, k);
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
                const double *zl = rf_tm_outputs(d, &p->lines[line], k, z);
                nm_k = changes_direction(zl, p->lines[line].count, 1, c->opt->probe_rtol * range[k]);
            }
            verdict[k * c->n + p->i] = nm_k ? RF_MONO_NONMONOTONIC : RF_MONO_MONOTONIC;
            nonmono |= nm_k;
        }
        c->cls[p->i] = nonmono ? RF_MONO_NONMONOTONIC : RF_MONO_MONOTONIC;
    }
    free(z);
}

/* Does a line of z parallel to an axis (radix r, stride s) have both a rise
 * and a fall larger than tol?  (= changes direction, ignoring steps <= tol;
 * a NaN step is ignored.)  The s lines of one block are scanned together, as
 * running maxima and minima of their steps, which vectorises. */
static int lines_change_direction(const double *z, size_t count, size_t r, size_t s, double tol,
                                  double *restrict rise, double *restrict fall)
{
    if (s == 1) { /* contiguous lines, one at a time */
        for (size_t outer = 0; outer < count; outer += r) {
            double up = 0, down = 0;
            for (size_t l = 1; l < r; l++) {
                double dz = z[outer + l] - z[outer + l - 1];
                up = dz > up ? dz : up;
                down = dz < down ? dz : down;
            }
            if (up > tol && down < -tol)
                return 1;
        }
        return 0;
    }
    for (size_t outer = 0; outer < count; outer += r * s) {
        const double *b = z + outer;
        for (size_t inner = 0; inner < s; inner++)
            rise[inner] = fall[inner] = 0;
        for (size_t l = 1; l < r; l++) {
            const double *restrict z0 = b + (l - 1) * s, *restrict z1 = b + l * s;
            for (size_t inner = 0; inner < s; inner++) {
                double dz = z1[inner] - z0[inner];
                rise[inner] = dz > rise[inner] ? dz : rise[inner];
                fall[inner] = dz < fall[inner] ? dz : fall[inner];
            }
        }
        int both = 0;
        for (size_t inner = 0; inner < s; inner++)
            both |= (rise[inner] > tol) & (fall[inner] < -tol);
        if (both)
            return 1;
    }
    return 0;
}

/* Monotonicity diagnostic on a grid: every line parallel to axis i. */
static void diagnose_grid(const struct rf_tm_data *d, const rf_grid *g, const double *range, double rtol,
                          rf_monotonicity *verdict)
{
    size_t n = d->n, no = d->n_out, count = g->count;
    int any = 0;
    for (size_t i = 0; i < n; i++)
        any |= g->radix[i] >= 3;
    if (!any)
        return;
    /* each output of the grid contiguous (gathered unless its ids are), then scan blocks */
    double *z = malloc(3 * count * sizeof(double));
    if (!z)
        return; /* the diagnostic stays "not checked" */
    for (size_t k = 0; k < no; k++) {
        const double *zk = rf_tm_outputs(d, g, k, z);
        for (size_t i = 0; i < n; i++) {
            rf_monotonicity *v = &verdict[k * n + i];
            if (g->radix[i] < 3 || *v == RF_MONO_NONMONOTONIC)
                continue;
            int nm = lines_change_direction(zk, count, g->radix[i], g->stride[i], rtol * range[k], z + count,
                                            z + 2 * count);
            *v = nm ? RF_MONO_NONMONOTONIC : RF_MONO_MONOTONIC;
        }
    }
    free(z);
}

/* ------------------------------------------------------- retransformation */

/* One pass over the outputs: NaN counts (and the first NaN point) per
 * output, the range of the defined values, and the points failed entirely. */
typedef struct {
    size_t *nan, *first_nan;
    double *range;
    size_t failed;
} output_scan;

#define LANES 4 /* independent running extrema: their latencies overlap */

/* NaN count and range (0 if none or constant) of col[0..np-1].  The
 * running minima and maxima of LANES interleaved lanes are merged at the
 * end: a minimum is the same whatever the order (NaN is never taken; -0 and
 * +0 may trade places, which changes no difference taken of them). */
static double column_range(const double *col, size_t np, size_t *nan)
{
    double lo[LANES], hi[LANES];
    size_t cnt[LANES] = {0};
    for (size_t q = 0; q < LANES; q++)
        lo[q] = INFINITY, hi[q] = -INFINITY;
    for (size_t p0 = 0; p0 < np; p0 += LANES)
        for (size_t q = 0; q < LANES; q++) { /* unrolled: the lanes stay in registers */
            double v = p0 + q < np ? col[p0 + q] : NAN;
            cnt[q] += p0 + q < np && isnan(v);
            lo[q] = v < lo[q] ? v : lo[q];
            hi[q] = v > hi[q] ? v : hi[q];
        }
    for (size_t q = 1; q < LANES; q++) {
        lo[0] = lo[q] < lo[0] ? lo[q] : lo[0];
        hi[0] = hi[q] > hi[0] ? hi[q] : hi[0];
        cnt[0] += cnt[q];
    }
    *nan = cnt[0];
    return hi[0] > lo[0] ? hi[0] - lo[0] : 0;
}

static int scan_outputs(const struct rf_tm_data *d, output_scan *s)
{
    size_t no = d->n_out, np = d->npoints;
    s->nan = calloc(2 * no, sizeof(size_t));
    s->range = malloc(no * sizeof(double));
    s->failed = 0;
    if (!s->nan || !s->range)
        return -1;
    s->first_nan = s->nan + no;
    int any_nan = 0;
    for (size_t k = 0; k < no; k++) {
        const double *col = d->y + k * d->cap_points;
        size_t nan = 0;
        s->range[k] = column_range(col, np, &nan);
        for (size_t p = 0; nan && p < np; p++)
            if (isnan(col[p])) {
                s->first_nan[k] = p;
                break;
            }
        s->nan[k] = nan;
        any_nan |= nan > 0;
    }
    for (size_t p = 0; any_nan && p < np; p++) {
        size_t k = 0;
        while (k < no && isnan(rf_tm_y(d, p, k)))
            k++;
        s->failed += k == no;
    }
    return 0;
}

/* Outputs NaN everywhere are undefined; NaN somewhere is an error. */
static rf_status check_nan_outputs(const tm_ctx *c, const rf_model *model, const output_scan *s,
                                   rf_tm_result *res, rf_error *err)
{
    const struct rf_tm_data *d = c->d;
    for (size_t k = 0; k < d->n_out; k++) {
        size_t nan = s->nan[k];
        if (nan == d->npoints) {
            res->output_undefined[k] = 1;
        } else if (nan > 0 && c->opt->tolerate_failures) {
            res->nan_points[k] = nan; /* left out of the bounds; the caller warns */
        } else if (nan > 0) {
            char pt[512];
            format_point(d, (uint32_t)s->first_nan[k], pt, sizeof pt);
            return rf_fail(err, RF_EMODEL,
                           "output '%s' is NaN at parameters %s (and %zu other points) but defined at others: "
                           "its bounds would be wrong",
                           model->output_names[k], pt, nan - 1);
        }
    }
    return RF_OK;
}

static void set_cut(const struct rf_tm_data *d, rf_tm_result *res, size_t at, int none, uint32_t amin,
                    uint32_t amax, double zmin, double zmax)
{
    size_t n = d->n;
    res->lo[at] = none ? NAN : zmin;
    res->hi[at] = none ? NAN : zmax;
    for (size_t i = 0; i < n; i++) {
        res->x_lo[at * n + i] = none ? NAN : d->values[i][rf_tm_tuple(d, amin, i)];
        res->x_hi[at * n + i] = none ? NAN : d->values[i][rf_tm_tuple(d, amax, i)];
    }
}

/* Smallest and largest of z[0..count-1] (NaN never; +-INFINITY if all
 * are NaN), as running extrema of LANES interleaved lanes, merged. */
static void grid_extremes(const double *z, size_t count, double *zlo, double *zhi)
{
    double lo[LANES], hi[LANES];
    for (size_t q = 0; q < LANES; q++)
        lo[q] = INFINITY, hi[q] = -INFINITY;
    size_t p0 = 0;
    for (; p0 + LANES <= count; p0 += LANES)
        for (size_t q = 0; q < LANES; q++) { /* unrolled: the lanes stay in registers */
            double v = z[p0 + q];
            lo[q] = v < lo[q] ? v : lo[q];
            hi[q] = v > hi[q] ? v : hi[q];
        }
    for (; p0 < count; p0++) {
        lo[0] = z[p0] < lo[0] ? z[p0] : lo[0];
        hi[0] = z[p0] > hi[0] ? z[p0] : hi[0];
    }
    for (size_t q = 1; q < LANES; q++) {
        lo[0] = lo[q] < lo[0] ? lo[q] : lo[0];
        hi[0] = hi[q] > hi[0] ? hi[q] : hi[0];
    }
    *zlo = lo[0];
    *zhi = hi[0];
}

/* First position of a value equal to v (which z holds). */
static size_t first_equal(const double *z, double v)
{
    size_t p = 0;
    while (z[p] != v)
        p++;
    return p;
}

/* Recursive retransformation (s.2.4), output by output: each level starts
 * from the bounds of level j+1 and moves only to a strictly smaller
 * (larger) value, the first point holding it.  A NaN never becomes a bound.
 * Outputs 0..d->n_out-1 of the columns d->y into res->lo/hi/x_lo/x_hi; reads
 * res->output_undefined.  Also the retransformation of extra outputs (values.c). */
int tm_retransform(const struct rf_tm_data *d, rf_tm_result *res)
{
    size_t m = d->m, no = d->n_out, maxc = 1;
    for (size_t j = 0; j <= m; j++)
        maxc = d->main[j].count > maxc ? d->main[j].count : maxc;
    double *scratch = malloc(maxc * sizeof(double));
    if (!scratch)
        return -1;
    for (size_t k = 0; k < no; k++) {
        uint32_t amin = 0, amax = 0;
        double zmin = INFINITY, zmax = -INFINITY;
        for (size_t jj = m + 1; jj-- > 0;) {
            const rf_grid *g = &d->main[jj];
            const double *z = rf_tm_outputs(d, g, k, scratch);
            /* a strict sequential scan stops at the first point holding a
             * new extremum: the same point, found after the extremum */
            double glo, ghi;
            grid_extremes(z, g->count, &glo, &ghi);
            if (glo < zmin) {
                size_t p = first_equal(z, glo);
                zmin = z[p];
                amin = g->ids[p];
            }
            if (ghi > zmax) {
                size_t p = first_equal(z, ghi);
                zmax = z[p];
                amax = g->ids[p];
            }
            /* tolerate_failures: every point of the cut was NaN so far */
            set_cut(d, res, k * (m + 1) + jj, res->output_undefined[k] || zmin > zmax, amin, amax, zmin, zmax);
        }
    }
    free(scratch);
    return 0;
}

/* ------------------------------------------------------------------ driver */

static rf_status plan(tm_ctx *c, int with_ids, probe_set *ps, size_t *nps, int *deferred, rf_error *err)
{
    *nps = 0;
    *deferred = 0;
    rf_status st = tm_build_nominal(c, with_ids, err); /* id 0: the reference of the analysis */
    if (!st && c->opt->left_right)
        st = tm_build_lr(c, with_ids, err);
    if (st)
        return st;
    if (c->opt->scheme == RF_TM_EXTENDED) {
        int any_auto = 0;
        for (size_t i = 0; i < c->n; i++)
            any_auto |= c->cls[i] == RF_MONO_AUTO;
        if (any_auto) {
            *deferred = 1;
            return tm_build_probe(c, ps, nps, with_ids, err);
        }
    }
    return tm_build_main(c, with_ids, err);
}

/* The cap was exceeded by the distinct points (no single grid exceeds it). */
static rf_status over_cap(const tm_ctx *c, const tm_grid_sizes *s, size_t distinct, rf_error *err)
{
    const rf_tm_options *opt = c->opt;
    char lr[160] = "";
    if (opt->left_right)
        snprintf(lr, sizeof lr, "turn off the left/right influence (options.left_right: false; its three-point "
                                "grids request %zu points), ", s->lr);
    return rf_fail(err, RF_ECAP,
                   "the study needs %zu distinct model evaluations (the %s-form grids request %zu points%s), more "
                   "than the cap of %zu (max_evaluations = %zu): %slower levels%s, or raise max_evaluations",
                   distinct, rf_tm_scheme_name(opt->scheme), s->main, opt->left_right ? ", with left/right" : "",
                   opt->max_evaluations, opt->max_evaluations, lr,
                   opt->scheme == RF_TM_GENERAL ? ", use scheme: reduced or extended" : "");
}

/* Count without storing any point: sizes analytically (refusing a grid
 * beyond the cap), then the distinct points by enumeration. */
static rf_status count_points(tm_ctx *c, size_t *requested, size_t *distinct, rf_error *err)
{
    tm_grid_sizes s;
    tm_sizes(c, &s);
    rf_status st = tm_check_sizes(c, &s, err);
    probe_set *ps = st ? NULL : calloc(c->n, sizeof *ps);
    size_t nps = 0, cap = c->opt->max_evaluations;
    int deferred = 0;
    if (!st && !ps)
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (!st)
        st = plan(c, 0, ps, &nps, &deferred, err);
    free(ps);
    if (!st && deferred && s.main_largest > (cap ? cap : UINT32_MAX - 1)) {
        /* extended form: an upper bound too large to enumerate; the probe decides */
        *requested = c->requested + s.main;
        *distinct = c->d->npoints + s.main;
        return RF_OK;
    }
    if (!st && deferred) {
        /* upper bound: every auto input non-monotonic (general form) */
        for (size_t i = 0; i < c->n; i++)
            if (c->cls[i] == RF_MONO_AUTO)
                c->cls[i] = RF_MONO_NONMONOTONIC;
        st = tm_build_main(c, 0, err);
    }
    if (!st && cap && c->d->npoints > cap && !deferred)
        st = over_cap(c, &s, c->d->npoints, err);
    if (!st) {
        *requested = c->requested;
        *distinct = c->d->npoints;
    }
    return st;
}

rf_status rf_tm_count(const rf_fuzzy *inputs, size_t n_inputs, const rf_tm_options *opt, size_t *requested,
                      size_t *distinct, rf_error *err)
{
    tm_ctx c;
    rf_status st = tm_ctx_init(&c, inputs, n_inputs, opt, 1, err);
    if (!st)
        st = count_points(&c, requested, distinct, err);
    tm_ctx_free(&c);
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
    rf_tm_data_free(res->data);
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
    if (!res->output_undefined || !res->nan_points || !res->in_lo || !res->in_hi || !res->in_nominal ||
        !res->lo || !res->hi || !res->x_lo || !res->x_hi || !res->nominal || !res->input_class ||
        !res->monotonicity)
        return rf_fail(err, RF_ENOMEM, "out of memory for the TM result");
    return RF_OK;
}

/* Before anything is built: every grid within the cap (analytically) and,
 * with a cap or a plan callback, the exact counts (nothing stored). */
static rf_status preflight(const tm_ctx *c, const rf_fuzzy *inputs, size_t n, const rf_tm_options *opt,
                           rf_error *err)
{
    tm_grid_sizes s;
    tm_sizes(c, &s);
    rf_status st = tm_check_sizes(c, &s, err);
    if (st || (!opt->max_evaluations && !opt->on_plan))
        return st;
    size_t rq = 0, ds = 0;
    st = rf_tm_count(inputs, n, opt, &rq, &ds, err);
    if (!st && opt->on_plan && opt->on_plan(opt->on_plan_user, rq, ds))
        st = rf_fail(err, RF_ECAP, "the run was cancelled before any evaluation");
    return st;
}

/* Extended form after the probe: the main grid with the classes found,
 * within the cap (no point beyond it is stored). */
static rf_status build_main_after_probe(tm_ctx *c, rf_error *err)
{
    tm_grid_sizes s;
    tm_sizes(c, &s);
    rf_status st = tm_check_sizes(c, &s, err);
    if (st)
        return rf_error_prefix(err, "with the classes the probe found");
    c->d->limit = c->opt->max_evaluations;
    st = tm_build_main(c, 1, err);
    c->d->limit = 0;
    if (st == RF_ECAP && c->opt->max_evaluations)
        return rf_fail(err, RF_ECAP,
                       "with the classes the probe found, the extended form needs more distinct evaluations than "
                       "the cap of %zu (max_evaluations = %zu): declare parameters monotonic, lower levels, or raise "
                       "max_evaluations",
                       c->opt->max_evaluations, c->opt->max_evaluations);
    return st;
}

static void count_lr_only(const struct rf_tm_data *d, rf_tm_result *res)
{
    /* evaluations only the three-point grid needed */
    unsigned char *used = calloc(d->npoints, 1);
    if (!used)
        return;
    for (size_t j = 0; j <= d->m; j++)
        for (size_t p = 0; p < d->main[j].count; p++)
            used[d->main[j].ids[p]] = 1;
    used[d->nominal_id] = 1;
    size_t lr_only = 0;
    for (size_t j = 0; j <= d->m; j++)
        for (size_t p = 0; p < d->lr[j].count; p++)
            if (!used[d->lr[j].ids[p]]) {
                used[d->lr[j].ids[p]] = 2;
                lr_only++;
            }
    res->lr_evaluations = lr_only;
    free(used);
}

/* Fill the result from the evaluated points and hand it the data. */
static rf_status finish(tm_ctx *c, const output_scan *s, rf_tm_result *res, rf_error *err)
{
    struct rf_tm_data *d = c->d;
    const rf_tm_options *opt = c->opt;
    size_t n = c->n, m = c->m, no = d->n_out;
    res->scheme = opt->scheme;
    memcpy(res->in_lo, c->lo, n * (m + 1) * sizeof(double));
    memcpy(res->in_hi, c->hi, n * (m + 1) * sizeof(double));
    memcpy(res->in_nominal, c->nominal, n * sizeof(double));
    for (size_t k = 0; k < no; k++)
        res->nominal[k] = rf_tm_y(d, d->nominal_id, k);
    if (opt->scheme == RF_TM_EXTENDED)
        memcpy(res->input_class, c->cls, n * sizeof *c->cls);
    /* diagnostic on whatever grids have interior points */
    for (size_t j = 0; d->lr && j <= m; j++)
        diagnose_grid(d, &d->lr[j], s->range, opt->probe_rtol, res->monotonicity);
    for (size_t j = 0; opt->scheme != RF_TM_REDUCED && j <= m; j++)
        diagnose_grid(d, &d->main[j], s->range, opt->probe_rtol, res->monotonicity);
    if (tm_retransform(d, res))
        return rf_fail(err, RF_ENOMEM, "out of memory for the retransformation");
    res->requested = c->requested;
    res->distinct = d->npoints;
    if (d->lr)
        count_lr_only(d, res);
    if (opt->tolerate_failures)
        res->failed_points = s->failed;
    res->data = d;
    c->d = NULL;
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
    size_t no = model->n_outputs, nps = 0, cap = opt->max_evaluations;
    tm_ctx c;
    probe_set *ps = NULL;
    int deferred = 0;
    rf_status st = tm_ctx_init(&c, inputs, n_inputs, opt, no, err);
    if (!st) {
        /* the serial path evaluates in chunks that stay in cache; an
         * evaluator (threads, store, MPI) gets every pending point at once */
        c.model = model;
        c.d->chunk = opt->evaluator ? 0 : SERIAL_CHUNK;
        c.d->flush = flush_points;
        c.d->flush_user = &c;
        st = preflight(&c, inputs, n_inputs, opt, err);
    }
    if (!st)
        st = result_alloc(res, n_inputs, no, opt->levels, err);
    if (!st && !(ps = calloc(n_inputs, sizeof *ps)))
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (!st)
        st = plan(&c, 1, ps, &nps, &deferred, err);
    if (!st && cap && c.d->npoints > cap)
        st = rf_fail(err, RF_ECAP, "%zu distinct evaluations needed, more than the cap of %zu (max_evaluations = %zu)",
                     c.d->npoints, cap, cap);
    if (!st)
        st = flush_points(&c, err);
    if (!st && deferred) {
        classify(&c, ps, nps, res->monotonicity);
        res->probe_evaluations = c.d->npoints;
        st = build_main_after_probe(&c, err);
        if (!st)
            st = flush_points(&c, err);
    }
    output_scan scan = {0};
    if (!st && scan_outputs(c.d, &scan))
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (!st)
        st = check_nan_outputs(&c, model, &scan, res, err);
    if (!st)
        st = finish(&c, &scan, res, err);
    free(scan.nan);
    free(scan.range);
    free(ps);
    tm_ctx_free(&c);
    if (st)
        rf_tm_result_free(res);
    return st;
}
