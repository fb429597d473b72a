/* fem_plastic_inputs.h - the inputs shared by tests/test_fem_plastic.c (logic,
 * coarse meshes) and tests/test_fem_plastic_accuracy.c (against closed forms
 * at the meshes those need), and by tests/test_fem_large*.c (axi_options):
 * nominal granite and the axisymmetric options. */
#ifndef ROCKFUZZ_FEM_PLASTIC_INPUTS_H
#define ROCKFUZZ_FEM_PLASTIC_INPUTS_H

#include "rockfuzz/fem.h"
#include "fem/fem_tuning.h"

static inline rf_impact_input granite(double v)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = v;
    return in;
}

/* Axisymmetric options at a refinement, the seed paper's 10 r0 domain, the given kinematics. */
static inline rf_fem_options axi_options(double refinement, rf_fem_kinematics kin)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = refinement;
    o.domain_factor = 10;
    o.large_deformation = kin;
    return o;
}

/* the small-strain kernel that sections 2-6d of docs/validation-plastic.md validate (the
   default, auto, runs a plastic body in large deformation: tests/test_fem_large.c); also
   keeps this suite inside the CI's time under AddressSanitizer (4x the cost per step) */
static inline rf_fem_options coarse(double refinement)
{
    return axi_options(refinement, RF_FEM_SMALL_STRAIN);
}

#endif
