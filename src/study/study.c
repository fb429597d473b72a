/* study.c - loading a study file: the top-level keys, the fuzzy parameters
 * and the options.  The model block is built in study_model.c.  Everything is
 * validated here, before any evaluation, and every message is located
 * (file:line: field = value: reason). */
#include "study/study_internal.h"
#include "study/bind.h"
#include "core/textfile.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PARAMS 64
#define MAX_POINTS 10000

static const char *const shape_keys[] = {"tfn", "trapezoid", "interval", "gaussian", "crisp", "points", "cuts"};
#define N_SHAPES (sizeof shape_keys / sizeof shape_keys[0])

const char *rf_study_model_kind_name(rf_study_model_kind k)
{
    switch (k) {
    case RF_STUDY_MODEL_FORMULA: return "formula";
    case RF_STUDY_MODEL_PROGRAM: return "program";
    case RF_STUDY_MODEL_IMPACT: return "impact";
    case RF_STUDY_MODEL_TRAJECTORY: return "trajectory";
    }
    return "unknown";
}

void rf_study_free(rf_study *s)
{
    if (!s)
        return;
    for (size_t i = 0; i < s->n_params; i++) {
        if (s->param_names)
            free(s->param_names[i]);
        if (s->param_units)
            free(s->param_units[i]);
        if (s->param_shapes)
            free(s->param_shapes[i]);
        if (s->inputs)
            rf_fuzzy_free(&s->inputs[i]);
    }
    free(s->param_names);
    free(s->param_units);
    free(s->param_shapes);
    free(s->inputs);
    free(s->param_class);
    free(s->param_line);
    rf_model_free(&s->model);
    free(s->model_description);
    for (size_t k = 0; k < s->n_fuzzy_rasters; k++)
        free(s->fuzzy_rasters[k]);
    free(s->fuzzy_rasters);
    free(s->path);
    free(s->dir);
    free(s->name);
    memset(s, 0, sizeof *s);
}

void rf_study_tm_options(const rf_study *s, rf_tm_options *opt)
{
    rf_tm_options_default(opt);
    opt->scheme = s->scheme;
    opt->levels = s->levels;
    opt->max_evaluations = s->max_evaluations;
    opt->left_right = s->left_right;
    opt->force_class = s->param_class;
}

static int is_identifier(const char *s)
{
    if (!(isalpha((unsigned char)s[0]) || s[0] == '_'))
        return 0;
    for (const char *p = s + 1; *p; p++)
        if (!(isalnum((unsigned char)*p) || *p == '_'))
            return 0;
    return strlen(s) <= 64;
}

/* ---- parameters ---- */

/* Element k of a number list, for located element messages. */
static struct fy_node *item(struct fy_node *seq, size_t k) { return fy_node_sequence_get_by_index(seq, (int)k); }

static rf_status shape_tfn(yr_ctx *c, struct fy_node *n, const char *path, rf_fuzzy *f, char *desc, size_t dsz)
{
    double v[3];
    rf_status st = yr_numbers(c, n, path, 3, 3, v, NULL);
    if (st != RF_OK)
        return st;
    char p[256];
    for (size_t k = 1; k < 3; k++) {
        if (v[k] < 0) {
            yr_pathf(p, sizeof p, "%s[%zu]", path, k);
            return yr_fail(c, item(n, k), p, "the %s deviation must be >= 0 (tfn: [peak, left deviation, right deviation])",
                           k == 1 ? "left" : "right");
        }
    }
    snprintf(desc, dsz, "tfn(%.15g, %.15g, %.15g)", v[0], v[1], v[2]);
    if (rf_fuzzy_tfn(f, v[0], v[1], v[2], c->err) != RF_OK)
        return yr_prefix(c, n, path);
    return RF_OK;
}

