/* bench_soil_gerber.c - the axisymmetric soil model's largest penetration
 * against Gerber's empirical law d = 0.1 M^(1/3) M_E^(-0.4) V^0.8 (issue 29,
 * "Published data"; docs/soil-impacts.md).  A rigid granite sphere (2600
 * kg/m^3, radius from the mass) falls normally on a thick Drucker-Prager +
 * cap soil layer (3 m, t= to change) over granite, which the block never
 * feels (the layer is thick: depth < t / 2); the soil's E comes from M_E through the oedometric
 * modulus (fem_soil_E_from_oedometric, nu 0.3), its plastic parameters are
 * the S5 colluvium's (docs/materials.md ranges; never fitted to the law).
 * Gravity and large deformation auto (on), absorbing boundary.
 *   bench_soil_gerber [ref=A] [t=layer m] [cap=oedometer] [mass=m1,m2,..] [v=v1,..] [ME=M1,..] (ME in Pa)
 * cap=oedometer: M_E is also the cap's loading modulus (cap_from_oedometer).
 * One CSV row per impact on stdout:
 *   mass_kg,r0_m,V_m_s,ME_Pa,E_Pa,Hc_Pa,ref,d_model_m,d_gerber_m,ratio,R_n,W_p_KE0,energy_error,cpu_s
 * A failed run prints its row with "failed" and the message. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "core/util.h"
#include "fem/fem_soil.h"
#include "rockfuzz/fem.h"
#include "rockfuzz/material.h"
#include "bench_util.h"

static double layer_t = 3.0;
static int cap_from_ME = 0; /* cap=oedometer */

/* cap=oedometer: M_E read as the virgin (loading) constrained modulus D, the
   recipe of docs/materials.md "The cap: X0 and H_c from an oedometer test":
   E = 3 x the E whose oedometric modulus is M_E (E_ur ~ 3 E_50), K_t = D / (1 +
   2 eta / sqrt3), H_c = K K_t / (K - K_t). */
static void cap_from_oedometer(rf_impact_input *in, double M_E)
{
    const double nu = in->layer_poisson, E = 3 * fem_soil_E_from_oedometric(M_E, nu);
    const double K = E / (3 * (1 - 2 * nu)), eta = rf_material_dp_eta(in->layer_friction_angle);
    const double Kt = M_E / (1 + 2 * eta / sqrt(3.0));
    in->layer_E = E, in->layer_cap_hardening = K * Kt / (K - Kt);
}

static void soil_input(rf_impact_input *in, double mass, double V, double M_E)
{
    rf_impact_input_default(in);
    const double rho = 2600, nu = 0.3;
    in->boulder_material = RF_MATERIAL_RIGID_BODY, in->boulder_density = rho;
    in->radius = cbrt(3 * mass / (4 * RF_PI * rho));
    in->velocity = V, in->gravity = RF_GRAVITY_AUTO;
    in->layer_thickness = layer_t;
    in->layer_material = RF_MATERIAL_DRUCKER_PRAGER, in->layer_density = 1900, in->layer_poisson = nu;
    in->layer_E = fem_soil_E_from_oedometric(M_E, nu);
    in->layer_cohesion = 10e3, in->layer_friction_angle = 40 * RF_PI / 180;
    in->layer_dilatancy_angle = 5 * RF_PI / 180;
    in->layer_cap_pressure = 200e3, in->layer_cap_hardening = 40e6;
    if (cap_from_ME)
        cap_from_oedometer(in, M_E);
}

static void run(double mass, double V, double M_E, double refinement)
{
    rf_impact_input in;
    soil_input(&in, mass, V, M_E);
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.threads = 1, o.refinement = refinement;
    rf_impact_output out;
    rf_fem_history H = {0};
    rf_error e = {0};
    const double c0 = cpu_now();
    const rf_status st = rf_fem_impact(&in, &o, &out, &H, &e);
    const double cpu = cpu_now() - c0, dg = fem_soil_gerber_penetration(mass, M_E, V);
    printf("%g,%.4f,%g,%.4g,%.4g,%.4g,%g,", mass, in.radius, V, M_E, in.layer_E, in.layer_cap_hardening, refinement);
    if (st != RF_OK)
        printf("failed,%.5f,,,,,%.2f,\"%s\"\n", dg, cpu, e.msg);
    else
        printf("%.5f,%.5f,%.4f,%.4f,%.4f,%.2e,%.2f\n", out.penetration_max, dg, out.penetration_max / dg, out.R_n,
               out.plastic_work, H.closure[H.n - 1] / H.ke0, cpu);
    fflush(stdout);
    if (st == RF_OK)
        rf_fem_history_free(&H);
}

int main(int argc, char **argv)
{
    double mass[16] = {100, 1000, 10000}, v[16] = {5, 10, 20}, me[16] = {10e6, 30e6, 100e6}, ref = 4;
    int nm = 3, nv = 3, ne = 3;
    for (int i = 1; i < argc; i++) {
        if (!strncmp(argv[i], "mass=", 5))
            nm = parse_list(argv[i] + 5, mass, 16);
        else if (!strncmp(argv[i], "v=", 2))
            nv = parse_list(argv[i] + 2, v, 16);
        else if (!strncmp(argv[i], "ME=", 3))
            ne = parse_list(argv[i] + 3, me, 16);
        else if (!strcmp(argv[i], "cap=oedometer"))
            cap_from_ME = 1;
        else if (!strncmp(argv[i], "t=", 2))
            layer_t = atof(argv[i] + 2);
        else if (!strncmp(argv[i], "ref=", 4))
            ref = atof(argv[i] + 4);
        else {
            fprintf(stderr, "bench_soil_gerber: unknown argument '%s'\n", argv[i]);
            return 2;
        }
    }
    printf("mass_kg,r0_m,V_m_s,ME_Pa,E_Pa,Hc_Pa,ref,d_model_m,d_gerber_m,ratio,R_n,W_p_KE0,energy_error,cpu_s\n");
    for (int a = 0; a < nm; a++)
        for (int b = 0; b < nv; b++)
            for (int c = 0; c < ne; c++)
                run(mass[a], v[b], me[c], ref);
    return 0;
}
