/* model.c - shared helpers behind the rf_model interface (see model.h). */
#include "rockfuzz/model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"

/* The points are evaluated first and their outputs checked after, in one
 * pass that vectorises: an infinite output is reported at its point, the
 * points after it may have been evaluated too. */
rf_status rf_model_eval_many(const rf_model *model, size_t count, const double *x, double *y, size_t *failed,
                             rf_error *err)
{
    if (!model || !model->eval)
        return rf_fail(err, RF_EINTERNAL, "model has no evaluation function");
    size_t nin = model->n_inputs, nout = model->n_outputs, done = 0;
    rf_model_eval_fn eval = model->eval; /* locals: the calls may write anywhere */
    void *ctx = model->ctx;
    rf_status st = RF_OK;
    for (; done < count && st == RF_OK; done++)
        st = eval(ctx, x + done * nin, y + done * nout, err);
    size_t evaluated = st == RF_OK ? done : done - 1; /* points with outputs */
    int any_inf = 0;
    for (size_t e = 0; e < evaluated * nout; e++)
        any_inf |= isinf(y[e]); /* NaN is allowed: "undefined here" */
    for (size_t e = 0; any_inf && e < evaluated * nout; e++)
        if (isinf(y[e])) {
            *failed = e / nout;
            return rf_fail(err, RF_EMODEL, "output '%s' is infinite", model->output_names[e % nout]);
        }
    if (st != RF_OK)
        *failed = done - 1;
    return st;
}

rf_status rf_model_eval(const rf_model *model, const double *x, double *y, rf_error *err)
{
    size_t failed = 0;
    return rf_model_eval_many(model, 1, x, y, &failed, err);
}

void rf_model_set_interrupt(rf_model *model, const atomic_int *flag)
{
    if (model && model->set_interrupt)
        model->set_interrupt(model->ctx, flag);
}

void rf_model_set_side_store(rf_model *model, const rf_model_side_store *store)
{
    if (model && model->set_side_store)
        model->set_side_store(model->ctx, store);
}

rf_status rf_model_prepare(rf_model *model, FILE *log, rf_error *err)
{
    return model && model->prepare ? model->prepare(model->ctx, log, err) : RF_OK;
}

void rf_model_free(rf_model *model)
{
    if (!model)
        return;
    if (model->destroy)
        model->destroy(model->ctx);
    for (size_t k = 0; k < model->n_outputs; k++) {
        if (model->output_names)
            free(model->output_names[k]);
        if (model->output_units)
            free(model->output_units[k]);
    }
    free(model->output_names);
    free(model->output_units);
    free(model->identity);
    memset(model, 0, sizeof *model);
}

rf_status rf_model_init_outputs(rf_model *model, size_t n_outputs, const char *const *names,
                                const char *const *units, rf_error *err)
{
    model->n_outputs = n_outputs;
    model->output_names = calloc(n_outputs ? n_outputs : 1, sizeof(char *));
    model->output_units = calloc(n_outputs ? n_outputs : 1, sizeof(char *));
    if (!model->output_names || !model->output_units)
        return rf_fail(err, RF_ENOMEM, "out of memory for model outputs");
    for (size_t k = 0; k < n_outputs; k++) {
        model->output_names[k] = rf_strdup(names[k]);
        model->output_units[k] = rf_strdup(units && units[k] ? units[k] : "");
        if (!model->output_names[k] || !model->output_units[k])
            return rf_fail(err, RF_ENOMEM, "out of memory for model outputs");
    }
    if (model->threads_per_eval < 1)
        model->threads_per_eval = 1;
    return RF_OK;
}

rf_status rf_model_set_identity(rf_model *model, const char *identity, rf_error *err)
{
    free(model->identity);
    model->identity = rf_strdup(identity);
    return model->identity ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory for model identity");
}
