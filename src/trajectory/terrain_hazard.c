/* terrain_hazard.c - hazard raster accumulators (issue 28 item 5): the
 * output grid, the records of touched cells, the walk of each piece over
 * the grid and a trajectory's end.  The design (storage, bins, pending
 * updates, percentiles and their error) is described in
 * terrain_hazard_internal.h; histograms in terrain_hazard_hist.c; merge,
 * pack and bands in terrain_hazard_out.c. */
#include "trajectory/terrain_hazard_internal.h"

#include <stdlib.h>
#include <string.h>

/* Two crossings of cell lines closer than this (in the segment's parameter,
 * 0..1) are one crossing of their corner. */
#define CORNER_TIE 1e-12

/* ---- records and the touch list ---- */

/* The record of grid cell `cell`, made on first use; NO_POS when out of memory. */
uint32_t hz_record_at(rf_terrain_hazard *h, size_t cell)
{
    if (h->slot[cell])
        return h->slot[cell] - 1;
    if (h->n_rec == h->cap_rec) {
        size_t cap = h->cap_rec ? 2 * h->cap_rec : 64;
        hz_rec *r = realloc(h->rec, cap * sizeof *r);
        if (!r) {
            h->nomem = 1;
            return NO_POS;
        }
        h->rec = r, h->cap_rec = cap;
    }
    hz_rec *r = &h->rec[h->n_rec];
    memset(r, 0, sizeof *r);
    r->e_max = r->h_max = -INFINITY;
    r->cell = (uint32_t)cell, r->pos = NO_POS;
    h->slot[cell] = (uint32_t)++h->n_rec;
    return (uint32_t)(h->n_rec - 1);
}

static void touch(rf_terrain_hazard *h, size_t cell, double e, double ht)
{
    uint32_t k = hz_record_at(h, cell);
    if (k == NO_POS)
        return;
    uint32_t pos = h->rec[k].pos;
    if (pos < h->n_touch && h->touch[pos].rec == k) {
        hz_touch *t = &h->touch[pos];
        t->e = max_of(t->e, e), t->h = max_of(t->h, ht);
        return;
    }
    if (h->n_touch == h->cap_touch) {
        size_t cap = h->cap_touch ? 2 * h->cap_touch : 64;
        hz_touch *t = realloc(h->touch, cap * sizeof *t);
        if (!t) {
            h->nomem = 1;
            return;
        }
        h->touch = t, h->cap_touch = cap;
    }
    h->rec[k].pos = (uint32_t)h->n_touch;
    h->touch[h->n_touch++] = (hz_touch){k, e, ht};
}

/* ---- the map walk ---- */

typedef struct {
    rf_terrain_hazard *h;
    const rf_terrain *dem;
    const terrain_piece *pc;
    double mass, T;
    double mx0, my0, mdx, mdy;  /* map path: (mx0, my0) + s (mdx, mdy), s in [0, 1], tau = s T */
    double s_last, e_last, h_last;  /* energy and height at s_last, the last cell's exit (its next entry) */
    size_t pi, pj;              /* the DEM cell of `patch` (pi = SIZE_MAX: none yet) */
    terrain_patch patch;
} hz_piece;

static double piece_energy(const hz_piece *q, double tau)
{
    const terrain_piece *pc = q->pc;
    double v2 = 0;
    for (int k = 0; k < 3; k++) {
        double vk = pc->v[k] + pc->a[k] * tau;
        v2 += vk * vk;
    }
    return 0.5 * q->mass * v2 + pc->e_rot;
}

/* The ground's height at (x, y) (0: off the surface): rf_terrain_height's
 * cell and arithmetic (the same bits), with the cell's patch kept for the
 * next point of the piece (3 to 4 points per cell: the patch's divisions
 * once). */
static int ground_at(hz_piece *q, double x, double y, double *zg)
{
    size_t i, j;
    double u, v;
    if (!terrain_cell_of(q->dem, x, y, &i, &j, &u, &v))
        return 0;
    if (i != q->pi || j != q->pj)
        q->patch = terrain_patch_of(q->dem, i, j), q->pi = i, q->pj = j;
    const terrain_patch *p = &q->patch;
    double X = x - p->xi, Y = y - p->yj;
    *zg = p->a + p->b * X + p->c * Y + p->d * X * Y;
    return 1;
}

/* Height of the piece over the ground at s (NaN off the surface). */
static double piece_height(hz_piece *q, double s)
{
    const terrain_piece *pc = q->pc;
    double tau = s * q->T, zg;
    if (!ground_at(q, q->mx0 + s * q->mdx, q->my0 + s * q->mdy, &zg))
        return NAN;
    return pc->p[2] + pc->v[2] * tau + 0.5 * pc->a[2] * tau * tau - zg;
}

