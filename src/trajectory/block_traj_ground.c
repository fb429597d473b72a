/* block_traj_ground.c - the grounds of the block engines as the core sees
 * them (docs/block-shape.md "Wiring", "Adaptive steps"): the terrain's
 * height callback, and for each of the profile and the terrain the bound of
 * the ground above a plane over a rectangle (rf_block_ground_bound_fn),
 * with which rf_block_advance proves a flight clear and a contact step
 * evaluates the ground only at the vertices near it. */
#include "trajectory/block_traj.h"
#include "trajectory/terrain_internal.h"

#include <math.h>

/* The profile: z(x) - p0 - p1 x - p2 y is linear in x between the nodes and
 * linear in y, so its largest value over the rectangle lies at x in {x0,
 * x1, the nodes between} and y in {y0, y1}. */
int traj_block_profile_bound(void *profile, double x0, double y0, double x1, double y1, const double p[3], double *dz)
{
    const rf_block_profile *pr = profile;
    if (pr->n < 2)
        return 0;
    x0 = fmax(x0, pr->x[0]), x1 = fmin(x1, pr->x[pr->n - 1]);
    if (!(x0 <= x1))
        return 0;
    size_t lo = 0, hi = pr->n - 1; /* the last node at or left of x0 */
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (x0 < pr->x[mid])
            hi = mid;
        else
            lo = mid;
    }
    double m = -INFINITY, z, n[3];
    if (rf_block_ground_profile(profile, x0, 0, &z, n))
        m = z - p[1] * x0;
    if (rf_block_ground_profile(profile, x1, 0, &z, n))
        m = fmax(m, z - p[1] * x1);
    for (size_t k = lo + 1; k < pr->n && pr->x[k] < x1; k++)
        m = fmax(m, pr->z[k] - p[1] * pr->x[k]);
    *dz = m - p[0] - fmin(p[2] * y0, p[2] * y1);
    return 1;
}

int traj_block_terrain_ground(void *dem, double x, double y, double *z, double n[3])
{
    return rf_terrain_height(dem, x, y, z, n);
}

/* More cells than this in a rectangle (a flight of tens of metres over a
 * fine DEM): the bound is left infinite (the step is then a contact step,
 * every vertex tested): a bound, though a useless one. */
#define BOUND_MAX_CELLS 4096

/* The cell index range [*a, *b] of [lo, hi] along one axis (origin o, step d, n nodes). */
static int cell_range(double lo, double hi, double o, double d, size_t n, size_t *a, size_t *b)
{
    double f0 = (lo - o) / d, f1 = (hi - o) / d, top = (double)(n - 1);
    if (!(f1 >= 0 && f0 <= top && f0 <= f1))
        return 0;
    f0 = f0 < 0 ? 0 : f0, f1 = f1 > top ? top : f1;
    *a = (size_t)f0, *b = (size_t)f1;
    if (*a > n - 2)
        *a = n - 2;
    if (*b > n - 2)
        *b = n - 2;
    return 1;
}

int traj_block_terrain_bound(void *dem, double x0, double y0, double x1, double y1, const double p[3], double *dz)
{
    const rf_terrain *t = dem;
    size_t i0, i1, j0, j1;
    if (t->nx < 2 || t->ny < 2 || !cell_range(x0, x1, t->x0, t->dx, t->nx, &i0, &i1) ||
        !cell_range(y0, y1, t->y0, t->dy, t->ny, &j0, &j1))
        return 0;
    if ((i1 - i0 + 1) * (j1 - j0 + 1) > BOUND_MAX_CELLS) {
        *dz = INFINITY;
        return 1;
    }
    double m = -INFINITY;
    for (size_t j = j0; j <= j1; j++)
        for (size_t i = i0; i <= i1; i++) {
            if (!t->valid[j * (t->nx - 1) + i])
                continue;
            terrain_patch pa = terrain_patch_of(t, i, j); /* the rectangle clipped to the cell, in its metres */
            double X[2] = {fmax(x0 - pa.xi, 0), fmin(x1 - pa.xi, t->dx)};
            double Y[2] = {fmax(y0 - pa.yj, 0), fmin(y1 - pa.yj, t->dy)};
            for (int c = 0; c < 4; c++) {
                double u = X[c & 1], v = Y[c >> 1];
                double d = pa.a + pa.b * u + pa.c * v + pa.d * u * v - p[0] - p[1] * (pa.xi + u) - p[2] * (pa.yj + v);
                m = d > m ? d : m;
            }
        }
    if (m == -INFINITY)
        return 0;
    *dz = m;
    return 1;
}
