/* external.c - a model that is another program (e.g. an FE code) run once
 * per evaluation, driven through input templates and output parsing.
 *
 * Creation checks everything that can be checked without running: the
 * program is looked up (PATH or path), every {placeholder} in argv and in the
 * templates names a parameter, template files are read once (their contents
 * enter the identity hash), output files are relative names, and regexes
 * compile with a capture group.
 *
 * One evaluation:
 *   1. a fresh directory workdir_root/eval-XXXXXX (mkdtemp) - the only state;
 *      no chdir in this process, so evaluations run concurrently;
 *   2. templates are written there with placeholders replaced by %.17g of
 *      the parameter values;
 *   3. fork + execve of the resolved program (never a shell, so a value or an
 *      argument cannot be interpreted as shell syntax), in its own process
 *      group, cwd = that directory, stdin /dev/null, stdout/stderr to
 *      stdout.txt/stderr.txt there;
 *   4. wait, polling, with a time limit; on timeout the whole process group
 *      is killed with SIGKILL;
 *   5. outputs are parsed from stdout.txt or files; the directory is removed
 *      on success (unless keep_workdirs) and kept and named on failure.
 *
 * Every file descriptor is opened close-on-exec so that a child forked by a
 * concurrent evaluation does not inherit another evaluation's files. */
#undef _POSIX_C_SOURCE
#define _GNU_SOURCE
#include "rockfuzz/model.h"
#include "core/hash.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <math.h>
#include <regex.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdint.h>
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

#define OUTPUT_FILE_MAX (256u << 20) /* refuse to parse larger output files */
#define TAIL_BYTES 400               /* stderr/stdout excerpt in error messages */

typedef struct {
    char *name;
    char *file;     /* NULL = stdout */
    char *pattern;  /* NULL = "NAME = value" lookup */
    char *unit;
    regex_t regex;  /* compiled pattern (regexec is thread-safe in glibc) */
    int has_regex;
} ext_output;

typedef struct {
    char *src;      /* path it was read from (for messages) */
    char *dst;      /* file name in the working directory */
    char *text;     /* contents, NUL-terminated */
    size_t len;
} ext_template;

typedef struct {
    size_t n_params;
    char **param_names;
    size_t argc;
    char **argv;        /* as given; argv[0] is used in messages */
    char *program_path; /* argv[0] resolved at creation (absolute or with '/') */
    size_t n_templates;
    ext_template *templates;
    size_t n_outputs;
    ext_output *outputs;
    double timeout;
    char *workdir_root;
    int keep_workdirs;
    const atomic_int *interrupt; /* rf_model.set_interrupt; NULL = never */
    uint64_t program_hash;       /* FNV-1a of the program file (identity) */
} ext_ctx;

/* ---- small helpers ---------------------------------------------------- */

typedef struct {
    char *data;
    size_t len, cap;
    int oom;
} strbuf;

static void sb_append(strbuf *b, const char *s, size_t n)
{
    if (b->oom)
        return;
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 64;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *d = realloc(b->data, cap);
        if (!d) {
            b->oom = 1;
            return;
        }
        b->data = d;
        b->cap = cap;
    }
    memcpy(b->data + b->len, s, n);
    b->len += n;
    b->data[b->len] = '\0';
}

static void sb_puts(strbuf *b, const char *s) { sb_append(b, s, strlen(s)); }

static void sb_printf(strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void sb_printf(strbuf *b, const char *fmt, ...)
{
    char tmp[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->oom = 1;
        return;
    }
    if ((size_t)n < sizeof tmp) {
        sb_append(b, tmp, (size_t)n);
        return;
    }
    char *big = malloc((size_t)n + 1);
    if (!big) {
        b->oom = 1;
        return;
    }
    va_start(ap, fmt);
    vsnprintf(big, (size_t)n + 1, fmt, ap);
    va_end(ap);
    sb_append(b, big, (size_t)n);
    free(big);
}

/* Read a whole file (binary-safe, NUL-terminated).  Returns 0 or errno. */
static int read_file(const char *path, size_t max, char **text, size_t *len)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return errno;
    strbuf b = {0};
    char chunk[65536];
    int e = 0;
    for (;;) {
        ssize_t n = read(fd, chunk, sizeof chunk);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            e = errno;
            break;
        }
        if (n == 0)
            break;
        if (b.len + (size_t)n > max) {
            e = EFBIG;
            break;
        }
        sb_append(&b, chunk, (size_t)n);
        if (b.oom) {
            e = ENOMEM;
            break;
        }
    }
    close(fd);
    if (!e && !b.data) {
        b.data = calloc(1, 1);
        if (!b.data)
            e = ENOMEM;
    }
    if (e) {
        free(b.data);
        return e;
    }
    *text = b.data;
    *len = b.len;
    return 0;
}

