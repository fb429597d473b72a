/* study_model.c - the `model:` block of a study file: a formula, an external
 * program, or the built-in impact model.  The model is constructed here, so
 * a formula naming an unknown parameter or an impact input bound to an
 * unknown name fails at load time with the constructor's message, located. */
#include "study/study_internal.h"
#include "study/bind.h"

#include "rockfuzz/impact_model.h"
#include "core/util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_OUTPUTS 256

static rf_status set_description(rf_study *s, rf_error *err, const char *fmt, const char *a)
{
    size_t n = strlen(fmt) + strlen(a) + 1;
    s->model_description = malloc(n);
    if (!s->model_description)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    snprintf(s->model_description, n, fmt, a);
    return RF_OK;
}

/* ---- formula ---- */

static rf_status parse_formula(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    const char *path = "model.formula";
    rf_status st;
    size_t no = 0;
    char **names = NULL, **exprs = NULL;
    struct fy_node **nodes = NULL;
    if (n && fy_node_get_type(n) == FYNT_SCALAR) { /* formula: "x1*x2" -> one output named y */
        no = 1;
        names = calloc(1, sizeof *names);
        exprs = calloc(1, sizeof *exprs);
        nodes = calloc(1, sizeof *nodes);
        if (!names || !exprs || !nodes) {
            st = rf_fail(c->err, RF_ENOMEM, "out of memory");
            goto done;
        }
        names[0] = yr_strdup("y");
        nodes[0] = n;
        if ((st = yr_string_dup(c, n, path, &exprs[0])) != RF_OK)
            goto done;
    } else {
        if ((st = yr_mapping(c, n, path)) != RF_OK)
            return st;
        int cnt = fy_node_mapping_item_count(n);
        if (cnt < 1 || cnt > MAX_OUTPUTS)
            return yr_fail(c, n, path, "expected 1 to %d outputs (name: \"expression\")", MAX_OUTPUTS);
        names = calloc((size_t)cnt, sizeof *names);
        exprs = calloc((size_t)cnt, sizeof *exprs);
        nodes = calloc((size_t)cnt, sizeof *nodes);
        if (!names || !exprs || !nodes) {
            st = rf_fail(c->err, RF_ENOMEM, "out of memory");
            goto done;
        }
        yr_iter it = {n, NULL, 0, {0}};
        const char *key;
        struct fy_node *k, *v;
        for (;;) {
            if ((st = yr_next(c, &it, path, &key, &k, &v)) != RF_OK)
                goto done;
            if (!key)
                break;
            char p[300];
            yr_pathf(p, sizeof p, "%s.%s", path, key);
            names[no] = yr_strdup(key);
            nodes[no] = v;
            no++;
            if (!names[no - 1]) {
                st = rf_fail(c->err, RF_ENOMEM, "out of memory");
                goto done;
            }
            if ((st = yr_string_dup(c, v, p, &exprs[no - 1])) != RF_OK)
                goto done;
            if (exprs[no - 1][0] == '\0') {
                st = yr_fail(c, v, p, "the expression is empty");
                goto done;
            }
        }
    }
    st = rf_formula_model_create(s->n_params, (const char *const *)s->param_names, no,
                                 (const char *const *)names, (const char *const *)exprs, &s->model, c->err);
    if (st != RF_OK) {
        rf_model_free(&s->model);
        /* Locate the failing expression by building the outputs one at a time. */
        rf_error first = *c->err, one;
        size_t bad = no;
        for (size_t k = 0; k < no && bad == no; k++) {
            rf_model m;
            memset(&m, 0, sizeof m);
            if (rf_formula_model_create(s->n_params, (const char *const *)s->param_names, 1,
                                        (const char *const *)&names[k], (const char *const *)&exprs[k], &m,
                                        &one) != RF_OK) {
                bad = k;
                *c->err = one;
            }
            rf_model_free(&m);
        }
        char p[300];
        yr_pathf(p, sizeof p, "%s.%s", path, bad < no ? names[bad] : "");
        if (bad == no) {
            *c->err = first;
            st = yr_prefix(c, n, path);
        } else {
            st = yr_prefix(c, nodes[bad], p);
        }
        goto done;
    }
    s->model_kind = RF_STUDY_MODEL_FORMULA;
    {
        char desc[512] = "";
        size_t len = 0;
        for (size_t k = 0; k < no && len < sizeof desc; k++)
            len += (size_t)snprintf(desc + len, sizeof desc - len, "%s%s = %s", k ? "; " : "", names[k], exprs[k]);
        st = set_description(s, c->err, "formula: %s", desc);
    }
done:
    for (size_t k = 0; k < no; k++) {
        free(names[k]);
        free(exprs[k]);
    }
    free(names);
    free(exprs);
    free(nodes);
    return st;
}

