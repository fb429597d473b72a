/* traj_impact_table.c - R_n, R_t and the spin ratio of an impact model
 * tabulated, per material (its own impact model, materials.NAME.impact, or
 * the run's bounce.impact for a material without one: one shared grid),
 * over normal speed v_n in bounce.impact.speeds (default [0.25, 40] m/s),
 * incidence theta in [0, max_incidence] (default 80 deg, the 3D FE model's
 * limit; from the normal) and the block radius over the run's range (the
 * sphere's radius, or the range of a random block.radius; one node when it
 * is fixed) on a tensor grid refined adaptively: an interval (in v_n, theta
 * or radius) is halved while, at its midpoint, multilinear interpolation
 * from the current nodes misses the model by more than the tolerance
 * (absolute, on R_n and R_t) on any grid line.  After the last refinement
 * every cell centre is evaluated as an independent check: the largest
 * |interpolated - model| there is the reported error estimate.  Outside the
 * box the table is clamped.  Built once per run (per world).
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

/* One material's grid: nodes x[0] (v_n), x[1] (theta), x[2] (radius). */
typedef struct {
    size_t n[3];
    double x[3][MAX_NODES];
    double *c;                 /* [((i * n1 + j) * n2 + l) * 3 + q]: R_n, R_t, spin */
    size_t evaluations;        /* impacts computed by the model for this grid */
    size_t from_cache;         /* impacts of the grid taken from the cache (file or store) */
    double error_estimate;
} grid;

struct traj_impact_table {
    size_t n_grids, n_materials;
    grid *grids;
    size_t *of;                /* n_materials: the grid of material k */
    /* a blend (traj_impact_table_blend): sum of w[k] * parts[k] (not owned), no grids */
    size_t n_parts;
    const traj_impact_table **parts;
    double *w;
};

typedef struct {
    traj_impact_setup setup;
    grid *g;
    const traj_impact_table *t; /* for the progress totals */
    rf_error *err;
    double *memo;             /* (v, theta, radius, R_n, R_t, spin) of every impact known */
    size_t n_memo, cap_memo;
    size_t n_cached;          /* the first n_cached rows of memo came from the cache */
    unsigned char *hit;       /* n_cached flags: the row was used by the grid */
    const char *cache;        /* bounce.impact.cache or NULL */
    const traj_table_watch *watch; /* stop flag, progress and store, or NULL */
} builder;

static size_t at(const grid *g, size_t i, size_t j, size_t l) { return (i * g->n[1] + j) * g->n[2] + l; }

static void totals(const traj_impact_table *t, size_t *computed, size_t *cached)
{
    *computed = *cached = 0;
    for (size_t k = 0; k < t->n_grids; k++)
        *computed += t->grids[k].evaluations, *cached += t->grids[k].from_cache;
}

static rf_status interrupted(builder *b)
{
    size_t computed, cached;
    totals(b->t, &computed, &cached);
    const char *kept = b->watch && b->watch->store ? "the study store" : b->cache;
    return rf_fail(b->err, RF_EINTERRUPTED, "interrupted while building the impact table after %zu impact%s of the "
                   "impact model%s%s", computed, computed == 1 ? "" : "s", kept ? "; they are kept in " : "",
                   kept ? kept : "");
}

/* Keep a computed impact: in the memo, then in the store or the cache file at once
 * (an interrupted build keeps its impacts). */
static rf_status keep(builder *b, const double p[3], const double *c)
{
    if (b->n_memo == b->cap_memo) {
        size_t cap = b->cap_memo ? 2 * b->cap_memo : 256;
        double *m = realloc(b->memo, cap * 6 * sizeof *m);
        if (!m)
            return RF_OK; /* only the memo is lost */
        b->memo = m, b->cap_memo = cap;
    }
    double *m = &b->memo[6 * b->n_memo++];
    memcpy(m, p, 3 * sizeof *m), memcpy(m + 3, c, 3 * sizeof *c);
    const traj_impact_store *s = b->watch ? b->watch->store : NULL;
    if (s)
        return s->put(s->user, &b->setup, m, b->err);
    traj_impact_cache_append(b->cache, &b->setup, m, 1);
    return RF_OK;
}

