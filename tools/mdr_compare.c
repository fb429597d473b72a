/* mdr_compare.c - one oblique impact by the MDR partial-slip model
 * (rockfuzz/mdr.h) and, on request, by the 3D FE (rockfuzz/fem3d.h), side by
 * side, for docs/validation-mdr.md.  Usage:
 *   mdr_compare [key=value ...]
 * keys (SI, angle in degrees): v, angle, f, r0, rho_b, rho_s, E_b, E_s, nu_b,
 *   nu_s, en (MDR normal COR; default 1 = elastic), spin (initial omega, rad/s),
 *   springs, steps (MDR discretisation), body (finite-body normal constant c,
 *   see below; default 0), arm (1: lever arm R - D/2 in the body variant),
 *   Iscale (inertia factor of the body variant, e.g. the FE's lumped I / exact I),
 *   fem (1 = also run the FE), ref (a/h), bc
 *   (fixed|absorbing), dom (L/r0), dtsafety, end (s), threads.
 * Prints one line "key=value ..." with, for each model, R_n, R_t, omega',
 * beta_t = v_c'/v_c (contact-point velocity after/before) and psi1, psi2.
 *
 * body = c > 0 runs a DIAGNOSTIC variant of the MDR (not the library model):
 * the CM approach D is taken smaller than the local Hertz indentation d by
 * c F / (E* R), F = 4/3 E* R^1/2 d^3/2, i.e. the finite sphere's stiffening
 * measured in the normal FE (fem_notes.md: -19 (a/R) % of the compression,
 * c = 0.14), with the contact radius kept Hertzian (a = sqrt(R d)).  With
 * arm=1 the friction force also acts at R - D/2 from the centre (the boulder's
 * share of the approach brings the contact closer), and Iscale multiplies I.
 * It tests how much of the FE's lower R_t these finite-body effects explain. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/fem3d.h"
#include "fem/fem_tuning.h"
#include "rockfuzz/mdr.h"

#define DEG (3.14159265358979323846 / 180.0)

typedef struct {
    rf_impact_input in;
    double en, spin, body, Iscale;
    int arm;
    rf_mdr_options mo;
    rf_fem_options fo;
    rf_fem_tuning tu; /* fo's numerics (fem_tune) */
    int fem;
} config;

static int parse(config *c, int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        const char *eq = strchr(argv[i], '=');
        if (!eq)
            return fprintf(stderr, "bad argument %s\n", argv[i]), 0;
        size_t n = (size_t)(eq - argv[i]);
        const char *k = argv[i], *val = eq + 1;
        double x = atof(val);
#define KEY(s) (n == strlen(s) && !strncmp(k, s, n))
        if (KEY("v")) c->in.velocity = x;
        else if (KEY("angle")) c->in.slope_angle = x * DEG;
        else if (KEY("f")) c->in.friction = x;
        else if (KEY("r0")) c->in.radius = x;
        else if (KEY("rho_b")) c->in.boulder_density = x;
        else if (KEY("rho_s")) c->in.slope_density = x;
        else if (KEY("E_b")) c->in.boulder_E = x;
        else if (KEY("E_s")) c->in.slope_E = x;
        else if (KEY("nu_b")) c->in.boulder_poisson = x;
        else if (KEY("nu_s")) c->in.slope_poisson = x;
        else if (KEY("en")) c->en = x;
        else if (KEY("spin")) c->spin = x;
        else if (KEY("body")) c->body = x;
        else if (KEY("arm")) c->arm = (int)x;
        else if (KEY("Iscale")) c->Iscale = x;
        else if (KEY("springs")) c->mo.springs = (size_t)x;
        else if (KEY("steps")) c->mo.steps = (size_t)x;
        else if (KEY("fem")) c->fem = (int)x;
        else if (KEY("ref")) c->fo.refinement = x;
        else if (KEY("bc")) c->fo.boundary = !strcmp(val, "absorbing") ? RF_FEM_BOUNDARY_ABSORBING : RF_FEM_BOUNDARY_FIXED;
        else if (KEY("dom")) c->fo.domain_factor = x;
        else if (KEY("dtsafety")) fem_tune(&c->fo, &c->tu)->dt_safety = x;
        else if (KEY("end")) c->fo.end_time = x;
        else if (KEY("threads")) c->fo.threads = (int)x;
        else
            return fprintf(stderr, "unknown key %.*s\n", (int)n, k), 0;
#undef KEY
    }
    return 1;
}

static rf_mdr_problem problem(const config *c, double e_n)
{
    const rf_impact_input *in = &c->in;
    return (rf_mdr_problem){.radius = in->radius, .mass = rf_impact_mass(in),
                            .inertia = rf_impact_moment_of_inertia(in),
                            .E_star = rf_impact_effective_modulus(in), .G_star = rf_mdr_tangential_modulus(in),
                            .friction = in->friction, .e_n = e_n,
                            .v_n = in->velocity * cos(in->slope_angle),
                            .v_t = in->velocity * sin(in->slope_angle), .omega = c->spin};
}

/* Local indentation d with d - beta d^3/2 = D (finite-body variant). */
static double local_indentation(double D, double beta)
{
    if (D <= 0.0)
        return 0.0;
    double d = D;
    for (int k = 0; k < 30; k++)
        d -= (d - beta * pow(d, 1.5) - D) / (1.0 - 1.5 * beta * sqrt(d));
    return d;
}

