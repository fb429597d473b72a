/* external_process.c - running the external model's program once: its
 * working directory (a fresh workdir_root/eval-XXXXXX), the supervisor and
 * the program, the time limit and interruption, the supervisor's report,
 * and the program's end as an error.  Uses external_text.c
 * (external_internal.h).
 *
 * Each evaluation forks a supervisor S, which forks the program P.  Between
 * fork and _exit only async-signal-safe system calls run (the parent has other
 * threads that may hold the malloc or stdio locks).
 *   S: blocks SIGTERM/SIGINT/SIGCHLD and waits for them with sigwaitinfo (no
 *      handler, no global state); dies with rockfuzz (PR_SET_PDEATHSIG sends
 *      it SIGTERM, which it handles like a stop request); is a child
 *      subreaper (PR_SET_CHILD_SUBREAPER), so every descendant of P that is
 *      orphaned - also one that called setsid() to leave P's process group -
 *      becomes S's child.  When P has ended, or on SIGTERM (timeout,
 *      interruption, rockfuzz gone), S kills P's group and then every child
 *      it has, repeatedly, until none is left; then it reports P's wait
 *      status on the report pipe and exits.
 *   P: own process group, PR_SET_PDEATHSIG = SIGKILL (S gone: P goes too),
 *      default signal dispositions, cwd = the working directory, exec.
 * Report pipe records (two ints): {1|2|3, errno} from P when it could not
 * enter the directory / redirect / exec; {4, errno} from S when fork failed;
 * {0, wait status of P} from S at the end. */
#undef _POSIX_C_SOURCE
#define _GNU_SOURCE /* pipe2, close_range, sigabbrev_np, environ, nftw */
#include "external_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/util.h"

/* ---- the supervisor and the program (between fork and _exit) --------- */

enum { REPORT_STATUS = 0, REPORT_CHDIR = 1, REPORT_EXEC = 3, REPORT_FORK = 4 };

static void report_record(int fd, int kind, int value)
{
    int rec[2] = {kind, value};
    ssize_t ignored = write(fd, rec, sizeof rec);
    (void)ignored;
}

static void default_signals(void)
{
    struct sigaction dfl;
    memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    for (int s = 1; s < 32; s++) {
        if (s != SIGKILL && s != SIGSTOP)
            sigaction(s, &dfl, NULL);
    }
}

static void child_exec(const char *dir, const char *path, char *const argv[], pid_t supervisor)
{
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != supervisor)
        _exit(127); /* the supervisor died before the line above */
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    if (chdir(dir) != 0) {
        report_record(3, REPORT_CHDIR, errno);
        _exit(127);
    }
    execve(path, argv, environ);
    report_record(3, REPORT_EXEC, errno);
    _exit(127);
}

/* Decimal text of v at *p (no snprintf here: not async-signal-safe). */
static char *put_int(char *p, long v)
{
    char tmp[24];
    int n = 0;
    do
        tmp[n++] = (char)('0' + v % 10);
    while ((v /= 10) > 0);
    while (n > 0)
        *p++ = tmp[--n];
    return p;
}

/* Kill and reap every child of this process (S), again and again, until it
 * has none: killing one orphans its children, which then become S's. */
static void sweep_children(void)
{
    char path[64] = "/proc/", *p = path + 6;
    pid_t self = getpid();
    p = put_int(p, self);
    memcpy(p, "/task/", 6);
    p = put_int(p + 6, self);
    memcpy(p, "/children", 10);
    for (int round = 0; round < 10000; round++) {
        char buf[4096];
        int fd = open(path, O_RDONLY | O_CLOEXEC);
        ssize_t n = fd >= 0 ? read(fd, buf, sizeof buf - 1) : -1;
        if (fd >= 0)
            close(fd);
        if (n <= 0) {
            while (waitpid(-1, NULL, WNOHANG) > 0) /* no /proc: reap what has ended */
                ;
            return;
        }
        buf[n] = '\0';
        for (char *q = buf; *q;) {
            long pid = 0;
            while (*q >= '0' && *q <= '9')
                pid = pid * 10 + (*q++ - '0');
            /* the kernel ends every pid with a space: a number cut by the buffer end is not one */
            int whole = *q == ' ' || *q == '\n';
            while (*q == ' ' || *q == '\n')
                q++;
            if (pid > 0 && whole) {
                kill((pid_t)pid, SIGKILL);
                while (waitpid((pid_t)pid, NULL, 0) < 0 && errno == EINTR)
                    ;
            } else if (*q) {
                q++;
            }
        }
    }
}

