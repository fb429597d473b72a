/* terrain_emit.c - what every phase of a 3D trajectory (flight in
 * terrain_simulate.c, contact in terrain_contact.c) reports through: the
 * events of a recorded trajectory, and each piece of path (barriers first,
 * then the hazard rasters for the part before a barrier's cut, and the
 * rebound height of a flight that starts at an impact).  Its own file so
 * that the phases call it without calling each other. */
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void terrain_event(terrain_run *r, rf_traj_event_kind kind, int flying)
{
    rf_terrain_result *res = r->res;
    if (!res->events)
        return;
    if (!rf_grow((void **)&res->events, res->n_events, &res->events_cap, sizeof *res->events)) {
        r->nomem = 1, r->phase = TERRAIN_DONE; /* rf_terrain_simulate reports it */
        return;
    }
    rf_terrain_event *e = &res->events[res->n_events++];
    e->kind = kind, e->flying = flying, e->t = r->t;
    memcpy(e->p, r->p, sizeof e->p), memcpy(e->v, r->v, sizeof e->v), memcpy(e->omega, r->omega, sizeof e->omega);
    memset(e->q, 0, sizeof e->q); /* a rigid block's orientation: set by block_traj_terrain.c */
}

/* Largest rise of a flight with initial upward speed vz over [0, T]. */
static double flight_rise(double vz, double g, double T)
{
    if (vz <= 0)
        return 0;
    double ta = vz / g;
    return ta <= T ? vz * vz / (2 * g) : vz * T - 0.5 * g * T * T;
}

terrain_piece_outcome terrain_emit(terrain_run *r, const terrain_piece *pc, double *tau_cut, double *scale)
{
    terrain_piece_outcome o = terrain_barrier_piece(r, pc, tau_cut, scale);
    terrain_piece cut = *pc;
    if (o != TERRAIN_PIECE_FREE && *tau_cut < cut.T)
        cut.T = *tau_cut;
    if (r->hazard && r->piece_in_cell) /* a contact step's piece: its cell is known */
        terrain_hazard_piece_in(r->hazard, r->dem, r->mass, &cut, r->piece_ci, r->piece_cj);
    else if (r->hazard)
        terrain_hazard_piece(r->hazard, r->dem, r->mass, &cut);
    int flight = !pc->on_ground && pc->a[0] == 0 && pc->a[1] == 0 && pc->a[2] == -r->g;
    if (flight && r->from_impact) {
        double rise = flight_rise(pc->v[2], r->g, cut.T);
        if (rise > r->res->rebound_height)
            r->res->rebound_height = rise;
    }
    return o;
}

