/* traj_csv.c - the trajectory CSV files written (rf_traj_write_csv; the
 * profile CSV is read by profile_csv.c): recorded paths, every sample's end point and
 * collector crossings, statistics, exceedance probabilities and the runout
 * histogram; every header names its unit. */
#include "trajectory/traj_internal.h"
#include "trajectory/block_traj.h"
#include "core/fmt.h"

#include <ctype.h>
#include <math.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATH_CHORD_M 0.01 /* [m] trajectories.csv: largest distance of the drawn path from the exact one */

/* One row of trajectories.csv: "i,t,x,y,vx,vy,kind" with the numbers as "%.9g" (rf_fmt_g: the same bytes,
 * without printf's cost, which was most of the outputs' time); a rigid block (q != NULL) adds its
 * orientation ",qw,qx,qy,qz" after the kind. */
static void path_row(FILE *f, size_t i, const double *v, const char *kind, const double *q)
{
    char row[24 + 9 * RF_FMT_G_MAX + 16];
    size_t n = (size_t)snprintf(row, 24, "%zu", i);
    for (int k = 0; k < 5; k++) {
        row[n++] = ',';
        n += rf_fmt_g(row + n, v[k], 9);
    }
    row[n++] = ',';
    fwrite(row, 1, n, f);
    fputs(kind, f);
    n = 0;
    for (int k = 0; q && k < 4; k++) {
        row[n++] = ',';
        n += rf_fmt_g(row + n, q[k], 9);
    }
    row[n++] = '\n';
    fwrite(row, 1, n, f);
}

/* A block's orientation d after event ev: on a profile the spin is about y in space and constant in
 * flight, so q(d) = rot_y(omega d) q (a contact stretch has no points inside). */
static void turned(const rf_traj_event *ev, double d, double q[4])
{
    double c = cos(0.5 * ev->omega * d), s = sin(0.5 * ev->omega * d);
    const double *p = ev->q; /* (c, 0, s, 0) * p */
    q[0] = c * p[0] - s * p[2], q[1] = c * p[1] + s * p[3], q[2] = c * p[2] + s * p[0], q[3] = c * p[3] - s * p[1];
}

static rf_status write_paths(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e)
{
    int block = s->block_kind != 0;
    fputs(block ? "sample,t_s,x_m,y_m,vx_m_s,vy_m_s,event,q_w,q_x,q_y,q_z\n" : "sample,t_s,x_m,y_m,vx_m_s,vy_m_s,event\n",
          f);
    static const char *const kinds[] = {"release", "impact", "launch", "contact", "vertex", "rest", "exit",
                                        "step_limit"};
    for (size_t i = 0; i < e->n_recorded; i++) {
        const rf_traj_result *r = &e->recorded[i];
        for (size_t k = 0; k < r->n_events; k++) {
            const rf_traj_event *ev = &r->events[k];
            path_row(f, i, (const double[]){ev->t, ev->x, ev->y, ev->vx, ev->vy}, kinds[ev->kind],
                     block ? ev->q : NULL);
            double t1 = k + 1 < r->n_events ? r->events[k + 1].t : ev->t;
            /* Points inside a flight, so that the polyline is within PATH_CHORD_M of the parabola (its
             * chord error over a time h is |a_y| h^2 / 8), at most 15; a contact stretch runs straight
             * along its segment: its ends draw it. */
            double T = t1 - ev->t, parts = ev->flying ? ceil(T * sqrt(fabs(ev->ay) / (8 * PATH_CHORD_M))) : 1;
            int n = parts < 16 ? (int)parts : 16;
            for (int j = 1; j < n && T > 0; j++) {
                double d = T * j / n, q[4];
                if (block)
                    turned(ev, d, q);
                path_row(f, i, (const double[]){ev->t + d, ev->x + ev->vx * d + 0.5 * ev->ax * d * d,
                                                ev->y + ev->vy * d + 0.5 * ev->ay * d * d, ev->vx + ev->ax * d,
                                                ev->vy + ev->ay * d}, "", block ? q : NULL);
            }
        }
    }
    return ferror(f) ? RF_EIO : RF_OK;
}

static rf_status write_samples(FILE *f, const rf_traj_ensemble *e)
{
    fputs("sample,state,runout_x_m,rebound_height_m\n", f);
    for (size_t i = 0; i < e->samples; i++)
        fprintf(f, "%zu,%s,%.17g,%.17g\n", i, rf_traj_state_name(e->state[i]), e->runout_x[i], e->rebound_height[i]);
    return ferror(f) ? RF_EIO : RF_OK;
}

static rf_status write_crossings(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e)
{
    fputs("sample,state,runout_x_m,collector,reached,t_s,height_lowest_m,height_centre_m,normal_height_m,speed_m_s,"
          "translational_energy_J,rotational_energy_J,total_energy_J,stopped_by_barrier\n", f);
    for (size_t i = 0; i < e->samples; i++)
        for (size_t c = 0; c < s->n_collectors; c++) {
            const rf_traj_crossing *x = &e->crossings[i * s->n_collectors + c];
            fprintf(f, "%zu,%s,%.17g,%s,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n", i,
                    rf_traj_state_name(e->state[i]), e->runout_x[i], s->collectors[c].name, x->reached, x->t,
                    x->height_lowest, x->height_centre, x->normal_height, x->speed, x->translational_energy,
                    x->rotational_energy, x->total_energy, x->stopped_by_barrier);
        }
    return ferror(f) ? RF_EIO : RF_OK;
}

