/* bench_impact_law.c - the `impact_model` bounce law's speed against the
 * `constant` law (issue 29 "Speed": trajectories per second with
 * impact_model within 2x of constant), on the 30-segment profile of
 * examples/trajectory/slope.yaml (a sphere of 0.5 m, its random restitution
 * and roughness, Latin hypercube):
 *   constant        the file as written;
 *   impact_model 1  one shared table (bounce.impact, solver rigid);
 *   impact_model 3  a table per material: rock, talus and soil each name an
 *                   impact model of their own (mdr on granite, on a 2 GPa
 *                   and on a 300 MPa ground), the road the run's rigid one.
 * Every table is built before the timing (its CPU time and impacts printed:
 * the "time to build the tables of a three-material terrain" with a cheap
 * solver), then the same samples run at 1 thread; CPU time is the figure to
 * compare on a shared machine.  Then the lookup alone (ns per call, the
 * 3-material table at random (v_n, incidence)), to see what a bounce costs.
 * Usage: bench_impact_law [samples (default 20000)] [file] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/textfile.h"
#include "trajectory/traj_internal.h"
#include "bench_util.h"

/* text with the first `from` replaced by `to` (fails loudly when absent). */
static char *replaced(const char *text, const char *from, const char *to)
{
    const char *at = strstr(text, from);
    if (!at) {
        fprintf(stderr, "bench_impact_law: '%s' not in the file\n", from);
        exit(1);
    }
    size_t n = strlen(text) - strlen(from) + strlen(to) + 1;
    char *out = malloc(n);
    if (!out)
        exit(1);
    snprintf(out, n, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
    return out;
}

static char *replace_in(char *text, const char *from, const char *to)
{
    char *out = replaced(text, from, to);
    free(text);
    return out;
}

static void load(const char *name, const char *text, rf_traj_spec *s)
{
    rf_error err;
    if (rf_traj_load_buffer(name, text, strlen(text), s, &err) != RF_OK) {
        fprintf(stderr, "bench_impact_law: %s\n", err.msg);
        exit(1);
    }
}

/* Mean impacts and events per trajectory over the first (up to) 2000 samples, recorded (untimed). */
static void per_trajectory(const rf_traj_spec *s, void *t, double *impacts, double *events)
{
    rf_traj_spec r;
    rf_traj_ensemble e;
    rf_error err;
    if (rf_traj_spec_copy(s, &r, &err) != RF_OK)
        exit(1);
    r.samples = r.record = s->samples < 2000 ? s->samples : 2000;
    if (traj_run_with(&r, 1, t, 0, &e, &err) != RF_OK) {
        fprintf(stderr, "bench_impact_law: %s\n", err.msg);
        exit(1);
    }
    size_t ni = 0, ne = 0;
    for (size_t k = 0; k < e.n_recorded; k++)
        ni += e.recorded[k].n_impacts, ne += e.recorded[k].n_events;
    *impacts = (double)ni / (double)e.n_recorded, *events = (double)ne / (double)e.n_recorded;
    rf_traj_ensemble_free(&e);
    rf_traj_spec_free(&r);
}

/* The samples at 1 thread on table t (NULL: the constant law); the CPU rate
 * (trajectories per second per core); *per_impact: CPU seconds per impact. */
static double run(const char *label, const rf_traj_spec *s, void *t, double *per_impact)
{
    rf_traj_ensemble e;
    rf_traj_stats st;
    rf_error err;
    double c0 = cpu_now();
    if (traj_run_with(s, 1, t, 0, &e, &err) != RF_OK) {
        fprintf(stderr, "bench_impact_law: %s: %s\n", label, err.msg);
        exit(1);
    }
    double cpu = cpu_now() - c0;
    if (rf_traj_stats_compute(&e, &st, &err) != RF_OK)
        exit(1);
    double rate = (double)s->samples / cpu, ni, ne;
    per_trajectory(s, t, &ni, &ne);
    *per_impact = cpu / ((double)s->samples * ni);
    printf("%-28s %zu trajectories: CPU %.3f s -> %.0f per second per core; %.1f impacts, %.1f events a "
           "trajectory: %.2f us per impact (runout p50 %.1f m, p95 %.1f m, stopped %zu, exited %zu)\n",
           label, s->samples, cpu, rate, ni, ne, 1e6 * *per_impact, st.runout_x.p50, st.runout_x.p95, st.stopped,
           st.exited);
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&e);
    return rate;
}

static traj_impact_table *table(const char *label, const rf_traj_spec *s)
{
    traj_impact_table *t;
    rf_error err;
    double c0 = cpu_now();
    if (traj_impact_table_build(s, &t, &err) != RF_OK) {
        fprintf(stderr, "bench_impact_law: %s: %s\n", label, err.msg);
        exit(1);
    }
    double cpu = cpu_now() - c0;
    size_t nv, nt, evals, cached;
    double est;
    traj_impact_table_info(t, &nv, &nt, &evals, &cached, &est);
    printf("table %-24s %zu grid%s, %zu impacts of the model, CPU %.3f s (%.1f us per impact), error estimate "
           "%.3g\n", label, traj_impact_table_grids(t), traj_impact_table_grids(t) == 1 ? "" : "s", evals, cpu,
           evals ? 1e6 * cpu / (double)evals : 0, est);
    return t;
}

