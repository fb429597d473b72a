/* fem_core.c - the stages both FE solvers share (see fem_core.h): the
 * workspace pool, the time step, and the run account (time span and stop
 * test, contact-force record and duration, maxima, energy-closure check,
 * sampled history, warnings, the common outputs). */
#include "fem_core.h"
#include "core/hash.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void *fem_pool_get(fem_pool *p, int slot, size_t bytes, int zero)
{
    if (bytes == 0)
        bytes = 1;
    if (p->cap[slot] < bytes) {
        free(p->ptr[slot]);
        p->ptr[slot] = malloc(bytes);
        p->cap[slot] = p->ptr[slot] ? bytes : 0;
        if (!p->ptr[slot])
            return NULL;
    }
    if (zero)
        memset(p->ptr[slot], 0, bytes);
    return p->ptr[slot];
}

void fem_pool_free(fem_pool *p)
{
    for (int k = 0; k < FEM_POOL_SLOTS; k++)
        free(p->ptr[k]), p->ptr[k] = NULL, p->cap[k] = 0;
}

rf_fem_workspace *rf_fem_workspace_alloc(void)
{
    return calloc(1, sizeof(rf_fem_workspace));
}

void rf_fem_workspace_free(rf_fem_workspace *ws)
{
    if (!ws)
        return;
    fem_pool_free(&ws->axi);
    fem_pool_free(&ws->solid);
    free(ws);
}

double fem_time_step(double lambda_max, double safety, double *dt_bound)
{
    *dt_bound = 2 / sqrt(lambda_max);
    return safety * *dt_bound;
}

rf_status fem_run_halving(fem_attempt_fn attempt, void *ctx, const rf_fem_options *o, rf_error *err)
{
    rf_fem_options oh = *o;
    rf_fem_tuning th = *fem_tuning_of(o); /* halved below */
    oh.tuning = &th;
    for (int k = 0;; k++) {
        long unstable = -1;
        const rf_status st = attempt(ctx, &oh, &unstable, err);
        if (unstable < 0 || k == FEM_STEP_HALVINGS)
            return st;
        th.dt_safety *= 0.5;
    }
}

rf_status fem_run_begin(fem_run *r, const char *who, const rf_fem_options *o, double dt, double t_h, int record,
                        int ncol, rf_error *err)
{
    memset(r, 0, sizeof *r);
    r->who = who;
    r->dt = dt, r->t_h = t_h, r->end_time = o->end_time;
    r->t_min = o->end_time > 0 ? o->end_time : 1.3 * t_h;
    r->t_max = o->end_time > 0 ? o->end_time : 3.0 * t_h;
    r->steps_estimate = (long)ceil(r->t_min / dt);
    r->stride = fem_tuning_of(o)->history_stride > 0 ? fem_tuning_of(o)->history_stride : (int)(r->steps_estimate / 5000 + 1);
    r->record = record;
    r->early_end = fem_tuning_of(o)->end_at_separation;
    r->progress = o->progress, r->progress_ctx = o->progress_ctx;
    r->series.ncol = ncol;
    r->force_cap = r->steps_estimate + 16;
    r->force = malloc((size_t)r->force_cap * sizeof *r->force);
    if (!r->force)
        return rf_fail(err, RF_ENOMEM, "%s: out of memory", who);
    return RF_OK;
}

static int force_record(fem_run *r, long n, double value)
{
    if (n >= r->force_cap) {
        long grown = 2 * r->force_cap > n ? 2 * r->force_cap : n + 1;
        double *p = realloc(r->force, (size_t)grown * sizeof *p);
        if (!p)
            return -1;
        r->force = p;
        r->force_cap = grown;
    }
    r->force[n] = value;
    return 0;
}