static int write_file(const char *path, const char *data, size_t len)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return errno;
    while (len > 0) {
        ssize_t n = write(fd, data, len);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            int e = errno;
            close(fd);
            return e;
        }
        data += n;
        len -= (size_t)n;
    }
    return close(fd) == 0 ? 0 : errno;
}

#define HASHED_FILE_MAX (1u << 30) /* program and script files hashed into the identity */

/* FNV-1a of a whole file; 0 and *h set, or errno. */
static int file_hash(const char *path, uint64_t *h)
{
    char *text = NULL;
    size_t len = 0;
    int e = read_file(path, HASHED_FILE_MAX, &text, &len);
    if (!e)
        *h = rf_fnv1a(RF_FNV1A_OFFSET, text, len);
    free(text);
    return e;
}

/* "(E=2.1e+11, F=1000)" for messages. */
static void format_point(const ext_ctx *c, const double *x, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    used += (size_t)snprintf(buf, size, "(");
    for (size_t i = 0; i < c->n_params && used + 1 < size; i++)
        used += (size_t)snprintf(buf + used, size - used, "%s%s=%.10g", i ? ", " : "", c->param_names[i], x[i]);
    if (used + 1 < size)
        snprintf(buf + used, size - used, ")");
}

/* ---- placeholders ----------------------------------------------------- */

static int is_placeholder_char(char ch)
{
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
           ch == '.' || ch == '-';
}

/* Expand {name} placeholders of text[0..len) into out.  "{{" is a literal
 * "{"; a "{" not followed by name characters and "}" is literal too, so
 * that awk programs or JSON survive.  With x == NULL nothing is written and
 * only unknown names are reported (where names the text, e.g. "argv[2]"). */
static rf_status expand(const ext_ctx *c, const char *text, size_t len, const double *x, const char *where,
                        strbuf *out, rf_error *err)
{
    size_t i = 0, lit = 0;
    while (i < len) {
        if (text[i] != '{') {
            i++;
            continue;
        }
        if (i + 1 < len && text[i + 1] == '{') {
            if (out) {
                sb_append(out, text + lit, i - lit);
                sb_append(out, "{", 1);
            }
            i += 2;
            lit = i;
            continue;
        }
        size_t j = i + 1;
        while (j < len && is_placeholder_char(text[j]))
            j++;
        if (j == i + 1 || j >= len || text[j] != '}') {
            i++;
            continue;
        }
        size_t name_len = j - i - 1;
        size_t p = 0;
        while (p < c->n_params &&
               !(strlen(c->param_names[p]) == name_len && memcmp(c->param_names[p], text + i + 1, name_len) == 0))
            p++;
        if (p == c->n_params) {
            size_t line = 1;
            for (size_t k = 0; k < i; k++)
                line += text[k] == '\n';
            strbuf known = {0};
            for (size_t k = 0; k < c->n_params; k++)
                sb_printf(&known, "%s%s", k ? ", " : "", c->param_names[k]);
            rf_status st = rf_fail(err, RF_EINVAL,
                                   "%s, line %zu: unknown placeholder '{%.*s}' (parameters: %s; write '{{' for a literal '{')",
                                   where, line, (int)name_len, text + i + 1, known.data ? known.data : "none");
            free(known.data);
            return st;
        }
        if (out) {
            sb_append(out, text + lit, i - lit);
            sb_printf(out, "%.17g", x[p]);
        }
        i = j + 1;
        lit = i;
    }
    if (out) {
        sb_append(out, text + lit, len - lit);
        if (!out->data)
            sb_append(out, "", 0);
        if (out->oom)
            return rf_fail(err, RF_ENOMEM, "out of memory expanding %s", where);
    }
    return RF_OK;
}

/* ---- program lookup --------------------------------------------------- */

static int is_executable_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) && access(path, X_OK) == 0;
}

