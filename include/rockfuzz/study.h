/* study.h - study files: a YAML description of one fuzzy analysis (inputs,
 * scheme, levels, model, options), parsed and validated completely before
 * anything is evaluated.
 *
 * Every error message names the file, line, field and value, e.g.
 *   study.yaml:7: parameters.x1.tfn[1] = -1: the left deviation must be >= 0
 * The file format is documented in docs/user-guide.md and `rockfuzz run --help`. */
#ifndef ROCKFUZZ_STUDY_H
#define ROCKFUZZ_STUDY_H

#include "rockfuzz/fuzzy.h"
#include "rockfuzz/model.h"
#include "rockfuzz/status.h"
#include "rockfuzz/tm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RF_STUDY_MODEL_FORMULA = 0,  /* model: {formula: {out: "expr", ...}} */
    RF_STUDY_MODEL_PROGRAM,      /* model: {program: {argv: [...], ...}} */
    RF_STUDY_MODEL_IMPACT,       /* model: {impact: {solver: ..., ...}} */
    RF_STUDY_MODEL_TRAJECTORY    /* model: {trajectory: {file: ..., bind: ...}} (src/trajectory/traj_study.c) */
} rf_study_model_kind;

/* Largest accepted `levels` (m); the TM's cost is bounded separately by the cap. */
#define RF_STUDY_MAX_LEVELS 1000

typedef struct {
    char *path;                  /* file name as given (used in messages) */
    char *dir;                   /* directory of the study file (relative paths resolve here) */
    char *name;                  /* `name:`, default: file name without extension */
    rf_tm_scheme scheme;         /* default: general for program and trajectory models, else reduced */
    int scheme_set;              /* the file sets `scheme:` */
    const char *scheme_reason;   /* why this scheme runs, one line (static text) */
    size_t levels;               /* m, default 10 */

    /* Parameters in file order; the model's x[i] is params[i]. */
    size_t n_params;
    char **param_names;
    char **param_units;          /* "" when not given */
    char **param_shapes;         /* the shape as written, e.g. "tfn(2, 1, 1)" */
    rf_fuzzy *inputs;            /* the fuzzy numbers handed to the TM */
    rf_monotonicity *param_class;/* forced class (extended form), RF_MONO_AUTO = probe */
    int *param_line;             /* 1-based line of each parameter */

    rf_study_model_kind model_kind;
    rf_model model;              /* constructed and ready to evaluate */
    char *model_description;     /* one line, e.g. "formula: y = x1*x2" */
    long main_output;            /* `main_output:` as an output index, -1 when not given: the report's
                                  * headline and a trajectory study's bound reruns (rp_main_output) */
    /* A trajectory study of a terrain file: the hazard bands made fuzzy per
     * cell (model.trajectory.rasters.fuzzy; default reach_probability and
     * energy_p95), none for a profile (docs/fuzzy-hazard.md). */
    char **fuzzy_rasters;
    size_t n_fuzzy_rasters;

    /* options: */
    size_t max_evaluations;      /* cap on distinct evaluations, 0 = none (default 100000) */
    int left_right;              /* evaluate the three-point grid (default 1) */
    int jobs;                    /* worker threads, 0 = automatic (default) */
} rf_study;

/* Parse and validate the study file at `path` and construct its model.  On
 * failure *study is left empty (safe to free) and err names file:line. */
rf_status rf_study_load(const char *path, rf_study *study, rf_error *err);

/* The same from a buffer; `name` is used in messages and its directory as the
 * base of relative paths (NULL: "<buffer>", base "."). */
rf_status rf_study_load_buffer(const char *name, const char *buf, size_t len, rf_study *study,
                               rf_error *err);

/* Fill TM options from the study (scheme, levels, cap, left_right, classes). */
void rf_study_tm_options(const rf_study *study, rf_tm_options *opt);

void rf_study_free(rf_study *study);

const char *rf_study_model_kind_name(rf_study_model_kind k);

#ifdef __cplusplus
}
#endif
#endif
