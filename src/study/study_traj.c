/* study_traj.c - the `model: {trajectory: ...}` block of a study file
 * (docs/trajectories.md sec. 5): the trajectory file, Monte Carlo overrides,
 * and the binding of every fuzzy parameter to a numeric input of that file.
 * A parameter may drive several inputs, each as value * scale + offset
 * (bind.h); the general form is the default scheme (bind_check.c).
 * At the end of a study the Monte Carlo is rerun at the nominal point and at
 * the points giving the bounds of the main output, for the report (below). */
#define _XOPEN_SOURCE 700 /* open_memstream, getline */
#include "study/study_internal.h"
#include "study/bind.h"
#include "study/report_internal.h"
#include "core/util.h"
#include "rockfuzz/fuzzy.h"
#include "rockfuzz/report.h"
#include "rockfuzz/trajectory.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
    char *file;
    long long samples, seed;
    int lhs;                 /* -1: as in the file */
    struct fy_node *bind, *file_node, *rasters;
} traj_block;

static rf_status read_block(yr_ctx *c, struct fy_node *n, traj_block *b)
{
    const char *path = "model.trajectory", *key;
    rf_status st = yr_mapping(c, n, path);
    yr_iter it = {n, NULL, 0, {0}};
    struct fy_node *k, *v;
    char p[300];
    while (st == RF_OK) {
        if ((st = yr_next(c, &it, path, &key, &k, &v)) != RF_OK || !key)
            break;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (!strcmp(key, "file")) {
            b->file_node = v;
            st = yr_string_dup(c, v, p, &b->file);
        } else if (!strcmp(key, "samples")) {
            st = yr_integer(c, v, p, 1, 100000000, &b->samples);
        } else if (!strcmp(key, "seed")) {
            st = yr_integer(c, v, p, 0, 9007199254740992LL, &b->seed);
        } else if (!strcmp(key, "sampling")) {
            const char *s;
            size_t len;
            if ((st = yr_string(c, v, p, &s, &len)) == RF_OK) {
                b->lhs = len == 3 && !strncmp(s, "lhs", 3) ? 1 : len == 6 && !strncmp(s, "random", 6) ? 0 : -2;
                if (b->lhs == -2)
                    st = yr_fail(c, v, p, "expected random or lhs");
            }
        } else if (!strcmp(key, "bind")) {
            b->bind = v;
            st = yr_mapping(c, v, p);
        } else if (!strcmp(key, "rasters")) {
            b->rasters = v;
            st = yr_mapping(c, v, p);
        } else {
            st = yr_fail(c, k, p, "unknown key; a trajectory model takes file, samples, seed, sampling, bind, rasters");
        }
    }
    if (st == RF_OK && !b->file)
        st = yr_fail(c, n, path, "missing file (the trajectory file, relative to the study file)");
    return st;
}

/* An index written other than as the spec names it ("01", "+1", " 1"):
 * the canonical path into buf, else NULL. */
static const char *index_alias(const char *path, char *buf, size_t size)
{
    size_t idx;
    char xy[3];
    int n = 0;
    if (sscanf(path, "profile.points.%zu.%2[xy]%n", &idx, xy, &n) != 2 || path[n] != '\0')
        return NULL;
    snprintf(buf, size, "profile.points.%zu.%s", idx, xy);
    return strcmp(buf, path) ? buf : NULL;
}

/* sb_check_fn: a numeric, non-random input of the spec, written canonically. */
static const char *check_path(void *user, const char *to, char *buf, size_t size)
{
    rf_traj_spec *spec = user;
    char canon[128];
    if (index_alias(to, canon, sizeof canon))
        return snprintf(buf, size, "write the index as the file numbers it: %s (no sign, space or leading zero)",
                        canon), buf;
    if (!rf_traj_path_bindable(spec, to, buf, size))
        return buf;
    for (size_t r = 0; r < spec->n_random; r++)
        if (!strcmp(spec->random[r].path, to))
            return snprintf(buf, size, "this input is random in the trajectory file; bind its distribution "
                            "(%s.lo/.hi or .mean/.sd)", to), buf;
    return NULL;
}

