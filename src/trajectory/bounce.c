/* bounce.c - the bounce laws, a registry of {name, parameters, validate,
 * apply} (BOUNCE_LAWS below: adding a law is its apply function, one line
 * there and its name in rf_bounce_law), in the frame (n, t) of the hit
 * segment, optionally tilted by the random roughness angle:
 *   constant         v_n' = -R_n v_n, v_t' = R_t v_t (no spin)
 *   velocity_scaled  R_n / (1 + (|v_n|/K)^2) (Pfeiffer & Bowen 1989, K = 9.144 m/s)
 *   rigid_sphere     rigid sphere with spin and Coulomb friction mu = tan(phi),
 *                    e_n = R_n (impact_refs.md sec. 4.1, with the pre-impact spin)
 *   impact_model     R_n, R_t and spin tabulated from a rockfuzz impact model
 * None of them can raise the kinetic energy: R_n, R_t <= 1, and a friction
 * impulse never exceeds the one that stops the slip. */
#include "trajectory/traj_internal.h"

#include <math.h>

/* Rigid sphere with pre-impact spin: slip of the contact point
 * s = v_t - omega r (omega > 0 rolls forward along t); normal impulse per unit
 * mass P_n = (1 + e) |v_n|; the tangential impulse P that stops the slip is
 * s / (1 + 1/k), k = I/(m r^2); Coulomb caps it at mu P_n.  With omega = 0 this
 * is rf_impact_rigid (src/impact/rigid_kinematics.c), checked in the tests. */
static void rigid_sphere(double vn_in, double vt, double omega, double e, double mu, double k, double r,
                         double *vn_out, double *vt_out, double *omega_out)
{
    double slip = vt - omega * r;
    double p_stick = fabs(slip) / (1 + 1 / k), p_slide = mu * (1 + e) * fabs(vn_in);
    double p = copysign(fmin(p_stick, p_slide), slip);
    *vn_out = e * fabs(vn_in);
    *vt_out = vt - p;
    *omega_out = omega + p / (k * r);
}

/* Random roughness: the slope angle tilted by delta ~ N(0, sd) at each impact;
 * a tilt the block does not approach, or after which it would not leave the
 * true segment, is replaced by no tilt (so roughness never creates energy nor
 * sends the block into the ground). */
static double roughness_angle(traj_run *r, double sd)
{
    if (!(sd > 0))
        return 0;
    double u = rf_traj_uniform(r->seed, r->sample * 2 + 1, r->n_rough++);
    return rf_traj_normal_quantile(u) * sd;
}

/* An interpolated (R_n, R_t, spin) may not be exactly energy-consistent: the
 * outgoing state is scaled down so that it never carries more kinetic energy
 * (translation + rotation) than the incoming one. */
static void cap_energy(const traj_run *r, double vn, double vt, double w_in, double *vn_out, double *vt_out,
                       double *omega)
{
    double k = r->mass > 0 ? r->inertia / r->mass : 0; /* I/m */
    double e_in = vn * vn + vt * vt + k * w_in * w_in;
    double e_out = *vn_out * *vn_out + *vt_out * *vt_out + k * *omega * *omega;
    if (e_out > e_in && e_out > 0) {
        double f = sqrt(e_in / e_out);
        *vn_out *= f, *vt_out *= f, *omega *= f;
    }
}

static void law_constant(traj_run *r, const rf_traj_material *m, double vn, double vt, double *vn_out,
                         double *vt_out, double *omega)
{
    (void)r;
    *vn_out = m->R_n * fabs(vn);
    *vt_out = m->R_t * vt;
    *omega = 0; /* lumped mass: no spin */
}

static void law_velocity_scaled(traj_run *r, const rf_traj_material *m, double vn, double vt, double *vn_out,
                                double *vt_out, double *omega)
{
    double q = vn / r->s->scale_speed, Rn = m->R_n;
    Rn /= 1 + q * q;
    *vn_out = Rn * fabs(vn);
    *vt_out = m->R_t * vt;
    *omega = 0;
}

static void law_rigid_sphere(traj_run *r, const rf_traj_material *m, double vn, double vt, double *vn_out,
                             double *vt_out, double *omega)
{
    rigid_sphere(vn, vt, *omega, m->R_n, tan(m->friction_angle), r->inertia / (r->mass * r->radius * r->radius),
                 r->radius, vn_out, vt_out, omega);
}

