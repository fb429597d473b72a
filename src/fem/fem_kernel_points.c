/* fem_kernel_points.c - the integration-point material kernel of the
 * axisymmetric quad (fem_kernel.h): strain at each Gauss point from B ue,
 * the point law's stress update from the strain increment, internal force
 * sum_q w_q B_q^T sigma_q; trial values become committed in commit().  And
 * the linear-elastic point law, which makes this kernel the reference for
 * elasto-plastic laws plugged in the same way. */
#include "fem_internal.h"
#include "fem_kernel.h"

#include <stdlib.h>
#include <string.h>

#define NQ 4 /* Gauss points per element */
#define NC 4 /* strain components */

typedef struct {
    fem_point_law law;
    double *B;      /* 4 x 32 per element */
    double *w;      /* 4 per element */
    double *eps, *sig, *var;          /* committed, per point */
    double *eps_t, *sig_t, *var_t;    /* trial of the last forces() */
} points_data;

static void points_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    points_data *d = k->data;
    const int ns = d->law.nstate;
    for (long e = e0; e < e1; e++, ue += 8, fe += 8) {
        const long le = e - k->first;
        double y[8] = {0};
        for (int q = 0; q < NQ; q++) {
            const long p = NQ * le + q;
            const double *B = d->B + 32 * p;
            double *eps = d->eps_t + NC * p, *sig = d->sig_t + NC * p, deps[NC];
            for (int i = 0; i < NC; i++) {
                double s = 0;
                for (int j = 0; j < 8; j++)
                    s += B[8 * i + j] * ue[j];
                eps[i] = s;
                deps[i] = s - d->eps[NC * p + i];
            }
            d->law.update(d->law.params, deps, d->sig + NC * p, d->var + (size_t)ns * p, sig,
                          d->var_t + (size_t)ns * p);
            for (int j = 0; j < 8; j++)
                y[j] += d->w[p] * (B[j] * sig[0] + B[8 + j] * sig[1] + B[16 + j] * sig[2] + B[24 + j] * sig[3]);
        }
        memcpy(fe, y, sizeof y);
    }
}

static void points_commit(fem_kernel *k)
{
    points_data *d = k->data;
    const size_t np = (size_t)NQ * (size_t)k->count;
    memcpy(d->eps, d->eps_t, np * NC * sizeof(double));
    memcpy(d->sig, d->sig_t, np * NC * sizeof(double));
    if (d->law.nstate)
        memcpy(d->var, d->var_t, np * (size_t)d->law.nstate * sizeof(double));
}

static void points_destroy(fem_kernel *k)
{
    points_data *d = k->data;
    if (d) {
        free(d->B), free(d->w), free(d->eps), free(d->sig), free(d->var), free(d->eps_t), free(d->sig_t);
        free(d->var_t);
    }
    free(d);
    k->data = NULL;
}

static const fem_kernel_ops points_ops = {"integration points (axisymmetric quad)", points_forces, NULL,
                                          points_commit, points_destroy, NULL};

rf_status fem_kernel_points_axi(fem_kernel *k, long first, long count, const double *r, const double *z,
                                const int *conn, const fem_point_law *law, rf_error *err)
{
    if (law->ncomp != NC)
        return rf_fail(err, RF_EINVAL, "fem: the point law '%s' has %d strain components; the axisymmetric quad "
                       "needs %d", law->name, law->ncomp, NC);
    points_data *d = calloc(1, sizeof *d);
    const size_t np = (size_t)NQ * (size_t)count, ns = (size_t)(law->nstate > 0 ? law->nstate : 1);
    k->ops = &points_ops, k->first = first, k->count = count, k->ndofe = 8, k->data = d;
    if (!d)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    d->law = *law;
    d->B = malloc(np * 32 * sizeof *d->B), d->w = malloc(np * sizeof *d->w);
    d->eps = calloc(np * NC, sizeof *d->eps), d->sig = calloc(np * NC, sizeof *d->sig);
    d->eps_t = calloc(np * NC, sizeof *d->eps_t), d->sig_t = calloc(np * NC, sizeof *d->sig_t);
    d->var = calloc(np * ns, sizeof *d->var), d->var_t = calloc(np * ns, sizeof *d->var_t);
    if (!d->B || !d->w || !d->eps || !d->sig || !d->eps_t || !d->sig_t || !d->var || !d->var_t)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory for %ld integration points", (long)np);
    for (long e = 0; e < count; e++) {
        const int *c = conn + 4 * (first + e);
        double re[4], ze[4];
        for (int a = 0; a < 4; a++)
            re[a] = r[c[a]], ze[a] = z[c[a]];
        fem_element_points(re, ze, (double(*)[32])(d->B + 128 * e), d->w + NQ * e);
    }
    return RF_OK;
}

static void linear_update(const void *params, const double *deps, const double *sig_n, const double *state_n,
                          double *sig, double *state)
{
    (void)state_n, (void)state;
    const fem_lame *p = params;
    const double tr = deps[0] + deps[1] + deps[2];
    for (int i = 0; i < 3; i++)
        sig[i] = sig_n[i] + p->lam * tr + 2 * p->mu * deps[i];
    sig[3] = sig_n[3] + p->mu * deps[3];
}

fem_point_law fem_point_law_linear(const fem_lame *lame)
{
    fem_point_law law = {"linear elastic", NC, 0, linear_update, lame};
    return law;
}
