/* cmd_run.c - `rockfuzz run STUDY.yaml --out DIR`: parse the command line,
 * start MPI when started by mpirun, catch SIGINT/SIGTERM, and hand everything
 * else to the library's rf_study_run (study_run.h): load, folder lock, result
 * store, TM, analysis, report.  Exit status: 0, 1 on an error, 2 on a usage
 * error, or the signal's own status after a clean stop on SIGINT/SIGTERM. */
#include "cli/cli.h"

#include <errno.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rockfuzz/mpi.h"
#include "rockfuzz/runner.h"
#include "rockfuzz/study_run.h"

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz run STUDY.yaml --out DIR [OPTIONS]\n"
        "\n"
        "Propagate the fuzzy parameters of a study through its model with the\n"
        "Transformation Method and write the fuzzy outputs and the influence analysis.\n"
        "\n"
        "Options:\n"
        "  --out DIR              output directory (created if missing; required); locked\n"
        "                         for the run: a second run into it is refused\n"
        "  --threads N            worker threads, 0..1024 (default or 0: options.jobs of the\n"
        "                         study, else cores / threads one model evaluation uses);\n"
        "                         --jobs N is the same option (an alias)\n"
        "  --max-evaluations N    cap on distinct model evaluations; the run stops before\n"
        "                         evaluating anything if the plan exceeds it (default:\n"
        "                         options.max_evaluations, else 100000; 0 = no cap)\n"
        "  --progress[=MODE]      MODE line (default): the progress line even when stderr\n"
        "                         is not a terminal; jsonl: one JSON object per finished\n"
        "                         evaluation on stderr (done, total, failed, left, x, ...)\n"
        "  --quiet                no progress line (--progress=jsonl still applies)\n"
        "  --fresh                discard the results stored in DIR/store.sqlite (also\n"
        "                         those of another model or version) and start over\n"
        "  --force                write into a non-empty DIR that holds no rockfuzz run\n"
        "                         (refused otherwise: its files could be overwritten)\n"
        "  --tolerate-failures    a failed evaluation (error or NaN) does not stop the run:\n"
        "                         it is stored, left out of the bounds, and warned about\n"
        "  --no-plots             skip the PNG/SVG plots (report.html then has no figures)\n"
        "  -h, --help             show this help\n"
        "\n"
        "Study file (YAML; full reference in docs/user-guide.md):\n"
        "  name: product                 # optional, default: file name\n"
        "  scheme: reduced               # general | reduced | extended (default: general for\n"
        "                                #   program and trajectory models, else reduced)\n"
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
        "    # impact: {solver: hunter, velocity: 10, ...}   parameters are impact inputs\n"
        "    # trajectory: {file: slope.yaml, samples: 10000, bind: {x1: materials.rock.R_n}}\n"
        "    #   rockfall trajectories, every parameter bound to a trajectory-file input\n"
        "    #   (docs/trajectories.md)\n"
        "    # bind (program, impact, trajectory): a parameter drives one input or a list,\n"
        "    #   each as value * scale + offset: {x1: [IN1, {to: IN2, scale: 0.9, offset: 0}]};\n"
        "    #   unbound program/impact parameters drive the input of their own name\n"
        "  options: {max_evaluations: 100000, left_right: true, jobs: 0}\n"
        "\n"
        "Units: whatever the study uses, stated with `unit:`; the impact model works in SI\n"
        "(m, kg, s, Pa, N) except slope_angle in degrees.  Template paths are relative to\n"
        "the study file.\n"
        "\n"
        "Resuming: every evaluation is committed to DIR/store.sqlite when it finishes;\n"
        "rerunning the same study into DIR evaluates only the points not stored yet.\n"
        "A store of another model, setting or rockfuzz version is refused (see --fresh);\n"
        "a damaged store is refused untouched (--fresh moves it to store.sqlite.damaged).\n"
        "result.json of the last complete run stays until a new run completes.\n"
        "`rockfuzz status DIR` shows the progress of a running or stopped run.\n"
        "\n"
        "MPI: `mpirun -np K rockfuzz run STUDY.yaml --out DIR` (if built with MPI): rank 0\n"
        "owns the store and hands out points, ranks 1..K-1 evaluate; rank 0 evaluates\n"
        "with --threads threads as well (default 1 under MPI).  Same results bit for bit.\n"
        "\n"
        "Outputs in DIR:\n"
        "  store.sqlite                every evaluation (parameters, outputs or error, time)\n"
        "  rockfuzz.lock               the folder lock; names the run holding it\n"
        "  report.html                 self-contained report (figures embedded)\n"
        "  result.json                 everything below plus metadata; written last and\n"
        "                              atomically, so it belongs to a complete run\n"
        "  cuts_OUTPUT.csv             mu,lower,upper of each output\n"
        "  influence_OUTPUT.csv        rho, kappa, rho_left, rho_right, ... per input\n"
        "  inputs.csv                  input,mu,lower,upper\n"
        "  input_NAME.{png,svg}        membership function of each input\n"
        "  output_NAME.{png,svg}       membership function of each output\n"
        "  influence_OUTPUT.{png,svg}  relative measures of influence rho (Hanss)\n"
        "  influence_lr_OUTPUT.{png,svg}  left/right measures (after Gauger et al. 2008)\n"
        "\n"
        "Stopping: Ctrl-C or SIGTERM stops cleanly (no new evaluation, external programs and\n"
        "everything they started killed, finished results stored; rerun to resume) and\n"
        "exits with the signal's status (130, 143); a second Ctrl-C stops at once.\n"
        "\n"
        "Exit status: 0 on success, 1 on any error (message on stderr), 2 on a usage error,\n"
        "128 + the signal number after a stop on SIGINT/SIGTERM.\n");
}