typedef struct {
    rf_traj_spec *spec;
    const sb_binding *b;
} traj_check;

/* sb_validate_fn: the spec's own validation with the bound inputs set. */
static rf_status validate_point(void *user, const double *xi, rf_error *err)
{
    traj_check *t = user;
    for (size_t j = 0; j < t->b->n; j++)
        rf_traj_spec_set(t->spec, t->b->t[j].to, xi[j]); /* as given: an angle in degrees */
    return rf_traj_spec_validate(t->spec, err);
}

/* The joint admissibility of the parameters; the spec is left at the nominal point. */
static rf_status check_support(yr_ctx *c, traj_block *b, rf_traj_spec *spec, const rf_study *s,
                               const sb_binding *bind)
{
    traj_check t = {spec, bind};
    rf_status st = sb_check_box(c, b->bind ? b->bind : b->file_node, "model.trajectory.bind", s, bind,
                                validate_point, &t);
    double x[64], xi[SB_MAX_TARGETS];
    for (size_t i = 0; i < s->n_params && i < 64; i++)
        x[i] = rf_fuzzy_nominal(&s->inputs[i]);
    sb_expand(bind, x, xi);
    rf_error tmp;
    validate_point(&t, xi, &tmp);
    return st;
}

static rf_status load_spec(yr_ctx *c, traj_block *b, rf_traj_spec *spec)
{
    char path[4096];
    if (b->file[0] == '/' || !strcmp(c->dir, "."))
        snprintf(path, sizeof path, "%s", b->file);
    else
        snprintf(path, sizeof path, "%s/%s", c->dir, b->file);
    if (rf_traj_load(path, spec, c->err) != RF_OK)
        return yr_prefix(c, b->file_node, "model.trajectory.file");
    if (b->samples > 0)
        spec->samples = (size_t)b->samples;
    if (b->seed >= 0)
        spec->seed = (uint64_t)b->seed;
    if (b->lhs >= 0)
        spec->lhs = b->lhs;
    spec->record = 0;
    return RF_OK;
}

static rf_status make_model(yr_ctx *c, struct fy_node *n, rf_traj_spec *spec, rf_study *s, const sb_binding *bind)
{
    const char **names = sb_names(bind);
    if (!names)
        return rf_fail(c->err, RF_ENOMEM, "out of memory");
    rf_status st = rf_traj_model_create(spec, bind->n, names, names, &s->model, c->err);
    free(names);
    double lo[SB_MAX_TARGETS], hi[SB_MAX_TARGETS]; /* each input's range over the parameters' supports */
    for (size_t j = 0; j < bind->n && st == RF_OK; j++) {
        const sb_target *t = &bind->t[j];
        double a, b;
        rf_fuzzy_cut(&s->inputs[t->param], 0.0, &a, &b);
        a = a * t->scale + t->offset, b = b * t->scale + t->offset;
        lo[j] = fmin(a, b), hi[j] = fmax(a, b);
    }
    if (st == RF_OK) /* bound impact-model inputs: the impact surrogate over that box */
        st = rf_traj_model_set_ranges(&s->model, lo, hi, c->err);
    if (st != RF_OK)
        return yr_prefix(c, n, "model.trajectory");
    return sb_wrap(bind, s->n_params, &s->model, c->err);
}

/* A hazard band a terrain run makes: passages, reach_probability, deposits,
 * energy_max, height_max, energy_pNN, height_pNN (terrain_hazard_bands). */
static int is_band_name(const char *w)
{
    const char *fixed[] = {"passages", "reach_probability", "deposits", "energy_max", "height_max"};
    for (size_t k = 0; k < sizeof fixed / sizeof *fixed; k++)
        if (!strcmp(w, fixed[k]))
            return 1;
    const char *num = !strncmp(w, "energy_p", 8) ? w + 8 : !strncmp(w, "height_p", 8) ? w + 8 : NULL;
    if (!num || !*num)
        return 0;
    for (; *num; num++)
        if ((*num < '0' || *num > '9') && *num != '.')
            return 0;
    return 1;
}

