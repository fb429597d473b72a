/* formula.c - a model given as expressions typed by the user (muParser).
 *
 * Each output is one muParser expression over the parameter names.  At
 * creation every expression is parsed once, its identifiers are checked
 * against the parameter names and a trial evaluation catches syntax errors,
 * so that a study fails before any evaluation with a message naming the
 * output, the identifier and the position.
 *
 * muParser handles are not thread-safe, so evaluations never share one: a
 * work area holds one handle per output, all bound to the work area's own
 * copy of the parameter vector.  Work areas live in a mutex-protected pool;
 * an evaluation takes one (creating it if the pool is empty), evaluates and
 * gives it back.  The pool therefore grows to the number of threads that
 * ever evaluate at once and no further. */
#include "rockfuzz/model.h"

#include <muParserDLL.h>

#include "core/util.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct formula_work {
    double *x;                  /* n_params values the handles are bound to */
    muParserHandle_t *handles;  /* one per output */
    struct formula_work *next;  /* free-list link */
} formula_work;

typedef struct {
    size_t n_params;
    char **param_names;
    size_t n_outputs;
    char **output_names;
    char **expressions;
    pthread_mutex_t lock;
    formula_work *free_list;    /* idle work areas */
} formula_ctx;

/* mupGetExprVar returns the name in a static buffer inside muParser, so
 * listing a handle's variables is serialised across all formula models. */
static pthread_mutex_t mup_static_buffer_lock = PTHREAD_MUTEX_INITIALIZER;

static void work_free(formula_work *w, size_t n_outputs)
{
    if (!w)
        return;
    if (w->handles) {
        for (size_t k = 0; k < n_outputs; k++) {
            if (w->handles[k])
                mupRelease(w->handles[k]);
        }
    }
    free(w->handles);
    free(w->x);
    free(w);
}

/* muParser accepts identifiers of [0-9a-zA-Z_] not starting with a digit;
 * a parameter with another name cannot appear in a formula, so it is simply
 * not defined (an expression using it then fails with "unknown parameter"). */
static int is_mup_identifier(const char *s)
{
    if (!s[0] || (s[0] >= '0' && s[0] <= '9'))
        return 0;
    for (const char *p = s; *p; p++) {
        char c = *p;
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'))
            return 0;
    }
    return 1;
}

static void list_params(const formula_ctx *c, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < c->n_params && used + 1 < size; i++) {
        int n = snprintf(buf + used, size - used, "%s%s", i ? ", " : "", c->param_names[i]);
        if (n < 0)
            break;
        used += (size_t)n;
    }
    if (c->n_params == 0)
        snprintf(buf, size, "none");
}

/* Up to size-1 characters of expr around pos, "..." marking what was cut. */
static void excerpt(const char *expr, int pos, char *buf, size_t size)
{
    size_t len = strlen(expr), room = size - 7; /* two "..." and the NUL */
    size_t p = pos < 0 ? 0 : (size_t)pos > len ? len : (size_t)pos;
    size_t from = p > room * 2 / 3 ? p - room * 2 / 3 : 0;
    size_t n = len - from < room ? len - from : room;
    snprintf(buf, size, "%s%.*s%s", from ? "..." : "", (int)n, expr + from, from + n < len ? "..." : "");
}

/* Positions are reported counting from 1 (muParser counts from 0); the
 * position muParser appends to its own message is dropped so that the
 * message does not carry two different numbers. */
static rf_status syntax_error(const formula_ctx *c, size_t k, muParserHandle_t h, rf_error *err)
{
    char msg[512];
    snprintf(msg, sizeof msg, "%s", mupGetErrorMsg(h));
    const char *suffixes[] = {" at expression position ", " at position "};
    for (size_t i = 0; i < 2; i++) {
        char *at = strstr(msg, suffixes[i]);
        if (at && at[strlen(suffixes[i]) + strspn(at + strlen(suffixes[i]), "0123456789")] == '\0') {
            *at = '\0';
            break;
        }
    }
    /* the reason first: a long expression must not push it out of the message */
    int pos = (int)mupGetErrorPos(h);
    char near[160];
    excerpt(c->expressions[k], pos, near, sizeof near);
    return rf_fail(err, RF_EPARSE, "output '%s': syntax error at position %d: %s, near \"%s\"", c->output_names[k],
                   pos + 1, msg, near);
}

