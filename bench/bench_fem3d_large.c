/* bench_fem3d_large.c - one rigid-boulder impact on soft Drucker-Prager + cap
 * soil (the whole slope, or a layer over granite) in the 3D and/or the
 * axisymmetric model, for the tables of docs/validation-plastic.md section 9c:
 * R_n, penetration, crater, W_p / KE, largest plastic strain, energy error,
 * steps, elements, dt and the CPU time of the process.
 *   bench_fem3d_large E c X0 thickness V refinement fine_box_factor which [kinematics]
 * E, c, X0 [Pa]: the soil's modulus, cohesion and cap pressure (phi 35 deg,
 * psi 5 deg, H_c = 200 X0, nu 0.3, 1800 kg/m^3); thickness [m] 0: the whole
 * slope, else a layer over granite; V [m/s]; which: 1 3D, 2 axisymmetric,
 * 3 both; kinematics 1 small strain, 2 large deformation (default).  Rigid
 * boulder r0 = 1 m, no gravity, domain 3 r0, absorbing boundary, one thread. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rockfuzz/fem.h"
#include "fem/fem_tuning.h"
#include "rockfuzz/fem3d.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

int main(int argc, char **argv)
{
    if (argc < 9) {
        fprintf(stderr, "usage: bench_fem3d_large E c X0 thickness V refinement fine_box_factor which [kinematics]\n");
        return 2;
    }
    double E = atof(argv[1]), c = atof(argv[2]), X0 = atof(argv[3]), t = atof(argv[4]), v = atof(argv[5]);
    double ref = atof(argv[6]), cf = atof(argv[7]);
    int which = atoi(argv[8]); /* 1 3D, 2 axi, 3 both */
    int kin = argc > 9 ? atoi(argv[9]) : 2;
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.velocity = v, in.boulder_material = RF_MATERIAL_RIGID_BODY, in.gravity = 0;
    in.layer_thickness = t, in.layer_density = 1800, in.layer_E = E, in.layer_poisson = 0.3;
    in.layer_material = RF_MATERIAL_DRUCKER_PRAGER, in.layer_cohesion = c;
    in.layer_friction_angle = 35 * M_PI / 180, in.layer_dilatancy_angle = 5 * M_PI / 180;
    in.layer_cap_pressure = X0, in.layer_cap_hardening = 200 * X0;
    if (t == 0) {
        in.slope_density = 1800, in.slope_E = E, in.slope_poisson = 0.3;
        in.slope_material = RF_MATERIAL_DRUCKER_PRAGER, in.slope_cohesion = c;
        in.slope_friction_angle = 35 * M_PI / 180, in.slope_dilatancy_angle = 5 * M_PI / 180;
        in.slope_cap_pressure = X0, in.slope_cap_hardening = 200 * X0;
    }
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = ref, o.domain_factor = 3, o.threads = 1, o.boundary = RF_FEM_BOUNDARY_ABSORBING;
    o.large_deformation = (rf_fem_kinematics)kin;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    o3.fine_box_factor = cf;
    rf_impact_output out;
    rf_fem_history h;
    rf_error err = {0};
    if (which & 1) {
        clock_t c0 = clock();
        memset(&h, 0, sizeof h);
        int st = rf_fem3d_impact_ex(&in, &o, &o3, &out, &h, NULL, &err);
        if (st) { printf("3D fail: %s\n", err.msg); }
        else printf("3D : R_n %.4f pen %.4f m crater %.4f W_p %.4f epsp %.3f err %.2e steps %.0f elems %.0f dt %.3g cpu %.1f s hertz a %.3f %s\n", out.R_n,
               out.penetration_max, out.indentation_depth, out.plastic_work, out.equivalent_plastic_strain_max, out.energy_error,
               out.steps, out.elements, h.dt, (double)(clock() - c0) / CLOCKS_PER_SEC, h.hertz_radius, h.warning);
    }
    if (which & 2) {
        clock_t c0 = clock();
        memset(&h, 0, sizeof h);
        int st = rf_fem_impact(&in, &o, &out, &h, &err);
        if (st) { printf("axi fail: %s\n", err.msg); }
        else printf("axi: R_n %.4f pen %.4f m crater %.4f W_p %.4f epsp %.3f err %.2e steps %.0f elems %.0f dt %.3g cpu %.1f s %s\n", out.R_n,
               out.penetration_max, out.indentation_depth, out.plastic_work, out.equivalent_plastic_strain_max, out.energy_error,
               out.steps, out.elements, h.dt, (double)(clock() - c0) / CLOCKS_PER_SEC, h.warning);
    }
    return 0;
}
