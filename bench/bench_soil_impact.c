/* bench_soil_impact.c - time to accuracy of the soil-layer impacts an impact
 * table needs (issue 29 item 2; docs/soil-impacts.md).  The S5 nominal
 * colluvium (examples/s5_v5.yaml: Drucker-Prager + cap, 1 m over granite,
 * rigid boulder r0 = 0.5 m, 1361 kg), with the defaults a table's FE call
 * gets (large deformation and gravity auto, absorbing boundary), over a
 * convergence ladder of the numerical levers: refinement a/h, domain radius,
 * boulder mesh, fine zone, grading, time-step safety, ALE, one thread.  The
 * first rung of a ladder is its reference (the finest); every rung prints its
 * CPU time (getrusage of this process), R_n, R_t, W_p/KE0, the energy error
 * (closure / KE0), the penetration and its difference from the reference, and
 * the ladder ends with the cheapest rung within 0.01 of the reference in R_n
 * and R_t ("time to accuracy 0.01").
 *   bench_soil_impact [case=n1|n5|n15|incline|all] [quick=1] [ref3d=1|2] [only=TEXT[,TEXT...]] [noref=1] [timeline=1] [early=1]
 *                     [key=value ...]
 * n1, n5, n15: axisymmetric normal impacts at 1, 5, 15 m/s; incline: the 3D
 * model, 30 deg slope, 10 m/s vertical (v_n 8.66, v_t 5 m/s), friction 0.5.
 * quick=1 skips the reference's finest rungs (for a smoke run: the reference
 * is then the next rung); only=TEXT[,TEXT...] runs the reference and the
 * rungs whose name contains one of the TEXTs (e.g. only=rock); timeline=1
 * prints under each rung where its simulated time went (print_timeline);
 * noref=1 with only= skips the reference too (the first rung run is then the
 * reference of the max|dR| column); early=1 runs every rung with the tuning's
 * end_at_separation (the run may end before 1.3 Hertz durations once the
 * boulder has left).  Other keys: the inputs of bench_fem3d_probe.h
 * (v=, E=, X0=, t=, f=, angle=, g=...) set the case's base before its ladder.
 * A failed rung prints its message and the ladder goes on. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "bench_fem3d_probe.h"
#include "core/util.h"
#include "rockfuzz/fem3d.h"
#include "bench_util.h"

/* One rung: the settings it changes from the case's base (0 = the base's). */
typedef struct {
    const char *name;
    double refinement, domain, ratio, core, grading, dt;
    int ale;  /* 0 base (auto = off), 1 on */
    int soil;    /* axisymmetric: 1 sizes the mesh from the layer's contact (mesh_sizing soil) */
    double rock; /* rock_mass_scale (0: the base's, 1) */
    int preset;  /* 1: the table preset rf_fem_soil_table_preset (sizing, a/h, rock scale), then the rung's others */
} rung;

/* The S5 nominal layer with the settings a table's FE call gets. */
static void s5_base(probe *p, double v, int three_d)
{
    rf_impact_input_default(&p->in);
    rf_impact_input *in = &p->in;
    in->radius = 0.5, in->velocity = v, in->gravity = RF_GRAVITY_AUTO;
    in->boulder_material = RF_MATERIAL_RIGID_BODY;
    in->layer_thickness = 1.0, in->layer_density = 1900, in->layer_E = 100e6, in->layer_poisson = 0.3;
    in->layer_material = RF_MATERIAL_DRUCKER_PRAGER, in->layer_cohesion = 10e3;
    in->layer_friction_angle = 40 * RF_PI / 180, in->layer_dilatancy_angle = 5 * RF_PI / 180;
    in->layer_cap_pressure = 200e3, in->layer_cap_hardening = 40e6;
    if (three_d)
        in->slope_angle = 30 * RF_PI / 180, in->friction = 0.5;
    rf_fem_options_default(&p->o);
    p->o.threads = 1;
    fem_tune(&p->o, &p->t);
    rf_fem3d_options_default(&p->o3);
    p->axi = !three_d;
}

typedef struct {
    int ok;
    double cpu, R_n, R_t, W_p, err, pen, elements, steps;
    char msg[160];
} result;

static int early;    /* key early=1: every rung with the tuning's end_at_separation */
static int timeline; /* key timeline=1: where a run's simulated time goes (print_timeline) */

/* The run's phases from its history, in Hertz durations t_h and as shares of
   the simulated time: the first contact, the peak force, the last sample
   with contact force, the time from which the boulder's velocity stays within
   0.005 V of the velocity the run reports (v_out: at separation, or 0 at
   rest) until that last contact (R_n settled to 0.005), and the end. */
