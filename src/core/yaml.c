/* yaml.c - typed, located access to a libfyaml document (core/yaml.h):
 * every failure becomes "file:line: field = value: reason".  Numbers must be
 * plain finite scalars; quoted scalars are strings. */
#include "core/yaml.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

char *yr_strndup(const char *s, size_t len)
{
    char *d = malloc(len + 1);
    if (d) {
        memcpy(d, s, len);
        d[len] = '\0';
    }
    return d;
}

char *yr_strdup(const char *s) { return yr_strndup(s, strlen(s)); }

void yr_pathf(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, size, fmt, ap);
    va_end(ap);
}

/* libfyaml 0.7 has no public start mark for collections: use the scalar
 * token, or the first entry of a collection, or the key naming an empty one. */
static int scalar_line(struct fy_node *n)
{
    struct fy_token *t = fy_node_get_scalar_token(n);
    const struct fy_mark *m = t ? fy_token_start_mark(t) : NULL;
    return m ? m->line + 1 : 0;
}

int yr_line(struct fy_node *n)
{
    struct fy_node *start = n;
    for (int depth = 0; n && depth < 64; depth++) {
        void *it = NULL;
        if (fy_node_get_type(n) == FYNT_SCALAR) {
            int line = scalar_line(n);
            if (line)
                return line;
            break;
        } else if (fy_node_get_type(n) == FYNT_MAPPING) {
            struct fy_node_pair *p = fy_node_mapping_iterate(n, &it);
            if (!p)
                break;
            n = fy_node_pair_key(p) ? fy_node_pair_key(p) : fy_node_pair_value(p);
        } else {
            n = fy_node_sequence_iterate(n, &it);
        }
    }
    struct fy_node *parent = start ? fy_node_get_parent(start) : NULL;
    if (parent && fy_node_get_type(parent) == FYNT_MAPPING) {
        void *it = NULL;
        struct fy_node_pair *p;
        while ((p = fy_node_mapping_iterate(parent, &it)))
            if (fy_node_pair_value(p) == start && fy_node_pair_key(p) && fy_node_get_type(fy_node_pair_key(p)) == FYNT_SCALAR)
                return scalar_line(fy_node_pair_key(p));
    }
    return 0;
}

/* The node's text for a message, shortened; "(empty)" for a missing node. */
static void node_text(struct fy_node *n, char *buf, size_t size)
{
    if (!n) {
        snprintf(buf, size, "(empty)");
        return;
    }
    if (fy_node_get_type(n) == FYNT_SCALAR) {
        size_t len = 0;
        const char *s = fy_node_get_scalar(n, &len);
        if (!s)
            s = "", len = 0;
        if (len == 0 && fy_node_get_style(n) == FYNS_PLAIN) {
            snprintf(buf, size, "(empty)");
            return;
        }
        int quoted = fy_node_get_style(n) == FYNS_SINGLE_QUOTED || fy_node_get_style(n) == FYNS_DOUBLE_QUOTED;
        if (len > 60)
            snprintf(buf, size, "%s%.57s...%s", quoted ? "\"" : "", s, quoted ? "\"" : "");
        else
            snprintf(buf, size, "%s%.*s%s", quoted ? "\"" : "", (int)len, s, quoted ? "\"" : "");
        return;
    }
    char *e = fy_emit_node_to_string(n, FYECF_MODE_FLOW_ONELINE);
    if (!e) {
        snprintf(buf, size, fy_node_get_type(n) == FYNT_MAPPING ? "{...}" : "[...]");
        return;
    }
    size_t len = strlen(e);
    while (len && isspace((unsigned char)e[len - 1]))
        len--;
    if (len > 60)
        snprintf(buf, size, "%.57s...", e);
    else
        snprintf(buf, size, "%.*s", (int)len, e);
    free(e);
}

