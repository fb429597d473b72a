/* traj_impact_surrogate.c - the impact model over its material parameters:
 * when a study binds inputs of a material's impact model
 * (materials.NAME.impact.layer_E, ...), the tables of traj_impact_table.c
 * (adaptive over v_n, incidence and radius) are built at the nodes of a
 * tensor grid over the bound parameters' box (their supports), refined
 * dyadically per axis, and a TM point's table is the multilinear blend of the
 * 2^d tables at the corners of its cell (traj_impact_table_blend).
 *
 * Why this and not tables at the TM's own abscissae: the general TM at m
 * levels evaluates every combination of 2m - 1 values per input, so exact
 * tables at its abscissae cost (2m - 1)^d tables (81 at m = 5, d = 2), each a
 * full adaptive FE table; R_n and R_t are smooth in the soil's modulus and
 * friction angle, so a grid of 3 nodes per axis refined where needed costs 9
 * to ~25 tables, and its error is measured, not assumed.  Piecewise
 * (multi)linear because it never overshoots (R_n stays in [0, 1] between
 * admissible nodes) and its hierarchical error (the miss at a midpoint) is
 * what drives the refinement, as on the table's own axes.
 *
 * Refinement: an interval of an axis is halved while, on any grid line of
 * the other axes' nodes, the table built at its midpoint differs from the mean
 * of the two end tables by more than bounce.impact.tolerance in R_n or R_t at
 * the probe points (7 speeds x 5 incidences x the radius range's ends, every
 * material).  At most SUR_ROUNDS rounds, SUR_MAX_NODES nodes per axis.
 *
 * Error: after the build, `checks` points drawn uniformly in the whole box
 * (v_n log-uniform over bounce.impact.speeds, incidence, radius and the bound
 * parameters; a fixed sequence, never a node) are evaluated by the impact
 * model itself and by the surrogate: the largest |dR_n| and |dR_t| are the
 * reported error (it includes the (v_n, theta, r) tables' own error).
 *
 * Every impact goes through the watch's store (a study's store.sqlite), keyed
 * by the material's full ground: a resumed or second study recomputes nothing,
 * the check runs included. */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"
#include "trajectory/traj_impact_surrogate.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SUR_MAX_DIM 4
#define SUR_MAX_NODES 17
#define SUR_ROUNDS 4
#define SUR_SEED 0x5eed50117ULL /* the check points' sequence: the same in every run (store reuse) */

typedef struct {
    double x[SUR_MAX_DIM];
    traj_impact_table *t;
} sur_point;

struct traj_impact_surrogate {
    rf_traj_spec spec;
    size_t d, checks;
    char *paths[SUR_MAX_DIM];
    double lo[SUR_MAX_DIM], hi[SUR_MAX_DIM];
    size_t n[SUR_MAX_DIM];
    double x[SUR_MAX_DIM][SUR_MAX_NODES];
    sur_point *pool;          /* every table built (nodes and tested midpoints) */
    size_t n_pool, cap_pool;
    traj_impact_table **lent; /* blends handed out by traj_impact_surrogate_table_lent */
    size_t n_lent;
    pthread_mutex_t lock;
    int built;
    rf_status build_status;
    rf_error build_err;
    traj_impact_surrogate_info info;
};

typedef struct {
    traj_impact_surrogate *s;
    const traj_table_watch *w;
    FILE *log;
    rf_error *err;
} sur_build;

