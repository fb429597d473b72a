/* bind_check.c - what a study checks about its bound parameters before any
 * evaluation: their joint admissibility at the corners of the parameter box
 * (by the model's validation, no run), and the scheme that runs and why. */
#include "study/bind.h"
#include "rockfuzz/fuzzy.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

static rf_status try_point(const sb_binding *b, const double *x, sb_validate_fn validate, void *user, rf_error *tmp)
{
    double xi[SB_MAX_TARGETS];
    sb_expand(b, x, xi);
    return validate(user, xi, tmp);
}

/* Each parameter at its support ends with the others nominal: the message names the parameter. */
static rf_status check_ends(yr_ctx *c, const rf_study *s, const sb_binding *b, sb_validate_fn validate,
                            void *user, double *x, const double *lo, const double *hi)
{
    rf_error tmp;
    char to[1024];
    for (size_t i = 0; i < s->n_params; i++) {
        double keep = x[i], ends[2] = {lo[i], hi[i]};
        for (int e = 0; e < 2; e++) {
            x[i] = ends[e];
            if (try_point(b, x, validate, user, &tmp) != RF_OK)
                return rf_fail(c->err, RF_EINVAL, "%s:%d: parameters.%s: the value %.17g (bound to %s) is not "
                               "admissible: %s", c->file, s->param_line[i], s->param_names[i], ends[e],
                               sb_targets_of(b, i, to, sizeof to), tmp.msg);
        }
        x[i] = keep;
    }
    return RF_OK;
}

static uint64_t splitmix64(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* Corner number k of the box in n dimensions as a bit mask (bit i: parameter i at its high end). */
static uint64_t corner(size_t n, uint64_t k)
{
    if (n <= SB_CORNER_DIM || k == 0)
        return k;
    uint64_t all = n >= 64 ? ~0ULL : (1ULL << n) - 1;
    return k == 1 ? all : splitmix64(k) & all;
}

static rf_status corner_fail(yr_ctx *c, struct fy_node *at, const char *path, const rf_study *s, uint64_t mask,
                             const double *x, const rf_error *tmp)
{
    char buf[1024];
    size_t len = 0;
    for (size_t i = 0; i < s->n_params && len < sizeof buf; i++)
        len += (size_t)snprintf(buf + len, sizeof buf - len, "%s%s = %.12g (%s)", i ? ", " : "", s->param_names[i],
                                x[i], mask >> i & 1 ? "high end" : "low end");
    return rf_fail(c->err, RF_EINVAL, "%s:%d: %s: the model refuses a corner of the parameter box (alpha = 0) "
                   "although each support end alone is admissible: %s; the corner: %s (the TM evaluates every "
                   "corner: narrow a support or bind differently)", c->file, yr_line(at), path, tmp->msg, buf);
}

static rf_status check_corners(yr_ctx *c, struct fy_node *at, const char *path, const rf_study *s,
                               const sb_binding *b, sb_validate_fn validate, void *user, double *x,
                               const double *lo, const double *hi)
{
    size_t n = s->n_params;
    uint64_t count = n <= SB_CORNER_DIM ? 1ULL << n : SB_CORNER_SAMPLE + 2;
    rf_error tmp;
    for (uint64_t k = 0; k < count; k++) {
        uint64_t mask = corner(n, k);
        for (size_t i = 0; i < n; i++)
            x[i] = mask >> i & 1 ? hi[i] : lo[i];
        if (try_point(b, x, validate, user, &tmp) != RF_OK)
            return corner_fail(c, at, path, s, mask, x, &tmp);
    }
    return RF_OK;
}

rf_status sb_check_box(yr_ctx *c, struct fy_node *at, const char *path, const rf_study *s, const sb_binding *b,
                       sb_validate_fn validate, void *user)
{
    double x[64], lo[64], hi[64];
    rf_error tmp;
    if (s->n_params > 64)
        return rf_fail(c->err, RF_EINTERNAL, "%s: more than 64 parameters", c->file);
    for (size_t i = 0; i < s->n_params; i++) {
        x[i] = rf_fuzzy_nominal(&s->inputs[i]);
        rf_fuzzy_cut(&s->inputs[i], 0.0, &lo[i], &hi[i]);
    }
    if (try_point(b, x, validate, user, &tmp) != RF_OK)
        return rf_fail(c->err, RF_EINVAL, "%s:%d: %s: with every parameter at its nominal value the model's "
                       "inputs are not admissible: %s", c->file, yr_line(at), path, tmp.msg);
    rf_status st = check_ends(c, s, b, validate, user, x, lo, hi);
    if (st == RF_OK && s->n_params > 1)
        st = check_corners(c, at, path, s, b, validate, user, x, lo, hi);
    return st;
}

void sb_default_scheme(rf_study *s)
{
    if (s->scheme_set) {
        s->scheme_reason = "set in the study file (scheme:)";
        return;
    }
    switch (s->model_kind) {
    case RF_STUDY_MODEL_TRAJECTORY:
        s->scheme = RF_TM_GENERAL;
        s->scheme_reason = "default for a trajectory model: its outputs are not monotonic in its inputs (a small "
                           "change moves an impact onto another segment)";
        break;
    case RF_STUDY_MODEL_PROGRAM:
        s->scheme = RF_TM_GENERAL;
        s->scheme_reason = "default for a program model: nothing shows that its outputs are monotonic in the "
                           "parameters";
        break;
    default:
        s->scheme = RF_TM_REDUCED;
        s->scheme_reason = s->left_right
                               ? "default for formula and impact models: exact where each output is monotonic in "
                                 "each parameter, which the left/right grid checks (set scheme: general if not)"
                               : "default for formula and impact models: exact where each output is monotonic in "
                                 "each parameter, unchecked here (options.left_right: false)";
        break;
    }
}
