/* report.c - the summary printed after a run, result.json and the CSV
 * tables (see report.h).  Plots are in report_plot.c.  Undefined values are
 * printed "n/a (reason)" and written as JSON null / CSV "nan". */
#include "rockfuzz/report.h"
#include "core/json.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "study/report_internal.h"

void rf_report_options_default(rf_report_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->plots = 1;
}

static const char *mono_text(rf_monotonicity m)
{
    switch (m) {
    case RF_MONO_MONOTONIC: return "monotonic";
    case RF_MONO_NONMONOTONIC: return "nonmonotonic";
    default: return "not checked";
    }
}

/* ---------------------------------------------------------------- summary */

static void print_value(FILE *f, double v)
{
    if (isnan(v))
        fprintf(f, " %12s", "n/a"); /* the reason follows on the line */
    else
        fprintf(f, " %12.6g", v);
}

/* The cut table, level-0 points and influence table of output k. */
static void print_output_detail(FILE *f, const rf_study *s, const rf_tm_result *res, const rf_analysis *an, size_t k,
                                int w)
{
    size_t n = res->n_inputs, m = res->levels;
    fprintf(f, "  %8s %16s %16s\n", "mu", "lower", "upper");
    for (size_t j = 0; j <= m; j++)
        fprintf(f, "  %8.4f %16.10g %16.10g\n", (double)j / (double)m, res->lo[k * (m + 1) + j],
                res->hi[k * (m + 1) + j]);
    fprintf(f, "  nominal: %.10g\n", res->nominal[k]);
    for (int side = 0; side < 2; side++) {
        const double *xs = side ? res->x_hi : res->x_lo;
        fprintf(f, "  level-0 %s bound %.10g at:", side ? "upper" : "lower",
                side ? res->hi[k * (m + 1)] : res->lo[k * (m + 1)]);
        for (size_t i = 0; i < n; i++)
            fprintf(f, " %s=%.10g", s->param_names[i], xs[(k * (m + 1) + 0) * n + i]);
        fputc('\n', f);
    }
    if (isnan(res->nominal[k]))
        fprintf(f, "  note: the model returns NaN for this output at the nominal point (undefined here)\n");
    fprintf(f, "  influence:\n    %-*s %12s %12s %12s %12s\n", w, "input", "rho", "kappa", "rho_left", "rho_right");
    for (size_t i = 0; i < n; i++) {
        size_t q = k * n + i;
        fprintf(f, "    %-*s", w, s->param_names[i]);
        print_value(f, an->rho[q]);
        print_value(f, an->kappa[q]);
        print_value(f, an->rho_left[q]);
        print_value(f, an->rho_right[q]);
        if (isnan(an->rho[q]) && an->reason_hanss[q] != RF_NA_NONE)
            fprintf(f, "  rho: n/a (%s)", rf_na_reason_text(an->reason_hanss[q]));
        if (isnan(an->rho_left[q]) && an->reason_lr[q] != RF_NA_NONE && s->left_right)
            fprintf(f, "  left/right: n/a (%s)", rf_na_reason_text(an->reason_lr[q]));
        fputc('\n', f);
    }
    if (!s->left_right)
        fprintf(f, "  rho_left, rho_right: n/a (options.left_right is off: the three-point grid was not evaluated)\n");
    if (isnan(an->degree_of_uncertainty[k]))
        fprintf(f, "  degree of uncertainty: n/a (%s)\n",
                an->reason_nu[k] != RF_NA_NONE ? rf_na_reason_text(an->reason_nu[k]) : "undefined");
    else if (isnan(an->interaction[k]))
        fprintf(f, "  degree of uncertainty: %.6g (interaction part n/a: %s)\n", an->degree_of_uncertainty[k],
                s->left_right ? "the nominal output is 0" : "needs the left/right grid, options.left_right is off");
    else
        fprintf(f, "  degree of uncertainty: %.6g (interaction part %.6g)\n", an->degree_of_uncertainty[k],
                an->interaction[k]);
}

