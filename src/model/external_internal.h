/* external_internal.h - what the files of the external-program model share
 * (internal, not public): the model's context, a growing string buffer, and
 * the functions each lower file offers to the ones above it.
 *
 * The files, in layers (a file calls only files listed above it):
 *   external_text.c     string buffer, whole-file read/write, {placeholder}
 *                       expansion, templates, the point x for messages;
 *   external_program.c  program lookup (PATH or path, executable check);
 *   external_output.c   parsing the outputs (named values, regexes) and the
 *                       stdout/stderr tails for messages;
 *   external_process.c  running and supervising the program (supervisor,
 *                       process group, time limit, signals, the supervisor's
 *                       report, work directories);
 *   external.c          the model: creation and validation, identity,
 *                       evaluation, destruction. */
#ifndef ROCKFUZZ_MODEL_EXTERNAL_INTERNAL_H
#define ROCKFUZZ_MODEL_EXTERNAL_INTERNAL_H

#include <regex.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "rockfuzz/status.h"

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

/* ---- external_text.c ------------------------------------------------- */

/* A growing NUL-terminated string; after a failed allocation oom is set and
 * further appends do nothing. */
typedef struct {
    char *data;
    size_t len, cap;
    int oom;
} strbuf;

void ext_sb_append(strbuf *b, const char *s, size_t n);
void ext_sb_puts(strbuf *b, const char *s);
void ext_sb_printf(strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Read a whole file (binary-safe, NUL-terminated).  Returns 0 or errno. */
int ext_read_file(const char *path, size_t max, char **text, size_t *len);
/* Write data[0..len) to path (created or truncated).  Returns 0 or errno. */
int ext_write_file(const char *path, const char *data, size_t len);

/* "(E=2.1e+11, F=1000)" for messages. */
void ext_format_point(const ext_ctx *c, const double *x, char *buf, size_t size);

/* Expand {name} placeholders of text[0..len) into out (see the definition);
 * with x == NULL and out == NULL only unknown names are reported. */
rf_status ext_expand(const ext_ctx *c, const char *text, size_t len, const double *x, const char *where, strbuf *out,
                     rf_error *err);

/* The templates with the values of x in place, written into dir. */
rf_status ext_write_templates(const ext_ctx *c, const double *x, const char *dir, rf_error *err);

/* ---- external_program.c ---------------------------------------------- */

/* The program argv[0] as a path to an executable file (*out malloc'ed). */
rf_status ext_resolve_program(const char *name, char **out, rf_error *err);

/* ---- external_output.c ----------------------------------------------- */

/* "; stderr tail: ..." (or stdout's when stderr is empty) for messages. */
void ext_output_tail(const char *dir, char *msg, size_t size);

/* Every output from stdout or its file; each file is read once. */
rf_status ext_read_outputs(const ext_ctx *c, const char *dir, const char *point, const char *tail, double *y,
                           rf_error *err);

/* ---- external_process.c ---------------------------------------------- */

/* A fresh directory root/eval-XXXXXX (root created if needed); *dir malloc'ed. */
rf_status ext_workdir_create(const char *root, char **dir, rf_error *err);
/* Remove a working directory and everything in it. */
void ext_workdir_remove(const char *dir);

/* Fork the supervisor of one run of the program (argv expanded for x); on
 * success *pid is the supervisor and *report_fd the read end of its report pipe. */
rf_status ext_start_program(const ext_ctx *c, const double *x, const char *dir, const char *point, pid_t *pid,
                            int *report_fd, rf_error *err);

/* Wait for the supervisor; on a timeout or an interruption ask it to stop. */
void ext_wait_supervisor(const ext_ctx *c, pid_t pid, int *timed_out, int *interrupted);

/* The records of the report pipe: the program's wait status, or why it never ran. */
rf_status ext_read_report(int fd, const ext_ctx *c, const char *point, int *status, rf_error *err);

/* The program's end as an error: timed out, killed by a signal, or a non-zero exit. */
rf_status ext_exit_error(const ext_ctx *c, int status, int timed_out, const char *point, const char *tail,
                         rf_error *err);

#endif