static rf_status shape_ordered(yr_ctx *c, struct fy_node *n, const char *path, size_t count, double *v)
{
    rf_status st = yr_numbers(c, n, path, count, count, v, NULL);
    if (st != RF_OK)
        return st;
    for (size_t k = 1; k < count; k++) {
        if (v[k] < v[k - 1]) {
            char p[256];
            yr_pathf(p, sizeof p, "%s[%zu]", path, k);
            return yr_fail(c, item(n, k), p, "must be >= the previous value %.17g (the values must not decrease)",
                           v[k - 1]);
        }
    }
    return RF_OK;
}

static rf_status shape_gaussian(yr_ctx *c, struct fy_node *n, const char *path, double cutoff, rf_fuzzy *f,
                                char *desc, size_t dsz)
{
    double v[3];
    size_t cnt;
    rf_status st = yr_numbers(c, n, path, 2, 3, v, &cnt);
    if (st != RF_OK)
        return st;
    if (cnt == 2)
        v[2] = v[1];
    char p[256];
    for (size_t k = 1; k < cnt; k++) {
        if (!(v[k] > 0)) {
            yr_pathf(p, sizeof p, "%s[%zu]", path, k);
            return yr_fail(c, item(n, k), p, "sigma must be > 0 (gaussian: [peak, sigma left, sigma right])");
        }
    }
    snprintf(desc, dsz, "gaussian(%.15g, %.15g, %.15g, cutoff %.15g)", v[0], v[1], v[2], cutoff);
    if (rf_fuzzy_gaussian(f, v[0], v[1], v[2], cutoff, c->err) != RF_OK)
        return yr_prefix(c, n, path);
    return RF_OK;
}

static rf_status shape_points(yr_ctx *c, struct fy_node *n, const char *path, rf_fuzzy *f, char *desc, size_t dsz)
{
    size_t cnt;
    rf_status st = yr_sequence(c, n, path, 2, MAX_POINTS, &cnt);
    if (st != RF_OK)
        return st;
    double *x = malloc(cnt * sizeof *x), *mu = malloc(cnt * sizeof *mu);
    if (!x || !mu) {
        free(x);
        free(mu);
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    }
    char p[256];
    for (size_t k = 0; k < cnt && st == RF_OK; k++) {
        double pair[2];
        yr_pathf(p, sizeof p, "%s[%zu]", path, k);
        st = yr_numbers(c, item(n, k), p, 2, 2, pair, NULL);
        if (st != RF_OK)
            break;
        x[k] = pair[0];
        mu[k] = pair[1];
        if (mu[k] < 0 || mu[k] > 1) {
            yr_pathf(p, sizeof p, "%s[%zu][1]", path, k);
            st = yr_fail(c, item(item(n, k), 1), p, "a membership must lie in [0, 1]");
        } else if (k > 0 && x[k] < x[k - 1]) {
            yr_pathf(p, sizeof p, "%s[%zu][0]", path, k);
            st = yr_fail(c, item(item(n, k), 0), p, "the abscissae must not decrease (previous x = %.17g)", x[k - 1]);
        }
    }
    if (st == RF_OK) {
        snprintf(desc, dsz, "points(%zu points, support [%.15g, %.15g])", cnt, x[0], x[cnt - 1]);
        if (rf_fuzzy_points(f, cnt, x, mu, c->err) != RF_OK)
            st = yr_prefix(c, n, path);
    }
    free(x);
    free(mu);
    return st;
}