/* Monotonicity of output k: a warning for the reduced form, information otherwise; returns 1 if warned. */
static int print_monotonicity(FILE *f, const rf_study *s, const rf_tm_result *res, size_t k)
{
    size_t n = res->n_inputs;
    int warned = 0;
    for (size_t i = 0; i < n; i++) {
        if (res->monotonicity[k * n + i] != RF_MONO_NONMONOTONIC)
            continue;
        if (res->scheme == RF_TM_REDUCED) {
            fprintf(f, "  WARNING: %s is not monotonic in %s on the three-point grid: the reduced form can "
                       "under-estimate this output; rerun with scheme: extended or general\n",
                    s->model.output_names[k], s->param_names[i]);
            warned = 1;
        } else {
            fprintf(f, "  note: %s is not monotonic in %s (the %s form handles this on its grid)\n",
                    s->model.output_names[k], s->param_names[i], rf_tm_scheme_name(res->scheme));
        }
    }
    return warned;
}

/* One line per kind of output that gets no section (0 everywhere, undefined, below its floor). */
static void print_skipped(FILE *f, const rf_study *s, const rf_tm_result *res)
{
    static const char *const title[] = {"", "undefined (the model returns NaN at every point)",
                                        "0 at every point", ""};
    char why[512];
    for (int kind = RP_OUTPUT_UNDEFINED; kind <= RP_OUTPUT_ZERO; kind++) {
        int any = 0;
        for (size_t k = 0; k < res->n_outputs; k++)
            if ((int)rp_output_classify(s, res, k, why, sizeof why) == kind)
                fprintf(f, "%s%s", any++ ? ", " : "\n", s->model.output_names[k]);
        if (any)
            fprintf(f, ": %s (no section).\n", title[kind]);
    }
    for (size_t k = 0; k < res->n_outputs; k++)
        if (rp_output_classify(s, res, k, why, sizeof why) == RP_OUTPUT_BELOW_FLOOR)
            fprintf(f, "\n%s: not shown, %s.\n", s->model.output_names[k], why);
}

/* The answer: per reported output its support at membership 0, nominal value and main input. */
static void print_answer(FILE *f, const rf_study *s, const rf_tm_result *res, const rf_analysis *an)
{
    size_t n = res->n_inputs, m = res->levels;
    char why[512];
    fprintf(f, "\nAnswer (support at membership 0; nominal value; the input with the largest influence rho):\n");
    for (size_t k = 0; k < res->n_outputs; k++) {
        if (rp_output_classify(s, res, k, why, sizeof why) != RP_OUTPUT_SHOWN)
            continue;
        double lo = res->lo[k * (m + 1)], hi = res->hi[k * (m + 1)], fac;
        const char *unit = s->model.output_units && s->model.output_units[k] ? s->model.output_units[k] : "";
        const char *du = rp_display_unit(unit, fmax(fabs(lo), fabs(hi)), &fac);
        fprintf(f, "  %s: %.4g to %.4g%s%s, nominal %.4g%s%s", s->model.output_names[k], lo * fac, hi * fac,
                du[0] ? " " : "", du, res->nominal[k] * fac, du[0] ? " " : "", du);
        int top = rp_main_input(an->rho + k * n, n);
        if (top >= 0)
            fprintf(f, "; %s %.0f %%", s->param_names[top], 100 * an->rho[k * n + (size_t)top]);
        fputc('\n', f);
    }
}

