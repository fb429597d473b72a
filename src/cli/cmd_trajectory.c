/* cmd_trajectory.c - `rockfuzz trajectory FILE.yaml`: one trajectory file
 * run (a single deterministic trajectory when nothing is random, else the
 * Monte Carlo ensemble), a readable summary or the JSON document, and with
 * --out the CSV files, plots and report.html.  Usage errors exit 2, invalid
 * files or failed runs 1. */
#include "cli/cli.h"
#include "rockfuzz/report.h"
#include "rockfuzz/trajectory.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz trajectory FILE.yaml [--json] [--out DIR] [--threads N] [--samples N] [--seed S]\n"
        "                           [--max-trajectories N] [--no-plots] [--quiet]\n"
        "\n"
        "Runs the rockfall trajectories of a trajectory file on its 2D slope profile: one\n"
        "deterministic trajectory when nothing is random, else `samples` Monte Carlo\n"
        "trajectories (random inputs written {uniform: [lo, hi]} or {normal: [mean, sd]}).\n"
        "File format and conventions: docs/trajectories.md.\n"
        "\n"
        "  --json                 print the JSON document (samples, trajectories with their\n"
        "                         impacts, rest point and collector crossings, statistics)\n"
        "  --out DIR              write DIR/result.json, trajectories.csv, crossings.csv,\n"
        "                         statistics.csv, envelopes.csv (along x, all trajectories),\n"
        "                         plots (PNG, SVG) and report.html\n"
        "  --threads N            worker threads (default: all cores; results do not depend on it)\n"
        "  --samples N, --seed S  override the file's samples and seed\n"
        "  --max-trajectories N   trajectories listed in the JSON (default 100)\n"
        "  --no-plots             skip the plots and report.html\n"
        "  --quiet                no summary\n"
        "\n"
        "Units: m, s, m/s, rad/s, kg, J; angles in the file in degrees.\n");
}

typedef struct {
    const char *file, *out;
    int json, quiet, plots, threads;
    long long samples, seed;
    size_t max_traj;
} traj_args;

static int parse_count(const char *opt, const char *v, long long min, long long *out)
{
    char *end;
    long long n = v ? strtoll(v, &end, 10) : 0;
    if (!v || *end || n < min) {
        fprintf(stderr, "rockfuzz trajectory: %s = %s: expected an integer >= %lld\n", opt, v ? v : "(missing)", min);
        return 0;
    }
    *out = n;
    return 1;
}

static int parse_args(int argc, char **argv, traj_args *a)
{
    memset(a, 0, sizeof *a);
    a->plots = 1, a->samples = -1, a->seed = -1, a->max_traj = 100;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        long long n;
        if (!strcmp(o, "--json")) a->json = 1;
        else if (!strcmp(o, "--quiet")) a->quiet = 1;
        else if (!strcmp(o, "--no-plots")) a->plots = 0;
        else if (!strcmp(o, "--out") && v) a->out = v, i++;
        else if (!strcmp(o, "--threads")) { if (!parse_count(o, v, 0, &n)) return 0; a->threads = (int)n, i++; }
        else if (!strcmp(o, "--samples")) { if (!parse_count(o, v, 1, &a->samples)) return 0; i++; }
        else if (!strcmp(o, "--seed")) { if (!parse_count(o, v, 0, &a->seed)) return 0; i++; }
        else if (!strcmp(o, "--max-trajectories")) { if (!parse_count(o, v, 0, &n)) return 0; a->max_traj = (size_t)n, i++; }
        else if (o[0] != '-' && !a->file) a->file = o;
        else {
            fprintf(stderr, "rockfuzz trajectory: unknown or incomplete option '%s' (try --help)\n", o);
            return 0;
        }
    }
    if (!a->file) {
        fprintf(stderr, "rockfuzz trajectory: no trajectory file given (try --help)\n");
        return 0;
    }
    return 1;
}

static int write_outputs(const traj_args *a, const rf_traj_spec *s, const rf_traj_ensemble *e,
                         const rf_traj_stats *st)
{
    rf_error err;
    char path[4096];
    if (rf_report_make_dir(a->out, &err) != RF_OK || rf_traj_write_csv(a->out, s, e, st, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        return 1;
    }
    snprintf(path, sizeof path, "%s/result.json", a->out);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "rockfuzz trajectory: cannot write %s\n", path);
        return 1;
    }
    rf_traj_write_json(f, s, e, st, a->max_traj);
    if (fclose(f) != 0) {
        fprintf(stderr, "rockfuzz trajectory: cannot write %s\n", path);
        return 1;
    }
    if (a->plots && rf_traj_write_plots(a->out, s, e, st, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        return 1;
    }
    return 0;
}

int rf_cli_trajectory(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return 0;
        }
    traj_args a;
    if (!parse_args(argc, argv, &a))
        return 2;
    rf_traj_spec spec;
    rf_error err;
    if (rf_traj_load(a.file, &spec, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        return 1;
    }
    if (a.samples > 0)
        spec.samples = (size_t)a.samples, spec.record = spec.record > spec.samples ? spec.samples : spec.record;
    if (a.seed >= 0)
        spec.seed = (uint64_t)a.seed;
    rf_traj_ensemble ens;
    rf_traj_stats st;
    int rc = 0;
    if (rf_traj_run(&spec, a.threads, &ens, &err) != RF_OK || rf_traj_stats_compute(&ens, &st, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        rf_traj_ensemble_free(&ens);
        rf_traj_spec_free(&spec);
        return 1;
    }
    if (a.json)
        rf_traj_write_json(stdout, &spec, &ens, &st, a.max_traj);
    else if (!a.quiet)
        rf_traj_write_summary(stdout, &spec, &ens, &st);
    if (a.out)
        rc = write_outputs(&a, &spec, &ens, &st);
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&ens);
    rf_traj_spec_free(&spec);
    return rc;
}
