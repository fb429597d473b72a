/* impact_model.h - the impact model that a study binds fuzzy parameters to:
 * a spec (which solver, the crisp base input, the solver settings), the one
 * dispatch rf_impact_solve that computes one impact with any solver, and the
 * rf_model adapter (parameter binding, identity, FE warnings).
 *
 * Layering: impact.h (the problem and the analytic references) <- fem.h /
 * fem3d.h (the FE solvers) <- this header <- study.  The FE settings are the
 * solvers' own rf_fem_options (no mirror): their defaults and validation live
 * in fem.h.  Units SI. */
#ifndef ROCKFUZZ_IMPACT_MODEL_H
#define ROCKFUZZ_IMPACT_MODEL_H

#include "rockfuzz/fem.h"
#include "rockfuzz/impact.h"
#include "rockfuzz/model.h"
#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RF_IMPACT_FEM = 0,  /* explicit finite elements (rockfuzz/fem.h, rf_fem_solve) */
    RF_IMPACT_HERTZ,    /* elastic Hertz: R_n = 1 */
    RF_IMPACT_HUNTER,   /* Hertz + Hunter wave loss */
    RF_IMPACT_RIGID,    /* rigid-body oblique impact with Coulomb friction, e_n given */
    RF_IMPACT_MDR       /* Hertz + Mindlin-Deresiewicz partial slip (rockfuzz/mdr.h), e_n given */
} rf_impact_solver;

/* The registry of solvers (rf_impact_law, impact.h), in rf_impact_solver
 * order: their number, and solver s's entry (NULL out of range). */
size_t rf_impact_n_solvers(void);
const rf_impact_law *rf_impact_solver_law(rf_impact_solver s);

/* "fem" | "hertz" | "hunter" | "rigid" | "mdr" <-> enum (the registry's names). */
const char *rf_impact_solver_name(rf_impact_solver s);
rf_status rf_impact_solver_parse(const char *name, rf_impact_solver *s, rf_error *err);

typedef struct {
    rf_impact_solver solver;
    rf_impact_input base;          /* crisp values of the inputs not bound to parameters (SI, angle in rad) */
    double e_n;                    /* rigid solver: normal COR; NaN = Hunter's e_n from the current inputs */
    double hunter_coefficient;     /* A of Hunter's loss (hunter solver, and rigid with e_n = NaN) */
    rf_fem_options fem;            /* FE settings (fem solver); fem.vtk_dir is ignored by the model */
} rf_impact_model_spec;

/* Defaults: FEM solver, nominal granite, e_n = NaN (Hunter), A = 1.04,
 * rf_fem_options_default. */
void rf_impact_model_spec_default(rf_impact_model_spec *spec);

/* Check the spec's own settings (solver, e_n, A, and the FE options). */
rf_status rf_impact_model_spec_validate(const rf_impact_model_spec *spec, rf_error *err);

/* Compute one impact: the spec's solver and settings on the input `in`
 * (validated here).  The one public entry for "one impact, any solver". */
rf_status rf_impact_solve(const rf_impact_model_spec *spec, const rf_impact_input *in,
                          rf_impact_output *out, rf_error *err);

/* Create the impact model: x[i] is the value of param_names[i] (one of
 * the bindable rows of rf_impact_fields (impact.h; angles in degrees); an
 * unknown or repeated name is RF_EINVAL).  Outputs, rf_impact_output_fields:
 * contact_force_max [N], compression_max [m], contact_duration [s],
 * contact_radius [m], R_n, R_t, R_ke [-], plastic_work [-, fraction of the
 * initial KE], penetration_max [m], indentation_depth [m],
 * equivalent_plastic_strain_max [-] (NaN for the analytic solvers).  eval copies spec->base, overwrites
 * the bound inputs, validates them and runs the solver; thread-safe.  Free
 * with rf_model_free. */
rf_status rf_impact_model_create(const rf_impact_model_spec *spec, const char *const *param_names,
                                 size_t n_params, rf_model *model, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
