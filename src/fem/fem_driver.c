/* fem_driver.c - the one stage loop of the FE solvers (fem_driver.h). */
#include "fem_driver.h"
#include "fem_internal.h" /* fem_vtk_index */

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
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

/* ---- the step budget, the estimate and the stop flag ---------------------- */

/* Steps measured before the time estimate (or the whole run when shorter). */
#define PROBE_STEPS 16

/* The run's budget in steps (max_steps: 0 the default, < 0 none: +inf). */
static double step_budget(const rf_fem_options *o)
{
    return o->max_steps < 0 ? INFINITY : o->max_steps > 0 ? o->max_steps : RF_FEM_DEFAULT_MAX_STEPS;
}

/* The least simulated time [s] (fem_run_begin's t_min) and the steps it takes, as doubles (no overflow). */
static double least_time(const fem_drive_params *p, const rf_fem_options *o)
{
    return o->end_time > 0 ? o->end_time : 1.3 * p->t_hertz;
}

/* "about 2.5e+06 time steps of 4e-09 s for 0.01 s simulated (...)" */
static void steps_text(const fem_drive_params *p, const rf_fem_options *o, char *buf, size_t size)
{
    const double t = least_time(p, o);
    snprintf(buf, size, "about %.3g time steps of %.3g s for %.3g s simulated (%s)", ceil(t / p->dt), p->dt, t,
             o->end_time > 0 ? "the given end time" : "1.3 Hertz contact durations at least");
}

/* The inputs a time step depends on, for the messages. */
static void step_inputs(const rf_impact_input *in, char *buf, size_t size)
{
    snprintf(buf, size, "boulder E = %g Pa, poisson = %g; slope E = %g Pa, poisson = %g; radius = %g m", in->boulder_E,
             in->boulder_poisson, in->slope_E, in->slope_poisson, in->radius);
}

/* After assembly, before anything is allocated for the steps: the estimated step count within the budget. */
static rf_status budget_check(const char *who, const fem_drive_params *p, const fem_attempt *a, rf_error *err)
{
    const rf_fem_options *o = a->opt;
    const double budget = step_budget(o), steps = ceil(least_time(p, o) / p->dt);
    char inputs[256], what[256];
    step_inputs(a->in, inputs, sizeof inputs);
    if (!(p->dt > 0) || !isfinite(steps))
        return rf_fail(err, RF_EINVAL, "%s: the stable time step (%g s) or the contact duration (%g s) is not a "
                       "positive finite number: the stiffness or the size of this input is beyond what the arithmetic "
                       "holds (%s)", who, p->dt, p->t_hertz, inputs);
    if (steps <= budget)
        return RF_OK;
    steps_text(p, o, what, sizeof what);
    return rf_fail(err, RF_EINVAL, "%s: the run needs %s, more than the budget of %.3g steps (max_steps; "
                   "`rockfuzz impact --max-steps N`, 0 = no limit): a time step this small comes from a stiff or "
                   "nearly incompressible material or a fine mesh (%s); a long end time multiplies it", who, what,
                   budget, inputs);
}

/* Before meshing (a nearly incompressible slope's automatic domain takes
 * minutes to mesh): a lower bound of the step count from one element the mesh
 * is known to hold, the slope's cube (square) of side h = a / refinement under
 * the contact (a the Hertz radius at the normal speed).  Its own stable step
 * is at most h / c_p (a lumped 1D bar: h / c_p, a square or cube: less), and
 * the run's step is the least over its elements, so the run takes at least
 * least_time / (h / c_p) steps.  Only without a layer (the element under the
 * contact is then the layer's). */
static rf_status budget_before_mesh(const fem_geometry *g, const fem_attempt *a, rf_error *err)
{
    const rf_impact_input *in = a->in;
    if (!in || in->layer_thickness > 0)
        return RF_OK;
    rf_hertz_reference H;
    rf_wave_speeds w;
    rf_impact_hertz_reference(in, &H);
    rf_impact_wave_speeds(in, 1, &w);
    const double h = H.contact_radius / rf_fem_refinement(a->opt, !strcmp(g->who, "fem3d"));
    const fem_drive_params p = {.dt = h / w.p, .t_hertz = H.duration};
    const double steps = ceil(least_time(&p, a->opt) / p.dt);
    char cause[256] = "", text[512], count[32];
    const double t = least_time(&p, a->opt);
    snprintf(count, sizeof count, steps < 1e12 ? "%.0f" : "%.3g", steps); /* exact: a budget can be set to it */
    if (isfinite(steps) && steps <= step_budget(a->opt)) { /* a long run allowed: said before the mesh */
        if (steps > RF_FEM_DEFAULT_MAX_STEPS && a->opt->say) {
            snprintf(text, sizeof text, "%s: at least %s time steps (of at most %.3g s) for %.3g s simulated, "
                     "estimated before meshing; meshing comes first", g->who, count, p.dt, t);
            a->opt->say(a->opt->say_ctx, text);
        }
        return RF_OK;
    }
    if (!isfinite(steps))
        return RF_OK; /* named after assembly, with the stiffness inputs */
    if (in->slope_poisson > 0.49)
        snprintf(cause, sizeof cause, "the slope is nearly incompressible (poisson = %.10g: its P waves run at "
                 "%.3g m/s, %.3g times its S waves), ", in->slope_poisson, w.p, w.p / w.s);
    return rf_fail(err, RF_EINVAL, "%s: before meshing: the run needs at least %s time steps (of at most %.3g s) for "
                   "%.3g s simulated (%s), more than the budget of %.3g steps (max_steps; `rockfuzz impact --max-steps "
                   "N`, 0 = no limit): %sthe time step is at most the finest element's h / c_p = %.3g m / %.3g m/s "
                   "(slope E = %g Pa, poisson = %.10g, density = %g kg/m^3; h = Hertz contact radius %.3g m / "
                   "refinement)", g->who, count, p.dt, t, a->opt->end_time > 0 ? "the given end time" : "1.3 Hertz "
                   "contact durations at least", step_budget(a->opt), cause, h, w.p, in->slope_E, in->slope_poisson,
                   in->slope_density, H.contact_radius);
}