void rf_report_print_summary(FILE *f, const rf_study *s, const rf_tm_result *res, const rf_analysis *an)
{
    size_t n = res->n_inputs;
    int w = 12; /* width of the input-name column */
    for (size_t i = 0; i < n; i++)
        if ((int)strlen(s->param_names[i]) > w)
            w = (int)strlen(s->param_names[i]);
    fprintf(f, "\nInputs:\n");
    for (size_t i = 0; i < n; i++) {
        fprintf(f, "  %-*s  %s%s%s%s", w, s->param_names[i], s->param_shapes[i], s->param_units[i][0] ? " [" : "",
                s->param_units[i], s->param_units[i][0] ? "]" : "");
        if (res->scheme == RF_TM_EXTENDED && res->input_class)
            fprintf(f, "  class: %s%s", mono_text(res->input_class[i]),
                    s->param_class[i] != RF_MONO_AUTO ? " (forced)" : " (probe)");
        fputc('\n', f);
    }
    int warned = 0;
    char why[512];
    for (size_t k = 0; k < res->n_outputs; k++) {
        if (rp_output_classify(s, res, k, why, sizeof why) != RP_OUTPUT_SHOWN)
            continue;
        const char *unit = s->model.output_units && s->model.output_units[k] ? s->model.output_units[k] : "";
        fprintf(f, "\nOutput %s%s%s%s\n", s->model.output_names[k], unit[0] ? " [" : "", unit, unit[0] ? "]" : "");
        print_output_detail(f, s, res, an, k, w);
        warned |= print_monotonicity(f, s, res, k);
    }
    print_skipped(f, s, res);
    if (!s->left_right)
        fprintf(f, "\nMonotonicity: not checked (options.left_right is off in the study).\n");
    print_answer(f, s, res, an);
    if (warned)
        fprintf(f, "\nSee the warnings above: the reduced form is exact only for models monotonic in every input.\n");
    fputc('\n', f);
}

/* ------------------------------------------------------------------- JSON */

static void json_levels(FILE *f, size_t m)
{
    fputc('[', f);
    for (size_t j = 0; j <= m; j++)
        fprintf(f, "%s%.17g", j ? ", " : "", (double)j / (double)m);
    fputc(']', f);
}

static void json_point(FILE *f, const rf_study *s, const double *x, size_t n)
{
    fputc('{', f);
    for (size_t i = 0; i < n; i++) {
        if (i)
            fputs(", ", f);
        rf_json_string(f, s->param_names[i]);
        fputs(": ", f);
        rf_json_number(f, x[i]);
    }
    fputc('}', f);
}

static void json_reason(FILE *f, const char *key, double v, rf_na_reason r)
{
    if (isnan(v) && r != RF_NA_NONE) {
        fprintf(f, ", \"%s\": ", key);
        rf_json_string(f, rf_na_reason_text(r));
    }
}

/* "model_settings": the readable settings (differing from the defaults for the impact model). */
static void write_settings(FILE *f, const rf_study *s)
{
    enum { MAX_SETTINGS = 128 };
    rp_setting *set = malloc(MAX_SETTINGS * sizeof *set);
    int vs_defaults = 0;
    size_t n = set ? rp_model_settings(s, set, MAX_SETTINGS, &vs_defaults) : 0;
    fprintf(f, ",\n  \"model_settings_vs_defaults\": %s,\n  \"model_settings\": {", vs_defaults ? "true" : "false");
    for (size_t i = 0; i < n; i++) {
        fputs(i ? ", " : "", f);
        rf_json_string(f, set[i].key);
        fputs(": ", f);
        rf_json_string(f, set[i].value);
    }
    fputc('}', f);
    free(set);
}

/* Every message a reader of result.json / report.html must see, as JSON strings. */
static void write_warnings(FILE *f, const rf_study *s, const rf_tm_result *res, const rf_report_options *opt)
{
    char msg[1024];
    int any = 0;
#define WARN()                                                                                                    \
    do {                                                                                                        \
        fputs(any++ ? ",\n    " : "\n    ", f);                                                               \
        rf_json_string(f, msg);                                                                                    \
    } while (0)
    size_t n = res->n_inputs;
    if (res->failed_points > 0) {
        snprintf(msg, sizeof msg,
                 "%zu of %zu evaluations failed (error or NaN) and were LEFT OUT of the bounds "
                 "(--tolerate-failures): the fuzzy outputs may be too narrow; the failures are listed by "
                 "`rockfuzz status DIR`",
                 res->failed_points, res->distinct);
        WARN();
    }
    for (size_t k = 0; k < res->n_outputs; k++) {
        if (res->nan_points && res->nan_points[k] > res->failed_points) {
            snprintf(msg, sizeof msg, "output %s: NaN at %zu points, left out of its bounds", s->model.output_names[k],
                     res->nan_points[k]);
            WARN();
        }
        for (size_t i = 0; i < n; i++)
            if (res->monotonicity[k * n + i] == RF_MONO_NONMONOTONIC && res->scheme == RF_TM_REDUCED) {
                snprintf(msg, sizeof msg,
                         "%s is not monotonic in %s on the three-point grid: the reduced form can under-estimate "
                         "this output; rerun with scheme: extended or general",
                         s->model.output_names[k], s->param_names[i]);
                WARN();
            }
    }
    /* options.left_right off is the study's choice, not a warning: the run table says it */
    if (opt && opt->model_warnings && opt->model_warnings[0]) {
        /* what the model itself reported while evaluating, handed over as data */
        snprintf(msg, sizeof msg, "model: %s", opt->model_warnings);
        WARN();
    }
#undef WARN
    if (any)
        fputs("\n  ", f);
}

