/* mdr.c - oblique elastic impact with exact Mindlin-Deresiewicz partial slip,
 * by the method of dimensionality reduction (Popov & Hess 2015, ch. 2-3, 8;
 * the problem of Maw, Barber & Fawcett 1976).  See rockfuzz/mdr.h.
 *
 * The spring bank.  Spring i stands for the strip i dx <= x < (i+1) dx of the
 * 1D profile g(x) = x^2/R.  Its normal force is the exact integral of
 * E* (d - g(x)) over the part of the strip in contact (|x| < a = sqrt(R d)),
 * so the bank's normal force is Hertz's 4/3 E* R^1/2 d^3/2 to round-off for
 * any number of springs.  Its tangential stiffness is G* times that contact
 * length.  Each step adds stiffness * du to the spring's force and caps it at
 * mu times its normal force (slip).  A spring that leaves the contact has a
 * zero cap, so it gives up its force: the Mindlin-Deresiewicz unloading.
 *
 * The impact.  The sphere's normal approach d, its CM velocity v_t and spin
 * omega are advanced by velocity Verlet with dt = t_Hertz / steps; the
 * tangential displacement increment of the contact is du = (v_t - omega R) dt.
 * Normal restitution e_n < 1 (Hunter's wave loss, which the elastic theory
 * does not contain) enters by scaling the normal force of the restitution
 * phase, and with it every spring's Coulomb cap, by e_n^2: the rebound then
 * leaves at e_n v_n and the normal impulse is (1 + e_n) m v_n, as in the
 * rigid-body law, so gross sliding reproduces rf_impact_rigid exactly. */
#include "rockfuzz/mdr.h"

#include "core/util.h"
#include "impact/impact_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

rf_status rf_mdr_contact_init(rf_mdr_contact *c, size_t n, double a_max, double R, double E_star,
                              double G_star, double friction, rf_error *err)
{
    *c = (rf_mdr_contact){0};
    if (n < 2 || n > 1000000 || !(a_max > 0.0) || !(R > 0.0) || !(E_star > 0.0) || !(G_star > 0.0) ||
        !(friction >= 0.0) || !isfinite(a_max + R + E_star + G_star + friction))
        return rf_fail(err, RF_EINVAL, "MDR contact: springs = %zu (2..1e6), a_max = %g m, R = %g m, "
                                       "E* = %g Pa, G* = %g Pa, friction = %g: need positive finite values",
                       n, a_max, R, E_star, G_star, friction);
    c->q = calloc(2 * n, sizeof *c->q);
    if (!c->q)
        return rf_fail(err, RF_ENOMEM, "out of memory for %zu MDR springs", n);
    c->w = c->q + n;
    c->n = n;
    c->dx = a_max / (double)n;
    for (size_t i = 0; i < n; i++) {
        double x0 = (double)i * c->dx, x1 = x0 + c->dx;
        c->w[i] = (x1 * x1 * x1 - x0 * x0 * x0) / (3.0 * R);
    }
    c->R = R;
    c->E_star = E_star;
    c->G_star = G_star;
    c->friction = friction;
    return RF_OK;
}

void rf_mdr_contact_free(rf_mdr_contact *c)
{
    free(c->q);
    *c = (rf_mdr_contact){0};
}

/* Length of the strip [x0, x0 + dx] inside the contact radius a. */
static double contact_length(double a, double x0, double dx)
{
    double l = a - x0;
    return l <= 0.0 ? 0.0 : (l < dx ? l : dx);
}

/* The springs 0 .. n_inner-1, wholly in contact before and after the step. */
static void step_inner(rf_mdr_contact *c, size_t n_inner, double d, double du, double scale, double *normal,
                       double *tangential)
{
    double sE = scale * c->E_star, dq = c->G_star * c->dx * du, n_sum = 0.0, t_sum = 0.0;
    for (size_t i = 0; i < n_inner; i++) {
        double p = sE * (d * c->dx - c->w[i]), cap = c->friction * p;
        double q = c->q[i] + dq;
        q = q > cap ? cap : (q < -cap ? -cap : q);
        c->q[i] = q;
        t_sum += q;
        n_sum += p;
    }
    *normal = n_sum;
    *tangential = t_sum;
}

