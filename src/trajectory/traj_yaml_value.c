/* traj_yaml_value.c - numbers of the trajectory file that may be random
 * ({uniform: [lo, hi]}, {normal: [mean, sd], min: a, max: b}), mappings of
 * numeric fields, and the validation of the finished spec located by the
 * lines recorded while reading (the longest recorded path that starts the
 * validator's message names the line). */
#include "trajectory/traj_yaml_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void ty_remember(ty_ctx *c, const char *path, struct fy_node *n)
{
    if (c->n_lines == c->cap_lines) {
        size_t cap = c->cap_lines ? 2 * c->cap_lines : 64;
        ty_line *p = realloc(c->lines, cap * sizeof *p);
        if (!p)
            return; /* only the message's line is lost */
        c->lines = p, c->cap_lines = cap;
    }
    ty_line *l = &c->lines[c->n_lines++];
    yr_pathf(l->path, sizeof l->path, "%s", path);
    l->line = yr_line(n);
}

void ty_ctx_free(ty_ctx *c) { free(c->lines); }

static rf_status add_random(ty_ctx *c, const char *path, rf_traj_random r)
{
    rf_traj_spec *s = c->spec;
    rf_traj_random *p = realloc(s->random, (s->n_random + 1) * sizeof *p);
    if (!p)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    s->random = p;
    r.path = rf_strdup(path);
    if (!r.path)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    s->random[s->n_random++] = r;
    return RF_OK;
}

static rf_status random_value(ty_ctx *c, struct fy_node *n, const char *path, double *dst)
{
    rf_traj_random r = {NULL, RF_DIST_FIXED, 0, 0, -INFINITY, INFINITY};
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    char p[300];
    double ab[2];
    rf_status st;
    for (;;) {
        if ((st = yr_next(&c->sp, &it, path, &key, &k, &v)) != RF_OK)
            return st;
        if (!key)
            break;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (!strcmp(key, "uniform") || !strcmp(key, "normal")) {
            if ((st = yr_numbers(&c->sp, v, p, 2, 2, ab, NULL)) != RF_OK)
                return st;
            r.dist = key[0] == 'u' ? RF_DIST_UNIFORM : RF_DIST_NORMAL;
            r.a = ab[0], r.b = ab[1];
            if (r.dist == RF_DIST_UNIFORM && !(r.a <= r.b))
                return yr_fail(&c->sp, v, p, "expected [lo, hi] with lo <= hi");
            if (r.dist == RF_DIST_NORMAL && !(r.b >= 0))
                return yr_fail(&c->sp, v, p, "expected [mean, sd] with sd >= 0");
        } else if (!strcmp(key, "min") || !strcmp(key, "max")) {
            if ((st = yr_number(&c->sp, v, p, key[1] == 'i' ? &r.lo : &r.hi)) != RF_OK)
                return st;
        } else {
            return yr_fail(&c->sp, k, p, "unknown key; a random value is {uniform: [lo, hi]} or "
                                         "{normal: [mean, sd], min: lo, max: hi}");
        }
    }
    if (r.dist == RF_DIST_FIXED)
        return yr_fail(&c->sp, n, path, "expected a number, {uniform: [lo, hi]} or {normal: [mean, sd]}");
    if (!(r.lo <= r.hi) || (r.dist == RF_DIST_NORMAL && !(r.a >= r.lo && r.a <= r.hi)))
        return yr_fail(&c->sp, n, path, "min must be <= max and the mean within them");
    *dst = r.dist == RF_DIST_UNIFORM ? 0.5 * (r.a + r.b) : r.a;
    return add_random(c, path, r);
}

rf_status ty_value(ty_ctx *c, struct fy_node *n, const char *path, double *dst, int allow_random)
{
    ty_remember(c, path, n);
    if (n && fy_node_get_type(n) == FYNT_MAPPING) {
        if (!allow_random)
            return yr_fail(&c->sp, n, path, "expected a number (this input cannot be random)");
        return random_value(c, n, path, dst);
    }
    return yr_number(&c->sp, n, path, dst);
}

rf_status ty_row_value(ty_ctx *c, struct fy_node *n, const char *path)
{
    double *dst;
    const rf_traj_field *f = rf_traj_field_at(c->spec, path, &dst);
    if (!f)
        return yr_fail(&c->sp, n, path, "not an input of a trajectory file");
    rf_status st = ty_value(c, n, path, dst, f->random);
    if (st == RF_OK)
        *dst = traj_field_store(f, *dst); /* angles: given in degrees, stored in radians */
    return st;
}

void ty_row_defaults(rf_traj_field_owner owner, void *obj)
{
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        for (size_t k = 0; tb->owner == owner && k < tb->n_rows; k++)
            *(double *)((char *)obj + tb->rows[k].offset) = traj_field_store(&tb->rows[k], tb->rows[k].def);
    }
}

