/* terrain_contact.c - sliding and rolling on the terrain surface (issue 28
 * item 3), with the laws of the 2D contact (contact.c, docs/trajectories.md
 * sec. 3.4) on the bilinear surface z = f(x, y) of terrain_grid.c.
 *
 * Equations.  On the patch of a cell f = a + b X + c Y + d X Y, so f_x = b +
 * d Y, f_y = c + d X and the Hessian H has f_xx = f_yy = 0, f_xy = d.  With
 * F = z - f >= 0, grad F = (-f_x, -f_y, 1), n = grad F / |grad F|, staying
 * on the surface means grad F . a = v_h^T H v_h = 2 d v_x v_y =: kappa (the
 * centripetal part; 0 on a plane).  Newton per unit mass, a = (0, 0, -g) +
 * N n + T with T tangent, gives the normal load per unit mass
 *     N = (g + kappa) / |grad F|             (g cos b on a plane)
 * and N <= 0 means the surface falls away faster than the block's parabola:
 * the block is launched with its velocity.  With g_t = (0, 0, -g) + g n_z n,
 * gravity along the surface, a = a_t + (kappa / |grad F|) n and
 *   sliding (a point block; a sphere that cannot roll):
 *     a_t = g_t - mu N s^,  s the slip of the contact point, s = v + r n x omega
 *     (s = v for a point), mu = tan(friction_angle); friction spins a sliding
 *     sphere: d omega/dt = mu N m r (n x s^) / I;
 *   rolling (a sphere where |g_t| k / (1 + k) <= mu N, k = I / (m r^2) = 2/5,
 *   the 2D rule of traj_contact_rolls):
 *     a_t = (g_t - mu_r N v^) / (1 + k),  omega = n x v / r,
 * and a sphere that starts to roll with slip takes the impulse that keeps its
 * angular momentum about the contact point: v' = (v + k r omega x n)/(1 + k).
 *
 * Integration.  On a plane (d = 0) with the velocity along the fall line, or
 * from rest (and for a sliding sphere its slip along the same line) the
 * acceleration is constant: the step is exact and ends at the cell's edge,
 * at rest or at the end of the slip (closed-form roots, as in 2D).
 * Elsewhere a second-order step (Heun, with the Euler difference as its
 * error estimate, CC_TOL of the speed per step) of at most two cell lengths
 * (so that a step from one edge usually reaches the next: one step per
 * cell, not a cell length and then the sliver left to the edge) and a
 * quarter of the speed, cut where its path leaves the cell (the patch
 * is smooth inside: its edges are the only kinks); a step in which the
 * speed (or a sliding sphere's slip) would vanish is one Euler step to that
 * instant.  The point is put back on the surface and the velocity into its
 * tangent plane, and the kinetic energy is capped by the start's plus
 * gravity's work minus (a lower bound of) the friction's.  Below v_stop, on
 * ground where it cannot start again, the block stops (no creeping to rest
 * in ever shorter steps).
 *
 * Edges.  Crossing a cell edge changes the normal: the velocity pointing
 * above the next patch's tangent plane (convex) launches the block (the
 * flight, terrain_fly, is flown from here: a soft landing goes on in this
 * phase without a new one; hop); else
 * (concave) it loses its part along the new normal (the plastic kink of
 * 2D).  When then the new patch pulls back to the edge and the speed away
 * from it is below v_stop or none (a notch: a valley whose sides meet at 90
 * deg or less), the block is in the valley line: it moves along the edge
 * (straight, so at constant acceleration: gravity along it minus the
 * friction of both faces, whose normal forces balance the rest of gravity),
 * node to node, until it stops there or the valley opens (a sphere rolls
 * along it: mu_r instead of mu, and 1 / (1 + k)).  A block at rest
 * on an edge or a node starts into the cell its fall line points into, or
 * along a sloping valley line, or stays (stopped).  The material is the
 * current cell's; leaving the DEM or entering a no-data cell: exited.
 *
 * Every step is a piece (uniform acceleration over the step) emitted with
 * terrain_emit: a barrier that holds the block stops it at the cut; one it
 * breaks through scales its velocity and spin there, and the motion goes on
 * from the cut. */
#include "trajectory/terrain_contact_internal.h"

#include <math.h>
#include <string.h>

/* ---- rest and edges ---- */

