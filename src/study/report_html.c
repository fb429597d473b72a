/* report_html.c - DIR/report.html, one self-contained page per study run.
 *
 * Built only from what a run leaves behind: result.json (read with libfyaml,
 * JSON being YAML) and the membership PNGs (embedded as base64 data URIs).
 * The influence bar charts are drawn here as inline SVG from the numbers in
 * result.json, so they exist even after --no-plots.  `rockfuzz report DIR`
 * regenerates the page without evaluating anything.  A trajectory study's
 * Monte Carlo reruns (study_traj.c: DIR/nominal, bound_lower, bound_upper)
 * are shown side by side from their folders. */
#define _XOPEN_SOURCE 700 /* strndup */
#include "rockfuzz/report.h"
#include "core/html.h"
#include "core/textfile.h"

#include <dirent.h>
#include <errno.h>
#include <libfyaml.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "study/report_internal.h"

static struct fy_node *get(struct fy_node *n, const char *key)
{
    return n && fy_node_get_type(n) == FYNT_MAPPING ? fy_node_mapping_lookup_by_string(n, key, FY_NT) : NULL;
}

/* Scalar text into buf ("" when absent). */
static const char *text(struct fy_node *n, char *buf, size_t size)
{
    buf[0] = '\0';
    if (n && fy_node_get_type(n) == FYNT_SCALAR) {
        size_t len = 0;
        const char *s = fy_node_get_scalar(n, &len);
        if (s)
            snprintf(buf, size, "%.*s", (int)(len < size ? len : size - 1), s);
    }
    return buf;
}

static double number(struct fy_node *n)
{
    char buf[64];
    text(n, buf, sizeof buf);
    if (!buf[0] || !strcmp(buf, "null"))
        return NAN;
    char *end = NULL;
    double v = strtod(buf, &end);
    return end && *end == '\0' ? v : NAN;
}

static void cell_number(FILE *f, double v)
{
    if (isnan(v))
        fputs("<td class=na>n/a</td>", f);
    else
        fprintf(f, "<td>%.6g</td>", v);
}

/* <img> with the PNG at dir/stem.png as a data URI; a note if it is missing. */
static void embed_png(FILE *f, const char *dir, const char *stem, const char *alt)
{
    rp_embed_png(f, dir, stem, alt);
}

/* Horizontal bars of rho (and rho_left/right) per input, inline SVG. */
static void influence_svg(FILE *f, struct fy_node *influence)
{
    size_t n = (size_t)fy_node_mapping_item_count(influence);
    if (n == 0)
        return;
    /* rho_left/right exist only with the three-point grid: otherwise one bar per input */
    int bars = 1;
    void *probe = NULL;
    struct fy_node_pair *pp;
    while ((pp = fy_node_mapping_iterate(influence, &probe)))
        if (!isnan(number(get(fy_node_pair_value(pp), "rho_left"))))
            bars = 3;
    int row = 20, label = 130, width = 300, h = (int)n * row * bars + 36;
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" class=bars>\n",
            label + width + 70, h);
    static const char *const keys[3] = {"rho", "rho_left", "rho_right"};
    static const char *const colours[3] = {"#1f77b4", "#2ca02c", "#d62728"};
    void *it = NULL;
    struct fy_node_pair *p;
    int y = 10;
    while ((p = fy_node_mapping_iterate(influence, &it))) {
        char name[256];
        text(fy_node_pair_key(p), name, sizeof name);
        fprintf(f, "<text x=\"%d\" y=\"%d\" text-anchor=\"end\" font-size=\"13\">", label - 6,
                y + (bars * row) / 2 + 2);
        rf_html_text(f, name);
        fputs("</text>\n", f);
        for (int c = 0; c < bars; c++) {
            double v = number(get(fy_node_pair_value(p), keys[c]));
            double w = isnan(v) ? 0 : fmin(fmax(v, 0), 1) * width;
            fprintf(f, "<rect x=\"%d\" y=\"%d\" width=\"%.1f\" height=\"%d\" fill=\"%s\"/>", label, y + c * row, w,
                    row - 6, colours[c]);
            if (isnan(v))
                fprintf(f, "<text x=\"%d\" y=\"%d\" font-size=\"11\" fill=\"#777\">n/a</text>\n", label + 4,
                        y + c * row + 12);
            else
                fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"11\">%.3f</text>\n", label + w + 4,
                        y + c * row + 12, v);
        }
        y += bars * row;
    }
    fprintf(f, "<text x=\"%d\" y=\"%d\" font-size=\"11\"><tspan fill=\"%s\">&#9632; rho (Hanss)</tspan>", label,
            h - 8, colours[0]);
    if (bars == 3)
        fprintf(f, " <tspan fill=\"%s\">&#9632; rho_left</tspan> <tspan fill=\"%s\">&#9632; rho_right</tspan>",
                colours[1], colours[2]);
    fputs("</text>\n", f);
    fputs("</svg>\n", f);
}