/* ---- external program ---- */

static void free_external_spec(rf_external_spec *e)
{
    for (size_t k = 0; k < e->argc; k++)
        free(e->argv[k]);
    free(e->argv);
    for (size_t k = 0; k < e->n_templates; k++) {
        free(e->template_src[k]);
        free(e->template_dst[k]);
    }
    free(e->template_src);
    free(e->template_dst);
    for (size_t k = 0; k < e->n_outputs; k++) {
        free(e->outputs[k].name);
        free(e->outputs[k].file);
        free(e->outputs[k].pattern);
        free(e->outputs[k].unit);
    }
    free(e->outputs);
    free(e->workdir_root);
}

static char *resolve(const char *dir, const char *p)
{
    if (p[0] == '/' || !strcmp(dir, "."))
        return yr_strdup(p);
    size_t n = strlen(dir) + strlen(p) + 2;
    char *r = malloc(n);
    if (r)
        snprintf(r, n, "%s/%s", dir, p);
    return r;
}

/* glibc's regcomp expands repetitions by copying the tree, so stacked
 * duplication symbols ("(.*+++...)", undefined in POSIX ERE anyway) or large
 * nested intervals make it allocate without bound (found by fuzz_study:
 * over 1 GB for one pattern).  Reject them here; NULL = acceptable. */
static const char *pattern_problem(const char *re)
{
    int prev_dup = 0;
    double product = 1;
    for (const char *p = re; *p; p++) {
        int dup = 0;
        if (*p == '\\') {
            if (p[1])
                p++;
        } else if (*p == '[') { /* bracket expression: skip to its closing ']' */
            const char *q = p + 1;
            if (*q == '^')
                q++;
            if (*q == ']')
                q++;
            while (*q && *q != ']') {
                if (*q == '[' && (q[1] == ':' || q[1] == '.' || q[1] == '=')) {
                    char close = q[1];
                    q += 2;
                    while (*q && !(*q == close && q[1] == ']'))
                        q++;
                    if (*q)
                        q++;
                }
                if (*q)
                    q++;
            }
            if (!*q)
                return "an unterminated bracket expression '['";
            p = q;
        } else if (*p == '*' || *p == '+' || *p == '?') {
            dup = 1;
            if (*p == '+') /* x+ is compiled as x x*: a copy, and nested copies multiply */
                product *= 2;
            if (product > 10000)
                return "too many repetitions ('+' counts twice, {n,m} m times; at most 10000 in product)";
        } else if (*p == '{') {
            char *end = NULL;
            long lo = strtol(p + 1, &end, 10), hi = lo;
            if (end && *end == ',')
                hi = end[1] == '}' ? lo : strtol(end + 1, &end, 10);
            if (end && *end == '}') {
                dup = 1;
                if (lo > 100 || hi > 100)
                    return "a repetition count above 100";
                product *= (double)(hi > 1 ? hi : 1);
                if (product > 10000)
                    return "too many repetitions ('+' counts twice, {n,m} m times; at most 10000 in product)";
                p = end;
            }
        }
        if (dup && prev_dup)
            return "two adjacent repetition operators (undefined in POSIX regular expressions)";
        prev_dup = dup;
    }
    return NULL;
}

