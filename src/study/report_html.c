/* report_html.c - DIR/report.html, one self-contained page per study run.
 *
 * Built only from what a run leaves behind: result.json (read with libfyaml,
 * JSON being YAML) and the membership PNGs (embedded as base64 data URIs).
 * The influence bar charts are drawn here as inline SVG from the numbers in
 * result.json, so they exist even after --no-plots.  `rockfuzz report DIR`
 * regenerates the page without evaluating anything. */
#include "rockfuzz/report.h"

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

static void html(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '&': fputs("&amp;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
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
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.png", dir, stem);
    FILE *in = fopen(path, "rb");
    if (!in) {
        fprintf(f, "<p class=note>(figure %s.png not written: run without --no-plots)</p>\n", stem);
        return;
    }
    static const char b64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    fputs("<img alt=\"", f);
    html(f, alt);
    fputs("\" src=\"data:image/png;base64,", f);
    unsigned char buf[3 * 1024];
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, in)) > 0) {
        for (size_t i = 0; i < got; i += 3) {
            unsigned v = (unsigned)buf[i] << 16;
            if (i + 1 < got)
                v |= (unsigned)buf[i + 1] << 8;
            if (i + 2 < got)
                v |= buf[i + 2];
            fputc(b64[(v >> 18) & 63], f);
            fputc(b64[(v >> 12) & 63], f);
            fputc(i + 1 < got ? b64[(v >> 6) & 63] : '=', f);
            fputc(i + 2 < got ? b64[v & 63] : '=', f);
        }
        if (got < sizeof buf)
            break;
    }
    fclose(in);
    fputs("\">\n", f);
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
        html(f, name);
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
    ".fig{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start}.wide img{max-width:100%}";

/* A trajectory study: its Monte Carlo rerun at the nominal point (DIR/nominal/, traj_study_report.c). */
static void nominal_trajectories(FILE *f, const char *dir)
{
    char path[4096];
    struct stat sb;
    snprintf(path, sizeof path, "%s/nominal/trajectory_profile.png", dir);
    if (stat(path, &sb) != 0)
        return;
    fputs("<h2>Trajectories at the nominal point</h2>\n<p>The Monte Carlo rerun at the end of the study with every "
          "fuzzy parameter at its nominal value: profile, envelopes from all its trajectories and end points; "
          "the statistics, collector histograms and CSV files are in <a href=\"nominal/report.html\">"
          "nominal/report.html</a>.</p>\n<div class=wide>", f);
    embed_png(f, dir, "nominal/trajectory_profile", "trajectories at the nominal point");
    fputs("</div>\n", f);
}

