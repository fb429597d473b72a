/* model.h - the one interface between the Transformation Method and any model.
 *
 * A model maps a crisp parameter vector x[0..n_inputs-1] to outputs
 * y[0..n_outputs-1].  The TM never knows what it calls (GSL's gsl_function
 * idea): built-in impact models, a typed formula and an external program all
 * sit behind this struct.
 *
 * Binding by name: a model is created for an ordered list of parameter names
 * (the study's fuzzy/crisp parameters); x[i] is the value of names[i].  The
 * constructor rejects a name it does not know.
 *
 * Thread safety: eval may be called concurrently from several threads with
 * the same ctx; each model guarantees this itself (per-thread work areas).
 * eval returns RF_OK or a status with a message in err; it never exits. */
#ifndef ROCKFUZZ_MODEL_H
#define ROCKFUZZ_MODEL_H

#include <stdatomic.h>
#include <stdio.h>

#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef rf_status (*rf_model_eval_fn)(void *ctx, const double *x, double *y, rf_error *err);

/* Rows of doubles a model keeps across runs beside its results (a trajectory
 * model's impact table), in the study's result store: put keeps one row of
 * `width` values under a text key (an identical row once); each calls fn on
 * every row stored under key with that width, in the order stored, and stops
 * at the first status fn returns that is not RF_OK. */
typedef struct {
    void *user;
    rf_status (*put)(void *user, const char *key, const double *row, size_t width, rf_error *err);
    rf_status (*each)(void *user, const char *key, size_t width, rf_status (*fn)(void *u, const double *row),
                      void *u, rf_error *err);
} rf_model_side_store;

typedef struct rf_model {
    size_t n_inputs;
    size_t n_outputs;
    char **output_names;        /* n_outputs names, owned by the model */
    char **output_units;        /* n_outputs unit strings ("" if dimensionless), owned */
    rf_model_eval_fn eval;
    void *ctx;
    void (*destroy)(void *ctx); /* frees ctx; may be NULL */
    char *identity;             /* canonical description of model + settings (for result stores), owned */
    int threads_per_eval;       /* threads one evaluation uses itself (FE solver), >= 1 */
    /* Optional (may be NULL): warnings the model raised during the evaluations
     * made so far in this process (e.g. FE boundary reflections), summarised
     * into buf; returns how many evaluations warned (0: buf is ""). */
    size_t (*warnings)(void *ctx, char *buf, size_t size);
    /* Optional (may be NULL): a flag that asks evaluations in progress to stop
     * early when it becomes non-zero (an external program is killed); they
     * then return RF_EINTERRUPTED.  The flag must outlive the evaluations. */
    void (*set_interrupt)(void *ctx, const atomic_int *flag);
    /* Optional (may be NULL): work deferred from the model's creation to the
     * run (a trajectory model's impact table of FE impacts).  A study run calls
     * it once, after the output folder is locked and the plan accepted, before
     * the first evaluation; it answers the interrupt flag (RF_EINTERRUPTED) and
     * says what it does on log (NULL: silent).  Without it the first
     * evaluation that needs the work does it. */
    rf_status (*prepare)(void *ctx, FILE *log, rf_error *err);
    /* Optional (may be NULL): where the model keeps its side rows (a study
     * run's store), handed before prepare; the store outlives the evaluations. */
    void (*set_side_store)(void *ctx, const rf_model_side_store *store);
    /* Optional (may be NULL): the error of a surrogate the model evaluates on
     * (a trajectory model's impact surrogate: "impact surrogate error R_n ..,
     * R_t .. (...)"), known after prepare, into buf; returns 1 when it has one
     * (0: buf is "").  A result carries it in a field of its own. */
    size_t (*surrogate_error)(void *ctx, char *buf, size_t size);
} rf_model;

/* Evaluate (convenience wrapper checking for NULL and non-finite outputs). */
rf_status rf_model_eval(const rf_model *model, const double *x, double *y, rf_error *err);
/* rf_model_eval over count points x[p*n_inputs..], y[p*n_outputs..] in
 * order; on failure sets *failed to the first failed point's index (a point
 * with an infinite output is found after the evaluations: the points after
 * it may have been evaluated as well). */
rf_status rf_model_eval_many(const rf_model *model, size_t count, const double *x, double *y, size_t *failed,
                             rf_error *err);

/* Hand the model an interrupt flag (no-op when it has no set_interrupt). */
void rf_model_set_interrupt(rf_model *model, const atomic_int *flag);

/* Hand the model its side store (no-op when it has no set_side_store). */
void rf_model_set_side_store(rf_model *model, const rf_model_side_store *store);

/* Do the model's deferred work (see prepare; RF_OK when it has none). */
rf_status rf_model_prepare(rf_model *model, FILE *log, rf_error *err);

/* Free everything the model owns (calls destroy); safe on a zeroed struct. */
void rf_model_free(rf_model *model);

/* Helpers for model implementations: allocate names/units/identity. */
rf_status rf_model_init_outputs(rf_model *model, size_t n_outputs, const char *const *names,
                                const char *const *units, rf_error *err);
rf_status rf_model_set_identity(rf_model *model, const char *identity, rf_error *err);


/* ---- Formula model (src/model/formula.c): expressions typed by the user,
 * parsed once by muParser; one parser per thread.  Every identifier must be a
 * parameter name (the message names output, identifier and position). */
rf_status rf_formula_model_create(size_t n_params, const char *const *param_names, size_t n_outputs,
                                  const char *const *output_names, const char *const *expressions,
                                  rf_model *model, rf_error *err);

/* ---- External-program model (src/model/external.c).  No shell is involved:
 * argv is executed directly after replacing {name} placeholders by the
 * parameter values (%.17g).  Each evaluation runs in a fresh working
 * directory under workdir_root into which the templates (with the same
 * placeholders) are written.  Each output is read from the program's stdout
 * or from a file in the working directory, either as the number following
 * "NAME =" / "NAME:" on a line, or with a POSIX extended regex whose first
 * capture group is the number. */
typedef struct {
    char *name;        /* output name */
    char *file;        /* NULL = stdout, else a file name relative to the working directory */
    char *pattern;     /* NULL = "NAME = value" lookup; else ERE with one capture group */
    char *unit;        /* may be NULL */
} rf_external_output;

typedef struct {
    size_t argc;
    char **argv;                  /* argv[0] is the program (PATH is searched) */
    size_t n_templates;
    char **template_src;          /* template file paths (already resolved) */
    char **template_dst;          /* file names inside the working directory */
    size_t n_outputs;
    rf_external_output *outputs;
    double timeout;               /* seconds per evaluation, 0 = none */
    char *workdir_root;           /* parent of the per-evaluation directories */
    int keep_workdirs;            /* keep them (else removed after success) */
} rf_external_spec;

rf_status rf_external_model_create(const rf_external_spec *spec, size_t n_params,
                                   const char *const *param_names, rf_model *model, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
