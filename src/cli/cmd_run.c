/* cmd_run.c - `rockfuzz run STUDY.yaml --out DIR`: load and validate the
 * study, open the result store DIR/store.sqlite (resume), show the evaluation
 * count, run the TM through the parallel runner (threads, and MPI ranks when
 * started by mpirun), analyse, print the summary and write the report
 * (result.json last, then report.html). */
#include "cli/cli.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "rockfuzz/analysis.h"
#include "rockfuzz/mpi.h"
#include "rockfuzz/report.h"
#include "rockfuzz/runner.h"
#include "rockfuzz/store.h"
#include "rockfuzz/study.h"
#include "rockfuzz/tm.h"

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz run STUDY.yaml --out DIR [OPTIONS]\n"
        "\n"
        "Propagate the fuzzy parameters of a study through its model with the\n"
        "Transformation Method and write the fuzzy outputs and the influence analysis.\n"
        "\n"
        "Options:\n"
        "  --out DIR              output directory (created if missing; required)\n"
        "  --jobs N               worker threads (default: options.jobs of the study, else\n"
        "                         cores / threads one model evaluation uses)\n"
        "  --max-evaluations N    cap on distinct model evaluations; the run stops before\n"
        "                         evaluating anything if the plan exceeds it (default:\n"
        "                         options.max_evaluations, else 100000; 0 = no cap)\n"
        "  --progress[=MODE]      MODE line (default): the progress line even when stderr\n"
        "                         is not a terminal; jsonl: one JSON object per finished\n"
        "                         evaluation on stderr (done, total, failed, left, x, ...)\n"
        "  --quiet                no progress line (--progress=jsonl still applies)\n"
        "  --fresh                discard the results stored in DIR/store.sqlite (also\n"
        "                         those of another model or version) and start over\n"
        "  --tolerate-failures    a failed evaluation (error or NaN) does not stop the run:\n"
        "                         it is stored, left out of the bounds, and warned about\n"
        "  --no-plots             skip the PNG/SVG plots (report.html then has no figures)\n"
        "  -h, --help             show this help\n"
        "\n"
        "Study file (YAML; full reference in docs/user-guide.md):\n"
        "  name: product                 # optional, default: file name\n"
        "  scheme: reduced               # general | reduced | extended (default reduced)\n"
        "  levels: 4                     # m membership intervals, levels mu = j/m (1..1000, default 10)\n"
        "  parameters:                   # in this order they are the model's inputs\n"
        "    x1: {tfn: [2, 1, 1]}        # peak, left deviation, right deviation\n"
        "    x2: {trapezoid: [0.05, 0.45, 0.55, 0.95]}   # support [x1,x4], core [x2,x3]\n"
        "    x3: {interval: [1, 2]}\n"
        "    x4: {gaussian: [10, 1, 2], cutoff: 3}       # peak, sigma left, sigma right\n"
        "    x5: {crisp: 1.5}            # or simply  x5: 1.5\n"
        "    x6: {points: [[0, 0], [1, 1], [3, 0]]}      # (x, membership) pairs\n"
        "    x7: {cuts: {mu: [0, 0.5, 1], lower: [1, 1.5, 2], upper: [3, 2.5, 2]}}\n"
        "    # per parameter, optional: unit: \"Pa\"; class: monotonic | nonmonotonic | auto\n"
        "  model:                        # exactly one of:\n"
        "    formula: {y: \"x1*x2 + x3\"}  # muParser expressions of the parameters\n"
        "    # program: {argv: [prog, \"{x1}\"], templates: {in.txt: in.tpl},\n"
        "    #           outputs: {y: {file: out.txt, pattern: \"y=(.*)\", unit: m}},\n"
        "    #           timeout: 60, keep_workdirs: false, workdir: /tmp}\n"
        "    # impact: {solver: hunter, velocity: 10, ...}   parameters must be impact inputs\n"
        "    # trajectory: {file: slope.yaml, samples: 10000, bind: {x1: materials.rock.R_n}}\n"
        "    #   rockfall trajectories, every parameter bound to a trajectory-file input\n"
        "    #   (docs/trajectories.md); the general form is the default scheme here\n"
        "  options: {max_evaluations: 100000, left_right: true, jobs: 0}\n"
        "\n"
        "Units: whatever the study uses, stated with `unit:`; the impact model works in SI\n"
        "(m, kg, s, Pa, N) except slope_angle in degrees.  Template paths are relative to\n"
        "the study file.\n"
        "\n"
        "Resuming: every evaluation is committed to DIR/store.sqlite when it finishes;\n"
        "rerunning the same study into DIR evaluates only the points not stored yet.\n"
        "A store of another model, setting or rockfuzz version is refused (see --fresh).\n"
        "`rockfuzz status DIR` shows the progress of a running or stopped run.\n"
        "\n"
        "MPI: `mpirun -np K rockfuzz run STUDY.yaml --out DIR` (if built with MPI): rank 0\n"
        "owns the store and hands out points, ranks 1..K-1 evaluate; rank 0 evaluates\n"
        "with --jobs threads as well (default 1 under MPI).  Same results bit for bit.\n"
        "\n"
        "Outputs in DIR:\n"
        "  store.sqlite                every evaluation (parameters, outputs or error, time)\n"
        "  report.html                 self-contained report (figures embedded)\n"
        "  result.json                 everything below plus metadata; written last and\n"
        "                              atomically, so it exists only after a complete run\n"
        "  cuts_OUTPUT.csv             mu,lower,upper of each output\n"
        "  influence_OUTPUT.csv        rho, kappa, rho_left, rho_right, ... per input\n"
        "  inputs.csv                  input,mu,lower,upper\n"
        "  input_NAME.{png,svg}        membership function of each input\n"
        "  output_NAME.{png,svg}       membership function of each output\n"
        "  influence_OUTPUT.{png,svg}  relative measures of influence rho (Hanss)\n"
        "  influence_lr_OUTPUT.{png,svg}  left/right measures (after Gauger et al. 2008)\n"
        "\n"
        "Exit status: 0 on success, 1 on any error (message on stderr), 2 on a usage error.\n");
}

