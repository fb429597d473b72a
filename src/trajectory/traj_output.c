/* traj_output.c - what `rockfuzz trajectory` writes: the JSON document
 * (shape fixed by issue 11 and docs/trajectories.md), a readable summary,
 * and CSV files.  Recorded paths are rebuilt exactly from their events (each
 * stretch is a parabola or a uniformly accelerated motion). */
#include "trajectory/traj_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static void jnum(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.17g", v);
    else
        fputs("null", f);
}

static void jstr(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fprintf(f, "\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            fprintf(f, "\\u%04x", *s);
        else
            fputc(*s, f);
    }
    fputc('"', f);
}

static void jpct(FILE *f, const rf_traj_percentiles *p)
{
    fputs("{\"p50\": ", f), jnum(f, p->p50);
    fputs(", \"p95\": ", f), jnum(f, p->p95);
    fputs(", \"p99\": ", f), jnum(f, p->p99);
    fputs(", \"max\": ", f), jnum(f, p->max);
    fputs(", \"mean\": ", f), jnum(f, p->mean);
    fputc('}', f);
}

static void json_impacts(FILE *f, const rf_traj_result *r)
{
    fputs("\"impacts\": [", f);
    for (size_t i = 0; i < r->n_impacts && r->impacts; i++) {
        const rf_traj_impact *m = &r->impacts[i];
        fprintf(f, "%s{\"t\": ", i ? ", " : ""), jnum(f, m->t);
        fputs(", \"x\": ", f), jnum(f, m->x);
        fputs(", \"y\": ", f), jnum(f, m->y);
        fprintf(f, ", \"segment\": %zu, \"vx_in\": ", m->segment), jnum(f, m->vx_in);
        fputs(", \"vy_in\": ", f), jnum(f, m->vy_in);
        fputs(", \"vx_out\": ", f), jnum(f, m->vx_out);
        fputs(", \"vy_out\": ", f), jnum(f, m->vy_out);
        fputs(", \"omega_out\": ", f), jnum(f, m->omega_out);
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
    fputs("{\"t\": ", f), jnum(f, c->t);
    fputs(", \"height\": ", f), jnum(f, c->height);
    fputs(", \"normal_height\": ", f), jnum(f, c->normal_height);
    fputs(", \"speed\": ", f), jnum(f, c->speed);
    fputs(", \"kinetic_energy\": ", f), jnum(f, c->kinetic_energy);
    fputs(", \"rotational_energy\": ", f), jnum(f, c->rotational_energy);
    fprintf(f, ", \"stopped_by_barrier\": %s}", c->stopped_by_barrier ? "true" : "false");
}

static void json_trajectory(FILE *f, const rf_traj_spec *s, const rf_traj_result *r)
{
    fprintf(f, "{\"state\": \"%s\", \"n_impacts\": %zu, ", rf_traj_state_name(r->state), r->n_impacts);
    json_impacts(f, r);
    if (r->state == RF_TRAJ_STOPPED) {
        fputs(", \"rest\": {\"t\": ", f), jnum(f, r->t_end);
        fputs(", \"x\": ", f), jnum(f, r->x_end);
        fputs(", \"y\": ", f), jnum(f, r->y_end);
        fputs("}", f);
    } else {
        fputs(", \"rest\": null", f);
    }
    fputs(", \"end\": {\"t\": ", f), jnum(f, r->t_end);
    fputs(", \"x\": ", f), jnum(f, r->x_end);
    fputs(", \"y\": ", f), jnum(f, r->y_end);
    fputs("}, \"collectors\": {", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        fputs(c ? ", " : "", f), jstr(f, s->collectors[c].name), fputs(": ", f);
        json_crossing(f, &r->crossings[c]);
    }
    fputs("}}", f);
}

void rf_traj_write_json(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st,
                        size_t max_traj)
{
    fputs("{\"name\": ", f), jstr(f, s->name ? s->name : "");
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
    fputs("],\n \"statistics\": {\"runout_x\": ", f), jpct(f, &st->runout_x);
    fputs(", \"rebound_height\": ", f), jpct(f, &st->rebound_height);
    fputs(", \"collectors\": {", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        fputs(c ? ", " : "", f), jstr(f, s->collectors[c].name);
        fputs(": {\"reach_probability\": ", f), jnum(f, st->reach_probability[c]);
        fputs(", \"kinetic_energy\": ", f), jpct(f, &st->kinetic_energy[c]);
        fputs(", \"height\": ", f), jpct(f, &st->height[c]);
        fputs(", \"speed\": ", f), jpct(f, &st->speed[c]);
        fputc('}', f);
    }
    fputs("}}", f);
    if (s->law == RF_BOUNCE_IMPACT_MODEL) {
        fprintf(f, ",\n \"impact_table\": {\"solver\": \"%s\", \"nodes_normal_speed\": %zu, \"nodes_incidence\": %zu, "
                   "\"impacts_computed\": %zu, \"impacts_from_cache\": %zu, \"tolerance\": %.6g, \"error_estimate\": ",
                s->impact_solver, e->impact_nodes_vn, e->impact_nodes_theta, e->impact_evaluations,
                e->impact_from_cache, s->impact_tolerance);
        jnum(f, e->impact_error_estimate);
        fputs("}", f);
    }
    fprintf(f, ",\n \"wall_seconds\": %.6g}\n", e->wall_seconds);
}

void rf_traj_write_summary(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st)
{
    fprintf(f, "%s: %zu trajector%s (%s sampling, seed %llu) in %.3g s\n", s->name ? s->name : "trajectory",
            e->samples, e->samples == 1 ? "y" : "ies", s->lhs ? "Latin hypercube" : "random",
            (unsigned long long)s->seed, e->wall_seconds);
    fprintf(f, "  stopped %zu, exited %zu, step_limit %zu\n", st->stopped, st->exited, st->step_limit);
    if (s->law == RF_BOUNCE_IMPACT_MODEL)
        fprintf(f, "  impact_model (%s): table of %zu normal speeds x %zu incidences; %zu impacts computed, %zu from "
                   "the cache; estimated interpolation error of R_n, R_t %.3g (tolerance %g)\n", s->impact_solver,
                e->impact_nodes_vn, e->impact_nodes_theta, e->impact_evaluations, e->impact_from_cache,
                e->impact_error_estimate, s->impact_tolerance);
    if (e->samples == 1 && e->n_recorded) {
        const rf_traj_result *r = &e->recorded[0];
        fprintf(f, "  %s at t = %.6g s, x = %.6g m, y = %.6g m after %zu impact%s\n", rf_traj_state_name(r->state),
                r->t_end, r->x_end, r->y_end, r->n_impacts, r->n_impacts == 1 ? "" : "s");
    } else {
        fprintf(f, "  runout x [m]: p50 %.4g  p95 %.4g  p99 %.4g  max %.4g\n", st->runout_x.p50, st->runout_x.p95,
                st->runout_x.p99, st->runout_x.max);
    }
    for (size_t c = 0; c < s->n_collectors; c++) {
        fprintf(f, "  collector %s (x = %g m): reach probability %.4g\n", s->collectors[c].name, s->collectors[c].x,
                st->reach_probability[c]);
        if (st->reach_probability[c] > 0) {
            const rf_traj_percentiles *k = &st->kinetic_energy[c], *h = &st->height[c];
            fprintf(f, "    energy [kJ]: p50 %.4g  p95 %.4g  p99 %.4g  max %.4g\n", k->p50 / 1e3, k->p95 / 1e3,
                    k->p99 / 1e3, k->max / 1e3);
            fprintf(f, "    height [m]:  p50 %.4g  p95 %.4g  p99 %.4g  max %.4g\n", h->p50, h->p95, h->p99, h->max);
        }
    }
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

static rf_status write_paths(FILE *f, const rf_traj_ensemble *e)
{
    fputs("sample,t_s,x_m,y_m,vx_m_s,vy_m_s,event\n", f);
    static const char *const kinds[] = {"release", "impact", "launch", "contact", "vertex", "rest", "exit",
                                        "step_limit"};
    for (size_t i = 0; i < e->n_recorded; i++) {
        const rf_traj_result *r = &e->recorded[i];
        for (size_t k = 0; k < r->n_events; k++) {
            const rf_traj_event *ev = &r->events[k];
            fprintf(f, "%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%s\n", i, ev->t, ev->x, ev->y, ev->vx, ev->vy, kinds[ev->kind]);
            double t1 = k + 1 < r->n_events ? r->events[k + 1].t : ev->t;
            for (int j = 1; j < 16 && t1 > ev->t; j++) { /* points inside the stretch */
                double d = (t1 - ev->t) * j / 16.0;
                fprintf(f, "%zu,%.9g,%.9g,%.9g,%.9g,%.9g,\n", i, ev->t + d, ev->x + ev->vx * d + 0.5 * ev->ax * d * d,
                        ev->y + ev->vy * d + 0.5 * ev->ay * d * d, ev->vx + ev->ax * d, ev->vy + ev->ay * d);
            }
        }
    }
    return ferror(f) ? RF_EIO : RF_OK;
}

static rf_status write_crossings(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e)
{
    fputs("sample,state,runout_x_m,collector,reached,t_s,height_m,normal_height_m,speed_m_s,kinetic_energy_J,"
          "rotational_energy_J,stopped_by_barrier\n", f);
    for (size_t i = 0; i < e->samples; i++)
        for (size_t c = 0; c < s->n_collectors; c++) {
            const rf_traj_crossing *x = &e->crossings[i * s->n_collectors + c];
            fprintf(f, "%zu,%s,%.9g,%s,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", i, rf_traj_state_name(e->state[i]),
                    e->runout_x[i], s->collectors[c].name, x->reached, x->t, x->height, x->normal_height, x->speed,
                    x->kinetic_energy, x->rotational_energy, x->stopped_by_barrier);
        }
    return ferror(f) ? RF_EIO : RF_OK;
}

static rf_status write_stats(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st)
{
    fputs("quantity,unit,p50,p95,p99,max,mean\n", f);
    const rf_traj_percentiles *r = &st->runout_x;
    fprintf(f, "runout_x,m,%.9g,%.9g,%.9g,%.9g,%.9g\n", r->p50, r->p95, r->p99, r->max, r->mean);
    for (size_t c = 0; c < s->n_collectors; c++) {
        const rf_traj_percentiles *q[3] = {&st->kinetic_energy[c], &st->height[c], &st->speed[c]};
        const char *n[3] = {"kinetic_energy", "height", "speed"}, *u[3] = {"J", "m", "m/s"};
        fprintf(f, "%s.reach_probability,-,%.9g,,,,\n", s->collectors[c].name, st->reach_probability[c]);
        for (int k = 0; k < 3; k++)
            fprintf(f, "%s.%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g\n", s->collectors[c].name, n[k], u[k], q[k]->p50, q[k]->p95,
                    q[k]->p99, q[k]->max, q[k]->mean);
    }
    return ferror(f) ? RF_EIO : RF_OK;
}

rf_status rf_traj_write_csv(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                            const rf_traj_stats *st, rf_error *err)
{
    const char *names[3] = {"trajectories.csv", "crossings.csv", "statistics.csv"};
    for (int k = 0; k < 3; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        FILE *f = fopen(path, "w");
        if (!f)
            return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
        rf_status rc = k == 0 ? write_paths(f, e) : k == 1 ? write_crossings(f, s, e) : write_stats(f, s, st);
        if (fclose(f) != 0 || rc != RF_OK)
            return rf_fail(err, RF_EIO, "cannot write %s", path);
    }
    return traj_write_envelopes_csv(dir, e, err); /* envelope.c */
}
