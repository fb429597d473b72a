/* traj_model.c - the trajectory model behind the rf_model interface: one
 * evaluation binds the TM point's values to paths of the trajectory spec,
 * runs the whole Monte Carlo ensemble (single-threaded: the study runner
 * parallelises over points) and returns its statistics, named as in the
 * trajectory JSON (percentiles at the file's outputs.percentiles, exceedance
 * probabilities at its thresholds).  Every evaluation
 * uses the spec's seed, so the TM's points see the same random numbers
 * (common random numbers): differences between points are the fuzzy inputs'
 * effect, not sampling noise.  A collector that no block reaches gets 0 for
 * its energy, height and speed percentiles (nothing passes), so outputs stay finite;
 * any other non-finite output is an error naming the output.
 * With the impact_model law the impact table is built once for the model and
 * shared by every evaluation (each impact of the impact model is computed
 * once per study process), unless a parameter changes it.  It is not built
 * when the model is created (a study is loaded before its output folder is
 * locked) but by the model's prepare (rf_model_prepare: the study run calls
 * it after the lock, saying progress), else by the first evaluation; every
 * build answers the interrupt flag (set_interrupt) between two impacts.  In a
 * study run the impacts are kept in the study's store (set_side_store:
 * traj_impact_store.c), else in bounce.impact.cache if given.
 * The rolling resistances derived from the materials' impact models
 * (rf_traj_rolling_resolve: a material with a soil layer whose file gives no
 * rolling_resistance) are resolved once on the model's spec, by prepare or
 * the first evaluation, and kept in memory for the model's life (not in the
 * store); per evaluation when a block parameter is bound; a bound
 * rolling_resistance is never derived.
 * A terrain file (spec->terrain) evaluates by the terrain Monte Carlo
 * (terrain_run_world on a world prepared once: the DEM is read once per
 * model; no rasters) and gives runout_pXX and reach_angle_pXX [deg] where a
 * profile gives runout_x_pXX; fuzzy hazard rasters are not outputs. */
#include "trajectory/terrain_internal.h"
#include "core/hash.h"
#include "trajectory/traj_impact.h"
#include "trajectory/traj_impact_surrogate.h"
#include "trajectory/traj_rolling.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    rf_traj_spec spec;
    size_t n_params;
    char **paths;
    void *table;             /* impact_model: built once when no parameter changes it, else NULL */
    int shared_table;        /* the impact_model law and no parameter changes the table */
    pthread_mutex_t table_lock; /* the shared table's build (prepare or the first evaluation) */
    const atomic_int *stop;  /* the run's interrupt flag (set_interrupt), or NULL */
    const rf_model_side_store *side; /* a study run's store: the impact table's impacts kept there, or NULL */
    int rolling_shared;      /* no block parameter bound: the derived rolling resistances resolved once ... */
    int rolling_done;        /* ... on spec (rf_traj_rolling_resolve, under table_lock), else per evaluation */
    rf_terrain_world *world; /* a terrain file: its world, prepared once */
    size_t n_outputs;
    traj_impact_surrogate *sur; /* bound impact-model inputs with their ranges (rf_traj_model_set_ranges), or NULL */
    traj_raster_sink sink;   /* a study's fuzzy hazard rasters (traj_model_raster_sink_set), or NULL */
    void *sink_ctx;
} traj_model_ctx;

/* The outputs, in order, as one walk over the spec (names) and the
 * statistics (values): a sink either counts, names or fills them. */
typedef struct {
    char **names;            /* naming pass, else NULL */
    const char **units;
    double *y;               /* filling pass, else NULL */
    size_t n, cap;           /* outputs seen; room in names/units/y */
    int nomem;
    char bad[400];           /* filling pass: the first output whose value is not finite */
} out_sink;

static void emit(out_sink *o, const char *name, const char *unit, double v)
{
    if (o->n >= o->cap) { /* counting, or more outputs than named (see traj_model_eval) */
        o->n++;
        return;
    }
    if (o->names && !(o->names[o->n] = rf_strdup(name)))
        o->nomem = 1;
    if (o->units)
        o->units[o->n] = unit;
    if (o->y)
        o->y[o->n] = v;
    if (o->y && !isfinite(v) && !o->bad[0])
        snprintf(o->bad, sizeof o->bad, "%.300s = %g", name, v);
    o->n++;
}