/* result.json: the study, its settings and the levels. */
static void json_head(FILE *f, const rf_study *s, const rf_tm_result *res)
{
    size_t m = res->levels;
    fputs("{\n  \"version\": ", f);
    rf_json_string(f, ROCKFUZZ_VERSION);
    fputs(",\n  \"name\": ", f);
    rf_json_string(f, s->name);
    fputs(",\n  \"study_file\": ", f);
    rf_json_string(f, s->path);
    fprintf(f, ",\n  \"scheme\": \"%s\",\n  \"levels\": %zu,\n  \"left_right\": %s,\n  \"model\": ",
            rf_tm_scheme_name(res->scheme), m, s->left_right ? "true" : "false");
    rf_json_string(f, s->model_description);
    fputs(",\n  \"scheme_reason\": ", f);
    rf_json_string(f, s->scheme_reason ? s->scheme_reason : "");
    fputs(",\n  \"model_kind\": ", f);
    rf_json_string(f, rf_study_model_kind_name(s->model_kind));
    long main_k = rp_main_output(s, res);
    fputs(",\n  \"main_output\": ", f);
    if (main_k >= 0)
        rf_json_string(f, s->model.output_names[main_k]);
    else
        fputs("null", f);
    fputs(",\n  \"model_identity\": ", f);
    rf_json_string(f, s->model.identity ? s->model.identity : "");
    write_settings(f, s);
    fputs(",\n  \"mu\": ", f);
    json_levels(f, m);
}

/* result.json: the fuzzy inputs. */
static void json_inputs(FILE *f, const rf_study *s, const rf_tm_result *res)
{
    size_t n = res->n_inputs, m = res->levels;
    fputs(",\n  \"inputs\": {", f);
    for (size_t i = 0; i < n; i++) {
        fputs(i ? ",\n    " : "\n    ", f);
        rf_json_string(f, s->param_names[i]);
        fputs(": {\"shape\": ", f);
        rf_json_string(f, s->param_shapes[i]);
        fputs(", \"unit\": ", f);
        rf_json_string(f, s->param_units[i]);
        fputs(", \"nominal\": ", f);
        rf_json_number(f, res->in_nominal[i]);
        fputs(", \"mu\": ", f);
        json_levels(f, m);
        fputs(", \"lower\": ", f);
        rf_json_array(f, res->in_lo + i * (m + 1), m + 1, 1);
        fputs(", \"upper\": ", f);
        rf_json_array(f, res->in_hi + i * (m + 1), m + 1, 1);
        if (res->scheme == RF_TM_EXTENDED && res->input_class)
            fprintf(f, ", \"class\": \"%s\", \"class_forced\": %s", mono_text(res->input_class[i]),
                    s->param_class[i] != RF_MONO_AUTO ? "true" : "false");
        fputc('}', f);
    }
}