/* One handle for output k bound to x.  With check set (creation time), also
 * verify identifiers and syntax and report them. */
static rf_status make_handle(const formula_ctx *c, size_t k, double *x, int check,
                             muParserHandle_t *out, rf_error *err)
{
    muParserHandle_t h = mupCreate(muBASETYPE_FLOAT);
    if (!h)
        return rf_fail(err, RF_ENOMEM, "out of memory for the parser of output '%s'", c->output_names[k]);
    for (size_t i = 0; i < c->n_params; i++) {
        if (is_mup_identifier(c->param_names[i]))
            mupDefineVar(h, c->param_names[i], &x[i]);
        if (mupError(h)) {
            rf_status st = rf_fail(err, RF_EINVAL, "output '%s': parameter '%s' cannot be used in a formula: %s",
                                   c->output_names[k], c->param_names[i], mupGetErrorMsg(h));
            mupRelease(h);
            return st;
        }
    }
    mupSetExpr(h, c->expressions[k]);
    if (mupError(h)) {
        rf_status st = syntax_error(c, k, h, err);
        mupRelease(h);
        return st;
    }
    if (check) {
        /* Listing the used variables parses with undefined names allowed,
         * so an unknown identifier is reported by name rather than as a
         * muParser "unexpected token". */
        int n_used = mupGetExprVarNum(h);
        if (mupError(h)) {
            rf_status st = syntax_error(c, k, h, err);
            mupRelease(h);
            return st;
        }
        for (int v = 0; v < n_used; v++) {
            char name[128] = "?";
            const char *name_buf = NULL;
            double *ptr = NULL;
            pthread_mutex_lock(&mup_static_buffer_lock);
            mupGetExprVar(h, (unsigned)v, &name_buf, &ptr);
            if (name_buf)
                snprintf(name, sizeof name, "%s", name_buf);
            pthread_mutex_unlock(&mup_static_buffer_lock);
            int known = 0;
            for (size_t i = 0; i < c->n_params; i++)
                known |= strcmp(name, c->param_names[i]) == 0;
            if (!known) {
                char params[512];
                list_params(c, params, sizeof params);
                char near[120];
                excerpt(c->expressions[k], (int)(strstr(c->expressions[k], name) ? strstr(c->expressions[k], name) -
                                                 c->expressions[k] : 0), near, sizeof near);
                rf_status st = rf_fail(err, RF_EINVAL, "output '%s': unknown parameter '%s' near \"%s\" (known: %s)",
                                       c->output_names[k], name, near, params);
                mupRelease(h);
                return st;
            }
        }
        int n_results = 0;
        mupEvalMulti(h, &n_results);
        if (mupError(h)) {
            rf_status st = syntax_error(c, k, h, err);
            mupRelease(h);
            return st;
        }
        if (n_results != 1) {
            mupRelease(h);
            return rf_fail(err, RF_EPARSE, "output '%s': \"%s\" gives %d values; one expression per output",
                           c->output_names[k], c->expressions[k], n_results);
        }
    }
    *out = h;
    return RF_OK;
}

