/* traj_plot.c - figures of a trajectory run (PLplot, PNG via pngcairo and
 * SVG): the profile with the recorded trajectories and collectors, the
 * envelopes along x of the passing height and of the kinetic energy (p50,
 * p95 and max over the recorded trajectories of each one's maximum in an x
 * bin, every stretch sampled densely from its exact motion), and per
 * collector histograms of energy and height; then report.html.
 * PLplot streams are global: call from one thread (as report_plot.c). */
#include "plot/figure.h"
#include "trajectory/traj_internal.h"

#include <errno.h>
#include <math.h>
#include <plplot.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define NBIN 160

typedef struct {
    const rf_traj_spec *s;
    const rf_traj_ensemble *e;
    const rf_traj_world *w;
    double xmin, xmax, mass, inertia;
    double env_h[3][NBIN], env_ke[3][NBIN];   /* p50, p95, max per bin */
} plot_data;

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Per trajectory the largest height and energy in each x bin, then percentiles over trajectories. */
static void envelopes(plot_data *p)
{
    size_t n = p->e->n_recorded;
    double *h = malloc((n ? n : 1) * NBIN * sizeof *h), *k = malloc((n ? n : 1) * NBIN * sizeof *k);
    if (!h || !k) {
        free(h), free(k);
        return;
    }
    for (size_t i = 0; i < n * NBIN; i++)
        h[i] = k[i] = 0;
    double dx = (p->xmax - p->xmin) / NBIN;
    for (size_t i = 0; i < n; i++) {
        const rf_traj_result *r = &p->e->recorded[i];
        for (size_t q = 0; q < r->n_events; q++) {
            const rf_traj_event *ev = &r->events[q];
            double t1 = q + 1 < r->n_events ? r->events[q + 1].t : ev->t, v0 = hypot(ev->vx, ev->vy);
            for (int j = 0; j <= 64; j++) {
                double d = (t1 - ev->t) * j / 64.0;
                double x = ev->x + ev->vx * d + 0.5 * ev->ax * d * d, y = ev->y + ev->vy * d + 0.5 * ev->ay * d * d;
                double vx = ev->vx + ev->ax * d, vy = ev->vy + ev->ay * d, v = hypot(vx, vy);
                double w = ev->flying || v0 == 0 ? ev->omega : ev->omega * v / v0; /* rolling: omega ~ v */
                long b = (long)floor((x - p->xmin) / dx);
                double g = traj_ground_y(p->w, x, NULL);
                if (b < 0 || b >= NBIN || !isfinite(g))
                    continue;
                double hh = y - g, kk = 0.5 * p->mass * v * v + 0.5 * p->inertia * w * w;
                if (hh > h[i * NBIN + b]) h[i * NBIN + b] = hh;
                if (kk > k[i * NBIN + b]) k[i * NBIN + b] = kk;
            }
        }
    }
    double *col = malloc((n ? n : 1) * sizeof *col);
    for (int b = 0; col && b < NBIN; b++) {
        for (int which = 0; which < 2; which++) {
            double *src = which ? k : h, (*dst)[NBIN] = which ? p->env_ke : p->env_h;
            for (size_t i = 0; i < n; i++)
                col[i] = src[i * NBIN + b];
            qsort(col, n, sizeof *col, cmp_d);
            dst[0][b] = n ? col[(size_t)(0.50 * (double)(n - 1))] : 0;
            dst[1][b] = n ? col[(size_t)(0.95 * (double)(n - 1))] : 0;
            dst[2][b] = n ? col[n - 1] : 0;
        }
    }
    free(col), free(h), free(k);
}

static void draw_paths(const plot_data *p)
{
    const rf_traj_spec *s = p->s;
    double ymin = s->py[0], ymax = s->py[0];
    for (size_t i = 0; i < s->n_points; i++)
        ymin = fmin(ymin, s->py[i]), ymax = fmax(ymax, s->py[i]);
    ymax = fmax(ymax, s->y0);
    double pad = 0.05 * (ymax - ymin + 1);
    plcol0(1);
    plenv(p->xmin, p->xmax, ymin - pad, ymax + pad, 0, 0);
    pllab("x [m]", "y [m]", "profile and recorded trajectories");
    size_t shown = p->e->n_recorded < 100 ? p->e->n_recorded : 100;
    plcol0(2);
    for (size_t i = 0; i < shown; i++) {
        const rf_traj_result *r = &p->e->recorded[i];
        for (size_t q = 0; q + 1 < r->n_events; q++) {
            const rf_traj_event *ev = &r->events[q];
            PLFLT x[17], y[17];
            double t1 = r->events[q + 1].t;
            for (int j = 0; j <= 16; j++) {
                double d = (t1 - ev->t) * j / 16.0;
                x[j] = ev->x + ev->vx * d + 0.5 * ev->ax * d * d;
                y[j] = ev->y + ev->vy * d + 0.5 * ev->ay * d * d;
            }
            plline(17, x, y);
        }
    }
    plcol0(1);
    plwidth(2);
    plline((PLINT)s->n_points, s->px, s->py);
    plwidth(1);
    plcol0(3);
    for (size_t c = 0; c < s->n_collectors; c++) {
        PLFLT x[2] = {s->collectors[c].x, s->collectors[c].x}, y[2] = {ymin - pad, ymax + pad};
        plline(2, x, y);
        plptex(s->collectors[c].x, ymax, 0, 1, 1.05, s->collectors[c].name);
    }
}