static const char *CSS =
    "body{font-family:sans-serif;max-width:1100px;margin:1em auto;color:#222}"
    "h1{font-size:1.5em}h2{border-bottom:1px solid #ccc;margin-top:1.6em}"
    "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}"
    "th{background:#eee;white-space:nowrap}td.l{text-align:left}td.na{color:#999}"
    ".warn{background:#fde2e1;border:2px solid #c00;padding:.5em 1em;margin:1em 0}"
    ".warn li{margin:.3em 0}.note{color:#666}img{max-width:340px;border:1px solid #ddd}"
    ".fig{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start}"
    ".summary{background:#eef5ff;border:2px solid #36c;padding:.5em 1em;margin:1em 0}"
    ".summary td.l b{font-weight:600}.wide img{max-width:100%}"
    ".reruns{display:grid;grid-template-columns:repeat(3,1fr);gap:10px}.reruns img{max-width:100%}"
    ".reruns h3{margin:.2em 0}"
    ".fuzzymaps{display:grid;grid-template-columns:repeat(2,1fr);gap:10px}.fuzzymaps img{max-width:100%}";
static void output_status(struct fy_node *o, char *buf, size_t size);

/* The outputs that get no section, one line per kind with the reason. */
static void write_skipped(FILE *f, struct fy_node *outputs)
{
    static const char *const kinds[][2] = {{"zero", "0 at every point of the study"},
                                           {"undefined", "undefined: the model returns NaN at every point"},
                                           {"below_floor", NULL}};
    char name[256], st[64], why[512];
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++) {
        int any = 0;
        void *it = NULL;
        struct fy_node_pair *p;
        while ((p = fy_node_mapping_iterate(outputs, &it))) {
            output_status(fy_node_pair_value(p), st, sizeof st);
            if (strcmp(st, kinds[k][0]) != 0)
                continue;
            fputs(any++ ? ", " : "<p class=note>Not shown: ", f);
            rf_html_text(f, text(fy_node_pair_key(p), name, sizeof name));
            if (!kinds[k][1]) {
                fputs(" (", f);
                rf_html_text(f, text(get(fy_node_pair_value(p), "status_reason"), why, sizeof why));
                fputs(")", f);
            }
        }
        if (any)
            fprintf(f, "%s%s.</p>\n", kinds[k][1] ? ": " : "", kinds[k][1] ? kinds[k][1] : "");
    }
}

/* The status of an output (result.json's "status"; older results: NaN everywhere is undefined). */
static void output_status(struct fy_node *o, char *buf, size_t size)
{
    text(get(o, "status"), buf, size);
    if (buf[0])
        return;
    struct fy_node *lo = get(o, "lower");
    int undefined = 1;
    for (int j = 0; j < fy_node_sequence_item_count(lo); j++)
        if (!isnan(number(fy_node_sequence_get_by_index(lo, j))))
            undefined = 0;
    snprintf(buf, size, "%s", undefined ? "undefined" : "shown");
}

/* The input with the largest rho of output o: its name into buf and its rho, or NaN. */
static double main_input(struct fy_node *o, char *buf, size_t size)
{
    double best = NAN;
    buf[0] = '\0';
    void *it = NULL;
    struct fy_node_pair *p;
    while ((p = fy_node_mapping_iterate(get(o, "influence"), &it))) {
        double r = number(get(fy_node_pair_value(p), "rho"));
        if (!isnan(r) && (isnan(best) || r > best)) {
            best = r;
            text(fy_node_pair_key(p), buf, size);
        }
    }
    return best;
}

/* v, or 0 where it is round-off against the scale big (e.g. -8.9e-16 m beside 6.8 m). */
static double round_off(double v, double big)
{
    return fabs(v) < 1e-12 * big ? 0 : v;
}

/* The output the headline answers: result.json's main_output (report_util.c rp_main_output); in a
 * result without it the first output called *_total_energy_p95 (a barrier's design energy), else the first shown. */
