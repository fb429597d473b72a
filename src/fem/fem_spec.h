/* fem_spec.h - the body specifications of an axisymmetric impact mesh
 * (fine-core size and count from the Hertz contact radius, grading, far
 * size), computed in one place so that benches and tests build exactly the
 * mesh the solver runs on.  Internal header. */
#ifndef ROCKFUZZ_FEM_SPEC_H
#define ROCKFUZZ_FEM_SPEC_H

#include "fem_internal.h"
#include "rockfuzz/fem.h"

/* Fills the boulder and slope specs as rf_fem_impact does for (in, o).
 * Returns RF_EINVAL (message in err) where the solver refuses the sizes. */
rf_status fem_impact_mesh_spec(const rf_impact_input *in, const rf_fem_options *o, fem_body_spec *boulder,
                               fem_body_spec *slope, rf_error *err);

#endif