static void draw_envelope(const plot_data *p, const double (*env)[NBIN], double scale, const char *ylab,
                          const char *title)
{
    PLFLT x[NBIN], y[3][NBIN];
    double top = 0;
    for (int b = 0; b < NBIN; b++) {
        x[b] = p->xmin + (b + 0.5) * (p->xmax - p->xmin) / NBIN;
        for (int q = 0; q < 3; q++)
            y[q][b] = env[q][b] * scale, top = fmax(top, y[q][b]);
    }
    plcol0(1);
    plenv(p->xmin, p->xmax, 0, top > 0 ? 1.08 * top : 1, 0, 0);
    pllab("x [m]", ylab, title);
    for (int q = 0; q < 3; q++) {
        plcol0(q == 0 ? 4 : q == 1 ? 2 : 3);
        plline(NBIN, x, y[q]);
    }
    plcol0(1);
    plmtex("t", 0.3, 0.98, 1.0, "green p50, blue p95, red max");
}

static void draw_profile(const void *v)
{
    const plot_data *p = v;
    plssub(1, 3);
    draw_paths(p);
    draw_envelope(p, (const double (*)[NBIN])p->env_h, 1, "height [m]", "passing height above the ground");
    draw_envelope(p, (const double (*)[NBIN])p->env_ke, 1e-3, "energy [kJ]", "kinetic energy (translation + rotation)");
}

typedef struct {
    const plot_data *p;
    size_t c;
} hist_data;

static void histogram(const double *v, size_t n, const char *xlab, const char *title)
{
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; i++)
        lo = fmin(lo, v[i]), hi = fmax(hi, v[i]);
    if (!n || !(hi > lo))
        lo = n ? lo - 0.5 : 0, hi = n ? hi + 0.5 : 1;
    PLFLT *data = malloc((n ? n : 1) * sizeof *data);
    if (!data)
        return;
    for (size_t i = 0; i < n; i++)
        data[i] = v[i];
    plcol0(1);
    plhist((PLINT)n, data, lo, hi, 40, 0);
    pllab(xlab, "count", title);
    free(data);
}

static void draw_hist(const void *v)
{
    const hist_data *hd = v;
    const plot_data *p = hd->p;
    size_t N = p->e->samples, nc = p->e->n_collectors, m = 0;
    double *ke = malloc((N ? N : 1) * sizeof *ke), *h = malloc((N ? N : 1) * sizeof *h);
    for (size_t i = 0; ke && h && i < N; i++) {
        const rf_traj_crossing *x = &p->e->crossings[i * nc + hd->c];
        if (x->reached)
            ke[m] = x->total_energy * 1e-3, h[m++] = x->height_lowest;
    }
    char title[300];
    plssub(1, 2);
    snprintf(title, sizeof title, "%s: energy of the %zu crossings", p->s->collectors[hd->c].name, m);
    if (ke && h)
        histogram(ke, m, "energy [kJ]", title);
    snprintf(title, sizeof title, "%s: passing height", p->s->collectors[hd->c].name);
    if (ke && h)
        histogram(h, m, "height above the ground [m]", title);
    free(ke), free(h);
}

rf_status traj_write_report_html(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                 const rf_traj_stats *st, rf_error *err);

rf_status rf_traj_write_plots(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                              const rf_traj_stats *st, rf_error *err)
{
    plot_data *p = calloc(1, sizeof *p);
    if (!p)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_traj_spec geo = *s;
    geo.law = RF_BOUNCE_CONSTANT; /* geometry only */
    rf_traj_world *w;
    rf_status rc = rf_traj_world_create(&geo, &w, err);
    if (rc != RF_OK) {
        free(p);
        return rc;
    }
    p->s = s, p->e = e, p->w = w;
    p->xmin = s->px[0], p->xmax = s->px[s->n_points - 1];
    p->mass = s->sphere ? 4.0 / 3.0 * RF_PI * pow(s->radius, 3) * s->density : s->mass;
    p->inertia = s->sphere ? 0.4 * p->mass * s->radius * s->radius : 0;
    envelopes(p);
    rc = rf_plot_figure(dir, "trajectory_profile", 900, 640, draw_profile, p, err);
    for (size_t c = 0; c < s->n_collectors && rc == RF_OK; c++) {
        char stem[300];
        hist_data hd = {p, c};
        snprintf(stem, sizeof stem, "trajectory_hist_%s", s->collectors[c].name);
        rc = rf_plot_figure(dir, stem, 900, 640, draw_hist, &hd, err);
    }
    if (rc == RF_OK)
        rc = traj_write_report_html(dir, s, e, st, err);
    rf_traj_world_free(w);
    free(p);
    return rc;
}