static struct fy_node_pair *main_output(struct fy_node *root)
{
    struct fy_node_pair *p, *pick = NULL;
    void *it = NULL;
    char name[256], st[64], want[256];
    int pick_is_p95 = 0;
    text(get(root, "main_output"), want, sizeof want);
    while ((p = fy_node_mapping_iterate(get(root, "outputs"), &it))) {
        output_status(fy_node_pair_value(p), st, sizeof st);
        size_t len = strlen(text(fy_node_pair_key(p), name, sizeof name));
        if (want[0] && strcmp(want, "null") != 0) {
            if (!strcmp(name, want))
                return p;
            continue;
        }
        int p95 = len > 17 && !strcmp(name + len - 17, "_total_energy_p95");
        if (!strcmp(st, "shown") && (!pick || (p95 && !pick_is_p95))) {
            pick = p;
            pick_is_p95 = p95;
        }
    }
    return pick;
}

/* The headline: the main output's support at membership 0, its nominal value and main input. */
static void write_headline(FILE *f, struct fy_node *root)
{
    struct fy_node_pair *pick = main_output(root);
    char name[256], unit[64], top[256];
    if (!pick)
        return;
    struct fy_node *o = fy_node_pair_value(pick);
    double lo = number(fy_node_sequence_get_by_index(get(o, "lower"), 0));
    double hi = number(fy_node_sequence_get_by_index(get(o, "upper"), 0)), fac;
    double big = fmax(fabs(lo), fabs(hi)), r = main_input(o, top, sizeof top);
    const char *du = rp_display_unit(text(get(o, "unit"), unit, sizeof unit), big, &fac);
    fputs("<p class=headline><b>", f);
    rf_html_text(f, text(fy_node_pair_key(pick), name, sizeof name));
    fprintf(f, "</b> lies between <b>%.4g and %.4g %s</b> with the inputs anywhere in their supports "
               "(membership 0); with every input at its nominal value it is <b>%.4g %s</b>.",
            round_off(lo, big) * fac, round_off(hi, big) * fac, du, round_off(number(get(o, "nominal")), big) * fac,
            du);
    if (lo == 0 && strstr(name, "_energy_"))
        fputs(" (0: at some inputs no block reaches the line.)", f);
    if (!isnan(r)) {
        fputs(" The input with the largest influence is <b>", f);
        rf_html_text(f, top);
        fprintf(f, "</b> (%.0f %% of the relative influence).", 100 * r);
    }
    fputs("</p>\n", f);
}

/* One row of the summary: support at membership 0, nominal, main input. */
static void summary_row(FILE *f, const char *name, struct fy_node *o)
{
    char unit[64], top[256];
    double lo = number(fy_node_sequence_get_by_index(get(o, "lower"), 0));
    double hi = number(fy_node_sequence_get_by_index(get(o, "upper"), 0)), fac;
    const char *du = rp_display_unit(text(get(o, "unit"), unit, sizeof unit), fmax(fabs(lo), fabs(hi)), &fac);
    fputs("<tr><td class=l><b>", f);
    rf_html_text(f, name);
    fputs("</b></td><td class=l>", f);
    rf_html_text(f, du);
    double big = fmax(fabs(lo), fabs(hi)), nom = number(get(o, "nominal"));
    fprintf(f, "</td><td>%.4g &ndash; %.4g</td><td>%.4g</td><td class=l>", round_off(lo, big) * fac,
            round_off(hi, big) * fac, round_off(nom, big) * fac);
    double r = main_input(o, top, sizeof top);
    if (isnan(r))
        fputs("n/a (no input changes it)", f);
    else {
        rf_html_text(f, top);
        fprintf(f, " (&rho; = %.2f)", r);
    }
    fputs("</td></tr>\n", f);
}

/* The answer first: per reported output its support at membership 0, nominal value and main input. */
static void write_summary(FILE *f, const char *dir, struct fy_node *root)
{
    struct fy_node *outputs = get(root, "outputs");
    fputs("<div class=summary id=summary><b>Summary: the answer</b>\n", f);
    write_headline(f, root);
    char path[4200];
    snprintf(path, sizeof path, "%s/bound_upper/rerun.txt", dir);
    if (access(path, R_OK) == 0)
        fputs("<p>The trajectories at the nominal point and at the inputs giving each bound are "
              "<a href=\"#reruns\">side by side below</a>.</p>\n", f);
    fputs("<p>Each output of the model as a fuzzy "
          "number: the range it can take with the inputs anywhere in their supports (membership 0), its value "
          "with every input at its nominal (peak) value, and the input with the largest share of its "
          "uncertainty (Hanss's relative influence &rho;, the shares add up to 1).</p>\n<table><tr><th>output</th>"
          "<th>unit</th><th>support at membership 0</th><th>nominal</th><th>largest influence</th></tr>\n",
          f);
    void *it = NULL;
    struct fy_node_pair *p;
    char name[256], st[64];
    while ((p = fy_node_mapping_iterate(outputs, &it))) {
        output_status(fy_node_pair_value(p), st, sizeof st);
        if (!strcmp(st, "shown"))
            summary_row(f, text(fy_node_pair_key(p), name, sizeof name), fy_node_pair_value(p));
    }
    fputs("</table>\n", f);
    write_skipped(f, outputs);
    fputs("</div>\n", f);
}