static rf_status resolve_program(const char *name, char **out, rf_error *err)
{
    if (!name[0])
        return rf_fail(err, RF_EINVAL, "external model: argv[0] (the program) is empty");
    if (strchr(name, '/')) {
        /* Relative paths are resolved now, against this process's working
         * directory: the child runs in another directory. */
        char *real = realpath(name, NULL);
        if (!real)
            return rf_fail(err, RF_EINVAL, "external model: program '%s' not found: %s", name, strerror(errno));
        if (!is_executable_file(real)) {
            rf_status st = rf_fail(err, RF_EINVAL, "external model: program '%s' is not an executable file", name);
            free(real);
            return st;
        }
        *out = real;
        return RF_OK;
    }
    const char *path = getenv("PATH");
    if (!path || !path[0])
        path = "/usr/local/bin:/usr/bin:/bin";
    const char *p = path;
    for (;;) {
        size_t n = strcspn(p, ":");
        strbuf cand = {0};
        if (n == 0)
            sb_puts(&cand, ".");
        else
            sb_append(&cand, p, n);
        sb_printf(&cand, "/%s", name);
        if (cand.oom) {
            free(cand.data);
            return rf_fail(err, RF_ENOMEM, "out of memory looking up program '%s'", name);
        }
        if (is_executable_file(cand.data)) {
            char *real = n == 0 ? realpath(cand.data, NULL) : NULL;
            if (real) {
                free(cand.data);
                cand.data = real;
            }
            *out = cand.data;
            return RF_OK;
        }
        free(cand.data);
        if (!p[n])
            break;
        p += n + 1;
    }
    return rf_fail(err, RF_EINVAL, "external model: program '%s' not found on PATH (%s)", name, path);
}

/* ---- output parsing --------------------------------------------------- */

/* Parse a number from s[0..len) (whitespace around allowed, nothing else).
 * Fortran's "1.5D-03" is accepted. */
static int parse_number(const char *s, size_t len, double *v)
{
    while (len && (*s == ' ' || *s == '\t'))
        s++, len--;
    while (len && (s[len - 1] == ' ' || s[len - 1] == '\t' || s[len - 1] == '\r' || s[len - 1] == '\n'))
        len--;
    char buf[128];
    if (len == 0 || len >= sizeof buf)
        return 0;
    memcpy(buf, s, len);
    buf[len] = '\0';
    for (size_t i = 1; i + 1 < len; i++) {
        if ((buf[i] == 'D' || buf[i] == 'd') && (buf[i - 1] == '.' || (buf[i - 1] >= '0' && buf[i - 1] <= '9')))
            buf[i] = 'e';
    }
    char *end = NULL;
    errno = 0;
    double d = strtod(buf, &end);
    if (end == buf || *end != '\0')
        return 0;
    *v = d;
    return 1;
}

static void copy_excerpt(const char *s, size_t len, char *buf, size_t size)
{
    if (len > size - 4) {
        len = size - 4;
        snprintf(buf, size, "%.*s...", (int)len, s);
    } else {
        snprintf(buf, size, "%.*s", (int)len, s);
    }
}

/* The first line whose first word is the output name: "NAME = v", "NAME: v"
 * or "NAME v"; text after the number (e.g. a unit) is ignored. */
static rf_status parse_named(const ext_output *o, const char *text, const char *source, double *v, rf_error *err)
{
    size_t name_len = strlen(o->name);
    size_t line_no = 0;
    for (const char *line = text; *line;) {
        line_no++;
        size_t line_len = strcspn(line, "\n");
        const char *p = line;
        while (*p == ' ' || *p == '\t')
            p++;
        if (strncmp(p, o->name, name_len) == 0 && strchr(" \t=:", p[name_len]) && p[name_len]) {
            p += name_len;
            while (*p == ' ' || *p == '\t')
                p++;
            if (*p == '=' || *p == ':')
                p++;
            while (*p == ' ' || *p == '\t')
                p++;
            size_t num_len = strcspn(p, " \t\r\n");
            char excerpt[160];
            copy_excerpt(line, line_len, excerpt, sizeof excerpt);
            if (!parse_number(p, num_len, v))
                return rf_fail(err, RF_EMODEL, "output '%s': line %zu of %s has no number after '%s': \"%s\"", o->name,
                               line_no, source, o->name, excerpt);
            if (!isfinite(*v))
                return rf_fail(err, RF_EMODEL, "output '%s': line %zu of %s gives a non-finite value: \"%s\"",
                               o->name, line_no, source, excerpt);
            return RF_OK;
        }
        line += line_len;
        if (*line == '\n')
            line++;
    }
    return rf_fail(err, RF_EMODEL, "output '%s': no line starting with '%s =', '%s:' or '%s ' in %s", o->name,
                   o->name, o->name, o->name, source);
}

