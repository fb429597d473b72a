/* bench_fem3d_soil.c - the S5 nominal soil layer (examples/s5_v10.yaml:
 * colluvium, Drucker-Prager + cap, 1 m over granite, rigid boulder r0 =
 * 0.5 m, 10 m/s vertical, gravity 0) on a slope, in the 3D model or the
 * axisymmetric one, one run per refinement, with the layer's contact
 * estimate (fem3d_spec.h) next to the measured penetration and contact
 * radius (docs/validation-plastic.md section 9d, docs/studies.md S6).
 *   bench_fem3d_soil [key=value ...] A [A ...]
 * keys (bench_fem3d_probe.h, which has them all): model=3d|axi, angle= (deg), f= (friction), large=0|1 (small strain or
 * large deformation, both models; default 0), E= (layer_E),
 * X0= (layer_cap_pressure), Hc= (layer_cap_hardening), t= (thickness),
 * core= (fine_box_factor), domain= (domain_factor), end= (end time, s),
 * law=elastic|dp (the layer's), boundary=fixed|absorbing, ratio= (boulder_mesh_ratio), threads=,
 * g= (gravity [m/s^2]; default 0, -1 = auto 9.81), kappa= (> 0: the mass redistribution at the
 * 3D contact face, the library's default, as kappa=0.1; without it the lumped face), sphere=1 (the
 * slope's face nodes against the rigid boulder's exact sphere, the library's default; without it the
 * faceted contact). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/util.h"
#include "fem/fem3d_spec.h"
#include "rockfuzz/fem3d.h"
#include "bench_fem3d_probe.h"


/* The S5 nominal point (examples/s5_v10.yaml), gravity 0, small strain. */
static void s5_nominal(probe *p)
{
    rf_impact_input_default(&p->in);
    rf_impact_input *in = &p->in;
    in->radius = 0.5, in->velocity = 10, in->gravity = 0, in->boulder_material = RF_MATERIAL_RIGID_BODY;
    in->layer_thickness = 1.0, in->layer_density = 1900, in->layer_E = 100e6, in->layer_poisson = 0.3;
    in->layer_material = RF_MATERIAL_DRUCKER_PRAGER, in->layer_cohesion = 10e3;
    in->layer_friction_angle = 40 * RF_PI / 180, in->layer_dilatancy_angle = 5 * RF_PI / 180;
    in->layer_cap_pressure = 200e3, in->layer_cap_hardening = 40e6;
    rf_fem_options_default(&p->o);
    p->o.boundary = RF_FEM_BOUNDARY_FIXED, p->o.threads = 1, p->o.large_deformation = RF_FEM_SMALL_STRAIN;
    /* the lumped 3D face unless kappa= > 0 is given (so that the commands of docs/validation-plastic.md
       9e-9f keep their meaning; the library's default since 9e is on, kappa 0.1) */
    fem_tune(&p->o, &p->t)->surface_mass_3d = 0;
    /* and the faceted contact unless sphere=1 (the library's default since 9g) */
    p->t.sphere_contact_3d = 0;
    rf_fem3d_options_default(&p->o3);
}

int main(int argc, char **argv)
{
    probe p;
    s5_nominal(&p);
    for (int i = 1; i < argc; i++) {
        if (probe_set(&p, argv[i], "bench_fem3d_soil"))
            continue;
        p.o.refinement = atof(argv[i]);
        f3_layer_contact lc;
        f3_layer_contact_estimate(&p.in, &lc);
        rf_impact_output out;
        rf_fem_history H;
        rf_fem3d_report rep = {0};
        const double cpu = probe_run(&p, &out, &H, &rep, "bench_fem3d_soil"), k0 = H.ke0;
        printf("model=%s angle=%.0f f=%g ref=%g large=%d h=%.4f elements=%.0f steps=%.0f cpu=%.2f R_n=%.4f R_t=%.4f "
               "R_ke=%.4f W_p=%.4f pen=%.4f crater=%.4f a=%.4f F=%.4g t_c=%.4g closure=%.2e contact_work=%.2e fric=%.3e g=%g W_g=%.3e "
               "rest=%d outside=%ld gap_pen=%.2e unlocated=%ld\n",
               p.axi ? "axi" : "3d", p.in.slope_angle * 180 / RF_PI, p.in.friction, p.o.refinement,
               rf_fem_large_deformation(&p.o, &p.in), H.h_contact, out.elements, out.steps, cpu, out.R_n,
               out.R_t, out.R_ke, out.plastic_work, out.penetration_max, out.indentation_depth, out.contact_radius,
               out.contact_force_max, out.contact_duration, H.closure[H.n - 1] / k0, H.contact_work[H.n - 1] / k0,
               (p.axi ? H.friction_work : rep.friction_work) / k0, H.gravity, H.gravity_work / k0,
               H.at_rest, H.geostatic_outside, H.penetration_max, rep.unlocated_pair_steps);
        printf("  estimate: thick=%d depth=%.4f radius=%.4f zone=%.4f t=%.4g; warning: %s\n", lc.thick,
               lc.compression, lc.radius, lc.zone_radius, lc.duration, H.warning[0] ? H.warning : "-");
        fflush(stdout);
        rf_fem_history_free(&H);
        rf_fem3d_report_free(&rep);
    }
    return 0;
}
