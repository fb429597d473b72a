/* report_plot.c - membership functions of every input and output, and the
 * influence measures as bar charts, each as PNG (pngcairo) and SVG.
 *
 * PLplot keeps global stream state (plmkstrm/plsstrm are not thread-safe):
 * call these functions from one thread only.  Each figure gets its own
 * stream (plot/figure.c). */
#include "plot/figure.h"
#include "rockfuzz/report.h"

#include <math.h>
#include <plplot.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "study/report_internal.h"

typedef struct {
    const double *lo, *hi;   /* m+1 cuts */
    size_t m;
    const char *title, *xlabel;
    double nominal;
    const rf_fuzzy *shape;   /* inputs: the exact membership, drawn finely; NULL for outputs */
} membership_plot;

static void draw_membership(const void *p)
{
    const membership_plot *mp = p;
    size_t m = mp->m, np = 2 * (m + 1);
    PLFLT *x = malloc(np * sizeof *x), *y = malloc(np * sizeof *y);
    if (!x || !y) {
        free(x);
        free(y);
        return;
    }
    for (size_t j = 0; j <= m; j++) {
        x[j] = mp->lo[j];
        y[j] = (double)j / (double)m;
        x[np - 1 - j] = mp->hi[j];
        y[np - 1 - j] = (double)j / (double)m;
    }
    double xmin = mp->lo[0], xmax = mp->hi[0];
    rf_plot_axis_range(&xmin, &xmax);
    double pad = (xmax - xmin) * 0.08;
    plcol0(1);
    plenv(xmin - pad, xmax + pad, 0, 1.05, 0, 0);
    pllab(mp->xlabel, "membership #gm", mp->title);
    plcol0(2);
    plwidth(2);
    if (mp->shape) {
        /* The exact shape at 201 levels, and the m+1 cuts the TM used as markers. */
        enum { FINE = 201 };
        PLFLT fx[2 * FINE], fy[2 * FINE];
        for (int j = 0; j < FINE; j++) {
            double mu = (double)j / (FINE - 1), lo, hi;
            rf_fuzzy_cut(mp->shape, mu, &lo, &hi);
            fx[j] = lo;
            fy[j] = mu;
            fx[2 * FINE - 1 - j] = hi;
            fy[2 * FINE - 1 - j] = mu;
        }
        plline(2 * FINE, fx, fy);
        plcol0(3);
        plpoin((PLINT)np, x, y, 17);
        plmtex("t", 0.5, 0.98, 1.0, "dots: cuts used by the TM");
    } else {
        plline((PLINT)np, x, y);
    }
    plcol0(2);
    /* Close the level-0 cut so a crisp-looking output still shows. */
    PLFLT bx[2] = {mp->lo[0], mp->hi[0]}, by[2] = {0, 0};
    plline(2, bx, by);
    plwidth(1);
    free(x);
    free(y);
}

typedef struct {
    size_t n;
    const char *const *names;
    const double *a, *b;       /* b NULL: one bar per input */
    const char *title, *ylabel, *legend_a, *legend_b;
} bar_plot;

static void bar(double x0, double x1, double h)
{
    PLFLT x[4] = {x0, x0, x1, x1}, y[4] = {0, h, h, 0};
    plfill(4, x, y);
}

static void draw_bars(const void *p)
{
    const bar_plot *bp = p;
    double top = 0;
    for (size_t i = 0; i < bp->n; i++) {
        if (isfinite(bp->a[i]) && bp->a[i] > top)
            top = bp->a[i];
        if (bp->b && isfinite(bp->b[i]) && bp->b[i] > top)
            top = bp->b[i];
    }
    if (!(top > 0))
        top = 1;
    plcol0(1);
    plenv(0, (double)bp->n, 0, top * 1.15, 0, -2);
    plbox("bc", 0, 0, "bcnstv", 0, 0);
    pllab("", bp->ylabel, bp->title);
    for (size_t i = 0; i < bp->n; i++) {
        double c = (double)i + 0.5;
        if (bp->b) {
            plcol0(2);
            if (isfinite(bp->a[i]))
                bar(c - 0.35, c, bp->a[i]);
            plcol0(3);
            if (isfinite(bp->b[i]))
                bar(c, c + 0.35, bp->b[i]);
        } else {
            plcol0(2);
            if (isfinite(bp->a[i]))
                bar(c - 0.3, c + 0.3, bp->a[i]);
        }
        plcol0(1);
        int na = !isfinite(bp->a[i]) && (!bp->b || !isfinite(bp->b[i]));
        char label[96];
        snprintf(label, sizeof label, "%s%s", bp->names[i], na ? " (n/a)" : "");
        /* more than four names do not fit side by side: stagger them on two lines */
        double disp = bp->n > 4 ? (i % 2 ? 2.9 : 1.3) : 1.5;
        plmtex("b", disp, (c) / (double)bp->n, 0.5, label);
    }
    if (bp->b) {
        plcol0(2);
        plmtex("t", 0.3, 0.02, 0.0, bp->legend_a);
        plcol0(3);
        plmtex("t", 0.3, 0.98, 1.0, bp->legend_b);
    }
}