static int in_list(const char *key, const char *keys)
{
    size_t len = strlen(key);
    for (const char *p = keys; (p = strstr(p, key)); p += len)
        if ((p == keys || p[-1] == ' ') && (p[len] == ' ' || p[len] == '\0'))
            return 1;
    return 0;
}

/* The row keys under `prefix` ("block", "materials.rock", "bounce") then `extra`. */
static void keys_under(const char *prefix, const char *extra, char *buf, size_t size)
{
    size_t len = 0, lp = strlen(prefix);
    rf_traj_field_owner owner = !strncmp(prefix, "materials.", 10)    ? RF_TRAJ_OWNER_MATERIAL
                                : !strncmp(prefix, "collectors.", 11) ? RF_TRAJ_OWNER_COLLECTOR
                                                                      : RF_TRAJ_OWNER_SPEC;
    buf[0] = '\0';
    /* a material's or collector's rows: those under the sub-mapping ("materials.rock.impact": "impact.") */
    const char *dot = owner != RF_TRAJ_OWNER_SPEC ? strchr(strchr(prefix, '.') + 1, '.') : NULL;
    const char *sub = dot ? dot + 1 : "";
    size_t ls = strlen(sub);
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        for (size_t k = 0; tb->owner == owner && k < tb->n_rows && len < size; k++) {
            char full[200];
            snprintf(full, sizeof full, "%s%s", owner == RF_TRAJ_OWNER_SPEC ? tb->prefix : "", tb->rows[k].key);
            const char *key = owner == RF_TRAJ_OWNER_SPEC ? full + lp + 1 : full + (ls ? ls + 1 : 0);
            int mine = owner == RF_TRAJ_OWNER_SPEC ? !strncmp(full, prefix, lp) && full[lp] == '.'
                                                   : !ls || (!strncmp(full, sub, ls) && full[ls] == '.');
            if (mine && !strchr(key, '.'))
                len += (size_t)snprintf(buf + len, size - len, "%s%s", len ? " " : "", key);
        }
    }
    for (size_t k = 0; owner == RF_TRAJ_OWNER_SPEC && k < rf_traj_n_settings && len < size; k++) {
        const char *full = rf_traj_settings[k].key; /* the settings: "bounce.law" */
        if (!strncmp(full, prefix, lp) && full[lp] == '.' && !strchr(full + lp + 1, '.'))
            len += (size_t)snprintf(buf + len, size - len, "%s%s", len ? " " : "", full + lp + 1);
    }
    if (len < size && extra[0])
        snprintf(buf + len, size - len, "%s%s", len ? " " : "", extra);
}

/* The rule's message at node n ("file:line: path = value: rule"). */
static rf_status setting_fail(ty_ctx *c, struct fy_node *n, const rf_traj_setting *g)
{
    char rule[300];
    rf_traj_setting_rule(g, rule, sizeof rule);
    return yr_fail(&c->sp, n, g->key, "%s", rule);
}

static rf_status read_count(ty_ctx *c, struct fy_node *v, const rf_traj_setting *g, char *dst)
{
    long long n;
    rf_status st = yr_integer(&c->sp, v, g->key, g->count_min, g->count_max, &n);
    if (st != RF_OK)
        return st;
    if (g->size == sizeof(uint64_t)) {
        uint64_t u = (uint64_t)n;
        memcpy(dst, &u, sizeof u);
    } else {
        size_t z = (size_t)n;
        memcpy(dst, &z, sizeof z);
    }
    return RF_OK;
}

static rf_status read_name(ty_ctx *c, struct fy_node *v, const rf_traj_setting *g, char *dst)
{
    const char *str, *name;
    size_t len;
    rf_status st = yr_string(&c->sp, v, g->key, &str, &len);
    for (size_t k = 0; st == RF_OK && (name = g->names(k)); k++) {
        if (len != strlen(name) || strncmp(str, name, len))
            continue;
        if (g->kind == RF_TRAJ_SETTING_NAME) {
            int i = (int)k;
            memcpy(dst, &i, sizeof i);
        } else {
            snprintf(dst, g->size, "%s", name);
        }
        return RF_OK;
    }
    return st != RF_OK ? st : setting_fail(c, v, g);
}

static int number_ok(const rf_traj_setting *g, double x)
{
    int above = g->lo_open ? x > g->lo : x >= g->lo;
    int below = isinf(g->hi) ? isfinite(x) : g->hi_open ? x < g->hi : x <= g->hi;
    return above && below;
}

