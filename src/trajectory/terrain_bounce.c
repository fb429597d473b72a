/* terrain_bounce.c - the bounce laws of the 2D engine (bounce.c) in 3D, in
 * the frame of the surface's exact normal n at the impact point: the normal
 * velocity v_n = v.n (< 0 approaching) and the tangential vector
 * v_t = v - v_n n.
 *   constant         v_n' = -R_n v_n, v_t' = R_t v_t, spin 0
 *   velocity_scaled  R_n / (1 + (v_n/K)^2) (Pfeiffer & Bowen 1989)
 *   rigid_sphere     slip of the contact point s = v_t + omega x (-r n); the
 *                    impulse per unit mass that stops it is |s| / (1 + 1/k)
 *                    along s, k = I/(m r^2), capped by mu (1 + e) |v_n|;
 *                    v_t' = v_t - P s^, omega' = omega + P (n x s^) / (k r).
 *                    In a plane (omega along n x t) it is the 2D law.
 *   impact_model     R_n, R_t, spin ratio from the impact table at (|v_n|,
 *                    incidence), spin about n x t; scaled down if the
 *                    interpolation would add energy.
 * Roughness: n tilted by delta ~ N(0, sd) about an axis drawn uniformly in
 * the tangent plane (two draws of the stream 2 sample + 1, as 2D draws one);
 * a tilt the block does not approach, or after which it would go into the
 * true surface, is replaced by no tilt.  None of the laws can add kinetic
 * energy (R_n, R_t <= 1; the friction impulse never exceeds the one that stops
 * the slip; the table's values are capped). */
#include "trajectory/terrain_internal.h"

#include <math.h>

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double a[3], const double b[3], double c[3])
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    c[0] = x, c[1] = y, c[2] = z;
}

/* x - lo clamped to [0, w] (fmin(fmax(x - lo, 0), w) inlined: the same
 * value for finite x, a library call less). */
static inline double clamp_local(double x, double lo, double w)
{
    double X = x - lo;
    X = X > 0 ? X : 0;
    return X < w ? X : w;
}

void terrain_patch_normal(const rf_terrain *t, const terrain_patch *p, double x, double y, double n[3])
{
    double X = clamp_local(x, p->xi, t->dx), Y = clamp_local(y, p->yj, t->dy);
    double zx = p->b + p->d * Y, zy = p->c + p->d * X, s = 1 / sqrt(1 + zx * zx + zy * zy);
    n[0] = -zx * s, n[1] = -zy * s, n[2] = s;
}

void terrain_surface_normal(const rf_terrain *t, size_t ci, size_t cj, double x, double y, double n[3])
{
    terrain_patch p = terrain_patch_of(t, ci, cj);
    terrain_patch_normal(t, &p, x, y, n);
}

/* Kinetic energy per unit mass times 2 of (v, omega) with I/m = i_m. */
static double energy2(const double v[3], const double w[3], double i_m) { return dot3(v, v) + i_m * dot3(w, w); }

/* A law: (vn < 0, vt in the tangent plane of n, omega) -> (vn' >= 0, vt', omega'). */
typedef struct {
    const terrain_run *r;
    const rf_traj_material *m;
    const double *n;
} bounce_ctx;

static void rigid_sphere3(const bounce_ctx *c, double vn, double vt[3], double w[3], double *vn_out)
{
    const terrain_run *r = c->r;
    double e = c->m->R_n, mu = tan(c->m->friction_angle), rad = r->radius;
    double k = r->inertia / (r->mass * rad * rad);
    double wxn[3], slip[3];
    cross3(w, c->n, wxn);
    for (int q = 0; q < 3; q++)
        slip[q] = vt[q] - rad * wxn[q];
    double s = sqrt(dot3(slip, slip));
    *vn_out = e * fabs(vn);
    if (s == 0)
        return;
    double p = fmin(s / (1 + 1 / k), mu * (1 + e) * fabs(vn)), sh[3] = {slip[0] / s, slip[1] / s, slip[2] / s};
    double nxs[3];
    cross3(c->n, sh, nxs);
    for (int q = 0; q < 3; q++) {
        vt[q] -= p * sh[q];
        w[q] += p * nxs[q] / (k * rad);
    }
}