static int series_push(fem_series *s, const double *v)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 1024;
        for (int k = 0; k < s->ncol; k++) {
            double *p = realloc(s->col[k], cap * sizeof *p);
            if (!p)
                return -1;
            s->col[k] = p;
        }
        s->cap = cap;
    }
    for (int k = 0; k < s->ncol; k++)
        s->col[k][s->n] = v[k];
    s->n++;
    return 0;
}

/* The automatic end's bound past t_max, in Hertz durations at most. */
#define FEM_RUN_BOUND_MAX 100.0

/* The impact has ended: the contact is open and the boulder does not move
 * toward the slope (a boulder still moving in meets it again).  With gravity:
 * the contact opened with the boulder moving away faster than the rest
 * rule's resolution (v_sep > FEM_REST_SPEED V), even if its weight has
 * turned it since (it falls back later: a new impact); a slower separation is
 * the block settling in its crater (the rest rule decides). */
static int run_ended(const fem_run *r)
{
    if (r->gravity > 0)
        return !r->in_contact && r->v_sep > FEM_REST_SPEED * fabs(r->v_start);
    return !r->in_contact && r->v_now >= 0;
}

/* The rest rule (fem_core.h) at time t. */
static void rest_check(fem_run *r, double t)
{
    const int slow = r->episodes > 0 && t - r->t_last_contact <= 0.1 * r->t_h &&
                     fabs(r->v_now) < FEM_REST_SPEED * fabs(r->v_start);
    if (!slow)
        r->rest_since = -1;
    else if (r->rest_since < 0)
        r->rest_since = t;
    if (slow && t - r->rest_since >= FEM_REST_WINDOW * r->t_h)
        r->at_rest = 1;
}

/* The roll rule (fem_core.h) at time t. */
static void roll_check(fem_run *r, double t)
{
    if (t >= r->t_max && r->in_contact && r->roll.a_max > 0 && fabs(r->roll.travel) > 2 * r->roll.a_max)
        r->at_rest = 1, r->roll.out = 1;
}

/* The expected end of the run at time t, for a progress line only: end_time
 * when given; else at least t_min, and by the state of the impact: while the
 * boulder approaches, at the mean rate so far the incoming momentum is
 * reversed at t / p, and the rebound takes at most as long again (elastic);
 * in a slow spell (gravity) the rest rule's window; after the contact opened,
 * the 0.1 t_h it must stay open. */
static double expected_end(const fem_run *r, double t)
{
    if (r->end_time > 0)
        return r->end_time;
    const double p = r->v_start < 0 ? (r->v_now - r->v_start) / -r->v_start : 1;
    double e = fmax(r->t_min, t + 0.1 * r->t_h);
    if (r->in_contact && p > 0.25 && p < 1) /* early, a Hertzian force reverses little: no estimate yet */
        e = fmax(e, 2 * t / p);
    if (r->rest_since >= 0 && r->gravity > 0)
        e = fmax(e, r->rest_since + FEM_REST_WINDOW * r->t_h);
    if (!r->in_contact && r->episodes > 0)
        e = fmax(e, r->t_last_contact + 0.1 * r->t_h);
    return e;
}

