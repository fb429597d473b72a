/* traj_plot.c - figures of a trajectory run (PLplot, PNG via pngcairo and
 * SVG).  trajectory_profile: one column sharing x, as RocFall users read it:
 * the profile to scale (equal axes, or a stated round vertical exaggeration
 * when it would be too flat or too tall to read) with the barriers and the
 * recorded trajectories; below it the envelopes of the passing height and of
 * the kinetic energy (p50, p95, max over ALL trajectories, envelope.c); then
 * the histogram of the end points with the fraction of trajectories reaching
 * each x.  Per collector: histograms of energy and height.  Then report.html.
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

#define FIG_W 1000                         /* [px] */
#define PAD_L 90
#define PAD_R 80
#define PAD_TOP 40
#define GAP 48
#define PANEL_H 170
#define HIST_H 150
#define PAD_BOTTOM 55
#define PROFILE_MIN 200                     /* [px] below this the profile is exaggerated vertically */
#define PROFILE_MAX 1200                    /* [px] above this it is compressed */
#define NRUN 160                            /* bins of the end-point histogram */

typedef struct {
    const rf_traj_spec *s;
    const rf_traj_ensemble *e;
    double xmin, xmax, ylo, yhi;   /* world of the profile panel [m] */
    double exaggeration;           /* vertical / horizontal scale of the profile panel */
    int height_px, profile_px;
    const rf_traj_plot_scales *sc; /* common axes of runs compared side by side, or NULL */
} plot_data;

/* Vertical exaggeration: 1 (equal axes) unless the profile would be flatter
 * than PROFILE_MIN or taller than PROFILE_MAX pixels; then a round factor. */
static void layout(plot_data *p)
{
    static const double up[] = {2, 3, 4, 5, 10, 20, 50, 100}, down[] = {0.5, 0.25, 0.2, 0.1, 0.05};
    double natural = (p->yhi - p->ylo) * (FIG_W - PAD_L - PAD_R) / (p->xmax - p->xmin);
    p->exaggeration = 1;
    for (size_t i = 0; natural < PROFILE_MIN && i < sizeof up / sizeof *up; i++)
        if (natural * (p->exaggeration = up[i]) >= PROFILE_MIN)
            break;
    for (size_t i = 0; natural > PROFILE_MAX && i < sizeof down / sizeof *down; i++)
        if (natural * (p->exaggeration = down[i]) <= PROFILE_MAX)
            break;
    p->profile_px = (int)lround(natural * p->exaggeration);
    p->height_px = PAD_TOP + p->profile_px + 3 * GAP + 2 * PANEL_H + HIST_H + PAD_BOTTOM;
}

/* Viewport of the panel whose top is `top` pixels below the page top, `h` pixels high. */
static void panel(const plot_data *p, int top, int h, double ylo, double yhi)
{
    double H = p->height_px;
    plvpor((double)PAD_L / FIG_W, 1 - (double)PAD_R / FIG_W, 1 - (top + h) / H, 1 - top / H);
    plwind(p->xmin, p->xmax, ylo, yhi);
    plcol0(1);
    plbox("bcnst", 0, 0, "bcnstv", 0, 0);
}

static void collector_lines(const plot_data *p, double ylo, double yhi)
{
    plcol0(3);
    pllsty(2);
    for (size_t c = 0; c < p->s->n_collectors; c++) {
        PLFLT x[2] = {p->s->collectors[c].x, p->s->collectors[c].x}, y[2] = {ylo, yhi};
        plline(2, x, y);
    }
    pllsty(1);
}

static void draw_ground(const plot_data *p)
{
    const rf_traj_spec *s = p->s;
    size_t n = s->n_points;
    PLFLT *x = malloc((n + 2) * sizeof *x), *y = malloc((n + 2) * sizeof *y);
    if (x && y) {
        for (size_t i = 0; i < n; i++)
            x[i] = s->px[i], y[i] = s->py[i];
        x[n] = s->px[n - 1], y[n] = p->ylo, x[n + 1] = s->px[0], y[n + 1] = p->ylo;
        plcol0(5);
        plfill((PLINT)n + 2, x, y);
        plcol0(1);
        plwidth(2);
        plline((PLINT)n, x, y);
        plwidth(1);
    }
    free(x), free(y);
}

static void draw_paths(const plot_data *p)
{
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
}

