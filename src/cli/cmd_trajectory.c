/* cmd_trajectory.c - `rockfuzz trajectory FILE.yaml`: one trajectory file
 * run (a single deterministic trajectory when nothing is random, else the
 * Monte Carlo ensemble), a readable summary or the JSON document, and with
 * --out the CSV files, plots and report.html.  A terrain file (`terrain:`
 * instead of `profile:`) runs on its DEM (rf_terrain_run) and writes the
 * terrain outputs (hazard.tif, paths.gpkg, maps).  Under `mpirun -np K` a
 * terrain file's samples are shared by the ranks (traj_ranks.c) and rank 0
 * writes everything, the same bytes as one process; a profile file runs on
 * rank 0 alone.  Usage errors exit 2, invalid files or failed runs 1. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "cli/cli.h"
#include "core/hash.h"
#include "core/json.h"
#include "core/outdir.h"
#include "rockfuzz/mpi.h"
#include "rockfuzz/report.h"
#include "rockfuzz/terrain.h"
#include "rockfuzz/trajectory.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

#include <libfyaml.h>

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz trajectory FILE.yaml [--json] [--out DIR] [--threads N] [--samples N] [--seed S]\n"
        "                           [--max-trajectories N] [--no-plots] [--progress] [--quiet]\n"
        "\n"
        "Runs the rockfall trajectories of a trajectory file on its 2D slope profile, or in\n"
        "3D on a DEM for a terrain file (`terrain:` instead of `profile:`): one\n"
        "deterministic trajectory when nothing is random, else `samples` Monte Carlo\n"
        "trajectories (random inputs written {uniform: [lo, hi]} or {normal: [mean, sd]}).\n"
        "The block is a point, a sphere or a rigid convex block (block.shape: ellipsoid,\n"
        "box, polyhedron, eota_cube, eota_wheel; docs/block-shape.md).\n"
        "File format and conventions: docs/trajectories.md; terrain files: docs/terrain.md.\n"
        "\n"
        "  --json                 print the JSON document (samples, trajectories with their\n"
        "                         impacts, rest point and collector crossings, statistics)\n"
        "  --out DIR              write DIR/result.json, trajectories.csv, samples.csv (every\n"
        "                         sample's runout), crossings.csv, statistics.csv, exceedance.csv,\n"
        "                         runout_histogram.csv, envelopes.csv (along x, all trajectories),\n"
        "                         plots (PNG, SVG), report.html and\n"
        "                         invocation.json (the file and options, for `rockfuzz report DIR`);\n"
        "                         a terrain file: result.json, samples.csv (start, end, runout,\n"
        "                         reach angle), crossings.csv, statistics.csv, hazard.tif (the\n"
        "                         rasters, one band per statistic), paths.gpkg (end points and\n"
        "                         trajectories), maps (PNG) and report.html. Either file,\n"
        "                         a rigid block with outputs.vtk: true: vtk/block_K.pvd (ParaView)\n"
        "  --threads N            worker threads, 0..1024 (default or 0: all cores; results do\n"
        "                         not depend on it)\n"
        "  --samples N, --seed S  override the file's samples (1..10^8) and seed (0..2^53)\n"
        "  --max-trajectories N   trajectories listed in the JSON, 0..10^8 (default 100)\n"
        "  --no-plots             skip the plots and report.html\n"
        "  --force                write into a non-empty DIR that holds no rockfuzz trajectory\n"
        "                         run (no invocation.json)\n"
        "  --progress             the progress line on stderr (trajectories done, time left)\n"
        "                         even when stderr is not a terminal; on a terminal it is\n"
        "                         shown for runs longer than a second unless --json or --quiet\n"
        "  --quiet                no summary, no progress line\n"
        "\n"
        "Units: m, s, m/s, rad/s, kg, J (the summary shows energies in kJ); angles in the file\n"
        "and the terrain outputs (reach angle) in degrees.\n"
        "\n"
        "MPI: `mpirun -np K rockfuzz trajectory TERRAIN.yaml --out DIR` (if built with MPI) shares\n"
        "a terrain file's samples among the K ranks (each with --threads threads); rank 0 gathers\n"
        "them and writes every output, the same as one process. A profile file runs on rank 0.\n");
}

typedef struct {
    const char *file, *out;
    int json, quiet, plots, threads, force, progress;
    long long samples, seed;
    size_t max_traj;
} traj_args;

static int parse_args(int argc, char **argv, traj_args *a)
{
    memset(a, 0, sizeof *a);
    a->plots = 1, a->samples = -1, a->seed = -1, a->max_traj = 100;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v = NULL;
        long long n;
        int counted = !strcmp(o, "--threads") || !strcmp(o, "--samples") || !strcmp(o, "--seed") ||
                      !strcmp(o, "--max-trajectories");
        if ((counted || !strcmp(o, "--out")) && !(v = rf_cli_value("trajectory", argc, argv, &i)))
            return 0;
        if (!strcmp(o, "--json")) a->json = 1;
        else if (!strcmp(o, "--quiet")) a->quiet = 1;
        else if (!strcmp(o, "--progress")) a->progress = 1;
        else if (!strcmp(o, "--no-plots")) a->plots = 0;
        else if (!strcmp(o, "--force")) a->force = 1;
        else if (!strcmp(o, "--out")) a->out = v;
        else if (!strcmp(o, "--threads")) { if (!rf_cli_count("trajectory", o, v, 0, RF_CLI_MAX_THREADS, &n)) return 0; a->threads = (int)n; }
        else if (!strcmp(o, "--samples")) { if (!rf_cli_count("trajectory", o, v, 1, RF_CLI_MAX_SAMPLES, &a->samples)) return 0; }
        else if (!strcmp(o, "--seed")) { if (!rf_cli_count("trajectory", o, v, 0, RF_CLI_MAX_SEED, &a->seed)) return 0; }
        else if (!strcmp(o, "--max-trajectories")) { if (!rf_cli_count("trajectory", o, v, 0, RF_CLI_MAX_SAMPLES, &n)) return 0; a->max_traj = (size_t)n; }
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

/* DIR/invocation.json: what ran (the trajectory file's absolute path and the
 * overrides), for `rockfuzz report DIR` (rf_cli_trajectory_report). */
