/* fuzzy.c - fuzzy numbers: constructors with validation, membership, alpha-cuts
 * and decomposition (tm_spec.md s.1).  Every shape is reduced to two things
 * the TM needs: the cut at a level and the nominal value. */
#include "rockfuzz/fuzzy.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static rf_status finite_or_fail(double v, const char *what, rf_error *err)
{
    if (!isfinite(v))
        return rf_fail(err, RF_EINVAL, "%s = %g: must be a finite number", what, v);
    return RF_OK;
}

/* Largest magnitude a support end may have: the TM forms sums and
 * differences of two support values (midpoints, widths), which must stay
 * finite. */
#define RF_FUZZY_MAX_ABS (DBL_MAX / 4)

/* A support end computed from the parameters must be a finite number the
 * TM can add and subtract. */
static rf_status end_or_fail(double v, const char *what, rf_error *err)
{
    if (!isfinite(v) || fabs(v) > RF_FUZZY_MAX_ABS)
        return rf_fail(err, RF_EINVAL, "%s = %g: beyond +-%g, the largest support end the TM can handle (sums "
                                       "and widths of support values must stay finite)",
                       what, v, RF_FUZZY_MAX_ABS);
    return RF_OK;
}

/* A spread given as positive must survive rounding at the peak's magnitude:
 * peak - left == peak would make a fuzzy input silently crisp. */
static rf_status spread_or_fail(double peak, double spread, double end, const char *what, rf_error *err)
{
    if (spread > 0 && end == peak)
        return rf_fail(err, RF_EINVAL,
                       "%s = %g vanishes next to the peak %g in double precision (spacing %g there): the "
                       "parameter would be crisp; shift or rescale it (e.g. give it relative to a reference value)",
                       what, spread, peak, nextafter(fabs(peak), INFINITY) - fabs(peak));
    return RF_OK;
}

static void reset(rf_fuzzy *f, rf_fuzzy_kind kind)
{
    memset(f, 0, sizeof *f);
    f->kind = kind;
}

rf_status rf_fuzzy_crisp(rf_fuzzy *f, double value, rf_error *err)
{
    reset(f, RF_FUZZY_CRISP);
    if (finite_or_fail(value, "value", err) || end_or_fail(value, "value", err))
        return RF_EINVAL;
    f->p[0] = value;
    return RF_OK;
}

rf_status rf_fuzzy_interval(rf_fuzzy *f, double lo, double hi, rf_error *err)
{
    reset(f, RF_FUZZY_INTERVAL);
    if (finite_or_fail(lo, "lower bound", err) || finite_or_fail(hi, "upper bound", err))
        return RF_EINVAL;
    if (lo > hi)
        return rf_fail(err, RF_EINVAL, "interval [%g, %g]: the lower bound exceeds the upper bound", lo, hi);
    if (end_or_fail(lo, "lower bound", err) || end_or_fail(hi, "upper bound", err))
        return RF_EINVAL;
    f->p[0] = lo;
    f->p[1] = hi;
    return RF_OK;
}

rf_status rf_fuzzy_tfn(rf_fuzzy *f, double peak, double left, double right, rf_error *err)
{
    reset(f, RF_FUZZY_TRIANGULAR);
    if (finite_or_fail(peak, "peak", err) || finite_or_fail(left, "left deviation", err) ||
        finite_or_fail(right, "right deviation", err))
        return RF_EINVAL;
    if (left < 0)
        return rf_fail(err, RF_EINVAL, "left deviation = %g: must be >= 0", left);
    if (right < 0)
        return rf_fail(err, RF_EINVAL, "right deviation = %g: must be >= 0", right);
    if (end_or_fail(peak, "peak", err) || end_or_fail(peak - left, "peak - left deviation", err) ||
        end_or_fail(peak + right, "peak + right deviation", err) ||
        spread_or_fail(peak, left, peak - left, "left deviation", err) ||
        spread_or_fail(peak, right, peak + right, "right deviation", err))
        return RF_EINVAL;
    f->p[0] = peak;
    f->p[1] = left;
    f->p[2] = right;
    return RF_OK;
}