/* result.json: the influence of each input on output k. */
static void json_influence(FILE *f, const rf_study *s, const rf_tm_result *res, const rf_analysis *an, size_t k)
{
    size_t n = res->n_inputs;
    fputs("],\n      \"influence\": {", f);
    for (size_t i = 0; i < n; i++) {
        size_t q = k * n + i;
        fputs(i ? ",\n        " : "\n        ", f);
        rf_json_string(f, s->param_names[i]);
        fputs(": {\"rho\": ", f);
        rf_json_number(f, an->rho[q]);
        fputs(", \"kappa\": ", f);
        rf_json_number(f, an->kappa[q]);
        fputs(", \"rho_left\": ", f);
        rf_json_number(f, an->rho_left[q]);
        fputs(", \"rho_right\": ", f);
        rf_json_number(f, an->rho_right[q]);
        fputs(", \"kappa_left\": ", f);
        rf_json_number(f, an->kappa_left[q]);
        fputs(", \"kappa_right\": ", f);
        rf_json_number(f, an->kappa_right[q]);
        fputs(", \"mean_gain\": ", f);
        rf_json_number(f, an->mean_gain[q]);
        fputs(", \"std_gain\": ", f);
        rf_json_number(f, an->std_gain[q]);
        fputs(", \"gain\": ", f);
        rf_json_array(f, an->gain + q * an->levels, an->levels, 1);
        fprintf(f, ", \"monotonicity\": \"%s\"", mono_text(res->monotonicity[q]));
        json_reason(f, "na_reason", an->rho[q], an->reason_hanss[q]);
        json_reason(f, "na_reason_std", an->std_gain[q], an->reason_std[q]);
        json_reason(f, "na_reason_lr", an->rho_left[q], an->reason_lr[q]);
        fputc('}', f);
    }
}

/* result.json: the fuzzy outputs, each with its influence measures. */
static void json_outputs(FILE *f, const rf_study *s, const rf_tm_result *res, const rf_analysis *an)
{
    size_t n = res->n_inputs, m = res->levels;
    fputs("\n  },\n  \"outputs\": {", f);
    for (size_t k = 0; k < res->n_outputs; k++) {
        fputs(k ? ",\n    " : "\n    ", f);
        rf_json_string(f, s->model.output_names[k]);
        fputs(": {\n      \"unit\": ", f);
        rf_json_string(f, s->model.output_units && s->model.output_units[k] ? s->model.output_units[k] : "");
        char why[512];
        rp_output_kind kind = rp_output_classify(s, res, k, why, sizeof why);
        fprintf(f, ",\n      \"status\": \"%s\"", rp_output_kind_name(kind));
        if (kind != RP_OUTPUT_SHOWN) {
            fputs(", \"status_reason\": ", f);
            rf_json_string(f, why);
        }
        fputs(",\n      \"mu\": ", f);
        json_levels(f, m);
        fputs(",\n      \"lower\": ", f);
        rf_json_array(f, res->lo + k * (m + 1), m + 1, 1);
        fputs(",\n      \"upper\": ", f);
        rf_json_array(f, res->hi + k * (m + 1), m + 1, 1);
        fputs(",\n      \"nominal\": ", f);
        rf_json_number(f, res->nominal[k]);
        fputs(",\n      \"x_lower\": [", f);
        for (size_t j = 0; j <= m; j++) {
            fputs(j ? ", " : "", f);
            json_point(f, s, res->x_lo + (k * (m + 1) + j) * n, n);
        }
        fputs("],\n      \"x_upper\": [", f);
        for (size_t j = 0; j <= m; j++) {
            fputs(j ? ", " : "", f);
            json_point(f, s, res->x_hi + (k * (m + 1) + j) * n, n);
        }
        json_influence(f, s, res, an, k);
        fputs("\n      },\n      \"degree_of_uncertainty\": ", f);
        rf_json_number(f, an->degree_of_uncertainty[k]);
        fputs(",\n      \"interaction\": ", f);
        rf_json_number(f, an->interaction[k]);
        if (isnan(an->degree_of_uncertainty[k]) && an->reason_nu[k] != RF_NA_NONE) {
            fputs(",\n      \"na_reason_degree_of_uncertainty\": ", f);
            rf_json_string(f, rf_na_reason_text(an->reason_nu[k]));
        }
        fputs("\n    }", f);
    }
}

