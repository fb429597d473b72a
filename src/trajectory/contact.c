/* contact.c - motion in contact with a segment (trajectory_refs.md sec. 2.6).
 * Along the tangent the acceleration is constant between events, so every
 * event time is a closed-form root:
 *   sliding (point block, or a sphere where rolling would need more friction
 *   than mu N):  a = g_t - sgn(s) mu N,             mu = tan(friction_angle)
 *   with s = u - omega r the slip of the contact point (s = u for a block)
 *   rolling (sphere):  a = (g_t - sgn(u) mu_r N) / (1 + k),  k = I/(m r^2) = 2/5
 * with g_t = -g t_y the pull of gravity along t and N = g n_y the normal load
 * per unit mass.  mu_r is the dimensionless rolling-resistance coefficient
 * (resisting force mu_r N, i.e. a lever arm mu_r r): STONE's and CRSP's
 * convention, independent of the block size, so one value per material works
 * for every block.  A sphere that lands with slip is brought to rolling by
 * the friction impulse that conserves angular momentum about the contact
 * point: u' = (u + k r omega)/(1 + k) (energy can only drop).
 * Events: rest (u = 0 and |g_t| within the static resistance), a vertex
 * (convex: launch along the old tangent; concave: keep the component of the
 * velocity along the new segment, a plastic kink, and rest in a hollow or a
 * notch; a wall that cannot carry contact: an impact), the end of a sliding
 * sphere's slip, a collector line, a barrier. */
#include "trajectory/traj_internal.h"

#include <math.h>

typedef struct {
    int rolling;
    double gt, N, resist; /* resist: |acceleration| from friction or rolling resistance */
    double inv;           /* 1/(1+k) rolling, 1 sliding */
} contact_law;

static contact_law law_on(const traj_run *r, const traj_segment *g)
{
    const rf_traj_material *m = &r->s->materials[g->material];
    contact_law L;
    L.gt = -r->g * g->ty;
    L.N = r->g * g->ny;
    double mu = tan(m->friction_angle);
    double k = r->s->sphere ? r->inertia / (r->mass * r->radius * r->radius) : 0;
    L.rolling = r->s->sphere && fabs(L.gt) * k / (1 + k) <= mu * L.N;
    L.inv = L.rolling ? 1 / (1 + k) : 1;
    L.resist = (L.rolling ? m->rolling_resistance : mu) * L.N;
    return L;
}

int traj_contact_rolls(const traj_run *r, size_t k, double *resist)
{
    contact_law L = law_on(r, &r->w->seg[k]);
    *resist = L.resist;
    return L.rolling;
}

/* The motion along g over [0, tau] with acceleration a, for traj_next_crossing. */
typedef struct {
    const traj_segment *g;
    double a, tau;
} contact_path;

static double contact_crossing(const traj_run *r, size_t c, const void *ctx)
{
    const contact_path *p = ctx;
    return traj_first_root(0.5 * p->a * p->g->tx, r->u * p->g->tx, r->x - r->w->col[c].x, p->tau);
}

/* Collectors crossed while moving along g over [0, tau]; 1 if a barrier stopped the block. */
static int contact_collectors(traj_run *r, const traj_segment *g, double a, double tau)
{
    const contact_path path = {g, a, tau};
    for (;;) {
        double tf;
        size_t first = traj_next_crossing(r, contact_crossing, &path, &tf);
        if (first == TRAJ_NONE)
            return 0;
        double ds = r->u * tf + 0.5 * a * tf * tf, v = r->u + a * tf;
        double w = r->s->sphere && r->radius > 0 ? (law_on(r, g).rolling ? v / r->radius : r->omega) : 0;
        int stopped;
        traj_record_crossing(r, first, r->t + tf, r->x + ds * g->tx, r->y + ds * g->ty, v * g->tx, v * g->ty, w,
                             &stopped);
        if (stopped)
            return 1;
    }
}

/* Time to cover distance d >= 0 at speed U >= 0 with acceleration A along the motion. */
static double time_to_cover(double U, double A, double d)
{
    if (d <= 0) /* already there (a block at rest at the end it is pulled to) */
        return 0;
    if (A == 0)
        return U > 0 ? d / U : INFINITY;
    double disc = U * U + 2 * A * d;
    if (disc < 0)
        return INFINITY;
    double den = U + sqrt(disc);
    return den > 0 ? 2 * d / den : INFINITY;
}