/* After PROBE_STEPS steps (wall0: when the first began): say the time a long run will take. */
static void say_estimate(const fem_drive_params *p, const rf_fem_options *o, const fem_run *R, long done,
                         double wall0)
{
    if (!o->say || done <= 0)
        return;
    const double per_step = (rf_monotonic_seconds() - wall0) / (double)done;
    const double total = per_step * ceil(least_time(p, o) / p->dt);
    if (total <= RF_FEM_SAY_SECONDS)
        return;
    char what[256], text[512];
    steps_text(p, o, what, sizeof what);
    snprintf(text, sizeof text, "%s: %s; about %.0f s at the %.3g ms per step of the first %ld steps", R->who, what,
             total, 1e3 * per_step, done);
    o->say(o->say_ctx, text);
}

/* Between two steps: the stop flag, and the budget (a run past its estimate). */
static rf_status step_allowed(const fem_run *R, const rf_fem_options *o, long n, rf_error *err)
{
    if (o->interrupt && atomic_load_explicit(o->interrupt, memory_order_relaxed))
        return rf_fail(err, RF_EINTERRUPTED, "%s: interrupted at step %ld (t = %.3g s)", R->who, n, (double)n * R->dt);
    if ((double)n >= step_budget(o))
        return rf_fail(err, RF_EMODEL, "%s: the impact has not ended after %ld time steps (t = %.3g s), the budget "
                       "(max_steps; `rockfuzz impact --max-steps N`, 0 = no limit)", R->who, n, (double)n * R->dt);
    return RF_OK;
}

/* The steps until the run's stop rule (fem_run_stop); *nsteps taken. */
static rf_status drive_loop(const fem_geometry *g, void *run, fem_run *R, const fem_drive_params *p,
                            const rf_fem_options *o, long *nsteps, rf_error *err)
{
    drive_frames f;
    rf_status st = frames_begin(&f, o, R, g->who, err);
    const double wall0 = rf_monotonic_seconds();
    long n = 0;
    for (; st == RF_OK; n++) {
        const double t = (double)n * p->dt;
        if (n == PROBE_STEPS)
            say_estimate(p, o, R, n, wall0);
        if ((st = step_allowed(R, o, n, err)) != RF_OK)
            break;
        if (f.dir && n % f.every == 0 && f.n < f.cap - 1 && (st = frame(g, run, &f, t, err)) != RF_OK)
            break;
        fem_step_row r = {.travel = 0};
        if ((st = g->step(run, t, &r, err)) != RF_OK)
            break;
        const int was_in_contact = R->in_contact;
        R->roll.travel = r.travel;
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

/* A mesh refused (too many elements, a zone that does not fit) for a contact
 * far smaller or larger than the block: say which input makes it so. */
static void mesh_hint(const rf_impact_input *in, rf_error *err)
{
    const double a = rf_hertz_contact_radius(in), ratio = a / in->radius;
    if (ratio > 1e-3 && ratio < 0.5)
        return;
    const size_t len = strlen(err->msg);
    snprintf(err->msg + len, sizeof err->msg - len, " (at this input the Hertz contact radius is a = %.3g m, %.3g "
             "times the block's radius %g m, from velocity = %g m/s, boulder E = %g Pa, slope E = %g Pa; the FE mesh "
             "is graded from a / refinement at the contact to the block's size, so such a ratio cannot be meshed; "
             "the analytic solvers hertz and hunter take the impact)", a, ratio, in->radius, in->velocity,
             in->boulder_E, in->slope_E);
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
        st = budget_before_mesh(g, a, err);
    if (st == RF_OK && (st = g->mesh(run, err)) != RF_OK) /* not after prepare: its input may be invalid or NULL */
        mesh_hint(a->in, err);
    if (st == RF_OK)
        st = g->assemble(run, err);
    if (st == RF_OK) {
        g->params(run, &p);
        st = budget_check(g->who, &p, a, err);
    }
    if (st == RF_OK)
        st = fem_run_begin(&R, g->who, a->opt, p.dt, p.t_hertz, a->hist || a->rep, p.columns, err);
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
