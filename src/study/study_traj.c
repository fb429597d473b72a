/* study_traj.c - the `model: {trajectory: ...}` block of a study file
 * (docs/trajectories.md sec. 5): the trajectory file, Monte Carlo overrides,
 * and the binding of every fuzzy parameter to a numeric input of that file.
 * Trajectory outputs are not monotonic in their inputs (a small change moves
 * an impact onto another segment), so unless the study names a scheme the
 * general form is used; the left/right grid keeps the monotonicity check on. */
#include "study/study_internal.h"
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

/* The path bound to parameter `name`, checked against the spec. */
static rf_status bound_path(yr_ctx *c, traj_block *b, rf_traj_spec *spec, const rf_study *s, size_t i,
                            char **out)
{
    struct fy_node *v = b->bind ? fy_node_mapping_lookup_by_string(b->bind, s->param_names[i], FY_NT) : NULL;
    char p[300];
    yr_pathf(p, sizeof p, "model.trajectory.bind.%s", s->param_names[i]);
    if (!v)
        return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: not bound to an input of the trajectory file "
                       "(model.trajectory.bind: {%s: materials.NAME.R_n, ...})", c->file, s->param_line[i],
                       s->param_names[i], s->param_names[i]);
    rf_status st = yr_string_dup(c, v, p, out);
    if (st != RF_OK)
        return st;
    char why[2400];
    if (!rf_traj_path_bindable(spec, *out, why, sizeof why))
        return yr_fail(c, v, p, "%s (%s)", why, b->file);
    return RF_OK;
}

/* The nominal values and every support end of each parameter must give a valid spec. */
static rf_status check_support(yr_ctx *c, rf_traj_spec *spec, const rf_study *s, char **paths)
{
    for (size_t i = 0; i < s->n_params; i++)
        rf_traj_spec_set(spec, paths[i], rf_fuzzy_nominal(&s->inputs[i]));
    for (size_t i = 0; i < s->n_params; i++) {
        double lo, hi, keep;
        rf_traj_spec_get(spec, paths[i], &keep); /* as given: an angle in degrees */
        rf_fuzzy_cut(&s->inputs[i], 0.0, &lo, &hi);
        double ends[3] = {keep, lo, hi};
        for (int e = 0; e < 3; e++) {
            rf_traj_spec_set(spec, paths[i], ends[e]);
            rf_error tmp;
            if (rf_traj_spec_validate(spec, &tmp) != RF_OK)
                return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: the value %.17g (bound to %s) is not "
                               "admissible: %s", c->file, s->param_line[i], s->param_names[i], ends[e], paths[i],
                               tmp.msg);
        }
        rf_traj_spec_set(spec, paths[i], keep);
    }
    return RF_OK;
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

rf_status rf_traj_study_parse(yr_ctx *c, struct fy_node *n, rf_study *s)
{
    traj_block b = {NULL, -1, -1, -1, NULL, NULL};
    rf_traj_spec spec;
    memset(&spec, 0, sizeof spec);
    char **paths = calloc(s->n_params ? s->n_params : 1, sizeof *paths);
    rf_status st = paths ? read_block(c, n, &b) : rf_fail(c->err, RF_ENOMEM, "out of memory");
    if (st == RF_OK)
        st = load_spec(c, &b, &spec);
    for (size_t i = 0; i < s->n_params && st == RF_OK; i++)
        st = bound_path(c, &b, &spec, s, i, &paths[i]);
    if (st == RF_OK)
        st = check_support(c, &spec, s, paths);
    if (st == RF_OK &&
        (st = rf_traj_model_create(&spec, s->n_params, (const char *const *)s->param_names,
                                   (const char *const *)paths, &s->model, c->err)) != RF_OK)
        st = yr_prefix(c, n, "model.trajectory");
    if (st == RF_OK) {
        s->model_kind = RF_STUDY_MODEL_TRAJECTORY;
        struct fy_node *root = fy_document_root(fy_node_document(n));
        if (!fy_node_mapping_lookup_by_string(root, "scheme", FY_NT))
            s->scheme = RF_TM_GENERAL; /* not monotonic: the general form unless the study says otherwise */
        char d[512];
        snprintf(d, sizeof d, "trajectory: %s, %zu samples per point, seed %llu (common random numbers)%s", b.file,
                 spec.samples, (unsigned long long)spec.seed, spec.lhs ? ", Latin hypercube" : "");
        if (!(s->model_description = rf_strdup(d)))
            st = rf_fail(c->err, RF_ENOMEM, "out of memory");
    }
    for (size_t i = 0; paths && i < s->n_params; i++)
        free(paths[i]);
    free(paths);
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
    double *x = malloc((s->n_params ? s->n_params : 1) * sizeof *x);
    if (!x)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < s->n_params; i++)
        x[i] = rf_fuzzy_nominal(&s->inputs[i]);
    rf_status st = rf_traj_model_write_run(&s->model, x, sub, threads, plots, err);
    free(x);
    return st;
}