/* At the end of segment k moving in direction dir: the next phase. */
static void at_vertex(traj_run *r, size_t k, int dir)
{
    const traj_segment *g = &r->w->seg[k];
    r->x = dir > 0 ? g->bx : g->ax;
    r->y = dir > 0 ? g->by : g->ay;
    r->vx = r->u * g->tx, r->vy = r->u * g->ty;
    size_t j = dir > 0 ? k + 1 : k - 1;
    if (dir < 0 && k == 0)
        j = TRAJ_NONE;
    if (j == TRAJ_NONE || j >= r->w->nseg) { /* off the end of the profile */
        traj_launch(r, k, TRAJ_NONE, RF_EV_LAUNCH);
        return;
    }
    const traj_segment *h = &r->w->seg[j];
    double fx = dir > 0 ? h->bx : h->ax, fy = dir > 0 ? h->by : h->ay;
    double side = g->nx * (fx - r->x) + g->ny * (fy - r->y);
    if (side < -traj_tol(1e-12, fabs(r->x) + fabs(fx), fabs(r->y) + fabs(fy))) { /* convex: the ground drops away */
        traj_launch(r, k, j, RF_EV_LAUNCH);
        return;
    }
    if (h->ny <= 0) { /* a wall ahead: it is hit */
        traj_impact(r, j);
        return;
    }
    double u = r->u * (g->tx * h->tx + g->ty * h->ty); /* concave kink: keep the part along h */
    double away = u * dir, pull = -r->g * h->ty * dir;  /* speed and gravity along h, away from the vertex */
    r->k = j, r->u = u;
    r->vx = u * h->tx, r->vy = u * h->ty;
    /* A hollow: gravity on h pulls back to the vertex and the block is slow; or
     * a notch (sides meeting at 90 deg or less): no velocity is left that
     * leaves the vertex, and none is admissible (both sides push it back). */
    if (pull <= 0 && (away <= 0 || away < r->s->v_stop)) {
        r->vx = r->vy = r->omega = 0;
        traj_finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
        return;
    }
    traj_event(r, RF_EV_VERTEX, 0, 0, 0);
}

/* Friction opposes the slip of the contact point, s = u - omega r: for a
 * block or a rolling sphere that is the direction of motion `dir`; a sliding
 * sphere spinning faster than it moves is pushed forward and spun down.
 * With no slip (it just ended on a slope too steep to roll) the slip grows
 * the way gravity pulls. */
static int friction_dir(const traj_run *r, const contact_law *L, int dir)
{
    if (!r->s->sphere || L->rolling)
        return dir;
    double slip = r->u - r->omega * r->radius;
    if (fabs(slip) <= 1e-12 * (fabs(r->u) + fabs(r->omega * r->radius)))
        return L->gt > 0 ? 1 : -1;
    return slip > 0 ? 1 : -1;
}

/* Sliding sphere: time until the slip reaches zero (ds/dt = g_t - f mu N (1 + 1/k)). */
static double slip_end(const traj_run *r, const contact_law *L, int f)
{
    if (!r->s->sphere || L->rolling)
        return INFINITY;
    double slip = r->u - r->omega * r->radius, k = r->inertia / (r->mass * r->radius * r->radius);
    double rate = L->gt - f * L->resist * (1 + 1 / k);
    if (fabs(slip) <= 1e-12 * (fabs(r->u) + fabs(r->omega * r->radius)) || !(slip * rate < 0))
        return INFINITY;
    return -slip / rate;
}

void traj_contact_step(traj_run *r)
{
    const traj_segment *g = &r->w->seg[r->k];
    if (g->ny <= 0) { /* cannot carry contact: it falls */
        r->vx = r->u * g->tx, r->vy = r->u * g->ty;
        traj_launch(r, r->k, TRAJ_NONE, RF_EV_LAUNCH);
        return;
    }
    contact_law L = law_on(r, g);
    if (L.rolling && fabs(r->omega * r->radius - r->u) > 0) {
        double k = r->inertia / (r->mass * r->radius * r->radius);
        r->u = (r->u + k * r->radius * r->omega) / (1 + k);
    }
    int dir = r->u > 0 ? 1 : r->u < 0 ? -1 : 0;
    if (dir == 0) {
        if (fabs(L.gt) <= L.resist) { /* static: at rest for good */
            r->vx = r->vy = r->omega = 0;
            traj_finish(r, RF_TRAJ_STOPPED, RF_EV_REST);
            return;
        }
        dir = L.gt > 0 ? 1 : -1;
    }
    int f = friction_dir(r, &L, dir);
    double a = (L.gt - f * L.resist) * L.inv;
    double s = g->tx * (r->x - g->ax) + g->ty * (r->y - g->ay);
    double d = dir > 0 ? g->len - s : s;
    double U = fabs(r->u), A = a * dir;
    double tau_v = time_to_cover(U, A, d < 0 ? 0 : d);
    double tau_s = A < 0 ? U / -A : INFINITY;
    double tau_k = slip_end(r, &L, f);
    double tau = fmin(fmin(tau_v, tau_s), tau_k);
    r->vx = r->u * g->tx, r->vy = r->u * g->ty;
    if (L.rolling)
        r->omega = r->u / r->radius;
    traj_event(r, RF_EV_CONTACT, 0, a * g->tx, a * g->ty);
    if (!isfinite(tau)) { /* cannot happen with a finite segment; guard anyway */
        traj_finish(r, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
        return;
    }
    if (contact_collectors(r, g, a, tau))
        return;
    double ds = r->u * tau + 0.5 * a * tau * tau;
    r->t += tau;
    r->x += ds * g->tx, r->y += ds * g->ty;
    if (r->s->sphere && !L.rolling) /* sliding sphere: friction spins it, dw/dt = f mu N m r / I */
        r->omega += f * (L.resist * r->mass * r->radius / r->inertia) * tau;
    if (tau_k < fmin(tau_v, tau_s)) { /* the slip ends: next step with the new friction */
        r->u += a * tau;
        r->omega = r->u / r->radius;
        return;
    }
    if (tau_s <= tau_v) {
        r->u = 0;
        r->vx = r->vy = 0;
        if (L.rolling)
            r->omega = 0;
        return; /* next step: the static test */
    }
    r->u += a * tau;
    if (L.rolling)
        r->omega = r->u / r->radius;
    at_vertex(r, r->k, dir);
}
