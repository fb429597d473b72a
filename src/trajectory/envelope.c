/* envelope.c - envelopes along x of the height above the ground and of the
 * kinetic energy, from every trajectory of a run (rf_traj_envelope).
 *
 * Exact passages: between two events the motion is a parabola (flight) or
 * uniformly accelerated along a segment (contact), so x(d) = x + vx d +
 * ax d^2 / 2 is solved for the first d at which the path reaches each edge
 * x_k; the state there gives the height (y minus the ground's y at x_k) and
 * the energy.  The spin is constant in flight, |v| / r while rolling and
 * grows linearly while a sphere slides (the contact law of contact.c).
 *
 * Bounded memory: per edge, a log histogram of each quantity (relative bin
 * width set by RF_TRAJ_ENVELOPE_ACCURACY, values below a floor in bin 0),
 * the exact maximum and the count of trajectories reaching it.  Counts and
 * maxima merge in any order to the same bits, so the result does not depend
 * on the thread count.  About 3.4 MB per accumulator (161 edges); counts are
 * 32-bit, enough: a run has at most 1e8 samples (traj_yaml.c). */
#include "trajectory/traj_internal.h"
#include "trajectory/block_traj.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define H_TOP 1e4  /* [m] larger heights share the last bin (the max stays exact) */
#define E_TOP 1e13 /* [J] */

typedef struct {
    double floor, gamma, lng; /* bin 0: below floor (value 0); bin i >= 1: [floor gamma^(i-1), floor gamma^i) */
    size_t nb;
} log_bins;

struct traj_env_acc {
    const rf_traj_world *w;
    size_t n;                 /* edges */
    log_bins bh, be;
    double *x, *ground;       /* n each */
    unsigned char *seen;      /* n: reached by the trajectory being added */
    uint64_t *reached;        /* n */
    double *hmax, *emax;      /* n */
    uint32_t *hist;           /* n * (bh.nb + be.nb): height bins then energy bins per edge */
};

static log_bins bins_make(double floor, double top)
{
    double a = RF_TRAJ_ENVELOPE_ACCURACY, g = (1 + a) / (1 - a);
    log_bins b = {floor, g, log(g), 0};
    b.nb = 2 + (size_t)ceil(log(top / floor) / b.lng);
    return b;
}

static size_t bin_of(const log_bins *b, double v)
{
    if (!(v >= b->floor))
        return 0;
    double i = 1 + floor(log(v / b->floor) / b->lng);
    return i < (double)(b->nb - 1) ? (size_t)i : b->nb - 1;
}

/* The value that is within (gamma - 1) / (gamma + 1) = accuracy of every value of bin i. */
static double bin_value(const log_bins *b, size_t i)
{
    return i == 0 ? 0 : b->floor * exp((double)(i - 1) * b->lng) * 2 * b->gamma / (1 + b->gamma);
}

traj_env_acc *traj_env_create(const rf_traj_spec *s, size_t n, const rf_traj_world *w)
{
    traj_env_acc *a = calloc(1, sizeof *a);
    if (!a || n < 2)
        return free(a), NULL;
    a->w = w, a->n = n;
    a->bh = bins_make(RF_TRAJ_ENVELOPE_HEIGHT_FLOOR, H_TOP);
    a->be = bins_make(RF_TRAJ_ENVELOPE_ENERGY_FLOOR, E_TOP);
    a->x = malloc(n * sizeof *a->x), a->ground = malloc(n * sizeof *a->ground);
    a->seen = malloc(n), a->reached = calloc(n, sizeof *a->reached);
    a->hmax = malloc(n * sizeof *a->hmax), a->emax = malloc(n * sizeof *a->emax);
    a->hist = calloc(n * (a->bh.nb + a->be.nb), sizeof *a->hist);
    if (!a->x || !a->ground || !a->seen || !a->reached || !a->hmax || !a->emax || !a->hist) {
        traj_env_free(a);
        return NULL;
    }
    double x0 = s->px[0], x1 = s->px[s->n_points - 1];
    for (size_t k = 0; k < n; k++) {
        a->x[k] = k + 1 < n ? x0 + (x1 - x0) * (double)k / (double)(n - 1) : x1;
        a->ground[k] = traj_ground_y(w, a->x[k], NULL);
        a->hmax[k] = a->emax[k] = -INFINITY;
    }
    return a;
}

