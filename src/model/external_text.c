/* external_text.c - the text work of the external-program model: a growing
 * string buffer, whole files read and written (every descriptor
 * close-on-exec, see external.c), the point x for messages, and the
 * {placeholder} expansion of arguments and templates.  The lowest of the
 * model's files (external_internal.h): it calls none of the others. */
#include "external_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- string buffer and whole files ----------------------------------- */

void ext_sb_append(strbuf *b, const char *s, size_t n)
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

void ext_sb_puts(strbuf *b, const char *s) { ext_sb_append(b, s, strlen(s)); }

void ext_sb_printf(strbuf *b, const char *fmt, ...)
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
        ext_sb_append(b, tmp, (size_t)n);
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
    ext_sb_append(b, big, (size_t)n);
    free(big);
}

/* Read a whole file (binary-safe, NUL-terminated).  Returns 0 or errno. */
int ext_read_file(const char *path, size_t max, char **text, size_t *len)
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
        ext_sb_append(&b, chunk, (size_t)n);
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

int ext_write_file(const char *path, const char *data, size_t len)
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

/* "(E=2.1e+11, F=1000)" for messages. */
void ext_format_point(const ext_ctx *c, const double *x, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    used += (size_t)snprintf(buf, size, "(");
    for (size_t i = 0; i < c->n_params && used + 1 < size; i++)
        used += (size_t)snprintf(buf + used, size - used, "%s%s=%.10g", i ? ", " : "", c->param_names[i], x[i]);
    if (used + 1 < size)
        snprintf(buf + used, size - used, ")");
}

/* ---- placeholders ---------------------------------------------------- */

static int is_placeholder_char(char ch)
{
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
           ch == '.' || ch == '-';
}

/* Expand {name} placeholders of text[0..len) into out.  "{{" is a literal
 * "{"; a "{" not followed by name characters and "}" is literal too, so
 * that awk programs or JSON survive.  With x == NULL nothing is written and
 * only unknown names are reported (where names the text, e.g. "argv[2]"). */
rf_status ext_expand(const ext_ctx *c, const char *text, size_t len, const double *x, const char *where,
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
                ext_sb_append(out, text + lit, i - lit);
                ext_sb_append(out, "{", 1);
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
                ext_sb_printf(&known, "%s%s", k ? ", " : "", c->param_names[k]);
            rf_status st = rf_fail(err, RF_EINVAL,
                                   "%s, line %zu: unknown placeholder '{%.*s}' (parameters: %s; write '{{' for a literal '{')",
                                   where, line, (int)name_len, text + i + 1, known.data ? known.data : "none");
            free(known.data);
            return st;
        }
        if (out) {
            ext_sb_append(out, text + lit, i - lit);
            ext_sb_printf(out, "%.17g", x[p]);
        }
        i = j + 1;
        lit = i;
    }
    if (out) {
        ext_sb_append(out, text + lit, len - lit);
        if (!out->data)
            ext_sb_append(out, "", 0);
        if (out->oom)
            return rf_fail(err, RF_ENOMEM, "out of memory expanding %s", where);
    }
    return RF_OK;
}

/* The templates with the values of x in place, written into dir. */
rf_status ext_write_templates(const ext_ctx *c, const double *x, const char *dir, rf_error *err)
{
    for (size_t t = 0; t < c->n_templates; t++) {
        strbuf text = {0};
        rf_status st = ext_expand(c, c->templates[t].text, c->templates[t].len, x, c->templates[t].src, &text, err);
        if (st != RF_OK)
            return st;
        strbuf path = {0};
        ext_sb_printf(&path, "%s/%s", dir, c->templates[t].dst);
        int e = path.oom ? ENOMEM : ext_write_file(path.data, text.data, text.len);
        free(text.data);
        free(path.data);
        if (e)
            return rf_fail(err, RF_EIO, "cannot write template '%s' into %s: %s", c->templates[t].dst, dir, strerror(e));
    }
    return RF_OK;
}
