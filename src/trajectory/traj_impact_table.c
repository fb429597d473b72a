/* traj_impact_table.c - R_n, R_t and the spin ratio of an impact model
 * tabulated over normal speed v_n in bounce.impact.speeds (default [0.25, 40] m/s) and incidence theta in
 * [0, max_incidence] (default 80 deg, the 3D FE model's limit; from the normal) on a tensor grid refined adaptively: an
 * interval (in v_n or theta) is halved while, at its midpoint, bilinear
 * interpolation from the current nodes misses the model by more than the
 * tolerance (absolute, on R_n and R_t) on any grid line.  After the last
 * refinement every cell centre is evaluated as an independent check: the
 * largest |interpolated - model| there is the reported error estimate.
 * Outside the box the table is clamped.  Built once per run (per world).
 * A watched build (traj_impact_table_build_watched) checks a stop flag before
 * every impact it computes (RF_EINTERRUPTED; the impacts computed so far stay
 * in the cache file) and reports each one to a progress callback. */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#define MAX_NODES 65

struct traj_impact_table {
    size_t nv, nt;
    double v[MAX_NODES], th[MAX_NODES];
    double *c;                 /* [(i * nt + j) * 3 + q]: R_n, R_t, spin */
    size_t evaluations;        /* impacts computed by the model for this table */
    size_t from_cache;         /* impacts of the table taken from bounce.impact.cache */
    double error_estimate;
};

typedef struct {
    traj_impact_setup setup;
    traj_impact_table *t;
    rf_error *err;
    double *memo;             /* (v, theta, R_n, R_t, spin) of every impact computed */
    size_t n_memo, cap_memo;
    size_t n_cached;          /* the first n_cached rows of memo came from the cache file */
    unsigned char *hit;       /* n_cached flags: the row was used by the table */
    const char *cache;        /* bounce.impact.cache or NULL */
    const traj_table_watch *watch; /* stop flag and progress, or NULL */
} builder;

/* One impact of the model, computed once (the grid is refilled after each refinement). */
static rf_status eval(builder *b, double v, double th, double *c)
{
    for (size_t k = 0; k < b->n_memo; k++)
        if (b->memo[5 * k] == v && b->memo[5 * k + 1] == th) {
            memcpy(c, &b->memo[5 * k + 2], 3 * sizeof *c);
            if (k < b->n_cached && b->hit && !b->hit[k]) /* a cache hit, counted once per impact */
                b->hit[k] = 1, b->t->from_cache++;
            return RF_OK;
        }
    const traj_table_watch *w = b->watch;
    rf_status st = w && w->stop && atomic_load(w->stop) ? RF_EINTERRUPTED : RF_OK;
    if (st == RF_OK)
        st = traj_impact_coefficients(&b->setup, v, th, &c[0], &c[1], &c[2], b->err);
    if (st == RF_EINTERRUPTED) /* before this impact or inside it (an FE run stops between two steps) */
        return rf_fail(b->err, RF_EINTERRUPTED, "interrupted while building the impact table after %zu impact%s of "
                       "the impact model%s%s", b->t->evaluations, b->t->evaluations == 1 ? "" : "s",
                       b->cache ? "; they are kept in " : "", b->cache ? b->cache : "");
    if (st != RF_OK)
        return st;
    b->t->evaluations++;
    if (w && w->progress)
        w->progress(w->user, b->t->evaluations, b->t->from_cache, b->t->nv, b->t->nt);
    if (b->n_memo == b->cap_memo) {
        size_t cap = b->cap_memo ? 2 * b->cap_memo : 256;
        double *m = realloc(b->memo, cap * 5 * sizeof *m);
        if (!m)
            return RF_OK; /* only the memo is lost */
        b->memo = m, b->cap_memo = cap;
    }
    double *m = &b->memo[5 * b->n_memo++];
    m[0] = v, m[1] = th, memcpy(m + 2, c, 3 * sizeof *c);
    traj_impact_cache_append(b->cache, &b->setup, m, 1); /* at once: an interrupted build keeps its impacts */
    return RF_OK;
}

static size_t locate(const double *x, size_t n, double v, double *f)
{
    if (v <= x[0]) {
        *f = 0;
        return 0;
    }
    if (v >= x[n - 1]) {
        *f = 1;
        return n - 2;
    }
    size_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (x[mid] <= v) lo = mid; else hi = mid;
    }
    *f = (v - x[lo]) / (x[lo + 1] - x[lo]);
    return lo;
}

static void interp(const traj_impact_table *t, double v, double th, double *c)
{
    double fv, ft;
    size_t i = locate(t->v, t->nv, v, &fv), j = locate(t->th, t->nt, th, &ft);
    for (int q = 0; q < 3; q++) {
        double a = t->c[(i * t->nt + j) * 3 + q], b = t->c[(i * t->nt + j + 1) * 3 + q];
        double d = t->c[((i + 1) * t->nt + j) * 3 + q], e = t->c[((i + 1) * t->nt + j + 1) * 3 + q];
        c[q] = (1 - fv) * ((1 - ft) * a + ft * b) + fv * ((1 - ft) * d + ft * e);
    }
}

void traj_impact_table_eval(const traj_impact_table *t, double vn, double theta, double *R_n, double *R_t,
                            double *spin_ratio)
{
    double c[3];
    interp(t, vn, theta, c);
    *R_n = fmin(fmax(c[0], 0), 1), *R_t = fmin(fmax(c[1], 0), 1), *spin_ratio = fmax(c[2], 0);
}

