/* analysis.c - influence measures of the TM (tm_spec.md s.5).
 *
 * Gain factors (s.5.1/5.2) are mean secant slopes along every grid line
 * parallel to an input axis in the level-j grid of the chosen form (corners
 * for the reduced form, the general-form points otherwise), from the first
 * to the last value (the cut bounds).  Hanss's measures (s.5.3) weight them
 * with the membership levels j = 1..m-1.  The left/right measures and the
 * degree of uncertainty (s.5.4, project definition after Gauger et al. 2008)
 * use the three-point grids {a, nominal, b}; at level m they span the core
 * (zero for single-peaked inputs, as in s.5.4; non-zero for flat cores). */
#include "rockfuzz/analysis.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tm/tm_internal.h"

const char *rf_na_reason_text(rf_na_reason r)
{
    switch (r) {
    case RF_NA_NONE: return "";
    case RF_NA_CRISP: return "input has zero width";
    case RF_NA_ZERO_NOMINAL: return "nominal output is 0";
    case RF_NA_NO_LR: return "left/right grid not evaluated";
    case RF_NA_ALL_ZERO: return "no input changes the output on the levels weighted";
    case RF_NA_FEW_LEVELS: return "needs levels >= 2";
    case RF_NA_UNDEFINED: return "output undefined for this study";
    }
    return "?";
}

void rf_analysis_free(rf_analysis *an)
{
    if (!an)
        return;
    free(an->gain);
    free(an->mean_gain);
    free(an->std_gain);
    free(an->kappa);
    free(an->rho);
    free(an->kappa_left);
    free(an->kappa_right);
    free(an->rho_left);
    free(an->rho_right);
    free(an->reason_hanss);
    free(an->reason_std);
    free(an->reason_lr);
    free(an->degree_of_uncertainty);
    free(an->interaction);
    free(an->reason_nu);
    memset(an, 0, sizeof *an);
}

#define LANES 4 /* line sums computed side by side */

/* Which difference of a line: first to last, first to nominal, nominal to last. */
typedef enum { SPAN, LEFT, RIGHT } line_part;

/* The shape of the line sums along axis i of a grid: points, radix and
 * stride of i, the two positions differenced.  Grids with equal shapes
 * (every level of the reduced form, as a rule) are summed together. */
typedef struct {
    size_t count, r, s, pa, pb;
} line_shape;

/* Shape of `part` along axis i of g; returns 0 when that difference is not
 * defined there (one value on the axis, or the nominal at that end). */
static int shape_of(const rf_grid *g, size_t i, line_part part, line_shape *sh)
{
    size_t last = g->radix[i] - 1, pn = g->nominal_pos[i];
    *sh = (line_shape){g->count, g->radix[i], g->stride[i], part == RIGHT ? pn : 0, part == LEFT ? pn : last};
    return sh->pb > sh->pa;
}

static int same_shape(const line_shape *a, const line_shape *b)
{
    return a->count == b->count && a->r == b->r && a->s == b->s && a->pa == b->pa && a->pb == b->pb;
}

/* Mean over the lines of shape sh of z[q](pb) - z[q](pa), for the `lanes`
 * outputs z[q] of grids of that shape.  Each lane is one chain of additions
 * in the order of a sum taken alone (blocks, then the lines of a block), so
 * its result is the same to the bit; side by side, the chains' latencies
 * overlap (a single chain is bound by the latency of one addition).  Called
 * with a constant `lanes`, for which it is unrolled. */
static inline void lane_sums(const double *const *z, const line_shape *sh, size_t lanes, double *out)
{
    size_t r = sh->r, s = sh->s, da = sh->pa * s, db = sh->pb * s;
    double sum[LANES] = {0};
    if (s == 1) { /* the last input: one line per block */
        for (size_t outer = 0; outer < sh->count; outer += r)
            for (size_t q = 0; q < lanes; q++)
                sum[q] += z[q][outer + db] - z[q][outer + da];
    } else {
        for (size_t outer = 0; outer < sh->count; outer += r * s)
            for (size_t at = outer; at < outer + s; at++)
                for (size_t q = 0; q < lanes; q++)
                    sum[q] += z[q][at + db] - z[q][at + da];
    }
    for (size_t q = 0; q < lanes; q++)
        out[q] = sum[q] / (double)(sh->count / r);
}

/* lane_sums for 1..LANES lanes (3 runs as 4, the last lane repeating one). */
static void mean_differences(const double *z[LANES], const line_shape *sh, size_t nl, double out[LANES])
{
    if (nl == 1)
        lane_sums(z, sh, 1, out);
    else if (nl == 2)
        lane_sums(z, sh, 2, out);
    else
        lane_sums(z, sh, LANES, out);
}

