/* terrain_contact_internal.h - what the files of the contact phase share
 * (the equations and the stepping are described in terrain_contact.c):
 *   terrain_contact.c        the phase: steps, cell edges, rest and restart
 *   terrain_contact_cell.c   a cell's patch and material, the point put on the surface
 *   terrain_contact_state.c  the block's state: pieces emitted, advanced, rolling, energy cap, the end
 *   terrain_contact_step.c   the acceleration, the exact step on a plane and the numerical step
 *   terrain_contact_crease.c motion along a valley line (an edge pressed into both faces)
 * The small geometry below is inline: it runs several times per step. */
#ifndef ROCKFUZZ_TERRAIN_CONTACT_INTERNAL_H
#define ROCKFUZZ_TERRAIN_CONTACT_INTERNAL_H

#include "trajectory/terrain_internal.h"

#include <math.h>

typedef struct {
    double n[3], gt[3];      /* unit normal; gravity along the surface [m/s^2] */
    double N, an;            /* normal load per unit mass; normal acceleration kappa / |grad F| */
    double fx, fy;           /* slopes */
    double w;                /* 1 / |grad F| */
} cc_geom;

typedef struct {
    long i, j;
    terrain_patch P;
    int planar;              /* d = 0 within round-off */
    size_t mat;              /* its material */
    double mu, mur;          /* tan(friction angle), rolling resistance of its material */
    double x1, y1;           /* the north-east corner */
    int has_g;               /* G holds the velocity-free geometry (geom_at) at the point gp */
    double gp[3];
    cc_geom G;
} cc_cell;

typedef struct {
    double tau, a[3], dw[3]; /* duration, acceleration, spin rate of the piece */
    int ex, ey;              /* the edge it ends on: -1 west / south, +1 east / north */
    int rest;                /* it ends at rest */
    int slip_end;            /* a sliding sphere's slip ends */
    double work;             /* lower bound of the resistance's work per unit mass (numerical steps) */
} cc_step;

/* ---- the valley line: motion along an edge pressed into both faces ---- */

typedef struct {
    cc_cell A, B;            /* the two cells, A west / south of B */
    int axis;                /* 0: the edge runs along x (y = const), 1: along y (x = const) */
} cc_crease;

/* fmin and fmax with the library's results (NaN: the other argument), inline. */
static inline double tc_fmin(double a, double b) { return a < b || isnan(b) ? a : b; }
static inline double tc_fmax(double a, double b) { return a > b || isnan(b) ? a : b; }

static inline double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static inline void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double kratio(const terrain_run *r) { return r->inertia / (r->mass * r->radius * r->radius); }
static inline int is_sphere(const terrain_run *r) { return r->s->sphere && r->radius > 0 && r->inertia > 0; }

static inline double height(const cc_cell *c, double x, double y)
{
    double X = x - c->P.xi, Y = y - c->P.yj;
    return c->P.a + c->P.b * X + c->P.c * Y + c->P.d * X * Y;
}

/* The geometry at p that does not depend on the velocity (slopes, normal, gravity along the surface). */
static inline void geom_at(const terrain_run *r, const cc_cell *c, const double p[3], cc_geom *G)
{
    double X = p[0] - c->P.xi, Y = p[1] - c->P.yj;
    double fx = c->P.b + c->P.d * Y, fy = c->P.c + c->P.d * X, q = 1 + fx * fx + fy * fy, w = 1 / sqrt(q);
    G->fx = fx, G->fy = fy, G->w = w;
    G->n[0] = -fx * w, G->n[1] = -fy * w, G->n[2] = w;
    G->gt[0] = -r->g * fx / q, G->gt[1] = -r->g * fy / q, G->gt[2] = -r->g * (fx * fx + fy * fy) / q;
}

/* The normal load and acceleration at velocity v, on the geometry of geom_at. */
static inline void geom_load(const terrain_run *r, const cc_cell *c, const double v[3], cc_geom *G)
{
    double kappa = 2 * c->P.d * v[0] * v[1];
    G->N = (r->g + kappa) * G->w;
    G->an = kappa * G->w;
}