/* The part s in [sa, sb] of the piece lies in cell (i, j): energy at its
 * ends (convex in tau: exact); height at its ends, its middle and the apex
 * of the path if inside (0 on the ground). */
static void piece_cell(hz_piece *q, size_t i, size_t j, double sa, double sb)
{
    rf_terrain_hazard *h = q->h;
    int energy = h->stats & RF_TERRAIN_ENERGY, height = (h->stats & RF_TERRAIN_HEIGHT) && !q->pc->on_ground;
    int again = sa == q->s_last;
    double e_in = NAN, e_out = NAN, h_in = NAN, h_out = NAN, ht = NAN;
    if (energy) {
        e_in = again ? q->e_last : piece_energy(q, sa * q->T);
        e_out = piece_energy(q, sb * q->T);
    }
    if (height) {
        h_in = again ? q->h_last : piece_height(q, sa);
        h_out = piece_height(q, sb);
        ht = max_of(max_of(h_in, h_out), piece_height(q, 0.5 * (sa + sb)));
        double az = q->pc->a[2], s_apex = az < 0 && q->T > 0 ? -q->pc->v[2] / az / q->T : -1;
        if (s_apex > sa && s_apex < sb)
            ht = max_of(ht, piece_height(q, s_apex));
        if (ht < 0)
            ht = 0;
    } else if (h->stats & RF_TERRAIN_HEIGHT)
        ht = 0; /* on the ground */
    q->s_last = sb, q->e_last = e_out, q->h_last = h_out;
    touch(h, j * h->nx + i, max_of(e_in, e_out), ht);
}

/* The parameters [*sa, *sb] of f0 + s d inside [0, hi]; 0 if none. */
static int clip_axis(double f0, double d, double hi, double *sa, double *sb)
{
    if (d == 0)
        return f0 >= 0 && f0 <= hi;
    double s0 = -f0 / d, s1 = (hi - f0) / d;
    if (s0 > s1) {
        double t = s0;
        s0 = s1, s1 = t;
    }
    *sa = s0 > *sa ? s0 : *sa, *sb = s1 < *sb ? s1 : *sb;
    return *sa <= *sb;
}

/* Start cell index along one axis at f going in direction d: a start on a
 * cell line going down belongs to the cell below. */
static long long start_index(double f, double d)
{
    double fl = floor(f);
    return (long long)fl - (d < 0 && f == fl);
}

/* Next line crossed along one axis from cell index c (INFINITY: none). */
static double next_crossing(long long c, double f0, double d)
{
    if (d > 0)
        return ((double)(c + 1) - f0) / d;
    if (d < 0)
        return ((double)c - f0) / d;
    return INFINITY;
}

/* The cells of the map segment in grid units (fx0, fy0) + s (gdx, gdy),
 * s in [0, 1], in order, each with its parameter interval; two crossings at
 * a corner (to CORNER_TIE) step diagonally; a segment along a cell line
 * lies in the cells to its north / east (half-open cells). */
static void walk(hz_piece *q, double fx0, double fy0, double gdx, double gdy)
{
    const rf_terrain_hazard *h = q->h;
    double sa = 0, sb = 1;
    if (!clip_axis(fx0, gdx, (double)h->nx, &sa, &sb) || !clip_axis(fy0, gdy, (double)h->ny, &sa, &sb))
        return;
    long long i = start_index(fx0 + sa * gdx, gdx), j = start_index(fy0 + sa * gdy, gdy);
    long long di = gdx > 0 ? 1 : -1, dj = gdy > 0 ? 1 : -1;
    size_t steps = 2 * (h->nx + h->ny) + 8; /* more than the lines a segment in the grid crosses */
    double s = sa;
    for (size_t k = 0; k < steps; k++) {
        double sx = next_crossing(i, fx0, gdx), sy = next_crossing(j, fy0, gdy);
        double sn = sx < sy ? sx : sy;
        int last = !(sn < sb);
        if (i >= 0 && j >= 0 && i < (long long)h->nx && j < (long long)h->ny)
            piece_cell(q, (size_t)i, (size_t)j, s, last ? sb : sn);
        if (last)
            break;
        int corner = fabs(sx - sy) <= CORNER_TIE;
        if (sx <= sy || corner)
            i += di;
        if (sy <= sx || corner)
            j += dj;
        s = sn;
    }
}

/* ---- the interface ---- */

static size_t cells_over(double width, double cell)
{
    double n = ceil(width / cell - 1e-9);
    return n < 1 ? 1 : (size_t)n;
}