/* `part` along axis i of the nj grids g[0..nj-1] (outputs z[q]) into
 * out[q]; where not defined, `none`.  Grids of equal shape share one pass;
 * lanes beyond those are not summed or repeat a used one. */
static void axis_differences(const rf_grid *g, const double *const *z, size_t nj, size_t i, line_part part,
                             double none, double *out)
{
    line_shape sh[LANES];
    int todo[LANES];
    for (size_t q = 0; q < nj; q++)
        if (!(todo[q] = shape_of(&g[q], i, part, &sh[q])))
            out[q] = none;
    for (size_t q0 = 0; q0 < nj; q0++) {
        if (!todo[q0])
            continue;
        size_t lane[LANES], nl = 0;
        const double *zz[LANES];
        for (size_t q = q0; q < nj; q++)
            if (todo[q] && same_shape(&sh[q], &sh[q0])) {
                todo[q] = 0;
                lane[nl++] = q;
            }
        for (size_t l = 0; l < LANES; l++)
            zz[l] = z[lane[l < nl ? l : 0]];
        double res[LANES];
        mean_differences(zz, &sh[q0], nl, res);
        for (size_t l = 0; l < nl; l++)
            out[lane[l]] = res[l];
    }
}

/* Differences of the output below this are rounding, not influence: a
 * model constant on a level box (e.g. R_t = 5/7 while a boulder rolls)
 * returns values that differ in the last bits with inputs that cannot
 * matter, and normalising such noise would rank an input by it. */
#define NOISE_RTOL 1e-12

static double denoise(double diff, double floor_abs) { return fabs(diff) <= floor_abs ? 0.0 : diff; }

/* Trapezoidal rule over the levels mu_j = j/m of g[0..m]. */
static double integrate_levels(const double *g, size_t m)
{
    double t = 0;
    for (size_t j = 0; j < m; j++)
        t += 0.5 * (g[j] + g[j + 1]);
    return t / (double)m;
}

/* Mean differences along every input of every output on a family of grids
 * (levels 0..nlev-1), LANES levels at a time, each grid's outputs gathered
 * once: first-to-last into span[(k*n + i)*nlev + j] (NaN if the input has
 * one value there); with left != NULL also first-to-nominal into left and
 * nominal-to-last into right (0 where the nominal is an end). */
static int grid_differences(const struct rf_tm_data *d, const rf_grid *grids, size_t nlev, double *span,
                            double *left, double *right)
{
    size_t n = d->n, no = d->n_out, maxc = 1;
    for (size_t j = 0; j < nlev; j++)
        maxc = grids[j].count > maxc ? grids[j].count : maxc;
    double *scratch = malloc(LANES * maxc * sizeof(double)); /* outputs of grids whose ids are not consecutive */
    if (!scratch)
        return -1;
    for (size_t k = 0; k < no; k++)
        for (size_t j0 = 0; j0 < nlev; j0 += LANES) {
            const rf_grid *g = &grids[j0];
            size_t nj = nlev - j0 < LANES ? nlev - j0 : LANES;
            const double *z[LANES];
            for (size_t q = 0; q < nj; q++)
                z[q] = rf_tm_outputs(d, &g[q], k, scratch + q * maxc);
            for (size_t i = 0; i < n; i++) {
                size_t at = (k * n + i) * nlev + j0;
                if (span)
                    axis_differences(g, z, nj, i, SPAN, NAN, span + at);
                if (left) {
                    axis_differences(g, z, nj, i, LEFT, 0, left + at);
                    axis_differences(g, z, nj, i, RIGHT, 0, right + at);
                }
            }
        }
    free(scratch);
    return 0;
}

/* Gain factors and Hanss's measures (s.5.1-5.3) of output k; diff from
 * grid_differences on the main grids, levels 0..m-1. */
static void hanss_measures(const rf_tm_result *res, rf_analysis *an, size_t k, const double *diff, double noise)
{
    size_t n = res->n_inputs, m = res->levels;
    double zbar = res->nominal[k], ksum = 0;
    int any_kappa = 0;
    for (size_t i = 0; i < n; i++) {
        size_t at = k * n + i;
        double wsum = 0, gsum = 0, ksum_i = 0, kw = 0;
        for (size_t j = 0; j < m; j++) {
            double w = res->in_hi[i * (m + 1) + j] - res->in_lo[i * (m + 1) + j];
            double dz = diff[at * m + j], eta = NAN;
            if (!isnan(dz) && w > 0)
                eta = denoise(dz, noise) / w;
            an->gain[at * m + j] = eta;
            double mu = (double)j / (double)m;
            if (j >= 1) {
                kw += mu;
                if (!isnan(eta)) {
                    wsum += mu;
                    gsum += mu * eta;
                    ksum_i += mu * fabs(eta) * w;
                }
            }
        }
        if (wsum > 0) {
            an->mean_gain[at] = gsum / wsum;
            an->kappa[at] = ksum_i / kw;
            ksum += an->kappa[at];
            any_kappa = 1;
            if (zbar != 0) {
                an->std_gain[at] = an->mean_gain[at] * res->in_nominal[i] / zbar;
            } else {
                an->std_gain[at] = NAN;
                an->reason_std[at] = RF_NA_ZERO_NOMINAL;
            }
        } else {
            an->mean_gain[at] = an->kappa[at] = an->std_gain[at] = NAN;
            an->reason_hanss[at] = an->reason_std[at] = m < 2 ? RF_NA_FEW_LEVELS : RF_NA_CRISP;
        }
    }
    for (size_t i = 0; i < n; i++) {
        size_t at = k * n + i;
        if (an->reason_hanss[at]) {
            an->rho[at] = NAN;
        } else if (!any_kappa || ksum <= 0) {
            an->rho[at] = NAN;
            an->reason_hanss[at] = RF_NA_ALL_ZERO;
        } else {
            an->rho[at] = an->kappa[at] / ksum;
        }
    }
}

