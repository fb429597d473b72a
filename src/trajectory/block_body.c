/* block_body.c - the rigid block's state and its free flight (issue 30).
 *
 * State: centre x and velocity v in space, orientation q (unit quaternion,
 * body -> space), angular velocity w in the principal body frame.  Free
 * flight: the centre moves exactly (x += v h - g h^2/2 e_z); the rotation is
 * the free rigid rotor, integrated by the symplectic splitting of its
 * energy T = L1^2/2I1 + L2^2/2I2 + L3^2/2I3 (body angular momentum L) into
 * the three parts L_i^2/2I_i (Reich 1994; Dullweber, Leimkuhler & McLachlan
 * 1997, J. Chem. Phys. 107:5840).  The flow of one part is exact: a rotation
 * by theta = tau L_i/I_i about body axis i, of the orientation (q <- q
 * rot(e_i, theta)) and, backwards, of L in the body (L <- rot(e_i,
 * -theta) L), so that the space angular momentum R(q) L is unchanged.  The
 * Strang composition R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2) is symmetric and
 * second order: the space angular momentum and |L| are kept to round-off,
 * the energy to O(h^2) without drift (a symplectic method); q is
 * renormalised after each step (its drift is round-off). */
#include "trajectory/block_internal.h"

#include <string.h>

void rf_block_to_space(const double q[4], const double b[3], double s[3])
{
    double r[9];
    bk_quat_matrix(q, r);
    bk_mat_vec(r, b, s);
}

void rf_block_to_body(const double q[4], const double s[3], double b[3])
{
    double r[9];
    bk_quat_matrix(q, r);
    bk_mat_tvec(r, s, b);
}

/* Shepperd's method: the largest of 4w^2, 4x^2, 4y^2, 4z^2 first. */
void rf_block_quat_from_matrix(const double r[9], double q[4])
{
    double tr = r[0] + r[4] + r[8];
    if (tr >= r[0] && tr >= r[4] && tr >= r[8]) {
        double s = 2 * sqrt(1 + tr);
        q[0] = s / 4, q[1] = (r[7] - r[5]) / s, q[2] = (r[2] - r[6]) / s, q[3] = (r[3] - r[1]) / s;
    } else if (r[0] >= r[4] && r[0] >= r[8]) {
        double s = 2 * sqrt(1 + r[0] - r[4] - r[8]);
        q[0] = (r[7] - r[5]) / s, q[1] = s / 4, q[2] = (r[1] + r[3]) / s, q[3] = (r[2] + r[6]) / s;
    } else if (r[4] >= r[8]) {
        double s = 2 * sqrt(1 + r[4] - r[0] - r[8]);
        q[0] = (r[2] - r[6]) / s, q[1] = (r[1] + r[3]) / s, q[2] = s / 4, q[3] = (r[5] + r[7]) / s;
    } else {
        double s = 2 * sqrt(1 + r[8] - r[0] - r[4]);
        q[0] = (r[3] - r[1]) / s, q[1] = (r[2] + r[6]) / s, q[2] = (r[5] + r[7]) / s, q[3] = s / 4;
    }
    bk_quat_normalize(q);
}

void rf_block_angular_momentum(const rf_block_shape *s, const rf_block_state *st, double L[3])
{
    double lb[3] = {s->inertia[0] * st->w[0], s->inertia[1] * st->w[1], s->inertia[2] * st->w[2]};
    rf_block_to_space(st->q, lb, L);
}

double rf_block_kinetic_energy(const rf_block_shape *s, const rf_block_state *st, double rot[3])
{
    double e = 0.5 * s->mass * bk_dot(st->v, st->v);
    for (int i = 0; i < 3; i++) {
        double r = 0.5 * s->inertia[i] * st->w[i] * st->w[i];
        if (rot)
            rot[i] = r;
        e += r;
    }
    return e;
}

double rf_block_energy(const rf_block_shape *s, const rf_block_state *st, double g)
{
    return rf_block_kinetic_energy(s, st, NULL) + s->mass * g * st->x[2];
}

/* sin and cos of x; below |x| = 0.02 by their Taylor series, whose first
 * omitted terms (x^9/9!, x^10/10!) are below 1e-19 of the result there:
 * the same to round-off, without the libm call (the rotor's angles are
 * small at millisecond steps). */
static void sin_cos(double x, double *s, double *c)
{
    if (fabs(x) < 0.02) {
        double x2 = x * x;
        *s = x * (1 - x2 / 6 * (1 - x2 / 20 * (1 - x2 / 42)));
        *c = 1 - x2 / 2 * (1 - x2 / 12 * (1 - x2 / 30 * (1 - x2 / 56)));
    } else {
        *s = sin(x), *c = cos(x);
    }
}

/* The exact flow of L_i^2/2I_i over tau (iI: the inverse principal moments). */
static inline void rotor_axis(const double iI[3], double q[4], double L[3], int i, double tau)
{
    double theta = tau * L[i] * iI[i], c, s;
    sin_cos(theta / 2, &s, &c);
    int j = (i + 1) % 3, k = (i + 2) % 3;
    /* q <- q (c, s e_i): the quaternion product with its zero terms left out (the same bits) */
    double q0 = q[0], qi = q[1 + i], qj = q[1 + j], qk = q[1 + k];
    q[0] = q0 * c - qi * s, q[1 + i] = q0 * s + qi * c;
    q[1 + j] = qj * c + qk * s, q[1 + k] = qk * c - qj * s;
    double ct = 1 - 2 * s * s, st = 2 * s * c; /* cos, sin of theta from the half angle */
    double lj = L[j], lk = L[k];
    L[j] = ct * lj + st * lk; /* rot(e_i, -theta) */
    L[k] = -st * lj + ct * lk;
}

void rf_block_rotor_step(const double inertia[3], double q[4], double w[3], double h)
{
    /* the reciprocals once: the five turns are a chain, and a division in it costs ten products */
    double L[3] = {inertia[0] * w[0], inertia[1] * w[1], inertia[2] * w[2]};
    const double iI[3] = {1 / inertia[0], 1 / inertia[1], 1 / inertia[2]};
    rotor_axis(iI, q, L, 0, h / 2);
    rotor_axis(iI, q, L, 1, h / 2);
    rotor_axis(iI, q, L, 2, h);
    rotor_axis(iI, q, L, 1, h / 2);
    rotor_axis(iI, q, L, 0, h / 2);
    double n = 1 / sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    q[0] *= n, q[1] *= n, q[2] *= n, q[3] *= n;
    for (int i = 0; i < 3; i++) /* a division here: (L / I) I returns L where L (1/I) I drifts by a bias per step */
        w[i] = L[i] / inertia[i];
}

void rf_block_flight_step(const rf_block_shape *s, rf_block_state *st, double g, double h)
{
    for (int i = 0; i < 3; i++)
        st->x[i] += st->v[i] * h;
    st->x[2] -= 0.5 * g * h * h;
    st->v[2] -= g * h;
    rf_block_rotor_step(s->inertia, st->q, st->w, h);
}

double rf_block_lowest_point(const rf_block_shape *s, const rf_block_state *st, const double up[3], double p[3])
{
    double r[9], d[3] = {-up[0], -up[1], -up[2]}, db[3], pb[3];
    bk_quat_matrix(st->q, r);
    bk_mat_tvec(r, d, db);
    rf_block_support(s, db, pb);
    bk_mat_vec(r, pb, p);
    for (int i = 0; i < 3; i++)
        p[i] += st->x[i];
    return bk_dot(up, p);
}
