/* terrain_contact_step.c - one step of the contact phase (terrain_contact.c):
 * the acceleration (sliding, rolling, friction spin), the exact step on a
 * plane along the fall line (closed-form roots) and the numerical step
 * with error control, each cut at the first cell edge its path meets. */
#include "trajectory/terrain_contact_internal.h"

#include <math.h>
#include <string.h>

#define CC_TOL 5e-4      /* relative error allowed per numerical step (velocity); with the steps of two
                          * cells, 5e-4 keeps every case of test_across_fall_line closer to RK4 than
                          * 1e-3 with steps of one cell did */
#define CC_CELL_FRAC 2.0 /* a numerical step covers at most this share of a cell (and is cut at its edge) */
#define CC_DV_FRAC 0.25 /* and changes the velocity by at most this share of the speed */

/* ---- the acceleration and the steps ---- */

/* Unit direction of motion: along v, or from rest along gravity (0 if neither). */
static void motion_dir(const double v[3], const double gt[3], double e[3])
{
    double s = norm3(v);
    if (s > 0) {
        for (int k = 0; k < 3; k++)
            e[k] = v[k] / s;
        return;
    }
    double gs = norm3(gt); /* (only from rest: a square root less per call) */
    for (int k = 0; k < 3; k++)
        e[k] = gs > 0 ? gt[k] / gs : 0;
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
    if (v * out <= 0 && a * out <= 0)
        return INFINITY; /* never moving outwards: no root can leave (before the bounds' arithmetic) */
    /* the farthest the path gets towards the bound over [0, h] (ends, apex):
     * clearly short of it, no root to look for (the roots cost a square root) */
    double far = tc_fmax(c0 * out, (c0 + v * h + 0.5 * a * h * h) * out), ta = a != 0 ? -v / a : -1;
    if (ta > 0 && ta < h)
        far = tc_fmax(far, (c0 - 0.5 * v * v / a) * out);
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
    double tx = tc_fmin(tw, te), ty = tc_fmin(ts, tn), tmin = tc_fmin(tx, ty);
    if (!(tmin <= st->tau))
        return;
    st->tau = tmin, st->rest = st->slip_end = 0;
    st->ex = tx == tmin ? (tw <= te ? -1 : 1) : 0;
    st->ey = ty == tmin ? (ts <= tn ? -1 : 1) : 0;
}

/* The exact step on a plane, the motion along the line e at speed U >= 0 (0 if it does not apply). */
int tc_exact_step(terrain_run *r, const cc_cell *c, const cc_geom *G, int rolling, cc_step *st)
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
    st->tau = tc_fmin(tau_stop, tau_slip);
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
void tc_numeric_step(const terrain_run *r, const cc_cell *c, const cc_geom *G0, int rolling, cc_step *st)
{
    double a0[3], dw0[3], a1[3], dw1[3], ps[3], vs[3], ws[3];
    cc_geom G = *G0;
    geom_load(r, c, r->v, &G);
    accel_g(r, c, &G, r->v, r->omega, rolling, a0, dw0);
    double sp = norm3(r->v), am = norm3(a0), cell = tc_fmin(r->dem->dx, r->dem->dy);
    double h = am > 0 ? sqrt(2 * CC_CELL_FRAC * cell / am) : INFINITY;
    if (sp > 0)
        h = tc_fmin(h, CC_CELL_FRAC * cell / sp);
    if (am > 0)
        h = tc_fmin(h, CC_DV_FRAC * tc_fmax(sp, 0.05 * sqrt(r->g * cell)) / am);
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
        h *= tc_fmax(0.2, 0.9 * sqrt(tol / err));
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