static rf_status parse_program_outputs(yr_ctx *c, struct fy_node *n, rf_external_spec *e)
{
    const char *path = "model.program.outputs";
    rf_status st = yr_mapping(c, n, path);
    if (st != RF_OK)
        return st;
    int cnt = fy_node_mapping_item_count(n);
    if (cnt < 1 || cnt > MAX_OUTPUTS)
        return yr_fail(c, n, path, "expected 1 to %d outputs", MAX_OUTPUTS);
    e->outputs = calloc((size_t)cnt, sizeof *e->outputs);
    if (!e->outputs)
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    for (;;) {
        if ((st = yr_next(c, &it, path, &key, &k, &v)) != RF_OK)
            return st;
        if (!key)
            return RF_OK;
        rf_external_output *o = &e->outputs[e->n_outputs++];
        o->name = yr_strdup(key);
        if (!o->name)
            return rf_fail(c->err, RF_ENOMEM, "out of memory");
        char p[300], q[400];
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (v && fy_node_get_type(v) == FYNT_SCALAR) {
            size_t len;
            const char *str;
            if ((st = yr_string(c, v, p, &str, &len)) != RF_OK)
                return st;
            if (len == 0 || (len == 4 && !strncmp(str, "null", 4)) || (len == 1 && str[0] == '~'))
                continue; /* name: {} / name: ~ -> "NAME = value" on stdout */
            return yr_fail(c, v, p, "expected a mapping with file, pattern and unit (all optional)");
        }
        if ((st = yr_mapping(c, v, p)) != RF_OK)
            return st;
        yr_iter jt = {v, NULL, 0, {0}};
        const char *ok;
        struct fy_node *okn, *ov;
        for (;;) {
            if ((st = yr_next(c, &jt, p, &ok, &okn, &ov)) != RF_OK)
                return st;
            if (!ok)
                break;
            yr_pathf(q, sizeof q, "%s.%s", p, ok);
            char **dst = !strcmp(ok, "file") ? &o->file : !strcmp(ok, "pattern") ? &o->pattern
                       : !strcmp(ok, "unit")  ? &o->unit
                                              : NULL;
            if (!dst)
                return yr_fail(c, okn, q, "unknown key; an output takes file, pattern and unit");
            free(*dst);
            *dst = NULL;
            if ((st = yr_string_dup(c, ov, q, dst)) != RF_OK)
                return st;
            if (dst == &o->file && ((*dst)[0] == '\0' || (*dst)[0] == '/' || strstr(*dst, "..")))
                return yr_fail(c, ov, q, "the file must be a relative path inside the working directory");
            const char *why = dst == &o->pattern ? pattern_problem(*dst) : NULL;
            if (why)
                return yr_fail(c, ov, q, "the pattern has %s; simplify it", why);
        }
    }
}

/* sb_check_fn: a {placeholder} name (the external model refuses one its files do not know). */
static const char *check_placeholder(void *user, const char *to, char *buf, size_t size)
{
    (void)user;
    int ok = (to[0] == '_' || (to[0] >= 'A' && to[0] <= 'Z') || (to[0] >= 'a' && to[0] <= 'z')) && strlen(to) <= 64;
    for (const char *p = to; ok && *p; p++)
        ok = *p == '_' || *p == '.' || *p == '-' || (*p >= '0' && *p <= '9') || (*p >= 'A' && *p <= 'Z') ||
             (*p >= 'a' && *p <= 'z');
    if (ok)
        return NULL;
    snprintf(buf, size, "not a placeholder name (letters, digits, _, . and -, starting with a letter or _, at most 64)");
    return buf;
}

/* The program model of the bound placeholders, driven by the study's parameters. */
static rf_status make_program(const rf_external_spec *e, const sb_binding *b, rf_study *s, rf_error *err)
{
    const char **names = sb_names(b);
    if (!names)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_status st = rf_external_model_create(e, b->n, names, &s->model, err);
    free(names);
    return st == RF_OK ? sb_wrap(b, s->n_params, &s->model, err) : st;
}

