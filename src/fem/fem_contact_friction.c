/* fem_contact_friction.c - Coulomb friction on the axisymmetric contact's
 * pairs (static = kinetic coefficient mu).
 *
 * After the normal multipliers of a step have closed the predicted gaps
 * (fem_contact.c), each closed pair (lambda > 0) gets a tangential
 * multiplier lam_t along the master segment's tangent t = (n_z, -n_r) (radial
 * in small strain, where the gap is vertical).  Its row c_t gives the
 * relative tangential velocity of the slave and the master point,
 * s = c_t . v_{n+1/2}; the multipliers are the forces at step n that stop that
 * slip (stick) as far as |lam_t| <= mu lambda allows (slip at the bound,
 * opposing the motion).  The pairs are coupled through shared master nodes
 * and, for a rigid boulder, through its mass: projected Gauss-Seidel over
 * the closed pairs, started from each pair's force of the step before
 * (within its new bound), the explicit counterpart of the forward-increment
 * normal contact (Carpenter, Taylor & Katona 1991; the 3D solver's pairs are
 * solved the same way, fem3d_contact.c).  The tangential corrections move
 * master nodes along the surface, which changes the normal gaps only to
 * second order; the next step's normal solve closes what is left.
 * The friction work lam_t s dt (trapezoidal in v) is dissipated: the energy
 * account of the solver counts it as its own term. */
#include "fem_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { FRICTION_SWEEPS = 200 };

rf_status fem_contact_friction_setup(fem_contact *C, long ndof, double mu, rf_error *err)
{
    C->friction = mu, C->ndof = ndof;
    C->lam_t = calloc((size_t)C->npairs + 1, sizeof *C->lam_t);
    C->vt_old = calloc((size_t)ndof + 1, sizeof *C->vt_old);
    if (!C->lam_t || !C->vt_old)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    return RF_OK;
}

/* The tangential row of pair p: dofs (z of slave, masters; r of slave,
 * masters) and coefficients; a rigid boulder's slave has no r dof. */
static void tangential_row(const fem_contact *C, const contact_pair *p, int dof[6], double c[6])
{
    const double tr = p->n[1], tz = -p->n[0], w1 = 1 - p->xi, w2 = p->xi;
    const int z[3] = {p->dof[0], p->dof[1], p->dof[2]};
    for (int k = 0; k < 3; k++)
        dof[k] = z[k], dof[3 + k] = p->rdof[k];
    c[0] = tz, c[1] = -w1 * tz, c[2] = -w2 * tz;
    c[3] = C->rigid_invm > 0 ? 0 : tr, c[4] = -w1 * tr, c[5] = -w2 * tr;
}

/* c . v, with a rigid boulder's pending velocity change drig on the slave's z. */
static double row_rate(const fem_contact *C, const int dof[6], const double c[6], const double *v, double drig)
{
    double s = 0;
    for (int q = 0; q < 6; q++)
        s += c[q] * v[dof[q]];
    return C->rigid_invm > 0 ? s + c[0] * drig : s;
}

/* One Gauss-Seidel update of pair i (warm: only apply lam_t itself, from
 * 0); returns the size of the tangential displacement correction it made [m]. */
static double pair_update(fem_contact *C, long i, const double *invm, double dt, double *u, double *v, double *drig,
                          int warm)
{
    const contact_pair *p = C->pair + i;
    int dof[6];
    double c[6], a = 0;
    tangential_row(C, p, dof, c);
    const int rigid = C->rigid_invm > 0;
    for (int q = 0; q < 6; q++)
        a += c[q] * c[q] * (rigid && q == 0 ? C->rigid_invm : invm[dof[q]]);
    if (!(a > 0))
        return C->lam_t[i] = 0;
    const double bound = C->friction * C->lambda[i];
    double lam, d;
    if (warm) {
        lam = fmin(fmax(C->lam_t[i], -bound), bound), d = lam;
    } else {
        const double s = row_rate(C, dof, c, v, *drig);
        lam = fmin(fmax(C->lam_t[i] - s / (dt * a), -bound), bound), d = lam - C->lam_t[i];
    }
    C->lam_t[i] = lam;
    for (int q = 0; q < 6; q++) {
        if (rigid && q == 0) {
            *drig += dt * C->rigid_invm * c[0] * d;
            continue;
        }
        const double dv = dt * invm[dof[q]] * c[q] * d;
        v[dof[q]] += dv, u[dof[q]] += dt * dv;
    }
    return fabs(d) * dt * dt * a;
}

/* The friction work of the step, lam_t c_t (v_{n+1/2} + v_{n-1/2}) dt / 2, and the stick count;
 * returns the vertical force of the tangential multipliers on the boulder (t_z lam_t per slave). */
static double friction_account(fem_contact *C, double dt, const double *v)
{
    double Fz = 0;
    for (long i = 0; i < C->npairs; i++) {
        if (!(C->lambda[i] > 0))
            continue;
        int dof[6];
        double c[6];
        tangential_row(C, C->pair + i, dof, c);
        Fz += c[0] * C->lam_t[i];
        const double s_new = row_rate(C, dof, c, v, 0), s_old = row_rate(C, dof, c, C->vt_old, 0);
        C->W_fric -= C->lam_t[i] * (s_new + s_old) * dt / 2;
        C->pair_steps++;
        if (fabs(C->lam_t[i]) < (1 - 1e-9) * C->friction * C->lambda[i]) {
            C->stick_steps++;
            C->stick_residual_max = fmax(C->stick_residual_max, fabs(s_new) * dt);
        }
    }
    return Fz;
}

double fem_contact_friction(fem_contact *C, const double *invm, double dt, double *u, double *v)
{
    double drig = 0;
    int closed = 0;
    /* warm start: each closed pair's force of the last step, within its new bound */
    for (long i = 0; i < C->npairs; i++) {
        if (!(C->lambda[i] > 0)) {
            C->lam_t[i] = 0;
            continue;
        }
        closed = 1;
        pair_update(C, i, invm, dt, u, v, &drig, 1);
    }
    if (!closed)
        return 0;
    /* until no pair's correction moves it by more than the gap tolerance (1e-9 of the element size) */
    int sweep = 0;
    for (double change = HUGE_VAL; sweep < FRICTION_SWEEPS && change > C->tol; sweep++) {
        change = 0;
        for (long i = 0; i < C->npairs; i++)
            if (C->lambda[i] > 0)
                change = fmax(change, pair_update(C, i, invm, dt, u, v, &drig, 0));
    }
    if (sweep > C->sweeps_max)
        C->sweeps_max = sweep;
    if (drig != 0) /* the whole rigid boulder */
        for (long d = 1; d < C->rigid_dofs; d += 2)
            v[d] += drig, u[d] += dt * drig;
    return friction_account(C, dt, v);
}
