/* terrain_maps.c - the maps of a terrain run (PLplot through plot/figure.h):
 * drawn to scale (the same metres per pixel on both axes; map coordinates
 * in m on the axes) over a hillshade of the DEM, computed from the exact
 * normal of the bilinear surface at each cell's centre with light from
 * azimuth 315 deg, altitude 45 deg (shade = max(0, n . l)), no-data cells
 * left white.  One map per hazard band (a colour scale with the band's
 * name and unit; cells no block reached are transparent so the hillshade
 * shows), and one of the end points (by state) with the recorded
 * trajectories, the release features and the barriers.  PNG only: a raster
 * of 250 000 cells is no vector figure (as SVG it weighs tens of MB).
 * PLplot streams are global: call from one thread. */
#include "plot/figure.h"
#include "trajectory/terrain_internal.h"

#include <ctype.h>
#include <math.h>
#include <plplot.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAP_PAD_L 120               /* [px] */
#define MAP_PAD_R 170               /* colour scale */
#define MAP_PAD_T 74
#define MAP_PAD_B 62
#define MAP_W 780                   /* [px] the map's width, unless it would be taller than MAP_MAX_H */
#define MAP_MAX_H 1000
#define SHADE_PX 2                  /* [px] the hillshade is drawn in blocks of cells at least this wide */
#define PATHS_SHOWN 200
#define PI 3.14159265358979323846

/* The page of a map of the extent [xmin, xmax] x [ymin, ymax] [m]: the map
 * MAP_W pixels wide (less when it would be taller than MAP_MAX_H), its height
 * the same metres per pixel, within half a pixel. */
terrain_map_layout terrain_map_layout_of(double xmin, double xmax, double ymin, double ymax)
{
    terrain_map_layout L;
    double r = (ymax - ymin) / (xmax - xmin);
    L.map_w = MAP_W;
    L.map_h = (int)lround(MAP_W * r);
    if (L.map_h > MAP_MAX_H) {
        L.map_h = MAP_MAX_H;
        L.map_w = (int)lround(MAP_MAX_H / r);
    }
    if (L.map_h < 1)
        L.map_h = 1;
    L.map_left = MAP_PAD_L, L.map_top = MAP_PAD_T;
    L.width = MAP_PAD_L + L.map_w + MAP_PAD_R;
    L.height = MAP_PAD_T + L.map_h + MAP_PAD_B;
    L.xmin = xmin, L.xmax = xmax, L.ymin = ymin, L.ymax = ymax;
    /* the map spans exactly map_w x map_h pixels: its metres per pixel, both ways */
    L.m_per_px = (xmax - xmin) / L.map_w;
    return L;
}

double terrain_hillshade_cell(const rf_terrain *t, size_t i, size_t j)
{
    if (!t->valid[j * (t->nx - 1) + i])
        return NAN;
    terrain_patch p = terrain_patch_of(t, i, j);
    double zx = p.b + p.d * 0.5 * t->dy, zy = p.c + p.d * 0.5 * t->dx, s = 1 / sqrt(1 + zx * zx + zy * zy);
    const double az = 315 * PI / 180, alt = 45 * PI / 180;
    double l[3] = {sin(az) * cos(alt), cos(az) * cos(alt), sin(alt)};
    return fmax(0, (-zx * l[0] - zy * l[1] + l[2]) * s);
}

/* A column-major PLplot matrix nx x ny (m[i][j], i to the east), one block. */
typedef struct {
    PLFLT **col;
    PLFLT *data;
    size_t nx, ny;
} matrix;

static int matrix_alloc(matrix *m, size_t nx, size_t ny)
{
    m->nx = nx, m->ny = ny;
    m->data = malloc(nx * ny * sizeof *m->data);
    m->col = malloc(nx * sizeof *m->col);
    if (!m->data || !m->col) {
        free(m->data), free(m->col);
        return 0;
    }
    for (size_t i = 0; i < nx; i++)
        m->col[i] = m->data + i * ny;
    return 1;
}