rf_status fem_run_account(fem_run *r, long n, double Fc, double rad, double comp, double closure, double ke0,
                          const double *row, rf_error *err)
{
    const double t = (double)n * r->dt;
    if (force_record(r, n, Fc))
        return rf_fail(err, RF_ENOMEM, "%s: out of memory", r->who);
    if (n == 0)
        r->v_start = row[11], r->rest_since = -1;
    r->v_now = row[11];
    if (r->gravity > 0 && !(Fc > 0) && r->in_contact)
        r->v_sep = row[11];
    if (Fc > 0) {
        if (!r->in_contact)
            r->episodes++;
        r->in_contact = 1;
        r->t_last_contact = t;
    } else
        r->in_contact = 0;
    if (Fc > r->F_max)
        r->F_max = Fc, r->a_at_Fmax = rad;
    if (Fc > 0 && rad > r->roll.a_max)
        r->roll.a_max = rad;
    if (comp > r->comp_max)
        r->comp_max = comp;
    if (!isfinite(closure) || fabs(closure) > 10 * ke0)
        return rf_fail(err, RF_EMODEL,
                       "%s: the solution diverged at t = %.4g s (energy %.3g x KE0); time step %.3g s is unstable",
                       r->who, t, closure / ke0, r->dt);
    if (fabs(closure) > r->closure_max)
        r->closure_max = fabs(closure);
    if (r->record && n % r->stride == 0 && series_push(&r->series, row) != 0)
        return rf_fail(err, RF_ENOMEM, "%s: out of memory", r->who);
    if (r->gravity > 0 && r->end_time == 0)
        rest_check(r, t), roll_check(r, t);
    if (r->progress)
        r->progress(r->progress_ctx, t, expected_end(r, t));
    const double tn = (double)(n + 1) * r->dt;
    if (r->end_time > 0 || tn < r->t_max || run_ended(r) || r->at_rest)
        return RF_OK;
    /* Past t_max = 3 t_h the impact has not ended (a plastic contact lasts
       longer than the elastic one): the run goes on.  Its bound: at t_max a
       share p of the incoming momentum has been reversed (p = 1: the boulder
       is at rest); at that mean rate the approach ends at t_max / p; allowed:
       4 times that (the resisting force may fall to a quarter of its mean
       before the boulder stops), at most FEM_RUN_BOUND_MAX t_h. */
    const double p = r->v_start < 0 ? (r->v_now - r->v_start) / -r->v_start : 1;
    if (r->t_bound == 0) /* with gravity a block settles by small bounces and oscillations: the full bound */
        r->t_bound = r->gravity > 0 ? FEM_RUN_BOUND_MAX * r->t_h
                                    : fmin(FEM_RUN_BOUND_MAX * r->t_h, 4 * r->t_max / fmax(fmin(p, 1), 1e-3));
    if (tn < r->t_bound)
        return RF_OK;
    return rf_fail(err, RF_EMODEL,
                   "%s: the impact has not ended at t = %.4g s (%.1f Hertz durations, the bound of the automatic "
                   "end): the boulder is %s (normal velocity %.3g m/s, %.0f %% of the incoming momentum reversed); "
                   "no rebound velocity exists yet: set end_time [s] to see the state at a given time",
                   r->who, tn, tn / r->t_h, r->in_contact ? "still in contact" : "moving toward the slope", r->v_now,
                   100 * p);
}

int fem_run_stop(const fem_run *r, long n)
{
    const double tn = (double)(n + 1) * r->dt;
    if (r->end_time > 0)
        return tn >= r->end_time;
    if (r->at_rest)
        return 1;
    if (tn >= r->t_max && run_ended(r) && r->t_bound == 0) /* ended by t_max: the old fixed end */
        return 1;
    const int least = tn >= r->t_min || (r->early_end && r->gravity > 0); /* the tuning's end_at_separation */
    return least && run_ended(r) && tn - r->t_last_contact > 0.1 * r->t_h;
}

void fem_contact_window(const double *force, long nsteps, double dt, double threshold, double *t_first,
                        double *t_last)
{
    double t0 = -1, t1 = -1;
    for (long k = 0; k < nsteps; k++)
        if (force[k] > threshold) {
            if (t0 < 0) {
                t0 = (double)k * dt;
                if (k > 0)
                    t0 -= dt * fmin(1, (force[k] - threshold) / (force[k] - force[k - 1]));
            }
            t1 = (double)k * dt;
            if (k + 1 < nsteps && k > 0 && force[k - 1] > force[k])
                t1 += dt * fmin(1, (force[k] - threshold) / (force[k - 1] - force[k]));
        }
    *t_first = t0 < 0 ? 0 : t0;
    *t_last = t1;
}

/* Contact duration: first to last nonzero multiplier (exact zeros off
 * contact; the threshold only guards round-off). */