static int any_finite(const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (isfinite(v[i]))
            return 1;
    return 0;
}

rf_status rf_report_write_plots(const char *dir, const rf_study *s, const rf_tm_result *res, const rf_analysis *an,
                                rf_error *err)
{
    return rf_report_write_plots_until(dir, s, res, an, NULL, err);
}

rf_status rf_report_write_plots_until(const char *dir, const rf_study *s, const rf_tm_result *res,
                                      const rf_analysis *an, const atomic_int *interrupt, rf_error *err)
{
    size_t n = res->n_inputs, m = res->levels;
    char stem[256], safe[128], title[512], xlabel[256];
    rf_status st;
    for (size_t i = 0; i < n; i++) {
        rp_safe_name(s->param_names[i], safe, sizeof safe);
        snprintf(stem, sizeof stem, "input_%s", safe);
        snprintf(title, sizeof title, "input %s = %.200s", s->param_names[i], s->param_shapes[i]);
        snprintf(xlabel, sizeof xlabel, "%s%s%s%s", s->param_names[i], s->param_units[i][0] ? " [" : "",
                 s->param_units[i], s->param_units[i][0] ? "]" : "");
        membership_plot mp = {res->in_lo + i * (m + 1), res->in_hi + i * (m + 1), m, title, xlabel,
                              res->in_nominal[i], &s->inputs[i]};
        if ((st = rf_report_stopped(interrupt, "the plots", err)) != RF_OK ||
            (st = rf_plot_figure(dir, stem, 800, 560, draw_membership, &mp, err)) != RF_OK)
            return st;
    }
    double *tmp = malloc(3 * (n ? n : 1) * sizeof *tmp);
    if (!tmp)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    st = RF_OK;
    for (size_t k = 0; k < res->n_outputs && st == RF_OK; k++) {
        char why[512];
        if (rp_output_classify(s, res, k, why, sizeof why) != RP_OUTPUT_SHOWN)
            continue; /* nothing worth drawing; the summary says why in one line */
        const char *name = s->model.output_names[k];
        const char *unit = s->model.output_units && s->model.output_units[k] ? s->model.output_units[k] : "";
        rp_safe_name(name, safe, sizeof safe);
        snprintf(stem, sizeof stem, "output_%s", safe);
        snprintf(title, sizeof title, "output %.100s (%s form, m = %zu)", name, rf_tm_scheme_name(res->scheme), m);
        snprintf(xlabel, sizeof xlabel, "%.100s%s%.50s%s", name, unit[0] ? " [" : "", unit, unit[0] ? "]" : "");
        membership_plot mp = {res->lo + k * (m + 1), res->hi + k * (m + 1), m, title, xlabel, res->nominal[k],
                              NULL};
        if ((st = rf_report_stopped(interrupt, "the plots", err)) != RF_OK ||
            (st = rf_plot_figure(dir, stem, 800, 560, draw_membership, &mp, err)) != RF_OK)
            break;
        for (size_t i = 0; i < n; i++) {
            tmp[i] = an->rho[k * n + i];
            tmp[n + i] = an->rho_left[k * n + i];
            tmp[2 * n + i] = an->rho_right[k * n + i];
        }
        snprintf(stem, sizeof stem, "influence_%s", safe);
        snprintf(title, sizeof title, "relative influence on %.100s (Hanss #gr)", name);
        bar_plot bp = {n, (const char *const *)s->param_names, tmp, NULL, title, "#gr", NULL, NULL};
        if (any_finite(tmp, n) && (st = rf_plot_figure(dir, stem, 800, 560, draw_bars, &bp, err)) != RF_OK)
            break;
        if (!any_finite(tmp + n, 2 * n))
            continue; /* no left/right grid (options.left_right off): an empty plot is not drawn */
        snprintf(stem, sizeof stem, "influence_lr_%s", safe);
        snprintf(title, sizeof title, "left/right influence on %.100s", name);
        bar_plot lr = {n, (const char *const *)s->param_names, tmp + n, tmp + 2 * n, title, "#gr",
                       "#gr left (lower side)", "#gr right (upper side)"};
        st = rf_plot_figure(dir, stem, 800, 560, draw_bars, &lr, err);
    }
    free(tmp);
    return st;
}