static void law_impact_model(traj_run *r, const rf_traj_material *m, double vn, double vt, double *vn_out,
                             double *vt_out, double *omega)
{
    double rn, rt, spin; /* the table of the segment's material at the block's radius */
    traj_impact_table_lookup(r->w->impact_table, (size_t)(m - r->s->materials), r->radius, fabs(vn),
                             atan2(fabs(vt), fabs(vn)), &rn, &rt, &spin);
    *vn_out = rn * fabs(vn);
    *vt_out = rt * vt;
    double w_in = *omega;
    *omega = r->radius > 0 ? spin * *vt_out / r->radius : 0;
    cap_energy(r, vn, vt, w_in, vn_out, vt_out, omega);
}

static rf_status any_block(const rf_traj_spec *s, rf_error *err)
{
    (void)s, (void)err;
    return RF_OK;
}

static rf_status needs_sphere(const rf_traj_spec *s, rf_error *err)
{
    if (!s->sphere)
        return rf_fail(err, RF_EINVAL, "bounce.law = %s: needs block.shape: sphere", rf_traj_bounce_law_names[s->law]);
    return RF_OK;
}

typedef void (*bounce_apply)(traj_run *r, const rf_traj_material *m, double vn, double vt, double *vn_out,
                             double *vt_out, double *omega);
typedef struct {
    const char *name;
    const char *parameters;  /* the inputs it reads */
    rf_status (*validate)(const rf_traj_spec *s, rf_error *err);
    bounce_apply apply;
} bounce_law;

/* In the order of rf_bounce_law. */
#define BOUNCE_LAWS(X) \
    X("constant", "materials.NAME.R_n, R_t", any_block, law_constant) \
    X("velocity_scaled", "materials.NAME.R_n, R_t; bounce.scale_speed", any_block, law_velocity_scaled) \
    X("rigid_sphere", "materials.NAME.R_n, friction_angle; the sphere's radius", needs_sphere, law_rigid_sphere) \
    X("impact_model", "bounce.impact; the sphere's radius and density", needs_sphere, law_impact_model)

#define LAW_ROW(name, params, validate, apply) {name, params, validate, apply},
#define LAW_NAME(name, params, validate, apply) name,
static const bounce_law laws[] = {BOUNCE_LAWS(LAW_ROW)};
const char *const rf_traj_bounce_law_names[RF_BOUNCE_N_LAWS] = {BOUNCE_LAWS(LAW_NAME)};
_Static_assert(sizeof laws / sizeof laws[0] == RF_BOUNCE_N_LAWS, "one registry row per rf_bounce_law");

const char *rf_traj_bounce_law_parameters(rf_bounce_law law)
{
    return (unsigned)law < RF_BOUNCE_N_LAWS ? laws[law].parameters : "";
}

rf_status traj_bounce_law_validate(const rf_traj_spec *s, rf_error *err)
{
    return laws[s->law].validate(s, err);
}

int traj_bounce(traj_run *r, size_t k, double *vx, double *vy, double *omega)
{
    const traj_segment *g = &r->w->seg[k];
    const rf_traj_material *m = &r->s->materials[g->material];
    double vn0 = g->nx * *vx + g->ny * *vy;
    if (-vn0 < r->s->contact_speed && g->ny > 0) { /* soft landing: keep the part along the segment */
        double vt = g->tx * *vx + g->ty * *vy;
        *vx = vt * g->tx, *vy = vt * g->ty;
        return 1;
    }
    double d = roughness_angle(r, m->roughness), c = cos(d), s = sin(d);
    for (int attempt = 0; attempt < 2; attempt++) {
        double nx = g->nx * c - g->ny * s, ny = g->nx * s + g->ny * c; /* n rotated by d */
        double tx = ny, ty = -nx;
        double vn = nx * *vx + ny * *vy, vt = tx * *vx + ty * *vy;
        if (vn < 0) {
            double vn_out = 0, vt_out = 0, w = *omega;
            laws[r->s->law].apply(r, m, vn, vt, &vn_out, &vt_out, &w);
            double ox = vn_out * nx + vt_out * tx, oy = vn_out * ny + vt_out * ty;
            if (attempt == 1 || g->nx * ox + g->ny * oy >= 0) {
                *vx = ox, *vy = oy, *omega = w;
                return 0;
            }
        }
        c = 1, s = 0; /* retry without tilt */
    }
    return 0;
}
