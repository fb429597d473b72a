/* cmd_run.c - `rockfuzz run STUDY.yaml --out DIR`: load and validate the
 * study, show the evaluation count, run the TM through the parallel runner,
 * analyse, print the summary and write the report (result.json last). */
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
#include "rockfuzz/report.h"
#include "rockfuzz/runner.h"
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
        "  --progress             show the progress line even when stderr is not a terminal\n"
        "  --quiet                no progress line and no plan line on stderr\n"
        "  --no-plots             skip the PNG/SVG plots\n"
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
        "  options: {max_evaluations: 100000, left_right: true, jobs: 0}\n"
        "\n"
        "Units: whatever the study uses, stated with `unit:`; the impact model works in SI\n"
        "(m, kg, s, Pa, N) except slope_angle in degrees.  Template paths are relative to\n"
        "the study file.\n"
        "\n"
        "Outputs in DIR:\n"
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

static int on_plan(void *user, size_t requested, size_t distinct)
{
    (void)requested;
    rf_runner *r = user;
    r->planned_total = distinct;
    return 0;
}

int rf_cli_run(int argc, char **argv)
{
    const char *study_path = NULL, *out_dir = NULL;
    long long jobs = -1, cap = -1;
    int quiet = 0, plots = 1, progress = 0;
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
        } else if (!strcmp(arg, "--progress")) {
            progress = 1;
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
    rf_study study;
    if (rf_study_load(study_path, &study, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        return 1;
    }
    int rc = 1;
    rf_tm_result res;
    rf_analysis an;
    memset(&res, 0, sizeof res);
    memset(&an, 0, sizeof an);

    /* An old result must not survive a failed rerun into the same directory. */
    if (mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "rockfuzz run: %s: cannot create the output directory: %s\n", out_dir, strerror(errno));
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
    rf_runner runner;
    rf_runner_init(&runner);
    runner.jobs = jobs > 0 ? (int)jobs : study.jobs > 0 ? study.jobs : rf_runner_default_jobs(&study.model);
    runner.progress = !quiet && (progress || isatty(STDERR_FILENO));
    rf_evaluator ev = rf_runner_evaluator(&runner);
    opt.evaluator = &ev;
    opt.on_plan = on_plan;
    opt.on_plan_user = &runner;

    size_t requested = 0, distinct = 0;
    if (rf_tm_count(study.inputs, study.n_params, &opt, &requested, &distinct, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s: %s\n", study_path, err.msg);
        goto done;
    }
    printf("Study '%s': %s form, m = %zu, %zu parameter%s; model %s\n", study.name,
           rf_tm_scheme_name(study.scheme), study.levels, study.n_params, study.n_params == 1 ? "" : "s",
           study.model_description);
    printf("Evaluations: %zu requested, %zu distinct%s%s; %d job%s\n", requested, distinct,
           study.scheme == RF_TM_EXTENDED ? " (at most; the probe decides)" : "",
           study.left_right ? ", including the left/right three-point grid" : "", runner.jobs,
           runner.jobs == 1 ? "" : "s");
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
        fprintf(stderr, "rockfuzz run: %s: %s\n", study_path, err.msg);
        goto done;
    }
    if (rf_analysis_compute(&res, &an, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s: analysis: %s\n", study_path, err.msg);
        goto done;
    }
    double wall = now_seconds() - t0;
    rf_report_print_summary(stdout, &study, &res, &an);
    fflush(stdout);

    rf_report_options ropt;
    rf_report_options_default(&ropt);
    ropt.plots = plots;
    ropt.wall_seconds = wall;
    ropt.jobs = runner.jobs;
    ropt.cap = opt.max_evaluations;
    if (rf_report_write(out_dir, &study, &res, &an, &ropt, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        goto done;
    }
    printf("Wall time %.3f s (%zu evaluations, %.3f s in the model). Results: %s/result.json\n", wall,
           runner.evaluated, runner.eval_seconds, out_dir);
    rc = 0;
done:
    rf_analysis_free(&an);
    rf_tm_result_free(&res);
    rf_study_free(&study);
    return rc;
}
