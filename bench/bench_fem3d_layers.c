/* bench_fem3d_layers.c - mesh probe of the 3D impact (issue 9,
 * docs/fem-speed.md section 5): one run per refinement of the 10 m/s,
 * 45 degree, f = 0.6 impact (or any other given below) with one mesh setting
 * changed, and the energy balance at the end: boulder vibration, slope
 * (waves), friction and normal contact work, closure, all / KE0.
 *   bench_fem3d_layers [key=value ...] A [A ...]
 * keys (bench_fem3d_probe.h, which has them all): model=3d|axi, v= (m/s), angle= (deg), f=, aspect= (layer_aspect),
 * inner= (boulder_inner), core= (fine_box_factor), elong= (elongation),
 * domain= (domain_factor), full=0|1, dt= (dt_safety), ratio= (boulder_mesh_ratio),
 * threads=. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/util.h"
#include "rockfuzz/fem3d.h"
#include "bench_fem3d_probe.h"


int main(int argc, char **argv)
{
    probe p = {.in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                      .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10,
                      .slope_angle = 45 * RF_PI / 180, .friction = 0.6}};
    rf_fem_options_default(&p.o);
    rf_fem3d_options_default(&p.o3);
    for (int i = 1; i < argc; i++) {
        if (probe_set(&p, argv[i], "bench_fem3d_layers"))
            continue;
        p.o.refinement = atof(argv[i]);
        rf_impact_output out;
        rf_fem_history H;
        rf_fem3d_report rep = {0};
        const double cpu = probe_run(&p, &out, &H, &rep, "bench_fem3d_layers"), k0 = H.ke0;
        printf("model=%s ref=%g aspect=%g inner=%g core=%g domain=%g elements=%.0f steps=%.0f cpu=%.2f R_n=%.6f "
               "R_t=%.6f R_ke=%.6f omega=%.5f vib=%.3e slope=%.3e fric=%.3e W_n=%.3e closure=%.3e\n",
               p.axi ? "axi" : "3d", p.o.refinement, p.o3.layer_aspect, p.o3.boulder_inner, p.o3.fine_box_factor,
               rf_fem_domain_factor(&p.o, &p.in), out.elements, out.steps, cpu, out.R_n, out.R_t, out.R_ke,
               out.omega_after,
               H.vibration_energy / k0, H.slope_energy / k0, rep.friction_work / k0, rep.normal_work / k0,
               H.closure[H.n - 1] / k0);
        if (!p.axi)
            printf("  contact: sweeps_max=%d residual_max=%.2e slip_max=%.2e stick=%.3f pen_max=%.2e\n",
                   rep.pgs_sweeps_max, rep.pgs_residual_max, rep.slip_max, rep.stick_fraction, H.penetration_max);
        fflush(stdout);
        rf_fem_history_free(&H);
        rf_fem3d_report_free(&rep);
    }
    return 0;
}
