/* traj_model.c - the trajectory model behind the rf_model interface: one
 * evaluation binds the TM point's values to paths of the trajectory spec,
 * runs the whole Monte Carlo ensemble (single-threaded: the study runner
 * parallelises over points) and returns its statistics.  Every evaluation
 * uses the spec's seed, so the TM's points see the same random numbers
 * (common random numbers): differences between points are the fuzzy inputs'
 * effect, not sampling noise.  A collector that no block reaches gets 0 for
 * its energy and height percentiles (no energy passes), so outputs stay finite.
 * With the impact_model law the impact table is built once for the model and
 * shared by every evaluation (each impact of the impact model is computed
 * once per study process), unless a parameter changes it. */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    rf_traj_spec spec;
    size_t n_params;
    char **paths;
    void *table;             /* impact_model: built once when no parameter changes it, else NULL */
} traj_model_ctx;

static const char *const pct_names[4] = {"p50", "p95", "p99", "max"};

static void put_pct(double *y, const rf_traj_percentiles *p)
{
    double v[4] = {p->p50, p->p95, p->p99, p->max};
    for (int k = 0; k < 4; k++)
        y[k] = isfinite(v[k]) ? v[k] : 0;
}

/* Outputs: per collector 4 ke + 4 height + reach; then 4 runout + 4 rebound. */
static size_t n_outputs_for(size_t nc) { return 9 * nc + 8; }

static rf_status traj_model_eval(void *vctx, const double *x, double *y, rf_error *err)
{
    traj_model_ctx *c = vctx;
    rf_traj_spec s;
    rf_status st = rf_traj_spec_copy(&c->spec, &s, err);
    if (st != RF_OK)
        return st;
    for (size_t i = 0; i < c->n_params; i++)
        *rf_traj_spec_field(&s, c->paths[i]) = x[i];
    s.record = 0;
    rf_traj_ensemble e;
    rf_traj_stats t;
    if ((st = traj_run_with(&s, 1, c->table, 0, &e, err)) == RF_OK) { /* no envelopes: not outputs */
        if ((st = rf_traj_stats_compute(&e, &t, err)) == RF_OK) {
            size_t nc = s.n_collectors, o = 0;
            for (size_t k = 0; k < nc; k++, o += 9) {
                put_pct(y + o, &t.kinetic_energy[k]);
                put_pct(y + o + 4, &t.height[k]);
                y[o + 8] = t.reach_probability[k];
            }
            put_pct(y + o, &t.runout_x);
            put_pct(y + o + 4, &t.rebound_height);
            rf_traj_stats_free(&t);
        }
        rf_traj_ensemble_free(&e);
    }
    rf_traj_spec_free(&s);
    return st;
}

static void traj_model_destroy(void *vctx)
{
    traj_model_ctx *c = vctx;
    if (!c)
        return;
    for (size_t i = 0; i < c->n_params; i++)
        free(c->paths[i]);
    free(c->paths);
    traj_impact_table_free(c->table);
    rf_traj_spec_free(&c->spec);
    free(c);
}

/* The impact table depends on the block's radius and density, the impact
 * friction and the solver settings: shared by all evaluations unless a
 * parameter is bound to one of them. */
static rf_status share_table(traj_model_ctx *c, rf_error *err)
{
    if (c->spec.law != RF_BOUNCE_IMPACT_MODEL)
        return RF_OK;
    for (size_t i = 0; i < c->n_params; i++)
        if (!strncmp(c->paths[i], "block.", 6) || strstr(c->paths[i], ".friction_angle"))
            return RF_OK; /* rebuilt at every evaluation */
    return traj_impact_table_build(&c->spec, (traj_impact_table **)&c->table, err);
}

