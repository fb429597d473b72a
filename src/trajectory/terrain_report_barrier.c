/* terrain_report_barrier.c - per barrier of a terrain run, where along the
 * line the blocks arrive and with what: the total kinetic energy and the
 * passing height of every crossing against the distance along the line
 * from its first vertex, coloured by the outcome (held, broke through,
 * flew over, passed a collector), with the capacity and the height as
 * dashed lines.  A designer reads from it where along the fence the energy
 * concentrates (a gully) and whether the fence is high and strong enough
 * there.  PNG (a scatter of 10^4 points is heavy as SVG). */
#include "plot/figure.h"
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <plplot.h>
#include <stdio.h>
#include <stdlib.h>

#define FIG_W 1000
#define FIG_H 700

typedef struct {
    const rf_traj_spec *s;
    const rf_traj_ensemble *e;
    size_t c;
    double length;              /* [m] of the line */
} barrier_fig;

/* 0 held, 1 broke through, 2 flew over, 3 passed (a collector, or below a barrier without capacity). */
static int outcome(const rf_traj_collector *k, const rf_traj_crossing *x)
{
    if (x->stopped_by_barrier)
        return 0;
    if (x->energy_after < x->total_energy)
        return 1;
    return k->height > 0 && x->height_lowest > k->height ? 2 : 3;
}

/* The crossings of outcome o as points (along, value * scale); how many. */
static size_t points(const barrier_fig *d, int o, int height, double scale)
{
    const rf_traj_ensemble *e = d->e;
    const rf_traj_collector *k = &d->s->collectors[d->c];
    size_t N = e->samples, m = 0;
    PLFLT *x = malloc((N ? N : 1) * sizeof *x), *y = malloc((N ? N : 1) * sizeof *y);
    for (size_t i = 0; x && y && i < N; i++) {
        const rf_traj_crossing *c = &e->crossings[i * e->n_collectors + d->c];
        if (c->reached && outcome(k, c) == o)
            x[m] = c->along, y[m++] = (height ? c->height_lowest : c->total_energy) * scale;
    }
    static const int colour[4] = {4, 3, 6, 2};
    plcol0(colour[o]);
    plssym(0, 0.6);
    if (m && x && y)
        plpoin((PLINT)m, x, y, 17);
    free(x), free(y);
    return m;
}

static double largest(const barrier_fig *d, int height, double scale)
{
    double hi = 0;
    for (size_t i = 0; i < d->e->samples; i++) {
        const rf_traj_crossing *c = &d->e->crossings[i * d->e->n_collectors + d->c];
        if (c->reached)
            hi = fmax(hi, (height ? c->height_lowest : c->total_energy) * scale);
    }
    return hi;
}

static void panel(const barrier_fig *d, double y0, double y1, int height)
{
    const rf_traj_collector *k = &d->s->collectors[d->c];
    double scale = height ? 1 : 1e-3, limit = height ? k->height : k->capacity * 1e-3;
    double lo = 0, hi = 1.08 * fmax(largest(d, height, scale), limit), xlo = 0, xhi = d->length;
    rf_plot_axis_range(&lo, &hi);
    rf_plot_axis_range(&xlo, &xhi);
    plvpor(0.12, 0.96, y0, y1);
    plwind(xlo, xhi, lo, hi);
    for (int o = 0; o < 4; o++)
        points(d, o, height, scale);
    if (limit > 0) {
        PLFLT x[2] = {xlo, xhi}, y[2] = {limit, limit};
        plcol0(1);
        pllsty(2);
        plline(2, x, y);
        pllsty(1);
        plptex(xhi - 0.01 * (xhi - xlo), limit + 0.02 * (hi - lo), 1, 0, 1, height ? "barrier height" : "capacity");
    }
    plcol0(1);
    plbox("bcnst", 0, 0, "bcnstv", 0, 0);
    plmtex("l", 5.2, 0.5, 0.5, height ? "passing height of the lowest point [m]" : "total kinetic energy [kJ]");
}

static void draw(const void *v)
{
    const barrier_fig *d = v;
    const rf_traj_collector *k = &d->s->collectors[d->c];
    pladv(0);
    plschr(0, 0.8);
    plscol0(6, 148, 103, 189);
    panel(d, 0.56, 0.9, 0);
    size_t n = 0;
    for (size_t i = 0; i < d->e->samples; i++)
        n += d->e->crossings[i * d->e->n_collectors + d->c].reached;
    char title[300];
    snprintf(title, sizeof title, "%s: %zu crossings of %zu blocks, along the line from its first vertex", k->name, n,
             d->e->samples);
    plmtex("t", 2.6, 0, 0, title);
    plmtex("t", 1.0, 0, 0, "green held, red broke through, purple flew over, blue passed");
    panel(d, 0.1, 0.46, 1);
    plmtex("b", 3.0, 0.5, 0.5, "distance along the barrier [m]");
}

void terrain_barrier_stem(const char *name, char *buf, size_t size)
{
    snprintf(buf, size, "terrain_barrier_%s", name); /* names are letters, digits, '_', '-' (rf_traj_name_valid) */
}

rf_status terrain_draw_barrier_figures(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                       rf_error *err)
{
    const rf_terrain_def *td = s->terrain;
    for (size_t c = 0; c < s->n_collectors && c < e->n_collectors; c++) {
        barrier_fig d = {s, e, c, 0};
        for (size_t v = td && td->barrier_start ? td->barrier_start[c] + 1 : 0;
             td && td->barrier_start && v < td->barrier_start[c + 1]; v++)
            d.length += hypot(td->barrier_x[v] - td->barrier_x[v - 1], td->barrier_y[v] - td->barrier_y[v - 1]);
        char stem[120];
        terrain_barrier_stem(s->collectors[c].name, stem, sizeof stem);
        rf_status rc = rf_plot_figure_png(dir, stem, FIG_W, FIG_H, draw, &d, err);
        if (rc != RF_OK)
            return rc;
    }
    return RF_OK;
}