/* One impact of the model at p = (v, theta, radius), computed once (the grid is refilled after each refinement). */
static rf_status eval(builder *b, const double p[3], double *c)
{
    for (size_t k = 0; k < b->n_memo; k++)
        if (b->memo[6 * k] == p[0] && b->memo[6 * k + 1] == p[1] && b->memo[6 * k + 2] == p[2]) {
            memcpy(c, &b->memo[6 * k + 3], 3 * sizeof *c);
            if (k < b->n_cached && b->hit && !b->hit[k]) /* a cache hit, counted once per impact */
                b->hit[k] = 1, b->g->from_cache++;
            return RF_OK;
        }
    const traj_table_watch *w = b->watch;
    rf_status st = w && w->stop && atomic_load(w->stop) ? RF_EINTERRUPTED : RF_OK;
    b->setup.radius = p[2];
    if (st == RF_OK && w && w->model)
        st = w->model(&b->setup, p[0], p[1], c, b->err);
    else if (st == RF_OK)
        st = traj_impact_coefficients(&b->setup, p[0], p[1], &c[0], &c[1], &c[2], b->err);
    if (st == RF_EINTERRUPTED) /* before this impact or inside it (an FE run stops between two steps) */
        return interrupted(b);
    if (st != RF_OK)
        return st;
    b->g->evaluations++;
    if (w && w->progress) {
        size_t computed, cached;
        totals(b->t, &computed, &cached);
        w->progress(w->user, computed, cached, b->g->n[0], b->g->n[1]);
    }
    return keep(b, p, c);
}