/* Which sides of c the point lies on (within round-off). */
static void on_sides(const terrain_run *r, const cc_cell *c, int *sx, int *sy)
{
    double tol = 1e-9 * tc_fmin(r->dem->dx, r->dem->dy);
    *sx = fabs(r->p[0] - c->P.xi) <= tol ? -1 : fabs(r->p[0] - c->x1) <= tol ? 1 : 0;
    *sy = fabs(r->p[1] - c->P.yj) <= tol ? -1 : fabs(r->p[1] - c->y1) <= tol ? 1 : 0;
}

/* How much gravity exceeds the static resistance in cell q at the point when
 * its fall line leads into q (else -1). */
static double start_excess(const terrain_run *r, const cc_cell *q)
{
    const double zero[3] = {0, 0, 0};
    cc_geom G;
    geom(r, q, r->p, zero, &G);
    int sx, sy;
    on_sides(r, q, &sx, &sy);
    double tiny = 1e-12 * r->g;
    if ((sx && G.gt[0] * sx > tiny) || (sy && G.gt[1] * sy > tiny))
        return -1;
    double excess = norm3(G.gt) - (rolls(r, q, &G) ? q->mur : q->mu) * G.N;
    return excess > 0 ? excess : -1;
}

/* The block at rest (v = 0) in cell c: 1 if it starts into *c, 2 if a
 * valley line took it on (state changed), 0 if the phase ended. */
static int rest_at(terrain_run *r, cc_cell *c)
{
    int sx, sy;
    on_sides(r, c, &sx, &sy);
    cc_cell cand[4], best = *c;
    int n = 0;
    double top = -1;
    cand[n++] = *c;
    for (int a = 0; a <= (sx != 0); a++)
        for (int b = 0; b <= (sy != 0); b++)
            if ((a || b) && tc_cell_load(r, c->i + a * sx, c->j + b * sy, &cand[n]))
                n++;
    for (int q = 0; q < n; q++) {
        double ex = start_excess(r, &cand[q]);
        if (ex > top)
            top = ex, best = cand[q];
    }
    if (top > 0) {
        *c = best;
        return 1;
    }
    /* a sloping valley line through the point: along it */
    for (int q = 0; q < 4; q++) {
        int axis = q < 2, side = axis ? sx : sy, other = axis ? sy : sx, row = q % 2 ? other : 0;
        if (!side || (q % 2 && !other))
            continue;
        cc_crease k;
        k.axis = axis;
        long ai = c->i + (axis ? (side > 0 ? 0 : -1) : row), aj = c->j + (axis ? row : (side > 0 ? 0 : -1));
        if (!tc_cell_load(r, ai, aj, &k.A) || !tc_cell_load(r, ai + axis, aj + !axis, &k.B))
            continue;
        double resist, ge, e[3];
        if (tc_crease_loads(r, &k, &resist, &ge, e) && fabs(ge) > resist)
            return tc_crease_run(r, k, c) ? 2 : 0;
    }
    tc_stop_here(r);
    return 0;
}

/* The state machine's count of events (terrain_simulate.c counts one per
 * phase it starts); 0 at the limit (ended: step_limit). */