static rf_status parse_program(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    const char *path = "model.program";
    rf_status st = yr_mapping(c, n, path);
    if (st != RF_OK)
        return st;
    rf_external_spec e;
    memset(&e, 0, sizeof e);
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v, *outputs = NULL, *argv_node = NULL, *templates = NULL, *bind = NULL;
    char p[300], q[400];
    sb_binding b = {0, NULL};
    for (;;) {
        if ((st = yr_next(c, &it, path, &key, &k, &v)) != RF_OK)
            goto done;
        if (!key)
            break;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (!strcmp(key, "argv")) {
            size_t cnt;
            if ((st = yr_sequence(c, v, p, 1, 1000, &cnt)) != RF_OK)
                goto done;
            argv_node = v;
            e.argv = calloc(cnt, sizeof(char *));
            if (!e.argv) {
                st = rf_fail(c->err, RF_ENOMEM, "out of memory");
                goto done;
            }
            for (size_t a = 0; a < cnt; a++) {
                yr_pathf(q, sizeof q, "%s[%zu]", p, a);
                if ((st = yr_string_dup(c, fy_node_sequence_get_by_index(v, (int)a), q, &e.argv[a])) != RF_OK)
                    goto done;
                e.argc = a + 1;
            }
            if (e.argv[0][0] == '\0') {
                st = yr_fail(c, fy_node_sequence_get_by_index(v, 0), p, "the program name is empty");
                goto done;
            }
        } else if (!strcmp(key, "templates")) {
            if ((st = yr_mapping(c, v, p)) != RF_OK)
                goto done;
            templates = v;
            int cnt = fy_node_mapping_item_count(v);
            e.template_src = calloc(cnt > 0 ? (size_t)cnt : 1, sizeof(char *));
            e.template_dst = calloc(cnt > 0 ? (size_t)cnt : 1, sizeof(char *));
            if (!e.template_src || !e.template_dst) {
                st = rf_fail(c->err, RF_ENOMEM, "out of memory");
                goto done;
            }
            yr_iter jt = {v, NULL, 0, {0}};
            const char *dst;
            struct fy_node *dn, *sn;
            for (;;) {
                if ((st = yr_next(c, &jt, p, &dst, &dn, &sn)) != RF_OK)
                    goto done;
                if (!dst)
                    break;
                yr_pathf(q, sizeof q, "%s.%s", p, dst);
                if (strchr(dst, '/') || !strcmp(dst, ".") || !strcmp(dst, "..")) {
                    st = yr_fail(c, dn, q, "the destination must be a plain file name in the working directory");
                    goto done;
                }
                char *src = NULL;
                if ((st = yr_string_dup(c, sn, q, &src)) != RF_OK)
                    goto done;
                size_t t = e.n_templates++;
                e.template_dst[t] = yr_strdup(dst);
                e.template_src[t] = src[0] ? resolve(c->dir, src) : NULL;
                free(src);
                if (!e.template_dst[t] || !e.template_src[t]) {
                    st = e.template_dst[t] && !e.template_src[t] && sn
                             ? yr_fail(c, sn, q, "the template path is empty")
                             : rf_fail(c->err, RF_ENOMEM, "out of memory");
                    goto done;
                }
                if (access(e.template_src[t], R_OK) != 0) {
                    st = yr_fail(c, sn, q, "cannot read the template '%s' (paths are relative to the study file)",
                                 e.template_src[t]);
                    goto done;
                }
            }
        } else if (!strcmp(key, "outputs")) {
            outputs = v;
            if ((st = parse_program_outputs(c, v, &e)) != RF_OK)
                goto done;
        } else if (!strcmp(key, "timeout")) {
            if ((st = yr_number(c, v, p, &e.timeout)) != RF_OK)
                goto done;
            if (e.timeout < 0) {
                st = yr_fail(c, v, p, "the timeout must be >= 0 seconds (0 = none)");
                goto done;
            }
        } else if (!strcmp(key, "keep_workdirs")) {
            if ((st = yr_bool(c, v, p, &e.keep_workdirs)) != RF_OK)
                goto done;
        } else if (!strcmp(key, "workdir")) {
            char *w = NULL;
            if ((st = yr_string_dup(c, v, p, &w)) != RF_OK)
                goto done;
            free(e.workdir_root);
            e.workdir_root = w[0] ? resolve(c->dir, w) : NULL;
            free(w);
        } else if (!strcmp(key, "bind")) {
            bind = v;
        } else {
            st = yr_fail(c, k, p, "unknown key; a program takes argv, templates, outputs, timeout, keep_workdirs, "
                                  "workdir, bind");
            goto done;
        }
    }
    if (!argv_node) {
        st = yr_fail(c, n, path, "missing argv (the program and its arguments)");
        goto done;
    }
    if (!outputs) {
        st = yr_fail(c, n, path, "missing outputs (name: {file:, pattern:, unit:})");
        goto done;
    }
    if ((st = sb_parse(c, bind, "model.program.bind", s, 1, check_placeholder, NULL, &b)) != RF_OK)
        goto done;
    /* workdir_root NULL: the external model's default, $TMPDIR/rockfuzz-eval. */
    st = make_program(&e, &b, s, c->err);
    if (st != RF_OK) {
        rf_model_free(&s->model);
        /* Point at the part of the block the constructor's message is about. */
        const char *msg = c->err->msg;
        struct fy_node *at = n;
        const char *where = path;
        if (strstr(msg, "template") && templates)
            at = templates, where = "model.program.templates";
        else if ((strstr(msg, "argv") || strstr(msg, "program '")) && argv_node)
            at = argv_node, where = "model.program.argv";
        else if (strstr(msg, "output") && outputs)
            at = outputs, where = "model.program.outputs";
        st = yr_prefix(c, at, where);
        goto done;
    }
    s->model_kind = RF_STUDY_MODEL_PROGRAM;
    st = set_description(s, c->err, "program: %s", e.argv[0]);
done:
    sb_free(&b);
    free_external_spec(&e);
    return st;
}