void traj_stats_row(FILE *f, const char *c, const char *what, const char *unit, const rf_traj_percentiles *p,
                    double scale)
{
    fprintf(f, "%s%s%s,%s", c ? c : "", c ? "." : "", what, unit);
    for (size_t k = 0; k < p->n; k++)
        fprintf(f, ",%.9g", p->value[k] * scale);
    fprintf(f, ",%.9g,%.9g\n", p->max * scale, p->mean * scale);
}

void traj_stats_header(FILE *f, const rf_traj_stats *st)
{
    char name[32];
    fputs("quantity,unit", f);
    for (size_t k = 0; k < st->runout_x.n; k++)
        rf_traj_percentile_name(st->runout_x.level[k], name, sizeof name), fprintf(f, ",%s", name);
    fputs(",max,mean\n", f);
}

void traj_stats_collectors(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st)
{
    for (size_t c = 0; c < s->n_collectors; c++) {
        const rf_traj_collector_stats *cs = &st->collectors[c];
        const char *n = s->collectors[c].name;
        fprintf(f, "%s.reach_probability,-,%.9g", n, cs->reach_probability);
        for (size_t k = 0; k <= st->runout_x.n; k++)
            fputc(',', f);
        fputc('\n', f);
        traj_stats_row(f, n, "total_energy", "J", &cs->total_energy, 1);
        traj_stats_row(f, n, "translational_energy", "J", &cs->translational_energy, 1);
        traj_stats_row(f, n, "rotational_energy", "J", &cs->rotational_energy, 1);
        traj_stats_row(f, n, "height_lowest", "m", &cs->height_lowest, 1);
        traj_stats_row(f, n, "height_centre", "m", &cs->height_centre, 1);
        traj_stats_row(f, n, "speed", "m/s", &cs->speed, 1);
    }
}

/* One row per quantity: its percentiles at the chosen levels, max, mean. */
static rf_status write_stats(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st)
{
    traj_stats_header(f, st);
    traj_stats_row(f, NULL, "runout_x", "m", &st->runout_x, 1);
    traj_stats_row(f, NULL, "rebound_height", "m", &st->rebound_height, 1);
    traj_stats_collectors(f, s, st);
    return ferror(f) ? RF_EIO : RF_OK;
}

/* quantity,threshold,unit,source,probability: P(quantity > threshold) over all samples. */
static rf_status write_exceedance(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st)
{
    fputs("quantity,threshold,unit,source,probability\n", f);
    for (size_t k = 0; k < s->outputs.n_runout_thresholds; k++)
        fprintf(f, "runout_x,%.9g,m,user,%.9g\n", s->outputs.runout_thresholds[k], st->p_runout_above[k]);
    for (size_t c = 0; c < s->n_collectors; c++) {
        double t[RF_TRAJ_MAX_THRESHOLDS];
        int own;
        size_t n = rf_traj_thresholds(&s->collectors[c], 0, t, &own);
        for (size_t k = 0; k < n; k++)
            fprintf(f, "%s.total_energy,%.9g,J,%s,%.9g\n", s->collectors[c].name, t[k],
                    own && !k ? "capacity" : "user", st->collectors[c].p_energy_above[k]);
        n = rf_traj_thresholds(&s->collectors[c], 1, t, &own);
        for (size_t k = 0; k < n; k++)
            fprintf(f, "%s.height_lowest,%.9g,m,%s,%.9g\n", s->collectors[c].name, t[k],
                    own && !k ? "barrier_height" : "user", st->collectors[c].p_height_above[k]);
    }
    return ferror(f) ? RF_EIO : RF_OK;
}

static rf_status write_histogram(FILE *f, const rf_traj_stats *st)
{
    const rf_traj_histogram *h = &st->runout_histogram;
    fputs("bin,runout_x_from_m,runout_x_to_m,count\n", f);
    for (size_t k = 0; k < h->bins; k++)
        fprintf(f, "%zu,%.9g,%.9g,%zu\n", k, h->edge[k], h->edge[k + 1], h->count[k]);
    return ferror(f) ? RF_EIO : RF_OK;
}

rf_status rf_traj_write_csv(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                            const rf_traj_stats *st, rf_error *err)
{
    static const char *const names[6] = {"trajectories.csv", "samples.csv", "crossings.csv", "statistics.csv",
                                         "exceedance.csv", "runout_histogram.csv"};
    for (int k = 0; k < 6; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        FILE *f = fopen(path, "w");
        if (!f)
            return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
        rf_status rc = k == 0 ? write_paths(f, s, e) : k == 1 ? write_samples(f, e) : k == 2 ? write_crossings(f, s, e)
                     : k == 3 ? write_stats(f, s, st) : k == 4 ? write_exceedance(f, s, st) : write_histogram(f, st);
        if (fclose(f) != 0 || rc != RF_OK)
            return rf_fail(err, RF_EIO, "cannot write %s", path);
    }
    rf_status rc = traj_write_envelopes_csv(dir, e, err); /* envelope.c */
    return rc == RF_OK ? traj_block_write_vtk_runs(dir, s, e, err) : rc; /* a rigid block: block_traj_vtk.c */
}
