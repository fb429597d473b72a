/* fem3d_spec.h - the mesh specification of a 3D impact (fine-box counts and
 * size from the Hertz contact radius, layer settings), computed in one place
 * so that benches and tests build exactly the mesh the solver runs on.
 * Internal header. */
#ifndef ROCKFUZZ_FEM3D_SPEC_H
#define ROCKFUZZ_FEM3D_SPEC_H

#include "fem3d_internal.h"
#include "rockfuzz/fem3d.h"

/* Fills *ms (and the contact element size h [m] and Hertz radius a [m]) as
 * rf_fem3d_impact_ex does for (in, o, o3).  Does not validate the inputs. */
void f3_impact_mesh_spec(const rf_impact_input *in, const rf_fem_options *o, const rf_fem3d_options *o3,
                         f3_mesh_spec *ms, double *h, double *a_hertz);

#endif