/* The supervisor S (see above); never returns. */
static void supervise(const char *dir, const char *path, char *const argv[], int fd_in, int fd_out, int fd_err,
                      int report_fd, pid_t parent)
{
    sigset_t wait_for;
    sigemptyset(&wait_for);
    sigaddset(&wait_for, SIGTERM);
    sigaddset(&wait_for, SIGINT);
    sigaddset(&wait_for, SIGCHLD);
    sigprocmask(SIG_SETMASK, &wait_for, NULL);
    default_signals();
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent)
        _exit(1);
    prctl(PR_SET_CHILD_SUBREAPER, 1);
    /* out of the way of 0..3 first, in case the caller had closed its standard streams */
    fd_in = fcntl(fd_in, F_DUPFD, 10);
    fd_out = fcntl(fd_out, F_DUPFD, 10);
    fd_err = fcntl(fd_err, F_DUPFD, 10);
    report_fd = fcntl(report_fd, F_DUPFD, 10);
    if (fd_in < 0 || fd_out < 0 || fd_err < 0 || report_fd < 0)
        _exit(1);
    if (dup2(fd_in, 0) < 0 || dup2(fd_out, 1) < 0 || dup2(fd_err, 2) < 0 || dup2(report_fd, 3) < 0) {
        report_record(report_fd, 2, errno);
        _exit(1);
    }
    fcntl(3, F_SETFD, FD_CLOEXEC);
    close_range(4, ~0U, 0); /* nothing of rockfuzz's (e.g. the folder lock) stays open in S */
    pid_t self = getpid();
    pid_t prog = fork();
    if (prog == 0)
        child_exec(dir, path, argv, self);
    if (prog < 0) {
        report_record(3, REPORT_FORK, errno);
        _exit(1);
    }
    int status = 0;
    for (int done = 0; !done;) {
        siginfo_t si;
        int sig = sigwaitinfo(&wait_for, &si);
        if (sig == SIGTERM || sig == SIGINT) {
            kill(-prog, SIGKILL);
            kill(prog, SIGKILL);
        }
        pid_t w;
        int st;
        while ((w = waitpid(-1, &st, WNOHANG)) > 0)
            if (w == prog) {
                status = st;
                done = 1;
            }
    }
    kill(-prog, SIGKILL); /* anything P left running in its group */
    sweep_children();     /* and every other descendant */
    report_record(3, REPORT_STATUS, status);
    _exit(0);
}

/* ---- one run, from rockfuzz's side ----------------------------------- */

/* Fork the supervisor of one run of the program (argv expanded for x); on
 * success *pid is the supervisor and *report_fd the read end of its report pipe. */
rf_status ext_start_program(const ext_ctx *c, const double *x, const char *dir, const char *point, pid_t *pid,
                            int *report_fd, rf_error *err)
{
    const char *prog = c->argv[0];
    *pid = -1;
    *report_fd = -1;
    char **argv = calloc(c->argc + 1, sizeof *argv);
    if (!argv)
        return rf_fail(err, RF_ENOMEM, "out of memory for the argument list");
    rf_status st = RF_OK;
    for (size_t a = 0; a < c->argc && st == RF_OK; a++) {
        strbuf arg = {0};
        st = ext_expand(c, c->argv[a], strlen(c->argv[a]), x, "argv", &arg, err);
        argv[a] = arg.data;
    }
    strbuf out_path = {0}, err_path = {0};
    ext_sb_printf(&out_path, "%s/stdout.txt", dir);
    ext_sb_printf(&err_path, "%s/stderr.txt", dir);
    int fd_in = -1, fd_out = -1, fd_err = -1, report[2] = {-1, -1};
    if (st == RF_OK && (out_path.oom || err_path.oom))
        st = rf_fail(err, RF_ENOMEM, "out of memory for output paths");
    if (st == RF_OK) {
        fd_in = open("/dev/null", O_RDONLY | O_CLOEXEC);
        fd_out = open(out_path.data, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        fd_err = open(err_path.data, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd_in < 0 || fd_out < 0 || fd_err < 0 || pipe2(report, O_CLOEXEC) != 0)
            st = rf_fail(err, RF_EIO, "cannot set up the standard streams of program '%s' in %s: %s", prog, dir,
                         strerror(errno));
    }
    if (st == RF_OK) {
        pid_t self = getpid();
        *pid = fork();
        if (*pid == 0)
            supervise(dir, c->program_path, argv, fd_in, fd_out, fd_err, report[1], self);
        if (*pid < 0)
            st = rf_fail(err, RF_EIO, "cannot start program '%s' at %s: fork: %s", prog, point, strerror(errno));
    }
    int fds[4] = {report[1], fd_in, fd_out, fd_err};
    for (int k = 0; k < 4; k++)
        if (fds[k] >= 0)
            close(fds[k]);
    if (st == RF_OK)
        *report_fd = report[0];
    else if (report[0] >= 0)
        close(report[0]);
    for (size_t a = 0; a < c->argc; a++)
        free(argv[a]);
    free(argv);
    free(out_path.data);
    free(err_path.data);
    return st;
}

/* Wait for the supervisor; on a timeout or an interruption ask it to stop
 * (SIGTERM: it kills the program and every descendant), then reap it. */
void ext_wait_supervisor(const ext_ctx *c, pid_t pid, int *timed_out, int *interrupted)
{
    double start = rf_monotonic_seconds(), stop_sent = 0;
    long nap_ns = 1000000;
    for (;;) {
        int status;
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid || (w < 0 && errno != EINTR))
            return;
        double now = rf_monotonic_seconds();
        if (!stop_sent) {
            if (c->interrupt && atomic_load(c->interrupt))
                *interrupted = 1;
            else if (c->timeout > 0 && now - start >= c->timeout)
                *timed_out = 1;
            if (*interrupted || *timed_out) {
                kill(pid, SIGTERM);
                stop_sent = now;
            }
        } else if (now - stop_sent > 10) {
            kill(pid, SIGKILL); /* the supervisor is stuck: the program still dies (PDEATHSIG) */
        }
        struct timespec nap = {0, nap_ns};
        nanosleep(&nap, NULL);
        if (nap_ns < 10000000)
            nap_ns *= 2;
    }
}