static rf_status shape_cuts(yr_ctx *c, struct fy_node *n, const char *path, rf_fuzzy *f, char *desc, size_t dsz)
{
    rf_status st = yr_mapping(c, n, path);
    if (st != RF_OK)
        return st;
    struct fy_node *node[3] = {NULL, NULL, NULL};
    static const char *const names[3] = {"mu", "lower", "upper"};
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *kn, *v;
    char p[256];
    for (;;) {
        if ((st = yr_next(c, &it, path, &key, &kn, &v)) != RF_OK)
            return st;
        if (!key)
            break;
        int found = -1;
        for (int k = 0; k < 3; k++)
            if (!strcmp(key, names[k]))
                found = k;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (found < 0)
            return yr_fail(c, kn, p, "unknown key; cuts take mu, lower and upper (lists of equal length)");
        node[found] = v;
    }
    for (int k = 0; k < 3; k++)
        if (!node[k])
            return yr_fail(c, n, path, "missing '%s' (cuts take mu, lower and upper lists)", names[k]);
    size_t cnt[3];
    double *arr[3] = {NULL, NULL, NULL};
    for (int k = 0; k < 3 && st == RF_OK; k++) {
        yr_pathf(p, sizeof p, "%s.%s", path, names[k]);
        st = yr_sequence(c, node[k], p, 2, MAX_POINTS, &cnt[k]);
        if (st != RF_OK)
            break;
        arr[k] = malloc(cnt[k] * sizeof(double));
        if (!arr[k]) {
            st = rf_fail(c->err, RF_ENOMEM, "out of memory");
            break;
        }
        st = yr_numbers(c, node[k], p, cnt[k], cnt[k], arr[k], NULL);
        if (st == RF_OK && k > 0 && cnt[k] != cnt[0])
            st = yr_fail(c, node[k], p, "has %zu values but mu has %zu", cnt[k], cnt[0]);
    }
    double *mu = arr[0], *lo = arr[1], *hi = arr[2];
    for (size_t j = 0; st == RF_OK && j < cnt[0]; j++) {
        if (mu[j] < 0 || mu[j] > 1 || (j > 0 && mu[j] <= mu[j - 1])) {
            yr_pathf(p, sizeof p, "%s.mu[%zu]", path, j);
            st = yr_fail(c, item(node[0], j), p, "levels must increase strictly from 0 to 1");
        } else if (lo[j] > hi[j]) {
            yr_pathf(p, sizeof p, "%s.lower[%zu]", path, j);
            st = yr_fail(c, item(node[1], j), p, "the lower bound exceeds the upper bound %.17g at mu = %.17g", hi[j],
                         mu[j]);
        } else if (j > 0 && lo[j] < lo[j - 1]) {
            yr_pathf(p, sizeof p, "%s.lower[%zu]", path, j);
            st = yr_fail(c, item(node[1], j), p,
                         "the cuts do not nest: the lower bound at mu = %.17g is below %.17g at mu = %.17g", mu[j],
                         lo[j - 1], mu[j - 1]);
        } else if (j > 0 && hi[j] > hi[j - 1]) {
            yr_pathf(p, sizeof p, "%s.upper[%zu]", path, j);
            st = yr_fail(c, item(node[2], j), p,
                         "the cuts do not nest: the upper bound at mu = %.17g is above %.17g at mu = %.17g", mu[j],
                         hi[j - 1], mu[j - 1]);
        }
    }
    if (st == RF_OK) {
        snprintf(desc, dsz, "cuts(%zu levels, support [%.15g, %.15g])", cnt[0], lo[0], hi[0]);
        if (rf_fuzzy_cuts(f, cnt[0], mu, lo, hi, c->err) != RF_OK)
            st = yr_prefix(c, n, path);
    }
    for (int k = 0; k < 3; k++)
        free(arr[k]);
    return st;
}

static rf_status parse_param(yr_ctx *c, rf_study *s, size_t i, const char *name, struct fy_node *kn,
                             struct fy_node *v)
{
    char path[300], p[400], desc[256] = "";
    yr_pathf(path, sizeof path, "parameters.%s", name);
    s->param_line[i] = yr_line(kn);
    s->param_class[i] = RF_MONO_AUTO;
    rf_fuzzy *f = &s->inputs[i];
    rf_status st;