static void matrix_free(matrix *m) { free(m->data), free(m->col); }

typedef struct {
    const rf_traj_spec *s;
    const rf_traj_ensemble *e;
    const rf_terrain *dem;
    terrain_map_layout L;
    const terrain_map_grid *g;
    const terrain_band *band;       /* NULL: the end-point map */
    const terrain_map_style *style; /* NULL: the run's own style */
} map_data;

/* Map axes: whole metres (map coordinates have 6 or 7 digits: no exponent). */
static void label_metres(PLINT axis, PLFLT value, char *label, PLINT length, PLPointer data)
{
    (void)axis, (void)data;
    snprintf(label, (size_t)length, "%.0f", value);
}

/* A round tick step giving about n ticks over span. */
static double tick_step(double span, int n)
{
    double raw = span / n, p = pow(10, floor(log10(raw))), f = raw / p;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * p;
}

static void map_viewport(const terrain_map_layout *L)
{
    double W = L->width, H = L->height;
    plvpor(MAP_PAD_L / W, (MAP_PAD_L + L->map_w) / W, MAP_PAD_B / H, (MAP_PAD_B + L->map_h) / H);
    plwind(L->xmin, L->xmax, L->ymin, L->ymax);
}

/* The hillshade: grey cmap1 from 0.15 (facing away) to 1 (facing the light). */
static void draw_hillshade(const rf_terrain *t, const terrain_map_layout *L)
{
    /* a block of step x step cells per shade value: at least SHADE_PX pixels on the map (a background) */
    size_t cx = t->nx - 1, cy = t->ny - 1, wx = (size_t)L->map_w / SHADE_PX + 1, wy = (size_t)L->map_h / SHADE_PX + 1;
    size_t sx = (cx + wx - 1) / wx, sy = (cy + wy - 1) / wy, step = sx > sy ? sx : sy;
    step += !step;
    size_t mx = (cx + step - 1) / step, my = (cy + step - 1) / step;
    matrix m;
    if (!matrix_alloc(&m, mx, my))
        return;
    for (size_t a = 0; a < mx; a++)
        for (size_t b = 0; b < my; b++) {
            size_t i = a * step + step / 2, j = b * step + step / 2;
            double v = terrain_hillshade_cell(t, i < cx ? i : cx - 1, j < cy ? j : cy - 1);
            m.col[a][b] = isfinite(v) ? v : -1;     /* below zmin: not drawn (white page) */
        }
    PLFLT pos[2] = {0, 1}, c[2] = {0.15, 1};
    plscmap1n(256);
    plscmap1l(1, 2, pos, c, c, c, NULL);
    double x1 = t->x0 + (double)(mx * step) * t->dx, y1 = t->y0 + (double)(my * step) * t->dy;
    plimagefr((PLFLT_MATRIX)m.col, (PLINT)mx, (PLINT)my, t->x0, x1, t->y0, y1, 0, 1, 0, 1, NULL, NULL);
    matrix_free(&m);
}

/* A band is a count (0 where no block passed) or a per-cell statistic (NaN there). */
static int band_is_count(const char *name)
{
    return !strncmp(name, "passages", 8) || !strncmp(name, "reach_probability", 17) || !strncmp(name, "deposits", 8);
}

/* Displayed unit and factor: energies in kJ. */
static const char *band_unit(const terrain_band *b, double *scale)
{
    *scale = 1;
    if (b->unit && !strcmp(b->unit, "J")) {
        *scale = 1e-3;
        return "kJ";
    }
    return b->unit && *b->unit ? b->unit : "-";
}