static rf_status init_outputs(rf_model *m, const rf_traj_spec *s, rf_error *err)
{
    size_t n = n_outputs_for(s->n_collectors), o = 0;
    char **names = calloc(n, sizeof *names);
    const char **units = calloc(n, sizeof *units);
    rf_status st = names && units ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory");
    char buf[300];
    for (size_t k = 0; k < s->n_collectors && st == RF_OK; k++) {
        for (int q = 0; q < 8; q++, o++) {
            snprintf(buf, sizeof buf, "%s_%s_%s", s->collectors[k].name, q < 4 ? "ke" : "height", pct_names[q % 4]);
            names[o] = rf_strdup(buf), units[o] = q < 4 ? "J" : "m";
        }
        snprintf(buf, sizeof buf, "%s_reach_probability", s->collectors[k].name);
        names[o] = rf_strdup(buf), units[o++] = "";
    }
    for (int q = 0; q < 8 && st == RF_OK; q++, o++) {
        snprintf(buf, sizeof buf, "%s_%s", q < 4 ? "runout" : "rebound_height", pct_names[q % 4]);
        names[o] = rf_strdup(buf), units[o] = "m";
    }
    for (size_t k = 0; k < n && st == RF_OK; k++)
        if (!names[k])
            st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (st == RF_OK)
        st = rf_model_init_outputs(m, n, (const char *const *)names, units, err);
    for (size_t k = 0; names && k < n; k++)
        free(names[k]);
    free(names);
    free(units);
    return st;
}

static rf_status set_identity(rf_model *m, const traj_model_ctx *c, rf_error *err)
{
    char buf[2048];
    int len = snprintf(buf, sizeof buf, "trajectory: file=%s samples=%zu seed=%llu lhs=%d bind=",
                       c->spec.file ? c->spec.file : "?", c->spec.samples, (unsigned long long)c->spec.seed,
                       c->spec.lhs);
    for (size_t i = 0; i < c->n_params && len > 0 && (size_t)len < sizeof buf; i++)
        len += snprintf(buf + len, sizeof buf - (size_t)len, "%s%s", i ? "," : "", c->paths[i]);
    return rf_model_set_identity(m, buf, err);
}

rf_status rf_traj_model_create(const rf_traj_spec *spec, size_t n_params, const char *const *param_names,
                               const char *const *bind_paths, rf_model *model, rf_error *err)
{
    memset(model, 0, sizeof *model);
    traj_model_ctx *c = calloc(1, sizeof *c);
    if (!c)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_status st = rf_traj_spec_copy(spec, &c->spec, err);
    if (st != RF_OK) {
        free(c);
        return st;
    }
    c->paths = calloc(n_params ? n_params : 1, sizeof *c->paths);
    if (!c->paths)
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < n_params && st == RF_OK; i++) {
        c->n_params = i + 1;
        if (!rf_traj_spec_field(&c->spec, bind_paths[i]))
            st = rf_fail(err, RF_EINVAL, "parameter %s: '%s' is not a numeric input of the trajectory file",
                         param_names[i], bind_paths[i]);
        else if (!(c->paths[i] = rf_strdup(bind_paths[i])))
            st = rf_fail(err, RF_ENOMEM, "out of memory");
    }
    model->n_inputs = n_params;
    model->ctx = c;
    model->destroy = traj_model_destroy;
    model->eval = traj_model_eval;
    model->threads_per_eval = 1;
    if (st == RF_OK)
        st = share_table(c, err);
    if (st == RF_OK)
        st = init_outputs(model, &c->spec, err);
    if (st == RF_OK)
        st = set_identity(model, c, err);
    if (st != RF_OK)
        rf_model_free(model);
    return st;
}

rf_status traj_model_spec_at(const rf_model *m, const double *x, rf_traj_spec *spec, void **table, rf_error *err)
{
    if (m->eval != traj_model_eval)
        return rf_fail(err, RF_EINVAL, "not a trajectory model");
    const traj_model_ctx *c = m->ctx;
    rf_status st = rf_traj_spec_copy(&c->spec, spec, err);
    for (size_t i = 0; i < c->n_params && st == RF_OK; i++)
        *rf_traj_spec_field(spec, c->paths[i]) = x[i];
    *table = c->table;
    return st;
}
