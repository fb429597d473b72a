/* traj_output.c - what `rockfuzz trajectory` prints: the JSON document
 * (shape in docs/trajectories.md; energies in J) and a readable summary
 * (energies in kJ, said once in its header); the CSV files are traj_csv.c's.
 * Recorded paths are rebuilt exactly from their events (each stretch is a
 * parabola or a uniformly accelerated motion). */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_rolling.h"
#include "trajectory/block_traj.h"
#include "core/json.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* {"p50": .., <the chosen levels>, "max": .., "mean": ..} */
void traj_json_percentiles(FILE *f, const rf_traj_percentiles *p)
{
    char name[32];
    fputc('{', f);
    for (size_t k = 0; k < p->n; k++) {
        rf_traj_percentile_name(p->level[k], name, sizeof name);
        fprintf(f, "\"%s\": ", name), rf_json_number(f, p->value[k]), fputs(", ", f);
    }
    fputs("\"max\": ", f), rf_json_number(f, p->max);
    fputs(", \"mean\": ", f), rf_json_number(f, p->mean);
    fputc('}', f);
}

static void json_impacts(FILE *f, const rf_traj_result *r, int block)
{
    fputs("\"impacts\": [", f);
    for (size_t i = 0; i < r->n_impacts && r->impacts; i++) {
        const rf_traj_impact *m = &r->impacts[i];
        fprintf(f, "%s{\"t\": ", i ? ", " : ""), rf_json_number(f, m->t);
        fputs(", \"x\": ", f), rf_json_number(f, m->x);
        fputs(", \"y\": ", f), rf_json_number(f, m->y);
        fprintf(f, ", \"segment\": %zu, \"vx_in\": ", m->segment), rf_json_number(f, m->vx_in);
        fputs(", \"vy_in\": ", f), rf_json_number(f, m->vy_in);
        fputs(", \"vx_out\": ", f), rf_json_number(f, m->vx_out);
        fputs(", \"vy_out\": ", f), rf_json_number(f, m->vy_out);
        fputs(", \"omega_out\": ", f), rf_json_number(f, m->omega_out);
        if (block) /* a rigid block: orientation, rotational energy per body axis (block_traj_output.c) */
            traj_block_json_impact(f, m->q, m->rot_energy);
        fputc('}', f);
    }
    fputs("]", f);
}

static void json_crossing(FILE *f, const rf_traj_crossing *c)
{
    if (!c->reached) {
        fputs("null", f);
        return;
    }
    fputs("{\"t\": ", f), rf_json_number(f, c->t);
    fputs(", \"height_lowest\": ", f), rf_json_number(f, c->height_lowest);
    fputs(", \"height_centre\": ", f), rf_json_number(f, c->height_centre);
    fputs(", \"normal_height\": ", f), rf_json_number(f, c->normal_height);
    fputs(", \"speed\": ", f), rf_json_number(f, c->speed);
    fputs(", \"translational_energy\": ", f), rf_json_number(f, c->translational_energy);
    fputs(", \"rotational_energy\": ", f), rf_json_number(f, c->rotational_energy);
    fputs(", \"total_energy\": ", f), rf_json_number(f, c->total_energy);
    fprintf(f, ", \"stopped_by_barrier\": %s}", c->stopped_by_barrier ? "true" : "false");
}

static void json_trajectory(FILE *f, const rf_traj_spec *s, const rf_traj_result *r)
{
    fprintf(f, "{\"state\": \"%s\", \"n_impacts\": %zu, ", rf_traj_state_name(r->state), r->n_impacts);
    json_impacts(f, r, s->block_kind != RF_TRAJ_BLOCK_NONE);
    if (s->block_kind != RF_TRAJ_BLOCK_NONE)
        traj_block_json_orientation(f, r);
    if (r->state == RF_TRAJ_STOPPED) {
        fputs(", \"rest\": {\"t\": ", f), rf_json_number(f, r->t_end);
        fputs(", \"x\": ", f), rf_json_number(f, r->x_end);
        fputs(", \"y\": ", f), rf_json_number(f, r->y_end);
        fputs("}", f);
    } else {
        fputs(", \"rest\": null", f);
    }
    fputs(", \"end\": {\"t\": ", f), rf_json_number(f, r->t_end);
    fputs(", \"x\": ", f), rf_json_number(f, r->x_end);
    fputs(", \"y\": ", f), rf_json_number(f, r->y_end);
    fputs("}, \"collectors\": {", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        fputs(c ? ", " : "", f), rf_json_string(f, s->collectors[c].name), fputs(": ", f);
        json_crossing(f, &r->crossings[c]);
    }
    fputs("}}", f);
}