rf_status yr_fail(yr_ctx *c, struct fy_node *n, const char *path, const char *fmt, ...)
{
    char reason[RF_ERROR_MAX / 2], value[128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    node_text(n, value, sizeof value);
    int line = yr_line(n ? n : c->last_key);
    /* An unknown key is its own value: "x.colour: reason", not "x.colour = colour: reason". */
    const char *last = path ? strrchr(path, '.') : NULL;
    last = last ? last + 1 : path;
    if (path && *path && !strcmp(last, value))
        return rf_fail(c->err, RF_EINVAL, "%s:%d: %s: %s", c->file, line, path, reason);
    if (path && *path)
        return rf_fail(c->err, RF_EINVAL, "%s:%d: %s = %s: %s", c->file, line, path, value, reason);
    return rf_fail(c->err, RF_EINVAL, "%s:%d: %s", c->file, line, reason);
}

rf_status yr_prefix(yr_ctx *c, struct fy_node *n, const char *path)
{
    char old[RF_ERROR_MAX / 2];
    yr_pathf(old, sizeof old, "%s", c->err ? c->err->msg : "invalid");
    rf_status code = c->err ? c->err->code : RF_EINVAL;
    if (code == RF_OK)
        code = RF_EINVAL;
    yr_fail(c, n, path, "%s", old);
    if (c->err)
        c->err->code = code;
    return code;
}

static int is_quoted(struct fy_node *n);

static const char *type_name(struct fy_node *n)
{
    if (!n)
        return "nothing";
    switch (fy_node_get_type(n)) {
    case FYNT_MAPPING: return "a mapping";
    case FYNT_SEQUENCE: return "a list";
    default:
        if (fy_node_get_style(n) == FYNS_ALIAS)
            return "an alias (aliases are not supported)";
        if (is_quoted(n))
            return "a string";
        return "a scalar";
    }
}

rf_status yr_mapping(yr_ctx *c, struct fy_node *n, const char *path)
{
    if (!n || fy_node_get_type(n) != FYNT_MAPPING)
        return yr_fail(c, n, path, "expected a mapping ({key: value, ...}), got %s", type_name(n));
    return RF_OK;
}

rf_status yr_sequence(yr_ctx *c, struct fy_node *n, const char *path, size_t min, size_t max, size_t *count)
{
    if (!n || fy_node_get_type(n) != FYNT_SEQUENCE)
        return yr_fail(c, n, path, "expected a list ([a, b, ...]), got %s", type_name(n));
    int k = fy_node_sequence_item_count(n);
    size_t cnt = k < 0 ? 0 : (size_t)k;
    if (cnt < min || cnt > max) {
        if (min == max)
            return yr_fail(c, n, path, "expected a list of %zu items, got %zu", min, cnt);
        return yr_fail(c, n, path, "expected a list of %zu to %zu items, got %zu", min, max, cnt);
    }
    if (count)
        *count = cnt;
    return RF_OK;
}

static int is_scalar(struct fy_node *n)
{
    return n && fy_node_get_type(n) == FYNT_SCALAR && fy_node_get_style(n) != FYNS_ALIAS;
}

/* A scalar that is text by the author's choice: quoted, or tagged !!str
 * (YAML's explicit "this is a string", e.g. `levels: !!str 2`). */
static int is_quoted(struct fy_node *n)
{
    enum fy_node_style st = fy_node_get_style(n);
    if (st == FYNS_SINGLE_QUOTED || st == FYNS_DOUBLE_QUOTED)
        return 1;
    size_t len = 0;
    const char *tag = fy_node_get_tag(n, &len);
    static const char str_tag[] = "tag:yaml.org,2002:str";
    return tag && ((len == 5 && !memcmp(tag, "!!str", 5)) ||
                   (len == sizeof str_tag - 1 && !memcmp(tag, str_tag, len)));
}

rf_status yr_number(yr_ctx *c, struct fy_node *n, const char *path, double *v)
{
    if (!is_scalar(n) || is_quoted(n))
        return yr_fail(c, n, path, "expected a number, got %s", type_name(n));
    size_t len = 0;
    const char *s = fy_node_get_scalar(n, &len);
    char buf[64];
    if (!s || len == 0 || len >= sizeof buf)
        return yr_fail(c, n, path, "expected a number");
    memcpy(buf, s, len);
    buf[len] = '\0';
    if (isspace((unsigned char)buf[0]))
        return yr_fail(c, n, path, "expected a number");
    char *end = NULL;
    double d = strtod(buf, &end);
    if (end == buf || *end != '\0')
        return yr_fail(c, n, path, "expected a number");
    if (!isfinite(d))
        return yr_fail(c, n, path, "the number must be finite");
    *v = d;
    return RF_OK;
}

rf_status yr_integer(yr_ctx *c, struct fy_node *n, const char *path, long long min, long long max, long long *v)
{
    double d = 0;
    rf_status st = yr_number(c, n, path, &d);
    if (st != RF_OK) {
        if (is_scalar(n) && !is_quoted(n))
            return yr_fail(c, n, path, "expected an integer");
        return st;
    }
    if (d != floor(d))
        return yr_fail(c, n, path, "expected an integer");
    size_t len = 0;
    const char *s = fy_node_get_scalar(n, &len);
    size_t sign = len && (s[0] == '-' || s[0] == '+');
    long long exact = (long long)d;
    if (len > sign && len < 32 && strspn(s + sign, "0123456789") == len - sign) { /* plain digits: read exactly */
        char buf[32];
        memcpy(buf, s, len);
        buf[len] = '\0';
        errno = 0;
        exact = strtoll(buf, NULL, 10);
        if (errno)
            exact = d < 0 ? LLONG_MIN : LLONG_MAX;
    } else if (fabs(d) >= 9007199254740992.0) { /* 2^53 + 1 rounds to 2^53 */
        return yr_fail(c, n, path, "from 2^53 on an integer must be written in plain digits (a number "
                                   "with an exponent is not exact there)");
    }
    if (exact < min || exact > max)
        return yr_fail(c, n, path, "must lie in [%lld, %lld]", min, max);
    *v = exact;
    return RF_OK;
}

rf_status yr_bool(yr_ctx *c, struct fy_node *n, const char *path, int *v)
{
    if (!is_scalar(n) || is_quoted(n))
        return yr_fail(c, n, path, "expected true or false, got %s", type_name(n));
    size_t len = 0;
    const char *s = fy_node_get_scalar(n, &len);
    static const char *const yes[] = {"true", "yes", "on"}, *const no[] = {"false", "no", "off"};
    for (size_t k = 0; k < 3; k++) {
        if (s && len == strlen(yes[k]) && !strncasecmp(s, yes[k], len)) {
            *v = 1;
            return RF_OK;
        }
        if (s && len == strlen(no[k]) && !strncasecmp(s, no[k], len)) {
            *v = 0;
            return RF_OK;
        }
    }
    return yr_fail(c, n, path, "expected true or false");
}

rf_status yr_string(yr_ctx *c, struct fy_node *n, const char *path, const char **s, size_t *len)
{
    if (!is_scalar(n))
        return yr_fail(c, n, path, "expected a string, got %s", type_name(n));
    size_t l = 0;
    const char *p = fy_node_get_scalar(n, &l);
    if (!p)
        p = "", l = 0;
    if (memchr(p, '\0', l))
        return yr_fail(c, n, path, "the string contains a NUL character");
    *s = p;
    *len = l;
    return RF_OK;
}

rf_status yr_word(yr_ctx *c, struct fy_node *n, const char *path, char *buf, size_t size)
{
    const char *s = NULL;
    size_t len = 0;
    rf_status st = yr_string(c, n, path, &s, &len);
    if (st != RF_OK)
        return st;
    snprintf(buf, size, "%.*s", len < size ? (int)len : 0, s);
    return RF_OK;
}

rf_status yr_string_dup(yr_ctx *c, struct fy_node *n, const char *path, char **out)
{
    const char *s = NULL;
    size_t len = 0;
    rf_status st = yr_string(c, n, path, &s, &len);
    if (st != RF_OK)
        return st;
    *out = yr_strndup(s, len);
    if (!*out)
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    return RF_OK;
}

rf_status yr_numbers(yr_ctx *c, struct fy_node *n, const char *path, size_t min, size_t max, double *v,
                     size_t *count)
{
    size_t cnt;
    rf_status st = yr_sequence(c, n, path, min, max, &cnt);
    if (st != RF_OK)
        return st;
    for (size_t k = 0; k < cnt; k++) {
        char p[256];
        yr_pathf(p, sizeof p, "%s[%zu]", path, k);
        st = yr_number(c, fy_node_sequence_get_by_index(n, (int)k), p, &v[k]);
        if (st != RF_OK)
            return st;
    }
    if (count)
        *count = cnt;
    return RF_OK;
}

rf_status yr_next(yr_ctx *c, yr_iter *it, const char *path, const char **key, struct fy_node **keynode,
                  struct fy_node **val)
{
    *key = NULL;
    struct fy_node_pair *p = fy_node_mapping_iterate(it->map, &it->it);
    if (!p)
        return RF_OK;
    struct fy_node *k = fy_node_pair_key(p);
    struct fy_node *v = fy_node_pair_value(p);
    if (!is_scalar(k))
        return yr_fail(c, k ? k : it->map, path, "keys must be plain names, got %s", type_name(k));
    size_t len = 0;
    const char *s = fy_node_get_scalar(k, &len);
    if (!s || len == 0 || len > 200 || memchr(s, '\0', len))
        return yr_fail(c, k, path, "keys must be non-empty names of at most 200 characters");
    /* Duplicate keys are allowed by the YAML parser so that we can name them here. */
    void *jt = NULL;
    for (size_t j = 0; j < it->index; j++) {
        struct fy_node_pair *q = fy_node_mapping_iterate(it->map, &jt);
        size_t ql = 0;
        const char *qs = fy_node_get_scalar(fy_node_pair_key(q), &ql);
        if (qs && ql == len && !memcmp(qs, s, len)) {
            char full[300];
            yr_pathf(full, sizeof full, "%s%s%.*s", path, *path ? "." : "", (int)len, s);
            return yr_fail(c, k, "", "%s: duplicate key '%.*s' (first given at line %d)", full, (int)len, s,
                           yr_line(fy_node_pair_key(q)));
        }
    }
    it->index++;
    c->last_key = k;
    snprintf(it->key, sizeof it->key, "%.*s", (int)len, s);
    *key = it->key;
    *keynode = k;
    *val = v;
    return RF_OK;
}

rf_status yr_check_text(const char *name, const char *buf, size_t len, rf_error *err)
{
    const unsigned char *p = (const unsigned char *)buf;
    int line = 1;
    size_t col = 1;
    for (size_t k = 0; k < len;) {
        unsigned char ch = p[k];
        size_t extra = 0;
        unsigned cp = 0;
        if (ch == 0)
            return rf_fail(err, RF_EPARSE, "%s:%d: column %zu: the file contains a NUL byte (not a text file?)", name,
                           line, col);
        if (ch < 0x80)
            extra = 0, cp = ch;
        else if (ch >= 0xc2 && ch <= 0xdf)
            extra = 1, cp = ch & 0x1f;
        else if (ch >= 0xe0 && ch <= 0xef)
            extra = 2, cp = ch & 0x0f;
        else if (ch >= 0xf0 && ch <= 0xf4)
            extra = 3, cp = ch & 0x07;
        else
            goto bad;
        for (size_t e = 1; e <= extra; e++) {
            if (k + e >= len || (p[k + e] & 0xc0) != 0x80)
                goto bad;
            cp = (cp << 6) | (p[k + e] & 0x3f);
        }
        if ((extra == 2 && (cp < 0x800 || (cp >= 0xd800 && cp <= 0xdfff))) || (extra == 3 && (cp < 0x10000 || cp > 0x10ffff)))
            goto bad;
        if (ch == '\n')
            line++, col = 1;
        else
            col++;
        k += extra + 1;
        continue;
    bad:
        return rf_fail(err, RF_EPARSE, "%s:%d: column %zu: byte 0x%02x is not valid UTF-8 (YAML files are UTF-8 text)",
                       name, line, col, ch);
    }
    return RF_OK;
}

/* Flow collections ('[', '{') nested deeper than this are refused before
 * libfyaml parses them: it takes ~250 bytes per level (4 MB of '[': 1 GB and
 * over 30 s) before its own depth error.  The nodes' walk stops at the same
 * depth (yr_line). */
#define YR_MAX_FLOW_DEPTH 64

/* The scan's place: line, column, and the last character that was not blank. */
typedef struct {
    int line;
    size_t col;
    char prev;
} flow_pos;

/* A bracket or quote opens something only where a token starts: after a line's indent, ':', ',', '[', '{', '-' or
 * '?' (in "a[1]" or "O'Brien" it is part of a plain scalar). */
static int token_start(char prev) { return prev && strchr("\n:,[{-?", prev) != NULL; }

/* The end of the quoted scalar opened at buf[k] (the index of its closing quote, or len), counting lines. */
static size_t skip_quoted(const char *buf, size_t len, size_t k, flow_pos *at)
{
    const char q = buf[k];
    for (k++; k < len && (buf[k] != q || (q == '\'' && k + 1 < len && buf[k + 1] == '\'')); k++) {
        if ((q == '"' && buf[k] == '\\' && k + 1 < len) || (q == '\'' && buf[k] == '\''))
            k++; /* an escape, or '' in single quotes */
        if (buf[k] == '\n')
            at->line++, at->col = 0;
    }
    return k;
}

static rf_status flow_depth_check(const char *name, const char *buf, size_t len, rf_error *err)
{
    flow_pos at = {1, 1, '\n'};
    int depth = 0;
    for (size_t k = 0; k < len; k++, at.col++) {
        const char ch = buf[k];
        if (ch == '\n') {
            at.line++, at.col = 0, at.prev = '\n';
        } else if (ch == '#' && (k == 0 || buf[k - 1] == ' ' || buf[k - 1] == '\t' || buf[k - 1] == '\n')) {
            while (k + 1 < len && buf[k + 1] != '\n')
                k++;
        } else if ((ch == '"' || ch == '\'') && token_start(at.prev)) {
            k = skip_quoted(buf, len, k, &at), at.prev = ch;
        } else if ((ch == '[' || ch == '{') && token_start(at.prev)) {
            if (++depth > YR_MAX_FLOW_DEPTH)
                return rf_fail(err, RF_EPARSE, "%s:%d: column %zu: collections nested deeper than %d levels", name,
                               at.line, at.col, YR_MAX_FLOW_DEPTH);
            at.prev = ch;
        } else if ((ch == ']' || ch == '}') && depth > 0) {
            depth--, at.prev = ch;
        } else if (ch != ' ' && ch != '\t' && ch != '\r') {
            at.prev = strchr("[{\"'", ch) ? 'a' : ch; /* inside a plain scalar: it opens nothing */
        }
    }
    return RF_OK;
}

static rf_status first_document(yr_doc *d, const char *name, const char *buf, size_t len, const char *what,
                                rf_error *err)
{
    struct fy_parse_cfg pc;
    memset(&pc, 0, sizeof pc);
    /* Duplicate keys are accepted by the parser and reported by us with both lines. */
    pc.flags = FYPCF_QUIET | FYPCF_COLLECT_DIAG | FYPCF_ALLOW_DUPLICATE_KEYS;
    pc.diag = d->diag;
    d->parser = fy_parser_create(&pc);
    if (!d->parser)
        return rf_fail(err, RF_ENOMEM, "out of memory (YAML parser)");
    if (fy_parser_set_string(d->parser, len ? buf : "", len) == 0)
        d->doc = fy_parse_load_document(d->parser);
    if (d->doc)
        return RF_OK;
    void *it = NULL;
    struct fy_diag_error *e = fy_diag_errors_iterate(d->diag, &it);
    if (e)
        return rf_fail(err, RF_EPARSE, "%s:%d: not valid YAML: %s (column %d)", name, e->line, e->msg, e->column);
    return rf_fail(err, RF_EPARSE, "%s:1: the %s holds no YAML document (empty?)", name, what);
}

/* One document per file: a second one would otherwise be ignored without a word. */
static rf_status no_second_document(yr_doc *d, const char *name, const char *what, rf_error *err)
{
    struct fy_document *more = fy_parse_load_document(d->parser);
    if (!more && !fy_parser_get_stream_error(d->parser))
        return RF_OK;
    int line = more && fy_document_root(more) ? yr_line(fy_document_root(more)) : 0;
    fy_parse_document_destroy(d->parser, more);
    if (line)
        return rf_fail(err, RF_EPARSE, "%s:%d: a second YAML document (after '---'); a %s holds exactly one", name,
                       line, what);
    return rf_fail(err, RF_EPARSE, "%s: a second YAML document, or text after the first that is not YAML; a %s "
                   "holds exactly one document", name, what);
}

rf_status yr_doc_load(yr_doc *d, const char *name, const char *buf, size_t len, const char *what, rf_error *err)
{
    memset(d, 0, sizeof *d);
    rf_status st = yr_check_text(name, buf, len, err);
    if (st == RF_OK)
        st = flow_depth_check(name, buf, len, err);
    if (st != RF_OK)
        return st;
    struct fy_diag_cfg dc;
    fy_diag_cfg_default(&dc);
    dc.fp = NULL;
    dc.colorize = false;
    if (!(d->diag = fy_diag_create(&dc)))
        return rf_fail(err, RF_ENOMEM, "out of memory (YAML diagnostics)");
    fy_diag_set_collect_errors(d->diag, true);
    st = first_document(d, name, buf, len, what, err);
    if (st == RF_OK)
        st = no_second_document(d, name, what, err);
    return st;
}

void yr_doc_free(yr_doc *d)
{
    if (d->doc)
        fy_parse_document_destroy(d->parser, d->doc);
    if (d->parser)
        fy_parser_destroy(d->parser);
    if (d->diag)
        fy_diag_destroy(d->diag);
    memset(d, 0, sizeof *d);
}