void traj_env_free(traj_env_acc *a)
{
    if (!a)
        return;
    free(a->x), free(a->ground), free(a->seen), free(a->reached);
    free(a->hmax), free(a->emax), free(a->hist);
    free(a);
}

/* The segment a contact stretch starting at ev runs on: it holds the point
 * and its tangent is parallel to the acceleration (or the velocity). */
static size_t contact_segment(const rf_traj_world *w, const rf_traj_event *ev)
{
    size_t k;
    traj_ground_y(w, ev->x, &k);
    if (k == TRAJ_NONE)
        return k;
    double dx = ev->ax, dy = ev->ay, tol = traj_tol(1e-9, ev->x, ev->y), best_c = INFINITY;
    if (dx == 0 && dy == 0)
        dx = ev->vx, dy = ev->vy;
    size_t best = TRAJ_NONE;
    for (size_t j = k > 0 ? k - 1 : 0; j <= k + 1 && j < w->nseg; j++) {
        const traj_segment *g = &w->seg[j];
        if (g->ny <= 0 || ev->x < g->xmin - tol || ev->x > g->xmax + tol)
            continue;
        double c = fabs(g->tx * dy - g->ty * dx);
        if (c < best_c)
            best_c = c, best = j;
    }
    return best;
}

typedef struct {
    int rolling;       /* omega = |v| / r */
    double w0, rate;   /* else omega = w0 + rate d */
} spin_model;

static spin_model stretch_spin(const traj_run *r, const rf_traj_event *ev)
{
    spin_model m = {0, ev->omega, 0};
    if (ev->flying || ev->kind != RF_EV_CONTACT || !(r->inertia > 0))
        return m;
    size_t k = contact_segment(r->w, ev);
    double resist;
    if (k == TRAJ_NONE)
        return m;
    if (traj_contact_rolls(r, k, &resist)) {
        m.rolling = 1;
        return m;
    }
    const traj_segment *g = &r->w->seg[k];
    double u = g->tx * ev->vx + g->ty * ev->vy, at = g->tx * ev->ax + g->ty * ev->ay;
    int dir = u > 0 ? 1 : u < 0 ? -1 : at > 0 ? 1 : at < 0 ? -1 : 0;
    m.rate = dir * resist * r->mass * r->radius / r->inertia; /* as contact.c's sliding sphere */
    return m;
}

static void record(traj_env_acc *a, size_t k, double h, double e)
{
    uint32_t *hist = a->hist + k * (a->bh.nb + a->be.nb);
    hist[bin_of(&a->bh, h)]++;
    hist[a->bh.nb + bin_of(&a->be, e)]++;
    a->reached[k]++;
    a->hmax[k] = fmax(a->hmax[k], h);
    a->emax[k] = fmax(a->emax[k], e);
    a->seen[k] = 1;
}

/* The passages of the edges not yet reached during the stretch [0, T] from ev
 * (x_next: where the next event starts, closing rounding gaps); e_rot: a rigid
 * block's rotational energy over the stretch [J] (NAN: a sphere's spin model). */