/* [{"threshold": v, "barrier": true|false, "probability": p}, ...] */
void traj_json_exceed(FILE *f, const double *t, const double *p, size_t n, int own)
{
    fputc('[', f);
    for (size_t k = 0; k < n; k++) {
        fputs(k ? ", {\"threshold\": " : "{\"threshold\": ", f), rf_json_number(f, t[k]);
        fprintf(f, ", \"barrier\": %s, \"probability\": ", own && k == 0 ? "true" : "false"), rf_json_number(f, p[k]);
        fputc('}', f);
    }
    fputc(']', f);
}

void traj_json_histogram(FILE *f, const rf_traj_histogram *h)
{
    fputs("{\"edges\": [", f);
    for (size_t k = 0; h->bins && k <= h->bins; k++)
        fputs(k ? ", " : "", f), rf_json_number(f, h->edge[k]);
    fputs("], \"counts\": [", f);
    for (size_t k = 0; k < h->bins; k++)
        fprintf(f, "%s%zu", k ? ", " : "", h->count[k]);
    fputs("]}", f);
}

void traj_json_collector_stats(FILE *f, const rf_traj_collector *col, const rf_traj_collector_stats *cs)
{
    const rf_traj_percentiles *q[6] = {&cs->total_energy, &cs->translational_energy, &cs->rotational_energy,
                                       &cs->height_lowest, &cs->height_centre, &cs->speed};
    static const char *const names[6] = {"total_energy", "translational_energy", "rotational_energy",
                                         "height_lowest", "height_centre", "speed"};
    rf_json_string(f, col->name);
    fputs(": {\"reach_probability\": ", f), rf_json_number(f, cs->reach_probability);
    for (int k = 0; k < 6; k++)
        fprintf(f, ", \"%s\": ", names[k]), traj_json_percentiles(f, q[k]);
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own;
    size_t n = rf_traj_thresholds(col, 0, t, &own);
    fputs(", \"p_total_energy_above\": ", f), traj_json_exceed(f, t, cs->p_energy_above, n, own);
    n = rf_traj_thresholds(col, 1, t, &own);
    fputs(", \"p_height_lowest_above\": ", f), traj_json_exceed(f, t, cs->p_height_above, n, own);
    fputc('}', f);
}

static void json_statistics(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st)
{
    fputs("{\"runout_x\": ", f), traj_json_percentiles(f, &st->runout_x);
    fputs(", \"rebound_height\": ", f), traj_json_percentiles(f, &st->rebound_height);
    fputs(", \"p_runout_x_above\": ", f);
    traj_json_exceed(f, s->outputs.runout_thresholds, st->p_runout_above, s->outputs.n_runout_thresholds, 0);
    fputs(",\n  \"runout_histogram\": ", f), traj_json_histogram(f, &st->runout_histogram);
    fputs(",\n  \"collectors\": {", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        fputs(c ? ",\n   " : "", f);
        traj_json_collector_stats(f, &s->collectors[c], &st->collectors[c]);
    }
    fputs("}}", f);
}

void rf_traj_write_json(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st,
                        size_t max_traj)
{
    fputs("{\"name\": ", f), rf_json_string(f, s->name ? s->name : "");
    fprintf(f, ", \"samples\": %zu, \"seed\": %llu, \"sampling\": \"%s\", \"units\": {\"length\": \"m\", "
               "\"time\": \"s\", \"speed\": \"m/s\", \"energy\": \"J\", \"omega\": \"rad/s\"},\n",
            e->samples, (unsigned long long)s->seed, s->lhs ? "lhs" : "random");
    fprintf(f, " \"states\": {\"stopped\": %zu, \"exited\": %zu, \"step_limit\": %zu},\n", st->stopped, st->exited,
            st->step_limit);
    size_t n = e->n_recorded < max_traj ? e->n_recorded : max_traj;
    fprintf(f, " \"trajectories_shown\": %zu,\n \"trajectories\": [", n);
    for (size_t i = 0; i < n; i++) {
        fputs(i ? ",\n  " : "\n  ", f);
        json_trajectory(f, s, &e->recorded[i]);
    }
    fputs("],\n \"statistics\": ", f);
    json_statistics(f, s, st);
    if (s->law == RF_BOUNCE_IMPACT_MODEL) {
        fprintf(f, ",\n \"impact_table\": {\"solver\": \"%s\", \"nodes_normal_speed\": %zu, \"nodes_incidence\": %zu, "
                   "\"impacts_computed\": %zu, \"impacts_from_cache\": %zu, \"tolerance\": %.6g, \"error_estimate\": ",
                s->impact_solver, e->impact_nodes_vn, e->impact_nodes_theta, e->impact_evaluations,
                e->impact_from_cache, s->impact_tolerance);
        rf_json_number(f, e->impact_error_estimate);
        fputs("}", f);
        traj_rolling_json(f, s);
    }
    fprintf(f, ",\n \"wall_seconds\": %.6g}\n", e->wall_seconds);
}