void fem_run_outputs(const fem_run *r, long nsteps, double duration_threshold, double ke0, double force_factor,
                     long nodes, long elements, rf_impact_output *out)
{
    double t0, t1;
    fem_contact_window(r->force, nsteps, r->dt, duration_threshold * r->F_max, &t0, &t1);
    memset(out, 0, sizeof *out);
    out->contact_force_max = r->F_max * force_factor;
    out->compression_max = r->comp_max;
    out->contact_duration = t1 - t0;
    out->contact_radius = r->a_at_Fmax;
    out->energy_error = r->closure_max / ke0;
    out->nodes = (double)nodes;
    out->elements = (double)elements;
    out->steps = (double)nsteps;
}

void fem_run_history(fem_run *r, rf_fem_history *hist)
{
    double **dst[12] = {&hist->t,           &hist->contact_force,   &hist->compression,   &hist->contact_radius,
                        &hist->kinetic_boulder, &hist->strain_boulder, &hist->kinetic_slope, &hist->strain_slope,
                        &hist->contact_work, &hist->absorbed,       &hist->closure,       &hist->boulder_velocity};
    hist->n = r->series.n;
    for (int k = 0; k < 12; k++)
        *dst[k] = r->series.col[k], r->series.col[k] = NULL;
}

void fem_run_warnings(const fem_run *r, int fixed_outer, double L, double c_p, double r0, char *buf, size_t size,
                      const char *extra)
{
    size_t wl = 0;
    buf[0] = 0;
    if (fixed_outer && 2 * L / c_p < r->t_h)
        wl += (size_t)snprintf(buf + wl, size - wl,
                               "P waves reflected by the fixed boundary return after 2L/c_p = %.3g ms, before the "
                               "Hertz contact ends (%.3g ms): R_n includes reflected energy; use the absorbing "
                               "boundary (boundary auto, the default, takes it for a layer or a plastic body) "
                               "or a domain_factor of at least %.0f. ",
                               2e3 * L / c_p, 1e3 * r->t_h,
                               fmax(RF_FEM_DOMAIN_MIN, ceil(0.5 * RF_FEM_DOMAIN_MARGIN * c_p * r->t_h / r0)));
    if (r->episodes > 1 && wl < size)
        wl += (size_t)snprintf(buf + wl, size - wl, "Contact closed %d times (re-contact after separation). ",
                               r->episodes);
    if (extra && extra[0] && wl < size)
        wl += (size_t)snprintf(buf + wl, size - wl, "%s", extra);
    if (r->roll.out && wl < size)
        wl += (size_t)snprintf(buf + wl, size - wl, "The boulder rolled or slid out of its crater in contact (its "
                               "centre %.3g m along the slope, more than twice the contact radius %.3g m, at t = "
                               "%.3g s, %.3g Hertz durations): the impact is over, R_n = 0. ", r->roll.travel, r->roll.a_max,
                               r->t_last_contact, r->t_last_contact / r->t_h);
    else if (r->at_rest && wl < size)
        wl += (size_t)snprintf(buf + wl, size - wl, "The boulder came to rest in contact (normal speed below %g %% of "
                               "the incoming one for %g Hertz durations): R_n = 0. ", 100 * FEM_REST_SPEED,
                               FEM_REST_WINDOW);
    if (r->end_time > 0 && !run_ended(r) && wl < size)
        snprintf(buf + wl, size - wl, "%s at end_time: rebound velocity is not final. ",
                 r->in_contact ? "Still in contact" : "Boulder moving toward the slope");
}

void fem_run_free(fem_run *r)
{
    free(r->force);
    for (int k = 0; k < FEM_SERIES_MAX; k++)
        free(r->series.col[k]);
    memset(r, 0, sizeof *r);
}

uint64_t fem_hash(uint64_t h, const void *data, size_t n) { return rf_fnv1a(h, data, n); }
