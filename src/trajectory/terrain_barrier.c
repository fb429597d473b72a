/* terrain_barrier.c - barrier (collector) crossings of a piece of path on the
 * map.  A barrier is a polyline (w->col[c]) with the spec's collector c: its
 * height H (0 = unlimited) and energy capacity C (0 = a pure collector).
 *
 * The map path of a flight is a straight line, x and y linear in time, so
 * the crossing with each segment of a barrier is exact (two 2x2 linear
 * solves); a contact piece is taken as its chord, the time at the crossing
 * from the distance covered along the chord (a quadratic in time).  Only the
 * first crossing of each barrier is recorded (res->crossings[c]): time, map
 * point, distance along the line from its first vertex, the block's lowest
 * point above the ground there (vertically; 0 in contact), its centre
 * (+ radius of a sphere), the distance from the ground's tangent plane
 * ((z - ground) n_z), speed and energies.
 *
 * The rule (issue 28 item 4): a barrier with C > 0 that the block meets
 * below its top (H = 0, or lowest point <= H) either
 *   holds it, E <= C: the block stops at the crossing (stopped_by_barrier,
 *   energy_after 0), or
 *   is broken through, E > C: the block goes on with its velocity and spin
 *   scaled by sqrt((E - C) / E), i.e. it loses exactly the capacity
 *   (energy_after = E - C);
 * a block over the top (lowest point > H), or at a pure collector, passes
 * untouched (energy_after = E).  E is the total kinetic energy,
 * translational plus rotational.  The crossings of a piece are taken in time
 * order; the first barrier that holds or slows the block cuts the piece. */
#include "trajectory/terrain_internal.h"

#include <math.h>

/* Cross product of 2D vectors. */
static double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

/* First crossing of the straight map path P0 + D s, s in [0, smax], with the
 * polyline: smallest s, and the distance along the line there; 0 if none. */
static int path_line_crossing(const terrain_barrier_geo *b, double px, double py, double dx, double dy, double smax,
                              double *s_out, double *along)
{
    double best = INFINITY, best_along = 0;
    for (size_t k = 0; k + 1 < b->n; k++) {
        double ex = b->x[k + 1] - b->x[k], ey = b->y[k + 1] - b->y[k];
        double den = cross2(dx, dy, ex, ey);
        if (den == 0)
            continue; /* parallel (a path along the line does not cross it) */
        double qx = b->x[k] - px, qy = b->y[k] - py;
        double s = cross2(qx, qy, ex, ey) / den, u = cross2(qx, qy, dx, dy) / den;
        if (s >= 0 && s <= smax && u >= 0 && u <= 1 && s < best)
            best = s, best_along = b->cum[k] + u * hypot(ex, ey);
    }
    if (!(best < INFINITY))
        return 0;
    *s_out = best, *along = best_along;
    return 1;
}

/* The map segment from (x0, y0) to (x1, y1) lies wholly on one side of the
 * barrier's bounding box (widened by round-off): it cannot cross it. */
static int outside_box(const terrain_barrier_geo *b, double x0, double y0, double x1, double y1)
{
    return b->has_box && ((x0 < b->xmin && x1 < b->xmin) || (x0 > b->xmax && x1 > b->xmax) || (y0 < b->ymin && y1 < b->ymin) ||
           (y0 > b->ymax && y1 > b->ymax));
}

void terrain_barrier_box(terrain_barrier_geo *g)
{
    g->xmin = g->xmax = g->x[0], g->ymin = g->ymax = g->y[0];
    for (size_t k = 1; k < g->n; k++) {
        g->xmin = fmin(g->xmin, g->x[k]), g->xmax = fmax(g->xmax, g->x[k]);
        g->ymin = fmin(g->ymin, g->y[k]), g->ymax = fmax(g->ymax, g->y[k]);
    }
    double m = 1e-9 * (fabs(g->xmin) + fabs(g->xmax) + fabs(g->ymin) + fabs(g->ymax) + 1);
    g->xmin -= m, g->xmax += m, g->ymin -= m, g->ymax += m;
    g->has_box = 1;
}