static int count_phase(terrain_run *r)
{
    if (r->res->n_steps++ >= r->s->max_steps) {
        tc_finish(r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
        return 0;
    }
    return 1;
}

/* Into *c, the cell of the contact that starts at the current point after
 * a landing in cell (ci, cj): tc_pick_cell's cell (the one the horizontal
 * velocity leads into), taken without the search when the point lies inside
 * (ci, cj) away from its edges (the same cell, the same bits).  0: none. */
static int landing_cell(terrain_run *r, size_t ci, size_t cj, cc_cell *c)
{
    const rf_terrain *t = r->dem;
    double fx = (r->p[0] - t->x0) / t->dx - (double)ci, fy = (r->p[1] - t->y0) / t->dy - (double)cj;
    const double m = 1e-6;
    cc_cell hint = *c;
    if (fx > m && fx < 1 - m && fy > m && fy < 1 - m && tc_cell_load_near(r, (long)ci, (long)cj, c, &hint))
        return 1;
    return tc_pick_cell(r, r->p[0], r->p[1], r->v[0], r->v[1], c);
}

/* A launch at a convex edge (the velocity points above the next patch):
 * the flight (terrain_fly: the same exact first impact, piece and landing
 * rule as any flight) and, when it ends in contact, the contact phase goes
 * on from the landing without returning to the state machine: the same
 * events and counts as a new phase (terrain_contact_run's start), without
 * its search for the cell.  3: in contact again in *c; 0: the phase ended
 * (a rebound into a flight, a stop, an exit, a barrier's cut). */
static int hop(terrain_run *r, cc_cell *c)
{
    tc_launch(r);
    if (!count_phase(r))
        return 0;
    size_t ci, cj;
    terrain_fly(r, &ci, &cj);
    if (r->phase != TERRAIN_CONTACT || r->nomem || !count_phase(r))
        return 0;
    if (!landing_cell(r, ci, cj, c)) {
        tc_finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
        return 0;
    }
    cc_geom G;
    tc_onto_surface(r, c, &G);
    geom_keep(c, r->p, &G); /* the first step starts here */
    terrain_event(r, RF_EV_CONTACT, 0);
    return 3;
}

/* At the edge (ex, ey) of c after a step: the next cell, launch (and its
 * landing: hop), kink, valley line or exit.  1 to go on in *c, 3 after a
 * hop (in contact again in *c), 0 if the phase ended. */
static int cross_edge(terrain_run *r, cc_cell *c, int ex, int ey, const cc_geom *GAp)
{
    cc_cell b;
    if (ex)
        r->p[0] = ex > 0 ? c->x1 : c->P.xi;
    if (ey)
        r->p[1] = ey > 0 ? c->y1 : c->P.yj;
    if (!tc_cell_load_near(r, c->i + ex, c->j + ey, &b, c)) {
        tc_finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
        return 0;
    }
    cc_geom GB;
    const cc_geom GA = *GAp;
    geom_at(r, &b, r->p, &GB);
    GB.N = GB.an = 0; /* (not set by geom_at) */
    double sp = norm3(r->v), vn = dot3(r->v, GB.n);
    if (vn > 1e-9 * sp) /* the velocity points above the new patch: convex */
        return hop(r, c);
    for (int k = 0; k < 3; k++)
        r->v[k] -= vn * GB.n[k]; /* concave: the part into the new patch is lost */
    double m[2] = {(double)ex, (double)ey}, mm = ex && ey ? sqrt(2.0) : 1.0;
    double sB = (GB.fx * m[0] + GB.fy * m[1]) / mm, sA = (GA.fx * m[0] + GA.fy * m[1]) / mm;
    double away = (r->v[0] * m[0] + r->v[1] * m[1]) / mm * sqrt(1 + sB * sB);
    cc_cell a = *c;
    *c = b;
    geom_keep(c, r->p, &GB); /* the next step starts here */
    if (vn < -1e-9 * sp)
        terrain_event(r, RF_EV_VERTEX, 0);
    if (sB >= 0 && away < r->s->v_stop && sA < sB) { /* the new patch pulls back: a notch or hollow */
        if (ex && ey) {
            memset(r->v, 0, sizeof r->v), memset(r->omega, 0, sizeof r->omega);
            return 1;
        }
        cc_crease k;
        k.axis = ex ? 1 : 0;
        k.A = (ex > 0 || ey > 0) ? a : b;
        k.B = (ex > 0 || ey > 0) ? b : a;
        double resist, ge, e[3];
        if (tc_crease_loads(r, &k, &resist, &ge, e)) {
            double u = dot3(r->v, e);
            for (int q = 0; q < 3; q++)
                r->v[q] = u * e[q];
            return tc_crease_run(r, k, c);
        }
    }
    if (away <= 0) { /* it cannot go on into b: along the edge */
        double e[3] = {(double)(ey != 0), (double)(ex != 0), 0};
        e[2] = e[0] * GB.fx + e[1] * GB.fy;
        double u = dot3(r->v, e) / dot3(e, e);
        for (int q = 0; q < 3; q++)
            r->v[q] = u * e[q];
    }
    return 1;
}

/* ---- the contact phase ---- */

/* Emit the step's piece, move along it (to a barrier's cut), put the state
 * on the surface, cap its energy; then the edge it reached.  1 to go on. */
static int take_step(terrain_run *r, cc_cell *c, const cc_step *s, const cc_geom *G, int exact, int rolling,
                     double e0)
{
    cc_step st = *s;
    double tau = st.tau, scale;
    terrain_piece_outcome o = tc_emit(r, &tau, st.a, &scale, c); /* (a step never leaves its cell) */
    int cut = tau < st.tau;
    double p0[3];
    memcpy(p0, r->p, sizeof p0);
    tc_advance(r, tau, st.a, st.dw);
    if (!cut && st.ex)
        r->p[0] = st.ex > 0 ? c->x1 : c->P.xi;
    if (!cut && st.ey)
        r->p[1] = st.ey > 0 ? c->y1 : c->P.yj;
    r->p[0] = tc_fmin(tc_fmax(r->p[0], c->P.xi), c->x1), r->p[1] = tc_fmin(tc_fmax(r->p[1], c->P.yj), c->y1);
    cc_geom G1;
    tc_onto_surface(r, c, &G1);
    if (o == TERRAIN_PIECE_STOPPED) {
        tc_stop_here(r);
        return 0;
    }
    if (!cut && st.rest)
        memset(r->v, 0, sizeof r->v);
    geom_load(r, c, r->v, &G1);
    geom_keep(c, r->p, &G1); /* the next step starts here */
    if (rolling || (!cut && st.slip_end))
        tc_set_rolling(r, &G1, 0);
    if (!exact) {
        double d[3] = {r->p[0] - p0[0], r->p[1] - p0[1], r->p[2] - p0[2]};
        double N = tc_fmax(0, tc_fmin(G->N, G1.N));
        double work = is_sphere(r) && !rolling ? 0 : (rolling ? c->mur : c->mu) * N * norm3(d);
        tc_cap_energy(r, e0, work);
    }
    if (o == TERRAIN_PIECE_SLOWED) {
        for (int k = 0; k < 3; k++)
            r->v[k] *= scale, r->omega[k] *= scale;
        return 1;
    }
    if (!cut && (st.ex || st.ey))
        return cross_edge(r, c, st.ex, st.ey, &G1);
    return 1;
}

/* One step; 1 to go on. */
static int step_once(terrain_run *r, cc_cell *c)
{
    if (r->res->n_steps++ >= r->s->max_steps) {
        tc_finish(r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
        return 0;
    }
    cc_geom G;
    geom_at_cached(r, c, r->p, &G);
    geom_load(r, c, r->v, &G);
    if (G.N <= 0) {
        tc_launch(r);
        return 0;
    }
    int rolling = rolls(r, c, &G);
    if (rolling)
        tc_set_rolling(r, &G, 1);
    double sp = norm3(r->v);
    if (sp == 0) {
        int k = rest_at(r, c);
        if (k != 1)
            return k;
        geom_at_cached(r, c, r->p, &G);
        geom_load(r, c, r->v, &G);
        rolling = rolls(r, c, &G);
    }
    cc_step st;
    double e0 = tc_energy(r);
    int exact = tc_exact_step(r, c, &G, rolling, &st);
    if (!exact) {
        double resist = (rolling ? c->mur : c->mu) * G.N;
        if (sp > 0 && sp < r->s->v_stop && norm3(G.gt) <= resist) {
            tc_stop_here(r); /* creeping on ground where it cannot start again */
            return 0;
        }
        tc_numeric_step(r, c, &G, rolling, &st);
    }
    if (!isfinite(st.tau)) {
        tc_stop_here(r);
        return 0;
    }
    return take_step(r, c, &st, &G, exact, rolling, e0);
}

void terrain_contact_run(terrain_run *r)
{
    cc_cell c;
    double hx = r->v[0], hy = r->v[1];
    r->phase = TERRAIN_CONTACT;
    if (!tc_pick_cell(r, r->p[0], r->p[1], hx, hy, &c)) {
        tc_finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
        return;
    }
    cc_geom G;
    tc_onto_surface(r, &c, &G);
    geom_keep(&c, r->p, &G); /* the first step starts here */
    terrain_event(r, RF_EV_CONTACT, 0);
    double last[3] = {NAN, NAN, NAN};
    for (int idle = 0; r->phase == TERRAIN_CONTACT && !r->nomem;) {
        int k = step_once(r, &c);
        if (!k)
            break;
        if (k == 3) { /* a new contact after a hop: as a phase started afresh */
            idle = 0, last[0] = last[1] = last[2] = NAN;
            continue;
        }
        /* at rest on the same point step after step: every way out leads
         * back (a node or edge where the cells' fall lines meet) */
        int still = r->v[0] == 0 && r->v[1] == 0 && r->v[2] == 0 && !memcmp(last, r->p, sizeof last);
        idle = still ? idle + 1 : 0;
        if (idle >= 8) {
            tc_stop_here(r);
            break;
        }
        memcpy(last, r->p, sizeof last);
    }
}