/* The one piece of global mutable state in the program: a signal handler can
 * reach nothing else.  The first SIGINT/SIGTERM asks the run to stop cleanly;
 * a second SIGINT (Ctrl-C pressed again) ends the process at once (the
 * external programs then die with it: their supervisor gets PR_SET_PDEATHSIG).
 * A repeated SIGTERM does not: tools like timeout(1) send it twice. */
static atomic_int stop_requested;
static volatile sig_atomic_t stop_signal;

static void on_stop_signal(int sig)
{
    if (atomic_exchange(&stop_requested, 1) && sig == SIGINT) {
        signal(sig, SIG_DFL);
        raise(sig);
        return;
    }
    if (!stop_signal)
        stop_signal = sig;
}

static void catch_stop_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

/* After a stop on request: end with the signal's own status, as the shell expects. */
static int exit_for_signal(void)
{
    int sig = stop_signal;
    if (!sig)
        return 1;
    fflush(NULL);
    signal(sig, SIG_DFL);
    raise(sig);
    return 128 + sig; /* not reached */
}

int rf_cli_run(int argc, char **argv)
{
    const char *study_path = NULL;
    rf_study_run_options o;
    rf_study_run_options_default(&o);
    long long jobs = 0, cap = -1;
    int quiet = 0, progress = 0;
    for (int a = 1; a < argc; a++) {
        const char *arg = argv[a];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(arg, "--out") || !strcmp(arg, "--threads") || !strcmp(arg, "--jobs") ||
                   !strcmp(arg, "--max-evaluations")) {
            const char *val = rf_cli_value("run", argc, argv, &a);
            if (!val)
                return 2;
            if (!strcmp(arg, "--out"))
                o.out_dir = val;
            else if (strcmp(arg, "--max-evaluations") ? !rf_cli_count("run", arg, val, 0, RF_CLI_MAX_THREADS, &jobs)
                                                      : !rf_cli_count("run", arg, val, 0, 1000000000000LL, &cap))
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
            o.fresh = 1;
        } else if (!strcmp(arg, "--force")) {
            o.force = 1;
        } else if (!strcmp(arg, "--tolerate-failures")) {
            o.tolerate_failures = 1;
        } else if (!strcmp(arg, "--no-plots")) {
            o.plots = 0;
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
    if (!study_path || !o.out_dir) {
        fprintf(stderr, "rockfuzz run: %s (see `rockfuzz run --help`)\n",
                !study_path ? "missing the study file" : "missing --out DIR");
        return 2;
    }
    o.jobs = (int)jobs;
    o.max_evaluations = cap;
    o.progress = progress == RF_PROGRESS_JSONL ? RF_PROGRESS_JSONL
                 : quiet                       ? RF_PROGRESS_NONE
                 : progress                    ? progress
                 : isatty(STDERR_FILENO)       ? RF_PROGRESS_LINE
                                               : RF_PROGRESS_NONE;
    o.out = stdout;
    o.log = stderr;
    o.interrupt = &stop_requested;

    rf_error err;
    memset(&err, 0, sizeof err);
    if (rf_mpi_start(&argc, &argv, &o.mpi_rank, &o.mpi_ranks, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
        rf_mpi_stop();
        return 1;
    }
    catch_stop_signals();
    rf_status st = rf_study_run(study_path, &o, NULL, &err);
    rf_mpi_stop();
    if (st == RF_OK)
        return 0;
    if (o.mpi_rank == 0)
        fprintf(stderr, "rockfuzz run: %s\n", err.msg);
    if (st == RF_EINTERRUPTED || stop_signal)
        return exit_for_signal();
    return 1;
}
