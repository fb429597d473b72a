/* terrain_flight.c - exact first impact of a parabola with the bilinear
 * surface (terrain_internal.h), cell by cell.
 *
 * Along a flight x and y are linear in time, so the map path is a straight
 * line: the cells it crosses are walked in order (a grid traversal, the
 * crossing times of the x and y cell lines computed from the nodes, never
 * accumulated).  Inside a cell the surface is z = a + b X + c Y + d X Y, so
 * with time s counted from the cell's entry the gap
 *   gap(s) = z_path(s) - z_patch(X(s), Y(s)) = C + B s + A s^2,
 *   C = gap at entry, B = vz - (b + d Y) vx - (c + d X) vy at entry,
 *   A = -g/2 - d vx vy,
 * is a quadratic whose first root in the cell's time interval where the path
 * goes into the ground (gap' <= 0) is the impact; the roots come from the
 * cancellation-free formula (as roots.c).  Nothing is sampled: a ridge
 * thinner than a cell is hit in the cell that holds it.  Every tolerance is
 * local: relative to the heights and speeds at hand, never to the DEM's
 * extent. */
#include "trajectory/terrain_internal.h"

#include <math.h>

/* A start within this of the surface is on it [m] (round-off of the impact
 * point put on the surface, re-evaluated on a neighbouring cell). */
static double on_surface_tol(double z) { return 1e-10 * (1 + fabs(z)); }

/* Smallest root s in [0, L] of A s^2 + B s + C at which the gap decreases
 * (2 A s + B <= 0); INFINITY if none.  A gap at or below zero at entry while
 * it does not rise is a hit at once (round-off of a root on the cell line). */
static double entering_root(double A, double B, double C, double L)
{
    if (C <= 0 && B <= 0 && !(C == 0 && B == 0 && A >= 0))
        return 0;
    double r[2] = {INFINITY, INFINITY};
    if (A == 0) {
        if (B != 0)
            r[0] = -C / B;
    } else {
        double disc = B * B - 4 * A * C;
        if (disc < 0)
            return INFINITY; /* never touches in this cell (a graze that misses) */
        double q = -0.5 * (B + copysign(sqrt(disc), B));
        r[0] = q / A;
        r[1] = q != 0 ? C / q : r[0];
        if (r[1] < r[0]) {
            double tmp = r[0];
            r[0] = r[1], r[1] = tmp;
        }
    }
    for (int k = 0; k < 2; k++)
        if (r[k] >= 0 && r[k] <= L && 2 * A * r[k] + B <= 0)
            return r[k];
    return INFINITY;
}

/* A flight starting on the surface (C = 0): the root s = 0 is the point just
 * left unless the path goes into the ground (B < 0, beyond round-off of a
 * tangential velocity); a path leaving it comes back at s = -B/A (A < 0). */
static double start_root(double A, double B, double L, double speed)
{
    double tol = 1e-12 * (1 + speed);
    double s;
    if (B < -tol)
        s = 0;
    else if (A < 0)
        s = B > 0 ? -B / A : 0;
    else
        return INFINITY;
    return s <= L ? s : INFINITY;
}

/* First cell index along one axis of n nodes: the cell holding
 * f = (x - x0) / dx; on a cell line the one the motion enters (the sign of
 * v), so -1 or n - 1 (outside) when it leaves the grid there. */
static long first_index(double f, double v, size_t n)
{
    if (!(f >= 0))
        return -1; /* (also NaN) */
    if (f > (double)(n - 1))
        return (long)n - 1;
    double fl = floor(f);
    long i = (long)fl;
    if (f == fl && v < 0)
        i--;
    if (v == 0 && i == (long)n - 1)
        i--; /* standing still on the last line: the last cell */
    return i;
}

/* Cell (i, j) exists and holds data. */
static int cell_ok(const rf_terrain *t, long i, long j)
{
    return i >= 0 && j >= 0 && i < (long)t->nx - 1 && j < (long)t->ny - 1 &&
           t->valid[(size_t)j * (t->nx - 1) + (size_t)i];
}

/* The cell the path starts in; on a cell line it does not move across
 * (zero velocity along that axis) the neighbour is taken when the preferred
 * cell has no data (a path along the edge of a no-data area). */
static void first_cell(const rf_terrain *t, const double p[3], const double v[3], long *i, long *j)
{
    double fx = (p[0] - t->x0) / t->dx, fy = (p[1] - t->y0) / t->dy;
    *i = first_index(fx, v[0], t->nx), *j = first_index(fy, v[1], t->ny);
    if (cell_ok(t, *i, *j))
        return;
    if (v[0] == 0 && fx == floor(fx) && cell_ok(t, *i - 1, *j))
        (*i)--;
    else if (v[1] == 0 && fy == floor(fy) && cell_ok(t, *i, *j - 1))
        (*j)--;
}

/* Time at which the path reaches the next line of its axis from cell i
 * (INFINITY without motion along the axis). */
static double line_time(double p, double v, double origin, double step, long i)
{
    if (v == 0)
        return INFINITY;
    double line = origin + (double)(v > 0 ? i + 1 : i) * step;
    double s = (line - p) / v;
    return s > 0 ? s : 0;
}

/* The gap's quadratic on cell (i, j) for the path from time t_in. */
static void cell_gap(const rf_terrain *t, long i, long j, const double p[3], const double v[3], double g,
                     double t_in, double *A, double *B, double *C)
{
    terrain_patch pt = terrain_patch_of(t, (size_t)i, (size_t)j);
    double X = p[0] + v[0] * t_in - pt.xi, Y = p[1] + v[1] * t_in - pt.yj;
    double z = p[2] + v[2] * t_in - 0.5 * g * t_in * t_in, vz = v[2] - g * t_in;
    *C = z - (pt.a + pt.b * X + pt.c * Y + pt.d * X * Y);
    *B = vz - (pt.b + pt.d * Y) * v[0] - (pt.c + pt.d * X) * v[1];
    *A = -0.5 * g - pt.d * v[0] * v[1];
}

int terrain_first_impact(const rf_terrain *t, const double p[3], const double v[3], double g, double tmax,
                         double *tau, size_t *ci, size_t *cj)
{
    long i, j;
    first_cell(t, p, v, &i, &j);
    double t_in = 0, speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    int first = 1;
    for (;;) {
        if (!cell_ok(t, i, j)) { /* the border or a no-data cell */
            *tau = t_in;
            return 0;
        }
        double tx = line_time(p[0], v[0], t->x0, t->dx, i), ty = line_time(p[1], v[1], t->y0, t->dy, j);
        double t_out = tx < ty ? tx : ty; /* (fmin inlined: no NaN here, the same value) */
        t_out = t_out < tmax ? t_out : tmax;
        double A, B, C;
        cell_gap(t, i, j, p, v, g, t_in, &A, &B, &C);
        double s = first && fabs(C) <= on_surface_tol(p[2]) ? start_root(A, B, t_out - t_in, speed)
                                                           : entering_root(A, B, C, t_out - t_in);
        first = 0;
        if (s < INFINITY) {
            *tau = t_in + s, *ci = (size_t)i, *cj = (size_t)j;
            return 1;
        }
        if (t_out >= tmax) {
            *tau = INFINITY;
            return 0;
        }
        /* next cell: both lines at once at a corner (equal times up to round-off) */
        double close = 1e-13 * (1 + t_out);
        if (tx <= ty + close)
            i += v[0] > 0 ? 1 : -1;
        if (ty <= tx + close)
            j += v[1] > 0 ? 1 : -1;
        t_in = t_out;
    }
}
