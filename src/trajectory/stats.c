/* stats.c - statistics of an ensemble: percentiles (Hyndman & Fan type 7:
 * linear between order statistics, the default of R and NumPy) at the fixed
 * levels 50/95/99 and at the spec's `outputs.percentiles`, of the runout and
 * rebound height over all samples (on terrain also of the reach angle); the
 * runout histogram and P(runout > x);
 * and per collector the reach probability, the percentiles of the energies,
 * passing heights and speed over the samples that reached it, and the
 * exceedance probabilities of its thresholds over all samples. */
#include "trajectory/traj_internal.h"
#include "rockfuzz/terrain.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double default_levels[3] = {50, 95, 99};

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

rf_traj_percentiles rf_traj_percentiles_at(const double *v, size_t n, const double *levels, size_t n_levels)
{
    rf_traj_percentiles r = {NAN, NAN, NAN, NAN, NAN, 0, {0}, {0}};
    r.n = n_levels < RF_TRAJ_MAX_PERCENTILES ? n_levels : RF_TRAJ_MAX_PERCENTILES;
    for (size_t k = 0; k < r.n; k++)
        r.level[k] = levels[k], r.value[k] = NAN;
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
        for (size_t k = 0; k < r.n; k++)
            r.value[k] = quantile_sorted(s, m, r.level[k] / 100);
        r.max = s[m - 1];
        r.mean = sum / (double)m;
        if (!isfinite(r.mean)) { /* the sum overflowed: sum the values scaled by 1/m */
            r.mean = 0;
            for (size_t i = 0; i < m; i++)
                r.mean += s[i] / (double)m;
        }
    }
    free(s);
    return r;
}

rf_traj_percentiles rf_traj_percentiles_of(const double *v, size_t n)
{
    return rf_traj_percentiles_at(v, n, default_levels, 3);
}

void rf_traj_percentile_name(double level, char *buf, size_t size)
{
    snprintf(buf, size, "p%.10g", level);
    for (char *p = buf; *p; p++)
        if (*p == '.')
            *p = '_';
}

void rf_traj_histogram_of(const double *v, size_t n, size_t bins, rf_traj_histogram *h)
{
    memset(h, 0, sizeof *h);
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; i++)
        if (isfinite(v[i]))
            lo = fmin(lo, v[i]), hi = fmax(hi, v[i]);
    if (lo > hi)
        return; /* no finite value: no bin */
    h->bins = hi > lo ? (bins < 1 ? 1 : bins > RF_TRAJ_MAX_BINS ? RF_TRAJ_MAX_BINS : bins) : 1;
    for (size_t k = 0; k <= h->bins; k++)
        h->edge[k] = k == h->bins ? hi : lo + (hi - lo) * (double)k / (double)h->bins;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(v[i]))
            continue;
        size_t a = 0, b = h->bins - 1; /* the last bin whose lower edge is <= v */
        while (a < b) {
            size_t mid = (a + b + 1) / 2;
            if (h->edge[mid] <= v[i])
                a = mid;
            else
                b = mid - 1;
        }
        h->count[a]++, h->total++;
    }
}

void rf_traj_runout_histogram(const rf_traj_ensemble *e, size_t bins, rf_traj_histogram *h)
{
    rf_traj_histogram_of(e->runout_x, e->samples, bins, h);
}

void rf_traj_stats_free(rf_traj_stats *st)
{
    if (!st)
        return;
    free(st->collectors);
    memset(st, 0, sizeof *st);
}

/* Fraction of the n entries of v (NaN: not reached, never above) strictly above x. */
static double fraction_above(const double *v, size_t n, double x)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        k += v[i] > x;
    return n ? (double)k / (double)n : NAN;
}

/* Per-sample arrays of one collector (NaN where it was not reached). */
enum { Q_TOTAL, Q_TRANS, Q_ROT, Q_HLOW, Q_HCEN, Q_SPEED, NQ };