static void print_timeline(const rf_fem_history *H, double V, double v_out)
{
    if (H->n < 2)
        return;
    const size_t n = H->n;
    const double t_end = H->t[n - 1], th = H->hertz_duration;
    double t_peak = 0, f_peak = 0, t_settled = 0;
    size_t last = 0;
    for (size_t k = 0; k < n; k++) {
        const double f = H->contact_force[k];
        if (f > 0)
            last = k;
        if (f > f_peak)
            f_peak = f, t_peak = H->t[k];
    }
    for (size_t k = last + 1; k-- > 0;)
        if (fabs(H->boulder_velocity[k] - v_out) > 0.005 * V) {
            t_settled = H->t[k];
            break;
        }
    const double t_last = H->t[last];
    printf("   timeline [s, /t_h, share of run]: t_h %.4g; peak force %.4g (%.2f, %.0f %%); v within 0.005 V of "
           "v_out %.4g (%.2f, %.0f %%); last contact %.4g (%.2f, %.0f %%); end %.4g (%.2f)\n",
           th, t_peak, t_peak / th, 100 * t_peak / t_end, t_settled, t_settled / th, 100 * t_settled / t_end,
           t_last, t_last / th, 100 * t_last / t_end, t_end, t_end / th);
}

static result run_rung(const probe *base, const rung *r)
{
    probe p = *base;
    p.o.tuning = &p.t; /* the copy's own numerics */
    if (r->preset) /* the preset first, the rung's own settings over it */
        rf_fem_soil_table_preset(&p.o);
    if (r->refinement > 0)
        p.o.refinement = r->refinement;
    if (r->domain > 0)
        p.o.domain_factor = r->domain;
    if (r->ratio > 0)
        p.t.boulder_mesh_ratio = r->ratio;
    if (r->core > 0) {
        if (p.axi)
            p.t.fine_zone_factor = r->core;
        else
            p.o3.fine_box_factor = r->core;
    }
    if (r->grading > 0)
        p.t.grading = r->grading;
    if (r->dt > 0)
        p.t.dt_safety = r->dt;
    if (r->ale)
        p.o.ale = RF_FEM_ALE_ON;
    p.t.end_at_separation = early;
    if (!r->preset)
        p.o.mesh_sizing = r->soil ? RF_FEM_SIZING_SOIL : RF_FEM_SIZING_HERTZ;
    if (r->rock > 0)
        p.o.rock_mass_scale = r->rock;
    rf_impact_output out;
    rf_fem_history H = {0};
    rf_fem3d_report rep = {0};
    rf_error e = {0};
    result res = {0};
    const double c0 = cpu_now();
    rf_status st = p.axi ? rf_fem_impact(&p.in, &p.o, &out, &H, &e)
                         : rf_fem3d_impact_ex(&p.in, &p.o, &p.o3, &out, &H, &rep, &e);
    res.cpu = cpu_now() - c0;
    if (st != RF_OK) {
        snprintf(res.msg, sizeof res.msg, "%.150s", e.msg);
        return res;
    }
    const double k0 = H.ke0;
    if (timeline)
        print_timeline(&H, p.in.velocity, out.v_n_after);
    res = (result){1, res.cpu, out.R_n, out.R_t, out.plastic_work, H.closure[H.n - 1] / k0, out.penetration_max,
                   out.elements, out.steps, ""};
    rf_fem_history_free(&H);
    rf_fem3d_report_free(&rep);
    return res;
}

static const char *only; /* key only=TEXT[,TEXT...]: the reference and the rungs whose name contains a TEXT */
static int noref;        /* key noref=1: with only=, not even the reference (the first rung run is then the reference) */

static int matches(const char *name, const char *list)
{
    for (const char *p = list; *p;) {
        const size_t n = strcspn(p, ",");
        for (const char *q = name; n > 0 && *q; q++)
            if (!strncmp(q, p, n))
                return 1;
        p += n + (p[n] == ',');
    }
    return 0;
}