/* The diagnostic finite-body MDR (elastic): velocity Verlet on the CM approach. */
static void finite_body_mdr(const rf_mdr_problem *p, double c_body, int arm, const rf_mdr_options *o,
                            rf_mdr_result *r)
{
    double d_max = pow(15.0 * p->mass * p->v_n * p->v_n / (16.0 * p->E_star * sqrt(p->radius)), 0.4);
    double dt = 2.94328 * d_max / p->v_n / (double)o->steps, beta = 4.0 * c_body / (3.0 * sqrt(p->radius));
    rf_mdr_contact ct;
    rf_mdr_contact_init(&ct, o->springs, 1.3 * sqrt(p->radius * d_max), p->radius, p->E_star, p->G_star,
                        p->friction, NULL);
    double D = 0.0, w = p->v_n, vt = p->v_t, om = p->omega, fn = 0.0, ft = 0.0, lever = p->radius;
    for (size_t k = 0; k < 4 * o->steps; k++) {
        w -= fn / p->mass * 0.5 * dt;
        vt -= ft / p->mass * 0.5 * dt;
        om += ft * lever / p->inertia * 0.5 * dt;
        double du = (vt - om * lever) * dt;
        D += w * dt;
        lever = arm ? p->radius - 0.5 * D : p->radius;
        if (D <= 0.0) {
            fn = ft = 0.0;
            break;
        }
        ft = rf_mdr_contact_step(&ct, local_indentation(D, beta), du, 1.0, &fn);
        w -= fn / p->mass * 0.5 * dt;
        vt -= ft / p->mass * 0.5 * dt;
        om += ft * lever / p->inertia * 0.5 * dt;
    }
    rf_mdr_contact_free(&ct);
    r->v_n_after = -w;
    r->v_t_after = vt;
    r->omega_after = om;
}

static void print_model(const char *tag, const rf_mdr_problem *p, double vn_after, double vt_after, double om)
{
    double ratio = p->G_star / p->E_star, vc = p->v_t - p->omega * p->radius, vc1 = vt_after - om * p->radius;
    printf(" %s_Rn=%.6f %s_Rt=%.6f %s_w=%.6f %s_beta=%.6f %s_psi2=%.6f", tag, vn_after / p->v_n, tag,
           p->v_t != 0.0 ? vt_after / p->v_t : NAN, tag, om, tag, vc != 0.0 ? vc1 / vc : NAN, tag,
           p->friction > 0.0 ? ratio * vc1 / (p->friction * p->v_n) : NAN);
}

static int run_fem(const config *c, double *en, double *inertia)
{
    rf_impact_output out;
    rf_fem_history h;
    rf_fem3d_report rep;
    memset(&rep, 0, sizeof rep);
    rf_error err = {0};
    if (rf_fem3d_impact_ex(&c->in, &c->fo, NULL, &out, &h, &rep, &err) != RF_OK) {
        printf(" fe_error=\"%s\"\n", err.msg);
        return 0;
    }
    rf_mdr_problem p = problem(c, 1.0);
    print_model("fe", &p, out.v_n_after, out.v_t_after, out.omega_after);
    printf(" fe_comp=%.6e fe_F=%.6e fe_tc=%.6e fe_err=%.2e fe_wall=%.2f fe_I=%.6e", out.compression_max,
           out.contact_force_max, out.contact_duration, out.energy_error, out.wall_seconds, rep.inertia_lumped);
    *en = out.R_n;
    *inertia = rep.inertia_lumped;
    rf_fem_history_free(&h);
    rf_fem3d_report_free(&rep);
    return 1;
}

int main(int argc, char **argv)
{
    config c = {.en = 1.0};
    rf_impact_input_default(&c.in);
    rf_mdr_options_default(&c.mo);
    rf_fem_options_default(&c.fo);
    c.fo.refinement = 4;
    c.fo.boundary = RF_FEM_BOUNDARY_ABSORBING;
    if (!parse(&c, argc, argv))
        return 2;
    rf_mdr_problem p = problem(&c, c.en);
    rf_mdr_result r;
    rf_error err = {0};
    if (rf_mdr_impact(&p, &c.mo, &r, &err) != RF_OK)
        return fprintf(stderr, "%s\n", err.msg), 1;
    rf_impact_output hertz;
    rf_impact_hertz(&c.in, &hertz, NULL);
    printf("chi=%.6f psi1=%.6f hertz_comp=%.6e hertz_a_over_R=%.6f", r.chi, r.psi1, hertz.compression_max,
           hertz.contact_radius / c.in.radius);
    print_model("mdr", &p, r.v_n_after, r.v_t_after, r.omega_after);
    if (c.body > 0.0 || c.arm || c.Iscale > 0.0) {
        rf_mdr_problem pe = problem(&c, 1.0);
        if (c.Iscale > 0.0)
            pe.inertia *= c.Iscale;
        rf_mdr_result rb = {0};
        finite_body_mdr(&pe, c.body, c.arm, &c.mo, &rb);
        print_model("body", &pe, rb.v_n_after, rb.v_t_after, rb.omega_after);
    }
    double en_fe = NAN, inertia_fe = NAN;
    if (c.fem && run_fem(&c, &en_fe, &inertia_fe) && en_fe > 0.0) {
        rf_mdr_problem pf = problem(&c, en_fe); /* the MDR with the FE's own R_n */
        rf_mdr_impact(&pf, &c.mo, &r, NULL);
        print_model("mdrfe", &pf, r.v_n_after, r.v_t_after, r.omega_after);
        if (c.body > 0.0) { /* all three finite-body effects, with the FE mesh's inertia */
            rf_mdr_problem pb = problem(&c, 1.0);
            pb.inertia = inertia_fe;
            rf_mdr_result rb = {0};
            finite_body_mdr(&pb, c.body, 1, &c.mo, &rb);
            print_model("fbI", &pb, rb.v_n_after, rb.v_t_after, rb.omega_after);
        }
    }
    printf("\n");
    return 0;
}