/* result.json: the evaluations, warnings and run figures. */
static void json_tail(FILE *f, const rf_study *s, const rf_tm_result *res, const rf_report_options *opt)
{
    fprintf(f, "\n  },\n  \"evaluations\": {\"requested\": %zu, \"distinct\": %zu, \"probe\": %zu, \"left_right\": "
               "%zu, \"cap\": %zu, \"evaluated\": %zu, \"failed\": %zu, \"from_store\": %zu, "
               "\"failed_points\": %zu, \"on_worker_ranks\": %zu, \"model_seconds\": ",
            res->requested, res->distinct, res->probe_evaluations, res->lr_evaluations, opt ? opt->cap : 0,
            opt ? opt->evaluated : 0, opt ? opt->failed : 0, opt ? opt->resumed : 0, res->failed_points,
            opt ? opt->remote : 0);
    rf_json_number(f, opt ? opt->eval_seconds : NAN);
    fprintf(f, "},\n  \"mpi_ranks\": %d,\n  \"warnings\": [", opt && opt->mpi_ranks > 0 ? opt->mpi_ranks : 1);
    write_warnings(f, s, res, opt);
    fputs("],\n", f);
    if (opt && opt->surrogate_error && opt->surrogate_error[0]) {
        fputs("  \"impact_surrogate_error\": ", f);
        rf_json_string(f, opt->surrogate_error);
        fputs(",\n", f);
    }
    fputs("  \"wall_seconds\": ", f);
    rf_json_number(f, opt ? opt->wall_seconds : NAN);
    fprintf(f, ",\n  \"jobs\": %d,\n  \"measures\": \"rho, kappa: the influence measures of Hanss "
               "(Applied Fuzzy Arithmetic, Springer 2005); rho_left, rho_right, degree_of_uncertainty: left/right "
               "analysis, a project definition after Gauger et al. (2008); see docs/user-guide.md section 3\"\n}\n",
            opt ? opt->jobs : 0);
}

rf_status rf_report_write_json(const char *path, const rf_study *s, const rf_tm_result *res, const rf_analysis *an,
                               const rf_report_options *opt, rf_error *err)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "%s: cannot write: %s", path, strerror(errno));
    json_head(f, s, res);
    json_inputs(f, s, res);
    json_outputs(f, s, res, an);
    json_tail(f, s, res, opt);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad)
        return rf_fail(err, RF_EIO, "%s: write failed: %s", path, strerror(errno));
    return RF_OK;
}

/* -------------------------------------------------------------------- CSV */

static void csv_number(FILE *f, double v)
{
    if (isnan(v))
        fputs("nan", f);
    else
        fprintf(f, "%.17g", v);
}

static rf_status close_checked(FILE *f, const char *path, rf_error *err)
{
    int bad = ferror(f);
    if (fclose(f) != 0 || bad)
        return rf_fail(err, RF_EIO, "%s: write failed: %s", path, strerror(errno));
    return RF_OK;
}

