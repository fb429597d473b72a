/* bind.c - parsing `bind:` and the model that maps a study's parameters onto
 * the inputs they drive (bind.h). */
#include "study/bind.h"
#include "core/util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void sb_free(sb_binding *b)
{
    for (size_t j = 0; b && j < b->n; j++)
        free(b->t[j].to);
    if (b)
        free(b->t);
    if (b)
        memset(b, 0, sizeof *b);
}

/* The target already driving `to`, or NULL. */
static const sb_target *find_target(const sb_binding *b, const char *to)
{
    for (size_t j = 0; j < b->n; j++)
        if (!strcmp(b->t[j].to, to))
            return &b->t[j];
    return NULL;
}

/* Append one target after the checks that concern it alone and its duplicates. */
static rf_status add_target(yr_ctx *c, struct fy_node *at, const char *p, const rf_study *s, sb_binding *b,
                            sb_target t, sb_check_fn check, void *user)
{
    char why[512];
    const char *bad = check(user, t.to, why, sizeof why);
    const sb_target *old = bad ? NULL : find_target(b, t.to);
    rf_status st = RF_OK;
    if (bad)
        st = at ? yr_fail(c, at, p, "%s", bad)
                : rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: %s", c->file, t.line, s->param_names[t.param], bad);
    else if (old && old->param == t.param)
        st = yr_fail(c, at, p, "%s is listed twice for this parameter", t.to);
    else if (old)
        st = at ? yr_fail(c, at, p, "%s is already driven by parameter %s (line %d); an input takes one parameter",
                          t.to, s->param_names[old->param], old->line)
                : rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: the input %s is also bound to parameter %s "
                          "(line %d); an input takes one parameter", c->file, t.line, s->param_names[t.param], t.to,
                          s->param_names[old->param], old->line);
    else if (b->n >= SB_MAX_TARGETS)
        st = yr_fail(c, at, p, "more than %d bound inputs in all", SB_MAX_TARGETS);
    if (st != RF_OK) {
        free(t.to);
        return st;
    }
    b->t[b->n++] = t;
    return RF_OK;
}

/* {to: input, scale: a, offset: b} */
static rf_status parse_affine(yr_ctx *c, struct fy_node *n, const char *p, sb_target *t)
{
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    char q[400];
    rf_status st = RF_OK;
    while (st == RF_OK && (st = yr_next(c, &it, p, &key, &k, &v)) == RF_OK && key) {
        yr_pathf(q, sizeof q, "%s.%s", p, key);
        if (!strcmp(key, "to")) {
            free(t->to);
            t->to = NULL;
            st = yr_string_dup(c, v, q, &t->to);
        } else if (!strcmp(key, "scale") || !strcmp(key, "offset")) {
            double *d = key[0] == 's' ? &t->scale : &t->offset;
            if ((st = yr_number(c, v, q, d)) == RF_OK && !(fabs(*d) <= 1e300))
                st = yr_fail(c, v, q, "must be finite");
            else if (st == RF_OK && key[0] == 's' && *d == 0)
                st = yr_fail(c, v, q, "a scale of 0 would leave the input constant; give it as a crisp value");
        } else {
            st = yr_fail(c, k, q, "unknown key; a bound input takes to, scale and offset (value * scale + offset)");
        }
    }
    if (st == RF_OK && !t->to)
        st = yr_fail(c, n, p, "missing to (the input this parameter drives)");
    return st;
}

/* One element of a binding: "input" or {to: input, scale: a, offset: b}. */
static rf_status parse_one(yr_ctx *c, struct fy_node *n, const char *p, size_t param, const rf_study *s,
                           sb_binding *b, sb_check_fn check, void *user)
{
    sb_target t = {param, NULL, 1.0, 0.0, yr_line(n)};
    rf_status st = n && fy_node_get_type(n) == FYNT_MAPPING ? parse_affine(c, n, p, &t)
                                                           : yr_string_dup(c, n, p, &t.to);
    if (st != RF_OK) {
        free(t.to);
        return st;
    }
    return add_target(c, n, p, s, b, t, check, user);
}