    if (v && fy_node_get_type(v) == FYNT_SCALAR) { /* x: 1.5 is short for {crisp: 1.5} */
        double d;
        if ((st = yr_number(c, v, path, &d)) != RF_OK)
            return st;
        snprintf(desc, sizeof desc, "crisp(%.15g)", d);
        if (rf_fuzzy_crisp(f, d, c->err) != RF_OK)
            return yr_prefix(c, v, path);
    } else {
        if ((st = yr_mapping(c, v, path)) != RF_OK)
            return st;
        struct fy_node *shape = NULL, *cutoff_node = NULL;
        const char *shape_name = NULL;
        yr_iter it = {v, NULL, 0, {0}};
        const char *key;
        struct fy_node *k, *val;
        for (;;) {
            if ((st = yr_next(c, &it, path, &key, &k, &val)) != RF_OK)
                return st;
            if (!key)
                break;
            yr_pathf(p, sizeof p, "%s.%s", path, key);
            int is_shape = 0;
            for (size_t q = 0; q < N_SHAPES; q++)
                if (!strcmp(key, shape_keys[q])) {
                    is_shape = 1;
                    if (shape)
                        return yr_fail(c, k, p, "a parameter has one shape, and '%s' is already given", shape_name);
                    shape = val;
                    shape_name = shape_keys[q];
                }
            if (is_shape)
                continue;
            if (!strcmp(key, "cutoff")) {
                cutoff_node = val;
            } else if (!strcmp(key, "unit")) {
                free(s->param_units[i]);
                s->param_units[i] = NULL;
                if ((st = yr_string_dup(c, val, p, &s->param_units[i])) != RF_OK)
                    return st;
            } else if (!strcmp(key, "class")) {
                const char *cls;
                size_t len;
                if ((st = yr_string(c, val, p, &cls, &len)) != RF_OK)
                    return st;
                if (len == 9 && !strncmp(cls, "monotonic", len))
                    s->param_class[i] = RF_MONO_MONOTONIC;
                else if (len == 12 && !strncmp(cls, "nonmonotonic", len))
                    s->param_class[i] = RF_MONO_NONMONOTONIC;
                else if (len == 4 && !strncmp(cls, "auto", len))
                    s->param_class[i] = RF_MONO_AUTO;
                else
                    return yr_fail(c, val, p, "expected monotonic, nonmonotonic or auto");
            } else {
                return yr_fail(c, k, p,
                               "unknown key; a parameter takes one shape (tfn, trapezoid, interval, gaussian, "
                               "crisp, points, cuts) and optionally unit, class, cutoff (gaussian)");
            }
        }
        if (!shape)
            return yr_fail(c, v, path,
                           "no shape given; use one of tfn, trapezoid, interval, gaussian, crisp, points, cuts");
        if (cutoff_node && strcmp(shape_name, "gaussian"))
            return yr_fail(c, cutoff_node, "", "%s.cutoff: only a gaussian parameter takes a cutoff", path);
        yr_pathf(p, sizeof p, "%s.%s", path, shape_name);
        double w[4];
        if (!strcmp(shape_name, "tfn")) {
            st = shape_tfn(c, shape, p, f, desc, sizeof desc);
        } else if (!strcmp(shape_name, "trapezoid")) {
            if ((st = shape_ordered(c, shape, p, 4, w)) != RF_OK)
                return st;
            snprintf(desc, sizeof desc, "trapezoid(%.15g, %.15g, %.15g, %.15g)", w[0], w[1], w[2], w[3]);
            if (rf_fuzzy_trapezoid(f, w[0], w[1], w[2], w[3], c->err) != RF_OK)
                return yr_prefix(c, shape, p);
        } else if (!strcmp(shape_name, "interval")) {
            if ((st = shape_ordered(c, shape, p, 2, w)) != RF_OK)
                return st;
            snprintf(desc, sizeof desc, "interval(%.15g, %.15g)", w[0], w[1]);
            if (rf_fuzzy_interval(f, w[0], w[1], c->err) != RF_OK)
                return yr_prefix(c, shape, p);
        } else if (!strcmp(shape_name, "gaussian")) {
            double cutoff = 3;
            if (cutoff_node) {
                char cp[320];
                yr_pathf(cp, sizeof cp, "%s.cutoff", path);
                if ((st = yr_number(c, cutoff_node, cp, &cutoff)) != RF_OK)
                    return st;
                if (!(cutoff > 0))
                    return yr_fail(c, cutoff_node, cp, "the cutoff must be > 0 (usually 3)");
            }
            st = shape_gaussian(c, shape, p, cutoff, f, desc, sizeof desc);
        } else if (!strcmp(shape_name, "crisp")) {
            if ((st = yr_number(c, shape, p, &w[0])) != RF_OK)
                return st;
            snprintf(desc, sizeof desc, "crisp(%.15g)", w[0]);
            if (rf_fuzzy_crisp(f, w[0], c->err) != RF_OK)
                return yr_prefix(c, shape, p);
        } else if (!strcmp(shape_name, "points")) {
            st = shape_points(c, shape, p, f, desc, sizeof desc);
        } else {
            st = shape_cuts(c, shape, p, f, desc, sizeof desc);
        }
        if (st != RF_OK)
            return st;
    }
    s->param_shapes[i] = yr_strdup(desc);
    if (!s->param_shapes[i])
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    /* Decompose once now so that a shape that does not nest at these levels fails before any evaluation. */
    double *lo = malloc((s->levels + 1) * sizeof *lo), *hi = malloc((s->levels + 1) * sizeof *hi);
    if (!lo || !hi) {
        free(lo);
        free(hi);
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    }
    st = rf_fuzzy_decompose(f, s->levels, lo, hi, c->err);
    free(lo);
    free(hi);
    if (st != RF_OK)
        return yr_prefix(c, v, path);
    return RF_OK;
}