static int parse_count(const char *opt, const char *s, long long max, long long *out)
{
    char *end = NULL;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (errno || end == s || *end || v < 0 || v > max) {
        fprintf(stderr, "rockfuzz run: %s '%s': expected an integer in [0, %lld]\n", opt, s, max);
        return -1;
    }
    *out = v;
    return 0;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct {
    rf_runner *runner;
    rf_store *store;
    const char *study_name;
    rf_error err;
    int store_failed;
} plan_ctx;

static int on_plan(void *user, size_t requested, size_t distinct)
{
    (void)requested;
    plan_ctx *p = user;
    p->runner->planned_total = distinct;
    if (p->store && rf_store_begin_run(p->store, distinct, p->study_name, &p->err) != RF_OK) {
        p->store_failed = 1;
        return 1;
    }
    return 0;
}

int rf_cli_run(int argc, char **argv)
{
    const char *study_path = NULL, *out_dir = NULL;
    long long jobs = -1, cap = -1;
    int quiet = 0, plots = 1, progress = 0, fresh = 0, tolerate = 0;
    for (int a = 1; a < argc; a++) {
        const char *arg = argv[a];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(arg, "--out") || !strcmp(arg, "--jobs") || !strcmp(arg, "--max-evaluations")) {
            if (a + 1 >= argc) {
                fprintf(stderr, "rockfuzz run: %s needs a value (see `rockfuzz run --help`)\n", arg);
                return 2;
            }
            const char *val = argv[++a];
            if (!strcmp(arg, "--out"))
                out_dir = val;
            else if (!strcmp(arg, "--jobs") ? parse_count(arg, val, 1024, &jobs)
                                            : parse_count(arg, val, 1000000000000LL, &cap))
                return 2;
        } else if (!strcmp(arg, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(arg, "--progress") || !strcmp(arg, "--progress=line")) {
            progress = RF_PROGRESS_LINE;
        } else if (!strcmp(arg, "--progress=jsonl")) {
            progress = RF_PROGRESS_JSONL;
        } else if (!strncmp(arg, "--progress=", 11)) {
            fprintf(stderr, "rockfuzz run: %s: the progress mode is line or jsonl\n", arg);
            return 2;
        } else if (!strcmp(arg, "--fresh")) {
            fresh = 1;
        } else if (!strcmp(arg, "--tolerate-failures")) {
            tolerate = 1;
        } else if (!strcmp(arg, "--no-plots")) {
            plots = 0;
        } else if (arg[0] == '-' && arg[1]) {
            fprintf(stderr, "rockfuzz run: unknown option '%s' (see `rockfuzz run --help`)\n", arg);
            return 2;
        } else if (!study_path) {
            study_path = arg;
        } else {
            fprintf(stderr, "rockfuzz run: one study file only ('%s' and '%s')\n", study_path, arg);
            return 2;
        }
    }
    if (!study_path || !out_dir) {
        fprintf(stderr, "rockfuzz run: %s (see `rockfuzz run --help`)\n",
                !study_path ? "missing the study file" : "missing --out DIR");
        return 2;
    }

    rf_error err;
    memset(&err, 0, sizeof err);
    int rank = 0, ranks = 1;
    if (rf_mpi_start(&argc, &argv, &rank, &ranks, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        rf_mpi_stop();
        return 1;
    }
    rf_study study;
    rf_status loaded = rf_study_load(study_path, &study, &err);
    if (rank > 0) {
        /* A worker rank: evaluate what rank 0 sends; rank 0 prints every message. */
        int wrc = rf_mpi_worker(loaded == RF_OK ? &study.model : NULL, err.msg);
        if (loaded == RF_OK)
            rf_study_free(&study);
        rf_mpi_stop();
        return wrc;
    }
    if (ranks > 1) {
        rf_error herr;
        memset(&herr, 0, sizeof herr);
        if (rf_mpi_gather_hello(loaded == RF_OK ? &study.model : NULL, &herr) != RF_OK && loaded == RF_OK) {
            fprintf(stderr, "rockfuzz run: %s\n", herr.msg);
            rf_study_free(&study);
            rf_mpi_release_workers();
            rf_mpi_stop();
            return 1;
        }
    }
    if (loaded != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        rf_mpi_release_workers();
        rf_mpi_stop();
        return 1;
    }
    int rc = 1;
    rf_tm_result res;
    rf_analysis an;
    rf_store *store = NULL;
    memset(&res, 0, sizeof res);
    memset(&an, 0, sizeof an);
    char store_path[PATH_MAX];
    snprintf(store_path, sizeof store_path, "%s/%s", out_dir, RF_STORE_FILE);

    /* An old result must not survive a failed rerun into the same directory. */
    if (rf_report_make_dir(out_dir, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        goto done;
    }
    rf_store_key key = {study.model.identity ? study.model.identity : "", ROCKFUZZ_VERSION, study.n_params,
                        study.model.n_outputs, (const char *const *)study.param_names,
                        (const char *const *)study.model.output_names};
    if (rf_store_open(store_path, &key, fresh, &store, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        goto done;
    }
    {
        char old[PATH_MAX];
        snprintf(old, sizeof old, "%s/result.json", out_dir);
        if (unlink(old) != 0 && errno != ENOENT) {
            fprintf(stderr, "rockfuzz run: %s: cannot remove the old result: %s\n", old, strerror(errno));
            goto done;
        }
    }

    rf_tm_options opt;
    rf_study_tm_options(&study, &opt);
    if (cap >= 0)
        opt.max_evaluations = (size_t)cap;
    opt.tolerate_failures = tolerate;
    rf_runner runner;
    rf_runner_init(&runner);
    runner.jobs = jobs > 0    ? (int)jobs
                  : ranks > 1 ? 1
                  : study.jobs > 0 ? study.jobs
                                   : rf_runner_default_jobs(&study.model);
    runner.progress = progress == RF_PROGRESS_JSONL ? RF_PROGRESS_JSONL
                      : quiet ? RF_PROGRESS_NONE
                      : progress ? progress
                      : isatty(STDERR_FILENO) ? RF_PROGRESS_LINE
                                              : RF_PROGRESS_NONE;
    runner.store = store;
    runner.tolerate_failures = tolerate;
    runner.mpi_workers = ranks - 1;
    rf_evaluator ev = rf_runner_evaluator(&runner);
    opt.evaluator = &ev;
    plan_ctx pc;
    memset(&pc, 0, sizeof pc);
    pc.runner = &runner;
    pc.store = store;
    pc.study_name = study.name;
    opt.on_plan = on_plan;
    opt.on_plan_user = &pc;

    size_t requested = 0, distinct = 0;
    if (rf_tm_count(study.inputs, study.n_params, &opt, &requested, &distinct, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s: %s\n", study_path, err.msg);
        goto done;
    }
    printf("Study '%s': %s form, m = %zu, %zu parameter%s; model %s\n", study.name,
           rf_tm_scheme_name(study.scheme), study.levels, study.n_params, study.n_params == 1 ? "" : "s",
           study.model_description);
    printf("Evaluations: %zu requested, %zu distinct%s%s; %d job%s", requested, distinct,
           study.scheme == RF_TM_EXTENDED ? " (at most; the probe decides)" : "",
           study.left_right ? ", including the left/right three-point grid" : "", runner.jobs,
           runner.jobs == 1 ? "" : "s");
    if (ranks > 1)
        printf(" on rank 0 + %d MPI worker rank%s", ranks - 1, ranks == 2 ? "" : "s");
    printf("\n");
    fflush(stdout);
    if (opt.max_evaluations > 0 && distinct > opt.max_evaluations && study.scheme != RF_TM_EXTENDED) {
        fprintf(stderr,
                "rockfuzz run: %s: the study needs %zu distinct model evaluations, more than the cap of %zu; "
                "raise --max-evaluations (or options.max_evaluations), lower levels, or use scheme: reduced\n",
                study_path, distinct, opt.max_evaluations);
        goto done;
    }

    double t0 = now_seconds();
    if (rf_tm_run(study.inputs, study.n_params, &study.model, &opt, &res, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s: %s\n", study_path, pc.store_failed ? pc.err.msg : err.msg);
        fprintf(stderr, "rockfuzz run: %zu evaluation%s of this run committed to %s (%zu found there before); "
                        "rerun to resume\n",
                runner.evaluated + runner.failed, runner.evaluated + runner.failed == 1 ? "" : "s", store_path,
                runner.resumed);
        goto done;
    }
    if (rf_analysis_compute(&res, &an, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s: analysis: %s\n", study_path, err.msg);
        goto done;
    }
    double wall = now_seconds() - t0;
    rf_report_print_summary(stdout, &study, &res, &an);
    fflush(stdout);
    if (res.failed_points > 0 || runner.failed > 0)
        fprintf(stderr,
                "rockfuzz run: WARNING: %zu evaluation%s failed and %s left out of the bounds: the fuzzy outputs "
                "may be too narrow. The failures (parameters, message) are in %s; `rockfuzz status %s` lists "
                "them.\n",
                runner.failed, runner.failed == 1 ? "" : "s", runner.failed == 1 ? "was" : "were", store_path,
                out_dir);

    rf_report_options ropt;
    rf_report_options_default(&ropt);
    ropt.plots = plots;
    ropt.wall_seconds = wall;
    ropt.jobs = runner.jobs;
    ropt.cap = opt.max_evaluations;
    ropt.evaluated = runner.evaluated;
    ropt.failed = runner.failed;
    ropt.resumed = runner.resumed;
    ropt.mpi_ranks = ranks;
    ropt.remote = runner.remote;
    ropt.eval_seconds = runner.eval_seconds;
    if (rf_report_write(out_dir, &study, &res, &an, &ropt, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        goto done;
    }
    if (rf_report_write_html(out_dir, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        goto done;
    }
    printf("Wall time %.3f s (%zu evaluated, %zu failed, %zu from the store; %.3f s in the model). Results: "
           "%s/result.json, %s/report.html\n",
           wall, runner.evaluated, runner.failed, runner.resumed, runner.eval_seconds, out_dir, out_dir);
    rc = 0;
done:
    rf_store_close(store);
    rf_analysis_free(&an);
    rf_tm_result_free(&res);
    rf_study_free(&study);
    rf_mpi_release_workers();
    rf_mpi_stop();
    return rc;
}