/* Barriers: from the ground up to their height (or the whole panel when unlimited), named. */
static void draw_barriers(const plot_data *p)
{
    plcol0(3);
    for (size_t c = 0; c < p->s->n_collectors; c++) {
        const rf_traj_collector *b = &p->s->collectors[c];
        size_t i = 1;
        while (i + 1 < p->s->n_points && p->s->px[i] < b->x)
            i++;
        double x0 = p->s->px[i - 1], x1 = p->s->px[i], y0 = p->s->py[i - 1], y1 = p->s->py[i];
        double g = x1 > x0 ? y0 + (y1 - y0) * (b->x - x0) / (x1 - x0) : fmax(y0, y1);
        double top = b->height > 0 ? g + b->height : p->yhi;
        PLFLT x[2] = {b->x, b->x}, y[2] = {g, top};
        plwidth(b->height > 0 ? 4 : 1);
        plline(2, x, y);
        plwidth(1);
        plptex(b->x + 0.005 * (p->xmax - p->xmin), fmin(top, p->yhi) - 0.02 * (p->yhi - p->ylo), 1, 0, 0, b->name);
    }
}

static void draw_profile_panel(const plot_data *p)
{
    char ylab[120];
    panel(p, PAD_TOP, p->profile_px, p->ylo, p->yhi);
    draw_ground(p);
    draw_paths(p);
    draw_barriers(p);
    plcol0(1);
    plbox("bcnst", 0, 0, "bcnstv", 0, 0);
    if (p->exaggeration == 1)
        snprintf(ylab, sizeof ylab, "y [m] (to scale)");
    else
        snprintf(ylab, sizeof ylab, "y [m] (vertical exaggeration %gx)", p->exaggeration);
    plmtex("l", 4.2, 0.5, 0.5, ylab);
    char title[160];
    size_t shown = p->e->n_recorded < 100 ? p->e->n_recorded : 100;
    snprintf(title, sizeof title, "profile, barriers and %zu of the %zu trajector%s", shown, p->e->samples,
             p->e->samples == 1 ? "y" : "ies");
    plmtex("t", 0.6, 0, 0, title);
}

/* Polylines of env[k] * scale over the edges, broken where it is NaN. */
static void env_line(const rf_traj_envelope *v, const double *env, double scale)
{
    PLFLT *x = malloc(v->n_edges * sizeof *x), *y = malloc(v->n_edges * sizeof *y);
    size_t m = 0;
    for (size_t k = 0; x && y && k <= v->n_edges; k++) {
        if (k < v->n_edges && isfinite(env[k])) {
            x[m] = v->x[k], y[m++] = env[k] * scale;
            continue;
        }
        if (m > 1)
            plline((PLINT)m, x, y);
        m = 0;
    }
    free(x), free(y);
}

/* The largest finite value of env[0..n-1]; 0 if none. */
static double env_max(const double *env, size_t n)
{
    double hi = 0;
    for (size_t k = 0; k < n; k++)
        if (isfinite(env[k]))
            hi = fmax(hi, env[k]);
    return hi;
}

/* common: the upper end of the axis in the envelope's unit shared with other runs, 0: this run's own. */
static void draw_envelope(const plot_data *p, int top, double *const env[3], double scale, double common,
                          const char *ylab, const char *title)
{
    const rf_traj_envelope *v = &p->e->envelope;
    double hi = (common > 0 ? common : env_max(env[2], v->n_edges)) * scale;
    hi = hi > 0 ? 1.08 * hi : 1;
    panel(p, top, PANEL_H, 0, hi);
    collector_lines(p, 0, hi);
    static const int colour[3] = {4, 2, 3};
    static const char *const name[3] = {"p50", "p95", "max"};
    for (int q = 0; q < 3; q++) {
        plcol0(colour[q]);
        plwidth(q == 1 ? 2 : 1);
        env_line(v, env[q], scale);
        plmtex("t", 0.6, 0.88 + 0.06 * q, 1, name[q]);
    }
    plwidth(1);
    plcol0(1);
    plmtex("l", 4.2, 0.5, 0.5, ylab);
    plmtex("t", 0.6, 0, 0, title);
}