static void write_warnings(FILE *f, struct fy_node *root)
{
    char a[2048];
    struct fy_node *warnings = get(root, "warnings");
    if (!warnings || fy_node_sequence_item_count(warnings) == 0)
        return;
    fputs("<div class=warn><b>Warnings</b><ul>\n", f);
    void *it = NULL;
    struct fy_node *w;
    while ((w = fy_node_sequence_iterate(warnings, &it))) {
        fputs("<li>", f);
        rf_html_text(f, text(w, a, sizeof a));
        fputs("</li>\n", f);
    }
    fputs("</ul></div>\n", f);
}

/* The error of the surrogate the model ran on (result.json "impact_surrogate_error"), when there is one. */
static void write_surrogate_error(FILE *f, struct fy_node *root)
{
    char a[2048];
    struct fy_node *e = get(root, "impact_surrogate_error");
    if (!e)
        return;
    fputs("<p class=note><b>Impact surrogate.</b> ", f);
    rf_html_text(f, text(e, a, sizeof a));
    fputs("</p>\n", f);
}

/* The model's settings: those differing from its defaults (impact model), else all. */
static void write_settings(FILE *f, struct fy_node *root)
{
    char a[512], b[512];
    struct fy_node *set = get(root, "model_settings");
    int vs = !strcmp(text(get(root, "model_settings_vs_defaults"), a, sizeof a), "true");
    fprintf(f, "<tr><th>model settings%s</th><td class=l>", vs ? "<br>(those not at their default)" : "");
    if (!set) {
        rf_html_text(f, text(get(root, "model_identity"), a, sizeof a)); /* a result from an older version */
    } else if (fy_node_mapping_item_count(set) == 0) {
        fputs(vs ? "all at their defaults" : "as in the model line above", f);
    } else {
        fputs("<table>", f);
        void *it = NULL;
        struct fy_node_pair *p;
        while ((p = fy_node_mapping_iterate(set, &it))) {
            fputs("<tr><td class=l>", f);
            rf_html_text(f, text(fy_node_pair_key(p), a, sizeof a));
            fputs("</td><td class=l>", f);
            rf_html_text(f, text(fy_node_pair_value(p), b, sizeof b));
            fputs("</td></tr>", f);
        }
        fputs("</table>", f);
    }
    fputs("<span class=note>(the full identity string is model_identity in result.json)</span></td></tr>\n", f);
}

static void write_run_table(FILE *f, struct fy_node *root)
{
    char a[2048];
    struct fy_node *ev = get(root, "evaluations");
    fputs("<h2>Run</h2>\n<table>\n", f);
    static const char *const meta[][2] = {{"version", "rockfuzz version"}, {"study_file", "study file"},
                                          {"scheme", "TM scheme"},         {"scheme_reason", "why this scheme"},
                                          {"levels", "levels m"},
                                          {"model", "model"},              {"jobs", "threads"},
                                          {"mpi_ranks", "MPI ranks"},      {"wall_seconds", "wall time [s]"}};
    for (size_t k = 0; k < sizeof meta / sizeof *meta; k++) {
        fprintf(f, "<tr><th>%s</th><td class=l>", meta[k][1]);
        if (!strcmp(meta[k][0], "wall_seconds"))
            fprintf(f, "%.4g", number(get(root, meta[k][0])));
        else
            rf_html_text(f, text(get(root, meta[k][0]), a, sizeof a));
        fputs("</td></tr>\n", f);
    }
    write_settings(f, root);
    int lr = strcmp(text(get(root, "left_right"), a, sizeof a), "false") != 0;
    fprintf(f, "<tr><th>monotonicity check</th><td class=l>%s</td></tr>\n",
            lr ? "on (the left/right three-point grid)"
               : "off, as the study asks (options.left_right: false): no monotonicity check, no rho_left/right");
    static const char *const counts[][2] = {{"requested", "grid points requested"},
                                            {"distinct", "distinct evaluations"},
                                            {"evaluated", "evaluated in this run"},
                                            {"from_store", "taken from the result store"},
                                            {"failed", "failed"},
                                            {"on_worker_ranks", "evaluated on MPI worker ranks"},
                                            {"probe", "extended-form probe"},
                                            {"left_right", "only for the left/right grid"},
                                            {"model_seconds", "time in the model [s]"}};
    for (size_t k = 0; k < sizeof counts / sizeof *counts; k++) {
        fprintf(f, "<tr><th>%s</th><td class=l>", counts[k][1]);
        if (!strcmp(counts[k][0], "model_seconds"))
            fprintf(f, "%.4g", number(get(ev, counts[k][0])));
        else
            rf_html_text(f, text(get(ev, counts[k][0]), a, sizeof a));
        fputs("</td></tr>\n", f);
    }
    fputs("</table>\n", f);
}

