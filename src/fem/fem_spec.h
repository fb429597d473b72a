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

/* The contact that sizes the axisymmetric mesh of a thick layer when
 * o->mesh_sizing is RF_FEM_SIZING_SOIL: 1 with *a = the layer contact's radius sqrt(R d)
 * and *zone = the radius its uniform zone must cover (f3_layer_contact_estimate,
 * fem3d_spec.h), 0 (a, zone untouched) without a layer, with the option off,
 * or when the layer is thin (the boulder reaches the rock's influence).
 * docs/soil-impacts.md. */
int fem_soil_contact_zone(const rf_impact_input *in, const rf_fem_options *o, double *a, double *zone);

#endif