/* Lower node and fraction of v on the axis x[0..n) (clamped; one node: itself). */
static size_t locate(const double *x, size_t n, double v, double *f)
{
    if (n < 2 || v <= x[0]) {
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

/* Bilinear in (v, theta) on the radius node l. */
static void interp2(const grid *g, size_t i, size_t j, size_t l, double fv, double ft, double *c)
{
    for (int q = 0; q < 3; q++) {
        double a = g->c[at(g, i, j, l) * 3 + q], b = g->c[at(g, i, j + 1, l) * 3 + q];
        double d = g->c[at(g, i + 1, j, l) * 3 + q], e = g->c[at(g, i + 1, j + 1, l) * 3 + q];
        c[q] = (1 - fv) * ((1 - ft) * a + ft * b) + fv * ((1 - ft) * d + ft * e);
    }
}

/* Multilinear interpolation at p; one radius node: the bilinear table of before. */
static void interp(const grid *g, const double p[3], double *c)
{
    double fv, ft, fr;
    size_t i = locate(g->x[0], g->n[0], p[0], &fv), j = locate(g->x[1], g->n[1], p[1], &ft);
    size_t l = locate(g->x[2], g->n[2], p[2], &fr);
    interp2(g, i, j, l, fv, ft, c);
    if (g->n[2] < 2)
        return;
    double d[3];
    interp2(g, i, j, l + 1, fv, ft, d);
    for (int q = 0; q < 3; q++)
        c[q] = (1 - fr) * c[q] + fr * d[q];
}

static void clamp_out(const double *c, double *R_n, double *R_t, double *spin_ratio)
{
    *R_n = fmin(fmax(c[0], 0), 1), *R_t = fmin(fmax(c[1], 0), 1), *spin_ratio = fmax(c[2], 0);
}

/* The interpolated (R_n, R_t, spin) before clamping; a blend: its parts' weighted sum. */
static void raw_lookup(const traj_impact_table *t, size_t material, const double p[3], double *c)
{
    if (t->n_parts) {
        c[0] = c[1] = c[2] = 0;
        for (size_t k = 0; k < t->n_parts; k++) {
            double d[3];
            raw_lookup(t->parts[k], material, p, d);
            for (int q = 0; q < 3; q++)
                c[q] += t->w[k] * d[q];
        }
        return;
    }
    interp(&t->grids[t->of[material < t->n_materials ? material : 0]], p, c);
}

void traj_impact_table_lookup(const traj_impact_table *t, size_t material, double radius, double vn, double theta,
                              double *R_n, double *R_t, double *spin_ratio)
{
    double p[3] = {vn, theta, radius}, c[3];
    raw_lookup(t, material, p, c);
    clamp_out(c, R_n, R_t, spin_ratio);
}

rf_status traj_impact_table_blend(const traj_impact_table *const *parts, const double *w, size_t n,
                                  traj_impact_table **out, rf_error *err)
{
    traj_impact_table *t = calloc(1, sizeof *t);
    if (t && n && (t->parts = malloc(n * sizeof *t->parts)) && (t->w = malloc(n * sizeof *t->w))) {
        memcpy(t->parts, parts, n * sizeof *parts);
        memcpy(t->w, w, n * sizeof *w);
        t->n_parts = n;
        *out = t;
        return RF_OK;
    }
    traj_impact_table_free(t);
    *out = NULL;
    return rf_fail(err, RF_ENOMEM, "out of memory");
}

void traj_impact_table_eval(const traj_impact_table *t, double vn, double theta, double *R_n, double *R_t,
                            double *spin_ratio)
{
    const traj_impact_table *g = t;
    while (g->n_parts) /* a blend: the smallest radius of its first part */
        g = g->parts[0];
    traj_impact_table_lookup(t, 0, g->grids[g->of[0]].x[2][0], vn, theta, R_n, R_t, spin_ratio);
}

/* Evaluate every node (known ones come from the memo). */
static rf_status fill(builder *b)
{
    grid *g = b->g;
    free(g->c);
    g->c = malloc(g->n[0] * g->n[1] * g->n[2] * 3 * sizeof *g->c);
    if (!g->c)
        return rf_fail(b->err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < g->n[0]; i++)
        for (size_t j = 0; j < g->n[1]; j++)
            for (size_t l = 0; l < g->n[2]; l++) {
                double p[3] = {g->x[0][i], g->x[1][j], g->x[2][l]};
                rf_status st = eval(b, p, &g->c[at(g, i, j, l) * 3]);
                if (st != RF_OK)
                    return st;
            }
    return RF_OK;
}

static void insert(double *x, size_t *n, size_t at_, double v)
{
    memmove(x + at_ + 2, x + at_ + 1, (*n - at_ - 1) * sizeof *x);
    x[at_ + 1] = v;
    (*n)++;
}

/* Midpoint errors along one axis; split[k] = 1 for the intervals to halve.
 * The grid lines run over the nodes of the two other axes (in axis order). */
static rf_status refine_axis(builder *b, int axis, double tol, int *split, int *any)
{
    const grid *g = b->g;
    int a1 = axis == 0 ? 1 : 0, a2 = axis == 2 ? 1 : 2;
    for (size_t k = 0; k + 1 < g->n[axis]; k++) {
        split[k] = 0;
        for (size_t line = 0; line < g->n[a1] * g->n[a2] && !split[k]; line++) {
            double p[3], c[3], q[3];
            p[axis] = 0.5 * (g->x[axis][k] + g->x[axis][k + 1]);
            p[a1] = g->x[a1][line / g->n[a2]], p[a2] = g->x[a2][line % g->n[a2]];
            rf_status st = eval(b, p, c);
            if (st != RF_OK)
                return st;
            interp(g, p, q);
            split[k] = fabs(c[0] - q[0]) > tol || fabs(c[1] - q[1]) > tol;
        }
        *any |= split[k];
    }
    return RF_OK;
}

static rf_status refine(builder *b, double tol)
{
    grid *g = b->g;
    for (int round = 0; round < 8; round++) {
        int split[3][MAX_NODES], any = 0;
        for (int axis = 0; axis < 3; axis++) {
            rf_status st = refine_axis(b, axis, tol, split[axis], &any);
            if (st != RF_OK)
                return st;
        }
        if (!any)
            return RF_OK;
        for (int axis = 0; axis < 3; axis++) {
            size_t n0 = g->n[axis];
            for (size_t k = n0 - 1; k-- > 0;)
                if (split[axis][k] && g->n[axis] < MAX_NODES)
                    insert(g->x[axis], &g->n[axis], k, 0.5 * (g->x[axis][k] + g->x[axis][k + 1]));
        }
        rf_status st = fill(b);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

/* The error estimate: the largest miss at the cell centres of the final grid
 * (one radius node: the centres of the (v_n, theta) cells at that radius). */
static rf_status estimate_error(builder *b)
{
    grid *g = b->g;
    g->error_estimate = 0;
    size_t nr = g->n[2] > 1 ? g->n[2] - 1 : 1;
    for (size_t i = 0; i + 1 < g->n[0]; i++)
        for (size_t j = 0; j + 1 < g->n[1]; j++)
            for (size_t l = 0; l < nr; l++) {
                double p[3] = {0.5 * (g->x[0][i] + g->x[0][i + 1]), 0.5 * (g->x[1][j] + g->x[1][j + 1]),
                               g->n[2] > 1 ? 0.5 * (g->x[2][l] + g->x[2][l + 1]) : g->x[2][0]}, c[3], q[3];
                rf_status st = eval(b, p, c);
                if (st != RF_OK)
                    return st;
                interp(g, p, q);
                g->error_estimate = fmax(g->error_estimate, fmax(fabs(c[0] - q[0]), fabs(c[1] - q[1])));
            }
    return RF_OK;
}

/* The block radii a run meets: the sphere's radius, or the range of a random
 * block.radius (uniform [a, b]; normal: its truncation, else mean +- 4 SD,
 * kept > 0). */
void traj_impact_radius_range(const rf_traj_spec *s, double *lo, double *hi)
{
    *lo = *hi = s->radius;
    for (size_t k = 0; k < s->n_random; k++) {
        const rf_traj_random *r = &s->random[k];
        if (strcmp(r->path, "block.radius") != 0 || r->dist == RF_DIST_FIXED)
            continue;
        double a = r->dist == RF_DIST_UNIFORM ? r->a : r->a - 4 * r->b;
        double b = r->dist == RF_DIST_UNIFORM ? r->b : r->a + 4 * r->b;
        a = fmax(a, r->lo), b = fmin(b, r->hi);
        if (!(a > 0))
            a = fmin(b, r->a) * 1e-2;
        if (a > 0 && b > a)
            *lo = a, *hi = b;
    }
}

/* The first nodes: v_n geometric, theta uniform, bounce.impact.start_nodes each (5; a spec
 * not from the reader, 0: 5); radius geometric, 3 (1 when fixed). */
static void first_nodes(grid *g, const rf_traj_spec *spec)
{
    double rlo, rhi;
    traj_impact_radius_range(spec, &rlo, &rhi);
    size_t n = spec->impact_start_nodes >= 2 && spec->impact_start_nodes <= 17 ? spec->impact_start_nodes : 5;
    g->n[0] = g->n[1] = n;
    for (size_t i = 0; i < n; i++) {
        double f = (double)i / (double)(n - 1);
        g->x[0][i] = spec->impact_speed_min * pow(spec->impact_speed_max / spec->impact_speed_min, f);
        g->x[1][i] = spec->impact_max_incidence * f;
    }
    g->n[2] = rhi > rlo ? 3 : 1;
    g->x[2][0] = rlo;
    if (g->n[2] == 3)
        g->x[2][1] = sqrt(rlo * rhi), g->x[2][2] = rhi;
}

/* The impacts already known for this setup: from the store, else the cache file. */
static rf_status known(builder *b)
{
    const traj_impact_store *s = b->watch ? b->watch->store : NULL;
    if (s)
        return s->load(s->user, &b->setup, &b->memo, &b->n_memo, &b->cap_memo, b->err);
    return traj_impact_cache_load(b->cache, &b->setup, &b->memo, &b->n_memo, &b->cap_memo, b->err);
}

/* Build grid g for the setup of material k (its own impact model, or the run's). */
static rf_status build_grid(const rf_traj_spec *spec, const traj_table_watch *watch, traj_impact_table *t, grid *g,
                            size_t k, rf_error *err)
{
    builder b = {{0}, g, t, err, NULL, 0, 0, 0, NULL, spec->impact_cache, watch};
    rf_status st = traj_impact_setup_material(&b.setup, spec, k, err);
    b.setup.stop = watch ? watch->stop : NULL;
    first_nodes(g, spec);
    if (st == RF_OK)
        st = known(&b);
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
    if (st != RF_OK && spec->n_materials > 1 && spec->materials[k].impact.given)
        rf_error_prefix(err, "materials.%s.impact", spec->materials[k].name);
    return st;
}

/* Which grid each material uses: its own when it names an impact model, else
 * the one grid of bounce.impact (grid 0 when material 0 has none). */
static rf_status assign_grids(const rf_traj_spec *spec, traj_impact_table *t, size_t *first, rf_error *err)
{
    t->n_materials = spec->n_materials ? spec->n_materials : 1;
    t->of = calloc(t->n_materials, sizeof *t->of);
    t->grids = calloc(t->n_materials, sizeof *t->grids);
    if (!t->of || !t->grids)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    size_t shared = TRAJ_NONE;
    for (size_t k = 0; k < t->n_materials; k++) {
        int own = k < spec->n_materials && spec->materials[k].impact.given;
        if (!own && shared != TRAJ_NONE) {
            t->of[k] = shared;
            continue;
        }
        first[t->n_grids] = k;
        t->of[k] = t->n_grids++;
        if (!own)
            shared = t->of[k];
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
    size_t n = spec->n_materials ? spec->n_materials : 1, *first = calloc(n, sizeof *first);
    rf_status st = t && first ? assign_grids(spec, t, first, err) : rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t k = 0; st == RF_OK && k < t->n_grids; k++)
        st = build_grid(spec, watch, t, &t->grids[k], first[k], err);
    free(first);
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
    for (size_t k = 0; t->grids && k < t->n_grids; k++)
        free(t->grids[k].c);
    free(t->parts);
    free(t->w);
    free(t->grids);
    free(t->of);
    free(t);
}

void traj_impact_table_info(const traj_impact_table *t, size_t *nv, size_t *nt, size_t *evaluations,
                            size_t *from_cache, double *error_estimate)
{
    *nv = *nt = *evaluations = *from_cache = 0;
    *error_estimate = t ? 0 : NAN;
    for (size_t k = 0; t && k < t->n_parts; k++) { /* a blend: the largest of its parts */
        size_t a, b, e, c;
        double est;
        traj_impact_table_info(t->parts[k], &a, &b, &e, &c, &est);
        *nv = a > *nv ? a : *nv, *nt = b > *nt ? b : *nt;
        *evaluations += e, *from_cache += c;
        *error_estimate = fmax(*error_estimate, est);
    }
    for (size_t k = 0; t && k < t->n_grids; k++) {
        const grid *g = &t->grids[k];
        *nv = g->n[0] > *nv ? g->n[0] : *nv, *nt = g->n[1] > *nt ? g->n[1] : *nt;
        *evaluations += g->evaluations, *from_cache += g->from_cache;
        *error_estimate = fmax(*error_estimate, g->error_estimate);
    }
}

size_t traj_impact_table_grids(const traj_impact_table *t) { return t ? t->n_grids : 0; }

void traj_impact_table_grid_info(const traj_impact_table *t, size_t k, size_t nodes[3], size_t *evaluations,
                                 size_t *from_cache, double *error_estimate)
{
    const grid *g = &t->grids[k];
    memcpy(nodes, g->n, sizeof g->n);
    *evaluations = g->evaluations, *from_cache = g->from_cache, *error_estimate = g->error_estimate;
}