/* Run a ladder (rungs[0] the reference), print it and its time to accuracy. */
static void ladder(const char *label, const probe *base, const rung *rungs, int n, int quick)
{
    printf("== %s: v=%g m/s angle=%.0f deg f=%g layer E=%.3g Pa t=%g m (%s)\n", label, base->in.velocity,
           base->in.slope_angle * 180 / RF_PI, base->in.friction, base->in.layer_E, base->in.layer_thickness,
           base->axi ? "axisymmetric" : "3D");
    printf("%-26s %9s %8s %8s %8s %8s %9s %8s %8s %8s\n", "rung", "cpu_s", "elements", "steps", "R_n", "R_t",
           "W_p/KE0", "energy", "pen_m", "max|dR|");
    fflush(stdout);
    result ref = {0};
    int best = -1, ref_i = -1;
    double best_cpu = INFINITY;
    for (int i = quick ? 1 : 0; i < n; i++) {
        if (only && (i > (quick ? 1 : 0) || noref) && !matches(rungs[i].name, only))
            continue;
        const result r = run_rung(base, &rungs[i]);
        if (!r.ok) {
            printf("%-26s %9.2f failed: %s\n", rungs[i].name, r.cpu, r.msg);
            fflush(stdout);
            continue;
        }
        if (!ref.ok)
            ref = r, ref_i = i;
        const double dt = fabs(r.R_t - ref.R_t), d = fmax(fabs(r.R_n - ref.R_n), isnan(dt) ? 0 : dt); /* axi: no R_t */
        printf("%-26s %9.2f %8.0f %8.0f %8.4f %8.4f %9.4f %8.1e %8.4f %8.4f\n", rungs[i].name, r.cpu, r.elements,
               r.steps, r.R_n, r.R_t, r.W_p, r.err, r.pen, d);
        fflush(stdout);
        if (d <= 0.01 && r.cpu < best_cpu && i != ref_i)
            best = i, best_cpu = r.cpu;
    }
    if (best >= 0)
        printf("time to accuracy 0.01 (%s): %.2f s CPU, rung %s\n\n", label, best_cpu, rungs[best].name);
    else
        printf("time to accuracy 0.01 (%s): no rung other than the reference is within 0.01\n\n", label);
}

/* Axisymmetric ladder, in two parts.  The mesh sized as by default (from the
   finer of the rock's and the layer's Hertz radius, the uniform zone over 2.5 of
   it): a/h 10 (the default), 6, 4, 3, 2.  The mesh sized from the layer's own
   contact (soil_contact_mesh; a/h across the estimated soil contact, the uniform
   zone over it): a/h 16 (the reference, the finest rung), 12, 8, 6, 4, 3, 2, and
   the other levers at a/h 4 (domain, boulder mesh, grading, ALE). */