rf_status traj_impact_surrogate_create(const rf_traj_spec *spec, size_t d, const char *const *paths, const double *lo,
                                       const double *hi, size_t checks, traj_impact_surrogate **out, rf_error *err)
{
    *out = NULL;
    if (d == 0 || d > SUR_MAX_DIM)
        return rf_fail(err, RF_EINVAL, "impact surrogate: %zu bound impact-model inputs; it takes 1 to %d", d,
                       SUR_MAX_DIM);
    for (size_t a = 0; a < d; a++)
        if (!(isfinite(lo[a]) && isfinite(hi[a]) && lo[a] <= hi[a]))
            return rf_fail(err, RF_EINVAL, "impact surrogate: %s: range [%g, %g] is not an interval", paths[a], lo[a],
                           hi[a]);
    traj_impact_surrogate *s = calloc(1, sizeof *s);
    if (!s)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_status st = rf_traj_spec_copy(spec, &s->spec, err);
    if (st != RF_OK) {
        free(s);
        return st;
    }
    pthread_mutex_init(&s->lock, NULL);
    s->d = d, s->checks = checks;
    for (size_t a = 0; a < d && st == RF_OK; a++) {
        if (!(s->paths[a] = rf_strdup(paths[a])))
            st = rf_fail(err, RF_ENOMEM, "out of memory");
        s->lo[a] = lo[a], s->hi[a] = hi[a];
        size_t n0 = spec->impact_surrogate_nodes >= 2 && spec->impact_surrogate_nodes <= SUR_MAX_NODES
                        ? spec->impact_surrogate_nodes : 3; /* bounce.impact.surrogate_nodes */
        s->n[a] = hi[a] > lo[a] ? n0 : 1; /* a crisp input: one node */
        for (size_t k = 0; k < s->n[a]; k++)
            s->x[a][k] = s->n[a] == 1 ? lo[a] : lo[a] + (hi[a] - lo[a]) * (double)k / (double)(n0 - 1);
    }
    if (st != RF_OK) {
        traj_impact_surrogate_free(s);
        return st;
    }
    *out = s;
    return RF_OK;
}

void traj_impact_surrogate_free(traj_impact_surrogate *s)
{
    if (!s)
        return;
    for (size_t k = 0; k < s->n_lent; k++)
        traj_impact_table_free(s->lent[k]);
    free(s->lent);
    for (size_t k = 0; k < s->n_pool; k++)
        traj_impact_table_free(s->pool[k].t);
    free(s->pool);
    for (size_t a = 0; a < s->d; a++)
        free(s->paths[a]);
    pthread_mutex_destroy(&s->lock);
    rf_traj_spec_free(&s->spec);
    free(s);
}

/* The table already built at x, or NULL. */
static traj_impact_table *pooled(const traj_impact_surrogate *s, const double *x)
{
    for (size_t k = 0; k < s->n_pool; k++)
        if (!memcmp(s->pool[k].x, x, s->d * sizeof *x))
            return s->pool[k].t;
    return NULL;
}

/* The spec with the bound inputs at x (a copy, freed by the caller). */
static rf_status spec_at(const traj_impact_surrogate *s, const double *x, rf_traj_spec *out, rf_error *err)
{
    rf_status st = rf_traj_spec_copy(&s->spec, out, err);
    for (size_t a = 0; a < s->d && st == RF_OK; a++)
        if (!rf_traj_spec_set(out, s->paths[a], x[a]))
            st = rf_fail(err, RF_EINVAL, "impact surrogate: %s is not an input of the trajectory file", s->paths[a]);
    return st;
}

/* The (v_n, theta, radius) table at parameter point x: built once, kept in the pool. */
static rf_status table_at(sur_build *b, const double *x, traj_impact_table **out)
{
    traj_impact_surrogate *s = b->s;
    if ((*out = pooled(s, x)))
        return RF_OK;
    if (s->n_pool == s->cap_pool) {
        size_t cap = s->cap_pool ? 2 * s->cap_pool : 16;
        sur_point *p = realloc(s->pool, cap * sizeof *p);
        if (!p)
            return rf_fail(b->err, RF_ENOMEM, "out of memory");
        s->pool = p, s->cap_pool = cap;
    }
    rf_traj_spec at;
    memset(&at, 0, sizeof at);
    rf_status st = spec_at(s, x, &at, b->err);
    if (st == RF_OK)
        st = traj_impact_table_build_watched(&at, b->w, out, b->err);
    rf_traj_spec_free(&at);
    if (st != RF_OK)
        return rf_error_prefix(b->err, "impact surrogate: the table at %s = %g%s", s->paths[0], x[0],
                               s->d > 1 ? " (and the other bound inputs)" : "");
    sur_point *p = &s->pool[s->n_pool++];
    memset(p->x, 0, sizeof p->x);
    memcpy(p->x, x, s->d * sizeof *x), p->t = *out;
    size_t nv, nt, computed, cached;
    double e;
    traj_impact_table_info(*out, &nv, &nt, &computed, &cached, &e);
    s->info.tables++, s->info.computed += computed, s->info.from_store += cached;
    s->info.table_error = fmax(s->info.table_error, e);
    if (b->log) {
        fprintf(b->log, "Impact surrogate: table %zu at", s->info.tables);
        for (size_t a = 0; a < s->d; a++)
            fprintf(b->log, " %s = %g", s->paths[a], x[a]);
        fprintf(b->log, ": %zu impacts computed, %zu taken from the store\n", computed, cached);
        fflush(b->log);
    }
    return RF_OK;
}