/* PREFIX_pXX for each chosen level, then PREFIX_max. */
static void emit_pct(out_sink *o, const rf_traj_outputs *lv, const char *prefix, const char *unit,
                     const rf_traj_percentiles *p)
{
    char name[400], lvl[32];
    for (size_t k = 0; k < lv->n_percentiles; k++) {
        rf_traj_percentile_name(lv->percentiles[k], lvl, sizeof lvl);
        snprintf(name, sizeof name, "%s_%s", prefix, lvl);
        emit(o, name, unit, p && k < p->n ? p->value[k] : NAN);
    }
    snprintf(name, sizeof name, "%s_max", prefix);
    emit(o, name, unit, p ? p->max : NAN);
}

/* "500000J", "2_5m": a threshold in an output name ('.' -> '_', no '+'). */
static void threshold_tag(double v, const char *unit, char *buf, size_t size)
{
    char num[64], *q = buf;
    snprintf(num, sizeof num, "%.10g", v);
    for (const char *p = num; *p && q + 1 < buf + size; p++)
        if (*p != '+')
            *q++ = *p == '.' ? '_' : *p;
    *q = '\0';
    snprintf(q, size - (size_t)(q - buf), "%s", unit);
}

/* PREFIX_p_QUANTITY_above_TAG for each threshold (TAG = own_tag for the barrier's own). */
static void emit_exceed(out_sink *o, const char *prefix, const char *quantity, const char *unit, const double *t,
                        const double *p, size_t n, int own, const char *own_tag)
{
    char name[400], tag[96];
    for (size_t k = 0; k < n; k++) {
        if (own && !k)
            snprintf(tag, sizeof tag, "%s", own_tag);
        else
            threshold_tag(t[k], unit, tag, sizeof tag);
        snprintf(name, sizeof name, "%s%sp_%s_above_%s", prefix, *prefix ? "_" : "", quantity, tag);
        emit(o, name, "", p ? p[k] : NAN);
    }
}

static void emit_collector(out_sink *o, const rf_traj_spec *s, size_t c, const rf_traj_collector_stats *cs)
{
    const rf_traj_outputs *lv = &s->outputs;
    const char *nm = s->collectors[c].name;
    char prefix[300];
    const char *q[4] = {"total_energy", "height_lowest", "height_centre", "speed"}, *u[4] = {"J", "m", "m", "m/s"};
    static const rf_traj_percentiles none = {0, 0, 0, 0, 0, RF_TRAJ_MAX_PERCENTILES, {0}, {0}};
    const rf_traj_percentiles *p[4] = {cs ? &cs->total_energy : NULL, cs ? &cs->height_lowest : NULL,
                                       cs ? &cs->height_centre : NULL, cs ? &cs->speed : NULL};
    for (int k = 0; cs && !(cs->reach_probability > 0) && k < 4; k++)
        p[k] = &none; /* nothing passes */
    for (int k = 0; k < 4; k++) {
        snprintf(prefix, sizeof prefix, "%s_%s", nm, q[k]);
        emit_pct(o, lv, prefix, u[k], p[k]);
    }
    snprintf(prefix, sizeof prefix, "%s_reach_probability", nm);
    emit(o, prefix, "", cs ? cs->reach_probability : NAN);
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own;
    size_t n = rf_traj_thresholds(&s->collectors[c], 0, t, &own);
    emit_exceed(o, nm, "total_energy", "J", t, cs ? cs->p_energy_above : NULL, n, own, "capacity");
    n = rf_traj_thresholds(&s->collectors[c], 1, t, &own);
    emit_exceed(o, nm, "height_lowest", "m", t, cs ? cs->p_height_above : NULL, n, own, "barrier");
}