/* The colour scale: light yellow to dark red, 85 % opaque. */
static void band_colours(void)
{
    PLFLT pos[4] = {0, 0.35, 0.7, 1}, r[4] = {1.0, 0.99, 0.89, 0.5}, g[4] = {1.0, 0.55, 0.10, 0.0},
          b[4] = {0.7, 0.24, 0.11, 0.15}, a[4] = {0.85, 0.85, 0.85, 0.85};
    plscmap1n(256);
    plscmap1la(1, 4, pos, r, g, b, a, NULL);
}

/* The range of the shown cells' values (display unit); 0 if none. */
static int band_range(const terrain_band *b, size_t n, double scale, double *lo, double *hi)
{
    int count = band_is_count(b->name), any = 0;
    *lo = INFINITY, *hi = -INFINITY;
    for (size_t k = 0; k < n; k++) {
        double v = b->data[k];
        if (!isfinite(v) || (count && v <= 0))
            continue;
        *lo = fmin(*lo, v * scale), *hi = fmax(*hi, v * scale), any = 1;
    }
    if (any && count)
        *lo = 0;
    if (!any)
        *lo = 0, *hi = 1;
    rf_plot_axis_range(lo, hi);
    return any;
}

static void draw_band_cells(const map_data *d, double lo, double hi, double scale)
{
    const terrain_map_grid *g = d->g;
    int count = band_is_count(d->band->name);
    matrix m;
    if (!matrix_alloc(&m, g->nx, g->ny))
        return;
    for (size_t i = 0; i < g->nx; i++)
        for (size_t j = 0; j < g->ny; j++) {
            double v = d->band->data[j * g->nx + i];
            m.col[i][j] = !isfinite(v) || (count && v <= 0) ? lo - 1 - fabs(hi - lo) : v * scale;
        }
    plimagefr((PLFLT_MATRIX)m.col, (PLINT)g->nx, (PLINT)g->ny, g->x0, g->x0 + (double)g->nx * g->cell, g->y0,
              g->y0 + (double)g->ny * g->cell, lo, hi, lo, hi, NULL, NULL);
    matrix_free(&m);
}

/* The colour scale at the right of the map, labelled with name [unit]. */
static void draw_colour_scale(const map_data *d, double lo, double hi, const char *label)
{
    const terrain_map_layout *L = &d->L;
    double W = L->width, H = L->height, x0 = MAP_PAD_L + L->map_w + 18;
    plvpor(x0 / W, (x0 + 22) / W, MAP_PAD_B / H, (MAP_PAD_B + L->map_h) / H);
    plwind(0, 1, lo, hi);
    matrix m;
    if (matrix_alloc(&m, 2, 256)) {
        for (int k = 0; k < 256; k++)
            m.col[0][k] = m.col[1][k] = lo + (hi - lo) * (k + 0.5) / 256;
        plimagefr((PLFLT_MATRIX)m.col, 2, 256, 0, 1, lo, hi, lo, hi, lo, hi, NULL, NULL);
        matrix_free(&m);
    }
    plcol0(1);
    plbox("bc", 0, 0, "bcmstv", 0, 0);
    plmtex("r", 6.5, 0.5, 0.5, label);
}

/* The barriers: thick red lines (a pure collector thin and dashed), named. */
static void draw_barriers(const map_data *d)
{
    const rf_terrain_def *td = d->s->terrain;
    if (!td || !td->barrier_start)
        return;
    double off = 0.01 * (d->L.xmax - d->L.xmin);
    for (size_t c = 0; c < d->s->n_collectors; c++) {
        size_t a = td->barrier_start[c], n = td->barrier_start[c + 1] - a;
        if (n < 1)
            continue;
        const rf_traj_collector *k = &d->s->collectors[c];
        int barrier = k->capacity > 0 || k->height > 0;
        plcol0(3);
        plwidth(barrier ? 4 : 1.5);
        pllsty(barrier ? 1 : 2);
        plline((PLINT)n, td->barrier_x + a, td->barrier_y + a);
        pllsty(1);
        plwidth(1);
        plcol0(1);
        plptex(td->barrier_x[a + n - 1] + off, td->barrier_y[a + n - 1] + off, 1, 0, 0, k->name);
    }
}