static rf_status parse_parameters(yr_ctx *c, rf_study *s, struct fy_node *n)
{
    rf_status st = yr_mapping(c, n, "parameters");
    if (st != RF_OK)
        return st;
    int cnt = fy_node_mapping_item_count(n);
    if (cnt < 1)
        return yr_fail(c, n, "parameters", "at least one parameter is needed");
    if (cnt > MAX_PARAMS)
        return yr_fail(c, n, "parameters", "at most %d parameters are supported, got %d", MAX_PARAMS, cnt);
    size_t np = (size_t)cnt;
    s->param_names = calloc(np, sizeof(char *));
    s->param_units = calloc(np, sizeof(char *));
    s->param_shapes = calloc(np, sizeof(char *));
    s->inputs = calloc(np, sizeof(rf_fuzzy));
    s->param_class = calloc(np, sizeof(rf_monotonicity));
    s->param_line = calloc(np, sizeof(int));
    if (!s->param_names || !s->param_units || !s->param_shapes || !s->inputs || !s->param_class || !s->param_line)
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    for (size_t i = 0;; i++) {
        if ((st = yr_next(c, &it, "parameters", &key, &k, &v)) != RF_OK)
            return st;
        if (!key)
            break;
        if (i >= np)
            return rf_fail(c->err, RF_EINTERNAL, "parameter count changed while parsing");
        char path[300];
        yr_pathf(path, sizeof path, "parameters.%s", key);
        if (!is_identifier(key))
            return yr_fail(c, k, "", "%s: a parameter name must be an identifier (letters, digits, _; not "
                                     "starting with a digit; at most 64 characters)",
                           path);
        s->n_params = i + 1; /* from here rf_study_free releases entry i (also half-filled) */
        s->param_names[i] = yr_strdup(key);
        s->param_units[i] = yr_strdup("");
        if (!s->param_names[i] || !s->param_units[i])
            return rf_fail(c->err, RF_ENOMEM, "out of memory");
        if ((st = parse_param(c, s, i, s->param_names[i], k, v)) != RF_OK)
            return st;
    }
    return RF_OK;
}

