/* external_output.c - reading the external model's outputs after a run:
 * a named value ("NAME = v", "NAME: v", "NAME v") or the capture group of a
 * regex, from stdout.txt or an output file, each file read once; and the tail
 * of stderr (or stdout) that error messages quote.  Uses external_text.c
 * (external_internal.h). */
#include "external_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- parsing --------------------------------------------------------- */

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

/* ---- tails for messages ---------------------------------------------- */

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

/* "; stderr tail: ..." (or stdout's when stderr is empty) for messages. */
void ext_output_tail(const char *dir, char *msg, size_t size)
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

/* ---- reading the outputs --------------------------------------------- */

typedef struct {
    char *file;  /* NULL = stdout */
    char *text;
    size_t len;
} read_cache;

/* Every output from stdout or its file; each file is read once. */
rf_status ext_read_outputs(const ext_ctx *c, const char *dir, const char *point, const char *tail, double *y,
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
            ext_sb_printf(&path, "%s/%s", dir, file);
            int e = path.oom ? ENOMEM : ext_read_file(path.data, OUTPUT_FILE_MAX, &cache[hit].text, &cache[hit].len);
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