/* geom_at at the point p of c, from the cell's cache when it holds that point (the same bits). */
static inline void geom_at_cached(const terrain_run *r, const cc_cell *c, const double p[3], cc_geom *G)
{
    if (c->has_g && c->gp[0] == p[0] && c->gp[1] == p[1] && c->gp[2] == p[2])
        *G = c->G;
    else
        geom_at(r, c, p, G);
}

/* Keep G (geom_at at p) in c's cache. */
static inline void geom_keep(cc_cell *c, const double p[3], const cc_geom *G)
{
    c->has_g = 1, c->G = *G;
    c->gp[0] = p[0], c->gp[1] = p[1], c->gp[2] = p[2];
}

static inline void geom(const terrain_run *r, const cc_cell *c, const double p[3], const double v[3], cc_geom *G)
{
    geom_at(r, c, p, G);
    geom_load(r, c, v, G);
}

/* The 2D rule: a sphere rolls where rolling needs no more friction than mu N. */
static inline int rolls(const terrain_run *r, const cc_cell *c, const cc_geom *G)
{
    if (!is_sphere(r))
        return 0;
    double k = kratio(r);
    return norm3(G->gt) * k / (1 + k) <= c->mu * G->N;
}

/* terrain_contact_cell.c */
/* Cell (i, j) into *c; its material's friction from *hint when the same
 * (NULL: none).  0 outside the DEM or on no-data. */
int tc_cell_load_near(const terrain_run *r, long i, long j, cc_cell *c, const cc_cell *hint);
int tc_cell_load(const terrain_run *r, long i, long j, cc_cell *c);
/* The cell holding (x, y) that the horizontal direction (hx, hy) leads into; 0 if none. */
int tc_pick_cell(const terrain_run *r, double x, double y, double hx, double hy, cc_cell *c);
/* Put the state on the surface of c: z on the patch, v in its tangent plane;
 * the geometry there in *G (geom_at: its load is not set). */
void tc_onto_surface(terrain_run *r, const cc_cell *c, cc_geom *G);

/* terrain_contact_state.c */
void tc_finish(terrain_run *r, rf_traj_state state, rf_traj_event_kind kind);
void tc_stop_here(terrain_run *r);   /* at rest: v = omega = 0, stopped */
void tc_launch(terrain_run *r);      /* leaves the surface: the flight phase */
double tc_energy(const terrain_run *r); /* mechanical energy per unit mass [J/kg] */
/* Emit the piece over *tau (shortened to a barrier's cut); its outcome.  cell: the cell
 * whose closed square holds the piece's path (NULL: not known). */
terrain_piece_outcome tc_emit(terrain_run *r, double *tau, const double a[3], double *scale, const cc_cell *cell);
void tc_advance(terrain_run *r, double tau, const double a[3], const double dw[3]);
/* Roll: omega = n x v / r (after the impulse that ends a slip when `impulse`). */
void tc_set_rolling(terrain_run *r, const cc_geom *G, int impulse);
/* After a numerical step: no energy gained beyond e0 minus the work [J/kg]. */
void tc_cap_energy(terrain_run *r, double e0, double work);

/* terrain_contact_step.c */
/* The exact step on a plane along the fall line (1), or 0 if it does not apply. */
int tc_exact_step(terrain_run *r, const cc_cell *c, const cc_geom *G, int rolling, cc_step *st);
/* One numerical step with error control from the current state; G0: the geometry at the point. */
void tc_numeric_step(const terrain_run *r, const cc_cell *c, const cc_geom *G0, int rolling, cc_step *st);

/* terrain_contact_crease.c */
/* The valley line's loads (1) or 0 if it is not one pressed by both faces. */
int tc_crease_loads(const terrain_run *r, const cc_crease *k, double *resist, double *along_g, double e[3]);
/* Move along the valley line; 1 when the block leaves it into cell *c, 0 when the phase ended. */
int tc_crease_run(terrain_run *r, cc_crease k, cc_cell *c);

#endif
