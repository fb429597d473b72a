/* bench_fem3d_probe.h - the key=value settings shared by the 3D FE probes
 * (bench_fem3d_layers.c: mesh settings of the granite impact; bench_fem3d_soil.c:
 * the soil layer): a run's inputs and options, set from the command line, and
 * the process's CPU clock.
 * Input keys: model=3d|axi, v= (m/s), angle= (deg), f=, E= (layer_E, Pa),
 * X0= (layer cap pressure, Pa), Hc= (layer cap hardening, Pa), t= (layer
 * thickness, m), law=elastic|drucker_prager (the layer's), g= (gravity, m/s^2).
 * Option keys: large=0|1, core= (fine_box_factor), domain= (domain_factor), end=
 * (end_time, s), boundary=fixed|absorbing, ratio= (boulder_mesh_ratio),
 * threads=, aspect= (layer_aspect), inner= (boulder_inner), elong=
 * (elongation), full=0|1, dt= (dt_safety),
 * kappa= (surface_mass_kappa of src/fem/fem_tuning.h; > 0 also turns it on in 3D, 0 off), sphere= (sphere_contact_3d, 1 on). */
#ifndef ROCKFUZZ_BENCH_FEM3D_PROBE_H
#define ROCKFUZZ_BENCH_FEM3D_PROBE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/util.h"
#include "rockfuzz/fem3d.h"
#include "fem/fem_tuning.h"

typedef struct {
    int axi;
    rf_impact_input in;
    rf_fem_options o;
    rf_fem3d_options o3;
    rf_fem_tuning t; /* o's numerics (fem_tune) */
} probe;

static inline double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

#define PROBE_KEY(s) (n == strlen(s) && !strncmp(arg, s, n))

/* 1 if the key (its first n characters of arg) is an input key; value after '='. */
static inline int probe_set_input(probe *p, const char *arg, size_t n, const char *val)
{
    const double x = atof(val);
    if (PROBE_KEY("model"))
        p->axi = !strcmp(val, "axi");
    else if (PROBE_KEY("v"))
        p->in.velocity = x;
    else if (PROBE_KEY("angle"))
        p->in.slope_angle = x * RF_PI / 180;
    else if (PROBE_KEY("f"))
        p->in.friction = x;
    else if (PROBE_KEY("E"))
        p->in.layer_E = x;
    else if (PROBE_KEY("X0"))
        p->in.layer_cap_pressure = x;
    else if (PROBE_KEY("Hc"))
        p->in.layer_cap_hardening = x;
    else if (PROBE_KEY("t"))
        p->in.layer_thickness = x;
    else if (PROBE_KEY("law"))
        p->in.layer_material = !strcmp(val, "elastic") ? RF_MATERIAL_ELASTIC : RF_MATERIAL_DRUCKER_PRAGER;
    else if (PROBE_KEY("g"))
        p->in.gravity = x;
    else
        return 0;
    return 1;
}

/* 1 if the key is an option key. */
static inline int probe_set_option(probe *p, const char *arg, size_t n, const char *val)
{
    const double x = atof(val);
    if (PROBE_KEY("large"))
        p->o.large_deformation = x > 0 ? RF_FEM_LARGE_DEFORMATION : RF_FEM_SMALL_STRAIN;
    else if (PROBE_KEY("core"))
        p->o3.fine_box_factor = x;
    else if (PROBE_KEY("kappa"))
        fem_tune(&p->o, &p->t)->surface_mass_kappa = x, p->t.surface_mass_3d = x > 0;
    else if (PROBE_KEY("sphere"))
        fem_tune(&p->o, &p->t)->sphere_contact_3d = x > 0;
    else if (PROBE_KEY("domain"))
        p->o.domain_factor = x;
    else if (PROBE_KEY("end"))
        p->o.end_time = x;
    else if (PROBE_KEY("boundary"))
        p->o.boundary = strcmp(val, "fixed") ? RF_FEM_BOUNDARY_ABSORBING : RF_FEM_BOUNDARY_FIXED;
    else if (PROBE_KEY("ratio"))
        fem_tune(&p->o, &p->t)->boulder_mesh_ratio = x;
    else if (PROBE_KEY("threads"))
        p->o.threads = (int)x;
    else if (PROBE_KEY("aspect"))
        p->o3.layer_aspect = x;
    else if (PROBE_KEY("inner"))
        p->o3.boulder_inner = x;
    else if (PROBE_KEY("elong"))
        p->o3.elongation = x;
    else if (PROBE_KEY("full"))
        p->o3.full_model = (int)x;
    else if (PROBE_KEY("dt"))
        fem_tune(&p->o, &p->t)->dt_safety = x;
    else
        return 0;
    return 1;
}
#undef PROBE_KEY

/* 1 if arg was a key=value setting; an unknown key stops the program (exit 2). */
static inline int probe_set(probe *p, const char *arg, const char *program)
{
    const char *eq = strchr(arg, '=');
    if (!eq)
        return 0;
    const size_t n = (size_t)(eq - arg);
    if (probe_set_input(p, arg, n, eq + 1) || probe_set_option(p, arg, n, eq + 1))
        return 1;
    fprintf(stderr, "%s: unknown key in '%s'\n", program, arg);
    exit(2);
}

/* One run of the probe's model (axisymmetric or 3D) with its CPU seconds;
 * a failed run stops the program (exit 1) with the solver's message. */
static inline double probe_run(const probe *p, rf_impact_output *out, rf_fem_history *H, rf_fem3d_report *rep,
                               const char *program)
{
    rf_error err = {0};
    const double c0 = cpu_seconds();
    rf_status st = p->axi ? rf_fem_impact(&p->in, &p->o, out, H, &err)
                          : rf_fem3d_impact_ex(&p->in, &p->o, &p->o3, out, H, rep, &err);
    if (st != RF_OK) {
        fprintf(stderr, "%s: %s\n", program, err.msg);
        exit(1);
    }
    return cpu_seconds() - c0;
}

#endif
