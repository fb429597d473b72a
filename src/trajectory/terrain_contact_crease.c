/* terrain_contact_crease.c - motion along a valley line (terrain_contact.c,
 * "Edges"): an edge pressed into both faces, moved along node to node at
 * constant acceleration until the block stops or the valley opens. */
#include "trajectory/terrain_contact_internal.h"

#include <math.h>
#include <string.h>

/* Normal loads per unit mass of both faces at the current point (static:
 * the edge is straight) and their sum times friction; 0 if the edge is not
 * a concave valley line pressed by both. */
int tc_crease_loads(const terrain_run *r, const cc_crease *k, double *resist, double *along_g, double e[3])
{
    const double zero[3] = {0, 0, 0};
    cc_geom GA, GB;
    geom(r, &k->A, r->p, zero, &GA);
    geom(r, &k->B, r->p, zero, &GB);
    double sA = k->axis ? GA.fx : GA.fy, sB = k->axis ? GB.fx : GB.fy; /* slopes across, A -> B */
    if (!(sB > sA + 1e-12 * (1 + fabs(sA) + fabs(sB))))
        return 0; /* not concave */
    double cAB = dot3(GA.n, GB.n), det = 1 - cAB * cAB;
    if (det <= 1e-12)
        return 0;
    double bA = r->g * GA.n[2], bB = r->g * GB.n[2];
    double NA = (bA - cAB * bB) / det, NB = (bB - cAB * bA) / det;
    if (!(NA >= -1e-12 * r->g && NB >= -1e-12 * r->g))
        return 0;
    NA = tc_fmax(NA, 0), NB = tc_fmax(NB, 0);
    double s = k->axis ? GA.fy : GA.fx, q = sqrt(1 + s * s); /* slope along the edge (the same on both) */
    e[0] = k->axis ? 0 : 1 / q, e[1] = k->axis ? 1 / q : 0, e[2] = s / q;
    *along_g = -r->g * e[2];
    int roll = is_sphere(r);
    *resist = roll ? (k->A.mur * NA + k->B.mur * NB) : (k->A.mu * NA + k->B.mu * NB);
    return 1;
}

/* The crease's next segment along its axis in direction dir; 0 outside. */
static int crease_shift(const terrain_run *r, cc_crease *k, int dir)
{
    long di = k->axis ? 0 : dir, dj = k->axis ? dir : 0;
    cc_crease n = *k;
    if (!tc_cell_load_near(r, k->A.i + di, k->A.j + dj, &n.A, &k->A) ||
        !tc_cell_load_near(r, k->B.i + di, k->B.j + dj, &n.B, &k->B))
        return 0;
    *k = n;
    return 1;
}

/* Move along the valley line; 1 when the block leaves it into cell *c (state
 * updated), 0 when the phase ended. */
int tc_crease_run(terrain_run *r, cc_crease k, cc_cell *c)
{
    double inv = is_sphere(r) ? 1 / (1 + kratio(r)) : 1;
    for (int idle = 0;; idle++) {
        double resist, ge, e[3];
        if (!tc_crease_loads(r, &k, &resist, &ge, e)) { /* the valley opens: on the face it leans on */
            cc_geom G;
            geom(r, &k.A, r->p, r->v, &G);
            *c = dot3(G.gt, (double[3]){k.axis ? 1 : 0, k.axis ? 0 : 1, 0}) < 0 ? k.A : k.B;
            return 1;
        }
        if (r->res->n_steps++ >= r->s->max_steps) {
            tc_finish(r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
            return 0;
        }
        double u = dot3(r->v, e), U = fabs(u);
        int dir = u > 0 ? 1 : u < 0 ? -1 : 0;
        if (dir == 0) {
            if (fabs(ge) <= resist) {
                tc_stop_here(r);
                return 0;
            }
            dir = ge > 0 ? 1 : -1;
        }
        double A = (ge * dir - resist) * inv, pos = r->p[k.axis], lo = k.axis ? k.A.P.yj : k.A.P.xi;
        double hi = k.axis ? k.A.y1 : k.A.x1, ea = fabs(e[k.axis]);
        double d = (dir > 0 ? hi - pos : pos - lo) / ea;
        double tau_stop = A < 0 ? U / -A : INFINITY, tau_end = INFINITY;
        if (d <= 0)
            tau_end = 0;
        else if (A == 0)
            tau_end = U > 0 ? d / U : INFINITY;
        else if (U * U + 2 * A * d >= 0)
            tau_end = 2 * d / (U + sqrt(U * U + 2 * A * d));
        double tau = tc_fmin(tau_stop, tau_end), a[3], zero[3] = {0, 0, 0}, scale;
        if (tau > 0 || U > 0)
            idle = 0;
        else if (idle >= 4) { /* at rest at a node that every segment pulls it back to: a pit */
            tc_stop_here(r);
            return 0;
        }
        for (int q = 0; q < 3; q++)
            r->v[q] = U * dir * e[q], a[q] = A * dir * e[q];
        terrain_piece_outcome o = tc_emit(r, &tau, a, &scale, NULL);
        tc_advance(r, tau, a, zero);
        r->p[k.axis ? 0 : 1] = k.axis ? k.A.x1 : k.A.y1; /* exactly on the edge */
        if (o == TERRAIN_PIECE_STOPPED) {
            tc_stop_here(r);
            return 0;
        }
        if (is_sphere(r)) {
            cc_geom G;
            geom(r, &k.A, r->p, r->v, &G);
            tc_set_rolling(r, &G, 0);
        }
        if (o == TERRAIN_PIECE_SLOWED) {
            for (int q = 0; q < 3; q++)
                r->v[q] *= scale, r->omega[q] *= scale;
            continue;
        }
        if (tau_stop <= tau_end) {
            memset(r->v, 0, sizeof r->v), memset(r->omega, 0, sizeof r->omega);
            continue;
        }
        r->p[k.axis] = dir > 0 ? hi : lo;
        r->p[2] = height(&k.A, r->p[0], r->p[1]);
        if (!crease_shift(r, &k, dir)) {
            tc_finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
            return 0;
        }
    }
}
