/* stats.c - statistics of an ensemble: percentiles (Hyndman & Fan type 7:
 * linear between order statistics, the default of R and NumPy) of the runout
 * and rebound height over all samples, and per collector the reach
 * probability and the percentiles of energy (translational + rotational),
 * passing height and speed over the samples that reached it. */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double quantile_sorted(const double *v, size_t n, double p)
{
    double h = (double)(n - 1) * p;
    size_t lo = (size_t)floor(h);
    if (lo + 1 >= n)
        return v[n - 1];
    return v[lo] + (h - (double)lo) * (v[lo + 1] - v[lo]);
}

rf_traj_percentiles rf_traj_percentiles_of(const double *v, size_t n)
{
    rf_traj_percentiles r = {NAN, NAN, NAN, NAN, NAN};
    double *s = malloc((n ? n : 1) * sizeof *s);
    if (!s)
        return r;
    size_t m = 0;
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(v[i]))
            s[m++] = v[i], sum += v[i];
    if (m) {
        qsort(s, m, sizeof *s, cmp_double);
        r.p50 = quantile_sorted(s, m, 0.50);
        r.p95 = quantile_sorted(s, m, 0.95);
        r.p99 = quantile_sorted(s, m, 0.99);
        r.max = s[m - 1];
        r.mean = sum / (double)m;
    }
    free(s);
    return r;
}

void rf_traj_stats_free(rf_traj_stats *st)
{
    if (!st)
        return;
    free(st->reach_probability);
    free(st->kinetic_energy);
    free(st->height);
    free(st->speed);
    memset(st, 0, sizeof *st);
}

rf_status rf_traj_stats_compute(const rf_traj_ensemble *e, rf_traj_stats *st, rf_error *err)
{
    memset(st, 0, sizeof *st);
    size_t N = e->samples, nc = e->n_collectors;
    st->n_collectors = nc;
    for (size_t i = 0; i < N; i++) {
        st->stopped += e->state[i] == RF_TRAJ_STOPPED;
        st->exited += e->state[i] == RF_TRAJ_EXITED;
        st->step_limit += e->state[i] == RF_TRAJ_STEP_LIMIT;
    }
    st->runout_x = rf_traj_percentiles_of(e->runout_x, N);
    st->rebound_height = rf_traj_percentiles_of(e->rebound_height, N);
    st->reach_probability = calloc(nc ? nc : 1, sizeof(double));
    st->kinetic_energy = calloc(nc ? nc : 1, sizeof(rf_traj_percentiles));
    st->height = calloc(nc ? nc : 1, sizeof(rf_traj_percentiles));
    st->speed = calloc(nc ? nc : 1, sizeof(rf_traj_percentiles));
    double *ke = malloc((N ? N : 1) * sizeof *ke), *h = malloc((N ? N : 1) * sizeof *h),
           *sp = malloc((N ? N : 1) * sizeof *sp);
    if (!st->reach_probability || !st->kinetic_energy || !st->height || !st->speed || !ke || !h || !sp) {
        free(ke), free(h), free(sp);
        rf_traj_stats_free(st);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    for (size_t c = 0; c < nc; c++) {
        size_t m = 0;
        for (size_t i = 0; i < N; i++) {
            const rf_traj_crossing *x = &e->crossings[i * nc + c];
            if (!x->reached)
                continue;
            ke[m] = x->kinetic_energy + x->rotational_energy;
            h[m] = x->height;
            sp[m++] = x->speed;
        }
        st->reach_probability[c] = N ? (double)m / (double)N : NAN;
        st->kinetic_energy[c] = rf_traj_percentiles_of(ke, m);
        st->height[c] = rf_traj_percentiles_of(h, m);
        st->speed[c] = rf_traj_percentiles_of(sp, m);
    }
    free(ke), free(h), free(sp);
    return RF_OK;
}