/* A terrain run's reach angle percentiles in degrees. */
static rf_traj_percentiles reach_degrees(const rf_traj_stats *t)
{
    rf_traj_percentiles p = t->reach_angle;
    const double k = 180 / 3.14159265358979323846;
    p.p50 *= k, p.p95 *= k, p.p99 *= k, p.max *= k, p.mean *= k;
    for (size_t i = 0; i < p.n; i++)
        p.value[i] *= k;
    return p;
}

/* Every output: per collector, then runout_x (terrain: runout, reach_angle [deg]), rebound_height and
 * P(runout_x > x). */
static void walk_outputs(out_sink *o, const rf_traj_spec *s, const rf_traj_stats *t)
{
    for (size_t c = 0; c < s->n_collectors; c++)
        emit_collector(o, s, c, t ? &t->collectors[c] : NULL);
    if (s->terrain) {
        rf_traj_percentiles ra = t ? reach_degrees(t) : (rf_traj_percentiles){0};
        emit_pct(o, &s->outputs, "runout", "m", t ? &t->runout_x : NULL);
        emit_pct(o, &s->outputs, "reach_angle", "deg", t ? &ra : NULL);
    } else {
        emit_pct(o, &s->outputs, "runout_x", "m", t ? &t->runout_x : NULL);
    }
    emit_pct(o, &s->outputs, "rebound_height", "m", t ? &t->rebound_height : NULL);
    emit_exceed(o, "", s->terrain ? "runout" : "runout_x", "m", s->outputs.runout_thresholds,
                t ? t->p_runout_above : NULL, s->outputs.n_runout_thresholds, 0, "");
}

/* The hazard bands of a terrain evaluation at x, handed to the model's raster sink. */
static rf_status emit_rasters(const traj_model_ctx *c, const rf_traj_spec *s, const rf_traj_ensemble *e,
                              const double *x, rf_error *err)
{
    const rf_terrain_hazard *h = e->terrain ? e->terrain->hazard : NULL;
    if (!h)
        return rf_fail(err, RF_EINVAL, "fuzzy hazard rasters: the terrain file asks for no raster statistics "
                                       "(rasters.statistics)");
    terrain_band *bands;
    size_t n;
    rf_status st = terrain_hazard_bands(h, s, s->samples, &bands, &n, err);
    if (st != RF_OK)
        return st;
    traj_raster_grid g = {0, 0, 0, 0, 0, rf_terrain_crs_wkt(c->world->dem)};
    terrain_hazard_grid(h, &g.nx, &g.ny, &g.x0, &g.y0, &g.cell);
    st = c->sink(c->sink_ctx, x, c->n_params, bands, n, &g, err);
    terrain_bands_free(bands, n);
    return st;
}

/* ---- the impact table: built after the model's creation, interruptible ---- */

typedef struct {
    FILE *log;
    double t0, last; /* start and last line [s, monotonic] */
} table_progress;

static void table_say(void *user, size_t computed, size_t from_cache, size_t nv, size_t nt)
{
    table_progress *p = user;
    double now = rf_monotonic_seconds();
    if (!p->log || now - p->last < 5)
        return;
    p->last = now;
    fprintf(p->log, "Impact table: %zu impact%s computed, %zu taken from the cache, grid %zu x %zu nodes so far, "
                    "%.0f s\n", computed, computed == 1 ? "" : "s", from_cache, nv, nt, now - p->t0);
    fflush(p->log);
}

/* Build the table of spec s watched by the stop flag, saying progress on log (may be NULL). */
static rf_status table_build(const traj_model_ctx *c, const rf_traj_spec *s, FILE *log, traj_impact_table **t,
                             rf_error *err)
{
    table_progress p = {log, rf_monotonic_seconds(), rf_monotonic_seconds()};
    const char *kept = c->side ? "the study's store" : s->impact_cache;
    traj_impact_store store;
    if (c->side)
        traj_impact_store_from_side(c->side, &store);
    traj_table_watch w = {c->stop, table_say, &p, c->side ? &store : NULL, NULL};
    if (log) {
        fprintf(log, "Impact table (bounce law impact_model, solver %s): R_n, R_t and spin over normal speeds "
                     "[%g, %g] m/s and incidences [0, %g] deg to %g, before the first evaluation%s%s\n",
                s->impact_solver, s->impact_speed_min, s->impact_speed_max, s->impact_max_incidence * 180 / RF_PI,
                s->impact_tolerance, kept ? "; impacts kept in " : "", kept ? kept : "");
        fflush(log);
    }
    rf_status st = traj_impact_table_build_watched(s, &w, t, err);
    if (st == RF_OK && log) {
        size_t nv, nt, computed, cached;
        double e;
        traj_impact_table_info(*t, &nv, &nt, &computed, &cached, &e);
        fprintf(log, "Impact table: %zu x %zu nodes, %zu impact%s computed, %zu taken from the cache, error "
                     "estimate %.3g, %.1f s\n", nv, nt, computed, computed == 1 ? "" : "s", cached, e,
                rf_monotonic_seconds() - p.t0);
        fflush(log);
    }
    return st;
}

