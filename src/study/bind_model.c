/* bind_model.c - the model of a study whose parameters drive the inputs of
 * another model through a binding (several inputs, value * scale + offset):
 * evaluation, identity and the forwarding of warnings and interrupts. */
#include "study/bind.h"
#include "core/util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    rf_model inner;          /* the model of the targets */
    sb_binding b;            /* a copy of the binding */
} bind_ctx;

static rf_status bind_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    const bind_ctx *c = ctx;
    double xi[SB_MAX_TARGETS];
    sb_expand(&c->b, x, xi);
    return c->inner.eval(c->inner.ctx, xi, y, err);
}

static void bind_destroy(void *ctx)
{
    bind_ctx *c = ctx;
    rf_model_free(&c->inner);
    sb_free(&c->b);
    free(c);
}

static size_t bind_warnings(void *ctx, char *buf, size_t size)
{
    bind_ctx *c = ctx;
    return c->inner.warnings(c->inner.ctx, buf, size);
}

static size_t bind_surrogate_error(void *ctx, char *buf, size_t size)
{
    bind_ctx *c = ctx;
    return c->inner.surrogate_error(c->inner.ctx, buf, size);
}

static void bind_interrupt(void *ctx, const atomic_int *flag)
{
    bind_ctx *c = ctx;
    rf_model_set_interrupt(&c->inner, flag);
}

static void bind_side_store(void *ctx, const rf_model_side_store *store)
{
    bind_ctx *c = ctx;
    rf_model_set_side_store(&c->inner, store);
}

static int is_identity(const sb_binding *b, size_t n_params)
{
    if (b->n != n_params)
        return 0;
    for (size_t j = 0; j < b->n; j++)
        if (b->t[j].param != j || b->t[j].scale != 1.0 || b->t[j].offset != 0.0)
            return 0;
    return 1;
}

static rf_status copy_binding(const sb_binding *src, sb_binding *dst, rf_error *err)
{
    dst->n = 0;
    if (!(dst->t = calloc(src->n ? src->n : 1, sizeof *dst->t)))
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t j = 0; j < src->n; j++, dst->n++) {
        dst->t[j] = src->t[j];
        if (!(dst->t[j].to = rf_strdup(src->t[j].to)))
            return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    return RF_OK;
}

/* The inner identity, then every target as param->input*scale+offset (%.17g). */
static rf_status set_identity(rf_model *m, const bind_ctx *c, rf_error *err)
{
    size_t size = strlen(c->inner.identity ? c->inner.identity : "") + 64;
    for (size_t j = 0; j < c->b.n; j++)
        size += strlen(c->b.t[j].to) + 80;
    char *id = malloc(size);
    if (!id)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    size_t len = (size_t)snprintf(id, size, "%s; bound as", c->inner.identity ? c->inner.identity : "");
    for (size_t j = 0; j < c->b.n; j++)
        len += (size_t)snprintf(id + len, size - len, " x%zu->%s*%.17g+%.17g", c->b.t[j].param, c->b.t[j].to,
                                c->b.t[j].scale, c->b.t[j].offset);
    rf_status st = rf_model_set_identity(m, id, err);
    free(id);
    return st;
}

static rf_status fill(rf_model *m, bind_ctx *c, size_t n_params, rf_error *err)
{
    m->n_inputs = n_params;
    m->eval = bind_eval;
    m->ctx = c;
    m->destroy = bind_destroy;
    m->threads_per_eval = c->inner.threads_per_eval;
    m->warnings = c->inner.warnings ? bind_warnings : NULL;
    m->surrogate_error = c->inner.surrogate_error ? bind_surrogate_error : NULL;
    m->set_interrupt = c->inner.set_interrupt ? bind_interrupt : NULL;
    m->set_side_store = c->inner.set_side_store ? bind_side_store : NULL;
    rf_status st = rf_model_init_outputs(m, c->inner.n_outputs, (const char *const *)c->inner.output_names,
                                         (const char *const *)c->inner.output_units, err);
    return st == RF_OK ? set_identity(m, c, err) : st;
}

rf_status sb_wrap(const sb_binding *b, size_t n_params, rf_model *model, rf_error *err)
{
    if (is_identity(b, n_params))
        return RF_OK;
    bind_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        rf_model_free(model);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    c->inner = *model;
    memset(model, 0, sizeof *model);
    rf_status st = copy_binding(b, &c->b, err);
    if (st != RF_OK) {
        bind_destroy(c);
        return st;
    }
    if ((st = fill(model, c, n_params, err)) != RF_OK)
        rf_model_free(model);
    return st;
}

const rf_model *sb_unwrap(const rf_model *m, const double *x, double *xi)
{
    if (m->eval != bind_eval) {
        memcpy(xi, x, m->n_inputs * sizeof *x);
        return m;
    }
    const bind_ctx *c = m->ctx;
    sb_expand(&c->b, x, xi);
    return &c->inner;
}
