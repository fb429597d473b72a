/* terrain_contact_state.c - the block's state in the contact phase
 * (terrain_contact.c): the end of the phase (stop, launch, exit), a piece
 * emitted and the state advanced along it, rolling set, the energy cap. */
#include "trajectory/terrain_contact_internal.h"

#include <math.h>
#include <string.h>

void tc_finish(terrain_run *r, rf_traj_state state, rf_traj_event_kind kind)
{
    r->phase = TERRAIN_DONE;
    r->res->state = state;
    memcpy(r->res->end, r->p, sizeof r->res->end);
    r->res->t_end = r->t;
    terrain_event(r, kind, 0);
}

void tc_stop_here(terrain_run *r)
{
    memset(r->v, 0, sizeof r->v);
    memset(r->omega, 0, sizeof r->omega);
    tc_finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
}

void tc_launch(terrain_run *r)
{
    r->phase = TERRAIN_FLY;
    r->from_impact = 0;
    terrain_event(r, RF_EV_LAUNCH, 1);
}

/* Mechanical energy per unit mass [J/kg]. */
double tc_energy(const terrain_run *r)
{
    double kin = 0.5 * dot3(r->v, r->v);
    if (r->mass > 0)
        kin += 0.5 * r->inertia / r->mass * dot3(r->omega, r->omega);
    return kin + r->g * r->p[2];
}

/* The piece's map path, in the closed square of its cell, is that cell's alone
 * for the rasters (terrain_hazard_piece_in): not a point, and its chord (what
 * the rasters' walk follows) does not start on one of the cell's lines going
 * along it or out of the cell (the walk gives such a start to the cell beyond
 * the line, or a segment on the line to the cell north / east of it: a path
 * can dip into its cell by micrometres between two points of its edge). */
static int in_cell_alone(const cc_cell *c, const terrain_piece *pc)
{
    if (!(pc->T > 0))
        return 0;
    double T = pc->T, x0 = pc->p[0], y0 = pc->p[1];
    double xe = x0 + pc->v[0] * T + 0.5 * pc->a[0] * T * T, ye = y0 + pc->v[1] * T + 0.5 * pc->a[1] * T * T;
    if (x0 == xe && y0 == ye)
        return 0;
    if ((x0 == c->P.xi && xe <= x0) || (x0 == c->x1 && xe >= x0))
        return 0;
    if ((y0 == c->P.yj && ye <= y0) || (y0 == c->y1 && ye >= y0))
        return 0;
    return 1;
}

/* Emit the piece over *tau (shortened to a barrier's cut); its outcome. */
terrain_piece_outcome tc_emit(terrain_run *r, double *tau, const double a[3], double *scale, const cc_cell *cell)
{
    terrain_piece pc;
    memset(&pc, 0, sizeof pc);
    pc.t = r->t, pc.T = *tau, pc.on_ground = 1;
    memcpy(pc.p, r->p, sizeof pc.p);
    memcpy(pc.v, r->v, sizeof pc.v);
    memcpy(pc.a, a, sizeof pc.a);
    pc.e_rot = 0.5 * r->inertia * dot3(r->omega, r->omega);
    if (cell && in_cell_alone(cell, &pc))
        r->piece_in_cell = 1, r->piece_ci = (size_t)cell->i, r->piece_cj = (size_t)cell->j;
    double cut = INFINITY;
    *scale = 1;
    terrain_piece_outcome o = terrain_emit(r, &pc, &cut, scale);
    r->piece_in_cell = 0;
    if (o != TERRAIN_PIECE_FREE && cut < *tau)
        *tau = cut > 0 ? cut : 0;
    return o;
}

void tc_advance(terrain_run *r, double tau, const double a[3], const double dw[3])
{
    for (int k = 0; k < 3; k++) {
        r->p[k] += r->v[k] * tau + 0.5 * a[k] * tau * tau;
        r->v[k] += a[k] * tau;
        r->omega[k] += dw[k] * tau;
    }
    r->t += tau;
}

/* Roll: omega = n x v / r (after the impulse that ends a slip). */
void tc_set_rolling(terrain_run *r, const cc_geom *G, int impulse)
{
    if (impulse) {
        double k = kratio(r), wn[3];
        cross3(r->omega, G->n, wn);
        for (int q = 0; q < 3; q++)
            r->v[q] = (r->v[q] + k * r->radius * wn[q]) / (1 + k);
    }
    cross3(G->n, r->v, r->omega);
    for (int q = 0; q < 3; q++)
        r->omega[q] /= r->radius;
}

/* After a numerical step: no energy gained beyond the start's minus the work. */
void tc_cap_energy(terrain_run *r, double e0, double work)
{
    double kin = tc_energy(r) - r->g * r->p[2], allowed = e0 - work - r->g * r->p[2];
    if (kin <= allowed)
        return;
    double s = allowed > 0 && kin > 0 ? sqrt(allowed / kin) : 0;
    for (int k = 0; k < 3; k++)
        r->v[k] *= s, r->omega[k] *= s;
}