/* The release features: points as crosses, lines and polygon outlines in black. */
static void draw_release(const map_data *d)
{
    const rf_terrain_def *td = d->s->terrain;
    if (!td || !td->release.n_features)
        return;
    const rf_terrain_release *r = &td->release;
    plcol0(1);
    plwidth(1.5);
    for (size_t f = 0; f < r->n_features; f++) {
        size_t a = r->start[f], n = r->start[f + 1] - a;
        PLFLT *x = r->x + a, *y = r->y + a;
        if (r->kind == RF_TERRAIN_POINTS || n == 1) {
            plssym(0, 1.2);
            plpoin((PLINT)n, x, y, 5);
            continue;
        }
        plline((PLINT)n, x, y);
        if (r->kind == RF_TERRAIN_POLYGONS) {
            PLFLT cx[2] = {x[n - 1], x[0]}, cy[2] = {y[n - 1], y[0]};
            plline(2, cx, cy);
        }
    }
    plwidth(1);
}

static void draw_paths(const map_data *d)
{
    const rf_terrain_samples *ts = d->e->terrain;
    size_t shown = ts->n_recorded < PATHS_SHOWN ? ts->n_recorded : PATHS_SHOWN;
    plcol0(2);
    plwidth(0.8);
    for (size_t i = 0; i < shown; i++) {
        const rf_terrain_result *r = &ts->recorded[i];
        if (r->n_events < 2 || !r->events)
            continue;
        PLFLT *x = malloc(r->n_events * sizeof *x), *y = malloc(r->n_events * sizeof *y);
        for (size_t k = 0; x && y && k < r->n_events; k++)
            x[k] = r->events[k].p[0], y[k] = r->events[k].p[1];
        if (x && y)
            plline((PLINT)r->n_events, x, y);
        free(x), free(y);
    }
    plwidth(1);
}

/* End points of state st in colour col; how many. */
static size_t draw_ends(const map_data *d, rf_traj_state st, int col)
{
    const rf_terrain_samples *ts = d->e->terrain;
    size_t N = d->e->samples, m = 0;
    PLFLT *x = malloc((N ? N : 1) * sizeof *x), *y = malloc((N ? N : 1) * sizeof *y);
    for (size_t i = 0; x && y && i < N; i++)
        if (d->e->state[i] == st)
            x[m] = ts->end[3 * i], y[m++] = ts->end[3 * i + 1];
    plcol0(col);
    plssym(0, 0.55);
    if (m && x && y)
        plpoin((PLINT)m, x, y, 17);
    free(x), free(y);
    return m;
}

static void map_axes(const map_data *d, const char *title, const char *legend)
{
    char t2[200];
    plcol0(1);
    plslabelfunc(label_metres, NULL);
    plbox("bcnsto", tick_step(d->L.xmax - d->L.xmin, 5), 0, "bcnstvo", tick_step(d->L.ymax - d->L.ymin, 5), 0);
    plslabelfunc(NULL, NULL);
    plmtex("b", 3.0, 0.5, 0.5, "x (east) [m]");
    plmtex("l", 8.2, 0.5, 0.5, "y (north) [m]");
    plmtex("t", 3.6, 0, 0, title);
    plmtex("t", 2.15, 0, 0, legend);
    snprintf(t2, sizeof t2, "to scale: 1 pixel = %.3g m on both axes; hillshade of the DEM, light from the north-west",
             d->L.m_per_px);
    plmtex("t", 0.7, 0, 0, t2);
}

static void page(const map_data *d)
{
    pladv(0);
    plschr(0, 0.75 * 2260.0 / (d->L.width + d->L.height + 400));
    plscol0(6, 148, 103, 189);  /* purple: exited */
    map_viewport(&d->L);
    draw_hillshade(d->dem, &d->L);
}

