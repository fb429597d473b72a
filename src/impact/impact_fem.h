/* impact_fem.h - glue between the impact model and the FE solvers, compiled
 * only when rockfuzz/fem.h exists (RF_HAVE_FEM).  One dispatch decides which
 * FE model an impact needs, for the study model and the CLI alike:
 *   - axisymmetric (fem.h) for a normal impact in which friction cannot act;
 *   - 3D half model (fem3d.h) for an inclined slope, or a normal impact with
 *     friction between elastically dissimilar bodies (Dundurs beta != 0: the
 *     two surfaces would slip radially against each other). */
#ifndef ROCKFUZZ_IMPACT_FEM_H
#define ROCKFUZZ_IMPACT_FEM_H

#include "rockfuzz/impact.h"

#if defined(__has_include)
#if __has_include("rockfuzz/fem.h")
#include "rockfuzz/fem.h"
#define RF_HAVE_FEM 1
#endif
#if __has_include("rockfuzz/fem3d.h")
#include "rockfuzz/fem3d.h"
#define RF_HAVE_FEM3D 1
#endif
#endif

/* Default a/h when the spec leaves refinement at 0: the axisymmetric solver
 * is converged to < 0.1 % at 10; the 3D one costs ~50x more per a/h and is
 * within 0.3 % on R_t at 6 (docs/validation*.md). */
#define RF_IMPACT_FEM_REFINEMENT_AXI 10.0
#define RF_IMPACT_FEM_REFINEMENT_3D 6.0

/* 1 if the impact needs the 3D model (see above). */
int rf_impact_fem_needs_3d_(const rf_impact_input *in);

/* The refinement actually used for this impact. */
double rf_impact_fem_refinement_(const rf_impact_model_spec *spec, int three_d);

#ifdef RF_HAVE_FEM
/* rf_fem_options_default, then the spec's FE settings on top. */
void rf_impact_fem_options_(const rf_impact_model_spec *spec, int three_d, rf_fem_options *opt);

/* Run the FE model the impact needs.  hist may be NULL; friction_work (may
 * be NULL) receives the Coulomb dissipation [J] (0 for the axisymmetric
 * model); *three_d (may be NULL) says which model ran. */
rf_status rf_impact_fem_run_(const rf_impact_model_spec *spec, const rf_impact_input *in, rf_impact_output *out,
                             rf_fem_history *hist, double *friction_work, int *three_d, rf_error *err);
#endif

#endif