static int write_invocation(const traj_args *a)
{
    char path[4096], *file = realpath(a->file, NULL);
    snprintf(path, sizeof path, "%s/" RF_CLI_INVOCATION, a->out);
    FILE *f = file ? fopen(path, "w") : NULL;
    if (f) {
        fputs("{\"command\": \"trajectory\", \"file\": ", f);
        rf_json_string(f, file);
        fprintf(f, ", \"samples\": %lld, \"seed\": %lld, \"max_trajectories\": %zu}\n", a->samples, a->seed,
                a->max_traj);
    }
    free(file);
    if (!f || fclose(f) != 0) {
        fprintf(stderr, "rockfuzz trajectory: cannot write %s\n", path);
        return 1;
    }
    return 0;
}

/* The JSON document of a profile or a terrain run. */
static void write_json(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st,
                       size_t max_traj)
{
    if (s->terrain)
        rf_terrain_write_json(f, s, e, st, max_traj);
    else
        rf_traj_write_json(f, s, e, st, max_traj);
}

static int write_outputs(const traj_args *a, const rf_traj_spec *s, const rf_traj_ensemble *e,
                         const rf_traj_stats *st)
{
    rf_error err;
    char path[4096];
    rf_status rs = rf_report_make_dir(a->out, &err);
    if (rs == RF_OK)
        rs = s->terrain ? rf_terrain_write_outputs(a->out, s, e, st, a->plots, &err)
                        : rf_traj_write_csv(a->out, s, e, st, &err);
    if (rs != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        return 1;
    }
    snprintf(path, sizeof path, "%s/result.json", a->out);
    if (rf_traj_write_json_file(path, s, e, st, a->max_traj, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        return 1;
    }
    if (write_invocation(a) != 0)
        return 1;
    if (a->plots && !s->terrain && rf_traj_write_plots(a->out, s, e, st, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        return 1;
    }
    return 0;
}

/* Load a.file and apply the command line's overrides. */
static rf_status load_file(const traj_args *a, rf_traj_spec *spec, rf_error *err)
{
    rf_status st = rf_traj_load(a->file, spec, err);
    if (st != RF_OK)
        return st;
    if (a->samples > 0)
        spec->samples = (size_t)a->samples, spec->record = spec->record > spec->samples ? spec->samples : spec->record;
    if (a->seed >= 0)
        spec->seed = (uint64_t)a->seed;
    return rf_traj_rolling_resolve(spec, a->quiet || a->json ? NULL : stderr, err);
}

/* Load a.file, apply the command line's overrides, run and compute the
 * statistics; 1 (message printed, everything freed) on an error. */
static int run_file(const traj_args *a, rf_traj_spec *spec, rf_traj_ensemble *ens, rf_traj_stats *st)
{
    rf_error err;
    if (load_file(a, spec, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        return 1;
    }
    rf_cli_progress line;
    rf_cli_progress_begin(&line, a->progress || (!a->json && !a->quiet && isatty(STDERR_FILENO)), "trajectories");
    rf_status rs = spec->terrain ? rf_terrain_run(spec, a->threads, rf_cli_progress_count, &line, ens, &err)
                                 : rf_traj_run_progress(spec, a->threads, rf_cli_progress_count, &line, ens, &err);
    rf_cli_progress_end(&line);
    if (rs != RF_OK || rf_traj_stats_compute_spec(spec, ens, st, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        rf_traj_ensemble_free(ens);
        rf_traj_spec_free(spec);
        return 1;
    }
    return 0;
}

/* The folder is checked before anything runs: a user's own files are never overwritten. */
static rf_status check_out(const traj_args *a, rf_error *err)
{
    const char *const markers[] = {"invocation.json"};
    return a->out ? rf_check_out_dir(a->out, a->force, markers, 1, err) : RF_OK;
}

/* The summary or JSON on stdout, the run folder; frees the run. */
static int finish(const traj_args *a, rf_traj_spec *spec, rf_traj_ensemble *ens, rf_traj_stats *st)
{
    int rc = 0;
    if (a->json)
        write_json(stdout, spec, ens, st, a->max_traj);
    else if (!a->quiet && spec->terrain)
        rf_terrain_write_summary(stdout, spec, ens, st);
    else if (!a->quiet)
        rf_traj_write_summary(stdout, spec, ens, st);
    if (a->out)
        rc = write_outputs(a, spec, ens, st);
    rf_traj_stats_free(st);
    rf_traj_ensemble_free(ens);
    rf_traj_spec_free(spec);
    return rc;
}

/* One process. */
static int run_one(const traj_args *a)
{
    rf_error ferr = {0};
    if (check_out(a, &ferr) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", ferr.msg);
        return 2;
    }
    rf_traj_spec spec;
    rf_traj_ensemble ens;
    rf_traj_stats st;
    if (run_file(a, &spec, &ens, &st) != 0)
        return 1;
    return finish(a, &spec, &ens, &st);
}

/* What every rank must have read alike: the file's values and text, the run's overrides. */
static uint64_t run_identity(const rf_traj_spec *s)
{
    uint64_t w[5] = {rf_traj_spec_values_hash(s), s->text_hash, s->samples, s->seed, s->record};
    return rf_fnv1a(0xcbf29ce484222325ull, w, sizeof w);
}

/* Rank `rank` of `size` > 1 (every rank calls it): the folder checked on
 * rank 0, the file loaded on every rank, all agreeing; a terrain file's
 * samples shared (traj_ranks.c), rank 0 writing everything. */
static int run_ranks(const traj_args *a, int rank, int size)
{
    rf_error err = {0};
    rf_traj_spec spec;
    rf_status st = rank == 0 ? check_out(a, &err) : RF_OK;
    int bad_dir = st != RF_OK, loaded = st == RF_OK && load_file(a, &spec, &err) == RF_OK;
    st = rf_mpi_agree(loaded ? RF_OK : err.code ? err.code : RF_EINVAL, loaded ? run_identity(&spec) : 0, &err);
    if (st != RF_OK) {
        if (rank == 0)
            fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        if (loaded)
            rf_traj_spec_free(&spec);
        return bad_dir ? 2 : 1;
    }
    if (!spec.terrain) {
        rf_traj_spec_free(&spec);
        if (rank > 0)
            return 0;
        fprintf(stderr, "rockfuzz trajectory: a profile file runs on MPI rank 0 alone (%d ranks idle)\n", size - 1);
        return run_one(a);
    }
    rf_traj_ensemble ens;
    rf_traj_stats stats;
    rf_cli_progress line;
    rf_cli_progress_begin(&line, rank == 0 && (a->progress || (!a->json && !a->quiet && isatty(STDERR_FILENO))),
                          "trajectories");
    st = rf_cli_terrain_ranks(&spec, a->threads, rank, size, rf_cli_progress_count, &line, &ens, &err);
    rf_cli_progress_end(&line);
    if (st == RF_OK && rank == 0)
        st = rf_traj_stats_compute_spec(&spec, &ens, &stats, &err);
    if (st != RF_OK || rank > 0) {
        if (st != RF_OK && rank == 0)
            fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        rf_traj_ensemble_free(&ens);
        rf_traj_spec_free(&spec);
        return st != RF_OK;
    }
    return finish(a, &spec, &ens, &stats);
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
    int rank = 0, size = 1;
    rf_error err = {0};
    if (rf_mpi_start(&argc, &argv, &rank, &size, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz trajectory: %s\n", err.msg);
        rf_mpi_stop();
        return 1;
    }
    int rc = size > 1 ? run_ranks(&a, rank, size) : run_one(&a);
    rf_mpi_stop();
    return rc;
}

/* The result document's part that a rerun must reproduce: up to the run's
 * own counts (the impact table's cache hits, the wall time). */
static size_t comparable_length(const char *doc)
{
    const char *end = strstr(doc, "\n \"impact_table\"");
    const char *w = strstr(doc, "\n \"wall_seconds\"");
    if (!end || (w && w < end))
        end = w;
    return end ? (size_t)(end - doc) : strlen(doc);
}

static char *read_text(const char *path, size_t max)
{
    FILE *f = fopen(path, "rb");
    char *buf = f ? malloc(max + 1) : NULL;
    size_t n = buf ? fread(buf, 1, max + 1, f) : 0;
    if (f)
        fclose(f);
    if (!buf || n > max) {
        free(buf);
        return NULL;
    }
    buf[n] = '\0';
    return buf;
}

/* A scalar of the invocation document (NULL if absent). */
static const char *invocation_value(struct fy_document *doc, const char *key, char *buf, size_t size)
{
    struct fy_node *n = fy_node_by_path(fy_document_root(doc), key, -1, FYNWF_DONT_FOLLOW);
    size_t len = 0;
    const char *v = n && fy_node_is_scalar(n) ? fy_node_get_scalar(n, &len) : NULL;
    if (!v || len >= size)
        return NULL;
    memcpy(buf, v, len);
    buf[len] = '\0';
    return buf;
}

static int read_invocation(const char *path, traj_args *a, char *file, size_t size)
{
    struct fy_parse_cfg cfg = {.flags = FYPCF_QUIET | FYPCF_JSON_FORCE};
    struct fy_document *doc = fy_document_build_from_file(&cfg, path);
    char cmd[32], num[3][32];
    int ok = doc && invocation_value(doc, "/command", cmd, sizeof cmd) && !strcmp(cmd, "trajectory") &&
             invocation_value(doc, "/file", file, size) && invocation_value(doc, "/samples", num[0], 32) &&
             invocation_value(doc, "/seed", num[1], 32) && invocation_value(doc, "/max_trajectories", num[2], 32);
    fy_document_destroy(doc);
    memset(a, 0, sizeof *a);
    a->file = file, a->plots = 1;
    long long mt = 0;
    return ok && sscanf(num[0], "%lld", &a->samples) == 1 && sscanf(num[1], "%lld", &a->seed) == 1 &&
           sscanf(num[2], "%lld", &mt) == 1 && mt >= 0 && (a->max_traj = (size_t)mt, 1);
}

/* The trajectories again, checked against the stored result; then the plots
 * and report.html with the stored run's wall time. */
static int rerun_report(const char *dir, const traj_args *a, const char *stored)
{
    rf_traj_spec spec;
    rf_traj_ensemble ens;
    rf_traj_stats st;
    if (run_file(a, &spec, &ens, &st) != 0)
        return 1;
    char *doc = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&doc, &len);
    if (mem) {
        write_json(mem, &spec, &ens, &st, a->max_traj);
        fclose(mem);
    }
    const size_t n = doc ? comparable_length(doc) : 0;
    int rc = 0;
    if (!doc || n != comparable_length(stored) || memcmp(doc, stored, n) != 0) {
        fprintf(stderr, "rockfuzz report: %s/result.json is not what %s gives now (the file or a file it reads "
                        "was edited since, or another rockfuzz version wrote it): run `rockfuzz trajectory %s "
                        "--out %s` again\n", dir, a->file, a->file, dir);
        rc = 1;
    } else {
        const char *w = strstr(stored, "\n \"wall_seconds\": ");
        if (w)
            ens.wall_seconds = strtod(w + 18, NULL);
        rf_error err;
        /* a terrain run's maps are drawn with its rasters: the run folder is written again */
        rf_status rs = spec.terrain ? rf_terrain_write_outputs(dir, &spec, &ens, &st, 1, &err)
                                    : rf_traj_write_plots(dir, &spec, &ens, &st, &err);
        if (rs != RF_OK) {
            fprintf(stderr, "rockfuzz report: %s\n", err.msg);
            rc = 1;
        }
    }
    free(doc);
    rf_traj_stats_free(&st);
    rf_traj_ensemble_free(&ens);
    rf_traj_spec_free(&spec);
    return rc;
}

int rf_cli_trajectory_report(const char *dir, int *handled)
{
    char path[4096], result[4096], file[4096];
    snprintf(path, sizeof path, "%s/" RF_CLI_INVOCATION, dir);
    snprintf(result, sizeof result, "%s/result.json", dir);
    *handled = access(path, F_OK) == 0;
    if (!*handled)
        return 0;
    traj_args a;
    if (!read_invocation(path, &a, file, sizeof file)) {
        fprintf(stderr, "rockfuzz report: %s: not the record of a `rockfuzz trajectory` run\n", path);
        return 1;
    }
    char *stored = read_text(result, RF_CLI_RESULT_MAX);
    if (!stored) {
        fprintf(stderr, "rockfuzz report: %s: missing, unreadable or larger than %d MB\n", result,
                RF_CLI_RESULT_MAX >> 20);
        return 1;
    }
    const int rc = rerun_report(dir, &a, stored);
    free(stored);
    return rc;
}