/* ---- a trajectory study's Monte Carlo reruns (study_traj.c): DIR/nominal, bound_lower, bound_upper ---- */

/* The main output the rerun in DIR/SUB gave (its rerun.txt), NaN if none; 0 if the folder is incomplete. */
static int rerun_value(const char *dir, const char *sub, double *value)
{
    char path[4200], line[256];
    snprintf(path, sizeof path, "%s/%s/rerun.txt", dir, sub);
    FILE *in = fopen(path, "r");
    *value = NAN;
    if (!in)
        return 0;
    while (fgets(line, sizeof line, in))
        if (!strncmp(line, "value ", 6))
            *value = strtod(line + 6, NULL);
    fclose(in);
    snprintf(path, sizeof path, "%s/%s/trajectory_profile.png", dir, sub);
    return access(path, R_OK) == 0;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

#define RERUN_HISTS 64
typedef struct {
    char *name[RERUN_HISTS]; /* "trajectory_hist_C", sorted */
    size_t n;
} hist_list;

/* Add the trajectory_hist_*.png of DIR/SUB to the list (one per collector a block reaches there). */
static void list_histograms(const char *dir, const char *sub, hist_list *h)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, sub);
    DIR *d = opendir(path);
    struct dirent *e;
    while (d && (e = readdir(d)) && h->n < RERUN_HISTS) {
        size_t len = strlen(e->d_name), known = 0;
        if (strncmp(e->d_name, "trajectory_hist_", 16) || len <= 20 || strcmp(e->d_name + len - 4, ".png"))
            continue;
        for (size_t i = 0; i < h->n; i++)
            known = known || (strlen(h->name[i]) == len - 4 && !strncmp(h->name[i], e->d_name, len - 4));
        if (!known && (h->name[h->n] = strndup(e->d_name, len - 4)))
            h->n++;
    }
    if (d)
        closedir(d);
    qsort(h->name, h->n, sizeof *h->name, by_name);
}

/* Every collector's histograms in DIR/SUB, in the same rows in every column; a note where no block reaches it. */
static void rerun_histograms(FILE *f, const char *dir, const char *sub, const hist_list *h)
{
    char path[4200];
    for (size_t i = 0; i < h->n; i++) {
        snprintf(path, sizeof path, "%s/%s/%s.png", dir, sub, h->name[i]);
        if (access(path, R_OK) != 0) {
            fputs("<p class=note>", f);
            rf_html_text(f, h->name[i] + 16);
            fputs(": no block reaches it here (no histogram).</p>\n", f);
            continue;
        }
        snprintf(path, sizeof path, "%s/%s", sub, h->name[i]);
        embed_png(f, dir, path, h->name[i] + 16);
    }
}

/* The inputs of one rerun: name = value unit. */
static void rerun_inputs(FILE *f, struct fy_node *root, struct fy_node *point)
{
    char a[256], b[64];
    fputs("<table>", f);
    void *it = NULL;
    struct fy_node_pair *p;
    while ((p = fy_node_mapping_iterate(get(root, "inputs"), &it))) {
        text(fy_node_pair_key(p), a, sizeof a);
        double v = point ? number(get(point, a)) : number(get(fy_node_pair_value(p), "nominal"));
        fputs("<tr><td class=l>", f);
        rf_html_text(f, a);
        fputs("</td>", f);
        cell_number(f, v);
        if (text(get(fy_node_pair_value(p), "unit"), b, sizeof b)[0]) {
            fputs("<td class=l>", f);
            rf_html_text(f, b);
            fputs("</td>", f);
        }
        fputs("</tr>", f);
    }
    fputs("</table>\n", f);
}