/* The shared table, built once (by prepare, else by the first evaluation). */
static rf_status shared_table(traj_model_ctx *c, FILE *log, traj_impact_table **t, rf_error *err)
{
    pthread_mutex_lock(&c->table_lock);
    rf_status st = RF_OK;
    if (!c->table)
        st = table_build(c, &c->spec, log, (traj_impact_table **)&c->table, err);
    if (c->world)
        c->world->impact_table = c->table; /* a terrain world's table, built in the run (not at load) */
    *t = c->table;
    pthread_mutex_unlock(&c->table_lock);
    return st;
}

/* The impact surrogate, built once (by prepare, else by the first evaluation; traj_impact_surrogate.c). */
static rf_status surrogate_ready(const traj_model_ctx *c, FILE *log, rf_error *err)
{
    traj_impact_store store;
    if (c->side)
        traj_impact_store_from_side(c->side, &store);
    table_progress p = {log, rf_monotonic_seconds(), rf_monotonic_seconds()}; /* each table's progress */
    traj_table_watch w = {c->stop, table_say, &p, c->side ? &store : NULL, NULL};
    return traj_impact_surrogate_build(c->sur, &w, log, err);
}

/* The rolling resistances derived from the materials' impact models
 * (rf_traj_rolling_resolve), once on the model's spec, said on log. */
static rf_status shared_rolling(traj_model_ctx *c, FILE *log, rf_error *err)
{
    pthread_mutex_lock(&c->table_lock);
    rf_status st = RF_OK;
    if (c->rolling_shared && !c->rolling_done && (st = rf_traj_rolling_resolve(&c->spec, log, err)) == RF_OK)
        c->rolling_done = 1;
    pthread_mutex_unlock(&c->table_lock);
    return st;
}

/* The table an evaluation of spec s uses: the shared one, the surrogate's at
 * its point, or its own (*own, freed by the caller). */
static rf_status table_at(traj_model_ctx *c, const rf_traj_spec *s, traj_impact_table **t, traj_impact_table **own,
                          rf_error *err)
{
    if (c->sur) {
        rf_status st = surrogate_ready(c, NULL, err);
        if (st == RF_OK)
            st = traj_impact_surrogate_table(c->sur, s, own, err);
        *t = *own;
        return st;
    }
    if (c->shared_table)
        return shared_table(c, NULL, t, err);
    rf_status st = table_build(c, s, NULL, own, err);
    *t = *own;
    return st;
}

static rf_status traj_model_prepare(void *vctx, FILE *log, rf_error *err)
{
    traj_model_ctx *c = vctx;
    traj_impact_table *t;
    rf_status st = shared_rolling(c, log, err);
    if (st != RF_OK)
        return st;
    if (c->sur)
        return surrogate_ready(c, log, err);
    return c->shared_table ? shared_table(c, log, &t, err) : RF_OK;
}

/* The impact surrogate's error, reported with every result (a field of its own: rf_model.surrogate_error). */
static size_t traj_model_surrogate_error(void *vctx, char *buf, size_t size)
{
    const traj_model_ctx *c = vctx;
    buf[0] = '\0';
    traj_impact_surrogate_info info = {0};
    if (c->sur)
        traj_impact_surrogate_get(c->sur, &info);
    if (!info.check_runs)
        return 0;
    traj_impact_surrogate_describe(c->sur, buf, size);
    return 1;
}