static rf_status add_raster(rf_study *s, const char *name, rf_error *err)
{
    char **grown = realloc(s->fuzzy_rasters, (s->n_fuzzy_rasters + 1) * sizeof *grown);
    if (!grown)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    s->fuzzy_rasters = grown;
    if (!(grown[s->n_fuzzy_rasters] = rf_strdup(name)))
        return rf_fail(err, RF_ENOMEM, "out of memory");
    s->n_fuzzy_rasters++;
    return RF_OK;
}

/* model.trajectory.rasters: {fuzzy: [band, ...]}, a terrain file only; the
 * default for a terrain file: reach_probability and energy_p95. */
static rf_status parse_rasters(yr_ctx *c, struct fy_node *n, const rf_traj_spec *spec, rf_study *s)
{
    const char *path = "model.trajectory.rasters", *key;
    if (n && !spec->terrain)
        return yr_fail(c, n, path, "fuzzy hazard rasters need a terrain file (this one is a profile)");
    if (!n && !spec->terrain)
        return RF_OK;
    if (!n) {
        rf_status st = add_raster(s, "reach_probability", c->err);
        return st ? st : add_raster(s, "energy_p95", c->err);
    }
    yr_iter it = {n, NULL, 0, {0}};
    struct fy_node *k, *v;
    char p[300];
    rf_status st = RF_OK;
    while (st == RF_OK) {
        if ((st = yr_next(c, &it, path, &key, &k, &v)) != RF_OK || !key)
            break;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        if (strcmp(key, "fuzzy")) {
            st = yr_fail(c, k, p, "unknown key; rasters takes fuzzy (a list of hazard bands)");
            break;
        }
        size_t count = 0;
        st = yr_sequence(c, v, p, 0, 16, &count);
        for (size_t q = 0; st == RF_OK && q < count; q++) {
            char w[40], pq[320];
            struct fy_node *item = fy_node_sequence_get_by_index(v, (int)q);
            yr_pathf(pq, sizeof pq, "%s.%zu", p, q);
            st = yr_word(c, item, pq, w, sizeof w);
            if (st == RF_OK && !is_band_name(w))
                st = yr_fail(c, item, pq, "not a hazard band; expected passages, reach_probability, deposits, "
                                          "energy_max, height_max, energy_pNN or height_pNN");
            if (st == RF_OK)
                st = add_raster(s, w, c->err);
        }
    }
    return st;
}

rf_status rf_traj_study_parse(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    traj_block b = {NULL, -1, -1, -1, NULL, NULL, NULL};
    rf_traj_spec spec;
    sb_binding bind = {0, NULL};
    memset(&spec, 0, sizeof spec);
    rf_status st = read_block(c, n, &b);
    if (st == RF_OK)
        st = load_spec(c, &b, &spec);
    if (st == RF_OK)
        st = sb_parse(c, b.bind, "model.trajectory.bind", s, 0, check_path, &spec, &bind);
    if (st == RF_OK)
        st = check_support(c, &b, &spec, s, &bind);
    if (st == RF_OK)
        st = parse_rasters(c, b.rasters, &spec, s);
    if (st == RF_OK)
        st = make_model(c, n, &spec, s, &bind);
    if (st == RF_OK) {
        s->model_kind = RF_STUDY_MODEL_TRAJECTORY;
        char d[512];
        snprintf(d, sizeof d, "trajectory: %s, %zu samples per point, seed %llu (common random numbers)%s", b.file,
                 spec.samples, (unsigned long long)spec.seed, spec.lhs ? ", Latin hypercube" : "");
        if (!(s->model_description = rf_strdup(d)))
            st = rf_fail(c->err, RF_ENOMEM, "out of memory");
    }
    sb_free(&bind);
    free(b.file);
    rf_traj_spec_free(&spec);
    return st;
}