/* "  what:  p50 1.2  p95 3.4  max 5.6" in the chosen levels, values times scale. */
void traj_summary_row(FILE *f, int indent, const char *what, const rf_traj_percentiles *p, double scale)
{
    char name[32];
    fprintf(f, "%*s%-*s", indent, "", 26 - indent, what);
    for (size_t k = 0; k < p->n; k++) {
        rf_traj_percentile_name(p->level[k], name, sizeof name);
        fprintf(f, "%s %-9.4g ", name, p->value[k] * scale);
    }
    fprintf(f, "max %.4g\n", p->max * scale);
}

void traj_summary_exceed(FILE *f, const char *what, const char *unit, const double *t, const double *p, size_t n,
                           int own, const char *own_name, double scale)
{
    for (size_t k = 0; k < n; k++)
        fprintf(f, "%*sP(%s > %.4g %s%s) = %.4g\n", own_name ? 4 : 2, "", what, t[k] * scale, unit,
                own && !k ? own_name : "", p[k]);
}

static void summary_collector(FILE *f, const rf_traj_collector *col, const rf_traj_collector_stats *cs)
{
    fprintf(f, "  collector %s (x = %g m): reach probability %.4g\n", col->name, col->x, cs->reach_probability);
    if (cs->reach_probability > 0) {
        traj_summary_row(f, 4, "total energy", &cs->total_energy, 1e-3);
        traj_summary_row(f, 4, "translational energy", &cs->translational_energy, 1e-3);
        traj_summary_row(f, 4, "rotational energy", &cs->rotational_energy, 1e-3);
        traj_summary_row(f, 4, "height lowest point", &cs->height_lowest, 1);
        traj_summary_row(f, 4, "height centre", &cs->height_centre, 1);
        traj_summary_row(f, 4, "speed", &cs->speed, 1);
    }
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own;
    size_t n = rf_traj_thresholds(col, 0, t, &own);
    traj_summary_exceed(f, "total energy", "kJ", t, cs->p_energy_above, n, own, ", the capacity", 1e-3);
    n = rf_traj_thresholds(col, 1, t, &own);
    traj_summary_exceed(f, "height lowest point", "m", t, cs->p_height_above, n, own, ", the barrier height", 1);
}

void rf_traj_write_summary(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st)
{
    fprintf(f, "%s: %zu trajector%s (%s sampling, seed %llu) in %.3g s\n", s->name ? s->name : "trajectory",
            e->samples, e->samples == 1 ? "y" : "ies", s->lhs ? "Latin hypercube" : "random",
            (unsigned long long)s->seed, e->wall_seconds);
    fprintf(f, "  units: energy kJ, height and x m, speed m/s; collector statistics over the blocks that reach "
               "it, probabilities over all blocks\n");
    fprintf(f, "  stopped %zu, exited %zu, step_limit %zu\n", st->stopped, st->exited, st->step_limit);
    if (s->law == RF_BOUNCE_IMPACT_MODEL)
        fprintf(f, "  impact_model (%s): table of %zu normal speeds x %zu incidences; %zu impacts computed, %zu from "
                   "the cache; estimated interpolation error of R_n, R_t %.3g (tolerance %g)\n", s->impact_solver,
                e->impact_nodes_vn, e->impact_nodes_theta, e->impact_evaluations, e->impact_from_cache,
                e->impact_error_estimate, s->impact_tolerance);
    if (s->law == RF_BOUNCE_IMPACT_MODEL)
        traj_rolling_summary(f, s);
    if (e->samples == 1 && e->n_recorded) {
        const rf_traj_result *r = &e->recorded[0];
        fprintf(f, "  %s at t = %.6g s, x = %.6g m, y = %.6g m after %zu impact%s\n", rf_traj_state_name(r->state),
                r->t_end, r->x_end, r->y_end, r->n_impacts, r->n_impacts == 1 ? "" : "s");
    } else {
        traj_summary_row(f, 2, "runout x [m]", &st->runout_x, 1);
        traj_summary_exceed(f, "runout x", "m", s->outputs.runout_thresholds, st->p_runout_above,
                       s->outputs.n_runout_thresholds, 0, NULL, 1);
    }
    for (size_t c = 0; c < s->n_collectors; c++)
        summary_collector(f, &s->collectors[c], &st->collectors[c]);
}

int rf_traj_state_at(const rf_traj_result *r, double t, double *x, double *y, double *vx, double *vy)
{
    if (!r->events || !r->n_events || t < r->events[0].t || t > r->events[r->n_events - 1].t)
        return 0;
    size_t i = 0;
    for (size_t k = 0; k < r->n_events; k++) /* the last event at or before t */
        if (r->events[k].t <= t)
            i = k;
    const rf_traj_event *e = &r->events[i];
    double d = t - e->t;
    *x = e->x + e->vx * d + 0.5 * e->ax * d * d;
    *y = e->y + e->vy * d + 0.5 * e->ay * d * d;
    *vx = e->vx + e->ax * d;
    *vy = e->vy + e->ay * d;
    return 1;
}