static void traj_model_set_interrupt(void *vctx, const atomic_int *flag)
{
    ((traj_model_ctx *)vctx)->stop = flag;
}

static void traj_model_set_side_store(void *vctx, const rf_model_side_store *store)
{
    ((traj_model_ctx *)vctx)->side = store;
}

static rf_status traj_model_eval(void *vctx, const double *x, double *y, rf_error *err)
{
    traj_model_ctx *c = vctx;
    rf_traj_spec s;
    rf_status st = shared_rolling(c, NULL, err);
    if (st != RF_OK || (st = rf_traj_spec_copy(&c->spec, &s, err)) != RF_OK)
        return st;
    for (size_t i = 0; i < c->n_params; i++)
        rf_traj_spec_set(&s, c->paths[i], x[i]); /* as given: an angle in degrees */
    if (!c->rolling_shared && (st = rf_traj_rolling_resolve(&s, NULL, err)) != RF_OK) {
        rf_traj_spec_free(&s);
        return st;
    }
    s.record = 0;
    rf_traj_ensemble e;
    rf_traj_stats t;
    int rasters = c->world && c->sink; /* a study's fuzzy hazard rasters */
    traj_impact_table *table = NULL, *own = NULL;
    if (s.law == RF_BOUNCE_IMPACT_MODEL)
        st = table_at(c, &s, &table, &own, err);
    if (st == RF_OK)
        st = c->world ? terrain_run_world(&s, c->world, 1, rasters, NULL, NULL, &e, err)
                      : traj_run_with(&s, 1, table, 0, &e, err); /* no envelopes: not outputs */
    traj_impact_table_free(own);
    if (st != RF_OK) {
        rf_traj_spec_free(&s);
        return st;
    }
    if (rasters)
        st = emit_rasters(c, &s, &e, x, err);
    if (st == RF_OK) {
        if ((st = rf_traj_stats_compute_spec(&s, &e, &t, err)) == RF_OK) {
            out_sink o = {NULL, NULL, y, 0, c->n_outputs, 0, ""};
            walk_outputs(&o, &s, &t);
            rf_traj_stats_free(&t);
            /* a bound capacity or barrier height that reaches 0 drops its exceedance output */
            if (o.n != c->n_outputs)
                st = rf_fail(err, RF_EINVAL, "a bound collector capacity or height reaches 0 at this point: the "
                                             "outputs P(E > capacity), P(h > height) no longer exist; keep it > 0");
            else if (o.bad[0])
                st = rf_fail(err, RF_EINVAL, "output %s: not finite at this point (inputs beyond what the "
                                             "arithmetic holds)", o.bad);
        }
    }
    rf_traj_ensemble_free(&e);
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
    if (c->world && c->world->impact_table == c->table)
        c->world->impact_table = NULL; /* the model's, lent to the world */
    traj_impact_table_free(c->table);
    traj_impact_surrogate_free(c->sur);
    pthread_mutex_destroy(&c->table_lock);
    rf_terrain_world_free(c->world);
    rf_traj_spec_free(&c->spec);
    free(c);
}

/* A material whose rolling_resistance a parameter binds keeps it (never
 * derived); a bound block parameter makes the derivation per evaluation
 * (the terrain world's block is the nominal one: resolved once), and so
 * does a bound impact-model input (the layer the derivation indents). */
static void rolling_bound(traj_model_ctx *c)
{
    c->rolling_shared = 1;
    for (size_t i = 0; i < c->n_params; i++) {
        const char *p = c->paths[i];
        if ((!strncmp(p, "block.", 6) && !c->spec.terrain) || strstr(p, ".impact."))
            c->rolling_shared = 0; /* the block, or the layer the derivation indents */
        const char *r = strstr(p, ".rolling_resistance");
        if (strncmp(p, "materials.", 10) || !r)
            continue;
        for (size_t k = 0; k < c->spec.n_materials; k++)
            if (strlen(c->spec.materials[k].name) == (size_t)(r - p - 10) &&
                !strncmp(p + 10, c->spec.materials[k].name, (size_t)(r - p - 10)))
                c->spec.materials[k].impact.rolling_given = 1;
    }
}