/* One column: the point's main output (the study's value and the rerun's), inputs, figures. */
static void rerun_column(FILE *f, const char *dir, struct fy_node *root, int side, double rerun, const hist_list *h)
{
    static const char *const subs[3] = {"nominal", "bound_lower", "bound_upper"};
    static const char *const titles[3] = {"Nominal point", "Lower bound at membership 0",
                                          "Upper bound at membership 0"};
    struct fy_node_pair *mp = main_output(root);
    struct fy_node *o = mp ? fy_node_pair_value(mp) : NULL, *point = NULL;
    char name[256], unit[64], alt[300];
    double study = number(get(o, "nominal"));
    if (side) {
        study = number(fy_node_sequence_get_by_index(get(o, side == 1 ? "lower" : "upper"), 0));
        point = fy_node_sequence_get_by_index(get(o, side == 1 ? "x_lower" : "x_upper"), 0);
    }
    double big = fmax(fabs(number(fy_node_sequence_get_by_index(get(o, "lower"), 0))),
                      fabs(number(fy_node_sequence_get_by_index(get(o, "upper"), 0)))), fac;
    const char *du = rp_display_unit(text(get(o, "unit"), unit, sizeof unit), big, &fac);
    fprintf(f, "<div><h3>%s</h3>\n<p>", titles[side]);
    if (o) {
        rf_html_text(f, text(fy_node_pair_key(mp), name, sizeof name));
        fprintf(f, " = <b>%.4g %s</b>", round_off(study, big) * fac, du);
        if (study == 0 && strstr(name, "_energy_"))
            fputs(" (no block reaches the line)", f);
        if (!isnan(rerun) && rerun != study)
            fprintf(f, " (this rerun gives %.6g %s, not the study's value)", rerun * fac, du);
    }
    fprintf(f, " &middot; <a href=\"%s/report.html\">statistics, CSV files</a></p>\n", subs[side]);
    rerun_inputs(f, root, point);
    snprintf(name, sizeof name, "%s/trajectory_profile", subs[side]);
    snprintf(alt, sizeof alt, "trajectories: %s", titles[side]);
    embed_png(f, dir, name, alt);
    rerun_histograms(f, dir, subs[side], h);
    fputs("</div>\n", f);
}

static void trajectory_reruns(FILE *f, const char *dir, struct fy_node *root)
{
    static const char *const subs[3] = {"nominal", "bound_lower", "bound_upper"};
    double value[3];
    int have[3];
    for (int k = 0; k < 3; k++)
        have[k] = rerun_value(dir, subs[k], &value[k]);
    if (!have[0])
        return;
    int bounds = have[1] && have[2];
    char name[256];
    struct fy_node_pair *mp = main_output(root);
    fputs("<h2 id=reruns>Trajectories at the nominal point", f);
    fputs(bounds ? " and at the bounds</h2>\n" : "</h2>\n", f);
    fputs("<p>Monte Carlo runs repeated at the end of the study (same samples and seed as every evaluation, 100 "
          "trajectories drawn): with every fuzzy input at its nominal value", f);
    if (bounds && mp) {
        fputs(", and at the inputs the Transformation Method found to give the lower and the upper bound of <b>", f);
        rf_html_text(f, text(fy_node_pair_key(mp), name, sizeof name));
        fputs("</b> at membership 0. The figures of the three share their axes: profile with trajectories, "
              "envelopes of height and energy along x from all trajectories, end points; then the histograms "
              "per collector", f);
    }
    fputs(".</p>\n<div class=reruns>\n", f);
    hist_list h = {{NULL}, 0};
    for (int k = 0; k < (bounds ? 3 : 1); k++)
        list_histograms(dir, subs[k], &h);
    for (int k = 0; k < (bounds ? 3 : 1); k++)
        rerun_column(f, dir, root, k, value[k], &h);
    fputs("</div>\n", f);
    for (size_t i = 0; i < h.n; i++)
        free(h.name[i]);
}

static void write_inputs(FILE *f, const char *dir, struct fy_node *root)
{
    char a[2048], b[256], c[256];
    struct fy_node *inputs = get(root, "inputs");
    fputs("<h2>Fuzzy inputs</h2>\n<table><tr><th>input</th><th>shape</th><th>unit</th><th>nominal</th>"
          "<th>support lower</th><th>support upper</th></tr>\n",
          f);
    void *it = NULL;
    struct fy_node_pair *p;
    while ((p = fy_node_mapping_iterate(inputs, &it))) {
        struct fy_node *v = fy_node_pair_value(p);
        fputs("<tr><td class=l>", f);
        rf_html_text(f, text(fy_node_pair_key(p), a, sizeof a));
        fputs("</td><td class=l>", f);
        rf_html_text(f, text(get(v, "shape"), b, sizeof b));
        fputs("</td><td class=l>", f);
        rf_html_text(f, text(get(v, "unit"), c, sizeof c));
        fputs("</td>", f);
        cell_number(f, number(get(v, "nominal")));
        cell_number(f, number(fy_node_sequence_get_by_index(get(v, "lower"), 0)));
        cell_number(f, number(fy_node_sequence_get_by_index(get(v, "upper"), 0)));
        fputs("</tr>\n", f);
    }
    fputs("</table>\n<div class=fig>\n", f);
    it = NULL;
    while ((p = fy_node_mapping_iterate(inputs, &it))) {
        char stem[256], safe[128];
        rp_safe_name(text(fy_node_pair_key(p), a, sizeof a), safe, sizeof safe);
        snprintf(stem, sizeof stem, "input_%s", safe);
        embed_png(f, dir, stem, a);
    }
    fputs("</div>\n", f);
    rp_fuzzy_maps_html(f, dir);
    trajectory_reruns(f, dir, root);
}

