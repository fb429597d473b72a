/* terrain_contact_cell.c - the contact phase's cells (terrain_contact.c):
 * a cell's bilinear patch, planarity and material friction, the cell a
 * point and direction lead into, and the point put back on the surface. */
#include "trajectory/terrain_contact_internal.h"

#include <math.h>
#include <string.h>

/* tan(x), from the thread's last argument when the same (a contact phase
 * starts without a neighbour cell to take the friction from; the same bits). */
static double tan_cached(double x)
{
    static _Thread_local double last_x = 0, last_tan = 0;
    if (x != last_x)
        last_tan = tan(x), last_x = x;
    return last_tan;
}

/* Cell (i, j) into *c; its material's friction from *hint when the same
 * (NULL: none; a cell next to the current one mostly shares its material, and
 * tan is a tenth of a step's time).  0 outside the DEM or on no-data. */
int tc_cell_load_near(const terrain_run *r, long i, long j, cc_cell *c, const cc_cell *hint)
{
    const rf_terrain *t = r->dem;
    if (i < 0 || j < 0 || (size_t)i + 1 >= t->nx || (size_t)j + 1 >= t->ny || !t->valid[(size_t)j * (t->nx - 1) + (size_t)i])
        return 0;
    c->i = i, c->j = j, c->has_g = 0;
    c->P = terrain_patch_of(t, (size_t)i, (size_t)j);
    const double *z = t->z + (size_t)j * t->nx + (size_t)i;
    double zs = fabs(z[0]) + fabs(z[1]) + fabs(z[t->nx]) + fabs(z[t->nx + 1]);
    c->planar = fabs(c->P.d) * t->dx * t->dy <= 1e-13 * zs;
    if (c->planar)
        c->P.d = 0;
    c->mat = terrain_material_of(t, (size_t)i, (size_t)j);
    if (hint && hint->mat == c->mat) {
        c->mu = hint->mu, c->mur = hint->mur;
    } else {
        const rf_traj_material *m = &r->s->materials[c->mat];
        c->mu = tan_cached(m->friction_angle), c->mur = m->rolling_resistance;
    }
    c->x1 = c->P.xi + t->dx, c->y1 = c->P.yj + t->dy;
    return 1;
}

int tc_cell_load(const terrain_run *r, long i, long j, cc_cell *c) { return tc_cell_load_near(r, i, j, c, NULL); }


/* The cell holding (x, y) that the horizontal direction (hx, hy) leads into. */
int tc_pick_cell(const terrain_run *r, double x, double y, double hx, double hy, cc_cell *c)
{
    const rf_terrain *t = r->dem;
    double h = sqrt(hx * hx + hy * hy), /* (not hypot: a tenth of a step's time; no overflow at map scales) */
           eps = 1e-9 * tc_fmin(t->dx, t->dy), u, v;
    size_t i, j;
    if (h > 0 && terrain_cell_of(t, x + eps * hx / h, y + eps * hy / h, &i, &j, &u, &v))
        return tc_cell_load(r, (long)i, (long)j, c);
    if (terrain_cell_of(t, x, y, &i, &j, &u, &v))
        return tc_cell_load(r, (long)i, (long)j, c);
    return 0;
}

/* Put the state on the surface of c: z on the patch, v in its tangent plane;
 * the geometry there in *G (geom_at: its load is not set). */
void tc_onto_surface(terrain_run *r, const cc_cell *c, cc_geom *G)
{
    r->p[2] = height(c, r->p[0], r->p[1]);
    geom_at(r, c, r->p, G);
    double vn = dot3(r->v, G->n);
    for (int k = 0; k < 3; k++)
        r->v[k] -= vn * G->n[k];
}
