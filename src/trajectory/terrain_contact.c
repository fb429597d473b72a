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
 * above the next patch's tangent plane (convex) launches the block; else
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
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <string.h>

#define CC_TOL 5e-4      /* relative error allowed per numerical step (velocity); with the steps of two
                          * cells, 5e-4 keeps every case of test_across_fall_line closer to RK4 than
                          * 1e-3 with steps of one cell did */
#define CC_CELL_FRAC 2.0 /* a numerical step covers at most this share of a cell (and is cut at its edge) */
#define CC_DV_FRAC 0.25 /* and changes the velocity by at most this share of the speed */

typedef struct {
    long i, j;
    terrain_patch P;
    int planar;              /* d = 0 within round-off */
    size_t mat;              /* its material */
    double mu, mur;          /* tan(friction angle), rolling resistance of its material */
    double x1, y1;           /* the north-east corner */
} cc_cell;

typedef struct {
    double n[3], gt[3];      /* unit normal; gravity along the surface [m/s^2] */
    double N, an;            /* normal load per unit mass; normal acceleration kappa / |grad F| */
    double fx, fy;           /* slopes */
    double w;                /* 1 / |grad F| */
} cc_geom;

typedef struct {
    double tau, a[3], dw[3]; /* duration, acceleration, spin rate of the piece */
    int ex, ey;              /* the edge it ends on: -1 west / south, +1 east / north */
    int rest;                /* it ends at rest */
    int slip_end;            /* a sliding sphere's slip ends */
    double work;             /* lower bound of the resistance's work per unit mass (numerical steps) */
} cc_step;

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

static double kratio(const terrain_run *r) { return r->inertia / (r->mass * r->radius * r->radius); }
static int is_sphere(const terrain_run *r) { return r->s->sphere && r->radius > 0 && r->inertia > 0; }

/* Cell (i, j) into *c; its material's friction from *hint when the same
 * (NULL: none; a cell next to the current one mostly shares its material, and
 * tan is a tenth of a step's time).  0 outside the DEM or on no-data. */
static int cell_load_near(const terrain_run *r, long i, long j, cc_cell *c, const cc_cell *hint)
{
    const rf_terrain *t = r->dem;
    if (i < 0 || j < 0 || (size_t)i + 1 >= t->nx || (size_t)j + 1 >= t->ny || !t->valid[(size_t)j * (t->nx - 1) + (size_t)i])
        return 0;
    c->i = i, c->j = j;
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
        c->mu = tan(m->friction_angle), c->mur = m->rolling_resistance;
    }
    c->x1 = c->P.xi + t->dx, c->y1 = c->P.yj + t->dy;
    return 1;
}

static int cell_load(const terrain_run *r, long i, long j, cc_cell *c) { return cell_load_near(r, i, j, c, NULL); }

static double height(const cc_cell *c, double x, double y)
{
    double X = x - c->P.xi, Y = y - c->P.yj;
    return c->P.a + c->P.b * X + c->P.c * Y + c->P.d * X * Y;
}

/* The geometry at p that does not depend on the velocity (slopes, normal, gravity along the surface). */
static void geom_at(const terrain_run *r, const cc_cell *c, const double p[3], cc_geom *G)
{
    double X = p[0] - c->P.xi, Y = p[1] - c->P.yj;
    double fx = c->P.b + c->P.d * Y, fy = c->P.c + c->P.d * X, q = 1 + fx * fx + fy * fy, w = 1 / sqrt(q);
    G->fx = fx, G->fy = fy, G->w = w;
    G->n[0] = -fx * w, G->n[1] = -fy * w, G->n[2] = w;
    G->gt[0] = -r->g * fx / q, G->gt[1] = -r->g * fy / q, G->gt[2] = -r->g * (fx * fx + fy * fy) / q;
}

/* The normal load and acceleration at velocity v, on the geometry of geom_at. */
static void geom_load(const terrain_run *r, const cc_cell *c, const double v[3], cc_geom *G)
{
    double kappa = 2 * c->P.d * v[0] * v[1];
    G->N = (r->g + kappa) * G->w;
    G->an = kappa * G->w;
}