/* ---- impact ---- */

/* gravity: auto, or its magnitude [m/s^2] >= 0 (a negative value, say -9.81 for
   "downward", is refused rather than read as anything). */
static rf_status parse_gravity(yr_ctx *c, struct fy_node *v, const char *path, double *g)
{
    char buf[63];
    rf_status st = yr_word(c, v, path, buf, sizeof buf);
    if (st != RF_OK)
        return st;
    rf_error tmp;
    if (rf_impact_gravity_parse(buf, g, &tmp) != RF_OK)
        return yr_fail(c, v, path, "expected auto or a magnitude >= 0 [m/s^2] (gravity acts along -z)");
    return RF_OK;
}

/* A crisp input of the impact block, as the table says (degrees for angles). */
static rf_status parse_impact_input(yr_ctx *c, const rf_study *s, const sb_binding *b, const rf_impact_field *f,
                                    struct fy_node *v, const char *p, rf_impact_input *in)
{
    for (size_t j = 0; j < b->n; j++)
        if (!strcmp(b->t[j].to, f->name))
            return yr_fail(c, v, p, "'%s' is already driven by the fuzzy parameter %s (line %d); give it in one place",
                           f->name, s->param_names[b->t[j].param], b->t[j].line);
    double x;
    rf_status st = f->kind == RF_FIELD_GRAVITY ? parse_gravity(c, v, p, &x) : yr_number(c, v, p, &x);
    if (st == RF_OK)
        rf_impact_field_store(in, f, x);
    return st;
}

/* An unknown key: the nearest input name when it is close (a typo), and where the list is. */
static rf_status unknown_impact_key(yr_ctx *c, struct fy_node *k, const char *p, const char *key)
{
    const char *near = NULL;
    size_t best = 3; /* at most two edits */
    for (size_t q = 0; q < rf_impact_n_fields; q++) {
        size_t d = rf_name_distance(key, rf_impact_fields[q].name);
        if (d < best)
            best = d, near = rf_impact_fields[q].name;
    }
    char hint[128] = "";
    if (near)
        snprintf(hint, sizeof hint, "did you mean '%s'? ", near);
    char fem[256];
    size_t len = 0;
    fem[0] = '\0';
    for (size_t q = 0; q < rf_fem_n_option_fields && len < sizeof fem; q++)
        len += (size_t)snprintf(fem + len, sizeof fem - len, "%s, ", rf_fem_option_fields[q].name);
    return yr_fail(c, k, p, "unknown key; %sthe impact model takes solver, %se_n, bind, hunter_coefficient, "
                   "boulder_material, slope_material, layer_material and the crisp inputs that `rockfuzz impact "
                   "--help` and docs/impact.md list (radius [m], slope_angle [deg], ...)", hint, fem);
}

/* An FE option (a row of rf_fem_option_fields): a number, or one of its choices. */
static rf_status parse_fem_option(yr_ctx *c, const rf_fem_option_field *f, struct fy_node *v, const char *p,
                                  rf_fem_options *o)
{
    rf_error tmp; /* the FE solvers' own rule (fem_options.c) */
    rf_status st;
    if (f->kind == RF_FEM_OPTION_CHOICE) {
        char buf[32], list[128];
        if ((st = yr_word(c, v, p, buf, sizeof buf)) != RF_OK)
            return st;
        rf_fem_option_choices(f, list, sizeof list);
        if (rf_fem_option_parse(o, f, buf, &tmp) != RF_OK)
            return yr_fail(c, v, p, "unknown %s; expected %s", f->name, list);
        return RF_OK;
    }
    double x;
    if ((st = yr_number(c, v, p, &x)) != RF_OK)
        return st;
    if (rf_fem_option_set(o, f, x, &tmp) != RF_OK)
        return yr_fail(c, v, p, "%s", tmp.msg);
    return RF_OK;
}