/* Evaluate every node (known ones come from the memo). */
static rf_status fill(builder *b)
{
    traj_impact_table *t = b->t;
    free(t->c);
    t->c = malloc(t->nv * t->nt * 3 * sizeof *t->c);
    if (!t->c)
        return rf_fail(b->err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < t->nv; i++)
        for (size_t j = 0; j < t->nt; j++) {
            rf_status st = eval(b, t->v[i], t->th[j], &t->c[(i * t->nt + j) * 3]);
            if (st != RF_OK)
                return st;
        }
    return RF_OK;
}

static void insert(double *x, size_t *n, size_t at, double v)
{
    memmove(x + at + 2, x + at + 1, (*n - at - 1) * sizeof *x);
    x[at + 1] = v;
    (*n)++;
}

/* Midpoint errors along one axis; split[k] = 1 for the intervals to halve. */
static rf_status refine_axis(builder *b, int axis, double tol, int *split, int *any)
{
    traj_impact_table *t = b->t;
    size_t n = axis ? t->nt : t->nv, m = axis ? t->nv : t->nt;
    const double *x = axis ? t->th : t->v, *y = axis ? t->v : t->th;
    for (size_t k = 0; k + 1 < n; k++) {
        split[k] = 0;
        for (size_t l = 0; l < m && !split[k]; l++) {
            double mid = 0.5 * (x[k] + x[k + 1]), c[3], p[3];
            double v = axis ? y[l] : mid, th = axis ? mid : y[l];
            rf_status st = eval(b, v, th, c);
            if (st != RF_OK)
                return st;
            interp(t, v, th, p);
            split[k] = fabs(c[0] - p[0]) > tol || fabs(c[1] - p[1]) > tol;
        }
        *any |= split[k];
    }
    return RF_OK;
}

static rf_status refine(builder *b, double tol)
{
    traj_impact_table *t = b->t;
    for (int round = 0; round < 8; round++) {
        int split[2][MAX_NODES], any = 0;
        rf_status st;
        if ((st = refine_axis(b, 0, tol, split[0], &any)) != RF_OK || (st = refine_axis(b, 1, tol, split[1], &any)))
            return st;
        if (!any)
            return RF_OK;
        for (int axis = 0; axis < 2; axis++) {
            double *x = axis ? t->th : t->v;
            size_t *n = axis ? &t->nt : &t->nv, n0 = *n;
            for (size_t k = n0 - 1; k-- > 0;)
                if (split[axis][k] && *n < MAX_NODES)
                    insert(x, n, k, 0.5 * (x[k] + x[k + 1]));
        }
        if ((st = fill(b)) != RF_OK)
            return st;
    }
    return RF_OK;
}

/* The error estimate: the largest miss at the cell centres of the final grid. */
static rf_status estimate_error(builder *b)
{
    traj_impact_table *t = b->t;
    t->error_estimate = 0;
    for (size_t i = 0; i + 1 < t->nv; i++)
        for (size_t j = 0; j + 1 < t->nt; j++) {
            double v = 0.5 * (t->v[i] + t->v[i + 1]), th = 0.5 * (t->th[j] + t->th[j + 1]), c[3], p[3];
            rf_status st = eval(b, v, th, c);
            if (st != RF_OK)
                return st;
            interp(t, v, th, p);
            t->error_estimate = fmax(t->error_estimate, fmax(fabs(c[0] - p[0]), fabs(c[1] - p[1])));
        }
    return RF_OK;
}

rf_status traj_impact_table_build(const rf_traj_spec *spec, traj_impact_table **out, rf_error *err)
{
    return traj_impact_table_build_watched(spec, NULL, out, err);
}

rf_status traj_impact_table_build_watched(const rf_traj_spec *spec, const traj_table_watch *watch,
                                          traj_impact_table **out, rf_error *err)
{
    *out = NULL;
    traj_impact_table *t = calloc(1, sizeof *t);
    if (!t)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    builder b = {{0}, t, err, NULL, 0, 0, 0, NULL, spec->impact_cache, watch};
    rf_status st = traj_impact_setup_init(&b.setup, spec, err);
    b.setup.stop = watch ? watch->stop : NULL;
    t->nv = t->nt = 5;
    for (size_t i = 0; i < 5; i++) { /* v_n geometric, theta uniform */
        t->v[i] = spec->impact_speed_min * pow(spec->impact_speed_max / spec->impact_speed_min, (double)i / 4);
        t->th[i] = spec->impact_max_incidence * (double)i / 4;
    }
    if (st == RF_OK)
        st = traj_impact_cache_load(spec->impact_cache, &b.setup, &b.memo, &b.n_memo, &b.cap_memo, err);
    b.n_cached = b.n_memo;
    if (st == RF_OK && b.n_cached && !(b.hit = calloc(b.n_cached, 1)))
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (st == RF_OK)
        st = fill(&b);
    if (st == RF_OK)
        st = refine(&b, spec->impact_tolerance);
    if (st == RF_OK)
        st = estimate_error(&b);
    free(b.memo);
    free(b.hit);
    if (st != RF_OK) {
        traj_impact_table_free(t);
        return st;
    }
    *out = t;
    return RF_OK;
}

void traj_impact_table_free(traj_impact_table *t)
{
    if (!t)
        return;
    free(t->c);
    free(t);
}

void traj_impact_table_info(const traj_impact_table *t, size_t *nv, size_t *nt, size_t *evaluations,
                            size_t *from_cache, double *error_estimate)
{
    *nv = t ? t->nv : 0, *nt = t ? t->nt : 0;
    *from_cache = t ? t->from_cache : 0;
    *evaluations = t ? t->evaluations : 0;
    *error_estimate = t ? t->error_estimate : NAN;
}