static void stretch(traj_env_acc *a, const traj_run *r, const rf_traj_event *ev, double T, double x_next,
                    double e_rot)
{
    double xe = ev->x + ev->vx * T + 0.5 * ev->ax * T * T;
    double lo = fmin(ev->x, fmin(xe, x_next)), hi = fmax(ev->x, fmax(xe, x_next));
    double ds = ev->ax != 0 ? -ev->vx / ev->ax : -1;
    if (ds > 0 && ds < T) { /* x turns back inside the stretch */
        double xs = ev->x + ev->vx * ds + 0.5 * ev->ax * ds * ds;
        lo = fmin(lo, xs), hi = fmax(hi, xs);
    }
    double step = (a->x[a->n - 1] - a->x[0]) / (double)(a->n - 1);
    double k0 = ceil((lo - a->x[0]) / step) - 1, k1 = floor((hi - a->x[0]) / step) + 1;
    if (!(k1 >= 0) || !(k0 <= (double)(a->n - 1)))
        return;
    size_t kb = k0 > 0 ? (size_t)k0 : 0, ke = k1 < (double)(a->n - 1) ? (size_t)k1 : a->n - 1;
    int have_spin = 0;
    spin_model m = {0, 0, 0};
    for (size_t k = kb; k <= ke; k++) {
        if (a->seen[k] || a->x[k] < lo || a->x[k] > hi)
            continue;
        double d = traj_first_root(0.5 * ev->ax, ev->vx, ev->x - a->x[k], T);
        if (!isfinite(d)) /* on a rounding gap at either end */
            d = fabs(ev->x - a->x[k]) <= fabs(xe - a->x[k]) ? 0 : T;
        double vx = ev->vx + ev->ax * d, vy = ev->vy + ev->ay * d;
        double y = ev->y + ev->vy * d + 0.5 * ev->ay * d * d, v2 = vx * vx + vy * vy;
        if (isfinite(e_rot)) {
            record(a, k, y - a->ground[k], 0.5 * r->mass * v2 + e_rot);
            continue;
        }
        if (!have_spin)
            m = stretch_spin(r, ev), have_spin = 1;
        double w2 = m.rolling ? v2 / (r->radius * r->radius) : (m.w0 + m.rate * d) * (m.w0 + m.rate * d);
        record(a, k, y - a->ground[k], 0.5 * r->mass * v2 + 0.5 * r->inertia * w2);
    }
}

/* A rigid block's rotational energy at event ev [J]: on a profile its spin is omega about y in space
 * (constant in flight; between the events of a contact stretch, 0.01 s apart, it is taken as at the
 * event), with the inertia of the block's actual shape at orientation q. */
static double block_rot_energy(const rf_block_shape *b, const rf_traj_event *ev)
{
    rf_block_state st = {{0, 0, 0}, {ev->q[0], ev->q[1], ev->q[2], ev->q[3]}, {0, 0, 0}, {0, 0, 0}};
    const double w[3] = {0, ev->omega, 0};
    rf_block_to_body(st.q, w, st.w);
    return rf_block_kinetic_energy(b, &st, NULL);
}

void traj_env_add(traj_env_acc *a, const rf_traj_spec *s, const rf_traj_result *res)
{
    traj_run r;
    memset(&r, 0, sizeof r);
    r.w = a->w, r.s = s, r.g = s->gravity;
    r.mass = traj_spec_mass(s);
    r.radius = s->sphere ? s->radius : 0;
    r.inertia = s->sphere ? 0.4 * r.mass * s->radius * s->radius : 0;
    rf_block_shape b = {0};
    rf_error err;
    int block = s->block_kind && traj_block_shape(s, &b, &err) == RF_OK; /* this sample's shape and mass */
    if (block)
        r.mass = b.mass;
    memset(a->seen, 0, a->n);
    for (size_t q = 0; res->events && q < res->n_events; q++) {
        const rf_traj_event *ev = &res->events[q], *next = q + 1 < res->n_events ? ev + 1 : ev;
        double T = next->t - ev->t;
        stretch(a, &r, ev, T > 0 ? T : 0, next->x, block ? block_rot_energy(&b, ev) : NAN);
    }
    rf_block_shape_free(&b);
}

