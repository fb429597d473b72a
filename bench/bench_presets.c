/* bench_presets.c - R_n of each material preset (presets.h, docs/presets.md)
 * from its own impact model, set against the practitioners' R_n: a granite
 * sphere (radius r, 2600 kg/m^3) falls normally at v on the preset's ground,
 * built exactly as a trajectory's impact_model law builds it (the preset's
 * rows stored into the impact input by name, its words parsed), in the
 * axisymmetric FE model (threads 1).  Options:
 *   bench_presets [preset=NAME] [v=v1,v2,..] [r=m] [ref=a/h] [soil=1] [set=FIELD:VALUE,..]
 *                 [theta=deg1,deg2,..] [rock=K] [g=m/s^2] [vn=1] [ground=stable|incidence]
 * set: impact inputs (rockfuzz impact names and units, e.g. layer_cap_pressure:50e3)
 * set after the preset's, e.g. a corner of the preset's fuzzy support.
 * ref: FE refinement (0 = the solver's default); soil=1: the table preset of
 * docs/soil-impacts.md section 4 (tuning soil_contact_mesh, with ref=6).
 * One CSV row per impact on stdout:
 *   preset,v_m_s,r_m,ref,soil,R_n,Rn_lo,Rn_peak,Rn_hi,inside,penetration_m,W_p_KE0,energy_error,cpu_s
 * (Rn_lo..Rn_hi: the preset's fuzzy support of R_n, from the practitioners'
 * tables; inside: the model's R_n lies in it).  A failed run prints "failed"
 * and the message.
 *
 * theta (oblique mode, docs/presets.md section 4b): each impact at speed v
 * and incidence theta from the normal, in the 3D FE model, as a table's
 * impact_model law calls it (traj_impact_coefficients: a vertical speed v on
 * a slope inclined at theta, v_n = v cos theta, v_t = v sin theta; friction
 * tan(the preset's friction_angle); ref = the 3D a/h, 0 = its default 3;
 * rock = rock_mass_scale, by default 100 on a layer as the tables set it, 1
 * on a rock; g = gravity, by default auto = 9.81 m/s^2: a layer that cannot
 * stand on a slope of theta is refused by the FE, g=0 runs it gravity-free;
 * vn=1: the v list is the normal speed v_n, incidences below 1 deg are run
 * at 1 deg, both as the tables' nodes are; ground = the FE option, stable
 * by default as the tables set it: the ground no steeper than the layer
 * stands with FS 1.25, docs/soil-impacts.md section 4b).  One CSV row per impact:
 *   preset,v_m_s,theta_deg,v_n_m_s,ref,rock,g_m_s2,R_n,R_t,spin,Rn_lo,Rn_hi,Rt_lo,Rt_hi,
 *   penetration_m,W_p_KE0,W_f_KE0,energy_error,three_d,cpu_s
 * (spin: omega r / v_t' after the impact, 1 = rolling without slip). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "rockfuzz/fem.h"
#include "rockfuzz/impact.h"
#include "rockfuzz/material.h"
#include "rockfuzz/presets.h"
#include "bench_util.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* The preset's ground into the impact input, by the impact input's names
 * (the rows impact.<name>), as traj_impact_adapter.c's ground_apply does. */
static const char *overrides; /* set=FIELD:VALUE,... */
static double gravity = RF_GRAVITY_AUTO; /* g= */
static int normal_speeds;                 /* vn=1 */
static rf_fem_ground ground = RF_FEM_GROUND_STABLE; /* ground= */

/* The overrides into the impact input (by name); 0 on an unknown name. */
static int apply_overrides(rf_impact_input *in)
{
    const char *s = overrides;
    while (s && *s) {
        char name[64];
        size_t n = strcspn(s, ":");
        if (n >= sizeof name || !s[n])
            return 0;
        memcpy(name, s, n), name[n] = '\0';
        char *end;
        double v = strtod(s + n + 1, &end);
        const rf_impact_field *f = rf_impact_field_find(name);
        if (!f || end == s + n + 1)
            return 0;
        rf_impact_field_store(in, f, v);
        s = *end == ',' ? end + 1 : NULL;
    }
    return 1;
}

