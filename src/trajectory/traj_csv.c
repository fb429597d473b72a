/* traj_csv.c - the trajectory CSV files.  Read: a slope profile, one vertex
 * per line, "x,y" or "x,y,material" (metres; the material names one of the
 * spec's materials and applies to the segment starting at that vertex).
 * Blank lines and lines starting with '#' are skipped, and so is a first line
 * that is not numeric (a header).  Errors name the file, line and value.
 * Written (rf_traj_write_csv): recorded paths, every sample's end point and
 * collector crossings, statistics, exceedance probabilities and the runout
 * histogram; every header names its unit. */
#include "trajectory/traj_internal.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double *x, *y;
    size_t *mat;
    size_t n, cap;
} csv_rows;

static int push(csv_rows *r, double x, double y, size_t m)
{
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 64;
        double *px = realloc(r->x, cap * sizeof *px);
        if (px) r->x = px;
        double *py = realloc(r->y, cap * sizeof *py);
        if (py) r->y = py;
        size_t *pm = realloc(r->mat, cap * sizeof *pm);
        if (pm) r->mat = pm;
        if (!px || !py || !pm)
            return 0;
        r->cap = cap;
    }
    r->x[r->n] = x, r->y[r->n] = y, r->mat[r->n++] = m;
    return 1;
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1]))
        s[--n] = '\0';
    return s;
}

/* Parse one data line; returns 1 ok, 0 not numeric, -1 unknown material. */
static int parse_line(const rf_traj_spec *s, char *line, double *x, double *y, size_t *m, int *named, char **bad)
{
    char *f[3] = {NULL, NULL, NULL};
    int nf = 0;
    for (char *tok = strtok(line, ",;\t"); tok && nf < 3; tok = strtok(NULL, ",;\t"))
        f[nf++] = trim(tok);
    if (nf < 2)
        return 0;
    char *end;
    *x = strtod(f[0], &end);
    if (end == f[0] || *end)
        return 0;
    *y = strtod(f[1], &end);
    if (end == f[1] || *end)
        return 0;
    *m = 0;
    if (nf == 3 && *f[2]) {
        *named = 1;
        for (*m = 0; *m < s->n_materials && strcmp(s->materials[*m].name, f[2]); (*m)++)
            ;
        if (*m == s->n_materials) {
            *bad = f[2];
            return -1;
        }
    }
    return 1;
}

rf_status traj_csv_read(const char *path, rf_traj_spec *s, int *named, rf_error *err)
{
    FILE *fp = fopen(path, "r");
    if (!fp)
        return rf_fail(err, RF_EIO, "cannot open the profile CSV '%s': %s", path, strerror(errno));
    csv_rows r = {0};
    char line[4096];
    int lineno = 0, data = 0;
    rf_status st = RF_OK;
    *named = 0;
    while (st == RF_OK && fgets(line, sizeof line, fp)) {
        lineno++;
        char *t = trim(line), *bad = NULL;
        if (!*t || *t == '#')
            continue;
        double x, y;
        size_t m;
        int ok = parse_line(s, t, &x, &y, &m, named, &bad);
        if (ok == 0 && data == 0 && lineno == 1)
            continue; /* header */
        if (ok == 0)
            st = rf_fail(err, RF_EINVAL, "%s:%d: expected x,y[,material] with numbers x, y [m]", path, lineno);
        else if (ok < 0)
            st = rf_fail(err, RF_EINVAL, "%s:%d: material = %s: no such material", path, lineno, bad);
        else if (!push(&r, x, y, m))
            st = rf_fail(err, RF_ENOMEM, "out of memory");
        data++;
    }
    fclose(fp);
    if (st == RF_OK && r.n < 2)
        st = rf_fail(err, RF_EINVAL, "%s: %zu points; a profile needs at least 2", path, r.n);
    if (st != RF_OK) {
        free(r.x), free(r.y), free(r.mat);
        return st;
    }
    free(s->px), free(s->py), free(s->seg_material);
    s->px = r.x, s->py = r.y, s->seg_material = r.mat, s->n_points = r.n;
    return RF_OK;
}

rf_status rf_traj_profile_read_csv(const char *path, rf_traj_spec *s, rf_error *err)
{
    int named;
    return traj_csv_read(path, s, &named, err);
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

static void stats_row(FILE *f, const char *c, const char *what, const char *unit, const rf_traj_percentiles *p)
{
    fprintf(f, "%s%s%s,%s", c ? c : "", c ? "." : "", what, unit);
    for (size_t k = 0; k < p->n; k++)
        fprintf(f, ",%.9g", p->value[k]);
    fprintf(f, ",%.9g,%.9g\n", p->max, p->mean);
}

/* One row per quantity: its percentiles at the chosen levels, max, mean. */
static rf_status write_stats(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st)
{
    char name[32];
    fputs("quantity,unit", f);
    for (size_t k = 0; k < st->runout_x.n; k++)
        rf_traj_percentile_name(st->runout_x.level[k], name, sizeof name), fprintf(f, ",%s", name);
    fputs(",max,mean\n", f);
    stats_row(f, NULL, "runout_x", "m", &st->runout_x);
    stats_row(f, NULL, "rebound_height", "m", &st->rebound_height);
    for (size_t c = 0; c < s->n_collectors; c++) {
        const rf_traj_collector_stats *cs = &st->collectors[c];
        const char *n = s->collectors[c].name;
        fprintf(f, "%s.reach_probability,-,%.9g", n, cs->reach_probability);
        for (size_t k = 0; k <= st->runout_x.n; k++)
            fputc(',', f);
        fputc('\n', f);
        stats_row(f, n, "total_energy", "J", &cs->total_energy);
        stats_row(f, n, "translational_energy", "J", &cs->translational_energy);
        stats_row(f, n, "rotational_energy", "J", &cs->rotational_energy);
        stats_row(f, n, "height_lowest", "m", &cs->height_lowest);
        stats_row(f, n, "height_centre", "m", &cs->height_centre);
        stats_row(f, n, "speed", "m/s", &cs->speed);
    }
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
        rf_status rc = k == 0 ? write_paths(f, e) : k == 1 ? write_samples(f, e) : k == 2 ? write_crossings(f, s, e)
                     : k == 3 ? write_stats(f, s, st) : k == 4 ? write_exceedance(f, s, st) : write_histogram(f, st);
        if (fclose(f) != 0 || rc != RF_OK)
            return rf_fail(err, RF_EIO, "cannot write %s", path);
    }
    return traj_write_envelopes_csv(dir, e, err); /* envelope.c */
}
