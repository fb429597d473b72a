/* bench_material.c - cost of one stress update (ns per integration point)
 * of each constitutive model of src/material, over a block of points as an
 * FE element block would call it, on a path that keeps every point plastic
 * (confined compression plus shear) and on an elastic one.  Then the
 * closure of the energy identity W_int (trapezoidal) = elastic energy +
 * plastic work on random non-radial paths against the increment size (the
 * table of docs/materials.md).
 * Usage: bench_material [points] [steps] */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/util.h"
#include "rockfuzz/material.h"

#define DEG (RF_PI / 180.0)

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double run(const rf_material *m, size_t n, int steps, double scale, double *checksum)
{
    double *deps = malloc(6 * n * sizeof *deps), *sig = calloc(6 * n, sizeof *sig);
    double *diss = malloc(n * sizeof *diss);
    rf_material_state *st = calloc(n, sizeof *st);
    for (size_t i = 0; i < n; i++) {
        double f = 1.0 + 0.1 * (double)(i % 17) / 17.0;
        double d[6] = {-2e-4 * f, 0.8e-4, 0.8e-4, 2e-4 * f, 0.3e-4, 0};
        for (int k = 0; k < 6; k++)
            deps[6 * i + k] = scale * d[k];
    }
    double t0 = now();
    for (int s = 0; s < steps; s++)
        rf_material_update_block(m, n, deps, sig, st, diss);
    double t = now() - t0;
    *checksum = st[n - 1].plastic_strain_eq; /* > 0 on the plastic path */
    free(deps), free(sig), free(diss), free(st);
    return 1e9 * t / ((double)n * steps);
}

/* A fixed pseudo-random increment drifting into compression (LCG). */
static void random_increment(uint64_t *seed, double scale, double d[6])
{
    for (int i = 0; i < 6; i++) {
        *seed = *seed * 6364136223846793005ULL + 1442695040888963407ULL;
        d[i] = scale * ((double)(*seed >> 11) / 9007199254740992.0 - 0.5);
    }
    d[0] -= 0.3 * scale;
}

/* |W_int - elastic energy - W_p| / W_p after 0.4 of accumulated strain. */
static double energy_mismatch(const rf_material *m, double scale, uint64_t seed)
{
    double sig[6] = {-1e4, -1e4, -1e4, 0, 0, 0}, old[6], d[6], dw, w_int = 0.0, w_p = 0.0;
    double psi0 = rf_material_elastic_energy(m, sig);
    rf_material_state st = {0};
    for (long i = 0, n = (long)(0.4 / scale); i < n; i++) {
        random_increment(&seed, scale, d);
        memcpy(old, sig, sizeof old);
        rf_material_update(m, d, sig, &st, &dw);
        for (int j = 0; j < 6; j++)
            w_int += 0.5 * (old[j] + sig[j]) * d[j];
        w_p += dw;
    }
    return fabs(w_int - (rf_material_elastic_energy(m, sig) - psi0) - w_p) / w_p;
}

static void energy_table(void)
{
    rf_material_params p[3];
    const char *label[3] = {"von_mises Y=50kPa H=1MPa", "DP 35deg psi=5 + cap", "DP 28deg + flat cap H_c=0"};
    for (int k = 0; k < 3; k++) {
        rf_material_params_default(&p[k]);
        p[k].E = 30e6;
        p[k].poisson = 0.3;
        p[k].model = k == 0 ? RF_MATERIAL_VON_MISES : RF_MATERIAL_DRUCKER_PRAGER;
    }
    p[0].yield = 5e4, p[0].hardening = 1e6;
    p[1].cohesion = 2e3, p[1].friction_angle = 35 * DEG, p[1].dilatancy_angle = 5 * DEG;
    p[1].cap_pressure = 5e4, p[1].cap_hardening = 5e6;
    p[2].cohesion = 2e3, p[2].friction_angle = 28 * DEG, p[2].cap_pressure = 2e4;
    printf("energy identity |W_int - elastic - W_p| / W_p, random paths to 0.4 strain:\n");
    printf("%-28s %10s %10s %10s\n", "model \\ increment", "4e-5", "1e-5", "2.5e-6");
    for (int k = 0; k < 3; k++) {
        rf_material m;
        rf_error err;
        if (rf_material_init(&m, &p[k], &err) != RF_OK)
            return;
        printf("%-28s", label[k]);
        for (double scale = 4e-5; scale > 2e-6; scale /= 4)
            printf(" %10.2e", energy_mismatch(&m, scale, 7 + (uint64_t)k));
        printf("\n");
    }
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atol(argv[1]) : 10000;
    int steps = argc > 2 ? atoi(argv[2]) : 200;
    rf_material_params p[4];
    const char *label[4] = {"elastic", "von_mises", "drucker_prager", "drucker_prager+cap"};
    for (int k = 0; k < 4; k++) {
        rf_material_params_default(&p[k]);
        p[k].E = 30e6;
        p[k].poisson = 0.3;
    }
    p[1].model = RF_MATERIAL_VON_MISES, p[1].yield = 5e4, p[1].hardening = 1e6;
    for (int k = 2; k < 4; k++)
        p[k].model = RF_MATERIAL_DRUCKER_PRAGER, p[k].cohesion = 2e3, p[k].friction_angle = 0.6,
        p[k].dilatancy_angle = 0.1;
    p[3].cap_pressure = 5e4, p[3].cap_hardening = 5e6;
    printf("points %zu, steps %d\n", n, steps);
    for (int k = 0; k < 4; k++) {
        rf_material m;
        rf_error err;
        if (rf_material_init(&m, &p[k], &err) != RF_OK) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        double c1, c2;
        double plastic = run(&m, n, steps, 1.0, &c1), elastic = run(&m, n, steps, 1e-6, &c2);
        printf("%-20s %6.1f ns/point-update plastic path, %6.1f ns elastic path (final eps_p_eq %.3g, %.3g)\n",
               label[k], plastic, elastic, c1, c2);
    }
    energy_table();
    return 0;
}