/* The largest |R_n| or |R_t| difference of table t and the mean of u and v at the probe points. */
static double probe_miss(const rf_traj_spec *spec, const traj_impact_table *t, const traj_impact_table *u,
                         const traj_impact_table *v)
{
    double rlo, rhi, miss = 0;
    traj_impact_radius_range(spec, &rlo, &rhi);
    size_t nm = spec->n_materials ? spec->n_materials : 1;
    for (size_t m = 0; m < nm; m++)
        for (int i = 0; i < 7; i++)
            for (int j = 0; j < 5; j++)
                for (int l = 0; l < 2; l++) {
                    double vn = spec->impact_speed_min * pow(spec->impact_speed_max / spec->impact_speed_min, i / 6.0);
                    double th = spec->impact_max_incidence * j / 4.0, r = l ? rhi : rlo, a[3], b[3], c[3];
                    traj_impact_table_lookup(t, m, r, vn, th, &a[0], &a[1], &a[2]);
                    traj_impact_table_lookup(u, m, r, vn, th, &b[0], &b[1], &b[2]);
                    traj_impact_table_lookup(v, m, r, vn, th, &c[0], &c[1], &c[2]);
                    miss = fmax(miss, fmax(fabs(a[0] - 0.5 * (b[0] + c[0])), fabs(a[1] - 0.5 * (b[1] + c[1]))));
                }
    return miss;
}

/* The node point of grid line `line` (over every axis but `axis`, in axis order) at node k of `axis`. */
static void line_point(const traj_impact_surrogate *s, size_t axis, size_t line, size_t k, double *x)
{
    for (size_t a = s->d; a-- > 0;) {
        if (a == axis) {
            x[a] = s->x[a][k];
            continue;
        }
        x[a] = s->x[a][line % s->n[a]];
        line /= s->n[a];
    }
}

static size_t lines_of(const traj_impact_surrogate *s, size_t axis)
{
    size_t n = 1;
    for (size_t a = 0; a < s->d; a++)
        n *= a == axis ? 1 : s->n[a];
    return n;
}

/* split[k] = 1 for each interval k of `axis` whose midpoint misses on some line. */
static rf_status refine_axis(sur_build *b, size_t axis, int *split, int *any)
{
    traj_impact_surrogate *s = b->s;
    for (size_t k = 0; k + 1 < s->n[axis]; k++) {
        split[k] = 0;
        for (size_t line = 0; line < lines_of(s, axis) && !split[k]; line++) {
            double x0[SUR_MAX_DIM], x1[SUR_MAX_DIM], xm[SUR_MAX_DIM];
            line_point(s, axis, line, k, x0);
            line_point(s, axis, line, k + 1, x1);
            memcpy(xm, x0, sizeof xm);
            xm[axis] = 0.5 * (x0[axis] + x1[axis]);
            traj_impact_table *t0, *t1, *tm;
            rf_status st = table_at(b, x0, &t0);
            if (st == RF_OK)
                st = table_at(b, x1, &t1);
            if (st == RF_OK)
                st = table_at(b, xm, &tm);
            if (st != RF_OK)
                return st;
            double miss = probe_miss(&s->spec, tm, t0, t1);
            s->info.midpoint_miss = fmax(s->info.midpoint_miss, miss);
            split[k] = miss > s->spec.impact_tolerance && s->n[axis] < SUR_MAX_NODES;
        }
        *any |= split[k];
    }
    return RF_OK;
}