static rf_status work_create(const formula_ctx *c, int check, formula_work **out, rf_error *err)
{
    formula_work *w = calloc(1, sizeof *w);
    if (!w)
        return rf_fail(err, RF_ENOMEM, "out of memory for a formula work area");
    w->x = calloc(c->n_params ? c->n_params : 1, sizeof *w->x);
    w->handles = calloc(c->n_outputs ? c->n_outputs : 1, sizeof *w->handles);
    if (!w->x || !w->handles) {
        work_free(w, c->n_outputs);
        return rf_fail(err, RF_ENOMEM, "out of memory for a formula work area");
    }
    /* A trial evaluation at x = 1 (not 0, to avoid spurious 1/x poles in
     * the check; the value is discarded). */
    for (size_t i = 0; i < c->n_params; i++)
        w->x[i] = 1.0;
    for (size_t k = 0; k < c->n_outputs; k++) {
        rf_status st = make_handle(c, k, w->x, check, &w->handles[k], err);
        if (st != RF_OK) {
            work_free(w, c->n_outputs);
            return st;
        }
    }
    *out = w;
    return RF_OK;
}

static void formula_destroy(void *ctx)
{
    formula_ctx *c = ctx;
    if (!c)
        return;
    while (c->free_list) {
        formula_work *w = c->free_list;
        c->free_list = w->next;
        work_free(w, c->n_outputs);
    }
    pthread_mutex_destroy(&c->lock);
    for (size_t i = 0; i < c->n_params; i++)
        free(c->param_names[i]);
    for (size_t k = 0; k < c->n_outputs; k++) {
        free(c->output_names[k]);
        free(c->expressions[k]);
    }
    free(c->param_names);
    free(c->output_names);
    free(c->expressions);
    free(c);
}

static rf_status formula_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    formula_ctx *c = ctx;
    formula_work *w = NULL;

    pthread_mutex_lock(&c->lock);
    if (c->free_list) {
        w = c->free_list;
        c->free_list = w->next;
    }
    pthread_mutex_unlock(&c->lock);
    if (!w) {
        rf_status st = work_create(c, 0, &w, err);
        if (st != RF_OK)
            return st;
    }

    rf_status st = RF_OK;
    memcpy(w->x, x, c->n_params * sizeof *x);
    for (size_t k = 0; k < c->n_outputs && st == RF_OK; k++) {
        y[k] = mupEval(w->handles[k]);
        if (mupError(w->handles[k])) {
            st = rf_fail(err, RF_EMODEL, "output '%s': evaluation of \"%s\" failed: %s", c->output_names[k],
                         c->expressions[k], mupGetErrorMsg(w->handles[k]));
        } else if (!isfinite(y[k])) {
            char at[RF_ERROR_MAX / 2];
            size_t used = 0;
            at[0] = '\0';
            for (size_t i = 0; i < c->n_params && used + 1 < sizeof at; i++) {
                int n = snprintf(at + used, sizeof at - used, "%s%s=%.10g", i ? ", " : "", c->param_names[i], x[i]);
                if (n < 0)
                    break;
                used += (size_t)n;
            }
            st = rf_fail(err, RF_EMODEL, "output '%s': \"%s\" is %s at (%s)", c->output_names[k], c->expressions[k],
                         isnan(y[k]) ? "not a number (NaN)" : "infinite", at);
        }
    }

    pthread_mutex_lock(&c->lock);
    w->next = c->free_list;
    c->free_list = w;
    pthread_mutex_unlock(&c->lock);
    return st;
}

/* Canonical text: parameter order matters (x[i] binds names[i]). */
static char *formula_identity(const formula_ctx *c)
{
    size_t size = 32;
    for (size_t i = 0; i < c->n_params; i++)
        size += strlen(c->param_names[i]) + 2;
    for (size_t k = 0; k < c->n_outputs; k++)
        size += strlen(c->output_names[k]) + strlen(c->expressions[k]) + 8;
    char *s = malloc(size);
    if (!s)
        return NULL;
    size_t used = (size_t)snprintf(s, size, "formula(params=[");
    for (size_t i = 0; i < c->n_params; i++)
        used += (size_t)snprintf(s + used, size - used, "%s%s", i ? "," : "", c->param_names[i]);
    used += (size_t)snprintf(s + used, size - used, "];outputs=[");
    for (size_t k = 0; k < c->n_outputs; k++)
        used += (size_t)snprintf(s + used, size - used, "%s%s=\"%s\"", k ? "," : "", c->output_names[k],
                                 c->expressions[k]);
    snprintf(s + used, size - used, "])");
    return s;
}