rf_status rf_fuzzy_trapezoid(rf_fuzzy *f, double x1, double x2, double x3, double x4, rf_error *err)
{
    reset(f, RF_FUZZY_TRAPEZOID);
    const double x[4] = {x1, x2, x3, x4};
    for (int k = 0; k < 4; k++) {
        char what[16];
        snprintf(what, sizeof what, "x%d", k + 1);
        if (finite_or_fail(x[k], what, err))
            return RF_EINVAL;
    }
    if (!(x1 <= x2 && x2 <= x3 && x3 <= x4))
        return rf_fail(err, RF_EINVAL,
                       "trapezoid (%g, %g, %g, %g): needs x1 <= x2 <= x3 <= x4 (support [x1, x4], core [x2, x3])",
                       x1, x2, x3, x4);
    if (end_or_fail(x1, "x1", err) || end_or_fail(x4, "x4", err))
        return RF_EINVAL;
    memcpy(f->p, x, sizeof x);
    return RF_OK;
}

rf_status rf_fuzzy_gaussian(rf_fuzzy *f, double peak, double sigma_l, double sigma_r, double cutoff,
                            rf_error *err)
{
    reset(f, RF_FUZZY_GAUSSIAN);
    if (finite_or_fail(peak, "peak", err) || finite_or_fail(sigma_l, "left sigma", err) ||
        finite_or_fail(sigma_r, "right sigma", err) || finite_or_fail(cutoff, "cutoff", err))
        return RF_EINVAL;
    if (sigma_l < 0)
        return rf_fail(err, RF_EINVAL, "left sigma = %g: must be >= 0", sigma_l);
    if (sigma_r < 0)
        return rf_fail(err, RF_EINVAL, "right sigma = %g: must be >= 0", sigma_r);
    if (cutoff <= 0)
        return rf_fail(err, RF_EINVAL, "cutoff = %g: must be > 0 (usually 3)", cutoff);
    if (end_or_fail(peak, "peak", err) || end_or_fail(peak - cutoff * sigma_l, "peak - cutoff * left sigma", err) ||
        end_or_fail(peak + cutoff * sigma_r, "peak + cutoff * right sigma", err) ||
        spread_or_fail(peak, sigma_l, peak - cutoff * sigma_l, "left sigma", err) ||
        spread_or_fail(peak, sigma_r, peak + cutoff * sigma_r, "right sigma", err))
        return RF_EINVAL;
    f->p[0] = peak;
    f->p[1] = sigma_l;
    f->p[2] = sigma_r;
    f->p[3] = cutoff;
    return RF_OK;
}

rf_status rf_fuzzy_points(rf_fuzzy *f, size_t n, const double *x, const double *mu, rf_error *err)
{
    reset(f, RF_FUZZY_POINTS);
    if (n < 1)
        return rf_fail(err, RF_EINVAL, "points: at least one point is needed");
    size_t top_first = n, top_last = n;
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(x[k]) || !isfinite(mu[k]))
            return rf_fail(err, RF_EINVAL, "point %zu (%g, %g): coordinates must be finite", k + 1, x[k], mu[k]);
        if (mu[k] < 0 || mu[k] > 1)
            return rf_fail(err, RF_EINVAL, "point %zu (%g, %g): membership must lie in [0, 1]", k + 1, x[k], mu[k]);
        if (k > 0 && x[k] < x[k - 1])
            return rf_fail(err, RF_EINVAL, "point %zu (%g, %g): abscissae must not decrease (previous x = %g)",
                           k + 1, x[k], mu[k], x[k - 1]);
        if (mu[k] == 1) {
            if (top_first == n)
                top_first = k;
            top_last = k;
        }
    }
    if (top_first == n)
        return rf_fail(err, RF_EINVAL, "points: no point has membership 1 (a fuzzy number needs a non-empty core)");
    if (end_or_fail(x[0], "x of point 1", err) || end_or_fail(x[n - 1], "x of the last point", err))
        return RF_EINVAL;
    for (size_t k = top_first; k <= top_last; k++)
        if (mu[k] != 1)
            return rf_fail(err, RF_EINVAL,
                           "point %zu (%g, %g): membership dips below 1 inside the core, the cuts would not be intervals",
                           k + 1, x[k], mu[k]);
    for (size_t k = 1; k <= top_first; k++)
        if (mu[k] < mu[k - 1])
            return rf_fail(err, RF_EINVAL,
                           "point %zu (%g, %g): membership falls before the core, the cuts would not nest",
                           k + 1, x[k], mu[k]);
    for (size_t k = top_last + 1; k < n; k++)
        if (mu[k] > mu[k - 1])
            return rf_fail(err, RF_EINVAL,
                           "point %zu (%g, %g): membership rises after the core, the cuts would not nest",
                           k + 1, x[k], mu[k]);
    f->a = malloc(n * sizeof(double));
    f->b = malloc(n * sizeof(double));
    if (!f->a || !f->b) {
        rf_fuzzy_free(f);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    memcpy(f->a, x, n * sizeof(double));
    memcpy(f->b, mu, n * sizeof(double));
    f->n = n;
    return RF_OK;
}