static void geom(const terrain_run *r, const cc_cell *c, const double p[3], const double v[3], cc_geom *G)
{
    geom_at(r, c, p, G);
    geom_load(r, c, v, G);
}

/* The 2D rule: a sphere rolls where rolling needs no more friction than mu N. */
static int rolls(const terrain_run *r, const cc_cell *c, const cc_geom *G)
{
    if (!is_sphere(r))
        return 0;
    double k = kratio(r);
    return norm3(G->gt) * k / (1 + k) <= c->mu * G->N;
}

static void finish(terrain_run *r, rf_traj_state state, rf_traj_event_kind kind)
{
    r->phase = TERRAIN_DONE;
    r->res->state = state;
    memcpy(r->res->end, r->p, sizeof r->res->end);
    r->res->t_end = r->t;
    terrain_event(r, kind, 0);
}

static void stop_here(terrain_run *r)
{
    memset(r->v, 0, sizeof r->v);
    memset(r->omega, 0, sizeof r->omega);
    finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
}

static void launch(terrain_run *r)
{
    r->phase = TERRAIN_FLY;
    r->from_impact = 0;
    terrain_event(r, RF_EV_LAUNCH, 1);
}

/* The cell holding (x, y) that the horizontal direction (hx, hy) leads into. */
static int pick_cell(const terrain_run *r, double x, double y, double hx, double hy, cc_cell *c)
{
    const rf_terrain *t = r->dem;
    double h = hypot(hx, hy), eps = 1e-9 * fmin(t->dx, t->dy), u, v;
    size_t i, j;
    if (h > 0 && terrain_cell_of(t, x + eps * hx / h, y + eps * hy / h, &i, &j, &u, &v))
        return cell_load(r, (long)i, (long)j, c);
    if (terrain_cell_of(t, x, y, &i, &j, &u, &v))
        return cell_load(r, (long)i, (long)j, c);
    return 0;
}

/* Put the state on the surface of c: z on the patch, v in its tangent plane;
 * the geometry there in *G (geom_at: its load is not set). */
static void onto_surface(terrain_run *r, const cc_cell *c, cc_geom *G)
{
    r->p[2] = height(c, r->p[0], r->p[1]);
    geom_at(r, c, r->p, G);
    double vn = dot3(r->v, G->n);
    for (int k = 0; k < 3; k++)
        r->v[k] -= vn * G->n[k];
}

/* Mechanical energy per unit mass [J/kg]. */
static double energy(const terrain_run *r)
{
    double kin = 0.5 * dot3(r->v, r->v);
    if (r->mass > 0)
        kin += 0.5 * r->inertia / r->mass * dot3(r->omega, r->omega);
    return kin + r->g * r->p[2];
}

/* ---- the acceleration and the steps ---- */

/* Unit direction of motion: along v, or from rest along gravity (0 if neither). */
static void motion_dir(const double v[3], const double gt[3], double e[3])
{
    double s = norm3(v), gs = norm3(gt);
    for (int k = 0; k < 3; k++)
        e[k] = s > 0 ? v[k] / s : gs > 0 ? gt[k] / gs : 0;
}

/* Direction of the slip of a sliding block's contact point (2D friction_dir). */
static void slip_dir(const terrain_run *r, const cc_geom *G, const double v[3], const double w[3], double e[3])
{
    if (!is_sphere(r)) {
        motion_dir(v, G->gt, e);
        return;
    }
    double nw[3], s[3];
    cross3(G->n, w, nw);
    for (int k = 0; k < 3; k++)
        s[k] = v[k] + r->radius * nw[k];
    double ss = norm3(s);
    if (ss <= 1e-12 * (norm3(v) + r->radius * norm3(w)))
        motion_dir((const double[3]){0, 0, 0}, G->gt, e); /* no slip: it grows the way gravity pulls */
    else
        for (int k = 0; k < 3; k++)
            e[k] = s[k] / ss;
}

