/* cli.h - one function per subcommand of the rockfuzz program.
 * Each takes the arguments after the subcommand name (argv[0] is the
 * subcommand) and returns the process exit status. */
#ifndef ROCKFUZZ_CLI_H
#define ROCKFUZZ_CLI_H

#include <stddef.h>

#include "rockfuzz/trajectory.h"

/* Bound of every thread count option (--jobs, --threads), as in study files. */
#define RF_CLI_MAX_THREADS 1024
/* Bounds of `trajectory --samples` and `--seed`, as in trajectory files (a seed above 2^53 would
 * not survive a JSON reader). */
#define RF_CLI_MAX_SAMPLES 100000000LL
#define RF_CLI_MAX_SEED 9007199254740992LL

/* cli_args.c: the value of option argv[*i] (then *i points at it), or NULL with a message on
 * stderr when it has none or the next argument is another option (`--out --quiet`). */
const char *rf_cli_value(const char *cmd, int argc, char **argv, int *i);
/* cli_args.c: v as a count in [min, max] (plain decimal digits: no sign, exponent or space), else
 * 0 with "rockfuzz CMD: OPT = V: expected an integer in [MIN, MAX]" on stderr. */
int rf_cli_count(const char *cmd, const char *opt, const char *v, long long min, long long max, long long *out);

int rf_cli_run(int argc, char **argv);     /* cmd_run.c: run a study file */
int rf_cli_impact(int argc, char **argv);  /* cmd_impact.c: one impact */
int rf_cli_status(int argc, char **argv);  /* cmd_status.c: progress of a study run (its result store) */
int rf_cli_report(int argc, char **argv);  /* cmd_report.c: report.html from a finished run */
int rf_cli_material(int argc, char **argv); /* cmd_material.c: material-point driver */
int rf_cli_trajectory(int argc, char **argv); /* cmd_trajectory.c: rockfall trajectories of a trajectory file */
int rf_cli_presets(int argc, char **argv);  /* cmd_presets.c: the named materials of trajectory files */
/* cmd_trajectory.c: `rockfuzz report DIR` of a `rockfuzz trajectory --out DIR` result (DIR holds
 * RF_CLI_INVOCATION, else *handled = 0): the trajectories run again from the recorded file and
 * overrides, and only if they reproduce DIR/result.json, the plots and report.html are written. */
#define RF_CLI_INVOCATION "invocation.json"
#define RF_CLI_RESULT_MAX (256 << 20) /* bytes of a result.json read back */
int rf_cli_trajectory_report(const char *dir, int *handled);

/* traj_ranks.c: a terrain file's Monte Carlo shared over MPI ranks `rank` of `size` (collective:
 * every rank calls it); rank 0 ends with the whole ensemble, as rf_terrain_run gives it bit for bit
 * (progress: rank 0's, scaled to the run), the other ranks with none; on a failure on any rank every
 * rank gets the first failing rank's status and message. */
rf_status rf_cli_terrain_ranks(const rf_traj_spec *spec, int threads, int rank, int size, rf_traj_progress_fn progress,
                               void *ctx, rf_traj_ensemble *ens, rf_error *err);

/* cli_args.c: *x = the number s, the whole text, finite; else 0 with "rockfuzz CMD: --OPT 'S': not a
 * finite number" on stderr. */
int rf_cli_parse_double(const char *cmd, const char *opt, const char *s, double *x);
/* cli_args.c: the one DIR argument of `rockfuzz CMD DIR`; NULL when the command is done, with the exit
 * status in *status: 0 after -h/--help printed help, 2 after a usage error (message printed). */
const char *rf_cli_dir_argument(const char *cmd, int argc, char **argv, const char *help, int *status);

/* progress.c: the progress line of one long run (the FE solvers', the trajectory Monte Carlo's callback). */
#define RF_CLI_PROGRESS_HZ 4.0    /* redraws per second at most */
#define RF_CLI_PROGRESS_DELAY 1.0 /* [s] before the first line: short runs stay silent */
typedef struct {
    int on, drawn;
    const char *what;
    double start, last_draw, t_last; /* monotonic [s]; t_last: the simulated time last seen */
    double delay;      /* [s] before the first line */
} rf_cli_progress;
void rf_cli_progress_begin(rf_cli_progress *p, int on, const char *what);
void rf_cli_progress_fem(void *ctx, double t, double t_end); /* an rf_fem_options.progress */
void rf_cli_progress_count(void *ctx, size_t done, size_t total); /* WHAT: done of total (an rf_traj_progress_fn) */
void rf_cli_progress_end(rf_cli_progress *p);                /* erases the line if one was drawn */

#endif