double rf_mdr_contact_step(rf_mdr_contact *c, double d, double du, double scale, double *normal_force)
{
    double a = d > 0.0 ? sqrt(c->R * d) : 0.0;
    double inv3R = 1.0 / (3.0 * c->R), normal = 0.0, tangential = 0.0;
    double reach = (a > c->a ? a : c->a) / c->dx + 1.0; /* springs beyond carry nothing */
    size_t n = reach < (double)c->n ? (size_t)reach : c->n;
    double inner = (a < c->a ? a : c->a) / c->dx;
    size_t n_inner = inner < (double)n ? (size_t)inner : n;
    step_inner(c, n_inner, d, du, scale, &normal, &tangential);
    for (size_t i = n_inner; i < n; i++) { /* the strips the contact edge crossed */
        double x0 = (double)i * c->dx;
        double l = contact_length(a, x0, c->dx), l_old = contact_length(c->a, x0, c->dx);
        if (l <= 0.0) {
            c->q[i] = 0.0; /* out of contact: the spring carries nothing */
            continue;
        }
        double xe = x0 + l;
        double p = scale * c->E_star * (d * l - (xe * xe * xe - x0 * x0 * x0) * inv3R);
        double cap = c->friction * p;
        /* The part of the strip that left the contact takes its share of the
         * force with it; the part that entered during the step was loaded for
         * about half of it: midpoint stiffness, second order in dx and dt. */
        double q = c->q[i] * (l < l_old ? l / l_old : 1.0) + c->G_star * 0.5 * (l + l_old) * du;
        q = q > cap ? cap : (q < -cap ? -cap : q);
        c->q[i] = q;
        tangential += q;
        normal += p;
    }
    c->a = a;
    if (normal_force)
        *normal_force = 2.0 * normal; /* both halves of the profile */
    return 2.0 * tangential;
}

void rf_mdr_options_default(rf_mdr_options *o)
{
    o->springs = 100;
    o->steps = 400;
}

static rf_status check_problem(const rf_mdr_problem *p, const rf_mdr_options *o, rf_error *err)
{
    double all = p->radius + p->mass + p->inertia + p->E_star + p->G_star + p->friction + p->e_n + p->v_n +
                 p->v_t + p->omega;
    if (!isfinite(all) || !(p->radius > 0.0) || !(p->mass > 0.0) || !(p->inertia > 0.0) || !(p->E_star > 0.0) ||
        !(p->G_star > 0.0) || !(p->friction >= 0.0) || !(p->v_n > 0.0))
        return rf_fail(err, RF_EINVAL, "MDR impact: R = %g m, m = %g kg, I = %g kg m^2, E* = %g Pa, G* = %g Pa, "
                                       "friction = %g, v_n = %g m/s: need finite values, all > 0 (friction >= 0)",
                       p->radius, p->mass, p->inertia, p->E_star, p->G_star, p->friction, p->v_n);
    if (!(p->e_n >= 0.01 && p->e_n <= 1.0))
        return rf_fail(err, RF_EINVAL, "MDR impact: e_n = %g must lie in [0.01, 1]", p->e_n);
    if (o->steps < 10 || o->steps > 100000000 || o->springs < 2)
        return rf_fail(err, RF_EINVAL, "MDR impact: steps = %zu (10..1e8) and springs = %zu (>= 2)", o->steps,
                       o->springs);
    return RF_OK;
}

/* Hertz: maximum approach for the speed v_n, and the elastic duration. */
static double hertz_compression(const rf_mdr_problem *p)
{
    return pow(15.0 * p->mass * p->v_n * p->v_n / (16.0 * p->E_star * sqrt(p->radius)), 0.4);
}

static double hertz_duration(const rf_mdr_problem *p, double d_max)
{
    return 2.0 * 0.4 * tgamma(0.4) * tgamma(0.5) / tgamma(0.9) * d_max / p->v_n;
}

typedef struct {
    double d, w, vt, om;  /* approach [m], approach rate [m/s], CM tangential velocity, spin */
    double fn, ft;        /* normal force on the sphere, tangential force on the half-space [N] */
} mdr_state;

static void half_kick(mdr_state *s, const rf_mdr_problem *p, double dt)
{
    s->w -= s->fn / p->mass * 0.5 * dt;
    s->vt -= s->ft / p->mass * 0.5 * dt;
    s->om += s->ft * p->radius / p->inertia * 0.5 * dt;
}

/* Velocity Verlet until the sphere leaves the half-space; fills r except the
 * derived quantities. */
