/* report_util.c - small helpers shared by the report writers (report.c,
 * report_plot.c, report_html.c), kept apart so that those files never call
 * into each other for them. */
#include "study/report_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/html.h"
#include "core/util.h"
#include "rockfuzz/impact_model.h"

int rp_output_undefined(const rf_tm_result *res, size_t k)
{
    for (size_t j = 0; j <= res->levels; j++)
        if (!isnan(res->lo[k * (res->levels + 1) + j]) || !isnan(res->hi[k * (res->levels + 1) + j]))
            return 0;
    return isnan(res->nominal[k]);
}

void rp_safe_name(const char *name, char *buf, size_t size)
{
    size_t k = 0;
    for (; name[k] && k + 1 < size && k < 80; k++) {
        char ch = name[k];
        int ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
                 ch == '-' || (ch == '.' && k > 0);
        buf[k] = ok ? ch : '_';
    }
    buf[k] = '\0';
    if (k == 0)
        snprintf(buf, size, "_");
}

/* Every cut bound and the nominal value are exactly zero. */
static int output_all_zero(const rf_tm_result *res, size_t k)
{
    for (size_t j = 0; j <= res->levels; j++)
        if (res->lo[k * (res->levels + 1) + j] != 0 || res->hi[k * (res->levels + 1) + j] != 0)
            return 0;
    return res->nominal[k] == 0;
}

/* The largest |value| of output k over its cuts and nominal point. */
static double output_max_abs(const rf_tm_result *res, size_t k)
{
    double a = fabs(res->nominal[k]);
    for (size_t j = 0; j <= res->levels; j++)
        a = fmax(a, fmax(fabs(res->lo[k * (res->levels + 1) + j]), fabs(res->hi[k * (res->levels + 1) + j])));
    return a;
}

/* The index of the output called name, or -1. */
static long output_index(const rf_study *s, const char *name)
{
    for (size_t k = 0; k < s->model.n_outputs; k++)
        if (!strcmp(s->model.output_names[k], name))
            return (long)k;
    return -1;
}

rp_output_kind rp_output_classify(const rf_study *s, const rf_tm_result *res, size_t k, char *why, size_t size)
{
    why[0] = '\0';
    if (rp_output_undefined(res, k)) {
        snprintf(why, size, "undefined: the model returns NaN at every point");
        return RP_OUTPUT_UNDEFINED;
    }
    if (output_all_zero(res, k)) {
        snprintf(why, size, "0 at every point");
        return RP_OUTPUT_ZERO;
    }
    if (strcmp(s->model.output_names[k], "indentation_depth") != 0)
        return RP_OUTPUT_SHOWN;
    long pen = output_index(s, "penetration_max"), wp = output_index(s, "plastic_work");
    double a = output_max_abs(res, k);
    if (wp >= 0 && output_all_zero(res, (size_t)wp)) {
        snprintf(why, size,
                 "below its numerical floor: the bodies stay elastic (plastic_work 0 at every point), so the "
                 "permanent indentation is 0; the |value| <= %.2g m computed is the slope's residual elastic vibration",
                 a);
        return RP_OUTPUT_BELOW_FLOOR;
    }
    if (pen < 0)
        return RP_OUTPUT_SHOWN;
    /* the smallest penetration of the study: its level-0 lower bound */
    double ref = res->lo[(size_t)pen * (res->levels + 1)];
    if (isfinite(ref) && ref > 0 && a < RP_INDENTATION_FLOOR * ref) {
        snprintf(why, size,
                 "below its numerical floor: |value| <= %.2g m, less than %.0f %% of the smallest penetration_max "
                 "(%.3g m); an elastic slope springs back and leaves only this residual vibration",
                 a, 100 * RP_INDENTATION_FLOOR, ref);
        return RP_OUTPUT_BELOW_FLOOR;
    }
    return RP_OUTPUT_SHOWN;
}

const char *rp_output_kind_name(rp_output_kind kind)
{
    switch (kind) {
    case RP_OUTPUT_UNDEFINED: return "undefined";
    case RP_OUTPUT_ZERO: return "zero";
    case RP_OUTPUT_BELOW_FLOOR: return "below_floor";
    default: return "shown";
    }
}

/* value with every comma-separated number printed %.6g (no float noise) */
static void tidy_value(const char *v, size_t len, char *out, size_t size)
{
    size_t o = 0;
    out[0] = '\0';
    while (len > 0 && o + 1 < size) {
        size_t part = 0;
        while (part < len && v[part] != ',')
            part++;
        char num[128], *end = NULL;
        snprintf(num, sizeof num, "%.*s", (int)(part < sizeof num ? part : sizeof num - 1), v);
        double x = strtod(num, &end);
        int w = (end && end != num && *end == '\0') ? snprintf(out + o, size - o, "%.6g", x)
                                                     : snprintf(out + o, size - o, "%s", num);
        o = w > 0 && (size_t)w < size - o ? o + (size_t)w : size - 1;
        if (part < len && o + 1 < size)
            out[o++] = ',', out[o] = '\0';
        v += part < len ? part + 1 : part;
        len -= part < len ? part + 1 : part;
    }
}

