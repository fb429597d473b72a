/* cmd_report.c - `rockfuzz report DIR`: regenerate DIR/report.html of any
 * result rockfuzz writes.  A study run (`rockfuzz run`): from DIR/result.json
 * and the figures already there, nothing is evaluated.  A trajectory run
 * (`rockfuzz trajectory --out DIR`, recorded in DIR/invocation.json): its
 * trajectories are run again (the same bits whatever the thread count) and
 * the plots and report written only if they reproduce DIR/result.json. */
#include "cli/cli.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "rockfuzz/report.h"

/* A trajectory study's rerun folder (OUT/nominal, OUT/bound_lower,
 * OUT/bound_upper: src/study/study_traj.c, marked by rerun.txt) is part of the
 * study's result: its figures and report.html are written by the study, and
 * `rockfuzz report OUT` rewrites the study's report with them.  1 (and the
 * message) if dir is one. */
static int study_rerun(const char *dir)
{
    char mark[4200];
    snprintf(mark, sizeof mark, "%s/rerun.txt", dir);
    if (access(mark, F_OK) != 0)
        return 0;
    fprintf(stderr, "rockfuzz report: %s is a trajectory study's rerun (its rerun.txt), part of the study's result "
            "in the folder above it: `rockfuzz report %s/..` rewrites the study's report.html, which shows this "
            "run; `rockfuzz run` of the study writes this folder again\n", dir, dir);
    return 1;
}

int rf_cli_report(int argc, char **argv)
{
    int status = 0;
    const char *dir = rf_cli_dir_argument("report", argc, argv,
        "Usage: rockfuzz report DIR\n\n"
        "Write DIR/report.html (self-contained: figures embedded) again.\n"
        "  a `rockfuzz run` result: from DIR/result.json and the PNG figures, without\n"
        "      evaluating anything;\n"
        "  a `rockfuzz trajectory --out DIR` result: the trajectories are run again from\n"
        "      the file and options recorded in DIR/invocation.json (same bits) and the\n"
        "      plots and report.html written only if they reproduce DIR/result.json.\n"
        "Exit status: 0 on success, 1 on an error, 2 on a usage error.\n", &status);
    if (!dir)
        return status;
    rf_error err;
    memset(&err, 0, sizeof err);
    const rf_status st = rf_report_write_html(dir, &err);
    if (st == RF_EPARSE) { /* not a study's result: a trajectory run's, if it recorded itself */
        int trajectory = 0;
        const int rc = rf_cli_trajectory_report(dir, &trajectory);
        if (trajectory) {
            if (rc == 0)
                printf("%s/report.html\n", dir);
            return rc;
        }
        if (study_rerun(dir))
            return 1;
    }
    if (st != RF_OK) {
        fprintf(stderr, "rockfuzz report: %s\n", err.msg);
        return 1;
    }
    printf("%s/report.html\n", dir);
    return 0;
}