/* The acceleration and spin rate at velocity v and spin w on the geometry G (load set). */
static void accel_g(const terrain_run *r, const cc_cell *c, const cc_geom *Gp, const double v[3], const double w[3],
                    int rolling, double a[3], double dw[3])
{
    const cc_geom G = *Gp;
    double N = G.N > 0 ? G.N : 0, e[3];
    memset(dw, 0, 3 * sizeof *dw);
    if (rolling) {
        double inv = 1 / (1 + kratio(r));
        motion_dir(v, G.gt, e);
        for (int k = 0; k < 3; k++)
            a[k] = (G.gt[k] - c->mur * N * e[k]) * inv + G.an * G.n[k];
        return;
    }
    slip_dir(r, &G, v, w, e);
    for (int k = 0; k < 3; k++)
        a[k] = G.gt[k] - c->mu * N * e[k] + G.an * G.n[k];
    if (is_sphere(r)) {
        double ne[3], f = c->mu * N * r->mass * r->radius / r->inertia;
        cross3(G.n, e, ne);
        for (int k = 0; k < 3; k++)
            dw[k] = f * ne[k];
    }
}

static void accel(const terrain_run *r, const cc_cell *c, const double p[3], const double v[3], const double w[3],
                  int rolling, double a[3], double dw[3])
{
    cc_geom G;
    geom(r, c, p, v, &G);
    accel_g(r, c, &G, v, w, rolling, a, dw);
}

/* The real roots of c2 t^2 + c1 t + c0 (NR 5.6); their number. */
static int roots2(double c2, double c1, double c0, double t[2])
{
    if (c2 == 0) {
        if (c1 == 0)
            return 0;
        t[0] = -c0 / c1;
        return 1;
    }
    double disc = c1 * c1 - 4 * c2 * c0;
    if (disc < 0)
        return 0;
    double q = -0.5 * (c1 + copysign(sqrt(disc), c1));
    t[0] = q / c2;
    t[1] = q != 0 ? c0 / q : t[0];
    return 2;
}

/* First tau in [0, h] at which x0 + v tau + a tau^2 / 2 passes `bound`
 * moving outwards (out = +1: increasing), or INFINITY. */
static double pass_time(double x0, double v, double a, double bound, int out, double h)
{
    double c0 = x0 - bound;
    if (c0 * out >= 0 && (v * out > 0 || (v == 0 && a * out > 0)))
        return 0; /* on (or past) it, leaving */
    /* the farthest the path gets towards the bound over [0, h] (ends, apex):
     * clearly short of it, no root to look for (the roots cost a square root) */
    double far = fmax(c0 * out, (c0 + v * h + 0.5 * a * h * h) * out), ta = a != 0 ? -v / a : -1;
    if (ta > 0 && ta < h)
        far = fmax(far, (c0 - 0.5 * v * v / a) * out);
    if (h < INFINITY && far < -1e-9 * (1 + fabs(bound)))
        return INFINITY; /* (an exact step may be unbounded: h infinite) */
    double t[2], best = INFINITY;
    int n = roots2(0.5 * a, v, c0, t);
    for (int k = 0; k < n; k++)
        if (t[k] >= 0 && t[k] <= h && (v + a * t[k]) * out > 0 && t[k] < best)
            best = t[k];
    return best;
}

/* Cut the step at the first edge of c its path p + v tau + a tau^2 / 2 meets. */
static void cut_at_edge(const terrain_run *r, const cc_cell *c, const double a[3], cc_step *st)
{
    const double *p = r->p, *v = r->v;
    double tw = pass_time(p[0], v[0], a[0], c->P.xi, -1, st->tau), te = pass_time(p[0], v[0], a[0], c->x1, 1, st->tau);
    double ts = pass_time(p[1], v[1], a[1], c->P.yj, -1, st->tau), tn = pass_time(p[1], v[1], a[1], c->y1, 1, st->tau);
    double tx = fmin(tw, te), ty = fmin(ts, tn), tmin = fmin(tx, ty);
    if (!(tmin <= st->tau))
        return;
    st->tau = tmin, st->rest = st->slip_end = 0;
    st->ex = tx == tmin ? (tw <= te ? -1 : 1) : 0;
    st->ey = ty == tmin ? (ts <= tn ? -1 : 1) : 0;
}