static void integrate(const rf_mdr_problem *p, rf_mdr_contact *c, size_t steps, double dt, rf_mdr_result *r)
{
    mdr_state s = {0.0, p->v_n, p->v_t, p->omega, 0.0, 0.0};
    double scale = 1.0, t = 0.0;
    size_t k = 0, max_steps = (size_t)((double)steps * (2.0 + 1.0 / p->e_n)) + 100;
    for (; k < max_steps; k++) {
        half_kick(&s, p, dt);
        if (s.w < 0.0)
            scale = p->e_n * p->e_n; /* restitution phase: see the file comment */
        double du = (s.vt - s.om * p->radius) * dt;
        s.d += s.w * dt;
        t += dt;
        if (s.d <= 0.0) {
            s.fn = s.ft = 0.0;
            break;
        }
        s.ft = rf_mdr_contact_step(c, s.d, du, scale, &s.fn);
        half_kick(&s, p, dt);
        if (s.fn > r->contact_force_max)
            r->contact_force_max = s.fn;
        if (fabs(s.ft) > r->tangential_force_max)
            r->tangential_force_max = fabs(s.ft);
        if (s.d > r->compression_max)
            r->compression_max = s.d;
    }
    r->v_n_after = -s.w;
    r->v_t_after = s.vt;
    r->omega_after = s.om;
    r->contact_duration = t;
    r->steps = k;
}

static void derive(const rf_mdr_problem *p, rf_mdr_result *r)
{
    double ratio = p->G_star / p->E_star;
    double vc = p->v_t - p->omega * p->radius, vc_after = r->v_t_after - r->omega_after * p->radius;
    r->contact_radius = sqrt(p->radius * r->compression_max);
    r->chi = 0.5 * ratio * (1.0 + p->mass * p->radius * p->radius / p->inertia);
    r->beta_t = vc != 0.0 ? vc_after / vc : NAN;
    r->psi1 = p->friction > 0.0 ? ratio * vc / (p->friction * p->v_n) : INFINITY;
    r->psi2 = p->friction > 0.0 ? ratio * vc_after / (p->friction * p->v_n) : INFINITY;
    if (p->friction == 0.0 && vc == 0.0)
        r->psi1 = r->psi2 = NAN;
    double ke0 = p->mass * (p->v_n * p->v_n + p->v_t * p->v_t) + p->inertia * p->omega * p->omega;
    double ke1 = p->mass * (r->v_n_after * r->v_n_after + r->v_t_after * r->v_t_after) +
                 p->inertia * r->omega_after * r->omega_after;
    double normal_loss = p->mass * (p->v_n * p->v_n - r->v_n_after * r->v_n_after);
    r->friction_work = 0.5 * (ke0 - ke1 - normal_loss);
}

rf_status rf_mdr_impact(const rf_mdr_problem *p, const rf_mdr_options *o, rf_mdr_result *r, rf_error *err)
{
    rf_mdr_options def;
    rf_mdr_options_default(&def);
    if (!o)
        o = &def;
    *r = (rf_mdr_result){0};
    rf_status st = check_problem(p, o, err);
    if (st != RF_OK)
        return st;
    double d_max = hertz_compression(p);
    rf_mdr_contact c;
    /* 5 % margin: the discrete trajectory may overshoot d_max by O(dt^2) */
    st = rf_mdr_contact_init(&c, o->springs, 1.05 * sqrt(p->radius * d_max), p->radius, p->E_star, p->G_star,
                             p->friction, err);
    if (st != RF_OK)
        return st;
    integrate(p, &c, o->steps, hertz_duration(p, d_max) / (double)o->steps, r);
    rf_mdr_contact_free(&c);
    derive(p, r);
    return RF_OK;
}

/* --- inputs of the impact model --- */

static double shear_modulus(double E, double nu)
{
    return E / (2.0 * (1.0 + nu));
}

double rf_mdr_tangential_modulus(const rf_impact_input *in)
{
    double Gb = shear_modulus(in->boulder_E, in->boulder_poisson);
    double Gs = shear_modulus(in->slope_E, in->slope_poisson);
    return 1.0 / ((2.0 - in->boulder_poisson) / (4.0 * Gb) + (2.0 - in->slope_poisson) / (4.0 * Gs));
}

/* Dundurs (1969): beta = [G_b (1-2nu_s) - G_s (1-2nu_b)] / [2 (G_b (1-nu_s) + G_s (1-nu_b))]. */
double rf_mdr_dundurs_beta(const rf_impact_input *in)
{
    return rf_dundurs_beta(in->boulder_E, in->boulder_poisson, in->slope_E, in->slope_poisson);
}

