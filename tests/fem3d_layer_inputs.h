/* fem3d_layer_inputs.h - shared by tests/test_fem3d_layer.c (logic, coarse
 * and short) and tests/test_fem3d_layer_accuracy.c (against Hertz, a very
 * stiff boulder and the axisymmetric model): a result line and the
 * Drucker-Prager layer, over fem3d_plastic_inputs.h's granite inputs, coarse
 * options and 3D run.  Include after cmocka.h. */
#ifndef ROCKFUZZ_FEM3D_LAYER_INPUTS_H
#define ROCKFUZZ_FEM3D_LAYER_INPUTS_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rockfuzz/impact_model.h"

#include "fem3d_plastic_inputs.h" /* granite, coarse, run3d_ex */

static inline void show(const char *name, const rf_impact_output *o)
{
    print_message("%-28s R_n %.5f R_t %.5f R_ke %.5f F_max %.4g N t_c %.4g s W_p %.4f pen %.3f mm crater %.3f mm "
                  "err %.2e (%.2f s)\n", name, o->R_n, o->R_t, o->R_ke, o->contact_force_max, o->contact_duration,
                  o->plastic_work, 1e3 * o->penetration_max, 1e3 * o->indentation_depth, o->energy_error,
                  o->wall_seconds);
}

/* A Drucker-Prager layer with a cap (E 20 GPa, c 5 MPa, phi 0.6, psi 0.1, X0 50 MPa, H_c 1 GPa,
   2000 kg/m^3) of thickness t over elastic granite. */
static inline void dp_layer(rf_impact_input *in, double t)
{
    in->layer_thickness = t, in->layer_density = 2000, in->layer_E = 20e9, in->layer_poisson = 0.3;
    in->layer_material = RF_MATERIAL_DRUCKER_PRAGER, in->layer_cohesion = 5e6;
    in->layer_friction_angle = 0.6, in->layer_dilatancy_angle = 0.1;
    in->layer_cap_pressure = 50e6, in->layer_cap_hardening = 1e9;
}

/* The S5 nominal soil (examples/s5_v10.yaml): medium-dense gravelly colluvium, Drucker-Prager + cap
   (E 100 MPa, nu 0.3, 1900 kg/m^3, c 10 kPa, phi 40 deg, psi 5 deg, X0 200 kPa, H_c 40 MPa), 1 m over
   granite; a rigid boulder r0 = 0.5 m at 10 m/s, gravity 0. */
static inline void s5_soil(rf_impact_input *in)
{
    in->radius = 0.5, in->velocity = 10, in->gravity = 0, in->boulder_material = RF_MATERIAL_RIGID_BODY;
    in->layer_thickness = 1.0, in->layer_density = 1900, in->layer_E = 100e6, in->layer_poisson = 0.3;
    in->layer_material = RF_MATERIAL_DRUCKER_PRAGER, in->layer_cohesion = 10e3;
    in->layer_friction_angle = 40 * DEG, in->layer_dilatancy_angle = 5 * DEG;
    in->layer_cap_pressure = 200e3, in->layer_cap_hardening = 40e6;
}

#endif