/* Every node of the tensor grid has its table. */
static rf_status fill(sur_build *b)
{
    traj_impact_surrogate *s = b->s;
    size_t total = 1;
    for (size_t a = 0; a < s->d; a++)
        total *= s->n[a];
    for (size_t k = 0; k < total; k++) {
        double x[SUR_MAX_DIM];
        line_point(s, s->d, k, 0, x); /* axis d: none held, k runs over all nodes */
        traj_impact_table *t;
        rf_status st = table_at(b, x, &t);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

static rf_status refine(sur_build *b)
{
    traj_impact_surrogate *s = b->s;
    rf_status st = fill(b);
    for (int round = 0; round < SUR_ROUNDS && st == RF_OK; round++) {
        int split[SUR_MAX_DIM][SUR_MAX_NODES], any = 0;
        s->info.midpoint_miss = 0; /* the last round's: the grid's own hierarchical estimate */
        for (size_t a = 0; a < s->d && st == RF_OK; a++)
            st = refine_axis(b, a, split[a], &any);
        if (st != RF_OK || !any)
            break;
        for (size_t a = 0; a < s->d; a++)
            for (size_t k = s->n[a] - 1; k-- > 0;)
                if (split[a][k] && s->n[a] < SUR_MAX_NODES) {
                    memmove(&s->x[a][k + 2], &s->x[a][k + 1], (s->n[a] - k - 1) * sizeof(double));
                    s->x[a][k + 1] = 0.5 * (s->x[a][k] + s->x[a][k + 2]);
                    s->n[a]++;
                }
        st = fill(b);
    }
    return st;
}

/* Lower node and fraction of v on axis a (one node: itself); v outside the box: an error. */
static rf_status locate(const traj_impact_surrogate *s, size_t a, double v, size_t *i, double *f, rf_error *err)
{
    double slack = 1e-9 * fmax(fabs(s->lo[a]), fabs(s->hi[a]));
    if (!(v >= s->lo[a] - slack && v <= s->hi[a] + slack))
        return rf_fail(err, RF_EINVAL, "impact surrogate: %s = %g lies outside the range it was built over [%g, %g]",
                       s->paths[a], v, s->lo[a], s->hi[a]);
    *i = 0, *f = 0;
    if (s->n[a] < 2)
        return RF_OK;
    while (*i + 2 < s->n[a] && v >= s->x[a][*i + 1])
        (*i)++;
    *f = fmin(fmax((v - s->x[a][*i]) / (s->x[a][*i + 1] - s->x[a][*i]), 0), 1);
    return RF_OK;
}

/* The blend at parameter point x (after the build). */
static rf_status blend_at(const traj_impact_surrogate *s, const double *x, traj_impact_table **out, rf_error *err)
{
    size_t lo[SUR_MAX_DIM], n = 0;
    double f[SUR_MAX_DIM], w[1 << SUR_MAX_DIM];
    const traj_impact_table *parts[1 << SUR_MAX_DIM];
    for (size_t a = 0; a < s->d; a++)
        if (locate(s, a, x[a], &lo[a], &f[a], err) != RF_OK)
            return RF_EINVAL;
    for (size_t c = 0; c < ((size_t)1 << s->d); c++) {
        double wc = 1, y[SUR_MAX_DIM];
        for (size_t a = 0; a < s->d; a++) {
            int up = (int)((c >> a) & 1);
            wc *= up ? f[a] : 1 - f[a];
            y[a] = s->x[a][s->n[a] < 2 ? 0 : lo[a] + (size_t)up];
        }
        if (wc == 0)
            continue;
        if (!(parts[n] = pooled(s, y)))
            return rf_fail(err, RF_EINTERNAL, "impact surrogate: a node's table is missing");
        w[n++] = wc;
    }
    return traj_impact_table_blend(parts, w, n, out, err);
}

/* The values of the bound inputs in spec at. */
static void values_of(const traj_impact_surrogate *s, const rf_traj_spec *at, double *x)
{
    for (size_t a = 0; a < s->d; a++)
        if (!rf_traj_spec_get(at, s->paths[a], &x[a]))
            x[a] = NAN;
}


rf_status traj_impact_surrogate_lookup_at(const traj_impact_surrogate *s, const double *x, size_t material,
                                          double radius, double vn, double theta, double c[3], rf_error *err)
{
    traj_impact_table *t;
    rf_status st = blend_at(s, x, &t, err);
    if (st == RF_OK)
        traj_impact_table_lookup(t, material, radius, vn, theta, &c[0], &c[1], &c[2]);
    traj_impact_table_free(t);
    return st;
}

/* ---- the error at independent runs ---- */

/* The material named by a bound path materials.NAME.impact.X, or the count. */
static size_t material_of(const rf_traj_spec *spec, const char *path)
{
    const char *name = path + strlen("materials."), *end = strstr(name, ".impact.");
    for (size_t m = 0; end && m < spec->n_materials; m++)
        if (strlen(spec->materials[m].name) == (size_t)(end - name) &&
            !strncmp(spec->materials[m].name, name, (size_t)(end - name)))
            return m;
    return spec->n_materials;
}

typedef struct {
    double v[3], c[3];
    int found;
} known_row;

static rf_status find_row(void *u, const double *r)
{
    known_row *k = u;
    if (r[0] == k->v[0] && r[1] == k->v[1] && r[2] == k->v[2])
        memcpy(k->c, r + 3, sizeof k->c), k->found = 1;
    return RF_OK;
}

/* The model's (R_n, R_t, spin) at one check point: from the store, else computed and kept there. */
static rf_status model_at(sur_build *b, traj_impact_setup *setup, const double p[3], double c[3])
{
    const traj_table_watch *w = b->w;
    const traj_impact_store *store = w ? w->store : NULL;
    double *memo = NULL;
    size_t n = 0, cap = 0;
    rf_status st = store ? store->load(store->user, setup, &memo, &n, &cap, b->err) : RF_OK;
    known_row k = {{p[0], p[1], p[2]}, {0}, 0};
    for (size_t i = 0; st == RF_OK && i < n; i++)
        find_row(&k, memo + 6 * i);
    free(memo);
    if (st != RF_OK || k.found) {
        memcpy(c, k.c, sizeof k.c);
        b->s->info.check_from_store += k.found;
        return st;
    }
    if (w && w->stop && atomic_load(w->stop))
        return rf_fail(b->err, RF_EINTERRUPTED, "interrupted during the impact surrogate's error check");
    setup->radius = p[2];
    st = w && w->model ? w->model(setup, p[0], p[1], c, b->err)
                       : traj_impact_coefficients(setup, p[0], p[1], &c[0], &c[1], &c[2], b->err);
    if (st != RF_OK)
        return st;
    b->s->info.check_computed++;
    double row[6] = {p[0], p[1], p[2], c[0], c[1], c[2]};
    return store ? store->put(store->user, setup, row, b->err) : RF_OK;
}

/* Check point i: the bound inputs, v_n, incidence and radius drawn in the box. */
static rf_status check_one(sur_build *b, size_t i, const size_t *mats, size_t n_mats)
{
    traj_impact_surrogate *s = b->s;
    const rf_traj_spec *sp = &s->spec;
    double x[SUR_MAX_DIM], rlo, rhi, p[3], c[3], q[3];
    for (size_t a = 0; a < s->d; a++)
        x[a] = s->lo[a] + (s->hi[a] - s->lo[a]) * rf_traj_uniform(SUR_SEED, a, i);
    traj_impact_radius_range(sp, &rlo, &rhi);
    p[0] = sp->impact_speed_min * pow(sp->impact_speed_max / sp->impact_speed_min, rf_traj_uniform(SUR_SEED, 4, i));
    p[1] = sp->impact_max_incidence * rf_traj_uniform(SUR_SEED, 5, i);
    p[2] = rlo + (rhi - rlo) * rf_traj_uniform(SUR_SEED, 6, i);
    size_t m = mats[i % n_mats];
    rf_traj_spec at;
    traj_impact_setup setup;
    memset(&at, 0, sizeof at);
    rf_status st = spec_at(s, x, &at, b->err);
    if (st == RF_OK && (st = traj_impact_setup_material(&setup, &at, m, b->err)) == RF_OK) {
        setup.stop = b->w ? b->w->stop : NULL;
        st = model_at(b, &setup, p, c);
    }
    rf_traj_spec_free(&at);
    if (st == RF_OK)
        st = traj_impact_surrogate_lookup_at(s, x, m, p[2], p[0], p[1], q, b->err);
    if (st != RF_OK)
        return st;
    /* the model's values as the table's lookup hands them to the bounce (clamped) */
    double rn = fmin(fmax(c[0], 0), 1), rt = fmin(fmax(c[1], 0), 1);
    s->info.err_rn = fmax(s->info.err_rn, fabs(q[0] - rn));
    s->info.err_rt = fmax(s->info.err_rt, fabs(q[1] - rt));
    s->info.check_runs++;
    return RF_OK;
}

static rf_status check(sur_build *b)
{
    traj_impact_surrogate *s = b->s;
    size_t mats[SUR_MAX_DIM], n = 0;
    for (size_t a = 0; a < s->d; a++) {
        size_t m = material_of(&s->spec, s->paths[a]), k = 0;
        while (k < n && mats[k] != m)
            k++;
        if (k == n && m < s->spec.n_materials)
            mats[n++] = m;
    }
    if (!n)
        mats[n++] = 0;
    s->info.err_rn = s->info.err_rt = 0;
    s->info.check_runs = s->info.check_computed = s->info.check_from_store = 0;
    for (size_t i = 0; i < s->checks; i++) {
        rf_status st = check_one(b, i, mats, n);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

int traj_impact_surrogate_path(const char *path)
{
    return !strncmp(path, "materials.", 10) && strstr(path + 10, ".impact.") != NULL;
}

const char *traj_impact_surrogate_unused(const rf_traj_spec *spec, const char *path)
{
    if (!traj_impact_surrogate_path(path))
        return NULL;
    if (spec->terrain)
        return "a terrain file's world has one impact table: binding a material's impact model needs a profile file";
    if (spec->law != RF_BOUNCE_IMPACT_MODEL)
        return "the bounce law is not impact_model: the material's impact model is not used";
    size_t m = material_of(spec, path);
    if (m >= spec->n_materials || !spec->materials[m].impact.given)
        return "the material names no impact model of its own (materials.NAME.impact)";
    return NULL;
}

rf_status traj_impact_surrogate_for_model(const rf_traj_spec *spec, size_t n, char *const *paths, const double *lo,
                                          const double *hi, size_t checks, traj_impact_surrogate **out, rf_error *err)
{
    const char *p[SUR_MAX_DIM + 1];
    double a[SUR_MAX_DIM], b[SUR_MAX_DIM];
    size_t d = 0;
    *out = NULL;
    for (size_t i = 0; i < n; i++) {
        if (!traj_impact_surrogate_path(paths[i]))
            continue;
        if (d == SUR_MAX_DIM)
            return rf_fail(err, RF_EINVAL, "more than %d inputs of impact models bound (%s and others): the impact "
                           "surrogate takes at most %d", SUR_MAX_DIM, paths[i], SUR_MAX_DIM);
        p[d] = paths[i], a[d] = lo[i], b[d] = hi[i], d++;
    }
    return d ? traj_impact_surrogate_create(spec, d, p, a, b, checks, out, err) : RF_OK;
}

/* Build once (thread-safe; a failed build is reported again to every caller). */
rf_status traj_impact_surrogate_build(traj_impact_surrogate *s, const traj_table_watch *w, FILE *log, rf_error *err)
{
    pthread_mutex_lock(&s->lock);
    if (!s->built) {
        double t0 = rf_monotonic_seconds();
        if (log) {
            fprintf(log, "Impact surrogate over");
            for (size_t a = 0; a < s->d; a++)
                fprintf(log, "%s %s in [%g, %g]", a ? "," : "", s->paths[a], s->lo[a], s->hi[a]);
            fprintf(log, ": tables of R_n, R_t and spin at the nodes of a grid refined to %g, then %zu independent "
                         "impact-model runs at random points\n", s->spec.impact_tolerance, s->checks);
            fflush(log);
        }
        sur_build b = {s, w, log, &s->build_err};
        s->build_status = refine(&b);
        if (s->build_status == RF_OK)
            s->build_status = check(&b);
        s->info.seconds = rf_monotonic_seconds() - t0;
        /* interrupted: not built, the next call resumes from the store */
        s->built = s->build_status != RF_EINTERRUPTED;
        if (log && s->build_status == RF_OK) {
            char line[600];
            traj_impact_surrogate_describe(s, line, sizeof line);
            fprintf(log, "Impact surrogate: %s, %.1f s\n", line, s->info.seconds);
            fflush(log);
        }
    }
    rf_status st = s->build_status;
    if (st != RF_OK)
        *err = s->build_err;
    pthread_mutex_unlock(&s->lock);
    return st;
}

rf_status traj_impact_surrogate_table(const traj_impact_surrogate *s, const rf_traj_spec *at, traj_impact_table **out,
                                      rf_error *err)
{
    double x[SUR_MAX_DIM];
    values_of(s, at, x);
    *out = NULL;
    if (!s->built || s->build_status != RF_OK)
        return rf_fail(err, RF_EINTERNAL, "impact surrogate used before it was built");
    return blend_at(s, x, out, err);
}

rf_status traj_impact_surrogate_table_lent(traj_impact_surrogate *s, const rf_traj_spec *at,
                                           const traj_impact_table **out, rf_error *err)
{
    traj_impact_table *t;
    rf_status st = traj_impact_surrogate_table(s, at, &t, err);
    if (st != RF_OK)
        return st;
    pthread_mutex_lock(&s->lock);
    traj_impact_table **l = realloc(s->lent, (s->n_lent + 1) * sizeof *l);
    if (l)
        s->lent = l, l[s->n_lent++] = t;
    pthread_mutex_unlock(&s->lock);
    if (!l) {
        traj_impact_table_free(t);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    *out = t;
    return RF_OK;
}

void traj_impact_surrogate_get(const traj_impact_surrogate *s, traj_impact_surrogate_info *info)
{
    *info = s->info;
    info->dim = s->d;
    for (size_t a = 0; a < s->d; a++)
        info->nodes[a] = s->n[a];
}

void traj_impact_surrogate_describe(const traj_impact_surrogate *s, char *buf, size_t size)
{
    const traj_impact_surrogate_info *i = &s->info;
    int n = snprintf(buf, size, "impact surrogate error R_n %.3g, R_t %.3g (largest miss at %zu independent "
                     "impact-model runs at random points of (v_n, incidence, radius,", i->err_rn, i->err_rt,
                     i->check_runs);
    for (size_t a = 0; a < s->d && n > 0 && (size_t)n < size; a++)
        n += snprintf(buf + n, size - (size_t)n, " %s", s->paths[a]);
    if (n > 0 && (size_t)n < size)
        n += snprintf(buf + n, size - (size_t)n, "); grid");
    for (size_t a = 0; a < s->d && n > 0 && (size_t)n < size; a++)
        n += snprintf(buf + n, size - (size_t)n, "%s%zu", a ? " x " : " ", s->n[a]);
    if (n > 0 && (size_t)n < size)
        snprintf(buf + n, size - (size_t)n, " nodes, %zu tables, %zu impacts computed, %zu taken from the store, "
                 "last midpoint miss %.3g, largest table error estimate %.3g", i->tables, i->computed + i->check_computed,
                 i->from_store + i->check_from_store, i->midpoint_miss, i->table_error);
}