/* Left/right spreads L, U of input i (output k) at every level from the
 * three-point differences; returns whether the input has any width. */
static int lr_spreads(const rf_tm_result *res, size_t k, size_t i, const double *left, const double *right,
                      double noise, double *L, double *U)
{
    const struct rf_tm_data *d = res->data;
    size_t n = res->n_inputs, m = res->levels, at = (k * n + i) * (m + 1);
    int has_width = 0;
    for (size_t j = 0; j <= m; j++) {
        const rf_grid *g = &d->lr[j];
        double a = res->in_lo[i * (m + 1) + j], b = res->in_hi[i * (m + 1) + j];
        double xb = res->in_nominal[i], dm = xb - a, dp = b - xb;
        size_t pn = g->nominal_pos[i], last = g->radix[i] - 1;
        double em = 0, ep = 0;
        if (pn > 0 && dm > 0)
            em = denoise(left[at + j], noise) / dm;
        else
            dm = 0;
        if (pn < last && dp > 0)
            ep = denoise(right[at + j], noise) / dp;
        else
            dp = 0;
        has_width |= dm > 0 || dp > 0;
        L[j] = fmax(0, em) * dm + fmax(0, -ep) * dp;
        U[j] = fmax(0, -em) * dm + fmax(0, ep) * dp;
    }
    return has_width;
}

/* Left/right measures (s.5.4) of output k; returns their sum. */
static double lr_measures(const rf_tm_result *res, rf_analysis *an, size_t k, const double *left,
                          const double *right, double noise, double *L, double *U)
{
    size_t n = res->n_inputs, m = res->levels;
    double zbar = res->nominal[k], lrsum = 0;
    for (size_t i = 0; i < n; i++) {
        size_t at = k * n + i;
        an->kappa_left[at] = an->kappa_right[at] = NAN;
        if (!res->data->lr) {
            an->reason_lr[at] = RF_NA_NO_LR;
            continue;
        }
        if (!lr_spreads(res, k, i, left, right, noise, L, U)) {
            an->reason_lr[at] = RF_NA_CRISP;
            continue;
        }
        if (zbar == 0) {
            an->reason_lr[at] = RF_NA_ZERO_NOMINAL;
            continue;
        }
        an->kappa_left[at] = integrate_levels(L, m) / fabs(zbar);
        an->kappa_right[at] = integrate_levels(U, m) / fabs(zbar);
        lrsum += an->kappa_left[at] + an->kappa_right[at];
    }
    for (size_t i = 0; i < n; i++) {
        size_t at = k * n + i;
        if (an->reason_lr[at]) {
            an->rho_left[at] = an->rho_right[at] = NAN;
        } else if (lrsum <= 0) {
            an->rho_left[at] = an->rho_right[at] = NAN;
            an->reason_lr[at] = RF_NA_ALL_ZERO;
        } else {
            an->rho_left[at] = an->kappa_left[at] / lrsum;
            an->rho_right[at] = an->kappa_right[at] / lrsum;
        }
    }
    return lrsum;
}

static void undefined_output(rf_analysis *an, size_t k, size_t n, size_t m)
{
    for (size_t i = 0; i < n; i++) {
        size_t at = k * n + i;
        for (size_t j = 0; j < m; j++)
            an->gain[at * m + j] = NAN;
        an->mean_gain[at] = an->std_gain[at] = an->kappa[at] = an->rho[at] = NAN;
        an->kappa_left[at] = an->kappa_right[at] = an->rho_left[at] = an->rho_right[at] = NAN;
        an->reason_hanss[at] = an->reason_std[at] = an->reason_lr[at] = RF_NA_UNDEFINED;
    }
    an->degree_of_uncertainty[k] = an->interaction[k] = NAN;
    an->reason_nu[k] = RF_NA_UNDEFINED;
}