/* ns per lookup at random (v_n, incidence) over the table's box, every material. */
static void lookups(const rf_traj_spec *s, const traj_impact_table *t)
{
    const size_t n = 4000000;
    double sum = 0, c0 = cpu_now();
    for (size_t i = 0; i < n; i++) {
        double vn = s->impact_speed_min * pow(s->impact_speed_max / s->impact_speed_min, rf_traj_uniform(9, 0, i));
        double th = s->impact_max_incidence * rf_traj_uniform(9, 1, i), rn, rt, sp;
        traj_impact_table_lookup(t, i % s->n_materials, s->radius, vn, th, &rn, &rt, &sp);
        sum += rn + rt + sp;
    }
    double cpu = cpu_now() - c0;
    double c1 = cpu_now(), sum0 = 0; /* the same loop without the lookup: the draws' own cost */
    for (size_t i = 0; i < n; i++) {
        double vn = s->impact_speed_min * pow(s->impact_speed_max / s->impact_speed_min, rf_traj_uniform(9, 0, i));
        sum0 += vn + s->impact_max_incidence * rf_traj_uniform(9, 1, i);
    }
    double base = cpu_now() - c1;
    printf("lookup: %.1f ns per call (%.1f ns with the draws, %.1f ns the draws alone; checksum %.6g %.6g)\n",
           1e9 * (cpu - base) / (double)n, 1e9 * cpu / (double)n, 1e9 * base / (double)n, sum, sum0);
}

int main(int argc, char **argv)
{
    size_t samples = argc > 1 ? (size_t)atol(argv[1]) : 20000;
    const char *file = argc > 2 ? argv[2] : "examples/trajectory/slope.yaml";
    char *text;
    size_t len;
    rf_error err;
    if (rf_read_text_file(file, "trajectory file", 1 << 20, &text, &len, &err) != RF_OK) {
        fprintf(stderr, "bench_impact_law: %s\n", err.msg);
        return 1;
    }
    const char *law = "bounce: {law: impact_model, impact: {solver: rigid, tolerance: 0.01}}";
    char *one = replaced(text, "bounce: {law: constant}", law);
    char *three = replaced(one, "friction_angle: 30, roughness: 4}",
                           "friction_angle: 30, roughness: 4, impact: {solver: mdr}}");
    three = replace_in(three, "friction_angle: 32, roughness: 6, rolling_resistance: 0.25}",
                       "friction_angle: 32, roughness: 6, rolling_resistance: 0.25, "
                       "impact: {solver: mdr, slope_E: 2e9, slope_density: 2000, slope_poisson: 0.3}}");
    three = replace_in(three, "friction_angle: 35, roughness: 3, rolling_resistance: 0.4}",
                       "friction_angle: 35, roughness: 3, rolling_resistance: 0.4, "
                       "impact: {solver: mdr, slope_E: 300e6, slope_density: 1900, slope_poisson: 0.3}}");
    rf_traj_spec sc, s1, s3;
    load(file, text, &sc), load(file, one, &s1), load(file, three, &s3);
    sc.samples = s1.samples = s3.samples = samples;
    sc.record = s1.record = s3.record = 0;
    double load1 = 0;
    FILE *la = fopen("/proc/loadavg", "r");
    if (la && fscanf(la, "%lf", &load1) != 1)
        load1 = NAN;
    if (la)
        fclose(la);
    printf("profile %s: %zu segments, sphere r %.2f m, %zu materials; load %.1f\n", file, sc.n_points - 1,
           sc.radius, sc.n_materials, load1);
    traj_impact_table *t1 = table("rigid, shared", &s1), *t3 = table("3 materials (mdr) + rigid", &s3);
    double ic, ic2, i1, i3;
    double rc = run("constant", &sc, NULL, &ic);
    double r1 = run("impact_model, 1 table", &s1, t1, &i1);
    double r3 = run("impact_model, 3 materials", &s3, t3, &i3);
    rc = fmax(rc, run("constant (again)", &sc, NULL, &ic2)), ic = fmin(ic, ic2);
    printf("trajectories per second, constant / impact_model: %.2f (1 table), %.2f (3 materials); target <= 2\n"
           "CPU per impact, impact_model / constant: %.2f (1 table), %.2f (3 materials) (the laws' trajectories "
           "differ: this is the like-for-like figure)\n", rc / r1, rc / r3, i1 / ic, i3 / ic);
    lookups(&s3, t3);
    traj_impact_table_free(t1), traj_impact_table_free(t3);
    rf_traj_spec_free(&sc), rf_traj_spec_free(&s1), rf_traj_spec_free(&s3);
    free(three), free(one), free(text);
    return 0;
}