rf_terrain_hazard *terrain_hazard_create(const rf_traj_spec *s, const rf_terrain *dem)
{
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    const rf_terrain_def *d = s ? s->terrain : NULL;
    double cell = d && d->raster_cell > 0 ? d->raster_cell : dx;
    if (!(cell > 0) || !((xmax - xmin) / cell < 1e9) || !((ymax - ymin) / cell < 1e9))
        return NULL;
    size_t nx = cells_over(xmax - xmin, cell), ny = cells_over(ymax - ymin, cell);
    if (nx * ny >= UINT32_MAX)
        return NULL;
    rf_terrain_hazard *h = calloc(1, sizeof *h);
    if (!h)
        return NULL;
    h->slot = calloc(nx * ny, sizeof *h->slot);
    if (!h->slot) {
        free(h);
        return NULL;
    }
    h->nx = nx, h->ny = ny, h->x0 = xmin, h->y0 = ymin, h->cell = cell;
    h->dem_grid = cell == dx && cell == dy && nx == dem->nx - 1 && ny == dem->ny - 1;
    h->stats = d ? d->statistics
                 : RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS | RF_TERRAIN_ENERGY |
                       RF_TERRAIN_HEIGHT;
    return h;
}

void terrain_hazard_walk_only(rf_terrain_hazard *h)
{
    if (h)
        h->dem_grid = 0;
}

void terrain_hazard_begin(rf_terrain_hazard *h)
{
    if (h)
        h->n_touch = 0;
}

/* The walk's state for piece pc. */
static hz_piece piece_of(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc)
{
    hz_piece q = {h, dem, pc, mass, pc->T > 0 ? pc->T : 0, pc->p[0], pc->p[1], 0, 0, -1, NAN, NAN, SIZE_MAX, 0, {0, 0, 0, 0, 0, 0}};
    for (int k = 0; k < 2; k++) {
        double end = pc->p[k] + pc->v[k] * q.T + 0.5 * pc->a[k] * q.T * q.T;
        *(k ? &q.mdy : &q.mdx) = end - pc->p[k];
    }
    return q;
}

void terrain_hazard_piece(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc)
{
    if (!h)
        return;
    hz_piece q = piece_of(h, dem, mass, pc);
    double fx0 = (q.mx0 - h->x0) / h->cell, fy0 = (q.my0 - h->y0) / h->cell;
    double gdx = q.mdx / h->cell, gdy = q.mdy / h->cell;
    if (isfinite(fx0) && isfinite(fy0) && isfinite(gdx) && isfinite(gdy))
        walk(&q, fx0, fy0, gdx, gdy);
}

void terrain_hazard_piece_in(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc,
                             size_t ci, size_t cj)
{
    if (!h)
        return;
    if (!h->dem_grid || h->x0 != dem->x0 || h->y0 != dem->y0 || h->cell != dem->dx || ci >= h->nx || cj >= h->ny) {
        terrain_hazard_piece(h, dem, mass, pc);
        return;
    }
    hz_piece q = piece_of(h, dem, mass, pc);
    piece_cell(&q, ci, cj, 0, 1);
}

void terrain_hazard_end(rf_terrain_hazard *h, int stopped, const double end[3])
{
    if (!h)
        return;
    for (size_t k = 0; k < h->n_touch; k++) {
        const hz_touch *t = &h->touch[k];
        hz_rec *r = &h->rec[t->rec];
        r->passages++;
        if ((h->stats & RF_TERRAIN_ENERGY) && isfinite(t->e)) {
            r->e_max = max_of(r->e_max, t->e);
            hz_pend_add(h, t->rec, 0, t->e);
        }
        if ((h->stats & RF_TERRAIN_HEIGHT) && isfinite(t->h)) {
            r->h_max = max_of(r->h_max, t->h);
            hz_pend_add(h, t->rec, 1, t->h);
        }
    }
    h->n_touch = 0;
    if (!stopped || !end)
        return;
    /* the cell of the end point (on the grid's last line: the last cell) */
    double fx = (end[0] - h->x0) / h->cell, fy = (end[1] - h->y0) / h->cell;
    if (!(fx >= 0 && fy >= 0 && fx <= (double)h->nx && fy <= (double)h->ny))
        return;
    size_t i = (size_t)fx < h->nx ? (size_t)fx : h->nx - 1, j = (size_t)fy < h->ny ? (size_t)fy : h->ny - 1;
    uint32_t k = hz_record_at(h, j * h->nx + i);
    if (k != NO_POS)
        h->rec[k].deposits++;
}