/* The impact table depends on the block's radius and density, the impact
 * friction and the solver settings: shared by all evaluations unless a
 * parameter is bound to one of them (then built at every evaluation); a
 * terrain world has one table, of the nominal block, built in the run. */
static rf_status share_table(traj_model_ctx *c, rf_error *err)
{
    for (size_t i = 0; i < c->n_params; i++) {
        const char *why = traj_impact_surrogate_unused(&c->spec, c->paths[i]);
        if (why)
            return rf_fail(err, RF_EINVAL, "'%s': %s", c->paths[i], why);
    }
    c->shared_table = c->spec.law == RF_BOUNCE_IMPACT_MODEL;
    for (size_t i = 0; i < c->n_params && c->shared_table && !c->spec.terrain; i++) /* a terrain world: one table */
        if (!strncmp(c->paths[i], "block.", 6) || strstr(c->paths[i], ".friction_angle") ||
            traj_impact_surrogate_path(c->paths[i])) /* a material's impact model: the surrogate, else per point */
            c->shared_table = 0;
    rolling_bound(c);
    traj_impact_setup setup; /* its settings checked now, when the study is loaded; the FE impacts come later */
    return c->spec.law == RF_BOUNCE_IMPACT_MODEL ? traj_impact_setup_init(&setup, &c->spec, err) : RF_OK;
}

static rf_status init_outputs(rf_model *m, const rf_traj_spec *s, rf_error *err)
{
    out_sink o = {NULL, NULL, NULL, 0, 0, 0, ""};
    walk_outputs(&o, s, NULL); /* count */
    size_t n = o.n;
    o.names = calloc(n ? n : 1, sizeof *o.names);
    o.units = calloc(n ? n : 1, sizeof *o.units);
    o.n = 0, o.cap = n;
    if (o.names && o.units)
        walk_outputs(&o, s, NULL);
    rf_status st = o.names && o.units && !o.nomem ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory");
    if (st == RF_OK)
        st = rf_model_init_outputs(m, n, (const char *const *)o.names, o.units, err);
    for (size_t k = 0; o.names && k < n; k++)
        free(o.names[k]);
    free(o.names);
    free(o.units);
    return st;
}

/* The identity names the content, not the file name: the trajectory file's
 * text, the profile's vertices and segment materials as read (a profile CSV
 * or a DEM cut enters through them) and every value a run reads, walked over
 * the input tables (rf_traj_spec_values_hash), so an edited file or a spec
 * changed in memory is never served from a store. */
