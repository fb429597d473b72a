/* fem_plastic_inputs.h - the inputs shared by tests/test_fem_plastic.c (logic,
 * coarse meshes) and tests/test_fem_plastic_accuracy.c (against closed forms
 * at the meshes those need): nominal granite and the axisymmetric options. */
#ifndef ROCKFUZZ_FEM_PLASTIC_INPUTS_H
#define ROCKFUZZ_FEM_PLASTIC_INPUTS_H

#include "rockfuzz/fem.h"

static inline rf_impact_input granite(double v)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = v;
    return in;
}

static inline rf_fem_options coarse(double refinement)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = refinement;
    o.domain_factor = 10;
    /* the small-strain kernel that sections 2-6d of docs/validation-plastic.md validate (the
       default, auto, runs a plastic body in large deformation: tests/test_fem_large.c); also
       keeps this suite inside the CI's time under AddressSanitizer (4x the cost per step) */
    o.large_deformation = RF_FEM_SMALL_STRAIN;
    return o;
}

#endif