/* A model setting of the impact block (solver, materials, FE options, e_n,
 * hunter_coefficient) into spec; *known = 0 for a key that is none of them. */
static rf_status parse_impact_setting(yr_ctx *c, const char *key, struct fy_node *v, const char *p,
                                      rf_impact_model_spec *spec, int *known)
{
    rf_status st = RF_OK;
    char buf[32];
    *known = 1;
    if (!strcmp(key, "boulder_material") || !strcmp(key, "slope_material") || !strcmp(key, "layer_material")) {
        if ((st = yr_word(c, v, p, buf, sizeof buf)) != RF_OK)
            return st;
        rf_error tmp;
        if ((key[0] == 'b' ? rf_impact_boulder_material_parse(buf, &spec->base.boulder_material, &tmp)
                                         : rf_material_model_parse(buf, key[0] == 's' ? &spec->base.slope_material
                                                                                      : &spec->base.layer_material,
                                                                   &tmp)) != RF_OK)
            return yr_fail(c, v, p, key[0] == 'b' ? "unknown boulder material; expected elastic, von_mises or rigid"
                                                  : "unknown material; expected elastic, von_mises or "
                                                    "drucker_prager");
    } else if (!strcmp(key, "solver")) {
        if ((st = yr_word(c, v, p, buf, sizeof buf)) != RF_OK)
            return st;
        rf_error tmp;
        if (rf_impact_solver_parse(buf, &spec->solver, &tmp) != RF_OK)
            return yr_fail(c, v, p, "unknown solver; expected fem, hertz, hunter, rigid or mdr");
    } else if (rf_fem_option_find(key)) {
        return parse_fem_option(c, rf_fem_option_find(key), v, p, &spec->fem);
    } else if (!strcmp(key, "e_n")) {
        if ((st = yr_number(c, v, p, &spec->e_n)) != RF_OK)
            return st;
        if (spec->e_n < 0 || spec->e_n > 1)
            return yr_fail(c, v, p, "a coefficient of restitution must lie in [0, 1]");
    } else if (!strcmp(key, "hunter_coefficient")) {
        if ((st = yr_number(c, v, p, &spec->hunter_coefficient)) != RF_OK)
            return st;
        if (!(spec->hunter_coefficient >= 0))
            return yr_fail(c, v, p, "must be >= 0");
    } else {
        *known = 0;
    }
    return st;
}

/* sb_check_fn: a bindable impact input. */
static const char *check_impact_name(void *user, const char *to, char *buf, size_t size)
{
    (void)user;
    const rf_impact_field *f = rf_impact_field_find(to);
    if (f && f->bindable)
        return NULL;
    char list[1024];
    rf_impact_bindable_list(list, sizeof list);
    snprintf(buf, size, "'%s' is not an input of the impact model (inputs: %s)", to, list);
    return buf;
}

/* sb_validate_fn: the impact input with the bound fields set, in the model's order. */
static rf_status validate_impact(void *user, const double *xi, rf_error *err)
{
    const sb_binding *b = ((const void *const *)user)[0];
    rf_impact_input in = *(const rf_impact_input *)((const void *const *)user)[1];
    for (size_t j = 0; j < b->n; j++)
        rf_impact_field_set(&in, rf_impact_field_find(b->t[j].to), xi[j]);
    return rf_impact_input_validate(&in, err);
}

/* The crisp inputs and settings of the block (every key but bind). */
static rf_status parse_impact_keys(yr_ctx *c, struct fy_node *n, const rf_study *s, const sb_binding *b,
                                   rf_impact_model_spec *spec)
{
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    char p[300];
    rf_status st;
    while ((st = yr_next(c, &it, "model.impact", &key, &k, &v)) == RF_OK && key) {
        yr_pathf(p, sizeof p, "model.impact.%s", key);
        const rf_impact_field *field = rf_impact_field_find(key);
        int known = 1;
        if (!strcmp(key, "bind"))
            continue;
        if (field)
            st = parse_impact_input(c, s, b, field, v, p, &spec->base);
        else
            st = parse_impact_setting(c, key, v, p, spec, &known);
        if (st == RF_OK && !known)
            st = unknown_impact_key(c, k, p, key);
        if (st != RF_OK)
            return st;
    }
    return st;
}

