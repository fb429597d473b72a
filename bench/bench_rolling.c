/* bench_rolling.c - the figures of docs/soil-impacts.md "Rolling resistance
 * from the layer": the rolling resistance the reduced model derives from the
 * FE indentation of the S5 colluvium layer (and of a von Mises layer, whose
 * ideally plastic closed form is the second method) for the blocks asked.
 *
 *   build/bench_rolling [layer=s5|mises] [radius=0.5,1] [ref=A] [yield=Y]
 *
 * One CSV row per radius: layer, radius [m], mass [kg], FE speed [m/s],
 * depth reached [m], fit A [N/m^m], fit m, fit rms (log), rut depth z0 [m],
 * resistance F_r [N], mu_r, the mean pressure q = F(z0)/(2 pi R z0) [Pa] and the
 * ideally plastic closed form's mu_r at that q, CPU s of the calibration. */
#include "trajectory/traj_rolling.h"

#include "rockfuzz/impact.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

/* The ground of material `layer`: S5 (examples/s5_v5.yaml) or a von Mises layer of yield Y. */
static void ground(traj_impact_setup *s, const char *layer, double Y)
{
    memset(s, 0, sizeof *s);
    s->solver = 0; /* RF_IMPACT_FEM */
    s->density = 2600;
    s->has_ground = 1;
    rf_traj_impact_ground *g = &s->ground;
    g->given = 1;
    const double def[RF_TRAJ_IMPACT_N] = {68.2e9, 0.25, 2600, 0, 0, 1.0, 100e6, 0.3, 1900, 0, 0, 10e3, 40, 5,
                                          200e3, 40e6};
    memcpy(g->v, def, sizeof def);
    if (!strcmp(layer, "mises")) {
        snprintf(g->layer_material, sizeof g->layer_material, "von_mises");
        g->v[9] = Y, g->v[10] = 0;
    } else {
        snprintf(g->layer_material, sizeof g->layer_material, "drucker_prager");
    }
}

static double cpu_seconds(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

int main(int argc, char **argv)
{
    const char *layer = "s5";
    char radii[256] = "0.5,1";
    double ref = 0, Y = 200e3;
    for (int i = 1; i < argc; i++) {
        if (!strncmp(argv[i], "layer=", 6))
            layer = argv[i] + 6;
        else if (!strncmp(argv[i], "radius=", 7))
            snprintf(radii, sizeof radii, "%s", argv[i] + 7);
        else if (!strncmp(argv[i], "ref=", 4))
            ref = atof(argv[i] + 4);
        else if (!strncmp(argv[i], "yield=", 6))
            Y = atof(argv[i] + 6);
        else {
            fprintf(stderr, "usage: bench_rolling [layer=s5|mises] [radius=R,R..] [ref=A] [yield=Y]\n");
            return 2;
        }
    }
    printf("layer,radius_m,mass_kg,fe_speed_m_s,depth_max_m,fit_A,fit_m,fit_rms,rut_depth_m,force_N,mu_r,"
           "mean_pressure_Pa,mu_r_plastic_same_pressure,cpu_s\n");
    for (char *tok = strtok(radii, ","); tok; tok = strtok(NULL, ",")) {
        traj_impact_setup s;
        ground(&s, layer, Y);
        s.radius = atof(tok);
        s.refinement = ref;
        traj_rolling_calibration cal;
        rf_error err;
        double c0 = cpu_seconds();
        if (traj_rolling_calibrate(&s, 9.81, &cal, &err) != RF_OK) {
            fprintf(stderr, "radius %s: %s\n", tok, err.msg);
            return 1;
        }
        double q = 2 * cal.r.weight / (2 * RF_PI * s.radius * cal.r.sinkage); /* F(z0) / (2 pi R z0) */
        double mu_plastic = traj_rolling_power_mu(2 * RF_PI * s.radius * q, 1, s.radius, cal.r.weight, NULL);
        printf("%s,%g,%.6g,%g,%.6g,%.6g,%.4f,%.3g,%.6g,%.6g,%.5f,%.6g,%.5f,%.1f\n", layer, s.radius,
               cal.r.weight / 9.81, cal.speed, cal.depth_max, cal.fit_A, cal.fit_m, cal.fit_rms, cal.r.sinkage,
               cal.r.force, cal.r.mu_r, q, mu_plastic, cpu_seconds() - c0);
        fflush(stdout);
    }
    return 0;
}