/* The cut table of output o, its nominal value and degree of uncertainty. */
static void write_cuts(FILE *f, struct fy_node *o)
{
    struct fy_node *lo = get(o, "lower"), *hi = get(o, "upper"), *mu = get(o, "mu");
    char why[512];
    fputs("<div><table><tr><th>&mu;</th><th>lower</th><th>upper</th></tr>\n", f);
    for (int j = 0; j < fy_node_sequence_item_count(lo); j++) {
        fputs("<tr>", f);
        cell_number(f, number(fy_node_sequence_get_by_index(mu, j)));
        cell_number(f, number(fy_node_sequence_get_by_index(lo, j)));
        cell_number(f, number(fy_node_sequence_get_by_index(hi, j)));
        fputs("</tr>\n", f);
    }
    fputs("<tr><th>nominal</th>", f);
    cell_number(f, number(get(o, "nominal")));
    fputs("<td></td></tr></table>\n", f);
    double nu = number(get(o, "degree_of_uncertainty"));
    if (isnan(nu)) {
        text(get(o, "na_reason_degree_of_uncertainty"), why, sizeof why);
        fputs("<p>degree of uncertainty: n/a (", f);
        rf_html_text(f, why[0] ? why : "undefined for this output");
        fputs(")</p></div>\n", f);
    } else {
        fprintf(f, "<p>degree of uncertainty: %.4g</p></div>\n", nu);
    }
}

static void write_influence(FILE *f, struct fy_node *o)
{
    char a[512];
    fputs("<h3>Influence of the inputs</h3>\n<div class=fig><table><tr><th>input</th><th>rho</th>"
          "<th>kappa</th><th>rho_left</th><th>rho_right</th><th>monotonicity</th></tr>\n",
          f);
    struct fy_node *inf = get(o, "influence");
    void *jt = NULL;
    struct fy_node_pair *q;
    while ((q = fy_node_mapping_iterate(inf, &jt))) {
        struct fy_node *v = fy_node_pair_value(q);
        fputs("<tr><td class=l>", f);
        rf_html_text(f, text(fy_node_pair_key(q), a, sizeof a));
        fputs("</td>", f);
        cell_number(f, number(get(v, "rho")));
        cell_number(f, number(get(v, "kappa")));
        cell_number(f, number(get(v, "rho_left")));
        cell_number(f, number(get(v, "rho_right")));
        fputs("<td class=l>", f);
        rf_html_text(f, text(get(v, "monotonicity"), a, sizeof a));
        fputs("</td></tr>\n", f);
    }
    fputs("</table>\n", f);
    influence_svg(f, inf);
    fputs("</div>\n<p class=note>n/a: rho of an input that does not change the output (or of a crisp input); "
          "rho_left/right without the left/right grid.</p>\n", f);
}

static void write_outputs(FILE *f, const char *dir, struct fy_node *root)
{
    struct fy_node *outputs = get(root, "outputs");
    void *it = NULL;
    struct fy_node_pair *p;
    while ((p = fy_node_mapping_iterate(outputs, &it))) {
        struct fy_node *o = fy_node_pair_value(p);
        char name[256], safe[128], stem[256], unit[256], st[64];
        output_status(o, st, sizeof st);
        if (strcmp(st, "shown") != 0)
            continue; /* listed in one line in the summary */
        text(fy_node_pair_key(p), name, sizeof name);
        rp_safe_name(name, safe, sizeof safe);
        fputs("<h2>Output ", f);
        rf_html_text(f, name);
        if (text(get(o, "unit"), unit, sizeof unit)[0]) {
            fputs(" [", f);
            rf_html_text(f, unit);
            fputs("]", f);
        }
        fputs("</h2>\n<div class=fig>", f);
        write_cuts(f, o);
        snprintf(stem, sizeof stem, "output_%s", safe);
        embed_png(f, dir, stem, name);
        fputs("</div>\n", f);
        write_influence(f, o);
    }
}

