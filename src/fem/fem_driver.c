/* fem_driver.c - the one stage loop of the FE solvers (fem_driver.h). */
#include "fem_driver.h"
#include "fem_internal.h" /* fem_vtk_index */

#include <stdlib.h>
#include <string.h>

#include "core/util.h"

/* The results' buffers, released here: the driver releases them when a run fails. */
void rf_fem_history_free(rf_fem_history *h)
{
    if (!h)
        return;
    free(h->t);
    free(h->contact_force), free(h->compression), free(h->contact_radius);
    free(h->kinetic_boulder), free(h->strain_boulder), free(h->kinetic_slope), free(h->strain_slope);
    free(h->contact_work), free(h->absorbed), free(h->closure), free(h->boulder_velocity), free(h->remap);
    h->t = h->contact_force = h->compression = h->contact_radius = NULL;
    h->kinetic_boulder = h->strain_boulder = h->kinetic_slope = h->strain_slope = NULL;
    h->contact_work = h->absorbed = h->closure = h->boulder_velocity = h->remap = NULL;
    h->n = 0;
}

void rf_fem3d_report_free(rf_fem3d_report *rep)
{
    if (!rep)
        return;
    free(rep->friction_series);
    rep->friction_series = NULL;
    rep->n = 0;
}

/* The VTK frames of a run: about vtk_frames of them, and the final state. */
typedef struct {
    const char *dir;
    long every;
    int n, cap;
    double *times;
} drive_frames;

static rf_status frames_begin(drive_frames *f, const rf_fem_options *o, const fem_run *R, const char *who,
                              rf_error *err)
{
    const int want = fem_tuning_of(o)->vtk_frames;
    memset(f, 0, sizeof *f);
    f->dir = o->vtk_dir;
    if (!f->dir)
        return RF_OK;
    f->every = (long)(R->steps_estimate / (want > 0 ? want : 60) + 1);
    f->cap = 4 * (want + 8);
    if (!(f->times = malloc((size_t)f->cap * sizeof *f->times)))
        return rf_fail(err, RF_ENOMEM, "%s: out of memory", who);
    return RF_OK;
}

static rf_status frame(const fem_geometry *g, void *run, drive_frames *f, double t, rf_error *err)
{
    rf_status st = g->frame(run, f->n, t, err);
    if (st == RF_OK)
        f->times[f->n++] = t;
    return st;
}

/* The steps until the run's stop rule (fem_run_stop); *nsteps taken. */
static rf_status drive_loop(const fem_geometry *g, void *run, fem_run *R, const fem_drive_params *p,
                            const rf_fem_options *o, long *nsteps, rf_error *err)
{
    drive_frames f;
    rf_status st = frames_begin(&f, o, R, g->who, err);
    long n = 0;
    for (; st == RF_OK; n++) {
        const double t = (double)n * p->dt;
        if (f.dir && n % f.every == 0 && f.n < f.cap - 1 && (st = frame(g, run, &f, t, err)) != RF_OK)
            break;
        fem_step_row r;
        if ((st = g->step(run, t, &r, err)) != RF_OK)
            break;
        const int was_in_contact = R->in_contact;
        if ((st = fem_run_account(R, n, r.Fc, r.rad, r.comp, r.closure, p->ke0, r.row, err)) != RF_OK)
            break;
        if (g->accounted)
            g->accounted(run, was_in_contact, R->in_contact);
        if (fem_run_stop(R, n))
            break;
    }
    *nsteps = n + 1;
    if (st == RF_OK && f.dir && (st = frame(g, run, &f, (double)(n + 1) * p->dt, err)) == RF_OK)
        st = fem_vtk_index(f.dir, f.n, f.times, err);
    free(f.times);
    return st;
}

rf_status fem_drive(const fem_geometry *g, void *run, const fem_attempt *a, long *unstable, rf_error *err)
{
    const double wall0 = rf_monotonic_seconds();
    if (a->hist)
        memset(a->hist, 0, sizeof *a->hist);
    if (a->rep)
        memset(a->rep, 0, sizeof *a->rep);
    fem_run R;
    memset(&R, 0, sizeof R);
    fem_drive_params p = {0};
    rf_status st = g->prepare(run, a, err);
    if (st == RF_OK)
        st = g->mesh(run, err);
    if (st == RF_OK)
        st = g->assemble(run, err);
    if (st == RF_OK) {
        g->params(run, &p);
        st = fem_run_begin(&R, g->who, a->opt, p.dt, p.t_hertz, a->hist || a->rep, p.columns, err);
    }
    R.gravity = p.gravity;
    long nsteps = 0;
    if (st == RF_OK)
        st = drive_loop(g, run, &R, &p, a->opt, &nsteps, err);
    if (st == RF_OK) {
        g->extract(run, &R, nsteps, a);
        if (a->hist)
            fem_run_history(&R, a->hist);
        if (a->hist && g->history)
            g->history(run, &R, a->hist);
        a->out->wall_seconds = rf_monotonic_seconds() - wall0;
    }
    *unstable = g->release(run);
    fem_run_free(&R);
    if (st != RF_OK && a->hist)
        rf_fem_history_free(a->hist);
    if (st != RF_OK && a->rep)
        rf_fem3d_report_free(a->rep);
    return st;
}

rf_status fem_drive_impact(fem_attempt_fn attempt, fem_attempt *a, const char *who, rf_error *err)
{
    const double wall0 = rf_monotonic_seconds();
    if (!a->out || !a->ws)
        return rf_fail(err, RF_EINVAL, "%s: NULL output or workspace", who);
    rf_fem_options o;
    if (a->opt)
        o = *a->opt;
    else
        rf_fem_options_default(&o);
    const rf_status st = fem_run_halving(attempt, a, &o, err);
    if (st == RF_OK)
        a->out->wall_seconds = rf_monotonic_seconds() - wall0;
    return st;
}