static rf_status parse_options(yr_ctx *c, rf_study *s, struct fy_node *n)
{
    rf_status st = yr_mapping(c, n, "options");
    if (st != RF_OK)
        return st;
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    char p[300];
    for (;;) {
        if ((st = yr_next(c, &it, "options", &key, &k, &v)) != RF_OK)
            return st;
        if (!key)
            return RF_OK;
        yr_pathf(p, sizeof p, "options.%s", key);
        long long iv;
        if (!strcmp(key, "max_evaluations")) {
            if ((st = yr_integer(c, v, p, 0, 1000000000000LL, &iv)) != RF_OK)
                return st;
            s->max_evaluations = (size_t)iv;
        } else if (!strcmp(key, "left_right")) {
            if ((st = yr_bool(c, v, p, &s->left_right)) != RF_OK)
                return st;
        } else if (!strcmp(key, "jobs")) {
            if ((st = yr_integer(c, v, p, 0, 1024, &iv)) != RF_OK)
                return st;
            s->jobs = (int)iv;
        } else {
            return yr_fail(c, k, p, "unknown option; expected max_evaluations, left_right or jobs");
        }
    }
}

/* `main_output: NAME`, one of the model's outputs (known once the model is built). */
static rf_status parse_main_output(yr_ctx *c, rf_study *s, struct fy_node *v)
{
    const char *name;
    size_t len;
    rf_status st = yr_string(c, v, "main_output", &name, &len);
    for (size_t k = 0; st == RF_OK && k < s->model.n_outputs; k++)
        if (strlen(s->model.output_names[k]) == len && !strncmp(s->model.output_names[k], name, len)) {
            s->main_output = (long)k;
            return RF_OK;
        }
    if (st != RF_OK)
        return st;
    char list[1024] = "";
    size_t used = 0;
    for (size_t k = 0; k < s->model.n_outputs && used + 1 < sizeof list; k++)
        used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", k ? ", " : "", s->model.output_names[k]);
    return yr_fail(c, v, "main_output", "'%.*s' is not an output of the model; its outputs: %s", (int)len, name, list);
}

static rf_status parse_document(yr_ctx *c, rf_study *s, struct fy_document *doc)
{
    struct fy_node *root = fy_document_root(doc);
    if (!root)
        return rf_fail(c->err, RF_EINVAL, "%s:1: the study file is empty", c->file);
    rf_status st = yr_mapping(c, root, "(top level)");
    if (st != RF_OK)
        return st;
    struct fy_node *params = NULL, *model = NULL, *options = NULL, *params_key = NULL, *main_out = NULL;
    yr_iter it = {root, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    /* Scalars first (levels is needed to check the parameters), blocks after. */
    for (;;) {
        if ((st = yr_next(c, &it, "", &key, &k, &v)) != RF_OK)
            return st;
        if (!key)
            break;
        if (!strcmp(key, "name")) {
            free(s->name);
            s->name = NULL;
            if ((st = yr_string_dup(c, v, "name", &s->name)) != RF_OK)
                return st;
        } else if (!strcmp(key, "description")) {
            const char *d;
            size_t len;
            if ((st = yr_string(c, v, "description", &d, &len)) != RF_OK)
                return st;
        } else if (!strcmp(key, "scheme")) {
            char buf[32];
            if ((st = yr_word(c, v, "scheme", buf, sizeof buf)) != RF_OK)
                return st;
            if (rf_tm_scheme_parse(buf, &s->scheme) != RF_OK)
                return yr_fail(c, v, "scheme", "unknown scheme; expected general, reduced or extended");
            s->scheme_set = 1;
        } else if (!strcmp(key, "levels")) {
            long long m;
            if ((st = yr_integer(c, v, "levels", 1, RF_STUDY_MAX_LEVELS, &m)) != RF_OK) {
                double d;
                rf_error tmp;
                yr_ctx c2 = {c->file, c->dir, &tmp, NULL};
                if (yr_number(&c2, v, "levels", &d) == RF_OK && d < 1)
                    return yr_fail(c, v, "levels", "at least one membership interval is needed (levels >= 1)");
                return st;
            }
            s->levels = (size_t)m;
        } else if (!strcmp(key, "parameters")) {
            params = v;
            params_key = k;
        } else if (!strcmp(key, "model")) {
            model = v;
        } else if (!strcmp(key, "options")) {
            options = v;
        } else if (!strcmp(key, "main_output")) {
            main_out = v;
        } else {
            return yr_fail(c, k, key, "unknown key; the top level takes name, description, scheme, levels, "
                                      "parameters, model, main_output, options");
        }
    }
    if (!params)
        return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters: missing (at least one fuzzy parameter is needed)",
                       c->file, yr_line(root));
    if (!model)
        return rf_fail(c->err, RF_EINVAL, "%s:%d: model: missing (formula, program or impact)", c->file,
                       yr_line(root));
    (void)params_key;
    if (options && (st = parse_options(c, s, options)) != RF_OK)
        return st;
    if ((st = parse_parameters(c, s, params)) != RF_OK)
        return st;
    if ((st = sp_parse_model(c, model, s)) != RF_OK)
        return st;
    sb_default_scheme(s);
    return main_out ? parse_main_output(c, s, main_out) : RF_OK;
}