/* Time of the first crossing of barrier c by the piece (INFINITY if none). */
static double piece_crossing(const terrain_barrier_geo *b, const terrain_piece *pc, double *along)
{
    double s;
    if (outside_box(b, pc->p[0], pc->p[1], pc->p[0] + pc->v[0] * pc->T + 0.5 * pc->a[0] * pc->T * pc->T,
                    pc->p[1] + pc->v[1] * pc->T + 0.5 * pc->a[1] * pc->T * pc->T))
        return INFINITY; /* (the map path of a piece, a line or a chord, lies between its ends) */
    if (pc->a[0] == 0 && pc->a[1] == 0) /* straight at constant speed: s is the time */
        return path_line_crossing(b, pc->p[0], pc->p[1], pc->v[0], pc->v[1], pc->T, &s, along) ? s : INFINITY;
    double T = pc->T;
    double dx = pc->v[0] * T + 0.5 * pc->a[0] * T * T, dy = pc->v[1] * T + 0.5 * pc->a[1] * T * T;
    double len = sqrt(dx * dx + dy * dy); /* (not hypot: a tenth of a contact step's time; no overflow at map scales) */
    if (len == 0 || !path_line_crossing(b, pc->p[0], pc->p[1], dx, dy, 1, &s, along))
        return INFINITY;
    double cx = dx / len, cy = dy / len; /* covered along the chord: s len at the crossing */
    double tau = traj_first_root(0.5 * (cx * pc->a[0] + cy * pc->a[1]), cx * pc->v[0] + cy * pc->v[1], -s * len, T);
    return tau < INFINITY ? tau : s * T;
}

/* Record the crossing of barrier c at tau of the piece; the barrier's verdict. */
static terrain_piece_outcome record(terrain_run *r, size_t c, const terrain_piece *pc, double tau, double along,
                                    double *scale)
{
    rf_traj_crossing *cr = &r->res->crossings[c];
    const rf_traj_collector *col = &r->s->collectors[c];
    double p[3], v[3];
    for (int q = 0; q < 3; q++)
        p[q] = pc->p[q] + pc->v[q] * tau + 0.5 * pc->a[q] * tau * tau, v[q] = pc->v[q] + pc->a[q] * tau;
    double zg = p[2], n[3] = {0, 0, 1};
    int on_dem = rf_terrain_height(r->dem, p[0], p[1], &zg, n);
    cr->reached = 1;
    cr->t = pc->t + tau;
    cr->x = p[0], cr->y = p[1], cr->along = along;
    cr->height_lowest = pc->on_ground || !on_dem ? 0 : p[2] - zg;
    cr->height_centre = cr->height_lowest + r->radius;
    cr->normal_height = cr->height_lowest * n[2];
    cr->speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    cr->translational_energy = 0.5 * r->mass * cr->speed * cr->speed;
    cr->rotational_energy = pc->e_rot;
    double E = cr->translational_energy + cr->rotational_energy;
    cr->total_energy = E, cr->energy_after = E;
    if (!(col->capacity > 0) || (col->height > 0 && cr->height_lowest > col->height))
        return TERRAIN_PIECE_FREE;
    if (E <= col->capacity) {
        cr->stopped_by_barrier = 1, cr->energy_after = 0;
        return TERRAIN_PIECE_STOPPED;
    }
    cr->energy_after = E - col->capacity;
    *scale = sqrt((E - col->capacity) / E);
    return TERRAIN_PIECE_SLOWED;
}

terrain_piece_outcome terrain_barrier_piece(terrain_run *r, const terrain_piece *pc, double *tau_cut, double *scale)
{
    *tau_cut = INFINITY, *scale = 1;
    double done = -INFINITY; /* crossings recorded up to this time of the piece */
    for (;;) {
        size_t first = (size_t)-1;
        double tf = INFINITY, af = 0;
        for (size_t c = 0; c < r->w->ncol; c++) {
            if (r->res->crossings[c].reached)
                continue;
            double along, tc = piece_crossing(&r->w->col[c], pc, &along);
            if (tc >= done && tc < tf)
                tf = tc, af = along, first = c;
        }
        if (first == (size_t)-1)
            return TERRAIN_PIECE_FREE;
        terrain_piece_outcome o = record(r, first, pc, tf, af, scale);
        if (o != TERRAIN_PIECE_FREE) {
            *tau_cut = tf;
            return o;
        }
        done = tf;
    }
}