static void collector_stats(const rf_traj_ensemble *e, const rf_traj_spec *s, const rf_traj_outputs *o,
                            size_t c, double *q[NQ], rf_traj_collector_stats *cs)
{
    size_t N = e->samples, nc = e->n_collectors, m = 0;
    for (size_t i = 0; i < N; i++) {
        const rf_traj_crossing *x = &e->crossings[i * nc + c];
        double v[NQ] = {x->total_energy, x->translational_energy, x->rotational_energy, x->height_lowest,
                        x->height_centre, x->speed};
        m += x->reached != 0;
        for (int k = 0; k < NQ; k++)
            q[k][i] = x->reached ? v[k] : NAN;
    }
    cs->reach_probability = N ? (double)m / (double)N : NAN;
    rf_traj_percentiles *p[NQ] = {&cs->total_energy, &cs->translational_energy, &cs->rotational_energy,
                                  &cs->height_lowest, &cs->height_centre, &cs->speed};
    for (int k = 0; k < NQ; k++)
        *p[k] = rf_traj_percentiles_at(q[k], N, o->percentiles, o->n_percentiles);
    if (!s)
        return;
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own;
    size_t n = rf_traj_thresholds(&s->collectors[c], 0, t, &own);
    for (size_t k = 0; k < n; k++)
        cs->p_energy_above[k] = fraction_above(q[Q_TOTAL], N, t[k]);
    n = rf_traj_thresholds(&s->collectors[c], 1, t, &own);
    for (size_t k = 0; k < n; k++)
        cs->p_height_above[k] = fraction_above(q[Q_HLOW], N, t[k]);
}

size_t rf_traj_thresholds(const rf_traj_collector *c, int height, double *t, int *own)
{
    double barrier = height ? c->height : c->capacity;
    size_t n_user = height ? c->n_height_thresholds : c->n_energy_thresholds, n = 0;
    const double *user = height ? c->height_thresholds : c->energy_thresholds;
    *own = barrier > 0;
    if (*own)
        t[n++] = barrier;
    for (size_t k = 0; k < n_user && n < RF_TRAJ_MAX_THRESHOLDS; k++)
        t[n++] = user[k];
    return n;
}

/* The spec's outputs with its unset fields at their defaults (no spec: all defaults). */
static rf_traj_outputs effective_outputs(const rf_traj_spec *s)
{
    rf_traj_outputs o;
    memset(&o, 0, sizeof o);
    if (s)
        o = s->outputs;
    if (!o.n_percentiles) {
        o.n_percentiles = 3;
        memcpy(o.percentiles, default_levels, sizeof default_levels);
    }
    if (!o.runout_bins)
        o.runout_bins = 20;
    return o;
}

rf_status rf_traj_stats_compute_spec(const rf_traj_spec *s, const rf_traj_ensemble *e, rf_traj_stats *st,
                                     rf_error *err)
{
    memset(st, 0, sizeof *st);
    rf_traj_outputs o = effective_outputs(s);
    size_t N = e->samples, nc = e->n_collectors;
    st->samples = N, st->n_collectors = nc;
    for (size_t i = 0; i < N; i++) {
        st->stopped += e->state[i] == RF_TRAJ_STOPPED;
        st->exited += e->state[i] == RF_TRAJ_EXITED;
        st->step_limit += e->state[i] == RF_TRAJ_STEP_LIMIT;
    }
    st->runout_x = rf_traj_percentiles_at(e->runout_x, N, o.percentiles, o.n_percentiles);
    st->rebound_height = rf_traj_percentiles_at(e->rebound_height, N, o.percentiles, o.n_percentiles);
    for (size_t k = 0; k < o.n_runout_thresholds; k++)
        st->p_runout_above[k] = fraction_above(e->runout_x, N, o.runout_thresholds[k]);
    rf_traj_runout_histogram(e, o.runout_bins, &st->runout_histogram);
    st->reach_angle = rf_traj_percentiles_at(e->terrain ? e->terrain->reach_angle : NULL, e->terrain ? N : 0,
                                             o.percentiles, o.n_percentiles);
    st->collectors = calloc(nc ? nc : 1, sizeof *st->collectors);
    double *q[NQ], *buf = malloc((N ? N : 1) * NQ * sizeof *buf);
    if (!st->collectors || !buf) {
        free(buf);
        rf_traj_stats_free(st);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    for (int k = 0; k < NQ; k++)
        q[k] = buf + (size_t)k * (N ? N : 1);
    for (size_t c = 0; c < nc; c++)
        collector_stats(e, s, &o, c, q, &st->collectors[c]);
    free(buf);
    return RF_OK;
}

rf_status rf_traj_stats_compute(const rf_traj_ensemble *e, rf_traj_stats *st, rf_error *err)
{
    return rf_traj_stats_compute_spec(NULL, e, st, err);
}
