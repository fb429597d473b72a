/* bench_fem3d_plastic.c - the 3D twin of bench_fem_plastic.c: cost of the
 * material kernels of the 3D FE impact (half model, one thread) in CPU
 * nanoseconds per element-step, and their results, for a granite sphere at
 * V m/s on a slope at angle DEG that is elastic (matrix-free kernel, and the
 * integration-point kernel), von Mises (Y = 200 MPa) or Drucker-Prager with a
 * cap; with angle 0 the axisymmetric model's results at the same a/h follow.
 *   bench_fem3d_plastic [refinement=3] [velocity=10] [angle_deg=0] [friction=0] [repeats=1]
 * CPU time of the process (clock()), best of `repeats`: other jobs share the machine. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "rockfuzz/fem3d.h"

static void material(int m, rf_impact_input *in, rf_fem_options *o, const char **name)
{
    *name = "elastic (matrix-free kernel)";
    if (m == 1) {
        o->kernel[0] = o->kernel[1] = RF_FEM_KERNEL_POINTS;
        *name = "elastic (integration points)";
    } else if (m == 2) {
        in->slope_material = RF_MATERIAL_VON_MISES, in->slope_yield = 200e6;
        *name = "von_mises Y 200 MPa (B-bar)";
    } else if (m == 3) {
        in->slope_material = RF_MATERIAL_DRUCKER_PRAGER, in->slope_cohesion = 20e6;
        in->slope_friction_angle = 0.6, in->slope_dilatancy_angle = 0.1;
        in->slope_cap_pressure = 300e6, in->slope_cap_hardening = 5e9;
        *name = "drucker_prager + cap (B-bar)";
    }
}

static void row(const char *model, const char *name, const rf_impact_output *out, double cpu)
{
    printf("%-5s %-30s %7.0f %6.0f %7.2f %8.1f %8.5f %8.5f %7.4f %7.3f %7.3f %7.4f %8.1e\n", model, name,
           out->elements, out->steps, cpu, 1e9 * cpu / (out->elements * out->steps), out->R_n, out->R_t,
           out->plastic_work, 1e3 * out->penetration_max, 1e3 * out->indentation_depth,
           out->equivalent_plastic_strain_max, out->energy_error);
}

int main(int argc, char **argv)
{
    const double ref = argc > 1 ? atof(argv[1]) : 3, V = argc > 2 ? atof(argv[2]) : 10;
    const double angle = argc > 3 ? atof(argv[3]) : 0, mu = argc > 4 ? atof(argv[4]) : 0;
    const int repeats = argc > 5 ? atoi(argv[5]) : 1;
    printf("# a/h = %g, V = %g m/s, slope %g deg, friction %g, domain factor 10, fixed boundary, 1 thread, "
           "CPU s best of %d\n", ref, V, angle, mu, repeats);
    printf("%-5s %-30s %7s %6s %7s %8s %8s %8s %7s %7s %7s %7s %8s\n", "model", "slope material", "elems", "steps",
           "cpu[s]", "ns/el-st", "R_n", "R_t", "W_p/KE", "pen_mm", "crat_mm", "eps_p", "energy");
    for (int m = 0; m < 4; m++) {
        rf_impact_input in;
        rf_impact_input_default(&in);
        in.velocity = V, in.slope_angle = angle * 3.14159265358979323846 / 180, in.friction = mu;
        rf_fem_options o;
        rf_fem_options_default(&o);
        o.refinement = ref, o.domain_factor = 10, o.threads = 1;
        const char *name;
        material(m, &in, &o, &name);
        double best = 1e300;
        rf_impact_output out = {0};
        for (int r = 0; r < repeats; r++) {
            rf_error err = {0};
            const clock_t c0 = clock();
            if (rf_fem3d_impact(&in, &o, &out, NULL, &err) != RF_OK) {
                fprintf(stderr, "bench_fem3d_plastic: %s\n", err.msg);
                return 1;
            }
            best = fmin(best, (double)(clock() - c0) / CLOCKS_PER_SEC);
        }
        row("3D", name, &out, best);
        if (angle != 0 || mu != 0 || m == 1)
            continue;
        rf_error err = {0};
        const clock_t c0 = clock();
        if (rf_fem_impact(&in, &o, &out, NULL, &err) != RF_OK) {
            fprintf(stderr, "bench_fem3d_plastic (axisymmetric): %s\n", err.msg);
            return 1;
        }
        row("axi", name, &out, (double)(clock() - c0) / CLOCKS_PER_SEC);
    }
    return 0;
}
