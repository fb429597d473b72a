/* analysis.h - the analysis part of the TM (tm_spec.md s.5): gain factors,
 * mean and standardised gain factors, absolute and relative measures of
 * influence (Hanss 2002/2005), and the left/right measures with the degree of
 * uncertainty (project definition after Gauger et al. 2008, s.5.4).
 *
 * Undefined values are NaN with a reason code, never a silent 0. */
#ifndef ROCKFUZZ_ANALYSIS_H
#define ROCKFUZZ_ANALYSIS_H

#include "rockfuzz/tm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RF_NA_NONE = 0,
    RF_NA_CRISP,          /* input has zero width at every level */
    RF_NA_ZERO_NOMINAL,   /* nominal output is 0: normalised measure undefined */
    RF_NA_NO_LR,          /* the three-point grid was not evaluated (left_right off) */
    RF_NA_ALL_ZERO,       /* all influences are zero (Hanss: on levels 0 < mu < 1): relative measure undefined */
    RF_NA_FEW_LEVELS,     /* levels = 1: no level strictly between 0 and 1 to weight (s.5.3) */
    RF_NA_UNDEFINED       /* the output is NaN at every point (e.g. R_t of a normal impact) */
} rf_na_reason;

const char *rf_na_reason_text(rf_na_reason r);

typedef struct {
    size_t n_inputs, n_outputs, levels;
    /* [(k*n + i)*levels + j], j = 0..m-1 (level m has zero width) */
    double *gain;
    /* [k*n + i] */
    double *mean_gain, *std_gain;             /* etabar, sigma (s.5.3) */
    double *kappa, *rho;                      /* absolute (output units) and relative measures */
    double *kappa_left, *kappa_right;         /* s.5.4 (dimensionless) */
    double *rho_left, *rho_right;
    rf_na_reason *reason_hanss;               /* why mean_gain/kappa/rho are NaN */
    rf_na_reason *reason_std;                 /* why std_gain is NaN */
    rf_na_reason *reason_lr;                  /* why the left/right values are NaN */
    /* [k] */
    double *degree_of_uncertainty;            /* nu = area under output membership / |nominal| */
    double *interaction;                      /* nu - sum(kappa_left + kappa_right) */
    rf_na_reason *reason_nu;
} rf_analysis;

rf_status rf_analysis_compute(const rf_tm_result *res, rf_analysis *an, rf_error *err);
void rf_analysis_free(rf_analysis *an);

/* The analysis of n_cols extra outputs of a finished run (see
 * rf_tm_retransform_values for y): an has n_outputs = n_cols, each column's
 * numbers the same to the bit as rf_analysis_compute gives for an output of
 * the run with those values.  lo, hi (NULL or (m+1) per column) receive the
 * cuts as rf_tm_retransform_values does (one retransformation for both). */
rf_status rf_analysis_compute_values(const rf_tm_result *res, size_t n_cols, const double *y, double *lo, double *hi,
                                     rf_analysis *an, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