static rf_status read_number(ty_ctx *c, struct fy_node *v, const rf_traj_setting *g, char *dst)
{
    double x[2] = {0, 0};
    int pair = g->kind == RF_TRAJ_SETTING_PAIR;
    rf_status st = pair ? yr_numbers(&c->sp, v, g->key, 2, 2, x, NULL) : yr_number(&c->sp, v, g->key, x);
    if (st != RF_OK)
        return st;
    if (pair ? !(x[0] > g->lo && x[1] > x[0] && isfinite(x[1])) : !number_ok(g, x[0]))
        return setting_fail(c, v, g);
    if (g->degrees)
        x[0] = x[0] * (RF_PI / 180); /* stored in radians */
    memcpy(dst, x, pair ? 2 * sizeof(double) : sizeof(double));
    return RF_OK;
}

/* A file named relative to the trajectory file (absolute as it is). */
static rf_status read_path(ty_ctx *c, struct fy_node *v, const rf_traj_setting *g, char **dst)
{
    char *f = NULL;
    rf_status st = yr_string_dup(&c->sp, v, g->key, &f);
    if (st != RF_OK)
        return st;
    size_t n = strlen(c->sp.dir) + strlen(f) + 2;
    free(*dst);
    if ((*dst = malloc(n)) && (f[0] == '/' || !strcmp(c->sp.dir, ".")))
        snprintf(*dst, n, "%s", f); /* absolute, or relative to the working directory */
    else if (*dst)
        snprintf(*dst, n, "%s/%s", c->sp.dir, f); /* relative to the trajectory file */
    free(f);
    return *dst ? RF_OK : rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
}

rf_status ty_setting(ty_ctx *c, struct fy_node *v, const rf_traj_setting *g)
{
    char *dst = (char *)c->spec + g->offset;
    size_t k = (size_t)(g - rf_traj_settings);
    if (k < sizeof c->setting_given)
        c->setting_given[k] = 1;
    ty_remember(c, g->key, v);
    switch (g->kind) {
    case RF_TRAJ_SETTING_COUNT: return read_count(c, v, g, dst);
    case RF_TRAJ_SETTING_NAME:
    case RF_TRAJ_SETTING_WORD: return read_name(c, v, g, dst);
    case RF_TRAJ_SETTING_NUMBER:
    case RF_TRAJ_SETTING_PAIR: return read_number(c, v, g, dst);
    case RF_TRAJ_SETTING_PATH: return read_path(c, v, g, (char **)dst);
    }
    return yr_fail(&c->sp, v, g->key, "unknown setting");
}

/* Whether some setting's path continues `path` ("bounce.impact" for bounce.impact.solver). */
static int settings_under(const char *path)
{
    size_t len = strlen(path);
    for (size_t k = 0; k < rf_traj_n_settings; k++)
        if (!strncmp(rf_traj_settings[k].key, path, len) && rf_traj_settings[k].key[len] == '.')
            return 1;
    return 0;
}

rf_status ty_fields(ty_ctx *c, struct fy_node *n, const char *prefix, const char *extra)
{
    rf_status st = yr_mapping(&c->sp, n, prefix);
    if (st != RF_OK)
        return st;
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    char p[300], keys[600];
    for (;;) {
        if ((st = yr_next(&c->sp, &it, prefix, &key, &k, &v)) != RF_OK || !key)
            return st;
        yr_pathf(p, sizeof p, "%s.%s", prefix, key);
        const rf_traj_field *f = rf_traj_field_at(c->spec, p, NULL);
        if (f && !traj_field_used(c->spec, f))
            return yr_fail(&c->sp, k, p, "not used here: %s", traj_field_unused_reason(f));
        const rf_traj_setting *g = f || strchr(key, '.') ? NULL : rf_traj_setting_named(p);
        if (f)
            st = ty_row_value(c, v, p);
        else if (g)
            st = ty_setting(c, v, g);
        else if (settings_under(p))
            st = ty_fields(c, v, p, ""); /* a mapping of settings: bounce.impact */
        else if (in_list(key, extra))
            st = RF_OK; /* read by the caller */
        else {
            keys_under(prefix, extra, keys, sizeof keys);
            return yr_fail(&c->sp, k, p, "unknown key; %s takes: %s", prefix, keys);
        }
        if (st != RF_OK)
            return st;
    }
}

/* "file:line: message" with the line of the longest recorded path opening the message. */
static rf_status locate(ty_ctx *c, rf_status st)
{
    rf_error *e = c->sp.err;
    if (!e)
        return st;
    int line = 0;
    size_t best = 0;
    for (size_t i = 0; i < c->n_lines; i++) {
        size_t len = strlen(c->lines[i].path);
        char after = e->msg[len];
        if (len > best && !strncmp(e->msg, c->lines[i].path, len) &&
            (after == ' ' || after == ':' || after == '[' || after == '.' || after == '\0'))
            best = len, line = c->lines[i].line;
    }
    rf_error_prefix(e, "%s:%d", c->sp.file, line ? line : 1);
    e->code = st;
    return st;
}

rf_status ty_validate(ty_ctx *c)
{
    rf_status st = rf_traj_spec_validate(c->spec, c->sp.err);
    return st != RF_OK ? locate(c, st) : RF_OK;
}