/* ---- the Monte Carlo reruns behind the report (docs/trajectories.md sec. 7) ----
 * DIR/nominal/, DIR/bound_lower/, DIR/bound_upper/: the trajectories at the
 * nominal point and at the points the TM found for the lower and upper bound
 * of the main output at membership 0.  Each folder's RERUN_MARK, written
 * last, holds the identity of what ran (model, point, plots), the main output
 * the rerun gave and the axes of its figures: a folder whose mark matches is
 * not run again unless the common axes of the three changed. */
#define RERUN_MARK "rerun.txt"
#define N_RERUNS 3

typedef struct {
    const char *sub;
    const double *x;
    char *identity;
    int valid;                   /* the mark matches: nothing to run unless the axes changed */
    double value;                /* the main output of the rerun */
    rf_traj_plot_scales own, drawn;
    rf_traj_point_run *run;
} rerun;

static void scales_write(FILE *f, const char *tag, const rf_traj_plot_scales *sc)
{
    fprintf(f, "%s %zu %.17g %.17g %.17g", tag, sc->runs, sc->height_max, sc->energy_max, sc->runout_count_max);
    for (size_t c = 0; c < RF_TRAJ_SCALE_COLLECTORS; c++)
        fprintf(f, " %.17g %.17g %.17g %.17g", sc->energy_lo[c], sc->energy_hi[c], sc->height_lo[c], sc->height_hi[c]);
    fputc('\n', f);
}

/* The numbers after "TAG " in line into sc; 0 if the line is not that. */
static int scales_read(const char *line, const char *tag, rf_traj_plot_scales *sc)
{
    size_t len = strlen(tag);
    if (strncmp(line, tag, len) || line[len] != ' ')
        return 0;
    char *end;
    sc->runs = strtoul(line + len, &end, 10);
    double *v[3 + 4 * RF_TRAJ_SCALE_COLLECTORS] = {&sc->height_max, &sc->energy_max, &sc->runout_count_max};
    for (size_t c = 0; c < RF_TRAJ_SCALE_COLLECTORS; c++)
        v[3 + 4 * c] = &sc->energy_lo[c], v[4 + 4 * c] = &sc->energy_hi[c], v[5 + 4 * c] = &sc->height_lo[c],
        v[6 + 4 * c] = &sc->height_hi[c];
    for (size_t q = 0; q < sizeof v / sizeof *v; q++) {
        const char *at = end;
        *v[q] = strtod(at, &end);
        if (end == at)
            return 0;
    }
    return 1;
}

static int scales_equal(const rf_traj_plot_scales *a, const rf_traj_plot_scales *b)
{
    int eq = a->height_max == b->height_max && a->energy_max == b->energy_max &&
             a->runout_count_max == b->runout_count_max;
    for (size_t c = 0; c < RF_TRAJ_SCALE_COLLECTORS; c++)
        eq = eq && a->energy_lo[c] == b->energy_lo[c] && a->energy_hi[c] == b->energy_hi[c] &&
             a->height_lo[c] == b->height_lo[c] && a->height_hi[c] == b->height_hi[c];
    return eq;
}

static void scales_merge(rf_traj_plot_scales *into, const rf_traj_plot_scales *from)
{
    into->height_max = fmax(into->height_max, from->height_max);
    into->energy_max = fmax(into->energy_max, from->energy_max);
    into->runout_count_max = fmax(into->runout_count_max, from->runout_count_max);
    for (size_t c = 0; c < RF_TRAJ_SCALE_COLLECTORS; c++) {
        into->energy_lo[c] = into->runs ? fmin(into->energy_lo[c], from->energy_lo[c]) : from->energy_lo[c];
        into->energy_hi[c] = into->runs ? fmax(into->energy_hi[c], from->energy_hi[c]) : from->energy_hi[c];
        into->height_lo[c] = into->runs ? fmin(into->height_lo[c], from->height_lo[c]) : from->height_lo[c];
        into->height_hi[c] = into->runs ? fmax(into->height_hi[c], from->height_hi[c]) : from->height_hi[c];
    }
    into->runs += from->runs;
}