static rf_status parse_regex(const ext_output *o, const char *text, const char *source, double *v, rf_error *err)
{
    regmatch_t m[2];
    if (regexec(&o->regex, text, 2, m, 0) != 0)
        return rf_fail(err, RF_EMODEL, "output '%s': pattern \"%s\" does not match %s", o->name, o->pattern, source);
    if (m[1].rm_so < 0)
        return rf_fail(err, RF_EMODEL, "output '%s': pattern \"%s\" matched %s but its capture group did not",
                       o->name, o->pattern, source);
    const char *s = text + m[1].rm_so;
    size_t len = (size_t)(m[1].rm_eo - m[1].rm_so);
    char excerpt[160];
    copy_excerpt(s, len, excerpt, sizeof excerpt);
    if (!parse_number(s, len, v))
        return rf_fail(err, RF_EMODEL, "output '%s': pattern \"%s\" captured \"%s\" in %s, which is not a number",
                       o->name, o->pattern, excerpt, source);
    if (!isfinite(*v))
        return rf_fail(err, RF_EMODEL, "output '%s': pattern \"%s\" captured a non-finite value \"%s\" in %s",
                       o->name, o->pattern, excerpt, source);
    return RF_OK;
}

/* Last TAIL_BYTES of a file, lines joined with " | " (empty if none). */
static void file_tail(const char *path, char *buf, size_t size)
{
    buf[0] = '\0';
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return;
    char raw[TAIL_BYTES + 1];
    off_t end = lseek(fd, 0, SEEK_END);
    off_t start = end > TAIL_BYTES ? end - TAIL_BYTES : 0;
    ssize_t n = pread(fd, raw, TAIL_BYTES, start);
    close(fd);
    if (n <= 0)
        return;
    size_t a = 0, b = (size_t)n;
    if (start > 0) { /* start at a line boundary if one is near */
        const char *nl = memchr(raw, '\n', b);
        if (nl && (size_t)(nl - raw) < b / 2)
            a = (size_t)(nl - raw) + 1;
    }
    while (b > a && strchr(" \t\r\n", raw[b - 1]))
        b--;
    size_t used = 0;
    if (start > 0 && a == 0 && used + 4 < size)
        used += (size_t)snprintf(buf, size, "...");
    for (size_t i = a; i < b && used + 4 < size; i++) {
        char ch = raw[i];
        if (ch == '\n') {
            used += (size_t)snprintf(buf + used, size - used, " | ");
        } else if (ch != '\r' && ch != '\0') {
            buf[used++] = (ch == '\t') ? ' ' : ch;
            buf[used] = '\0';
        }
    }
}

/* ---- the supervisor and the program ------------------------------------
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

/* ---- evaluation ------------------------------------------------------- */

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

typedef struct {
    char *file;  /* NULL = stdout */
    char *text;
    size_t len;
} read_cache;

/* Wait for the supervisor; on a timeout or an interruption ask it to stop
 * (SIGTERM: it kills the program and every descendant), then reap it. */
static void wait_supervisor(const ext_ctx *c, pid_t pid, int *timed_out, int *interrupted)
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
static rf_status read_report(int fd, const ext_ctx *c, const char *point, int *status, rf_error *err)
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

/* The templates with the values of x in place, written into dir. */
static rf_status write_templates(const ext_ctx *c, const double *x, const char *dir, rf_error *err)
{
    for (size_t t = 0; t < c->n_templates; t++) {
        strbuf text = {0};
        rf_status st = expand(c, c->templates[t].text, c->templates[t].len, x, c->templates[t].src, &text, err);
        if (st != RF_OK)
            return st;
        strbuf path = {0};
        sb_printf(&path, "%s/%s", dir, c->templates[t].dst);
        int e = path.oom ? ENOMEM : write_file(path.data, text.data, text.len);
        free(text.data);
        free(path.data);
        if (e)
            return rf_fail(err, RF_EIO, "cannot write template '%s' into %s: %s", c->templates[t].dst, dir, strerror(e));
    }
    return RF_OK;
}

/* Fork the supervisor of one run of the program (argv expanded for x); on
 * success *pid is the supervisor and *report_fd the read end of its report pipe. */
