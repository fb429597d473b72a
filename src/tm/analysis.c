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

/* Mean over the lines parallel to axis i of z(last) - z(first), or of the
 * given positions pa -> pb. */
static double mean_difference(const struct rf_tm_data *d, const rf_grid *g, size_t i, size_t k, size_t pa,
                              size_t pb)
{
    size_t r = g->radix[i], s = g->stride[i], no = d->n_out, lines = 0;
    double sum = 0;
    for (size_t outer = 0; outer < g->count; outer += r * s)
        for (size_t inner = 0; inner < s; inner++) {
            size_t base = outer + inner;
            sum += d->y[(size_t)g->ids[base + pb * s] * no + k] - d->y[(size_t)g->ids[base + pa * s] * no + k];
            lines++;
        }
    return sum / (double)lines;
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

rf_status rf_analysis_compute(const rf_tm_result *res, rf_analysis *an, rf_error *err)
{
    memset(an, 0, sizeof *an);
    const struct rf_tm_data *d = res->data;
    if (!d)
        return rf_fail(err, RF_EINVAL, "the TM result holds no evaluation data");
    size_t n = res->n_inputs, no = res->n_outputs, m = res->levels, nk = n * no;
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
    double *L = malloc((m + 1) * sizeof(double)), *U = malloc((m + 1) * sizeof(double));
    double *width = malloc((m + 1) * sizeof(double));
    if (!an->gain || !an->mean_gain || !an->std_gain || !an->kappa || !an->rho || !an->kappa_left ||
        !an->kappa_right || !an->rho_left || !an->rho_right || !an->reason_hanss || !an->reason_std ||
        !an->reason_lr || !an->degree_of_uncertainty || !an->interaction || !an->reason_nu || !L || !U || !width) {
        free(L);
        free(U);
        free(width);
        rf_analysis_free(an);
        return rf_fail(err, RF_ENOMEM, "out of memory for the analysis");
    }

    for (size_t k = 0; k < no; k++) {
        double zbar = res->nominal[k];
        double noise = NOISE_RTOL * fmax(fabs(zbar), fmax(fabs(res->lo[k * (m + 1)]), fabs(res->hi[k * (m + 1)])));
        if (res->output_undefined && res->output_undefined[k]) {
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
            continue;
        }
        /* ---- gain factors and Hanss measures (s.5.1-5.3) */
        double ksum = 0;
        int any_kappa = 0;
        for (size_t i = 0; i < n; i++) {
            size_t at = k * n + i;
            double wsum = 0, gsum = 0, ksum_i = 0, kw = 0;
            for (size_t j = 0; j < m; j++) {
                const rf_grid *g = &d->main[j];
                double w = res->in_hi[i * (m + 1) + j] - res->in_lo[i * (m + 1) + j];
                double eta = NAN;
                if (g->radix[i] >= 2 && w > 0)
                    eta = denoise(mean_difference(d, g, i, k, 0, g->radix[i] - 1), noise) / w;
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

        /* ---- degree of uncertainty: area under the output membership / |zbar| */
        for (size_t j = 0; j <= m; j++)
            width[j] = res->hi[k * (m + 1) + j] - res->lo[k * (m + 1) + j];
        double area = integrate_levels(width, m);
        if (zbar != 0) {
            an->degree_of_uncertainty[k] = area / fabs(zbar);
        } else {
            an->degree_of_uncertainty[k] = NAN;
            an->reason_nu[k] = RF_NA_ZERO_NOMINAL;
        }

        /* ---- left/right measures (s.5.4) */
        double lrsum = 0;
        for (size_t i = 0; i < n; i++) {
            size_t at = k * n + i;
            an->kappa_left[at] = an->kappa_right[at] = NAN;
            if (!d->lr) {
                an->reason_lr[at] = RF_NA_NO_LR;
                continue;
            }
            int has_width = 0;
            for (size_t j = 0; j <= m; j++) {
                const rf_grid *g = &d->lr[j];
                double a = res->in_lo[i * (m + 1) + j], b = res->in_hi[i * (m + 1) + j];
                double xb = res->in_nominal[i], dm = xb - a, dp = b - xb;
                size_t pn = g->nominal_pos[i], last = g->radix[i] - 1;
                double em = 0, ep = 0;
                if (pn > 0 && dm > 0)
                    em = denoise(mean_difference(d, g, i, k, 0, pn), noise) / dm;
                else
                    dm = 0;
                if (pn < last && dp > 0)
                    ep = denoise(mean_difference(d, g, i, k, pn, last), noise) / dp;
                else
                    dp = 0;
                has_width |= dm > 0 || dp > 0;
                L[j] = fmax(0, em) * dm + fmax(0, -ep) * dp;
                U[j] = fmax(0, -em) * dm + fmax(0, ep) * dp;
            }
            if (!has_width) {
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
        an->interaction[k] = (d->lr && zbar != 0) ? an->degree_of_uncertainty[k] - lrsum : NAN;
    }
    free(L);
    free(U);
    free(width);
    return RF_OK;
}
