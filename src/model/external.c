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
 * concurrent evaluation does not inherit another evaluation's files.
 *
 * This file is the model itself (creation and validation, identity,
 * evaluation, destruction); the work it does lives in the files listed in
 * external_internal.h, below it. */
#include "rockfuzz/model.h"
#include "core/hash.h"
#include "external_internal.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <regex.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/util.h"

/* ---- evaluation ------------------------------------------------------ */

static rf_status run_once(const ext_ctx *c, const double *x, const char *dir, double *y, rf_error *err)
{
    char point[512];
    ext_format_point(c, x, point, sizeof point);
    pid_t pid = -1;
    int report_fd = -1;
    rf_status st = ext_write_templates(c, x, dir, err);
    if (st == RF_OK)
        st = ext_start_program(c, x, dir, point, &pid, &report_fd, err);
    if (st != RF_OK)
        return st;
    int status = 0, timed_out = 0, interrupted = 0;
    ext_wait_supervisor(c, pid, &timed_out, &interrupted);
    st = ext_read_report(report_fd, c, point, &status, err);
    close(report_fd);
    if (st == RF_OK && interrupted)
        return rf_fail(err, RF_EINTERRUPTED, "program '%s' at %s was stopped: the run was interrupted", c->argv[0],
                       point);
    if (st != RF_OK)
        return st;
    char tail[TAIL_BYTES + 128];
    ext_output_tail(dir, tail, sizeof tail);
    st = ext_exit_error(c, status, timed_out, point, tail, err);
    return st == RF_OK ? ext_read_outputs(c, dir, point, tail, y, err) : st;
}

static rf_status external_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    const ext_ctx *c = ctx;
    char *dir = NULL;
    rf_status st = ext_workdir_create(c->workdir_root, &dir, err);
    if (st != RF_OK)
        return st;
    rf_error local = {0};
    if (!err)
        err = &local;
    st = run_once(c, x, dir, y, err);
    if (st == RF_EINTERRUPTED && !c->keep_workdirs) {
        ext_workdir_remove(dir); /* stopped on request: no evidence to keep */
    } else if (st != RF_OK) {
        char msg[RF_ERROR_MAX];
        memcpy(msg, err->msg, sizeof msg);
        /* The directory is the evidence; make sure its name survives a long message. */
        size_t room = sizeof msg - strlen(dir) - 40;
        if (strlen(msg) > room)
            snprintf(msg + room - 3, 4, "...");
        rf_fail(err, st, "%s; working directory kept: %s", msg, dir);
    } else if (!c->keep_workdirs) {
        ext_workdir_remove(dir);
    }
    free(dir);
    return st;
}

/* ---- interruption and destruction ------------------------------------ */

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

/* ---- identity -------------------------------------------------------- */

#define HASHED_FILE_MAX (1u << 30) /* program and script files hashed into the identity */

/* FNV-1a of a whole file; 0 and *h set, or errno. */
static int file_hash(const char *path, uint64_t *h)
{
    char *text = NULL;
    size_t len = 0;
    int e = ext_read_file(path, HASHED_FILE_MAX, &text, &len);
    if (!e)
        *h = rf_fnv1a(RF_FNV1A_OFFSET, text, len);
    free(text);
    return e;
}

static char *build_identity(const ext_ctx *c)
{
    strbuf b = {0};
    ext_sb_puts(&b, "external(params=[");
    for (size_t i = 0; i < c->n_params; i++)
        ext_sb_printf(&b, "%s%s", i ? "," : "", c->param_names[i]);
    ext_sb_puts(&b, "];argv=[");
    for (size_t a = 0; a < c->argc; a++)
        ext_sb_printf(&b, "%s\"%s\"", a ? "," : "", c->argv[a]);
    ext_sb_printf(&b, "];program=%s:fnv1a64=%016llx;files=[", c->program_path, (unsigned long long)c->program_hash);
    /* arguments naming a file by absolute path (e.g. the script of an interpreter) */
    for (size_t a = 1, any = 0; a < c->argc; a++) {
        struct stat sb;
        uint64_t h;
        if (c->argv[a][0] == '/' && !strchr(c->argv[a], '{') && stat(c->argv[a], &sb) == 0 &&
            S_ISREG(sb.st_mode) && file_hash(c->argv[a], &h) == 0)
            ext_sb_printf(&b, "%s%zu:fnv1a64=%016llx", any++ ? "," : "", a, (unsigned long long)h);
    }
    ext_sb_puts(&b, "]");
    ext_sb_puts(&b, ";templates=[");
    for (size_t t = 0; t < c->n_templates; t++)
        ext_sb_printf(&b, "%s%s:fnv1a64=%016llx", t ? "," : "", c->templates[t].dst,
                      (unsigned long long)rf_fnv1a(RF_FNV1A_OFFSET, c->templates[t].text, c->templates[t].len));
    ext_sb_puts(&b, "];outputs=[");
    for (size_t k = 0; k < c->n_outputs; k++) {
        const ext_output *o = &c->outputs[k];
        ext_sb_printf(&b, "%s%s(file=%s,pattern=\"%s\",unit=%s)", k ? "," : "", o->name, o->file ? o->file : "stdout",
                      o->pattern ? o->pattern : "", o->unit ? o->unit : "");
    }
    ext_sb_puts(&b, "])");
    if (b.oom) {
        free(b.data);
        return NULL;
    }
    return b.data;
}

