/* terrain_output.c - what `rockfuzz trajectory` writes for a terrain file:
 * the JSON document (docs/terrain.md; SI units named in its "units" object,
 * angles in degrees), the readable summary (the answer first; energies in
 * kJ); the run folder is terrain_files.c's.  The JSON pieces shared with
 * the profile document come from traj_output.c. */
#include "trajectory/terrain_internal.h"
#include "trajectory/traj_rolling.h"
#include "trajectory/block_traj.h"
#include "core/json.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG (180.0 / 3.14159265358979323846) /* degrees per radian */

static void json_point(FILE *f, const char *key, double t, const double p[3])
{
    fprintf(f, "\"%s\": {\"t\": ", key), rf_json_number(f, t);
    fputs(", \"x\": ", f), rf_json_number(f, p[0]);
    fputs(", \"y\": ", f), rf_json_number(f, p[1]);
    fputs(", \"z\": ", f), rf_json_number(f, p[2]);
    fputc('}', f);
}

static const char *material_name(const rf_traj_spec *s, size_t m)
{
    return m < s->n_materials && s->materials[m].name ? s->materials[m].name : "?";
}

static void json_impacts(FILE *f, const rf_traj_spec *s, const rf_terrain_result *r)
{
    fputs("\"impacts\": [", f);
    for (size_t i = 0; i < r->n_impacts && r->impacts; i++) {
        const rf_terrain_impact *m = &r->impacts[i];
        fprintf(f, "%s{\"t\": ", i ? ", " : ""), rf_json_number(f, m->t);
        fputs(", \"x\": ", f), rf_json_number(f, m->x);
        fputs(", \"y\": ", f), rf_json_number(f, m->y);
        fputs(", \"z\": ", f), rf_json_number(f, m->z);
        fputs(", \"v_in\": ", f), rf_json_array(f, m->v_in, 3, 1);
        fputs(", \"v_out\": ", f), rf_json_array(f, m->v_out, 3, 1);
        fputs(", \"omega_out\": ", f), rf_json_array(f, m->omega_out, 3, 1);
        fputs(", \"class\": ", f), rf_json_string(f, material_name(s, m->material));
        if (s->block_kind != RF_TRAJ_BLOCK_NONE) /* a rigid block (block_traj_output.c) */
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
    const char *k[12] = {"t", "x", "y", "along", "height_lowest", "height_centre", "normal_height", "speed",
                         "translational_energy", "rotational_energy", "total_energy", "energy_after"};
    double v[12] = {c->t, c->x, c->y, c->along, c->height_lowest, c->height_centre, c->normal_height, c->speed,
                    c->translational_energy, c->rotational_energy, c->total_energy, c->energy_after};
    for (int i = 0; i < 12; i++)
        fprintf(f, "%s\"%s\": ", i ? ", " : "{", k[i]), rf_json_number(f, v[i]);
    fprintf(f, ", \"stopped_by_barrier\": %s}", c->stopped_by_barrier ? "true" : "false");
}

static void json_trajectory(FILE *f, const rf_traj_spec *s, size_t sample, const rf_terrain_result *r)
{
    fprintf(f, "{\"sample\": %zu, \"state\": \"%s\", \"n_impacts\": %zu, \"start\": ", sample,
            rf_traj_state_name(r->state), r->n_impacts);
    rf_json_array(f, r->start, 3, 1);
    fputs(", ", f);
    json_impacts(f, s, r);
    if (s->block_kind != RF_TRAJ_BLOCK_NONE)
        terrain_block_json_orientation(f, r);
    fputs(", ", f);
    if (r->state == RF_TRAJ_STOPPED)
        json_point(f, "rest", r->t_end, r->end);
    else
        fputs("\"rest\": null", f);
    fputs(", ", f), json_point(f, "end", r->t_end, r->end);
    fputs(", \"runout\": ", f), rf_json_number(f, r->runout);
    fputs(", \"reach_angle\": ", f), rf_json_number(f, r->reach_angle * DEG);
    fputs(", \"barriers\": {", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        fputs(c ? ", " : "", f), rf_json_string(f, s->collectors[c].name), fputs(": ", f);
        json_crossing(f, &r->crossings[c]);
    }
    fputs("}}", f);
}

/* Percentiles scaled (radians to degrees for the reach angle). */
static rf_traj_percentiles scaled(rf_traj_percentiles p, double k)
{
    p.p50 *= k, p.p95 *= k, p.p99 *= k, p.max *= k, p.mean *= k;
    for (size_t i = 0; i < p.n; i++)
        p.value[i] *= k;
    return p;
}

/* How many samples a barrier held. */
static size_t held_by(const rf_traj_ensemble *e, size_t c)
{
    size_t n = 0;
    for (size_t i = 0; i < e->samples; i++)
        n += e->crossings[i * e->n_collectors + c].stopped_by_barrier != 0;
    return n;
}

static void json_statistics(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st)
{
    rf_traj_percentiles ra = scaled(st->reach_angle, DEG);
    fputs("{\"runout\": ", f), traj_json_percentiles(f, &st->runout_x);
    fputs(", \"reach_angle\": ", f), traj_json_percentiles(f, &ra);
    fputs(", \"rebound_height\": ", f), traj_json_percentiles(f, &st->rebound_height);
    fputs(", \"p_runout_above\": ", f);
    traj_json_exceed(f, s->outputs.runout_thresholds, st->p_runout_above, s->outputs.n_runout_thresholds, 0);
    fputs(",\n  \"runout_histogram\": ", f), traj_json_histogram(f, &st->runout_histogram);
    fputs(",\n  \"barriers\": {", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        fputs(c ? ",\n   " : "", f);
        traj_json_collector_stats(f, &s->collectors[c], &st->collectors[c]);
    }
    fputs("},\n  \"held_by_barrier\": {", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        fputs(c ? ", " : "", f), rf_json_string(f, s->collectors[c].name);
        fprintf(f, ": %zu", held_by(e, c));
    }
    fputs("}}", f);
}

void rf_terrain_write_json(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st,
                           size_t max_traj)
{
    fputs("{\"name\": ", f), rf_json_string(f, s->name ? s->name : "");
    fprintf(f, ", \"kind\": \"terrain\", \"samples\": %zu, \"seed\": %llu, \"sampling\": \"%s\", \"units\": "
               "{\"length\": \"m\", \"time\": \"s\", \"speed\": \"m/s\", \"energy\": \"J\", \"omega\": \"rad/s\", "
               "\"angle\": \"deg\"},\n", e->samples, (unsigned long long)s->seed, s->lhs ? "lhs" : "random");
    fprintf(f, " \"states\": {\"stopped\": %zu, \"exited\": %zu, \"step_limit\": %zu},\n", st->stopped, st->exited,
            st->step_limit);
    const rf_terrain_samples *t = e->terrain;
    size_t n = !t ? 0 : t->n_recorded < max_traj ? t->n_recorded : max_traj;
    fprintf(f, " \"trajectories_shown\": %zu,\n \"trajectories\": [", n);
    for (size_t i = 0; i < n; i++) {
        fputs(i ? ",\n  " : "\n  ", f);
        json_trajectory(f, s, i, &t->recorded[i]);
    }
    fputs("],\n \"statistics\": ", f);
    json_statistics(f, s, e, st);
    if (s->law == RF_BOUNCE_IMPACT_MODEL)
        traj_rolling_json(f, s);
    fprintf(f, ",\n \"wall_seconds\": %.6g}\n", e->wall_seconds);
}

/* "  fence: reached by 12 % of the blocks, held 3 %; energy p95 850 kJ, ..." */
static void summary_barrier(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st,
                            size_t c)
{
    const rf_traj_collector *col = &s->collectors[c];
    const rf_traj_collector_stats *cs = &st->collectors[c];
    double N = e->samples ? (double)e->samples : 1;
    fprintf(f, "  barrier %s: reached by %.4g %% of the blocks", col->name, 100 * cs->reach_probability);
    if (col->capacity > 0)
        fprintf(f, ", held %.4g %%", 100 * (double)held_by(e, c) / N);
    if (cs->reach_probability > 0)
        fprintf(f, "; energy p95 %.4g kJ, passing height p95 %.4g m (lowest point)", 1e-3 * cs->total_energy.p95,
                cs->height_lowest.p95);
    fputc('\n', f);
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own;
    size_t n = rf_traj_thresholds(col, 0, t, &own);
    traj_summary_exceed(f, "total energy", "kJ", t, cs->p_energy_above, n, own, ", the capacity", 1e-3);
    n = rf_traj_thresholds(col, 1, t, &own);
    traj_summary_exceed(f, "height lowest point", "m", t, cs->p_height_above, n, own, ", the barrier height", 1);
}

/* The reach angle's low tail (the far-reaching blocks): p5 and p50 [deg]. */
static void summary_reach(FILE *f, const rf_traj_ensemble *e)
{
    const rf_terrain_samples *t = e->terrain;
    double *deg = t ? malloc((e->samples ? e->samples : 1) * sizeof *deg) : NULL;
    if (!deg)
        return;
    for (size_t i = 0; i < e->samples; i++)
        deg[i] = t->reach_angle[i] * DEG;
    const double lv[2] = {5, 50};
    rf_traj_percentiles p = rf_traj_percentiles_at(deg, e->samples, lv, 2);
    fprintf(f, "  reach angle (Fahrboeschung) [deg]: p5 %.4g, p50 %.4g (5 %% of the blocks reach farther than "
               "a line at %.4g deg below their release)\n", p.value[0], p.value[1], p.value[0]);
    free(deg);
}

void rf_terrain_write_summary(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st)
{
    double N = e->samples ? (double)e->samples : 1;
    fprintf(f, "%s: %zu block%s on terrain (%s sampling, seed %llu) in %.3g s\n", s->name ? s->name : "terrain",
            e->samples, e->samples == 1 ? "" : "s", s->lhs ? "Latin hypercube" : "random",
            (unsigned long long)s->seed, e->wall_seconds);
    fprintf(f, "  %.4g %% stop (%zu), %.4g %% leave the DEM (%zu), %.4g %% reach the step limit (%zu)\n",
            100 * (double)st->stopped / N, st->stopped, 100 * (double)st->exited / N, st->exited,
            100 * (double)st->step_limit / N, st->step_limit);
    fprintf(f, "  runout (horizontal, release to end) [m]: p50 %.4g, p95 %.4g, max %.4g\n", st->runout_x.p50,
            st->runout_x.p95, st->runout_x.max);
    summary_reach(f, e);
    if (s->law == RF_BOUNCE_IMPACT_MODEL)
        traj_rolling_summary(f, s);
    for (size_t c = 0; c < s->n_collectors; c++)
        summary_barrier(f, s, e, st, c);
    fprintf(f, "  units: energy kJ, lengths and heights m; barrier statistics over the blocks that reach it, "
               "probabilities over all blocks\n");
    traj_summary_row(f, 2, "runout [m]", &st->runout_x, 1);
    traj_summary_row(f, 2, "rebound height [m]", &st->rebound_height, 1);
    traj_summary_exceed(f, "runout", "m", s->outputs.runout_thresholds, st->p_runout_above,
                        s->outputs.n_runout_thresholds, 0, NULL, 1);
}