/* The exact step on a plane, the motion along the line e at speed U >= 0 (0 if it does not apply). */
static int exact_step(terrain_run *r, const cc_cell *c, const cc_geom *G, int rolling, cc_step *st)
{
    if (!c->planar)
        return 0;
    double e[3], U = norm3(r->v), ge, side[3], f = 1;
    motion_dir(r->v, G->gt, e);
    ge = dot3(G->gt, e);
    for (int k = 0; k < 3; k++)
        side[k] = G->gt[k] - ge * e[k];
    if (norm3(e) == 0 || norm3(side) > 1e-9 * norm3(G->gt))
        return 0;
    double A, tau_slip = INFINITY, sigma = 0, k = is_sphere(r) ? kratio(r) : 0;
    if (rolling)
        A = (ge - c->mur * G->N) / (1 + k);
    else if (!is_sphere(r))
        A = ge - c->mu * G->N;
    else { /* a sliding sphere: only with its slip along e */
        double nw[3], s[3];
        cross3(G->n, r->omega, nw);
        for (int q = 0; q < 3; q++)
            s[q] = r->v[q] + r->radius * nw[q];
        sigma = dot3(s, e);
        for (int q = 0; q < 3; q++)
            s[q] -= sigma * e[q];
        if (norm3(s) > 1e-9 * (U + r->radius * norm3(r->omega)))
            return 0;
        int slips = fabs(sigma) > 1e-12 * (U + r->radius * norm3(r->omega));
        f = slips ? (sigma > 0 ? 1 : -1) : (ge > 0 ? 1 : -1);
        A = ge - f * c->mu * G->N;
        double rate = ge - f * c->mu * G->N * (1 + 1 / k);
        if (slips && sigma * rate < 0)
            tau_slip = -sigma / rate;
    }
    double tau_stop = A < 0 && U > 0 ? U / -A : INFINITY;
    memset(st, 0, sizeof *st);
    st->tau = fmin(tau_stop, tau_slip);
    for (int q = 0; q < 3; q++)
        st->a[q] = A * e[q];
    if (is_sphere(r) && !rolling) {
        double ne[3], w = f * c->mu * G->N * r->mass * r->radius / r->inertia;
        cross3(G->n, e, ne);
        for (int q = 0; q < 3; q++)
            st->dw[q] = w * ne[q];
    }
    st->rest = tau_stop < INFINITY && tau_stop <= tau_slip;
    st->slip_end = tau_slip < tau_stop;
    for (int q = 0; q < 3; q++) /* the speed along the line (v may carry round-off across it) */
        r->v[q] = U * e[q];
    cut_at_edge(r, c, st->a, st);
    return 1;
}

/* A sliding sphere: the time at which its slip s = v + r n x omega, changing
 * at ds/dt = a + r n x d omega/dt, vanishes (INFINITY if it does not shrink). */
static double slip_end_time(const terrain_run *r, const cc_geom *Gp, int rolling, const double a[3],
                            const double dw[3])
{
    if (rolling || !is_sphere(r))
        return INFINITY;
    const cc_geom G = *Gp;
    double nw[3], ndw[3], s[3], ds[3];
    cross3(G.n, r->omega, nw);
    cross3(G.n, dw, ndw);
    for (int k = 0; k < 3; k++)
        s[k] = r->v[k] + r->radius * nw[k], ds[k] = a[k] + r->radius * ndw[k];
    double sd = dot3(s, ds);
    if (norm3(s) <= 1e-12 * (norm3(r->v) + r->radius * norm3(r->omega)))
        return INFINITY; /* no slip (round-off): it grows the way gravity pulls */
    return sd < 0 ? dot3(s, s) / -sd : INFINITY;
}

/* One Heun step with error control from the current state; G0: the geometry
 * at the current point (geom_at). */