/* The records of the report pipe (see the supervisor): P's wait status, or why it never ran. */
rf_status ext_read_report(int fd, const ext_ctx *c, const char *point, int *status, rf_error *err)
{
    const char *prog = c->argv[0];
    int rec[2], have_status = 0;
    ssize_t n;
    while ((n = read(fd, rec, sizeof rec)) == (ssize_t)sizeof rec || (n < 0 && errno == EINTR)) {
        if (n < 0)
            continue;
        if (rec[0] == REPORT_STATUS) {
            *status = rec[1];
            have_status = 1;
        } else {
            const char *stage = rec[0] == REPORT_CHDIR ? "cannot enter the working directory" :
                                rec[0] == REPORT_EXEC  ? "exec failed" :
                                rec[0] == REPORT_FORK  ? "fork failed" :
                                                         "cannot redirect its standard streams";
            return rf_fail(err, RF_EMODEL, "cannot run program '%s' (%s) at %s: %s: %s", prog, c->program_path,
                           point, stage, strerror(rec[1]));
        }
    }
    if (!have_status)
        return rf_fail(err, RF_EIO, "program '%s' at %s: its supervisor process ended without reporting (killed?)",
                       prog, point);
    return RF_OK;
}

/* The program's end as an error: timed out, killed by a signal, or a non-zero exit. */
rf_status ext_exit_error(const ext_ctx *c, int status, int timed_out, const char *point, const char *tail,
                         rf_error *err)
{
    const char *prog = c->argv[0];
    if (timed_out)
        return rf_fail(err, RF_EMODEL, "program '%s' timed out after %g s at %s%s", prog, c->timeout, point, tail);
    if (WIFSIGNALED(status)) {
        const char *sig = sigabbrev_np(WTERMSIG(status));
        return rf_fail(err, RF_EMODEL, "program '%s' was killed by signal %d (SIG%s) at %s%s", prog, WTERMSIG(status),
                       sig ? sig : "?", point, tail);
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) != 0)
        return rf_fail(err, RF_EMODEL, "program '%s' exited with status %d at %s%s", prog, WEXITSTATUS(status), point,
                       tail);
    return RF_OK;
}

/* ---- working directories --------------------------------------------- */

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    remove(path);
    return 0;
}

static int make_dirs(const char *path)
{
    char *p = rf_strdup(path);
    if (!p)
        return ENOMEM;
    int e = 0;
    for (char *s = p + 1; !e; s++) {
        if (*s == '/' || *s == '\0') {
            char saved = *s;
            *s = '\0';
            if (mkdir(p, 0755) != 0 && errno != EEXIST)
                e = errno;
            *s = saved;
            if (!saved)
                break;
        }
    }
    free(p);
    return e;
}

/* A fresh directory root/eval-XXXXXX (root created if needed); *dir malloc'ed. */
rf_status ext_workdir_create(const char *root, char **dir, rf_error *err)
{
    int e = make_dirs(root);
    if (e)
        return rf_fail(err, RF_EIO, "cannot create the working-directory root %s: %s", root, strerror(e));
    strbuf name = {0};
    ext_sb_printf(&name, "%s/eval-XXXXXX", root);
    if (name.oom)
        return rf_fail(err, RF_ENOMEM, "out of memory for the working directory name");
    if (!mkdtemp(name.data)) {
        rf_status st = rf_fail(err, RF_EIO, "cannot create a working directory in %s: %s", root, strerror(errno));
        free(name.data);
        return st;
    }
    *dir = name.data;
    return RF_OK;
}

void ext_workdir_remove(const char *dir)
{
    nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}