static void fill_output(const rf_impact_input *in, const rf_mdr_problem *p, const rf_mdr_result *r,
                        rf_impact_output *out)
{
    double V = in->velocity;
    out->contact_force_max = r->contact_force_max;
    out->compression_max = r->compression_max;
    out->contact_duration = r->contact_duration;
    out->contact_radius = r->contact_radius;
    out->v_n_before = -p->v_n;
    out->v_t_before = p->v_t;
    out->v_n_after = r->v_n_after;
    out->v_t_after = r->v_t_after;
    out->omega_after = r->omega_after;
    out->R_n = r->v_n_after / p->v_n;
    out->R_t = p->v_t > 0.0 ? r->v_t_after / p->v_t : NAN;
    out->R_ke = (p->mass * (r->v_n_after * r->v_n_after + r->v_t_after * r->v_t_after) +
                 p->inertia * r->omega_after * r->omega_after) / (p->mass * V * V);
}

rf_status rf_impact_mdr(const rf_impact_input *in, double e_n, rf_impact_output *out, rf_error *err)
{
    rf_impact_output_clear_(out);
    rf_status st = rf_impact_input_validate(in, err);
    if (st != RF_OK)
        return st;
    if (in->horizontal_axis > 0.0 && in->slope_angle > 0.0)
        return rf_fail(err, RF_EINVAL,
                       "horizontal_axis = %g with slope_angle = %g deg: the MDR model treats a spheroid "
                       "only in normal impact on its pole (slope_angle = 0); use the FE solver",
                       in->horizontal_axis, in->slope_angle * 180.0 / RF_PI);
    rf_mdr_problem p = {
        .radius = rf_impact_contact_curvature_radius(in),
        .mass = rf_impact_mass(in),
        .inertia = rf_impact_moment_of_inertia(in),
        .E_star = rf_impact_effective_modulus(in),
        .G_star = rf_mdr_tangential_modulus(in),
        .friction = in->friction,
        .e_n = e_n,
        .v_n = in->velocity * cos(in->slope_angle),
        .v_t = in->velocity * sin(in->slope_angle),
        .omega = 0.0,
    };
    rf_mdr_result r;
    st = rf_mdr_impact(&p, NULL, &r, err);
    if (st == RF_OK)
        fill_output(in, &p, &r, out);
    return st;
}

rf_status rf_impact_mdr_hunter(const rf_impact_input *in, double e_n, double hunter_A, rf_impact_output *out,
                               rf_error *err)
{
    if (isnan(e_n)) {
        rf_status st = rf_impact_hunter_A(in, hunter_A, out, err);
        if (st != RF_OK)
            return st;
        e_n = out->R_n;
    }
    return rf_impact_mdr(in, e_n, out, err);
}

/* The analytic checks, and a rigid boulder refused: MDR needs its tangential compliance. */
static rf_status mdr_validate(const rf_impact_law *law, const rf_impact_input *in, const rf_impact_law_settings *s,
                              rf_error *err)
{
    rf_status st = rf_impact_analytic_validate(law, in, s, err);
    if (st == RF_OK && in->boulder_material == RF_MATERIAL_RIGID_BODY)
        return rf_fail(err, RF_EINVAL, "boulder_material = rigid: the mdr solver takes the boulder's elastic "
                       "constants (its tangential compliance); use hertz, hunter, rigid or fem");
    return st;
}

static rf_status mdr_solve(const rf_impact_input *in, const rf_impact_law_settings *s, rf_impact_output *out,
                           rf_error *err)
{
    return rf_impact_mdr_hunter(in, s->e_n, s->hunter_coefficient, out, err);
}

/* e_n (rigid's words), then the discretisation of the partial-slip solution. */
static int mdr_identity(const rf_impact_law_settings *s, char *buf, size_t size)
{
    int n = rf_impact_en_identity(s, buf, size);
    rf_mdr_options mo;
    rf_mdr_options_default(&mo);
    size_t used = n > 0 && (size_t)n < size ? (size_t)n : size;
    int m = snprintf(buf + used, size - used, " mdr_springs=%zu mdr_steps=%zu", mo.springs, mo.steps);
    return n < 0 || m < 0 ? -1 : n + m;
}

const rf_impact_law rf_impact_law_mdr = {
    "mdr", "Hertz + exact Mindlin-Deresiewicz partial slip\n(elastic tangential compliance, micro-slip)",
    mdr_validate, mdr_solve, mdr_identity};