static void numeric_step(const terrain_run *r, const cc_cell *c, const cc_geom *G0, int rolling, cc_step *st)
{
    double a0[3], dw0[3], a1[3], dw1[3], ps[3], vs[3], ws[3];
    cc_geom G = *G0;
    geom_load(r, c, r->v, &G);
    accel_g(r, c, &G, r->v, r->omega, rolling, a0, dw0);
    double sp = norm3(r->v), am = norm3(a0), cell = fmin(r->dem->dx, r->dem->dy);
    double h = am > 0 ? sqrt(2 * CC_CELL_FRAC * cell / am) : INFINITY;
    if (sp > 0)
        h = fmin(h, CC_CELL_FRAC * cell / sp);
    if (am > 0)
        h = fmin(h, CC_DV_FRAC * fmax(sp, 0.05 * sqrt(r->g * cell)) / am);
    double va0 = dot3(r->v, a0);
    if (va0 < 0 && sp * sp / -va0 <= h) { /* it comes to rest within the step: one Euler step there */
        memset(st, 0, sizeof *st);
        st->tau = sp * sp / -va0, st->rest = 1;
        memcpy(st->a, a0, sizeof st->a);
        memcpy(st->dw, dw0, sizeof st->dw);
        cut_at_edge(r, c, st->a, st);
        return;
    }
    double tslip = slip_end_time(r, &G, rolling, a0, dw0);
    if (tslip <= h) { /* a sliding sphere's slip ends within the step: one Euler step there */
        memset(st, 0, sizeof *st);
        st->tau = tslip, st->slip_end = 1;
        memcpy(st->a, a0, sizeof st->a);
        memcpy(st->dw, dw0, sizeof st->dw);
        cut_at_edge(r, c, st->a, st);
        return;
    }
    for (int tries = 0;; tries++) {
        for (int k = 0; k < 3; k++) {
            ps[k] = r->p[k] + r->v[k] * h + 0.5 * a0[k] * h * h;
            vs[k] = r->v[k] + a0[k] * h;
            ws[k] = r->omega[k] + dw0[k] * h;
        }
        accel(r, c, ps, vs, ws, rolling, a1, dw1);
        double d[3] = {a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
        double err = 0.5 * norm3(d) * h, tol = CC_TOL * (sp + r->g * h);
        if (err <= tol || tries >= 30)
            break;
        h *= fmax(0.2, 0.9 * sqrt(tol / err));
    }
    memset(st, 0, sizeof *st);
    st->tau = h;
    for (int k = 0; k < 3; k++)
        st->a[k] = 0.5 * (a0[k] + a1[k]), st->dw[k] = 0.5 * (dw0[k] + dw1[k]);
    double va = dot3(r->v, st->a), aa = dot3(st->a, st->a);
    if (va < 0) { /* decelerating: at rest where the speed nearly vanishes within the step */
        double ts = -va / aa, vm[3];
        for (int k = 0; k < 3; k++)
            vm[k] = r->v[k] + st->a[k] * ts;
        if (ts <= h && norm3(vm) <= 0.1 * sp)
            st->tau = ts, st->rest = 1;
    }
    cut_at_edge(r, c, st->a, st);
}

/* ---- pieces and the state ---- */

/* Emit the piece over *tau (shortened to a barrier's cut); its outcome. */
static terrain_piece_outcome emit(terrain_run *r, double *tau, const double a[3], double *scale)
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

static void advance(terrain_run *r, double tau, const double a[3], const double dw[3])
{
    for (int k = 0; k < 3; k++) {
        r->p[k] += r->v[k] * tau + 0.5 * a[k] * tau * tau;
        r->v[k] += a[k] * tau;
        r->omega[k] += dw[k] * tau;
    }
    r->t += tau;
}

/* Roll: omega = n x v / r (after the impulse that ends a slip). */
static void set_rolling(terrain_run *r, const cc_geom *G, int impulse)
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
static void cap_energy(terrain_run *r, double e0, double work)
{
    double kin = energy(r) - r->g * r->p[2], allowed = e0 - work - r->g * r->p[2];
    if (kin <= allowed)
        return;
    double s = allowed > 0 && kin > 0 ? sqrt(allowed / kin) : 0;
    for (int k = 0; k < 3; k++)
        r->v[k] *= s, r->omega[k] *= s;
}

/* ---- the valley line: motion along an edge pressed into both faces ---- */

typedef struct {
    cc_cell A, B;            /* the two cells, A west / south of B */
    int axis;                /* 0: the edge runs along x (y = const), 1: along y (x = const) */
} cc_crease;

/* Normal loads per unit mass of both faces at the current point (static:
 * the edge is straight) and their sum times friction; 0 if the edge is not
 * a concave valley line pressed by both. */
static int crease_loads(const terrain_run *r, const cc_crease *k, double *resist, double *along_g, double e[3])
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
    NA = fmax(NA, 0), NB = fmax(NB, 0);
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
    if (!cell_load_near(r, k->A.i + di, k->A.j + dj, &n.A, &k->A) ||
        !cell_load_near(r, k->B.i + di, k->B.j + dj, &n.B, &k->B))
        return 0;
    *k = n;
    return 1;
}

