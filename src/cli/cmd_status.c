/* cmd_status.c - `rockfuzz status DIR`: progress of a study run read from
 * its result store DIR/store.sqlite (read-only, safe while the run goes on):
 * planned, done, failed, rate, time left, last update, running or stopped. */
#include "cli/cli.h"

#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/util.h"
#include "rockfuzz/store.h"
#include "rockfuzz/study_run.h"

static void when(double t, char *buf, size_t size)
{
    if (t <= 0) {
        snprintf(buf, size, "never");
        return;
    }
    time_t tt = (time_t)t;
    struct tm tmv;
    localtime_r(&tt, &tmv);
    strftime(buf, size, "%Y-%m-%d %H:%M:%S", &tmv);
}

/* 1 if a run holds DIR's lock (its text, naming the holder, into holder), 0 if
 * not, -1 if there is no lock file.  Only tries a shared lock: never blocks. */
static int lock_held(const char *dir, char *holder, size_t size)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", dir, RF_RUN_LOCK_FILE);
    holder[0] = '\0';
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    int held = flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
    ssize_t n = pread(fd, holder, size - 1, 0);
    holder[n > 0 ? n : 0] = '\0';
    holder[strcspn(holder, "\n")] = '\0';
    close(fd); /* also releases the shared lock, if taken */
    return held;
}

int rf_cli_status(int argc, char **argv)
{
    int status = 0;
    const char *dir = rf_cli_dir_argument("status", argc, argv,
        "Usage: rockfuzz status DIR\n\n"
        "Progress of the study run whose output directory is DIR, read from\n"
        "DIR/store.sqlite without changing it (safe while the run goes on): points\n"
        "planned, done, failed, rate, estimated time left, last update, and whether\n"
        "the run is running, stopped or finished; the failed evaluations are listed.\n"
        "Exit status: 0 on success, 1 if DIR holds no readable rockfuzz store.\n", &status);
    if (!dir)
        return status;
    char path[PATH_MAX], result[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", dir, RF_STORE_FILE);
    snprintf(result, sizeof result, "%s/result.json", dir);
    rf_error err;
    memset(&err, 0, sizeof err);
    rf_store_info info;
    if (rf_store_read_info(path, &info, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz status: %s\n", err.msg);
        return 1;
    }
    char host[256] = "";
    gethostname(host, sizeof host - 1);
    struct stat sb;
    int finished = stat(result, &sb) == 0 && sb.st_mtime + 1 >= (time_t)info.run_started;
    char holder[512];
    int locked = lock_held(dir, holder, sizeof holder);
    /* the folder lock is the authority (also across hosts on a shared file system);
     * without a lock file (an older run), a live pid on this host */
    int alive = locked >= 0 ? locked
                            : info.pid > 0 && !strcmp(host, info.host) &&
                                  (kill((pid_t)info.pid, 0) == 0 || errno == EPERM);
    const char *state = finished ? "finished (result.json written)"
                        : alive  ? "running"
                                 : "stopped (not running; rerun the same command to resume)";
    size_t total = info.planned_total, done = info.done;
    double now = (double)time(NULL);
    double span = (alive ? now : info.last_update) - info.run_started;
    double rate = info.done_this_run > 0 && span > 0 ? (double)info.done_this_run / span : 0;
    size_t left_pts = total > done ? total - done : 0;
    char left[64], last[64], started[64];
    if (!rf_format_duration(rate > 0 ? (double)left_pts / rate : (left_pts == 0 ? 0 : -1), 0, left, sizeof left))
        snprintf(left, sizeof left, "unknown");
    when(info.last_update, last, sizeof last);
    when(info.run_started, started, sizeof started);
    printf("Run directory   %s\n", dir);
    printf("Study           %s\n", info.study[0] ? info.study : "(unknown)");
    printf("State           %s", state);
    if (alive && !finished && locked > 0 && holder[0])
        printf(" (%s)", holder);
    else if (alive && !finished)
        printf(" (pid %ld on %s)", info.pid, info.host);
    printf("\nPlanned points  %zu distinct evaluations\n", total);
    printf("Done            %zu (%.1f %%)\n", done, total ? 100.0 * (double)done / (double)total : 0.0);
    printf("Failed          %zu\n", info.failed);
    if (info.unfinished > 0)
        printf("Unfinished      %zu (started, never finished: %s)\n", info.unfinished,
               alive && !finished ? "in flight now, or left by a killed run"
                                  : "the run was killed, or these evaluations crashed it");
    printf("This run        %zu results since %s\n", info.done_this_run, started);
    if (rate > 0)
        printf("Rate            %.3g evaluations/s (this run)\n", rate);
    else
        printf("Rate            unknown (no result in this run yet)\n");
    printf("Time left       %s%s\n", left, alive || finished ? "" : " at the last rate, once resumed");
    printf("Last update     %s\n", last);
    printf("Model time      %.1f s in total (all stored evaluations)\n", info.eval_seconds);
    printf("Model           %.200s%s\n", info.identity, strlen(info.identity) > 200 ? "..." : "");
    printf("rockfuzz        %s\n", info.version);
    if (info.failed + info.unfinished > 0) {
        enum { MAXF = 10 };
        char xs[MAXF][512], msgs[MAXF][512];
        size_t nf = rf_store_failures(path, MAXF, xs, msgs, &err);
        printf("Failed or unfinished evaluations%s:\n", info.failed + info.unfinished > nf ? " (first ones)" : "");
        for (size_t k = 0; k < nf; k++)
            printf("  x = (%s): %s\n", xs[k], msgs[k]);
    }
    return 0;
}