void traj_env_merge(traj_env_acc *into, const traj_env_acc *from)
{
    size_t nh = into->n * (into->bh.nb + into->be.nb);
    for (size_t i = 0; i < nh; i++)
        into->hist[i] += from->hist[i];
    for (size_t k = 0; k < into->n; k++) {
        into->reached[k] += from->reached[k];
        into->hmax[k] = fmax(into->hmax[k], from->hmax[k]);
        into->emax[k] = fmax(into->emax[k], from->emax[k]);
    }
}

/* Order statistic j (0-based) of the values in histogram h. */
static double order_stat(const uint32_t *h, const log_bins *b, uint64_t j, double max)
{
    uint64_t c = 0;
    for (size_t i = 0; i < b->nb; i++) {
        c += h[i];
        if (c > j)
            return fmin(bin_value(b, i), max);
    }
    return max;
}

/* Hyndman-Fan type 7 percentile p of the n values in h. */
static double quantile(const uint32_t *h, const log_bins *b, uint64_t n, double p, double max)
{
    double r = p * (double)(n - 1);
    uint64_t j = (uint64_t)r;
    double f = r - (double)j, lo = order_stat(h, b, j, max);
    return f > 0 ? lo + f * (order_stat(h, b, j + 1, max) - lo) : lo;
}

void traj_envelope_free(rf_traj_envelope *env)
{
    free(env->x);
    free(env->reached);
    for (int q = 0; q < 3; q++)
        free(env->height[q]), free(env->energy[q]);
    memset(env, 0, sizeof *env);
}

rf_status traj_env_finish(const traj_env_acc *a, rf_traj_envelope *env, rf_error *err)
{
    size_t n = a->n;
    memset(env, 0, sizeof *env);
    env->x = malloc(n * sizeof *env->x), env->reached = malloc(n * sizeof *env->reached);
    int ok = env->x && env->reached;
    for (int q = 0; q < 3; q++) {
        env->height[q] = malloc(n * sizeof *env->height[q]), env->energy[q] = malloc(n * sizeof *env->energy[q]);
        ok = ok && env->height[q] && env->energy[q];
    }
    if (!ok) {
        traj_envelope_free(env);
        return rf_fail(err, RF_ENOMEM, "out of memory for the envelopes");
    }
    env->n_edges = n;
    static const double p[2] = {0.50, 0.95};
    for (size_t k = 0; k < n; k++) {
        const uint32_t *hh = a->hist + k * (a->bh.nb + a->be.nb), *he = hh + a->bh.nb;
        uint64_t m = a->reached[k];
        env->x[k] = a->x[k], env->reached[k] = (size_t)m;
        for (int q = 0; q < 2; q++) {
            env->height[q][k] = m ? quantile(hh, &a->bh, m, p[q], a->hmax[k]) : NAN;
            env->energy[q][k] = m ? quantile(he, &a->be, m, p[q], a->emax[k]) : NAN;
        }
        env->height[2][k] = m ? a->hmax[k] : NAN;
        env->energy[2][k] = m ? a->emax[k] : NAN;
    }
    return RF_OK;
}

rf_status traj_write_envelopes_csv(const char *dir, const rf_traj_ensemble *e, rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/envelopes.csv", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "cannot write %s", path);
    const rf_traj_envelope *v = &e->envelope;
    fputs("x_m,reached,fraction_reaching,height_p50_m,height_p95_m,height_max_m,energy_p50_J,energy_p95_J,"
          "energy_max_J\n", f);
    for (size_t k = 0; k < v->n_edges; k++)
        fprintf(f, "%.9g,%zu,%.6g,%.6g,%.6g,%.9g,%.6g,%.6g,%.9g\n", v->x[k], v->reached[k],
                e->samples ? (double)v->reached[k] / (double)e->samples : 0.0, v->height[0][k], v->height[1][k],
                v->height[2][k], v->energy[0][k], v->energy[1][k], v->energy[2][k]);
    if (fclose(f) != 0)
        return rf_fail(err, RF_EIO, "cannot write %s", path);
    return RF_OK;
}