static rf_status set_identity(rf_model *m, const traj_model_ctx *c, rf_error *err)
{
    const rf_traj_spec *s = &c->spec;
    uint64_t profile = rf_fnv1a(RF_FNV1A_OFFSET, s->px, s->n_points * sizeof *s->px);
    profile = rf_fnv1a(profile, s->py, s->n_points * sizeof *s->py);
    profile = rf_fnv1a(profile, s->seg_material, (s->n_points ? s->n_points - 1 : 0) * sizeof *s->seg_material);
    char buf[2048];
    int len = snprintf(buf, sizeof buf, "trajectory v3: file=%s text=%016llx profile=%016llx values=%016llx "
                       "samples=%zu seed=%llu lhs=%d bind=", s->file ? s->file : "?", (unsigned long long)s->text_hash,
                       (unsigned long long)profile, (unsigned long long)rf_traj_spec_values_hash(s), s->samples,
                       (unsigned long long)s->seed, s->lhs);
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
    pthread_mutex_init(&c->table_lock, NULL);
    if (!c->spec.outputs.n_percentiles) { /* a spec built in code: the defaults */
        c->spec.outputs.n_percentiles = 3;
        c->spec.outputs.percentiles[0] = 50, c->spec.outputs.percentiles[1] = 95, c->spec.outputs.percentiles[2] = 99;
    }
    c->paths = calloc(n_params ? n_params : 1, sizeof *c->paths);
    if (!c->paths)
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < n_params && st == RF_OK; i++) {
        c->n_params = i + 1;
        char why[2400];
        if (!rf_traj_path_bindable(&c->spec, bind_paths[i], why, sizeof why))
            st = rf_fail(err, RF_EINVAL, "parameter %s: '%s': %s", param_names[i], bind_paths[i], why);
        else if (!(c->paths[i] = rf_strdup(bind_paths[i])))
            st = rf_fail(err, RF_ENOMEM, "out of memory");
    }
    model->n_inputs = n_params;
    model->ctx = c;
    model->destroy = traj_model_destroy;
    model->eval = traj_model_eval;
    model->threads_per_eval = 1;
    model->prepare = traj_model_prepare;
    model->set_interrupt = traj_model_set_interrupt;
    model->set_side_store = traj_model_set_side_store;
    model->surrogate_error = traj_model_surrogate_error;
    if (st == RF_OK && c->spec.terrain) /* checked as a run checks it, the DEM read once */
        if ((st = rf_traj_spec_validate(&c->spec, err)) == RF_OK)
            st = terrain_world_create_deferred(&c->spec, &c->world, err); /* its impact table: in the run */
    if (st == RF_OK)
        st = share_table(c, err);
    if (st == RF_OK)
        st = init_outputs(model, &c->spec, err);
    c->n_outputs = model->n_outputs;
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
    traj_model_ctx *c = m->ctx;
    traj_impact_table *t = NULL;
    const traj_impact_table *lent = NULL;
    *table = NULL;
    rf_status st = shared_rolling(c, NULL, err);
    if (st == RF_OK && c->shared_table)
        st = shared_table(c, NULL, &t, err);
    if (st == RF_OK)
        st = rf_traj_spec_copy(&c->spec, spec, err);
    for (size_t i = 0; i < c->n_params && st == RF_OK; i++)
        rf_traj_spec_set(spec, c->paths[i], x[i]);
    if (st == RF_OK && c->sur && (st = surrogate_ready(c, NULL, err)) == RF_OK) /* the surrogate's, kept by it */
        st = traj_impact_surrogate_table_lent(c->sur, spec, &lent, err);
    *table = lent ? (void *)lent : t;
    return st;
}

rf_status rf_traj_model_set_ranges(rf_model *m, const double *lo, const double *hi, rf_error *err)
{
    if (m->eval != traj_model_eval)
        return rf_fail(err, RF_EINVAL, "not a trajectory model");
    traj_model_ctx *c = m->ctx;
    traj_impact_surrogate_free(c->sur);
    c->sur = NULL;
    rf_status st = traj_impact_surrogate_for_model(&c->spec, c->n_params, c->paths, lo, hi, TRAJ_SURROGATE_CHECKS,
                                                   &c->sur, err);
    if (st != RF_OK || !c->sur)
        return st;
    char buf[4096]; /* the results at a point depend on the surrogate's box: in the identity */
    int len = snprintf(buf, sizeof buf, "%s impact_surrogate=%d:", m->identity ? m->identity : "", TRAJ_SURROGATE_CHECKS);
    for (size_t i = 0; i < c->n_params && len > 0 && (size_t)len < sizeof buf; i++)
        if (traj_impact_surrogate_path(c->paths[i]))
            len += snprintf(buf + len, sizeof buf - (size_t)len, "[%.17g,%.17g]", lo[i], hi[i]);
    return rf_model_set_identity(m, buf, err);
}

void traj_model_outputs(const rf_model *m, const rf_traj_spec *s, const rf_traj_stats *t, double *y)
{
    const traj_model_ctx *c = m->ctx;
    out_sink o = {NULL, NULL, y, 0, c->n_outputs, 0, ""};
    walk_outputs(&o, s, t);
}

rf_status traj_model_raster_sink_set(const rf_model *m, traj_raster_sink sink, void *ctx, rf_error *err)
{
    if (m->eval != traj_model_eval)
        return rf_fail(err, RF_EINVAL, "raster sink: not a trajectory model");
    traj_model_ctx *c = m->ctx;
    c->sink = sink;
    c->sink_ctx = sink ? ctx : NULL;
    return RF_OK;
}