static rf_status start_program(const ext_ctx *c, const double *x, const char *dir, const char *point, pid_t *pid,
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
        st = expand(c, c->argv[a], strlen(c->argv[a]), x, "argv", &arg, err);
        argv[a] = arg.data;
    }
    strbuf out_path = {0}, err_path = {0};
    sb_printf(&out_path, "%s/stdout.txt", dir);
    sb_printf(&err_path, "%s/stderr.txt", dir);
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

/* "; stderr tail: ..." (or stdout's when stderr is empty) for messages. */
static void output_tail(const char *dir, char *msg, size_t size)
{
    char path[PATH_MAX], tail[TAIL_BYTES + 64];
    const char *which = "stderr";
    snprintf(path, sizeof path, "%s/stderr.txt", dir);
    file_tail(path, tail, sizeof tail);
    if (!tail[0]) {
        which = "stdout";
        snprintf(path, sizeof path, "%s/stdout.txt", dir);
        file_tail(path, tail, sizeof tail);
    }
    if (tail[0])
        snprintf(msg, size, "; %s tail: %s", which, tail);
    else
        snprintf(msg, size, "; no output on stdout or stderr");
}

/* The program's end as an error: timed out, killed by a signal, or a non-zero exit. */
static rf_status exit_error(const ext_ctx *c, int status, int timed_out, const char *point, const char *tail,
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

/* Every output from stdout or its file; each file is read once. */
static rf_status read_outputs(const ext_ctx *c, const char *dir, const char *point, const char *tail, double *y,
                              rf_error *err)
{
    const char *prog = c->argv[0];
    read_cache *cache = calloc(c->n_outputs, sizeof *cache);
    if (!cache)
        return rf_fail(err, RF_ENOMEM, "out of memory reading outputs");
    size_t n_cache = 0;
    rf_status st = RF_OK;
    for (size_t k = 0; k < c->n_outputs && st == RF_OK; k++) {
        const ext_output *o = &c->outputs[k];
        const char *file = o->file ? o->file : "stdout.txt";
        size_t hit = 0;
        while (hit < n_cache && strcmp(cache[hit].file, file) != 0)
            hit++;
        if (hit == n_cache) {
            strbuf path = {0};
            sb_printf(&path, "%s/%s", dir, file);
            int e = path.oom ? ENOMEM : read_file(path.data, OUTPUT_FILE_MAX, &cache[hit].text, &cache[hit].len);
            free(path.data);
            if (e) {
                st = rf_fail(err, RF_EMODEL, "program '%s' at %s: output '%s': cannot read %s: %s%s", prog, point,
                             o->name, file, strerror(e), tail);
                break;
            }
            cache[hit].file = (char *)file;
            n_cache++;
        }
        const char *source = o->file ? o->file : "stdout";
        st = o->has_regex ? parse_regex(o, cache[hit].text, source, &y[k], err)
                          : parse_named(o, cache[hit].text, source, &y[k], err);
        if (st != RF_OK)
            rf_error_prefix(err, "program '%s' at %s", prog, point);
    }
    for (size_t i = 0; i < n_cache; i++)
        free(cache[i].text);
    free(cache);
    return st;
}

static rf_status run_once(const ext_ctx *c, const double *x, const char *dir, double *y, rf_error *err)
{
    char point[512];
    format_point(c, x, point, sizeof point);
    pid_t pid = -1;
    int report_fd = -1;
    rf_status st = write_templates(c, x, dir, err);
    if (st == RF_OK)
        st = start_program(c, x, dir, point, &pid, &report_fd, err);
    if (st != RF_OK)
        return st;
    int status = 0, timed_out = 0, interrupted = 0;
    wait_supervisor(c, pid, &timed_out, &interrupted);
    st = read_report(report_fd, c, point, &status, err);
    close(report_fd);
    if (st == RF_OK && interrupted)
        return rf_fail(err, RF_EINTERRUPTED, "program '%s' at %s was stopped: the run was interrupted", c->argv[0],
                       point);
    if (st != RF_OK)
        return st;
    char tail[TAIL_BYTES + 128];
    output_tail(dir, tail, sizeof tail);
    st = exit_error(c, status, timed_out, point, tail, err);
    return st == RF_OK ? read_outputs(c, dir, point, tail, y, err) : st;
}

static rf_status external_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    const ext_ctx *c = ctx;
    int e = make_dirs(c->workdir_root);
    if (e)
        return rf_fail(err, RF_EIO, "cannot create the working-directory root %s: %s", c->workdir_root, strerror(e));
    strbuf dir = {0};
    sb_printf(&dir, "%s/eval-XXXXXX", c->workdir_root);
    if (dir.oom)
        return rf_fail(err, RF_ENOMEM, "out of memory for the working directory name");
    if (!mkdtemp(dir.data)) {
        rf_status st = rf_fail(err, RF_EIO, "cannot create a working directory in %s: %s", c->workdir_root,
                               strerror(errno));
        free(dir.data);
        return st;
    }
    rf_error local = {0};
    if (!err)
        err = &local;
    rf_status st = run_once(c, x, dir.data, y, err);
    if (st == RF_EINTERRUPTED && !c->keep_workdirs) {
        nftw(dir.data, remove_entry, 16, FTW_DEPTH | FTW_PHYS); /* stopped on request: no evidence to keep */
    } else if (st != RF_OK) {
        char msg[RF_ERROR_MAX];
        memcpy(msg, err->msg, sizeof msg);
        /* The directory is the evidence; make sure its name survives a long message. */
        size_t room = sizeof msg - strlen(dir.data) - 40;
        if (strlen(msg) > room)
            snprintf(msg + room - 3, 4, "...");
        rf_fail(err, st, "%s; working directory kept: %s", msg, dir.data);
    } else if (!c->keep_workdirs) {
        nftw(dir.data, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
    }
    free(dir.data);
    return st;
}

/* ---- creation --------------------------------------------------------- */

static void external_set_interrupt(void *ctx, const atomic_int *flag)
{
    ((ext_ctx *)ctx)->interrupt = flag;
}

static void external_destroy(void *ctx)
{
    ext_ctx *c = ctx;
    if (!c)
        return;
    for (size_t i = 0; i < c->n_params; i++)
        free(c->param_names[i]);
    free(c->param_names);
    for (size_t a = 0; a < c->argc; a++)
        free(c->argv[a]);
    free(c->argv);
    free(c->program_path);
    for (size_t t = 0; t < c->n_templates; t++) {
        free(c->templates[t].src);
        free(c->templates[t].dst);
        free(c->templates[t].text);
    }
    free(c->templates);
    for (size_t k = 0; k < c->n_outputs; k++) {
        ext_output *o = &c->outputs[k];
        free(o->name);
        free(o->file);
        free(o->pattern);
        free(o->unit);
        if (o->has_regex)
            regfree(&o->regex);
    }
    free(c->outputs);
    free(c->workdir_root);
    free(c);
}

/* A relative path inside the working directory: no "..", not absolute. */
static int is_safe_relative(const char *path)
{
    if (!path[0] || path[0] == '/')
        return 0;
    for (const char *p = path; *p;) {
        size_t n = strcspn(p, "/");
        if ((n == 2 && p[0] == '.' && p[1] == '.') || n == 0)
            return 0;
        p += n;
        if (*p == '/')
            p++;
    }
    return 1;
}

static char *build_identity(const ext_ctx *c)
{
    strbuf b = {0};
    sb_puts(&b, "external(params=[");
    for (size_t i = 0; i < c->n_params; i++)
        sb_printf(&b, "%s%s", i ? "," : "", c->param_names[i]);
    sb_puts(&b, "];argv=[");
    for (size_t a = 0; a < c->argc; a++)
        sb_printf(&b, "%s\"%s\"", a ? "," : "", c->argv[a]);
    sb_printf(&b, "];program=%s:fnv1a64=%016llx;files=[", c->program_path, (unsigned long long)c->program_hash);
    /* arguments naming a file by absolute path (e.g. the script of an interpreter) */
    for (size_t a = 1, any = 0; a < c->argc; a++) {
        struct stat sb;
        uint64_t h;
        if (c->argv[a][0] == '/' && !strchr(c->argv[a], '{') && stat(c->argv[a], &sb) == 0 &&
            S_ISREG(sb.st_mode) && file_hash(c->argv[a], &h) == 0)
            sb_printf(&b, "%s%zu:fnv1a64=%016llx", any++ ? "," : "", a, (unsigned long long)h);
    }
    sb_puts(&b, "]");
    sb_puts(&b, ";templates=[");
    for (size_t t = 0; t < c->n_templates; t++)
        sb_printf(&b, "%s%s:fnv1a64=%016llx", t ? "," : "", c->templates[t].dst,
                  (unsigned long long)rf_fnv1a(RF_FNV1A_OFFSET, c->templates[t].text, c->templates[t].len));
    sb_puts(&b, "];outputs=[");
    for (size_t k = 0; k < c->n_outputs; k++) {
        const ext_output *o = &c->outputs[k];
        sb_printf(&b, "%s%s(file=%s,pattern=\"%s\",unit=%s)", k ? "," : "", o->name, o->file ? o->file : "stdout",
                  o->pattern ? o->pattern : "", o->unit ? o->unit : "");
    }
    sb_puts(&b, "])");
    if (b.oom) {
        free(b.data);
        return NULL;
    }
    return b.data;
}

static rf_status build_ctx(const rf_external_spec *spec, size_t n_params, const char *const *param_names, ext_ctx *c,
                           rf_error *err)
{
    if (spec->argc == 0 || !spec->argv || !spec->argv[0])
        return rf_fail(err, RF_EINVAL, "external model: argv is empty (the first element is the program)");
    if (spec->n_outputs == 0 || !spec->outputs)
        return rf_fail(err, RF_EINVAL, "external model: no outputs");
    if (!(spec->timeout >= 0) || !isfinite(spec->timeout))
        return rf_fail(err, RF_EINVAL, "external model: timeout %g s is not a non-negative number of seconds",
                       spec->timeout);

    c->param_names = calloc(n_params ? n_params : 1, sizeof(char *));
    c->argv = calloc(spec->argc, sizeof(char *));
    c->templates = calloc(spec->n_templates ? spec->n_templates : 1, sizeof *c->templates);
    c->outputs = calloc(spec->n_outputs, sizeof *c->outputs);
    if (!c->param_names || !c->argv || !c->templates || !c->outputs)
        return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
    /* Counters are raised before each element is filled, so that
     * external_destroy frees a half-built element after an error. */
    while (c->n_params < n_params) {
        size_t i = c->n_params++;
        if (!(c->param_names[i] = rf_strdup(param_names[i])))
            return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
    }
    while (c->argc < spec->argc) {
        size_t a = c->argc++;
        if (!spec->argv[a])
            return rf_fail(err, RF_EINVAL, "external model: argv[%zu] is NULL", a);
        if (!(c->argv[a] = rf_strdup(spec->argv[a])))
            return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
        char where[32];
        snprintf(where, sizeof where, "argv[%zu]", a);
        rf_status st = expand(c, c->argv[a], strlen(c->argv[a]), NULL, where, NULL, err);
        if (st != RF_OK)
            return rf_error_prefix(err, "external model");
    }
    if (strchr(c->argv[0], '{'))
        return rf_fail(err, RF_EINVAL, "external model: the program name '%s' cannot contain placeholders",
                       c->argv[0]);
    rf_status st = resolve_program(c->argv[0], &c->program_path, err);
    if (st != RF_OK)
        return st;
    /* An edited program must not be served from a result store: its contents enter the identity. */
    int e = file_hash(c->program_path, &c->program_hash);
    if (e)
        return rf_fail(err, e == ENOMEM ? RF_ENOMEM : RF_EIO, "external model: cannot read program '%s' (%s): %s",
                       c->argv[0], c->program_path, strerror(e));

    while (c->n_templates < spec->n_templates) {
        size_t t = c->n_templates++;
        ext_template *tp = &c->templates[t];
        const char *src = spec->template_src ? spec->template_src[t] : NULL;
        const char *dst = spec->template_dst ? spec->template_dst[t] : NULL;
        if (!src || !dst)
            return rf_fail(err, RF_EINVAL, "external model: template %zu has no source or destination", t + 1);
        tp->src = rf_strdup(src);
        tp->dst = rf_strdup(dst);
        if (!tp->src || !tp->dst)
            return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
        if (!is_safe_relative(dst) || strchr(dst, '/') || strcmp(dst, "stdout.txt") == 0 ||
            strcmp(dst, "stderr.txt") == 0)
            return rf_fail(err, RF_EINVAL,
                           "external model: template destination '%s' must be a plain file name (no '/', not "
                           "stdout.txt or stderr.txt)",
                           dst);
        for (size_t u = 0; u < t; u++) {
            if (strcmp(c->templates[u].dst, dst) == 0)
                return rf_fail(err, RF_EINVAL, "external model: template destination '%s' is given twice", dst);
        }
        int e = read_file(src, OUTPUT_FILE_MAX, &tp->text, &tp->len);
        if (e)
            return rf_fail(err, RF_EINVAL, "external model: cannot read template '%s': %s", src, strerror(e));
        char where[PATH_MAX + 32];
        snprintf(where, sizeof where, "template '%s'", src);
        st = expand(c, tp->text, tp->len, NULL, where, NULL, err);
        if (st != RF_OK)
            return rf_error_prefix(err, "external model");
    }

    while (c->n_outputs < spec->n_outputs) {
        size_t k = c->n_outputs++;
        const rf_external_output *in = &spec->outputs[k];
        ext_output *o = &c->outputs[k];
        if (!in->name || !in->name[0])
            return rf_fail(err, RF_EINVAL, "external model: output %zu has no name", k + 1);
        for (size_t j = 0; j < k; j++) {
            if (strcmp(c->outputs[j].name, in->name) == 0)
                return rf_fail(err, RF_EINVAL, "external model: output '%s' is defined twice", in->name);
        }
        o->name = rf_strdup(in->name);
        o->file = rf_strdup(in->file);
        o->pattern = rf_strdup(in->pattern);
        o->unit = rf_strdup(in->unit ? in->unit : "");
        if (!o->name || !o->unit || (in->file && !o->file) || (in->pattern && !o->pattern))
            return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
        if (o->file && !is_safe_relative(o->file))
            return rf_fail(err, RF_EINVAL,
                           "output '%s': file '%s' must be a relative path inside the working directory (no '..')",
                           o->name, o->file);
        if (o->pattern) {
            int rc = regcomp(&o->regex, o->pattern, REG_EXTENDED | REG_NEWLINE);
            if (rc != 0) {
                char msg[256];
                regerror(rc, &o->regex, msg, sizeof msg);
                return rf_fail(err, RF_EINVAL, "output '%s': invalid pattern \"%s\": %s", o->name, o->pattern, msg);
            }
            o->has_regex = 1;
            if (o->regex.re_nsub < 1)
                return rf_fail(err, RF_EINVAL,
                               "output '%s': pattern \"%s\" has no capture group; put the number in ( )", o->name,
                               o->pattern);
        }
    }

    c->timeout = spec->timeout;
    c->keep_workdirs = spec->keep_workdirs;
    if (spec->workdir_root && spec->workdir_root[0]) {
        c->workdir_root = rf_strdup(spec->workdir_root);
    } else {
        const char *tmp = getenv("TMPDIR");
        strbuf b = {0};
        sb_printf(&b, "%s/rockfuzz-eval", tmp && tmp[0] ? tmp : "/tmp");
        c->workdir_root = b.data;
    }
    if (!c->workdir_root)
        return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
    return RF_OK;
}

rf_status rf_external_model_create(const rf_external_spec *spec, size_t n_params, const char *const *param_names,
                                   rf_model *model, rf_error *err)
{
    if (!model)
        return rf_fail(err, RF_EINTERNAL, "rf_external_model_create: model is NULL");
    memset(model, 0, sizeof *model);
    if (!spec || (n_params && !param_names))
        return rf_fail(err, RF_EINTERNAL, "rf_external_model_create: NULL spec or parameter names");
    ext_ctx *c = calloc(1, sizeof *c);
    if (!c)
        return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
    rf_status st = build_ctx(spec, n_params, param_names, c, err);
    if (st != RF_OK) {
        external_destroy(c);
        return st;
    }

    model->n_inputs = n_params;
    model->eval = external_eval;
    model->ctx = c;
    model->destroy = external_destroy;
    model->set_interrupt = external_set_interrupt;
    model->threads_per_eval = 1;
    const char **names = calloc(c->n_outputs, sizeof *names);
    const char **units = calloc(c->n_outputs, sizeof *units);
    if (!names || !units) {
        st = rf_fail(err, RF_ENOMEM, "out of memory for the external model");
    } else {
        for (size_t k = 0; k < c->n_outputs; k++) {
            names[k] = c->outputs[k].name;
            units[k] = c->outputs[k].unit;
        }
        st = rf_model_init_outputs(model, c->n_outputs, names, units, err);
    }
    free(names);
    free(units);
    if (st == RF_OK) {
        char *id = build_identity(c);
        st = id ? rf_model_set_identity(model, id, err) : rf_fail(err, RF_ENOMEM, "out of memory for model identity");
        free(id);
    }
    if (st != RF_OK)
        rf_model_free(model);
    return st;
}