/* The end points per x bin (NRUN bins over the profile) into n; the largest count. */
static double runout_counts(const rf_traj_ensemble *e, double xmin, double xmax, PLFLT *x, PLFLT *n)
{
    double w = (xmax - xmin) / NRUN, most = 0;
    for (int b = 0; b < NRUN; b++)
        x[b] = xmin + b * w, n[b] = 0;
    for (size_t i = 0; i < e->samples; i++) {
        long b = (long)floor((e->runout_x[i] - xmin) / w);
        if (isfinite(e->runout_x[i]))
            n[b < 0 ? 0 : b >= NRUN ? NRUN - 1 : b] += 1;
    }
    for (int b = 0; b < NRUN; b++)
        most = fmax(most, n[b]);
    return most;
}

/* End points (runout x) of all samples per x bin, and the fraction of them reaching x (right axis). */
static void draw_runout(const plot_data *p, int top)
{
    PLFLT x[NRUN], n[NRUN];
    double w = (p->xmax - p->xmin) / NRUN, most = runout_counts(p->e, p->xmin, p->xmax, x, n);
    if (p->sc && p->sc->runout_count_max > 0)
        most = p->sc->runout_count_max;
    double hi = fmax(1, 1.08 * most);
    panel(p, top, HIST_H, 0, hi);
    collector_lines(p, 0, hi);
    plcol0(2);
    plbin(NRUN, x, n, PL_BIN_NOEXPAND);
    const rf_traj_envelope *v = &p->e->envelope;
    double *frac = malloc((v->n_edges ? v->n_edges : 1) * sizeof *frac);
    plwind(p->xmin, p->xmax, 0, 1.08);
    plcol0(1);
    plbox("", 0, 0, "cmstv", 0, 0);
    plmtex("r", 4.0, 0.5, 0.5, "fraction reaching x");
    for (size_t k = 0; frac && k < v->n_edges; k++)
        frac[k] = p->e->samples ? (double)v->reached[k] / (double)p->e->samples : NAN;
    plcol0(5);
    plwidth(2);
    if (frac)
        env_line(v, frac, 1);
    plwidth(1);
    free(frac);
    plcol0(1);
    char title[160];
    snprintf(title, sizeof title, "end points (runout x) per %.3g m, %zu trajector%s; grey: fraction reaching x", w,
             p->e->samples, p->e->samples == 1 ? "y" : "ies");
    plmtex("t", 0.6, 0, 0, title);
    plmtex("l", 4.2, 0.5, 0.5, "count");
    plmtex("b", 2.8, 0.5, 0.5, "x [m]");
}

static void draw_profile(const void *v)
{
    const plot_data *p = v;
    const rf_traj_envelope *env = &p->e->envelope;
    char title[200];
    pladv(0);
    plschr(0, 0.7 * 2260.0 / (FIG_W + p->height_px)); /* PLplot scales text with width + height */
    draw_profile_panel(p);
    int top = PAD_TOP + p->profile_px + GAP;
    const char *all = p->e->samples == 1 ? "the trajectory" : "all trajectories";
    snprintf(title, sizeof title, "passing height above the ground, %s (%zu)", all, p->e->samples);
    draw_envelope(p, top, env->height, 1, p->sc ? p->sc->height_max : 0, "height [m]", title);
    top += PANEL_H + GAP;
    snprintf(title, sizeof title, "kinetic energy (translation + rotation), %s (%zu)", all, p->e->samples);
    draw_envelope(p, top, env->energy, 1e-3, p->sc ? p->sc->energy_max : 0, "energy [kJ]", title);
    draw_runout(p, top + PANEL_H + GAP);
}

typedef struct {
    const plot_data *p;
    size_t c;
} hist_data;

/* The histogram of v[0..n-1] over [lo, hi] when hi > lo (axes shared with other runs), else over the data. */
static void histogram(const double *v, size_t n, double lo, double hi, const char *xlab, const char *title)
{
    if (!(hi > lo)) {
        lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < n; i++)
            lo = fmin(lo, v[i]), hi = fmax(hi, v[i]);
    }
    if (!n)
        lo = 0, hi = 1;
    rf_plot_axis_range(&lo, &hi);
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
    const rf_traj_plot_scales *sc = hd->c < RF_TRAJ_SCALE_COLLECTORS ? p->sc : NULL;
    plssub(1, 2);
    snprintf(title, sizeof title, "%s: energy of the %zu crossings", p->s->collectors[hd->c].name, m);
    if (ke && h)
        histogram(ke, m, sc ? sc->energy_lo[hd->c] * 1e-3 : 0, sc ? sc->energy_hi[hd->c] * 1e-3 : 0, "energy [kJ]",
                  title);
    snprintf(title, sizeof title, "%s: passing height", p->s->collectors[hd->c].name);
    if (ke && h)
        histogram(h, m, sc ? sc->height_lo[hd->c] : 0, sc ? sc->height_hi[hd->c] : 0, "height above the ground [m]",
                  title);
    free(ke), free(h);
}