static const rung AXI[] = {
    {"ref soil a/h16", 16, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h12", 12, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h8", 8, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h6", 6, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h4", 4, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h3", 3, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h2", 2, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h16 rock100", 16, 0, 0, 0, 0, 0, 0, 1, 100, 0},
    {"soil a/h12 rock100", 12, 0, 0, 0, 0, 0, 0, 1, 100, 0},
    {"soil a/h8 rock100", 8, 0, 0, 0, 0, 0, 0, 1, 100, 0},
    {"preset (rf_fem_soil_table_preset)", 0, 0, 0, 0, 0, 0, 0, 1, 0, 1},
    {"soil a/h6 rock100", 6, 0, 0, 0, 0, 0, 0, 1, 100, 0},
    {"soil a/h5 rock100", 5, 0, 0, 0, 0, 0, 0, 1, 100, 0},
    {"soil a/h5", 5, 0, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h6 rock16", 6, 0, 0, 0, 0, 0, 0, 1, 16, 0},
    {"soil a/h6 rock1000", 6, 0, 0, 0, 0, 0, 0, 1, 1000, 0},
    {"soil a/h4 rock100", 4, 0, 0, 0, 0, 0, 0, 1, 100, 0},
    {"soil a/h12 rock100 dt0.3", 12, 0, 0, 0, 0, 0.3, 0, 1, 100, 0},
    {"soil a/h8 rock100 dt0.3", 8, 0, 0, 0, 0, 0.3, 0, 1, 100, 0},
    {"soil a/h16 dt0.3", 16, 0, 0, 0, 0, 0.3, 0, 1, 0, 0},
    {"soil a/h4 domain5", 4, 5, 0, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h4 ratio1.25", 4, 0, 1.25, 0, 0, 0, 0, 1, 0, 0},
    {"soil a/h4 grading1.3", 4, 0, 0, 0, 1.3, 0, 0, 1, 0, 0},
    {"soil a/h4 ale", 4, 0, 0, 0, 0, 0, 1, 1, 0, 0},
    {"default a/h10", 10, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"hertz a/h6", 6, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"hertz a/h4", 4, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"hertz a/h3", 3, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"hertz a/h2", 2, 0, 0, 0, 0, 0, 0, 0, 0, 0},
};

/* 3D ladder: the reference a/h 2.5 (a/h 3, the default, and 4 take minutes of CPU: too long
   for the shared machine these were measured on), then a/h 2 and 1.5 and the other levers at
   a/h 2; key ref3d=1 puts the default a/h 3 first as the reference, ref3d=2 a/h 4 with the
   rock's inertia x100 (rock_mass_scale; docs/soil-impacts.md section 3). */
static const rung F3D[] = {
    {"ref a/h4 rock100", 4, 0, 0, 0, 0, 0, 0, 0, 100, 0},
    {"ref a/h3 (default)", 3, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"ref a/h2.5", 2.5, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"a/h2", 2, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"a/h1.5", 1.5, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {"a/h2 domain4", 2, 4, 0, 0, 0, 0, 0, 0, 0, 0},
    {"a/h2 ratio2", 2, 0, 2, 0, 0, 0, 0, 0, 0, 0},
    {"a/h2 core1.1", 2, 0, 0, 1.1, 0, 0, 0, 0, 0, 0},
    {"a/h2 rock100", 2, 0, 0, 0, 0, 0, 0, 0, 100, 0},
    {"a/h2 rock4", 2, 0, 0, 0, 0, 0, 0, 0, 4, 0},
    {"a/h2 rock16", 2, 0, 0, 0, 0, 0, 0, 0, 16, 0},
    {"a/h2 rock100 dt0.3", 2, 0, 0, 0, 0, 0.3, 0, 0, 100, 0},
    {"a/h2.5 rock100", 2.5, 0, 0, 0, 0, 0, 0, 0, 100, 0},
    {"a/h3 rock100", 3, 0, 0, 0, 0, 0, 0, 0, 100, 0},
    {"a/h4 rock100", 4, 0, 0, 0, 0, 0, 0, 0, 100, 0},
    {"a/h5 rock100 ratio2", 5, 0, 2, 0, 0, 0, 0, 0, 100, 0},
    {"a/h4 rock100 ratio2", 4, 0, 2, 0, 0, 0, 0, 0, 100, 0},
    {"a/h3 rock100 ratio2", 3, 0, 2, 0, 0, 0, 0, 0, 100, 0},
    {"a/h2 rock100 ratio2", 2, 0, 2, 0, 0, 0, 0, 0, 100, 0},
    {"a/h3 rock100 core2", 3, 0, 0, 2, 0, 0, 0, 0, 100, 0},
};

int main(int argc, char **argv)
{
    const char *which = "all";
    int quick = 0, ref3d = 0;
    probe over;
    s5_base(&over, 0, 0);
    int nover = 0;
    const char *overs[32];
    for (int i = 1; i < argc; i++) {
        if (!strncmp(argv[i], "case=", 5))
            which = argv[i] + 5;
        else if (!strncmp(argv[i], "ref3d=", 6))
            ref3d = atoi(argv[i] + 6);
        else if (!strncmp(argv[i], "quick=", 6))
            quick = atoi(argv[i] + 6);
        else if (!strncmp(argv[i], "early=", 6))
            early = atoi(argv[i] + 6);
        else if (!strncmp(argv[i], "noref=", 6))
            noref = atoi(argv[i] + 6);
        else if (!strncmp(argv[i], "timeline=", 9))
            timeline = atoi(argv[i] + 9);
        else if (!strncmp(argv[i], "only=", 5))
            only = argv[i] + 5;
        else if (nover < 32 && probe_set(&over, argv[i], "bench_soil_impact"))
            overs[nover++] = argv[i];
    }
    const struct {
        const char *name;
        double v;
        int three_d;
    } cases[] = {{"n1", 1, 0}, {"n5", 5, 0}, {"n15", 15, 0}, {"incline", 10, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        if (strcmp(which, "all") && strcmp(which, cases[c].name))
            continue;
        probe p;
        s5_base(&p, cases[c].v, cases[c].three_d);
        for (int k = 0; k < nover; k++)
            probe_set(&p, overs[k], "bench_soil_impact");
        if (cases[c].three_d)
        {
            const int first = ref3d == 2 ? 0 : ref3d == 1 ? 1 : 2;
            ladder(cases[c].name, &p, F3D + first, (int)(sizeof F3D / sizeof *F3D) - first, quick);
        }
        else
            ladder(cases[c].name, &p, AXI, (int)(sizeof AXI / sizeof *AXI), quick);
    }
    return 0;
}
