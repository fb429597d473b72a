/* terrain_fly.c - the flight phase of a 3D trajectory (the state machine is
 * terrain_simulate.c): the exact first impact (terrain_flight.c), the flight
 * emitted as a piece (barriers, hazard rasters, rebound height), and the
 * impact (terrain_bounce.c: a soft landing continues in contact; a rebound
 * slower than v_stop stops; one with normal speed below contact_speed, or
 * none, continues in contact; else a new flight).  Its own file so that both
 * the state machine and the contact phase (a launch at a convex cell edge
 * lands inside the contact phase, terrain_contact.c) call it without calling
 * each other.  Moved from terrain_simulate.c unchanged. */
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <string.h>

static void finish(terrain_run *r, rf_traj_state state, rf_traj_event_kind kind)
{
    r->phase = TERRAIN_DONE;
    r->res->state = state;
    terrain_event(r, kind, 0);
}

static double rot_energy(const terrain_run *r)
{
    return 0.5 * r->inertia * (r->omega[0] * r->omega[0] + r->omega[1] * r->omega[1] + r->omega[2] * r->omega[2]);
}

static void advance(terrain_run *r, double tau)
{
    r->t += tau;
    r->p[0] += r->v[0] * tau;
    r->p[1] += r->v[1] * tau;
    r->p[2] += r->v[2] * tau - 0.5 * r->g * tau * tau;
    r->v[2] -= r->g * tau;
}

/* Height of patch p at (x, y), clamped to the cell (fmin / fmax inlined:
 * the same values for finite x, y). */