/* The key=value tokens of an identity into out (at most max); returns the count. */
static size_t identity_tokens(const char *id, rp_setting *out, size_t max)
{
    size_t n = 0;
    while (id && *id && n < max) {
        while (*id == ' ')
            id++;
        size_t len = strcspn(id, " ");
        const char *eq = memchr(id, '=', len);
        if (eq && eq > id) {
            size_t kl = (size_t)(eq - id);
            snprintf(out[n].key, sizeof out[n].key, "%.*s", (int)(kl < 63 ? kl : 63), id);
            tidy_value(eq + 1, len - kl - 1, out[n].value, sizeof out[n].value);
            n++;
        }
        id += len;
    }
    return n;
}

/* The identity of the impact model with every setting at its default (same solver and parameters). */
static char *impact_default_identity(const rf_study *s)
{
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    const char *sv = s->model.identity ? strstr(s->model.identity, "solver=") : NULL;
    if (sv) {
        char name[32];
        snprintf(name, sizeof name, "%.*s", (int)strcspn(sv + 7, " "), sv + 7);
        rf_error e;
        if (rf_impact_solver_parse(name, &spec.solver, &e) != RF_OK)
            return NULL;
    }
    rf_model m;
    memset(&m, 0, sizeof m);
    rf_error err;
    if (rf_impact_model_create(&spec, (const char *const *)s->param_names, s->n_params, &m, &err) != RF_OK)
        return NULL;
    char *id = m.identity ? rf_strdup(m.identity) : NULL;
    rf_model_free(&m);
    return id;
}

size_t rp_model_settings(const rf_study *s, rp_setting *out, size_t max, int *vs_defaults)
{
    *vs_defaults = 0;
    if (s->model_kind != RF_STUDY_MODEL_IMPACT && s->model_kind != RF_STUDY_MODEL_TRAJECTORY)
        return 0; /* a formula or program: the model line (its description) says it all */
    size_t n = identity_tokens(s->model.identity, out, max);
    char *def = s->model_kind == RF_STUDY_MODEL_IMPACT ? impact_default_identity(s) : NULL;
    if (!def)
        return n;
    rp_setting *d = malloc(max * sizeof *d);
    size_t nd = d ? identity_tokens(def, d, max) : 0, kept = 0;
    for (size_t i = 0; d && i < n; i++) {
        int same = 0;
        for (size_t j = 0; j < nd && !same; j++)
            same = !strcmp(out[i].key, d[j].key) && !strcmp(out[i].value, d[j].value);
        if (!same)
            out[kept++] = out[i];
    }
    *vs_defaults = d != NULL;
    free(d);
    free(def);
    return d ? kept : n;
}

const char *rp_display_unit(const char *unit, double max_abs, double *factor)
{
    *factor = 1;
    if (unit && !strcmp(unit, "J") && max_abs >= 1e4) {
        *factor = 1e-3;
        return "kJ";
    }
    return unit ? unit : "";
}

int rp_main_input(const double *rho, size_t n)
{
    int best = -1;
    for (size_t i = 0; i < n; i++)
        if (isfinite(rho[i]) && (best < 0 || rho[i] > rho[best]))
            best = (int)i;
    return best;
}

long rp_main_output(const rf_study *s, const rf_tm_result *res)
{
    if (s->main_output >= 0 && (size_t)s->main_output < res->n_outputs)
        return s->main_output;
    long first = -1;
    char why[512];
    for (size_t k = 0; k < res->n_outputs; k++) {
        if (rp_output_classify(s, res, k, why, sizeof why) != RP_OUTPUT_SHOWN)
            continue;
        const char *name = s->model.output_names[k];
        size_t len = strlen(name);
        if (len > 17 && !strcmp(name + len - 17, "_total_energy_p95"))
            return (long)k;
        if (first < 0)
            first = (long)k;
    }
    return first;
}

/* (report.h) Here, below every writer of the report, which all ask it. */
rf_status rf_report_stopped(const atomic_int *interrupt, const char *writing, rf_error *err)
{
    if (!interrupt || !atomic_load(interrupt))
        return RF_OK;
    return rf_fail(err, RF_EINTERRUPTED, "interrupted while writing the report (%s)", writing);
}

/* <img> with the PNG at dir/stem.png as a data URI; a note if it is missing. */
void rp_embed_png(FILE *f, const char *dir, const char *stem, const char *alt)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.png", dir, stem);
    if (!rf_html_png(f, path, alt))
        fprintf(f, "<p class=note>(figure %s.png not written: run without --no-plots)</p>\n", stem);
}