rf_status rf_fuzzy_cuts(rf_fuzzy *f, size_t n, const double *mu, const double *lower, const double *upper,
                        rf_error *err)
{
    reset(f, RF_FUZZY_CUTS);
    if (n < 2)
        return rf_fail(err, RF_EINVAL, "cuts: at least the levels 0 and 1 are needed");
    if (mu[0] != 0 || mu[n - 1] != 1)
        return rf_fail(err, RF_EINVAL, "cuts: the levels must start at 0 and end at 1 (got %g ... %g)", mu[0],
                       mu[n - 1]);
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(mu[k]) || !isfinite(lower[k]) || !isfinite(upper[k]))
            return rf_fail(err, RF_EINVAL, "cut %zu (mu = %g): values must be finite", k + 1, mu[k]);
        if (k > 0 && !(mu[k] > mu[k - 1]))
            return rf_fail(err, RF_EINVAL, "cut %zu: levels must increase (mu = %g after %g)", k + 1, mu[k],
                           mu[k - 1]);
        if (lower[k] > upper[k])
            return rf_fail(err, RF_EINVAL, "cut %zu at mu = %g: lower bound %g exceeds upper bound %g", k + 1,
                           mu[k], lower[k], upper[k]);
        if (k > 0 && (lower[k] < lower[k - 1] || upper[k] > upper[k - 1]))
            return rf_fail(err, RF_EINVAL,
                           "cut %zu at mu = %g is [%g, %g], not inside the cut at mu = %g [%g, %g]: cuts must nest",
                           k + 1, mu[k], lower[k], upper[k], mu[k - 1], lower[k - 1], upper[k - 1]);
    }
    if (end_or_fail(lower[0], "lower bound at mu = 0", err) ||
        end_or_fail(upper[0], "upper bound at mu = 0", err))
        return RF_EINVAL;
    f->a = malloc(n * sizeof(double));
    f->b = malloc(n * sizeof(double));
    f->c = malloc(n * sizeof(double));
    if (!f->a || !f->b || !f->c) {
        rf_fuzzy_free(f);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    memcpy(f->a, mu, n * sizeof(double));
    memcpy(f->b, lower, n * sizeof(double));
    memcpy(f->c, upper, n * sizeof(double));
    f->n = n;
    return RF_OK;
}

void rf_fuzzy_free(rf_fuzzy *f)
{
    if (!f)
        return;
    free(f->a);
    free(f->b);
    free(f->c);
    f->a = f->b = f->c = NULL;
    f->n = 0;
}

static double *dup_array(const double *src, size_t n)
{
    if (!src)
        return NULL;
    double *d = malloc(n * sizeof(double));
    if (d)
        memcpy(d, src, n * sizeof(double));
    return d;
}