rf_status rf_formula_model_create(size_t n_params, const char *const *param_names, size_t n_outputs,
                                  const char *const *output_names, const char *const *expressions,
                                  rf_model *model, rf_error *err)
{
    if (!model)
        return rf_fail(err, RF_EINTERNAL, "rf_formula_model_create: model is NULL");
    memset(model, 0, sizeof *model);
    if (n_outputs == 0)
        return rf_fail(err, RF_EINVAL, "formula model: no outputs");
    if ((n_params && !param_names) || !output_names || !expressions)
        return rf_fail(err, RF_EINTERNAL, "rf_formula_model_create: NULL name or expression array");
    for (size_t k = 0; k < n_outputs; k++) {
        if (!output_names[k] || !output_names[k][0])
            return rf_fail(err, RF_EINVAL, "formula model: output %zu has no name", k + 1);
        if (!expressions[k] || !expressions[k][strspn(expressions[k], " \t\r\n")])
            return rf_fail(err, RF_EINVAL, "output '%s': empty formula", output_names[k]);
        for (size_t j = 0; j < k; j++) {
            if (strcmp(output_names[j], output_names[k]) == 0)
                return rf_fail(err, RF_EINVAL, "formula model: output '%s' is defined twice", output_names[k]);
        }
    }

    formula_ctx *c = calloc(1, sizeof *c);
    if (!c)
        return rf_fail(err, RF_ENOMEM, "out of memory for the formula model");
    if (pthread_mutex_init(&c->lock, NULL) != 0) {
        free(c);
        return rf_fail(err, RF_EINTERNAL, "formula model: cannot create a mutex");
    }
    c->param_names = calloc(n_params ? n_params : 1, sizeof(char *));
    c->output_names = calloc(n_outputs, sizeof(char *));
    c->expressions = calloc(n_outputs, sizeof(char *));
    if (!c->param_names || !c->output_names || !c->expressions) {
        formula_destroy(c);
        return rf_fail(err, RF_ENOMEM, "out of memory for the formula model");
    }
    c->n_params = n_params;
    c->n_outputs = n_outputs;
    for (size_t i = 0; i < n_params; i++) {
        if (!(c->param_names[i] = rf_strdup(param_names[i]))) {
            formula_destroy(c);
            return rf_fail(err, RF_ENOMEM, "out of memory for the formula model");
        }
    }
    for (size_t k = 0; k < n_outputs; k++) {
        c->output_names[k] = rf_strdup(output_names[k]);
        c->expressions[k] = rf_strdup(expressions[k]);
        if (!c->output_names[k] || !c->expressions[k]) {
            formula_destroy(c);
            return rf_fail(err, RF_ENOMEM, "out of memory for the formula model");
        }
    }

    /* Parse and check everything now; the checked work area becomes the
     * first member of the pool. */
    formula_work *w = NULL;
    rf_status st = work_create(c, 1, &w, err);
    if (st != RF_OK) {
        formula_destroy(c);
        return st;
    }
    c->free_list = w;

    model->n_inputs = n_params;
    model->eval = formula_eval;
    model->ctx = c;
    model->destroy = formula_destroy;
    model->threads_per_eval = 1;
    st = rf_model_init_outputs(model, n_outputs, output_names, NULL, err);
    if (st == RF_OK) {
        char *id = formula_identity(c);
        st = id ? rf_model_set_identity(model, id, err) : rf_fail(err, RF_ENOMEM, "out of memory for model identity");
        free(id);
    }
    if (st != RF_OK)
        rf_model_free(model);
    return st;
}
