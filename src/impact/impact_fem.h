/* impact_fem.h - glue between the impact model and the FE solver, compiled
 * only when rockfuzz/fem.h exists (RF_HAVE_FEM).  Used by impact_model.c and
 * by the CLI, which also wants the FE history for its diagnostics. */
#ifndef ROCKFUZZ_IMPACT_FEM_H
#define ROCKFUZZ_IMPACT_FEM_H

#include "rockfuzz/impact.h"

#if defined(__has_include)
#if __has_include("rockfuzz/fem.h")
#include "rockfuzz/fem.h"
#define RF_HAVE_FEM 1
#endif
#endif

#ifdef RF_HAVE_FEM
/* rf_fem_options_default, then the spec's FE settings on top. */
void rf_impact_fem_options_(const rf_impact_model_spec *spec, rf_fem_options *opt);
#endif

#endif