rf_status rf_fuzzy_copy(rf_fuzzy *dst, const rf_fuzzy *src, rf_error *err)
{
    *dst = *src;
    dst->a = dup_array(src->a, src->n);
    dst->b = dup_array(src->b, src->n);
    dst->c = dup_array(src->c, src->n);
    if ((src->a && !dst->a) || (src->b && !dst->b) || (src->c && !dst->c)) {
        rf_fuzzy_free(dst);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    return RF_OK;
}

/* Piecewise-linear cut (spec s.1.5): smallest x of the rising branch and
 * largest x of the falling branch with membership >= mu. */
static void points_cut(const rf_fuzzy *f, double mu, double *lo, double *hi)
{
    const double *x = f->a, *u = f->b;
    size_t n = f->n;
    if (mu <= 0) {
        *lo = x[0];
        *hi = x[n - 1];
        return;
    }
    size_t k = 0;
    while (u[k] < mu)
        k++; /* terminates: some u == 1 >= mu */
    if (k == 0 || u[k] == u[k - 1])
        *lo = x[k];
    else
        *lo = x[k - 1] + (mu - u[k - 1]) * (x[k] - x[k - 1]) / (u[k] - u[k - 1]);
    size_t r = n - 1;
    while (u[r] < mu)
        r--;
    if (r == n - 1 || u[r] == u[r + 1])
        *hi = x[r];
    else
        *hi = x[r + 1] - (mu - u[r + 1]) * (x[r + 1] - x[r]) / (u[r] - u[r + 1]);
}

static void cuts_cut(const rf_fuzzy *f, double mu, double *lo, double *hi)
{
    const double *lv = f->a;
    size_t k = 0;
    while (k + 1 < f->n - 1 && lv[k + 1] < mu)
        k++;
    if (mu >= 1) {
        *lo = f->b[f->n - 1];
        *hi = f->c[f->n - 1];
        return;
    }
    double t = (mu - lv[k]) / (lv[k + 1] - lv[k]);
    if (t < 0)
        t = 0;
    if (t > 1)
        t = 1;
    *lo = f->b[k] + t * (f->b[k + 1] - f->b[k]);
    *hi = f->c[k] + t * (f->c[k + 1] - f->c[k]);
}

void rf_fuzzy_cut(const rf_fuzzy *f, double mu, double *lo, double *hi)
{
    const double *p = f->p;
    switch (f->kind) {
    case RF_FUZZY_CRISP:
        *lo = *hi = p[0];
        return;
    case RF_FUZZY_INTERVAL:
        *lo = p[0];
        *hi = p[1];
        return;
    case RF_FUZZY_TRIANGULAR:
        *lo = p[0] - (1 - mu) * p[1];
        *hi = p[0] + (1 - mu) * p[2];
        return;
    case RF_FUZZY_TRAPEZOID:
        *lo = p[0] + mu * (p[1] - p[0]);
        *hi = p[3] - mu * (p[3] - p[2]);
        return;
    case RF_FUZZY_GAUSSIAN: {
        double c = p[3];
        double h = (mu > exp(-0.5 * c * c)) ? sqrt(-2 * log(mu)) : c;
        *lo = p[0] - h * p[1];
        *hi = p[0] + h * p[2];
        return;
    }
    case RF_FUZZY_POINTS:
        points_cut(f, mu, lo, hi);
        return;
    case RF_FUZZY_CUTS:
        cuts_cut(f, mu, lo, hi);
        return;
    }
    *lo = *hi = NAN;
}

static double ramp(double x, double x0, double x1)
{
    /* membership rising linearly from 0 at x0 to 1 at x1 */
    return x1 > x0 ? (x - x0) / (x1 - x0) : 1.0;
}

double rf_fuzzy_membership(const rf_fuzzy *f, double x)
{
    const double *p = f->p;
    switch (f->kind) {
    case RF_FUZZY_CRISP:
        return x == p[0] ? 1.0 : 0.0;
    case RF_FUZZY_INTERVAL:
        return (x >= p[0] && x <= p[1]) ? 1.0 : 0.0;
    case RF_FUZZY_TRIANGULAR:
        if (x == p[0])
            return 1.0;
        if (x < p[0])
            return (p[1] > 0 && x > p[0] - p[1]) ? 1 - (p[0] - x) / p[1] : 0.0;
        return (p[2] > 0 && x < p[0] + p[2]) ? 1 - (x - p[0]) / p[2] : 0.0;
    case RF_FUZZY_TRAPEZOID:
        if (x < p[0] || x > p[3])
            return 0.0;
        if (x < p[1])
            return ramp(x, p[0], p[1]);
        if (x <= p[2])
            return 1.0;
        return ramp(-x, -p[3], -p[2]);
    case RF_FUZZY_GAUSSIAN: {
        double s = x <= p[0] ? p[1] : p[2];
        if (x == p[0])
            return 1.0;
        if (s == 0 || fabs(x - p[0]) > p[3] * s)
            return 0.0;
        double z = (x - p[0]) / s;
        return exp(-0.5 * z * z);
    }
    case RF_FUZZY_POINTS: {
        const double *xs = f->a, *u = f->b;
        if (x < xs[0] || x > xs[f->n - 1])
            return 0.0;
        double best = 0;
        for (size_t k = 0; k < f->n; k++) {
            if (xs[k] == x && u[k] > best)
                best = u[k];
            if (k + 1 < f->n && xs[k] < x && x < xs[k + 1]) {
                double v = u[k] + (u[k + 1] - u[k]) * (x - xs[k]) / (xs[k + 1] - xs[k]);
                if (v > best)
                    best = v;
            }
        }
        return best;
    }
    case RF_FUZZY_CUTS: {
        /* largest listed-or-interpolated level whose cut contains x: bisection on mu */
        double lo, hi;
        rf_fuzzy_cut(f, 0, &lo, &hi);
        if (x < lo || x > hi)
            return 0.0;
        double a = 0, b = 1;
        rf_fuzzy_cut(f, 1, &lo, &hi);
        if (x >= lo && x <= hi)
            return 1.0;
        for (int it = 0; it < 60; it++) {
            double m = 0.5 * (a + b);
            rf_fuzzy_cut(f, m, &lo, &hi);
            if (x >= lo && x <= hi)
                a = m;
            else
                b = m;
        }
        return a;
    }
    }
    return 0.0;
}

double rf_fuzzy_nominal(const rf_fuzzy *f)
{
    double lo, hi;
    rf_fuzzy_cut(f, 1.0, &lo, &hi);
    return lo == hi ? lo : 0.5 * (lo + hi);
}

void rf_fuzzy_describe(const rf_fuzzy *f, char *buf, size_t size)
{
    const double *p = f->p;
    switch (f->kind) {
    case RF_FUZZY_CRISP: snprintf(buf, size, "crisp(%g)", p[0]); return;
    case RF_FUZZY_INTERVAL: snprintf(buf, size, "interval[%g, %g]", p[0], p[1]); return;
    case RF_FUZZY_TRIANGULAR: snprintf(buf, size, "tfn(%g, %g, %g)", p[0], p[1], p[2]); return;
    case RF_FUZZY_TRAPEZOID: snprintf(buf, size, "trapezoid(%g, %g, %g, %g)", p[0], p[1], p[2], p[3]); return;
    case RF_FUZZY_GAUSSIAN: snprintf(buf, size, "gaussian(%g, %g, %g; cutoff %g)", p[0], p[1], p[2], p[3]); return;
    case RF_FUZZY_POINTS: snprintf(buf, size, "points(%zu)", f->n); return;
    case RF_FUZZY_CUTS: snprintf(buf, size, "cuts(%zu levels)", f->n); return;
    }
    snprintf(buf, size, "?");
}

rf_status rf_cuts_check_nested(size_t m, const double *lo, const double *hi, rf_error *err)
{
    for (size_t j = 0; j <= m; j++) {
        if (!(lo[j] <= hi[j]))
            return rf_fail(err, RF_EINVAL, "cut at mu = %g is [%g, %g]: lower bound exceeds upper bound",
                           (double)j / (double)m, lo[j], hi[j]);
        if (j > 0 && (lo[j] < lo[j - 1] || hi[j] > hi[j - 1]))
            return rf_fail(err, RF_EINVAL, "cut at mu = %g [%g, %g] is not inside the cut at mu = %g [%g, %g]",
                           (double)j / (double)m, lo[j], hi[j], (double)(j - 1) / (double)m, lo[j - 1], hi[j - 1]);
    }
    return RF_OK;
}

rf_status rf_fuzzy_decompose(const rf_fuzzy *f, size_t m, double *lo, double *hi, rf_error *err)
{
    if (m < 1)
        return rf_fail(err, RF_EINVAL, "levels = %zu: at least one membership interval is needed", m);
    for (size_t j = 0; j <= m; j++) {
        rf_fuzzy_cut(f, (double)j / (double)m, &lo[j], &hi[j]);
        if (!isfinite(lo[j]) || !isfinite(hi[j]) || fabs(lo[j]) > RF_FUZZY_MAX_ABS || fabs(hi[j]) > RF_FUZZY_MAX_ABS)
            return rf_fail(err, RF_EINVAL, "the cut at mu = %g is [%g, %g]: its ends must be finite and within +-%g",
                           (double)j / (double)m, lo[j], hi[j], RF_FUZZY_MAX_ABS);
    }
    rf_status st = rf_cuts_check_nested(m, lo, hi, err);
    if (st)
        return st;
    return rf_cuts_check_resolution(m, lo, hi, err);
}

/* The TM's grids put about m values (more with the midpoints of the general
 * form) across the support; doubles must resolve them: the support width
 * must be at least RESOLUTION_ULPS * m spacings of doubles at the support's
 * magnitude, unless the number is crisp. */
#define RESOLUTION_ULPS 64

rf_status rf_cuts_check_resolution(size_t m, const double *lo, const double *hi, rf_error *err)
{
    double w = hi[0] - lo[0], a = fmax(fabs(lo[0]), fabs(hi[0]));
    double ulp = nextafter(a, INFINITY) - a;
    if (w > 0 && w < RESOLUTION_ULPS * (double)m * ulp)
        return rf_fail(err, RF_EINVAL,
                       "the support [%.17g, %.17g] is only %g wide, too narrow for doubles near %g (spacing %g): "
                       "the %zu levels' grid values would not be distinct; shift or rescale the parameter (e.g. "
                       "give it relative to a reference value) or lower levels",
                       lo[0], hi[0], w, a, ulp, m);
    return RF_OK;
}
