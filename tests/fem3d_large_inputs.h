/* fem3d_large_inputs.h - shared by tests/test_fem3d_large.c (logic, coarse)
 * and tests/test_fem3d_large_accuracy.c (finer meshes): soft Drucker-Prager +
 * cap soil under a rigid boulder and the options of the 3D large-deformation
 * runs, over fem3d_layer_inputs.h (show, granite, run3d_ex).  Include after
 * cmocka.h. */
#ifndef ROCKFUZZ_FEM3D_LARGE_INPUTS_H
#define ROCKFUZZ_FEM3D_LARGE_INPUTS_H

#include "fem3d_layer_inputs.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* A rigid boulder (r0 = 1 m) at 5 m/s, no gravity, on soft Drucker-Prager
 * soil with a cap (E 1 GPa, nu 0.3, 1800 kg/m^3, c 0.2 MPa, phi 35 deg,
 * psi 5 deg, X0 2 MPa, H_c 400 MPa): the whole slope if thickness is 0, else
 * a layer of that thickness over elastic granite.  Its Hertz contact radius
 * (0.19 m) keeps the 3D fine zone inside the boulder at fine_box_factor 1.5. */
static inline rf_impact_input soft_soil_3d(double thickness)
{
    rf_impact_input in = granite(0, 0);
    in.velocity = 5, in.boulder_material = RF_MATERIAL_RIGID_BODY, in.gravity = 0;
    rf_material_model *mat = thickness > 0 ? &in.layer_material : &in.slope_material;
    double *rho = thickness > 0 ? &in.layer_density : &in.slope_density;
    double *E = thickness > 0 ? &in.layer_E : &in.slope_E, *nu = thickness > 0 ? &in.layer_poisson : &in.slope_poisson;
    double *c = thickness > 0 ? &in.layer_cohesion : &in.slope_cohesion;
    double *phi = thickness > 0 ? &in.layer_friction_angle : &in.slope_friction_angle;
    double *psi = thickness > 0 ? &in.layer_dilatancy_angle : &in.slope_dilatancy_angle;
    double *X0 = thickness > 0 ? &in.layer_cap_pressure : &in.slope_cap_pressure;
    double *Hc = thickness > 0 ? &in.layer_cap_hardening : &in.slope_cap_hardening;
    in.layer_thickness = thickness;
    *mat = RF_MATERIAL_DRUCKER_PRAGER, *rho = 1800, *E = 1e9, *nu = 0.3;
    *c = 0.2e6, *phi = 35 * M_PI / 180, *psi = 5 * M_PI / 180, *X0 = 2e6, *Hc = 400e6;
    return in;
}

/* Section 9b's layer case: a rigid boulder at 10 m/s on a 0.1 m Drucker-Prager + cap layer (dp_layer:
   E 20 GPa, c 5 MPa) over elastic granite; penetration 25 mm, a quarter of the layer. */
static inline rf_impact_input dp_layer_case(void)
{
    rf_impact_input in = granite(0, 0);
    in.boulder_material = RF_MATERIAL_RIGID_BODY;
    dp_layer(&in, 0.1);
    return in;
}

/* Both models' options: a/h, a 3 r0 domain with absorbing boundaries, one thread, the kinematics. */
static inline rf_fem_options large_options(double refinement, rf_fem_kinematics kin)
{
    rf_fem_options o = coarse(refinement);
    o.domain_factor = 3, o.boundary = RF_FEM_BOUNDARY_ABSORBING, o.large_deformation = kin;
    return o;
}

/* The 3D fine zone over 1.5 Hertz radii (it must fit in 0.6 r0 on the boulder). */
static inline rf_fem3d_options large_options3d(void)
{
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    o3.fine_box_factor = 1.5;
    return o3;
}

#endif