/* The inputs at the nominal point: a refusal names the parameter, the crisp value or the default. */
static rf_status check_impact_nominal(yr_ctx *c, struct fy_node *n, const rf_study *s, const sb_binding *b,
                                      const rf_impact_input *base)
{
    double x[64], xi[SB_MAX_TARGETS];
    for (size_t i = 0; i < s->n_params; i++)
        x[i] = rf_fuzzy_nominal(&s->inputs[i]);
    sb_expand(b, x, xi);
    rf_impact_input probe = *base;
    for (size_t j = 0; j < b->n; j++)
        rf_impact_field_set(&probe, rf_impact_field_find(b->t[j].to), xi[j]);
    const char *bad = rf_impact_input_first_invalid(&probe);
    if (!bad)
        return RF_OK;
    rf_error tmp;
    rf_impact_input_validate(&probe, &tmp);
    for (size_t j = 0; j < b->n; j++)
        if (!strcmp(bad, b->t[j].to))
            return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: the nominal value %.17g (%s = %.17g) is not "
                           "admissible for the impact model: %s", c->file, b->t[j].line,
                           s->param_names[b->t[j].param], x[b->t[j].param], bad, xi[j], tmp.msg);
    struct fy_node *v = fy_node_mapping_lookup_by_string(n, bad, FY_NT);
    char p[300];
    yr_pathf(p, sizeof p, "model.impact.%s", bad);
    if (v) /* a crisp value in the block */
        return yr_fail(c, v, p, "not admissible: %s", tmp.msg);
    return rf_fail(c->err, RF_EINVAL, "%s:%d: model.impact: the default value of '%s' is not admissible with "
                   "these inputs: %s", c->file, yr_line(n), bad, tmp.msg);
}

static rf_status make_impact(yr_ctx *c, struct fy_node *n, rf_study *s, const sb_binding *b,
                             const rf_impact_model_spec *spec)
{
    const char **names = sb_names(b);
    if (!names)
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    rf_status st = rf_impact_model_create(spec, names, b->n, &s->model, c->err);
    free(names);
    if (st != RF_OK) {
        rf_model_free(&s->model);
        return yr_prefix(c, n, "model.impact");
    }
    return sb_wrap(b, s->n_params, &s->model, c->err);
}

static rf_status parse_impact(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    rf_status st = yr_mapping(c, n, "model.impact");
    if (st != RF_OK)
        return st;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    sb_binding b = {0, NULL};
    struct fy_node *bind = fy_node_mapping_lookup_by_string(n, "bind", FY_NT);
    st = sb_parse(c, bind, "model.impact.bind", s, 1, check_impact_name, NULL, &b);
    if (st == RF_OK)
        st = parse_impact_keys(c, n, s, &b, &spec);
    if (st == RF_OK)
        st = check_impact_nominal(c, n, s, &b, &spec.base);
    const void *user[2] = {&b, &spec.base};
    if (st == RF_OK)
        st = sb_check_box(c, bind ? bind : n, bind ? "model.impact.bind" : "model.impact", s, &b, validate_impact,
                          (void *)user);
    if (st == RF_OK)
        st = make_impact(c, n, s, &b, &spec);
    sb_free(&b);
    if (st != RF_OK)
        return st;
    s->model_kind = RF_STUDY_MODEL_IMPACT;
    return set_description(s, c->err, "impact: %s solver", rf_impact_solver_name(spec.solver));
}

rf_status sp_parse_model(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    rf_status st = yr_mapping(c, n, "model");
    if (st != RF_OK)
        return st;
    if (fy_node_mapping_item_count(n) != 1)
        return yr_fail(c, n, "model", "expected exactly one of formula, program, impact, trajectory");
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    if ((st = yr_next(c, &it, "model", &key, &k, &v)) != RF_OK)
        return st;
    if (!key)
        return yr_fail(c, n, "model", "expected exactly one of formula, program, impact, trajectory");
    if (!strcmp(key, "formula"))
        return parse_formula(c, v, s);
    if (!strcmp(key, "program"))
        return parse_program(c, v, s);
    if (!strcmp(key, "impact"))
        return parse_impact(c, v, s);
    if (!strcmp(key, "trajectory"))
        return rf_traj_study_parse(c, v, s);
    char p[300];
    yr_pathf(p, sizeof p, "model.%s", key);
    return yr_fail(c, k, p, "unknown model; expected formula, program, impact or trajectory");
}