/* Base name and directory of a path. */
static rf_status split_path(const char *path, char **dir, char **stem, rf_error *err)
{
    const char *slash = strrchr(path, '/');
    *dir = slash ? yr_strndup(path, slash == path ? 1 : (size_t)(slash - path)) : yr_strdup(".");
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    *stem = yr_strndup(base, dot && dot != base ? (size_t)(dot - base) : strlen(base));
    if (!*dir || !*stem)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    return RF_OK;
}

/* YAML text must be UTF-8 without NUL bytes.  Checked before libfyaml sees
 * the text: libfyaml 0.7.12 loops forever on some invalid bytes after '%'
 * (found by fuzz_study: "%\xff\xff\xff\xf8"). */

#define MAX_STUDY_BYTES (16u << 20)

static rf_status load(const char *name, const char *buf, size_t len, rf_study *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    s->scheme = RF_TM_REDUCED;
    s->levels = 10;
    s->max_evaluations = 100000;
    s->left_right = 1;
    s->jobs = 0;
    s->main_output = -1;
    char *stem = NULL;
    s->path = yr_strdup(name);
    if (!s->path)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_status st = split_path(name, &s->dir, &stem, err);
    s->name = stem;
    yr_doc d = {0};
    if (st == RF_OK)
        st = yr_doc_load(&d, name, buf, len, "study file", err);
    if (st == RF_OK) {
        yr_ctx c = {name, s->dir, err, NULL};
        st = parse_document(&c, s, d.doc);
    }
    yr_doc_free(&d);
    if (st != RF_OK)
        rf_study_free(s);
    return st;
}

rf_status rf_study_load(const char *path, rf_study *study, rf_error *err)
{
    if (!path || !study)
        return rf_fail(err, RF_EINTERNAL, "rf_study_load: NULL argument");
    memset(study, 0, sizeof *study);
    char *buf = NULL;
    size_t len = 0;
    rf_status st = rf_read_text_file(path, "study file", MAX_STUDY_BYTES, &buf, &len, err);
    if (st == RF_OK)
        st = load(path, buf, len, study, err);
    free(buf);
    return st;
}

rf_status rf_study_load_buffer(const char *name, const char *buf, size_t len, rf_study *study, rf_error *err)
{
    if (!study || (!buf && len))
        return rf_fail(err, RF_EINTERNAL, "rf_study_load_buffer: NULL argument");
    if (!buf)
        buf = "";
    return load(name ? name : "<buffer>", buf, len, study, err);
}