static void draw_band_map(const void *v)
{
    const map_data *d = v;
    double scale, lo, hi;
    const char *unit = band_unit(d->band, &scale);
    const terrain_band *range = d->style && d->style->range ? d->style->range : d->band;
    page(d);
    int any = band_range(range, d->g->nx * d->g->ny, scale, &lo, &hi);
    band_colours();
    if (any)
        draw_band_cells(d, lo, hi, scale);
    draw_barriers(d);
    char title[300], label[120], legend[200];
    snprintf(label, sizeof label, "%s [%s]", d->band->name, unit);
    snprintf(title, sizeof title, "%s%s", d->style && d->style->title ? d->style->title : label,
             any ? "" : " (no cell has a value)");
    snprintf(legend, sizeof legend, "transparent: cells %s; red: barriers",
             band_is_count(d->band->name) ? "with 0" : "no block passed");
    map_axes(d, title, legend);
    draw_colour_scale(d, lo, hi, label);
}

static void draw_end_map(const void *v)
{
    const map_data *d = v;
    page(d);
    draw_paths(d);
    draw_release(d);
    draw_barriers(d);
    size_t ns = draw_ends(d, RF_TRAJ_STOPPED, 4), ne = draw_ends(d, RF_TRAJ_EXITED, 6);
    size_t nl = draw_ends(d, RF_TRAJ_STEP_LIMIT, 5);
    const rf_terrain_samples *ts = d->e->terrain;
    char title[200], legend[200];
    snprintf(title, sizeof title, "end points of %zu blocks: green stopped (%zu), purple exited (%zu)%s",
             d->e->samples, ns, ne, nl ? ", grey step limit" : "");
    snprintf(legend, sizeof legend, "blue: %zu recorded trajectories; black: release; red: barriers",
             ts->n_recorded < PATHS_SHOWN ? ts->n_recorded : PATHS_SHOWN);
    map_axes(d, title, legend);
}

void terrain_map_stem(const char *band, char *buf, size_t size)
{
    size_t k = (size_t)snprintf(buf, size, "terrain_map_");
    for (; *band && k + 1 < size; band++)
        buf[k++] = (isalnum((unsigned char)*band) || *band == '-') ? *band : '_';
    buf[k < size ? k : size - 1] = 0;
}

rf_status terrain_draw_maps(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_terrain *dem,
                            const terrain_map_grid *g, const terrain_band *bands, size_t n, rf_error *err)
{
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    map_data d = {s, e, dem, terrain_map_layout_of(xmin, xmax, ymin, ymax), g, NULL, NULL};
    rf_status rc = RF_OK;
    if (e->terrain)
        rc = rf_plot_figure_png(dir, "terrain_endpoints", d.L.width, d.L.height, draw_end_map, &d, err);
    for (size_t k = 0; k < n && rc == RF_OK; k++) {
        char stem[120];
        terrain_map_stem(bands[k].name, stem, sizeof stem);
        d.band = &bands[k];
        rc = rf_plot_figure_png(dir, stem, d.L.width, d.L.height, draw_band_map, &d, err);
    }
    return rc;
}

/* ---- categories (a blame map): one colour per category, a legend naming them ---- */

/* Qualitative colours (Tableau 10), repeated beyond ten categories. */
static const unsigned char CATEGORY_RGB[10][3] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44}, {214, 39, 40},
                                                   {148, 103, 189}, {140, 86, 75}, {227, 119, 194},
                                                   {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};

static void category_colours(size_t n)
{
    PLINT r[64], g[64], b[64];
    PLFLT a[64];
    size_t m = n < 64 ? n : 64;
    for (size_t k = 0; k < m; k++)
        r[k] = CATEGORY_RGB[k % 10][0], g[k] = CATEGORY_RGB[k % 10][1], b[k] = CATEGORY_RGB[k % 10][2], a[k] = 0.8;
    plscmap1n((PLINT)m);
    plscmap1a(r, g, b, a, (PLINT)m);
}