rf_status traj_write_report_html(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                 const rf_traj_stats *st, rf_error *err);

/* Widen the histogram range [*lo, *hi] (empty: lo > hi) to the reached crossings of collector c. */
static void crossing_range(const rf_traj_ensemble *e, size_t c, int height, double *lo, double *hi)
{
    for (size_t i = 0; i < e->samples; i++) {
        const rf_traj_crossing *x = &e->crossings[i * e->n_collectors + c];
        if (x->reached)
            *lo = fmin(*lo, height ? x->height_lowest : x->total_energy),
            *hi = fmax(*hi, height ? x->height_lowest : x->total_energy);
    }
}

void traj_plot_extent(const rf_traj_spec *s, const rf_traj_ensemble *e, rf_traj_plot_scales *sc)
{
    const rf_traj_envelope *v = &e->envelope;
    PLFLT x[NRUN], n[NRUN];
    sc->height_max = fmax(sc->height_max, env_max(v->height[2], v->n_edges));
    sc->energy_max = fmax(sc->energy_max, env_max(v->energy[2], v->n_edges));
    sc->runout_count_max = fmax(sc->runout_count_max, runout_counts(e, s->px[0], s->px[s->n_points - 1], x, n));
    for (size_t c = 0; c < s->n_collectors && c < RF_TRAJ_SCALE_COLLECTORS; c++) {
        if (!sc->runs) /* the first run: the ranges start empty */
            sc->energy_lo[c] = sc->height_lo[c] = INFINITY, sc->energy_hi[c] = sc->height_hi[c] = -INFINITY;
        crossing_range(e, c, 0, &sc->energy_lo[c], &sc->energy_hi[c]);
        crossing_range(e, c, 1, &sc->height_lo[c], &sc->height_hi[c]);
    }
    sc->runs++;
}

rf_status rf_traj_write_plots(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                              const rf_traj_stats *st, rf_error *err)
{
    return traj_write_plots_scaled(dir, s, e, st, NULL, err);
}

rf_status traj_write_plots_scaled(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                  const rf_traj_stats *st, const rf_traj_plot_scales *sc, rf_error *err)
{
    plot_data p = {s, e, s->px[0], s->px[s->n_points - 1], s->py[0], s->py[0], 1, 0, 0, sc};
    for (size_t i = 0; i < s->n_points; i++)
        p.ylo = fmin(p.ylo, s->py[i]), p.yhi = fmax(p.yhi, s->py[i]);
    p.yhi = fmax(p.yhi, s->y0);
    for (size_t i = 0; s->release_kind == RF_TRAJ_RELEASE_LINE && i < s->n_release; i++)
        p.yhi = fmax(p.yhi, s->release_py[i]); /* every release of a line lies in the picture */
    double pad = 0.05 * (p.yhi - p.ylo) + 1;
    p.ylo -= pad, p.yhi += pad;
    layout(&p);
    rf_status rc = RF_OK;
    if (e->envelope.n_edges)
        rc = rf_plot_figure(dir, "trajectory_profile", FIG_W, p.height_px, draw_profile, &p, err);
    for (size_t c = 0; c < s->n_collectors && rc == RF_OK; c++) {
        char stem[300];
        hist_data hd = {&p, c};
        snprintf(stem, sizeof stem, "trajectory_hist_%s", s->collectors[c].name);
        if (st->collectors[c].reach_probability > 0) {
            rc = rf_plot_figure(dir, stem, 900, 640, draw_hist, &hd, err);
            continue;
        }
        char path[4400]; /* no histogram of nothing; none left from an earlier run either */
        snprintf(path, sizeof path, "%s/%s.png", dir, stem);
        remove(path);
        snprintf(path, sizeof path, "%s/%s.svg", dir, stem);
        remove(path);
    }
    if (rc == RF_OK)
        rc = traj_write_report_html(dir, s, e, st, err);
    return rc;
}
