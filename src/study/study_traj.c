/* study_traj.c - the `model: {trajectory: ...}` block of a study file
 * (docs/trajectories.md sec. 5): the trajectory file, Monte Carlo overrides,
 * and the binding of every fuzzy parameter to a numeric input of that file.
 * A parameter may drive several inputs, each as value * scale + offset
 * (bind.h); the general form is the default scheme (bind_check.c). */
#include "study/study_internal.h"
#include "study/bind.h"
#include "core/util.h"
#include "rockfuzz/fuzzy.h"
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
    struct fy_node *bind, *file_node;
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
        } else {
            st = yr_fail(c, k, p, "unknown key; a trajectory model takes file, samples, seed, sampling, bind");
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
    if (st != RF_OK)
        return yr_prefix(c, n, "model.trajectory");
    return sb_wrap(bind, s->n_params, &s->model, c->err);
}

rf_status rf_traj_study_parse(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    traj_block b = {NULL, -1, -1, -1, NULL, NULL};
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

rf_status rf_traj_study_nominal(const char *dir, const rf_study *s, int threads, int plots, rf_error *err)
{
    if (s->model_kind != RF_STUDY_MODEL_TRAJECTORY)
        return RF_OK;
    char sub[4096], old[4200];
    snprintf(sub, sizeof sub, "%s/nominal", dir);
    snprintf(old, sizeof old, "%s/trajectory_profile.png", sub);
    if (mkdir(sub, 0777) != 0 && errno != EEXIST)
        return rf_fail(err, RF_EIO, "cannot create %s: %s", sub, strerror(errno));
    unlink(old); /* the study report embeds it only if this run wrote it */
    double x[64], xi[SB_MAX_TARGETS];
    for (size_t i = 0; i < s->n_params && i < 64; i++)
        x[i] = rf_fuzzy_nominal(&s->inputs[i]);
    const rf_model *m = sb_unwrap(&s->model, x, xi); /* a bound study's model drives the trajectory model */
    return rf_traj_model_write_run(m, xi, sub, threads, plots, err);
}