/* Category k (1..n) has the colour position (k - 0.5) / n: cmap1 entry k - 1. */
static void draw_category_cells(const map_data *d, size_t n)
{
    const terrain_map_grid *g = d->g;
    matrix m;
    if (!matrix_alloc(&m, g->nx, g->ny))
        return;
    for (size_t i = 0; i < g->nx; i++)
        for (size_t j = 0; j < g->ny; j++) {
            double v = d->band->data[j * g->nx + i];
            m.col[i][j] = isfinite(v) && v >= 1 && v <= (double)n ? v : -1; /* -1: not drawn */
        }
    plimagefr((PLFLT_MATRIX)m.col, (PLINT)g->nx, (PLINT)g->ny, g->x0, g->x0 + (double)g->nx * g->cell, g->y0,
              g->y0 + (double)g->ny * g->cell, 0.5, (double)n + 0.5, 0.5, (double)n + 0.5, NULL, NULL);
    matrix_free(&m);
}

/* The legend at the right of the map: a square of each category's colour and its name. */
static void draw_category_legend(const map_data *d, size_t n, const size_t *count)
{
    const terrain_map_layout *L = &d->L;
    double W = L->width, H = L->height, x0 = MAP_PAD_L + L->map_w + 10, rows = n > 12 ? (double)n : 12;
    plvpor(x0 / W, (W - 4) / W, MAP_PAD_B / H, (MAP_PAD_B + L->map_h) / H);
    plwind(0, 1, 0, rows);
    plschr(0, 0.62 * 2260.0 / (L->width + L->height + 400)); /* the page's text, smaller: names fit */
    for (size_t k = 0; k < n && k < 64; k++) {
        double y = rows - (double)k;
        PLFLT sx[4] = {0, 0.1, 0.1, 0}, sy[4] = {y - 0.75, y - 0.75, y - 0.15, y - 0.15};
        plcol1(((double)k + 0.5) / (double)(n < 64 ? n : 64));
        plfill(4, sx, sy);
        char label[160];
        snprintf(label, sizeof label, "%.24s", d->style->labels[k]);
        plcol0(1);
        plptex(0.14, y - 0.3, 1, 0, 0, label);
        snprintf(label, sizeof label, "%zu cells", count[k]);
        plptex(0.14, y - 0.75, 1, 0, 0, label);
    }
}

static void draw_category_map(const void *v)
{
    const map_data *d = v;
    size_t n = d->style->n_labels, cells = d->g->nx * d->g->ny;
    size_t *count = calloc(n ? n : 1, sizeof *count);
    for (size_t c = 0; count && c < cells; c++) {
        double x = d->band->data[c];
        if (isfinite(x) && x >= 1 && x <= (double)n)
            count[(size_t)x - 1]++;
    }
    page(d);
    category_colours(n);
    draw_category_cells(d, n);
    draw_barriers(d);
    char legend[200];
    snprintf(legend, sizeof legend, "a colour per category (legend: its name and cells); transparent: none; red: barriers");
    map_axes(d, d->style->title ? d->style->title : d->band->name, legend);
    if (count)
        draw_category_legend(d, n, count);
    free(count);
}

rf_status terrain_draw_band_map(const char *dir, const char *stem, const rf_traj_spec *s, const rf_terrain *dem,
                                const terrain_map_grid *g, const terrain_band *band, const terrain_map_style *style,
                                rf_error *err)
{
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    map_data d = {s, NULL, dem, terrain_map_layout_of(xmin, xmax, ymin, ymax), g, band, style};
    int categories = style && style->labels && style->n_labels > 0;
    return rf_plot_figure_png(dir, stem, d.L.width, d.L.height, categories ? draw_category_map : draw_band_map, &d,
                              err);
}
