/* bind.h - how a study's fuzzy parameters drive a model's inputs (`bind:` of
 * the impact, program and trajectory blocks; docs/user-guide.md sec. 1.5).
 *
 * A parameter drives one input or several (a list), each as value * scale +
 * offset.  The model is constructed for its inputs (the targets, in order);
 * when the binding is not the identity, the study's model wraps it and maps
 * the parameter vector onto the inputs.  Every check happens at load time:
 * an input driven twice, a parameter driving nothing, and the joint
 * admissibility of the parameters' support corners (sb_check_box). */
#ifndef ROCKFUZZ_STUDY_BIND_H
#define ROCKFUZZ_STUDY_BIND_H

#include "study/study_internal.h"

/* At most this many inputs in all (a parameter may drive several). */
#define SB_MAX_TARGETS 256
/* All 2^k corners of the parameter box are checked up to k = SB_CORNER_DIM;
 * above it SB_CORNER_SAMPLE corners from a fixed sequence plus the all-low
 * and all-high corners. */
#define SB_CORNER_DIM 12
#define SB_CORNER_SAMPLE 4096

typedef struct {
    size_t param;            /* the study parameter driving it */
    char *to;                /* the model input: a name or a path */
    double scale, offset;    /* input = value * scale + offset */
    int line;                /* where it is written */
} sb_target;

typedef struct {
    size_t n;
    sb_target *t;            /* by parameter, then in the order written */
} sb_binding;

/* NULL when `to` names an input of the model; else why not (into buf). */
typedef const char *(*sb_check_fn)(void *user, const char *to, char *buf, size_t size);

/* Parse `bind` (NULL: none) found at `path`.  self: a parameter without an
 * entry drives the input of its own name (impact, program); otherwise it is
 * refused as bound to nothing (trajectory). */
rf_status sb_parse(yr_ctx *c, struct fy_node *bind, const char *path, const rf_study *s, int self,
                   sb_check_fn check, void *user, sb_binding *b);
void sb_free(sb_binding *b);

/* The targets' names in order (pointers into b), for the model constructors. */
const char **sb_names(const sb_binding *b);
/* "to" of every target of parameter i, joined by ", " into buf. */
const char *sb_targets_of(const sb_binding *b, size_t i, char *buf, size_t size);

/* xi[j] = x[t[j].param] * t[j].scale + t[j].offset. */
void sb_expand(const sb_binding *b, const double *x, double *xi);

/* *model was built for b's targets: unless b is the identity, replace it by a
 * model of the study's n_params parameters that drives it (owns it). */
rf_status sb_wrap(const sb_binding *b, size_t n_params, rf_model *model, rf_error *err);

/* The model that sb_wrap wrapped (or m itself) and x mapped onto its inputs
 * in xi (room for SB_MAX_TARGETS values). */
const rf_model *sb_unwrap(const rf_model *m, const double *x, double *xi);

/* Validation of one input vector by the model's own rules, no run. */
typedef rf_status (*sb_validate_fn)(void *user, const double *xi, rf_error *err);

/* Joint admissibility before any evaluation: the nominal point, each
 * parameter's support ends (alpha = 0) with the others nominal, then the
 * corners of the box of support ends (SB_CORNER_DIM).  A refusal names the
 * file, line, the values and the model's message; `at` locates the messages
 * that concern no single parameter. */
rf_status sb_check_box(yr_ctx *c, struct fy_node *at, const char *path, const rf_study *s, const sb_binding *b,
                       sb_validate_fn validate, void *user);

/* The scheme a study runs and why (s->scheme_set: as the file says), one line
 * for the console, result.json and the report (docs/user-guide.md 1.2). */
void sb_default_scheme(rf_study *s);

#endif