/* The entry of parameter i: one input, or a list of them. */
static rf_status parse_entry(yr_ctx *c, struct fy_node *v, const char *p, size_t i, const rf_study *s,
                             sb_binding *b, sb_check_fn check, void *user)
{
    if (!v || fy_node_get_type(v) != FYNT_SEQUENCE)
        return parse_one(c, v, p, i, s, b, check, user);
    int cnt = fy_node_sequence_item_count(v);
    if (cnt < 1)
        return yr_fail(c, v, p, "parameter %s is bound to nothing; list at least one input", s->param_names[i]);
    rf_status st = RF_OK;
    char q[400];
    for (int k = 0; k < cnt && st == RF_OK; k++) {
        yr_pathf(q, sizeof q, "%s[%d]", p, k);
        st = parse_one(c, fy_node_sequence_get_by_index(v, k), q, i, s, b, check, user);
    }
    return st;
}

/* Every key of `bind` must be a parameter. */
static rf_status check_keys(yr_ctx *c, struct fy_node *bind, const char *path, const rf_study *s)
{
    yr_iter it = {bind, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    rf_status st;
    char p[400];
    while ((st = yr_next(c, &it, path, &key, &k, &v)) == RF_OK && key) {
        size_t i = 0;
        while (i < s->n_params && strcmp(s->param_names[i], key))
            i++;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (i == s->n_params)
            return yr_fail(c, k, p, "not a parameter of this study (parameters: are the names bound here)");
    }
    return st;
}

static rf_status parse_param(yr_ctx *c, struct fy_node *bind, const char *path, const rf_study *s, size_t i,
                             int self, sb_check_fn check, void *user, sb_binding *b)
{
    struct fy_node *v = bind ? fy_node_mapping_lookup_by_string(bind, s->param_names[i], FY_NT) : NULL;
    char p[400];
    yr_pathf(p, sizeof p, "%s.%s", path, s->param_names[i]);
    if (v)
        return parse_entry(c, v, p, i, s, b, check, user);
    if (!self)
        return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: not bound to an input of the model (%s: {%s: "
                       "INPUT} or a list [INPUT, {to: INPUT, scale: a, offset: b}])", c->file, s->param_line[i],
                       s->param_names[i], path, s->param_names[i]);
    sb_target t = {i, yr_strdup(s->param_names[i]), 1.0, 0.0, s->param_line[i]};
    if (!t.to)
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    return add_target(c, NULL, p, s, b, t, check, user);
}

rf_status sb_parse(yr_ctx *c, struct fy_node *bind, const char *path, const rf_study *s, int self,
                   sb_check_fn check, void *user, sb_binding *b)
{
    memset(b, 0, sizeof *b);
    if (!(b->t = calloc(SB_MAX_TARGETS, sizeof *b->t)))
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    rf_status st = bind ? yr_mapping(c, bind, path) : RF_OK;
    if (st == RF_OK && bind)
        st = check_keys(c, bind, path, s);
    for (size_t i = 0; i < s->n_params && st == RF_OK; i++)
        st = parse_param(c, bind, path, s, i, self, check, user, b);
    if (st != RF_OK)
        sb_free(b);
    return st;
}

const char **sb_names(const sb_binding *b)
{
    const char **n = calloc(b->n ? b->n : 1, sizeof *n);
    for (size_t j = 0; n && j < b->n; j++)
        n[j] = b->t[j].to;
    return n;
}

const char *sb_targets_of(const sb_binding *b, size_t i, char *buf, size_t size)
{
    size_t len = 0;
    buf[0] = '\0';
    for (size_t j = 0; j < b->n && len < size; j++)
        if (b->t[j].param == i)
            len += (size_t)snprintf(buf + len, size - len, "%s%s", len ? ", " : "", b->t[j].to);
    return buf;
}

void sb_expand(const sb_binding *b, const double *x, double *xi)
{
    for (size_t j = 0; j < b->n; j++)
        xi[j] = x[b->t[j].param] * b->t[j].scale + b->t[j].offset;
}