/* ---- creation -------------------------------------------------------- */

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

/* Counters are raised before each element is filled, so that
 * external_destroy frees a half-built element after an error. */
static rf_status add_params_and_argv(const rf_external_spec *spec, size_t n_params, const char *const *param_names,
                                     ext_ctx *c, rf_error *err)
{
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
        rf_status st = ext_expand(c, c->argv[a], strlen(c->argv[a]), NULL, where, NULL, err);
        if (st != RF_OK)
            return rf_error_prefix(err, "external model");
    }
    return RF_OK;
}

static rf_status add_program(ext_ctx *c, rf_error *err)
{
    if (strchr(c->argv[0], '{'))
        return rf_fail(err, RF_EINVAL, "external model: the program name '%s' cannot contain placeholders",
                       c->argv[0]);
    rf_status st = ext_resolve_program(c->argv[0], &c->program_path, err);
    if (st != RF_OK)
        return st;
    /* An edited program must not be served from a result store: its contents enter the identity. */
    int e = file_hash(c->program_path, &c->program_hash);
    if (e)
        return rf_fail(err, e == ENOMEM ? RF_ENOMEM : RF_EIO, "external model: cannot read program '%s' (%s): %s",
                       c->argv[0], c->program_path, strerror(e));
    return RF_OK;
}

static rf_status add_templates(const rf_external_spec *spec, ext_ctx *c, rf_error *err)
{
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
        int e = ext_read_file(src, OUTPUT_FILE_MAX, &tp->text, &tp->len);
        if (e)
            return rf_fail(err, RF_EINVAL, "external model: cannot read template '%s': %s", src, strerror(e));
        char where[PATH_MAX + 32];
        snprintf(where, sizeof where, "template '%s'", src);
        rf_status st = ext_expand(c, tp->text, tp->len, NULL, where, NULL, err);
        if (st != RF_OK)
            return rf_error_prefix(err, "external model");
    }
    return RF_OK;
}

/* Output k's copy of in, with its file checked and its pattern compiled. */
static rf_status add_output(const rf_external_output *in, size_t k, ext_ctx *c, rf_error *err)
{
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
    return RF_OK;
}

static rf_status set_workdir_root(const rf_external_spec *spec, ext_ctx *c, rf_error *err)
{
    if (spec->workdir_root && spec->workdir_root[0]) {
        c->workdir_root = rf_strdup(spec->workdir_root);
    } else {
        const char *tmp = getenv("TMPDIR");
        strbuf b = {0};
        ext_sb_printf(&b, "%s/rockfuzz-eval", tmp && tmp[0] ? tmp : "/tmp");
        c->workdir_root = b.data;
    }
    if (!c->workdir_root)
        return rf_fail(err, RF_ENOMEM, "out of memory for the external model");
    return RF_OK;
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
    rf_status st = add_params_and_argv(spec, n_params, param_names, c, err);
    if (st == RF_OK)
        st = add_program(c, err);
    if (st == RF_OK)
        st = add_templates(spec, c, err);
    while (st == RF_OK && c->n_outputs < spec->n_outputs) {
        size_t k = c->n_outputs++; /* raised first: external_destroy frees a half-built output */
        st = add_output(&spec->outputs[k], k, c, err);
    }
    if (st != RF_OK)
        return st;
    c->timeout = spec->timeout;
    c->keep_workdirs = spec->keep_workdirs;
    return set_workdir_root(spec, c, err);
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