static int preset_input(const rf_traj_preset *p, rf_impact_input *in, rf_error *e)
{
    rf_impact_input_default(in);
    for (size_t i = 0; i < p->n_values; i++) {
        const char *key = p->values[i].key;
        if (strncmp(key, "impact.", 7))
            continue;
        const rf_impact_field *f = rf_impact_field_find(key + 7);
        if (!f)
            return 0;
        rf_impact_field_store(in, f, p->values[i].value);
    }
    if (p->boulder_material[0] && rf_impact_boulder_material_parse(p->boulder_material, &in->boulder_material, e))
        return 0;
    if (p->slope_material[0] && rf_material_model_parse(p->slope_material, &in->slope_material, e))
        return 0;
    if (p->layer_material[0] && rf_material_model_parse(p->layer_material, &in->layer_material, e))
        return 0;
    if (!apply_overrides(in)) {
        snprintf(e->msg, sizeof e->msg, "set=%s: expected FIELD:VALUE,... with impact input names", overrides);
        return 0;
    }
    return 1;
}

static double support(const rf_traj_preset *p, const char *key, int which)
{
    for (size_t i = 0; i < p->n_values; i++)
        if (!strcmp(p->values[i].key, key))
            return which < 0 ? p->values[i].lo : which > 0 ? p->values[i].hi : p->values[i].value;
    return NAN;
}

static double rn_support(const rf_traj_preset *p, int which) { return support(p, "R_n", which); }

static void run(const rf_traj_preset *p, double v, double r, double ref, int soil)
{
    rf_impact_input in;
    rf_error e = {0};
    if (!preset_input(p, &in, &e)) {
        printf("%s,%g,%g,%g,%d,failed,\"%s\"\n", p->name, v, r, ref, soil, e.msg);
        return;
    }
    in.radius = r, in.boulder_density = 2600, in.velocity = v;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.mesh_sizing = soil ? RF_FEM_SIZING_SOIL : RF_FEM_SIZING_HERTZ;
    o.threads = 1, o.refinement = ref;
    rf_impact_output out;
    rf_fem_history H = {0};
    const double c0 = cpu_now();
    const rf_status st = rf_fem_impact(&in, &o, &out, &H, &e);
    const double cpu = cpu_now() - c0, lo = rn_support(p, -1), hi = rn_support(p, 1);
    printf("%s,%g,%g,%g,%d,", p->name, v, r, ref, soil);
    if (st != RF_OK)
        printf("failed,%g,%g,%g,,,,,%.2f,\"%s\"\n", lo, rn_support(p, 0), hi, cpu, e.msg);
    else
        printf("%.4f,%g,%g,%g,%s,%.4f,%.4f,%.2e,%.2f\n", out.R_n, lo, rn_support(p, 0), hi,
               out.R_n >= lo && out.R_n <= hi ? "yes" : "no", out.penetration_max, out.plastic_work,
               H.closure[H.n - 1] / H.ke0, cpu);
    fflush(stdout);
    if (st == RF_OK)
        rf_fem_history_free(&H);
}

/* One oblique impact (theta_deg from the normal) in the 3D model; rock <= 0:
 * the tables' choice (100 on a layer, 1 on a rock). */