rf_status rf_report_write_csv(const char *dir, const rf_study *s, const rf_tm_result *res, const rf_analysis *an,
                              rf_error *err)
{
    size_t n = res->n_inputs, m = res->levels;
    char path[4096], safe[128];
    snprintf(path, sizeof path, "%s/inputs.csv", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "%s: cannot write: %s", path, strerror(errno));
    fputs("input,mu,lower,upper\n", f);
    for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j <= m; j++) {
            fprintf(f, "%s,%.17g,", s->param_names[i], (double)j / (double)m);
            csv_number(f, res->in_lo[i * (m + 1) + j]);
            fputc(',', f);
            csv_number(f, res->in_hi[i * (m + 1) + j]);
            fputc('\n', f);
        }
    rf_status st = close_checked(f, path, err);
    if (st != RF_OK)
        return st;
    for (size_t k = 0; k < res->n_outputs; k++) {
        rp_safe_name(s->model.output_names[k], safe, sizeof safe);
        snprintf(path, sizeof path, "%s/cuts_%s.csv", dir, safe);
        if (!(f = fopen(path, "w")))
            return rf_fail(err, RF_EIO, "%s: cannot write: %s", path, strerror(errno));
        fputs("mu,lower,upper\n", f);
        for (size_t j = 0; j <= m; j++) {
            fprintf(f, "%.17g,", (double)j / (double)m);
            csv_number(f, res->lo[k * (m + 1) + j]);
            fputc(',', f);
            csv_number(f, res->hi[k * (m + 1) + j]);
            fputc('\n', f);
        }
        if ((st = close_checked(f, path, err)) != RF_OK)
            return st;
        snprintf(path, sizeof path, "%s/influence_%s.csv", dir, safe);
        if (!(f = fopen(path, "w")))
            return rf_fail(err, RF_EIO, "%s: cannot write: %s", path, strerror(errno));
        fputs("input,rho,kappa,rho_left,rho_right,kappa_left,kappa_right,mean_gain,std_gain,monotonicity\n", f);
        for (size_t i = 0; i < n; i++) {
            size_t q = k * n + i;
            const double v[8] = {an->rho[q],        an->kappa[q],       an->rho_left[q],  an->rho_right[q],
                                 an->kappa_left[q], an->kappa_right[q], an->mean_gain[q], an->std_gain[q]};
            fputs(s->param_names[i], f);
            for (int c = 0; c < 8; c++) {
                fputc(',', f);
                csv_number(f, v[c]);
            }
            fprintf(f, ",%s\n", mono_text(res->monotonicity[q]));
        }
        if ((st = close_checked(f, path, err)) != RF_OK)
            return st;
    }
    return RF_OK;
}

/* ------------------------------------------------------------- everything */

rf_status rf_report_make_dir(const char *dir, rf_error *err)
{
    char path[4096];
    size_t len = strlen(dir);
    if (len == 0 || len >= sizeof path)
        return rf_fail(err, RF_EIO, "'%s': not a usable output directory name", dir);
    memcpy(path, dir, len + 1);
    /* like mkdir -p: every missing parent, then the directory itself */
    for (char *p = path + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST)
            return rf_fail(err, RF_EIO, "%s: cannot create the output directory (at %s): %s", dir, path,
                           strerror(errno));
        *p = '/';
    }
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return rf_fail(err, RF_EIO, "%s: cannot create the output directory: %s", dir, strerror(errno));
    return RF_OK;
}

rf_status rf_report_write(const char *dir, const rf_study *s, const rf_tm_result *res, const rf_analysis *an,
                          const rf_report_options *opt, rf_error *err)
{
    rf_report_options def;
    if (!opt) {
        rf_report_options_default(&def);
        opt = &def;
    }
    rf_status made = rf_report_make_dir(dir, err);
    if (made != RF_OK)
        return made;
    char final_path[4096], tmp_path[4096];
    snprintf(final_path, sizeof final_path, "%s/result.json", dir);
    snprintf(tmp_path, sizeof tmp_path, "%s/result.json.tmp", dir);
    /* A result.json from an earlier run must not survive a failed rerun. */
    if (unlink(final_path) != 0 && errno != ENOENT)
        return rf_fail(err, RF_EIO, "%s: cannot remove the old result: %s", final_path, strerror(errno));
    rf_status st = rf_report_stopped(opt->interrupt, "the CSV files", err);
    if (st == RF_OK)
        st = rf_report_write_csv(dir, s, res, an, err);
    if (st == RF_OK && opt->plots)
        st = rf_report_write_plots_until(dir, s, res, an, opt->interrupt, err);
    if (st == RF_OK)
        st = rf_report_stopped(opt->interrupt, "result.json", err);
    if (st == RF_OK)
        st = rf_report_write_json(tmp_path, s, res, an, opt, err);
    if (st == RF_OK && rename(tmp_path, final_path) != 0)
        st = rf_fail(err, RF_EIO, "%s: cannot rename to result.json: %s", tmp_path, strerror(errno));
    if (st != RF_OK)
        unlink(tmp_path);
    return st;
}
