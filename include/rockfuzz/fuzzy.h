/* fuzzy.h - fuzzy numbers and their alpha-cut decomposition (tm_spec.md s.1).
 *
 * One type, rf_fuzzy, for every shape.  Constructors validate and return a
 * message naming the offending value; a constructed number is always valid:
 * its support ends are finite and within +-DBL_MAX/4 (the TM adds and
 * subtracts them), and a positive spread does not vanish in rounding at the
 * peak.  rf_fuzzy_decompose also refuses a support too narrow for doubles
 * to resolve the m levels' grid values.
 * Level j of a decomposition with m intervals has membership mu_j = j/m; the
 * level-0 cut is the closure of the support. */
#ifndef ROCKFUZZ_FUZZY_H
#define ROCKFUZZ_FUZZY_H

#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RF_FUZZY_CRISP,       /* p[0] = value */
    RF_FUZZY_INTERVAL,    /* p[0..1] = lo, hi (flat core: trapezoid lo,lo,hi,hi) */
    RF_FUZZY_TRIANGULAR,  /* p[0..2] = peak, left deviation, right deviation (Hanss tfn) */
    RF_FUZZY_TRAPEZOID,   /* p[0..3] = x1 <= x2 <= x3 <= x4: support [x1,x4], core [x2,x3] */
    RF_FUZZY_GAUSSIAN,    /* p[0..3] = peak, sigma left, sigma right, cut-off factor c */
    RF_FUZZY_POINTS,      /* piecewise linear through (x, mu) points */
    RF_FUZZY_CUTS         /* given by its cuts at listed levels, linear in mu between them */
} rf_fuzzy_kind;

typedef struct {
    rf_fuzzy_kind kind;
    double p[4];
    size_t n;       /* POINTS: number of points; CUTS: number of levels */
    double *a;      /* POINTS: abscissae x;  CUTS: membership levels (ascending, 0 first, 1 last) */
    double *b;      /* POINTS: memberships;  CUTS: lower bounds */
    double *c;      /* CUTS: upper bounds */
} rf_fuzzy;

rf_status rf_fuzzy_crisp(rf_fuzzy *f, double value, rf_error *err);
rf_status rf_fuzzy_interval(rf_fuzzy *f, double lo, double hi, rf_error *err);
rf_status rf_fuzzy_tfn(rf_fuzzy *f, double peak, double left, double right, rf_error *err);
rf_status rf_fuzzy_trapezoid(rf_fuzzy *f, double x1, double x2, double x3, double x4, rf_error *err);
/* Quasi-Gaussian truncated at peak - cutoff*sigma_l and peak + cutoff*sigma_r (cutoff > 0, usually 3). */
rf_status rf_fuzzy_gaussian(rf_fuzzy *f, double peak, double sigma_l, double sigma_r, double cutoff,
                            rf_error *err);
/* Piecewise-linear through n points (x_k, mu_k), x non-decreasing, mu rising
 * from 0 to 1, optionally flat at 1 (core), then falling to 0; copies the arrays. */
rf_status rf_fuzzy_points(rf_fuzzy *f, size_t n, const double *x, const double *mu, rf_error *err);
/* Cuts [lower_k, upper_k] at levels mu_k (ascending, mu_0 = 0, mu_last = 1);
 * they must nest: lower non-decreasing, upper non-increasing, lower <= upper. */
rf_status rf_fuzzy_cuts(rf_fuzzy *f, size_t n, const double *mu, const double *lower,
                        const double *upper, rf_error *err);

void rf_fuzzy_free(rf_fuzzy *f);
rf_status rf_fuzzy_copy(rf_fuzzy *dst, const rf_fuzzy *src, rf_error *err);

/* Cut at membership mu in [0, 1]; mu = 0 gives the support closure. */
void rf_fuzzy_cut(const rf_fuzzy *f, double mu, double *lo, double *hi);
/* Membership of x. */
double rf_fuzzy_membership(const rf_fuzzy *f, double x);
/* Nominal (modal) value: the peak, or the midpoint of a flat core. */
double rf_fuzzy_nominal(const rf_fuzzy *f);
/* Short description, e.g. "tfn(2, 1, 1)". */
void rf_fuzzy_describe(const rf_fuzzy *f, char *buf, size_t size);

/* Decompose into m+1 cuts lo[j], hi[j], j = 0..m at mu_j = j/m, and check
 * that they nest (the message names the level and the bounds if not). */
rf_status rf_fuzzy_decompose(const rf_fuzzy *f, size_t m, double *lo, double *hi, rf_error *err);

/* Check that m+1 cuts nest: lo[j] <= lo[j+1] <= hi[j+1] <= hi[j]. */
rf_status rf_cuts_check_nested(size_t m, const double *lo, const double *hi, rf_error *err);

/* Check that a support of positive width is wide enough for doubles to
 * resolve the TM's grid values at m levels (64 m spacings of doubles at the
 * support's magnitude); rf_fuzzy_decompose applies it. */
rf_status rf_cuts_check_resolution(size_t m, const double *lo, const double *hi, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
