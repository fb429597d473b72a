/* bench_fem3d_plastic.c - the 3D twin of bench_fem_plastic.c.
 * 1. The kernels alone: CPU ns per element evaluation (forces_field + commit)
 *    on a 16^3 grid of unit-ish cubes, for the matrix-free elastic kernel, the
 *    integration-point kernel with the linear law, and with the J2 and
 *    Drucker-Prager + cap laws, elastic (small field) and plastic (large),
 *    each in small strain and in the updated-Lagrangian form (UL).
 * 2. The whole solver (half model, one thread): CPU ns per element-step and
 *    the results, for a granite sphere at V m/s on a slope at angle DEG that
 *    is elastic (matrix-free kernel; integration-point kernel in both bodies),
 *    von Mises (Y = 200 MPa) or Drucker-Prager with a cap; with angle 0 the
 *    axisymmetric model's results at the same a/h follow.
 *   bench_fem3d_plastic [refinement=3] [velocity=10] [angle_deg=0] [friction=0] [repeats=1] [kinematics=auto]
 * CPU time of the process (clock()), best of `repeats`: other jobs share the machine. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "fem/fem_kernel.h"
#include "rockfuzz/fem3d.h"
#include "fem/fem_tuning.h"

enum { G = 16, GN = G + 1 };

/* CPU ns per element of forces_field + commit over `reps` evaluations of the field amp * u1. */
static double kernel_ns(fem_kernel *k, const double *u1, double amp, long ne, int reps, double *fe)
{
    static double u[3 * GN * GN * GN];
    double best = 1e300;
    for (int r = 0; r < reps; r++) {
        const clock_t c0 = clock();
        for (int i = 1; i <= 10; i++) {
            for (long d = 0; d < 3L * GN * GN * GN; d++)
                u[d] = amp * (r * 10 + i) * u1[d];
            k->ops->forces_field(k, 0, k->units, u, fe);
            if (k->ops->commit)
                k->ops->commit(k);
        }
        best = fmin(best, (double)(clock() - c0) / CLOCKS_PER_SEC / 10);
    }
    return 1e9 * best / (double)ne;
}

static int kernels_alone(void)
{
    static double x[3 * GN * GN * GN], u1[3 * GN * GN * GN];
    static int conn[8 * G * G * G];
    double *fe = malloc(24 * sizeof(double) * G * G * G);
    unsigned long long s = 1;
    for (int k = 0; k < GN; k++)
        for (int j = 0; j < GN; j++)
            for (int i = 0; i < GN; i++) {
                const long n = (long)(k * GN + j) * GN + i;
                x[3 * n] = i, x[3 * n + 1] = j, x[3 * n + 2] = k;
                for (int c = 0; c < 3; c++) {
                    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
                    u1[3 * n + c] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
                }
            }
    static const int off[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    long ne = 0;
    for (int k = 0; k < G; k++)
        for (int j = 0; j < G; j++)
            for (int i = 0; i < G; i++, ne++)
                for (int a = 0; a < 8; a++)
                    conn[8 * ne + a] = ((k + off[a][2]) * GN + j + off[a][1]) * GN + i + off[a][0];
    rf_material_params p;
    rf_material_params_default(&p);
    const fem_lame lame = {p.E * p.poisson / ((1 + p.poisson) * (1 - 2 * p.poisson)), p.E / (2 * (1 + p.poisson))};
    rf_material mj, md;
    rf_error err;
    p.model = RF_MATERIAL_VON_MISES, p.yield = 200e6;
    rf_material_init(&mj, &p, &err);
    p.model = RF_MATERIAL_DRUCKER_PRAGER, p.cohesion = 20e6, p.friction_angle = 0.6, p.dilatancy_angle = 0.1;
    p.cap_pressure = 300e6, p.cap_hardening = 5e9;
    rf_material_init(&md, &p, &err);
    printf("# kernels alone: %ld hexahedra, CPU ns per element evaluation (forces + commit), best of 3\n", ne);
    fem_kernel k;
    if (fem_kernel_hex8_matfree(&k, 0, ne, x, conn, lame.lam, lame.mu, 1, &err) != RF_OK)
        return 1;
    printf("%-44s %8.1f\n", "elastic, matrix-free (hex8_kernel.c)", kernel_ns(&k, u1, 1e-6, ne, 3, fe));
    fem_kernel_release(&k);
    const fem_point_law laws[3] = {fem_point_law_linear3d(&lame), fem_point_law_material3d(&mj),
                                   fem_point_law_material3d(&md)};
    const char *names[3] = {"linear", "von_mises", "drucker_prager + cap"};
    for (int l = 0; l < 3; l++)
        for (int v = 0; v < (l ? 4 : 2); v++) {
            const int plastic = v / 2, large = v % 2;
            if (fem_kernel_points_hex(&k, 0, ne, x, conn, &laws[l], NULL, NULL, l > 0, &err) != RF_OK)
                return 1;
            if (large && fem_kernel_points_hex_large(&k, x, &err) != RF_OK)
                return 1;
            char name[80];
            const char *regime = l ? (plastic ? ", plastic (B-bar)" : ", elastic (B-bar)") : "";
            snprintf(name, sizeof name, "points%s, %s%s", large ? " UL" : "", names[l], regime);
            printf("%-44s %8.1f\n", name, kernel_ns(&k, u1, plastic ? 1e-3 : 1e-7, ne, 3, fe));
            fem_kernel_release(&k);
        }
    free(fe);
    return 0;
}

static void material(int m, rf_impact_input *in, rf_fem_options *o, const char **name)
{
    static rf_fem_tuning tu; /* one run at a time */
    *name = "elastic (matrix-free kernel)";
    if (m == 1) {
        fem_tune(o, &tu)->kernel[0] = tu.kernel[1] = RF_FEM_KERNEL_POINTS;
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
    rf_fem_kinematics kin = RF_FEM_KINEMATICS_AUTO;
    rf_error kerr = {0};
    if (argc > 6 && rf_fem_kinematics_parse(argv[6], &kin, &kerr) != RF_OK) {
        fprintf(stderr, "bench_fem3d_plastic: %s\n", kerr.msg);
        return 2;
    }
    if (kernels_alone())
        return 1;
    printf("# a/h = %g, V = %g m/s, slope %g deg, friction %g, domain factor 10, fixed boundary, 1 thread, "
           "large_deformation %s, CPU s best of %d\n", ref, V, angle, mu, rf_fem_kinematics_name(kin), repeats);
    printf("%-5s %-30s %7s %6s %7s %8s %8s %8s %7s %7s %7s %7s %8s\n", "model", "slope material", "elems", "steps",
           "cpu[s]", "ns/el-st", "R_n", "R_t", "W_p/KE", "pen_mm", "crat_mm", "eps_p", "energy");
    for (int m = 0; m < 4; m++) {
        rf_impact_input in;
        rf_impact_input_default(&in);
        in.velocity = V, in.slope_angle = angle * 3.14159265358979323846 / 180, in.friction = mu;
        rf_fem_options o;
        rf_fem_options_default(&o);
        o.refinement = ref, o.domain_factor = 10, o.threads = 1, o.large_deformation = kin;
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
        row("axi", m == 0 ? "elastic (stiffness kernel)" : name, &out, (double)(clock() - c0) / CLOCKS_PER_SEC);
    }
    return 0;
}
