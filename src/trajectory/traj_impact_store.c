/* traj_impact_store.c - the impacts of the `impact_model` table kept in a
 * study's result store (store.sqlite, side rows: rf_model_side_store) instead
 * of the cache file: one row (v_n, theta, radius, R_n, R_t, spin) per impact
 * under the key "impact_model <setup identity>" (traj_impact_setup_key: the
 * solver, density, friction, FE refinement and the material's ground), so an
 * interrupted study resumes without recomputing and a second study on the
 * same store reuses them.  Every row read is checked as the cache file's are
 * (traj_impact_row_invalid; a second, different result for the same impact is
 * refused, an identical repeat kept once). */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double **memo;
    size_t *n, *cap;
    size_t first;             /* rows of *memo before the store's */
    const char *key;
    rf_error *err;
} reader;

static void store_key(const traj_impact_setup *s, char *key, size_t size)
{
    char id[300];
    traj_impact_setup_key(s, id, sizeof id);
    snprintf(key, size, "impact_model %s", id);
}

static rf_status add(void *u, const double *r)
{
    reader *c = u;
    const char *why = traj_impact_row_invalid(r);
    if (why)
        return rf_fail(c->err, RF_EIO, "result store: impact table row (v_n %g, theta %g, radius %g, R_n %g, R_t %g, "
                       "spin %g) of %s: %s; the store is damaged: remove the study folder's store.sqlite (--fresh "
                       "keeps the impacts)", r[0], r[1], r[2], r[3], r[4],
                       r[5], c->key, why);
    for (size_t k = c->first; k < *c->n; k++) {
        const double *m = *c->memo + 6 * k;
        if (m[0] == r[0] && m[1] == r[1] && m[2] == r[2])
            return memcmp(m, r, 6 * sizeof *r) == 0 ? RF_OK
                   : rf_fail(c->err, RF_EIO, "result store: the impact v_n %g m/s, theta %g rad, radius %g m of %s "
                             "has two different results; the store is damaged: remove the study folder's store.sqlite "
                             "(--fresh keeps the impacts)", r[0], r[1], r[2],
                             c->key);
    }
    if (*c->n == *c->cap) {
        size_t cap = *c->cap ? 2 * *c->cap : 256;
        double *m = realloc(*c->memo, cap * 6 * sizeof *m);
        if (!m)
            return rf_fail(c->err, RF_ENOMEM, "out of memory reading the impact table from the store");
        *c->memo = m, *c->cap = cap;
    }
    memcpy(*c->memo + 6 * (*c->n)++, r, 6 * sizeof *r);
    return RF_OK;
}

static rf_status load(void *user, const traj_impact_setup *s, double **memo, size_t *n, size_t *cap, rf_error *err)
{
    const rf_model_side_store *side = user;
    char key[400];
    store_key(s, key, sizeof key);
    reader c = {memo, n, cap, *n, key, err};
    return side->each(side->user, key, 6, add, &c, err);
}

static rf_status put(void *user, const traj_impact_setup *s, const double row[6], rf_error *err)
{
    const rf_model_side_store *side = user;
    char key[400];
    store_key(s, key, sizeof key);
    const char *why = traj_impact_row_invalid(row); /* never store what the next read would refuse */
    if (why)
        return rf_fail(err, RF_EMODEL, "impact model at v_n %g m/s, incidence %g rad, radius %g m: R_n %g, R_t %g, "
                       "spin %g: %s", row[0], row[1], row[2], row[3], row[4], row[5], why);
    return side->put(side->user, key, row, 6, err);
}

void traj_impact_store_from_side(const rf_model_side_store *side, traj_impact_store *out)
{
    *out = (traj_impact_store){(void *)side, load, put};
}
