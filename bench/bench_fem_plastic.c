/* bench_fem_plastic.c - cost of the material kernels of the axisymmetric FE
 * impact (issue 10): nanoseconds per element-step and wall time of a granite
 * sphere at V m/s on a slope that is elastic (precomputed stiffness, and the
 * integration-point kernel), von Mises, or Drucker-Prager with a cap, the
 * plastic ones in small strain and in large deformation (updated Lagrangian,
 * docs/validation-plastic.md section 6e).
 *   bench_fem_plastic [refinement=10] [velocity=10] [repeats=3] [rows=012345]
 * rows: the digits of the rows to run (0 stiffness kernel, 1 elastic points,
 * 2 J2, 3 DP + cap, 4 J2 large deformation, 5 DP + cap large deformation).
 * Prints the best of `repeats` runs (other jobs share the machine): CPU
 * seconds of the process (one thread) and ns per element-step from them, and
 * the wall time (noisy under load). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rockfuzz/fem.h"
#include "fem/fem_tuning.h"

int main(int argc, char **argv)
{
    const double ref = argc > 1 ? atof(argv[1]) : 10, V = argc > 2 ? atof(argv[2]) : 10;
    const int repeats = argc > 3 ? atoi(argv[3]) : 3;
    const char *rows = argc > 4 ? argv[4] : "012345";
    printf("# refinement a/h = %g, V = %g m/s, domain factor 10, best of %d\n", ref, V, repeats);
    printf("%-40s %8s %6s %7s %7s %10s %9s %9s\n", "slope material", "elements", "steps", "CPU[s]", "wall[s]",
           "ns/el-step", "R_n", "W_p/KE");
    for (int m = 0; m < 6; m++) {
        if (!strchr(rows, '0' + m))
            continue;
        rf_impact_input in;
        rf_impact_input_default(&in);
        in.velocity = V;
        rf_fem_options o;
        rf_fem_options_default(&o);
        rf_fem_tuning tu;
        o.refinement = ref;
        o.domain_factor = 10;
        const char *name = "elastic (stiffness kernel)";
        if (m == 1) {
            fem_tune(&o, &tu)->kernel[0] = tu.kernel[1] = RF_FEM_KERNEL_POINTS;
            name = "elastic (integration points, 2x2)";
        } else if (m == 2 || m == 4) {
            in.slope_material = RF_MATERIAL_VON_MISES, in.slope_yield = 200e6;
            name = m == 2 ? "von_mises Y 200 MPa (B-bar)" : "von_mises, large deformation";
        } else if (m == 3 || m == 5) {
            in.slope_material = RF_MATERIAL_DRUCKER_PRAGER, in.slope_cohesion = 20e6;
            in.slope_friction_angle = 0.6, in.slope_dilatancy_angle = 0.1;
            in.slope_cap_pressure = 300e6, in.slope_cap_hardening = 5e9;
            name = m == 3 ? "drucker_prager + cap (B-bar)" : "drucker_prager + cap, large deformation";
        }
        o.large_deformation = m < 4 ? RF_FEM_SMALL_STRAIN : RF_FEM_LARGE_DEFORMATION;
        o.threads = 1;
        double best = 1e300, wall = 1e300;
        rf_impact_output out = {0};
        for (int r = 0; r < repeats; r++) {
            rf_error err = {0};
            const clock_t c0 = clock();
            if (rf_fem_impact(&in, &o, &out, NULL, &err) != RF_OK) {
                fprintf(stderr, "bench_fem_plastic: %s\n", err.msg);
                return 1;
            }
            const double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
            best = cpu < best ? cpu : best, wall = out.wall_seconds < wall ? out.wall_seconds : wall;
        }
        printf("%-40s %8.0f %6.0f %7.3f %7.3f %10.1f %9.5f %9.4f\n", name, out.elements, out.steps, best, wall,
               1e9 * best / (out.elements * out.steps), out.R_n, out.plastic_work);
    }
    return 0;
}
