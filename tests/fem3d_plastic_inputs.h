/* fem3d_plastic_inputs.h - shared by tests/test_fem3d_plastic.c (logic, coarse
 * meshes, short runs) and tests/test_fem3d_plastic_accuracy.c (against the
 * axisymmetric model and the elastic one), and by fem3d_layer_inputs.h:
 * granite, options, one 3D run.
 * Include after cmocka.h. */
#ifndef ROCKFUZZ_FEM3D_PLASTIC_INPUTS_H
#define ROCKFUZZ_FEM3D_PLASTIC_INPUTS_H

#include "rockfuzz/fem3d.h"
#include "fem/fem_tuning.h"

#define DEG (3.14159265358979323846 / 180)

static inline rf_impact_input granite(double angle_deg, double f)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = 10, in.slope_angle = angle_deg * DEG, in.friction = f;
    return in;
}

/* small strain: the kernel that sections 9 and 9b of docs/validation-plastic.md validate (the default,
   auto, runs a plastic body in large deformation: tests/test_fem3d_large*.c, section 9c), as the
   axisymmetric tests' coarse() (fem_plastic_inputs.h) */
static inline rf_fem_options coarse(double ref)
{
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = ref, o.domain_factor = 10, o.threads = 1, o.large_deformation = RF_FEM_SMALL_STRAIN;
    return o;
}

/* One 3D run with explicit 3D options (NULL: the defaults); hash may be NULL. */
static inline void run3d_ex(const rf_impact_input *in, const rf_fem_options *o, const rf_fem3d_options *o3,
                            rf_impact_output *out, rf_fem_history *hist, uint64_t *hash)
{
    rf_error err = {0};
    rf_fem3d_report rep = {0};
    rf_status st = rf_fem3d_impact_ex(in, o, o3, out, hist, &rep, &err);
    if (st != RF_OK)
        print_error("fem3d: %s\n", err.msg);
    assert_int_equal(st, RF_OK);
    if (hash)
        *hash = rep.state_hash;
    rf_fem3d_report_free(&rep);
}

static inline void run3d(const rf_impact_input *in, const rf_fem_options *o, rf_impact_output *out,
                         rf_fem_history *hist, uint64_t *hash)
{
    run3d_ex(in, o, NULL, out, hist, hash);
}

#endif