/* "MODEL-IDENTITY | SUB at NAME=X,... plots=P main=OUTPUT" (malloc'ed). */
static char *rerun_identity(const rf_study *s, const rerun *r, int plots, long main_k)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f)
        return NULL;
    fprintf(f, "%s | %s at", s->model.identity ? s->model.identity : "", r->sub);
    for (size_t i = 0; i < s->n_params; i++)
        fprintf(f, " %s=%.17g", s->param_names[i], r->x[i]);
    fprintf(f, " plots=%d main=%s", plots, main_k >= 0 ? s->model.output_names[main_k] : "-");
    fclose(f);
    return buf;
}

/* The folder's mark: valid when it names this identity (value, own and drawn axes read back). */
static void read_mark(const char *dir, rerun *r)
{
    char path[4200], *line = NULL;
    size_t cap = 0;
    snprintf(path, sizeof path, "%s/%s/" RERUN_MARK, dir, r->sub);
    FILE *f = fopen(path, "r");
    int id = 0, val = 0, own = 0, drawn = 0;
    while (f && getline(&line, &cap, f) > 0) {
        line[strcspn(line, "\n")] = '\0';
        if (!strncmp(line, "identity ", 9))
            id = r->identity && !strcmp(line + 9, r->identity);
        else if (!strncmp(line, "value ", 6))
            val = 1, r->value = strtod(line + 6, NULL);
        own = own || scales_read(line, "own", &r->own);
        drawn = drawn || scales_read(line, "drawn", &r->drawn);
    }
    if (f)
        fclose(f);
    free(line);
    r->valid = id && val && own && drawn;
}

static rf_status write_mark(const char *dir, const rerun *r, rf_error *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s/" RERUN_MARK, dir, r->sub);
    FILE *f = fopen(path, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
    fprintf(f, "identity %s\nvalue %.17g\n", r->identity, r->value);
    scales_write(f, "own", &r->own);
    scales_write(f, "drawn", &r->drawn);
    return fclose(f) == 0 ? RF_OK : rf_fail(err, RF_EIO, "cannot write %s", path);
}

/* Run the Monte Carlo of r (its mark goes first: an interrupted folder is never taken as complete). */
static rf_status run_point(const char *dir, const rf_study *s, rerun *r, long main_k, int threads, rf_error *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, r->sub);
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return rf_fail(err, RF_EIO, "cannot create %s: %s", path, strerror(errno));
    snprintf(path, sizeof path, "%s/%s/" RERUN_MARK, dir, r->sub);
    if (unlink(path) != 0 && errno != ENOENT)
        return rf_fail(err, RF_EIO, "cannot replace %s: %s", path, strerror(errno));
    double *y = malloc((s->model.n_outputs ? s->model.n_outputs : 1) * sizeof *y);
    if (!y)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    double xi[SB_MAX_TARGETS];
    const rf_model *m = sb_unwrap(&s->model, r->x, xi); /* a bound study's model drives the trajectory model */
    rf_status st = rf_traj_model_run_at(m, xi, threads, y, &r->run, err);
    if (st == RF_OK) {
        r->value = main_k >= 0 ? y[main_k] : NAN;
        memset(&r->own, 0, sizeof r->own);
        rf_traj_plot_scales_add(&r->own, r->run);
    }
    free(y);
    return st;
}

