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

/* Emit the piece over *tau (shortened to a barrier's cut); its outcome. */
terrain_piece_outcome tc_emit(terrain_run *r, double *tau, const double a[3], double *scale)
{
    terrain_piece pc;
    memset(&pc, 0, sizeof pc);
    pc.t = r->t, pc.T = *tau, pc.on_ground = 1;
    memcpy(pc.p, r->p, sizeof pc.p);
    memcpy(pc.v, r->v, sizeof pc.v);
    memcpy(pc.a, a, sizeof pc.a);
    pc.e_rot = 0.5 * r->inertia * dot3(r->omega, r->omega);
    double cut = INFINITY;
    *scale = 1;
    terrain_piece_outcome o = terrain_emit(r, &pc, &cut, scale);
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
