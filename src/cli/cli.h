/* cli.h - one function per subcommand of the rockfuzz program.
 * Each takes the arguments after the subcommand name (argv[0] is the
 * subcommand) and returns the process exit status. */
#ifndef ROCKFUZZ_CLI_H
#define ROCKFUZZ_CLI_H

/* Bound of every thread count option (--jobs, --threads), as in study files. */
#define RF_CLI_MAX_THREADS 1024

int rf_cli_run(int argc, char **argv);     /* cmd_run.c: run a study file */
int rf_cli_impact(int argc, char **argv);  /* cmd_impact.c: one impact */
int rf_cli_status(int argc, char **argv);  /* cmd_status.c: progress of a study run (its result store) */
int rf_cli_report(int argc, char **argv);  /* cmd_report.c: report.html from a finished run */
int rf_cli_material(int argc, char **argv); /* cmd_material.c: material-point driver */
int rf_cli_trajectory(int argc, char **argv); /* cmd_trajectory.c: rockfall trajectories of a trajectory file */

#endif