static void run_oblique(const rf_traj_preset *p, double v, double theta_deg, double r, double ref, double rock)
{
    rf_impact_input in;
    rf_error e = {0};
    if (normal_speeds && theta_deg < 1)
        theta_deg = 1;
    const double th = theta_deg * M_PI / 180;
    if (normal_speeds)
        v /= cos(th);
    if (!preset_input(p, &in, &e)) {
        printf("%s,%g,%g,%g,%g,%g,%g,failed,\"%s\"\n", p->name, v, theta_deg, v * cos(th), ref, rock, gravity, e.msg);
        return;
    }
    in.radius = r, in.boulder_density = 2600, in.velocity = v, in.slope_angle = th;
    in.friction = tan(support(p, "friction_angle", 0) * M_PI / 180);
    in.gravity = gravity;
    if (rock <= 0)
        rock = in.layer_thickness > 0 ? 100 : 1;
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.threads = 1, o.refinement = ref, o.rock_mass_scale = rock, o.ground = ground;
    rf_impact_output out;
    rf_fem_history H = {0};
    double wf = 0;
    int three_d = 0;
    const double c0 = cpu_now();
    const rf_status st = rf_fem_solve(&in, &o, &out, &H, &wf, &three_d, &e);
    const double cpu = cpu_now() - c0;
    printf("%s,%g,%g,%.4g,%g,%g,%g,", p->name, v, theta_deg, v * cos(th), ref, rock, rf_impact_gravity(&in, 1));
    if (st != RF_OK) {
        printf("failed,,,,,,,,,,,,%.2f,\"%s\"\n", cpu, e.msg);
        return;
    }
    const double spin = fabs(out.v_t_after) > 1e-12 ? out.omega_after * r / out.v_t_after : 0;
    printf("%.4f,%.4f,%.3f,%g,%g,%g,%g,%.4f,%.4f,%.4f,%.2e,%d,%.2f\n", out.R_n, out.R_t, spin, rn_support(p, -1),
           rn_support(p, 1), support(p, "R_t", -1), support(p, "R_t", 1), out.penetration_max, out.plastic_work,
           wf / H.ke0, H.closure[H.n - 1] / H.ke0, three_d, cpu);
    fflush(stdout);
    rf_fem_history_free(&H);
}

int main(int argc, char **argv)
{
    double v[16] = {1, 5, 10}, theta[16], r = 0.5, ref = 0, rock = 0;
    int nv = 3, soil = 0, nt = 0;
    const char *only = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strncmp(argv[i], "v=", 2))
            nv = parse_list(argv[i] + 2, v, 16);
        else if (!strncmp(argv[i], "preset=", 7))
            only = argv[i] + 7;
        else if (!strncmp(argv[i], "r=", 2))
            r = atof(argv[i] + 2);
        else if (!strncmp(argv[i], "ref=", 4))
            ref = atof(argv[i] + 4);
        else if (!strncmp(argv[i], "set=", 4))
            overrides = argv[i] + 4;
        else if (!strncmp(argv[i], "theta=", 6))
            nt = parse_list(argv[i] + 6, theta, 16);
        else if (!strncmp(argv[i], "vn=", 3))
            normal_speeds = atoi(argv[i] + 3);
        else if (!strncmp(argv[i], "g=", 2))
            gravity = atof(argv[i] + 2);
        else if (!strcmp(argv[i], "ground=stable") || !strcmp(argv[i], "ground=incidence"))
            ground = strcmp(argv[i] + 7, "incidence") ? RF_FEM_GROUND_STABLE : RF_FEM_GROUND_INCIDENCE;
        else if (!strncmp(argv[i], "rock=", 5))
            rock = atof(argv[i] + 5);
        else if (!strncmp(argv[i], "soil=", 5))
            soil = atoi(argv[i] + 5);
        else {
            fprintf(stderr, "bench_presets: unknown argument '%s'\n", argv[i]);
            return 2;
        }
    }
    const rf_traj_preset *p;
    if (nt > 0) {
        printf("preset,v_m_s,theta_deg,v_n_m_s,ref,rock,g_m_s2,R_n,R_t,spin,Rn_lo,Rn_hi,Rt_lo,Rt_hi,penetration_m,W_p_KE0,"
               "W_f_KE0,energy_error,three_d,cpu_s\n");
        for (size_t k = 0; (p = rf_traj_preset_at(k)); k++)
            for (int j = 0; (!only || !strcmp(only, p->name)) && j < nv; j++)
                for (int t = 0; t < nt; t++)
                    run_oblique(p, v[j], theta[t], r, ref, rock);
        return 0;
    }
    printf("preset,v_m_s,r_m,ref,soil,R_n,Rn_lo,Rn_peak,Rn_hi,inside,penetration_m,W_p_KE0,energy_error,cpu_s\n");
    for (size_t k = 0; (p = rf_traj_preset_at(k)); k++)
        if (!only || !strcmp(only, p->name))
            for (int j = 0; j < nv; j++)
                run(p, v[j], r, ref, soil);
    return 0;
}