static int analysis_alloc(rf_analysis *an, size_t n, size_t no, size_t m)
{
    size_t nk = n * no;
    an->n_inputs = n;
    an->n_outputs = no;
    an->levels = m;
    an->gain = malloc(nk * m * sizeof(double));
    an->mean_gain = malloc(nk * sizeof(double));
    an->std_gain = malloc(nk * sizeof(double));
    an->kappa = malloc(nk * sizeof(double));
    an->rho = malloc(nk * sizeof(double));
    an->kappa_left = malloc(nk * sizeof(double));
    an->kappa_right = malloc(nk * sizeof(double));
    an->rho_left = malloc(nk * sizeof(double));
    an->rho_right = malloc(nk * sizeof(double));
    an->reason_hanss = calloc(nk, sizeof(rf_na_reason));
    an->reason_std = calloc(nk, sizeof(rf_na_reason));
    an->reason_lr = calloc(nk, sizeof(rf_na_reason));
    an->degree_of_uncertainty = malloc(no * sizeof(double));
    an->interaction = malloc(no * sizeof(double));
    an->reason_nu = calloc(no, sizeof(rf_na_reason));
    return !an->gain || !an->mean_gain || !an->std_gain || !an->kappa || !an->rho || !an->kappa_left ||
           !an->kappa_right || !an->rho_left || !an->rho_right || !an->reason_hanss || !an->reason_std ||
           !an->reason_lr || !an->degree_of_uncertainty || !an->interaction || !an->reason_nu;
}

/* Degree of uncertainty: area under the output membership / |zbar|. */
static void degree_of_uncertainty(const rf_tm_result *res, rf_analysis *an, size_t k, double *width)
{
    size_t m = res->levels;
    double zbar = res->nominal[k];
    for (size_t j = 0; j <= m; j++)
        width[j] = res->hi[k * (m + 1) + j] - res->lo[k * (m + 1) + j];
    double area = integrate_levels(width, m);
    if (zbar != 0) {
        an->degree_of_uncertainty[k] = area / fabs(zbar);
    } else {
        an->degree_of_uncertainty[k] = NAN;
        an->reason_nu[k] = RF_NA_ZERO_NOMINAL;
    }
}

rf_status rf_analysis_compute(const rf_tm_result *res, rf_analysis *an, rf_error *err)
{
    memset(an, 0, sizeof *an);
    const struct rf_tm_data *d = res->data;
    if (!d)
        return rf_fail(err, RF_EINVAL, "the TM result holds no evaluation data");
    size_t n = res->n_inputs, no = res->n_outputs, m = res->levels, nk = n * no;
    double *L = malloc(3 * (m + 1) * sizeof(double)), *U = L ? L + (m + 1) : NULL, *width = L ? U + (m + 1) : NULL;
    double *diff = malloc(nk * (3 * m + 2) * sizeof(double));
    double *left = diff ? diff + nk * m : NULL, *right = diff ? left + nk * (m + 1) : NULL;
    int bad = analysis_alloc(an, n, no, m) || !L || !diff || grid_differences(d, d->main, m, diff, NULL, NULL) ||
              (d->lr && grid_differences(d, d->lr, m + 1, NULL, left, right));
    for (size_t k = 0; !bad && k < no; k++) {
        double zbar = res->nominal[k];
        double noise = NOISE_RTOL * fmax(fabs(zbar), fmax(fabs(res->lo[k * (m + 1)]), fabs(res->hi[k * (m + 1)])));
        if (res->output_undefined && res->output_undefined[k]) {
            undefined_output(an, k, n, m);
            continue;
        }
        hanss_measures(res, an, k, diff, noise);
        degree_of_uncertainty(res, an, k, width);
        double lrsum = lr_measures(res, an, k, left, right, noise, L, U);
        an->interaction[k] = (d->lr && zbar != 0) ? an->degree_of_uncertainty[k] - lrsum : NAN;
    }
    free(L);
    free(diff);
    if (bad) {
        rf_analysis_free(an);
        return rf_fail(err, RF_ENOMEM, "out of memory for the analysis");
    }
    return RF_OK;
}

rf_status rf_analysis_compute_values(const rf_tm_result *res, size_t n_cols, const double *y, double *lo, double *hi,
                                     rf_analysis *an, rf_error *err)
{
    memset(an, 0, sizeof *an);
    rf_tm_result v;
    rf_status st = tm_values_result(res, n_cols, y, lo, hi, &v, err);
    if (!st)
        st = rf_analysis_compute(&v, an, err);
    if (!st && (lo == NULL) != (hi == NULL)) /* one of them asked for: copy it out of the view */
        memcpy(lo ? lo : hi, lo ? v.lo : v.hi, n_cols * (res->levels + 1) * sizeof(double));
    tm_values_result_free(&v);
    return st;
}