/* Move along the valley line; 1 when the block leaves it into cell *c (state
 * updated), 0 when the phase ended. */
static int crease_run(terrain_run *r, cc_crease k, cc_cell *c)
{
    double inv = is_sphere(r) ? 1 / (1 + kratio(r)) : 1;
    for (int idle = 0;; idle++) {
        double resist, ge, e[3];
        if (!crease_loads(r, &k, &resist, &ge, e)) { /* the valley opens: on the face it leans on */
            cc_geom G;
            geom(r, &k.A, r->p, r->v, &G);
            *c = dot3(G.gt, (double[3]){k.axis ? 1 : 0, k.axis ? 0 : 1, 0}) < 0 ? k.A : k.B;
            return 1;
        }
        if (r->res->n_steps++ >= r->s->max_steps) {
            finish(r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
            return 0;
        }
        double u = dot3(r->v, e), U = fabs(u);
        int dir = u > 0 ? 1 : u < 0 ? -1 : 0;
        if (dir == 0) {
            if (fabs(ge) <= resist) {
                stop_here(r);
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
        double tau = fmin(tau_stop, tau_end), a[3], zero[3] = {0, 0, 0}, scale;
        if (tau > 0 || U > 0)
            idle = 0;
        else if (idle >= 4) { /* at rest at a node that every segment pulls it back to: a pit */
            stop_here(r);
            return 0;
        }
        for (int q = 0; q < 3; q++)
            r->v[q] = U * dir * e[q], a[q] = A * dir * e[q];
        terrain_piece_outcome o = emit(r, &tau, a, &scale);
        advance(r, tau, a, zero);
        r->p[k.axis ? 0 : 1] = k.axis ? k.A.x1 : k.A.y1; /* exactly on the edge */
        if (o == TERRAIN_PIECE_STOPPED) {
            stop_here(r);
            return 0;
        }
        if (is_sphere(r)) {
            cc_geom G;
            geom(r, &k.A, r->p, r->v, &G);
            set_rolling(r, &G, 0);
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
            finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
            return 0;
        }
    }
}

/* ---- rest and edges ---- */

/* Which sides of c the point lies on (within round-off). */
static void on_sides(const terrain_run *r, const cc_cell *c, int *sx, int *sy)
{
    double tol = 1e-9 * fmin(r->dem->dx, r->dem->dy);
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
            if ((a || b) && cell_load(r, c->i + a * sx, c->j + b * sy, &cand[n]))
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
        if (!cell_load(r, ai, aj, &k.A) || !cell_load(r, ai + axis, aj + !axis, &k.B))
            continue;
        double resist, ge, e[3];
        if (crease_loads(r, &k, &resist, &ge, e) && fabs(ge) > resist)
            return crease_run(r, k, c) ? 2 : 0;
    }
    stop_here(r);
    return 0;
}

/* At the edge (ex, ey) of c after a step: the next cell, launch, kink,
 * valley line or exit.  1 to go on in *c, 0 if the phase ended. */
static int cross_edge(terrain_run *r, cc_cell *c, int ex, int ey, const cc_geom *GAp)
{
    cc_cell b;
    if (ex)
        r->p[0] = ex > 0 ? c->x1 : c->P.xi;
    if (ey)
        r->p[1] = ey > 0 ? c->y1 : c->P.yj;
    if (!cell_load_near(r, c->i + ex, c->j + ey, &b, c)) {
        finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
        return 0;
    }
    cc_geom GB;
    const cc_geom GA = *GAp;
    geom_at(r, &b, r->p, &GB);
    double sp = norm3(r->v), vn = dot3(r->v, GB.n);
    if (vn > 1e-9 * sp) { /* the velocity points above the new patch: convex */
        launch(r);
        return 0;
    }
    for (int k = 0; k < 3; k++)
        r->v[k] -= vn * GB.n[k]; /* concave: the part into the new patch is lost */
    double m[2] = {(double)ex, (double)ey}, mm = ex && ey ? sqrt(2.0) : 1.0;
    double sB = (GB.fx * m[0] + GB.fy * m[1]) / mm, sA = (GA.fx * m[0] + GA.fy * m[1]) / mm;
    double away = (r->v[0] * m[0] + r->v[1] * m[1]) / mm * sqrt(1 + sB * sB);
    cc_cell a = *c;
    *c = b;
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
        if (crease_loads(r, &k, &resist, &ge, e)) {
            double u = dot3(r->v, e);
            for (int q = 0; q < 3; q++)
                r->v[q] = u * e[q];
            return crease_run(r, k, c);
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
    terrain_piece_outcome o = emit(r, &tau, st.a, &scale);
    int cut = tau < st.tau;
    double p0[3];
    memcpy(p0, r->p, sizeof p0);
    advance(r, tau, st.a, st.dw);
    if (!cut && st.ex)
        r->p[0] = st.ex > 0 ? c->x1 : c->P.xi;
    if (!cut && st.ey)
        r->p[1] = st.ey > 0 ? c->y1 : c->P.yj;
    r->p[0] = fmin(fmax(r->p[0], c->P.xi), c->x1), r->p[1] = fmin(fmax(r->p[1], c->P.yj), c->y1);
    cc_geom G1;
    onto_surface(r, c, &G1);
    if (o == TERRAIN_PIECE_STOPPED) {
        stop_here(r);
        return 0;
    }
    if (!cut && st.rest)
        memset(r->v, 0, sizeof r->v);
    geom_load(r, c, r->v, &G1);
    if (rolling || (!cut && st.slip_end))
        set_rolling(r, &G1, 0);
    if (!exact) {
        double d[3] = {r->p[0] - p0[0], r->p[1] - p0[1], r->p[2] - p0[2]};
        double N = fmax(0, fmin(G->N, G1.N));
        double work = is_sphere(r) && !rolling ? 0 : (rolling ? c->mur : c->mu) * N * norm3(d);
        cap_energy(r, e0, work);
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
        finish(r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
        return 0;
    }
    cc_geom G;
    geom(r, c, r->p, r->v, &G);
    if (G.N <= 0) {
        launch(r);
        return 0;
    }
    int rolling = rolls(r, c, &G);
    if (rolling)
        set_rolling(r, &G, 1);
    double sp = norm3(r->v);
    if (sp == 0) {
        int k = rest_at(r, c);
        if (k != 1)
            return k;
        geom(r, c, r->p, r->v, &G);
        rolling = rolls(r, c, &G);
    }
    cc_step st;
    double e0 = energy(r);
    int exact = exact_step(r, c, &G, rolling, &st);
    if (!exact) {
        double resist = (rolling ? c->mur : c->mu) * G.N;
        if (sp > 0 && sp < r->s->v_stop && norm3(G.gt) <= resist) {
            stop_here(r); /* creeping on ground where it cannot start again */
            return 0;
        }
        numeric_step(r, c, &G, rolling, &st);
    }
    if (!isfinite(st.tau)) {
        stop_here(r);
        return 0;
    }
    return take_step(r, c, &st, &G, exact, rolling, e0);
}

void terrain_contact_run(terrain_run *r)
{
    cc_cell c;
    double hx = r->v[0], hy = r->v[1];
    r->phase = TERRAIN_CONTACT;
    if (!pick_cell(r, r->p[0], r->p[1], hx, hy, &c)) {
        finish(r, RF_TRAJ_EXITED, RF_EV_EXIT);
        return;
    }
    cc_geom G;
    onto_surface(r, &c, &G);
    terrain_event(r, RF_EV_CONTACT, 0);
    double last[3] = {NAN, NAN, NAN};
    for (int idle = 0; r->phase == TERRAIN_CONTACT && !r->nomem;) {
        if (!step_once(r, &c))
            break;
        /* at rest on the same point step after step: every way out leads
         * back (a node or edge where the cells' fall lines meet) */
        int still = r->v[0] == 0 && r->v[1] == 0 && r->v[2] == 0 && !memcmp(last, r->p, sizeof last);
        idle = still ? idle + 1 : 0;
        if (idle >= 8) {
            stop_here(r);
            break;
        }
        memcpy(last, r->p, sizeof last);
    }
}