static double patch_height(const rf_terrain *t, const terrain_patch *p, double x, double y)
{
    double X = x - p->xi, Y = y - p->yj;
    X = X > 0 ? X : 0, Y = Y > 0 ? Y : 0;
    X = X < t->dx ? X : t->dx, Y = Y < t->dy ? Y : t->dy;
    return p->a + p->b * X + p->c * Y + p->d * X * Y;
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Continue in contact: the velocity along the surface of normal n. */
void terrain_to_contact(terrain_run *r, const double n[3])
{
    double vn = dot3(r->v, n);
    for (int q = 0; q < 3; q++)
        r->v[q] -= vn * n[q];
    r->phase = TERRAIN_CONTACT;
    r->from_impact = 0;
}

static void record_impact(terrain_run *r, size_t ci, size_t cj, const double v_in[3])
{
    rf_terrain_result *res = r->res;
    if (res->impacts && !rf_grow((void **)&res->impacts, res->n_impacts, &res->impacts_cap, sizeof *res->impacts)) {
        r->nomem = 1, r->phase = TERRAIN_DONE;
        return;
    }
    if (res->impacts) {
        rf_terrain_impact *m = &res->impacts[res->n_impacts];
        m->t = r->t, m->x = r->p[0], m->y = r->p[1], m->z = r->p[2];
        memcpy(m->v_in, v_in, sizeof m->v_in), memcpy(m->v_out, r->v, sizeof m->v_out);
        memcpy(m->omega_out, r->omega, sizeof m->omega_out);
        m->material = terrain_material_of(r->dem, ci, cj);
        memset(m->q, 0, sizeof m->q), memset(m->rot_energy, 0, sizeof m->rot_energy); /* a rigid block's only */
    }
    res->n_impacts++;
}

/* The block at the current point (on cell (ci, cj)'s patch p) hits the
 * surface: its normal there, once for the bounce and the contact. */
static void impact(terrain_run *r, size_t ci, size_t cj, const terrain_patch *p)
{
    double v_in[3] = {r->v[0], r->v[1], r->v[2]}, n[3];
    terrain_patch_normal(r->dem, p, r->p[0], r->p[1], n);
    if (terrain_bounce_n(r, ci, cj, n, r->v, r->omega)) { /* soft landing */
        terrain_to_contact(r, n);
        terrain_event(r, RF_EV_CONTACT, 0);
        return;
    }
    record_impact(r, ci, cj, v_in);
    if (r->nomem)
        return;
    double speed = sqrt(dot3(r->v, r->v));
    if (speed < r->s->v_stop || speed == 0) {
        memset(r->v, 0, sizeof r->v), memset(r->omega, 0, sizeof r->omega);
        terrain_event(r, RF_EV_IMPACT, 0);
        finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
        return;
    }
    double vn = dot3(r->v, n);
    if (vn < r->s->contact_speed || vn <= 1e-9 * speed) { /* (no normal speed at all: a flight would graze) */
        terrain_to_contact(r, n);
        terrain_event(r, RF_EV_IMPACT, 0);
        return;
    }
    r->phase = TERRAIN_FLY;
    r->from_impact = 1;
    terrain_event(r, RF_EV_IMPACT, 1);
}

/* The flight is cut at a barrier: held (rest there) or slowed (on it goes). */
static void barrier_cut(terrain_run *r, terrain_piece_outcome o, double tau, double scale)
{
    advance(r, tau);
    if (o == TERRAIN_PIECE_STOPPED) {
        memset(r->v, 0, sizeof r->v), memset(r->omega, 0, sizeof r->omega);
        finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
        return;
    }
    for (int q = 0; q < 3; q++)
        r->v[q] *= scale, r->omega[q] *= scale;
    r->from_impact = 0;
    terrain_event(r, RF_EV_BARRIER, 1);
}

/* The flight's map chord lies in the closed square of its landing cell
 * (ci, cj) and does not start on one of the cell's lines going along it or
 * out of the cell (the rule of a contact step's piece, terrain_contact_state.c):
 * it is that cell's alone for the rasters (terrain_hazard_piece_in), no walk
 * over the grid.  A launch at a convex cell edge lands in the next cell: its
 * flight starts on the line between the two and goes into the landing cell. */
static int in_landing_cell(const terrain_run *r, const terrain_piece *pc, size_t ci, size_t cj)
{
    const rf_terrain *t = r->dem;
    double xi = t->x0 + (double)ci * t->dx, yj = t->y0 + (double)cj * t->dy, x1 = xi + t->dx, y1 = yj + t->dy;
    double x0 = pc->p[0], y0 = pc->p[1], xe = x0 + pc->v[0] * pc->T, ye = y0 + pc->v[1] * pc->T;
    if (!(pc->T > 0) || (x0 == xe && y0 == ye))
        return 0;
    if (!(x0 >= xi && x0 <= x1 && xe >= xi && xe <= x1 && y0 >= yj && y0 <= y1 && ye >= yj && ye <= y1))
        return 0;
    if ((x0 == xi && xe <= x0) || (x0 == x1 && xe >= x0) || (y0 == yj && ye <= y0) || (y0 == y1 && ye >= y0))
        return 0;
    return 1;
}

void terrain_fly(terrain_run *r, size_t *cell_i, size_t *cell_j)
{
    double tau;
    size_t ci = 0, cj = 0;
    int hit = terrain_first_impact(r->dem, r->p, r->v, r->g, INFINITY, &tau, &ci, &cj);
    double T = isfinite(tau) ? tau : 0;
    terrain_piece pc = {r->t, T, {r->p[0], r->p[1], r->p[2]}, {r->v[0], r->v[1], r->v[2]}, {0, 0, -r->g},
                        rot_energy(r), 0};
    double cut, scale;
    if (hit && r->hazard && in_landing_cell(r, &pc, ci, cj))
        r->piece_in_cell = 1, r->piece_ci = ci, r->piece_cj = cj;
    terrain_piece_outcome o = terrain_emit(r, &pc, &cut, &scale);
    r->piece_in_cell = 0;
    if (o != TERRAIN_PIECE_FREE) {
        barrier_cut(r, o, cut, scale);
        return;
    }
    advance(r, T);
    if (!hit) {
        finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
        return;
    }
    terrain_patch p = terrain_patch_of(r->dem, ci, cj);
    r->p[2] = patch_height(r->dem, &p, r->p[0], r->p[1]); /* exactly on the surface */
    *cell_i = ci, *cell_j = cj;
    impact(r, ci, cj, &p);
}