static rf_status write_page(FILE *f, const char *dir, struct fy_node *root)
{
    char a[2048];
    fputs("<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>rockfuzz report: ", f);
    rf_html_text(f, text(get(root, "name"), a, sizeof a));
    fprintf(f, "</title><style>%s</style></head><body>\n<h1>Study ", CSS);
    rf_html_text(f, a);
    fputs("</h1>\n", f);
    write_summary(f, dir, root); /* the answer first */
    write_warnings(f, root); /* then what changes how it must be read */
    write_surrogate_error(f, root);
    write_run_table(f, root);
    write_inputs(f, dir, root);
    write_outputs(f, dir, root);
    fputs("<p class=note>", f);
    rf_html_text(f, text(get(root, "measures"), a, sizeof a));
    fputs("</p>\n</body></html>\n", f);
    return RF_OK;
}

#define RESULT_MAX_BYTES (256u << 20) /* a result.json read back */
#define RESULT_MAX_DEPTH 64            /* nesting of [ and { in it (ours: under 10) */

/* The deepest nesting of arrays and objects outside strings: a parser's memory grows with it
 * (10 MB of '[' took 3.5 GB), so a too deep document is refused before it is parsed. */
static int json_depth(const char *s, size_t len)
{
    int depth = 0, deepest = 0, in_string = 0;
    for (size_t i = 0; i < len; i++) {
        char ch = s[i];
        if (in_string)
            in_string = ch == '\\' ? (i++, 1) : ch != '"';
        else if (ch == '"')
            in_string = 1;
        else if (ch == '[' || ch == '{')
            deepest = ++depth > deepest ? depth : deepest;
        else if (ch == ']' || ch == '}')
            depth--;
    }
    return deepest;
}

/* result.json parsed, if it is a regular file within the size and depth limits; *text (the
 * document's text, freed by the caller after the document) is set whenever the file was read. */
static struct fy_document *read_result(const char *json, char **text, rf_error *err)
{
    size_t len = 0;
    *text = NULL;
    if (rf_read_text_file(json, "result", RESULT_MAX_BYTES, text, &len, err) != RF_OK)
        return NULL;
    if (json_depth(*text, len) > RESULT_MAX_DEPTH) {
        rf_fail(err, RF_EPARSE, "%s: nested deeper than %d levels: not a rockfuzz result", json, RESULT_MAX_DEPTH);
        return NULL;
    }
    struct fy_parse_cfg cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.flags = FYPCF_QUIET | FYPCF_JSON_FORCE;
    return fy_document_build_from_string(&cfg, *text, len);
}

rf_status rf_report_write_html(const char *dir, rf_error *err)
{
    char json[4096], out[4096], tmp[4096];
    snprintf(json, sizeof json, "%s/result.json", dir);
    snprintf(out, sizeof out, "%s/report.html", dir);
    snprintf(tmp, sizeof tmp, "%s/report.html.tmp", dir);
    struct stat sb;
    if (stat(json, &sb) != 0)
        return rf_fail(err, RF_EIO, "%s: %s (a report needs a finished run)", json, strerror(errno));
    rf_error why = {RF_OK, ""};
    char *text = NULL;
    struct fy_document *doc = read_result(json, &text, &why);
    struct fy_node *root = doc ? fy_document_root(doc) : NULL;
    if (!root || fy_node_get_type(root) != FYNT_MAPPING || !get(root, "outputs") || !get(root, "inputs")) {
        fy_document_destroy(doc);
        free(text);
        if (why.msg[0])
            return rf_fail(err, RF_EPARSE, "%s", why.msg);
        return rf_fail(err, RF_EPARSE, "%s: not a rockfuzz result (cannot read it as JSON with inputs and outputs)",
                       json);
    }
    FILE *f = fopen(tmp, "w");
    if (!f) {
        fy_document_destroy(doc);
        free(text);
        return rf_fail(err, RF_EIO, "%s: cannot write: %s", tmp, strerror(errno));
    }
    write_page(f, dir, root);
    fy_document_destroy(doc);
    free(text);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        unlink(tmp);
        return rf_fail(err, RF_EIO, "%s: write failed: %s", tmp, strerror(errno));
    }
    if (rename(tmp, out) != 0) {
        unlink(tmp);
        return rf_fail(err, RF_EIO, "%s: cannot rename to report.html: %s", tmp, strerror(errno));
    }
    return RF_OK;
}