static rf_status write_page(FILE *f, const char *dir, struct fy_node *root)
{
    char a[2048], b[256], c[256];
    fputs("<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>rockfuzz report: ", f);
    html(f, text(get(root, "name"), a, sizeof a));
    fprintf(f, "</title><style>%s</style></head><body>\n<h1>Study ", CSS);
    html(f, a);
    fputs("</h1>\n", f);

    /* warnings first: they change how everything below must be read */
    struct fy_node *warnings = get(root, "warnings");
    if (warnings && fy_node_sequence_item_count(warnings) > 0) {
        fputs("<div class=warn><b>Warnings</b><ul>\n", f);
        void *it = NULL;
        struct fy_node *w;
        while ((w = fy_node_sequence_iterate(warnings, &it))) {
            fputs("<li>", f);
            html(f, text(w, a, sizeof a));
            fputs("</li>\n", f);
        }
        fputs("</ul></div>\n", f);
    }

    struct fy_node *ev = get(root, "evaluations");
    fputs("<h2>Run</h2>\n<table>\n", f);
    static const char *const meta[][2] = {{"version", "rockfuzz version"}, {"study_file", "study file"},
                                          {"scheme", "TM scheme"},         {"levels", "levels m"},
                                          {"model", "model"},              {"model_identity", "model identity"},
                                          {"jobs", "threads"},             {"mpi_ranks", "MPI ranks"},
                                          {"wall_seconds", "wall time [s]"}};
    for (size_t k = 0; k < sizeof meta / sizeof *meta; k++) {
        fprintf(f, "<tr><th>%s</th><td class=l>", meta[k][1]);
        if (!strcmp(meta[k][0], "wall_seconds"))
            fprintf(f, "%.4g", number(get(root, meta[k][0])));
        else
            html(f, text(get(root, meta[k][0]), a, sizeof a));
        fputs("</td></tr>\n", f);
    }
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
            html(f, text(get(ev, counts[k][0]), a, sizeof a));
        fputs("</td></tr>\n", f);
    }
    fputs("</table>\n", f);

    /* inputs */
    struct fy_node *inputs = get(root, "inputs");
    fputs("<h2>Fuzzy inputs</h2>\n<table><tr><th>input</th><th>shape</th><th>unit</th><th>nominal</th>"
          "<th>support lower</th><th>support upper</th></tr>\n",
          f);
    void *it = NULL;
    struct fy_node_pair *p;
    while ((p = fy_node_mapping_iterate(inputs, &it))) {
        struct fy_node *v = fy_node_pair_value(p);
        fputs("<tr><td class=l>", f);
        html(f, text(fy_node_pair_key(p), a, sizeof a));
        fputs("</td><td class=l>", f);
        html(f, text(get(v, "shape"), b, sizeof b));
        fputs("</td><td class=l>", f);
        html(f, text(get(v, "unit"), c, sizeof c));
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
    nominal_trajectories(f, dir);

    /* outputs */
    struct fy_node *outputs = get(root, "outputs");
    it = NULL;
    while ((p = fy_node_mapping_iterate(outputs, &it))) {
        struct fy_node *o = fy_node_pair_value(p);
        char name[256], safe[128], stem[256];
        text(fy_node_pair_key(p), name, sizeof name);
        rp_safe_name(name, safe, sizeof safe);
        fputs("<h2>Output ", f);
        html(f, name);
        text(get(o, "unit"), b, sizeof b);
        if (b[0]) {
            fputs(" [", f);
            html(f, b);
            fputs("]", f);
        }
        fputs("</h2>\n", f);
        struct fy_node *lo = get(o, "lower"), *hi = get(o, "upper"), *mu = get(o, "mu");
        int undefined = 1;
        for (int j = 0; j < fy_node_sequence_item_count(lo); j++)
            if (!isnan(number(fy_node_sequence_get_by_index(lo, j))))
                undefined = 0;
        if (undefined) {
            fputs("<p class=note>Undefined for this study: the model returns NaN at every point (e.g. R_t of a "
                  "normal impact).</p>\n",
                  f);
            continue;
        }
        fputs("<div class=fig><div><table><tr><th>&mu;</th><th>lower</th><th>upper</th></tr>\n", f);
        for (int j = 0; j < fy_node_sequence_item_count(lo); j++) {
            fputs("<tr>", f);
            cell_number(f, number(fy_node_sequence_get_by_index(mu, j)));
            fprintf(f, "<td>%.10g</td><td>%.10g</td></tr>\n", number(fy_node_sequence_get_by_index(lo, j)),
                    number(fy_node_sequence_get_by_index(hi, j)));
        }
        fprintf(f, "<tr><th>nominal</th><td colspan=2>%.10g</td></tr></table>\n",
                number(get(o, "nominal")));
        fprintf(f, "<p>degree of uncertainty: %.4g</p></div>\n", number(get(o, "degree_of_uncertainty")));
        snprintf(stem, sizeof stem, "output_%s", safe);
        embed_png(f, dir, stem, name);
        fputs("</div>\n<h3>Influence of the inputs</h3>\n<div class=fig><table><tr><th>input</th><th>rho</th>"
              "<th>kappa</th><th>rho_left</th><th>rho_right</th><th>monotonicity</th></tr>\n",
              f);
        struct fy_node *inf = get(o, "influence");
        void *jt = NULL;
        struct fy_node_pair *q;
        while ((q = fy_node_mapping_iterate(inf, &jt))) {
            struct fy_node *v = fy_node_pair_value(q);
            fputs("<tr><td class=l>", f);
            html(f, text(fy_node_pair_key(q), a, sizeof a));
            fputs("</td>", f);
            cell_number(f, number(get(v, "rho")));
            cell_number(f, number(get(v, "kappa")));
            cell_number(f, number(get(v, "rho_left")));
            cell_number(f, number(get(v, "rho_right")));
            fputs("<td class=l>", f);
            html(f, text(get(v, "monotonicity"), a, sizeof a));
            fputs("</td></tr>\n", f);
        }
        fputs("</table>\n", f);
        influence_svg(f, inf);
        fputs("</div>\n", f);
    }
    fputs("<p class=note>", f);
    html(f, text(get(root, "measures"), a, sizeof a));
    fputs("</p>\n</body></html>\n", f);
    return RF_OK;
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
    struct fy_parse_cfg cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.flags = FYPCF_QUIET | FYPCF_JSON_FORCE;
    struct fy_document *doc = fy_document_build_from_file(&cfg, json);
    struct fy_node *root = doc ? fy_document_root(doc) : NULL;
    if (!root || fy_node_get_type(root) != FYNT_MAPPING || !get(root, "outputs") || !get(root, "inputs")) {
        fy_document_destroy(doc);
        return rf_fail(err, RF_EPARSE, "%s: not a rockfuzz result (cannot read it as JSON with inputs and outputs)",
                       json);
    }
    FILE *f = fopen(tmp, "w");
    if (!f) {
        fy_document_destroy(doc);
        return rf_fail(err, RF_EIO, "%s: cannot write: %s", tmp, strerror(errno));
    }
    write_page(f, dir, root);
    fy_document_destroy(doc);
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
