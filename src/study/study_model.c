/* study_model.c - the `model:` block of a study file: a formula, an external
 * program, or the built-in impact model.  The model is constructed here, so
 * a formula naming an unknown parameter or an impact input bound to an
 * unknown name fails at load time with the constructor's message, located. */
#include "study/study_internal.h"

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
    struct fy_node *k, *v, *outputs = NULL, *argv_node = NULL, *templates = NULL;
    char p[300], q[400];
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
        } else {
            st = yr_fail(c, k, p, "unknown key; a program takes argv, templates, outputs, timeout, keep_workdirs, "
                                  "workdir");
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
    /* workdir_root NULL: the external model's default, $TMPDIR/rockfuzz-eval. */
    st = rf_external_model_create(&e, s->n_params, (const char *const *)s->param_names, &s->model, c->err);
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
static rf_status parse_impact_input(yr_ctx *c, const rf_study *s, const rf_impact_field *f, struct fy_node *v,
                                    const char *p, rf_impact_input *in)
{
    for (size_t i = 0; i < s->n_params; i++)
        if (!strcmp(s->param_names[i], f->name))
            return yr_fail(c, v, p, "'%s' is already a fuzzy parameter (line %d); give it in one place", f->name,
                           s->param_line[i]);
    double x;
    rf_status st = f->kind == RF_FIELD_GRAVITY ? parse_gravity(c, v, p, &x) : yr_number(c, v, p, &x);
    if (st == RF_OK)
        rf_impact_field_store(in, f, x);
    return st;
}

/* Levenshtein distance of two short names (capped at 64 characters). */
static size_t name_distance(const char *a, const char *b)
{
    size_t la = strlen(a) < 64 ? strlen(a) : 64, lb = strlen(b) < 64 ? strlen(b) : 64, row[65];
    for (size_t j = 0; j <= lb; j++)
        row[j] = j;
    for (size_t i = 1; i <= la; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            size_t up = row[j], best = diag + (a[i - 1] != b[j - 1]);
            best = up + 1 < best ? up + 1 : best;
            best = row[j - 1] + 1 < best ? row[j - 1] + 1 : best;
            diag = up, row[j] = best;
        }
    }
    return row[lb];
}

/* An unknown key: the nearest input name when it is close (a typo), and where the list is. */
static rf_status unknown_impact_key(yr_ctx *c, struct fy_node *k, const char *p, const char *key)
{
    const char *near = NULL;
    size_t best = 3; /* at most two edits */
    for (size_t q = 0; q < rf_impact_n_fields; q++) {
        size_t d = name_distance(key, rf_impact_fields[q].name);
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
    return yr_fail(c, k, p, "unknown key; %sthe impact model takes solver, %se_n, hunter_coefficient, "
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

static rf_status parse_impact(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    const char *path = "model.impact";
    rf_status st = yr_mapping(c, n, path);
    if (st != RF_OK)
        return st;
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    char p[300];
    for (;;) {
        if ((st = yr_next(c, &it, path, &key, &k, &v)) != RF_OK)
            return st;
        if (!key)
            break;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        const rf_impact_field *field = rf_impact_field_find(key);
        if (field) {
            if ((st = parse_impact_input(c, s, field, v, p, &spec.base)) != RF_OK)
                return st;
        } else {
            int known;
            if ((st = parse_impact_setting(c, key, v, p, &spec, &known)) != RF_OK)
                return st;
            if (!known)
                return unknown_impact_key(c, k, p, key);
        }
    }
    /* Every parameter must name an impact input. */
    for (size_t i = 0; i < s->n_params; i++) {
        const rf_impact_field *f = rf_impact_field_find(s->param_names[i]);
        if (!f || !f->bindable) {
            char list[1024];
            rf_impact_bindable_list(list, sizeof list);
            return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: '%s' is not an input of the impact model "
                           "(inputs: %s)", c->file, s->param_line[i], s->param_names[i], s->param_names[i], list);
        }
    }
    /* Check the crisp inputs with the fuzzy ones at their nominal values, then each support end. */
    rf_impact_input probe = spec.base;
    for (size_t i = 0; i < s->n_params; i++)
        rf_impact_field_set(&probe, rf_impact_field_find(s->param_names[i]), rf_fuzzy_nominal(&s->inputs[i]));
    const char *bad = rf_impact_input_first_invalid(&probe);
    if (bad) {
        for (size_t i = 0; i < s->n_params; i++)
            if (!strcmp(bad, s->param_names[i]))
                return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: the nominal value %.17g is not admissible "
                               "for the impact model", c->file, s->param_line[i], bad,
                               rf_fuzzy_nominal(&s->inputs[i]));
        /* A crisp value in the block: find its line. */
        yr_iter jt = {n, NULL, 0, {0}};
        for (;;) {
            if (yr_next(c, &jt, path, &key, &k, &v) != RF_OK || !key)
                break;
            if (!strcmp(key, bad)) {
                yr_pathf(p, sizeof p, "%s.%s", path, key);
                rf_error tmp;
                rf_impact_input_validate(&probe, &tmp);
                return yr_fail(c, v, p, "not admissible: %s", tmp.msg);
            }
        }
        rf_error tmp;
        rf_impact_input_validate(&probe, &tmp);
        return rf_fail(c->err, RF_EINVAL, "%s:%d: model.impact: the default value of '%s' is not admissible with "
                       "these inputs: %s", c->file, yr_line(n), bad, tmp.msg);
    }
    for (size_t i = 0; i < s->n_params; i++) {
        double lo, hi;
        rf_fuzzy_cut(&s->inputs[i], 0.0, &lo, &hi);
        double ends[2] = {lo, hi};
        for (int e = 0; e < 2; e++) {
            rf_impact_input q = probe;
            rf_impact_field_set(&q, rf_impact_field_find(s->param_names[i]), ends[e]);
            const char *b = rf_impact_input_first_invalid(&q);
            if (b && !strcmp(b, s->param_names[i])) {
                rf_error tmp;
                rf_impact_input_validate(&q, &tmp);
                return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: the support [%.17g, %.17g] reaches an "
                               "inadmissible value %.17g: %s", c->file, s->param_line[i], s->param_names[i], lo, hi,
                               ends[e], tmp.msg);
            }
        }
    }
    st = rf_impact_model_create(&spec, (const char *const *)s->param_names, s->n_params, &s->model, c->err);
    if (st != RF_OK) {
        rf_model_free(&s->model);
        return yr_prefix(c, n, path);
    }
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