/* The points: nominal, and with a main output whose level-0 bounds are defined, the bounds' points. */
static size_t rerun_points(const rf_study *s, const rf_tm_result *res, long main_k, const double *nominal,
                           rerun *r)
{
    static const char *const subs[N_RERUNS] = {"nominal", "bound_lower", "bound_upper"};
    size_t n = s->n_params, m = res ? res->levels : 0, count = 1;
    r[0].sub = subs[0], r[0].x = nominal;
    if (main_k >= 0) {
        const double *lo = res->x_lo + (size_t)main_k * (m + 1) * n, *hi = res->x_hi + (size_t)main_k * (m + 1) * n;
        int defined = 1;
        for (size_t i = 0; i < n; i++)
            defined = defined && isfinite(lo[i]) && isfinite(hi[i]);
        if (defined) {
            r[1].sub = subs[1], r[1].x = lo, r[2].sub = subs[2], r[2].x = hi;
            count = 3;
        }
    }
    return count;
}

/* Run what is not valid, then write every folder whose figures are not on the common axes. */
static rf_status rerun_all(const char *dir, const rf_study *s, rerun *r, size_t count, long main_k, int threads,
                           int plots, const atomic_int *interrupt, rf_error *err)
{
    rf_status st = RF_OK;
    rf_traj_plot_scales common;
    memset(&common, 0, sizeof common);
    for (size_t p = 0; p < count && st == RF_OK; p++) {
        if (!r[p].valid && (st = rf_report_stopped(interrupt, "the trajectories at the nominal point and the "
                                                             "bounds", err)) == RF_OK)
            st = run_point(dir, s, &r[p], main_k, threads, err);
        if (st == RF_OK)
            scales_merge(&common, &r[p].own);
    }
    for (size_t p = 0; p < count && st == RF_OK; p++) {
        if (r[p].valid && scales_equal(&r[p].drawn, &common))
            continue;
        if ((st = rf_report_stopped(interrupt, "the trajectory figures", err)) != RF_OK)
            break;
        if (!r[p].run) /* complete, but drawn on other axes: the figures again */
            st = run_point(dir, s, &r[p], main_k, threads, err);
        char sub[4200];
        snprintf(sub, sizeof sub, "%s/%s", dir, r[p].sub);
        r[p].drawn = common;
        if (st == RF_OK)
            st = rf_traj_point_run_write(r[p].run, sub, plots, &common, err);
        if (st == RF_OK)
            st = write_mark(dir, &r[p], err);
    }
    return st;
}

rf_status rf_traj_study_reruns(const char *dir, const rf_study *s, const rf_tm_result *res, int threads, int plots,
                               const atomic_int *interrupt, rf_error *err)
{
    if (s->model_kind != RF_STUDY_MODEL_TRAJECTORY)
        return RF_OK;
    long main_k = res ? rp_main_output(s, res) : -1;
    double *nominal = malloc((s->n_params ? s->n_params : 1) * sizeof *nominal);
    rerun r[N_RERUNS];
    memset(r, 0, sizeof r);
    if (!nominal)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < s->n_params; i++)
        nominal[i] = rf_fuzzy_nominal(&s->inputs[i]);
    size_t count = rerun_points(s, res, main_k, nominal, r);
    rf_status st = RF_OK;
    for (size_t p = 0; p < count && st == RF_OK; p++) {
        if (!(r[p].identity = rerun_identity(s, &r[p], plots, main_k)))
            st = rf_fail(err, RF_ENOMEM, "out of memory");
        else
            read_mark(dir, &r[p]);
    }
    for (size_t p = count; p < N_RERUNS; p++) { /* no bounds to show: none from an earlier run either */
        char path[4200];
        static const char *const subs[N_RERUNS] = {"nominal", "bound_lower", "bound_upper"};
        snprintf(path, sizeof path, "%s/%s/" RERUN_MARK, dir, subs[p]);
        unlink(path);
    }
    if (st == RF_OK)
        st = rerun_all(dir, s, r, count, main_k, threads, plots, interrupt, err);
    for (size_t p = 0; p < N_RERUNS; p++) {
        free(r[p].identity);
        rf_traj_point_run_free(r[p].run);
    }
    free(nominal);
    return st;
}