static void impact_model3(const bounce_ctx *c, double vn, double vt[3], double w[3], double *vn_out)
{
    const terrain_run *r = c->r;
    double st = sqrt(dot3(vt, vt)), rn, rt, spin;
    traj_impact_table_lookup(r->w->impact_table, (size_t)(c->m - r->s->materials), r->radius, fabs(vn),
                             atan2(st, fabs(vn)), &rn, &rt, &spin); /* the cell class's table at the block's radius */
    double i_m = r->mass > 0 ? r->inertia / r->mass : 0, e_in = vn * vn + energy2(vt, w, i_m);
    *vn_out = rn * fabs(vn);
    for (int q = 0; q < 3; q++)
        vt[q] *= rt;
    double nxt[3];
    cross3(c->n, vt, nxt); /* |n x vt'| = |vt'|: spin ratio * vt' / r about n x t */
    for (int q = 0; q < 3; q++)
        w[q] = r->radius > 0 ? spin * nxt[q] / r->radius : 0;
    double e_out = *vn_out * *vn_out + energy2(vt, w, i_m);
    if (e_out > e_in && e_out > 0) {
        double f = sqrt(e_in / e_out);
        *vn_out *= f;
        for (int q = 0; q < 3; q++)
            vt[q] *= f, w[q] *= f;
    }
}

/* The law of the spec on (vn, vt, w) in the frame of n. */
static void apply_law(const bounce_ctx *c, double vn, double vt[3], double w[3], double *vn_out)
{
    const terrain_run *r = c->r;
    double Rn = c->m->R_n;
    switch (r->s->law) {
    case RF_BOUNCE_VELOCITY_SCALED: {
        double q = vn / r->s->scale_speed;
        Rn /= 1 + q * q;
    } /* fall through */
    case RF_BOUNCE_CONSTANT:
        *vn_out = Rn * fabs(vn);
        for (int q = 0; q < 3; q++)
            vt[q] *= c->m->R_t, w[q] = 0; /* lumped mass: no spin */
        return;
    case RF_BOUNCE_RIGID_SPHERE:
        rigid_sphere3(c, vn, vt, w, vn_out);
        return;
    default:
        impact_model3(c, vn, vt, w, vn_out);
    }
}

/* The normal n tilted by the roughness (unchanged without roughness). */
static void tilt_normal(terrain_run *r, double sd, const double n[3], double nt[3])
{
    nt[0] = n[0], nt[1] = n[1], nt[2] = n[2];
    if (!(sd > 0))
        return;
    double u1 = rf_traj_uniform(r->seed, r->sample * 2 + 1, r->n_rough++);
    double u2 = rf_traj_uniform(r->seed, r->sample * 2 + 1, r->n_rough++);
    double delta = rf_traj_normal_quantile(u1) * sd, phi = 2 * RF_PI * u2;
    double h = sqrt(n[2] * n[2] + n[0] * n[0]);    /* n_z > 0 on a DEM */
    double e1[3] = {n[2] / h, 0, -n[0] / h}, e2[3], a[3], axn[3];
    cross3(n, e1, e2);
    for (int q = 0; q < 3; q++)
        a[q] = cos(phi) * e1[q] + sin(phi) * e2[q]; /* the axis, in the tangent plane */
    cross3(a, n, axn);
    for (int q = 0; q < 3; q++)
        nt[q] = n[q] * cos(delta) + axn[q] * sin(delta);
}

static double cell_roughness(const terrain_run *r, size_t ci, size_t cj, const rf_traj_material *m)
{
    const rf_terrain *t = r->dem;
    return t->roughness ? (double)t->roughness[cj * (t->nx - 1) + ci] : m->roughness;
}

int terrain_bounce(terrain_run *r, size_t ci, size_t cj, double v[3], double omega[3])
{
    double n[3];
    terrain_surface_normal(r->dem, ci, cj, r->p[0], r->p[1], n);
    return terrain_bounce_n(r, ci, cj, n, v, omega);
}

int terrain_bounce_n(terrain_run *r, size_t ci, size_t cj, const double n[3], double v[3], double omega[3])
{
    const rf_traj_material *m = &r->s->materials[terrain_material_of(r->dem, ci, cj)];
    double vn0 = dot3(v, n);
    if (-vn0 < r->s->contact_speed) { /* soft landing: keep the part along the surface */
        for (int q = 0; q < 3; q++)
            v[q] -= vn0 * n[q];
        return 1;
    }
    double nt[3];
    tilt_normal(r, cell_roughness(r, ci, cj, m), n, nt);
    bounce_ctx c = {r, m, nt};
    for (int attempt = 0; attempt < 2; attempt++) {
        double vn = dot3(v, nt);
        if (vn < 0) {
            double vt[3], w[3] = {omega[0], omega[1], omega[2]}, vn_out = 0, out[3];
            for (int q = 0; q < 3; q++)
                vt[q] = v[q] - vn * nt[q];
            apply_law(&c, vn, vt, w, &vn_out);
            for (int q = 0; q < 3; q++)
                out[q] = vn_out * nt[q] + vt[q];
            if (attempt == 1 || dot3(out, n) >= 0) {
                for (int q = 0; q < 3; q++)
                    v[q] = out[q], omega[q] = w[q];
                return 0;
            }
        }
        nt[0] = n[0], nt[1] = n[1], nt[2] = n[2]; /* retry without tilt */
    }
    return 0;
}
