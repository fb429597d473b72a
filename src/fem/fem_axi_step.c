/* fem_axi_step.c - one time step of the axisymmetric run (fem_axi_run.h):
 * internal force -> ALE rezone -> dashpots -> predictor -> contact
 * (fem_contact.c), the works of that step (dashpots, gravity, internal), and
 * the stability of the step in large deformation. */
#include "fem_axi_run.h"

#include <math.h>

/* Large deformation: the central-difference step must stay below every
 * element's bound as the elements are compressed; the bound is scaled with
 * the element's current size.  Returns the first element that violates it, -1 if none. */
long axi_step_violation(const axi_run *S)
{
    for (long e = 0; e < S->sys.ne; e++)
        if (S->ts.dte[e] > 0 && S->ts.dt > S->ts.dte[e] * fem_ale_element_size(&S->mesh, e, S->sys.u))
            return e;
    return -1;
}

/* The force on dof d besides the dashpot's: gravity's body load less the internal force. */
static inline double other_force(const axi_run *S, long d)
{
    return S->grav.fgrav ? S->grav.fgrav[d] - S->sys.f[d] : -S->sys.f[d];
}

/* Dashpot forces into fext, semi-implicit: the force -C v_{n+1/2} with the
 * velocity the node reaches under it and the internal force, from the lumped
 * mass m: (m + dt C) v_{n+1/2} = m v_{n-1/2} - dt f_int, solved in the
 * normal and tangential directions (C = C_p n n' + C_s (1 - n n')).  Stable
 * for any dt C / m (the explicit form, -C v_{n-1/2}, needs dt C / m < 2,
 * which a light layer's outer nodes exceed); the predictor then gives the
 * node that velocity.  An axis node (u_r = 0) solves for v_z alone.  Returns
 * half of their work with v_{n-1/2}. */
static double axi_dashpot_forces(axi_run *S)
{
    double W = 0;
    const double dt = S->ts.dt;
    for (long k = 0; k < S->sys.nouter; k++) {
        int i = S->sys.outer[k];
        double nr = S->mesh.r[i] / S->set.L, nz = S->mesh.z[i] / S->set.L, len = hypot(nr, nz);
        nr /= len, nz /= len;
        const double m = S->sys.mass[2 * i + 1], Cp = S->sys.dash[2 * i], Cs = S->sys.dash[2 * i + 1];
        const double vr = S->sys.v[2 * i], vz = S->sys.v[2 * i + 1];
        double fr, fz;
        if (S->sys.invm[2 * i] == 0) { /* on the axis: v_r = 0 */
            const double Czz = Cp * nz * nz + Cs * nr * nr;
            const double wz = fem_dashpot_velocity(m, Czz, vz, other_force(S, 2 * i + 1), dt);
            fr = -(Cp - Cs) * nr * nz * wz, fz = -Czz * wz;
        } else {
            const double gr = other_force(S, 2 * i), gz = other_force(S, 2 * i + 1);
            const double vn = vr * nr + vz * nz, vt = -vr * nz + vz * nr;
            const double gn = gr * nr + gz * nz, gt = -gr * nz + gz * nr;
            const double wn = fem_dashpot_velocity(m, Cp, vn, gn, dt), wt = fem_dashpot_velocity(m, Cs, vt, gt, dt);
            fr = -(Cp * wn * nr - Cs * wt * nz), fz = -(Cp * wn * nz + Cs * wt * nr);
        }
        S->sys.fext[2 * i] = fr, S->sys.fext[2 * i + 1] = fz;
    }
    for (long k = 0; k < S->sys.nouter; k++) {
        int i = S->sys.outer[k];
        W -= 0.5 * S->ts.dt * (S->sys.fext[2 * i] * S->sys.v[2 * i] + S->sys.fext[2 * i + 1] * S->sys.v[2 * i + 1]);
    }
    return W;
}

/* f_int' v of each body (boulder dofs first). */
static void axi_power(const axi_run *S, double fv[2])
{
    for (long d = 0; d < S->sys.nbd; d++)
        fv[0] += S->sys.f[d] * S->sys.v[d];
    for (long d = S->sys.nbd; d < S->sys.ndof; d++)
        fv[1] += S->sys.f[d] * S->sys.v[d];
}

/* fgrav' v: the power of gravity. */
static double axi_gravity_power(const axi_run *S)
{
    double p = 0;
    for (long d = 0; d < S->sys.ndof; d++)
        p += S->grav.fgrav[d] * S->sys.v[d];
    return p;
}

/* ALE (fem_ale.h), between the Lagrangian steps where the committed state
 * and the nodes are both at u_n: a rezone of the slope if an element has
 * become too small, then the internal force again on the new mesh (a zero
 * increment: the remapped stresses, returned to the yield surface where the
 * mix of two admissible states is not).  The elastic energy the remap
 * changes enters the internal work, so that the stored energy stays the
 * committed stresses'; the remap's energy is its own term of the closure. */
static rf_status axi_rezone(axi_run *S, rf_error *err)
{
    const double el0 = S->ale.acc.elastic;
    const long moved = fem_ale_rezone(&S->ale.state, &S->mesh, S->sys.u, S->sys.v, S->sys.mass, S->sys.invm,
                                      S->grav.fgrav, &S->body.kernel[FEM_SLOPE], S->ale.delta, &S->ale.acc, err);
    if (moved < 0)
        return rf_error_prefix(err, "fem");
    if (moved == 0)
        return RF_OK;
    S->acc.W_int[FEM_SLOPE] += S->ale.acc.elastic - el0;
    axi_internal_force(S, S->sys.u, S->sys.f);
    axi_commit(S);
    return RF_OK;
}

/* One step: internal force -> dashpots -> predictor -> contact.  Returns the
 * total contact force in *Fc and the contact radius in *rad. */
rf_status axi_step(axi_run *S, double *Fc, double *rad, rf_error *err)
{
    const double dt = S->ts.dt;
    double *u = S->sys.u, *v = S->sys.v;
    axi_internal_force(S, u, S->sys.f);
    axi_commit(S); /* the state at u_n is accepted */
    rf_status st = S->ale.on ? axi_rezone(S, err) : RF_OK;
    if (st != RF_OK)
        return st;
    double W_abs_inc = axi_dashpot_forces(S);
    double fv[2] = {0, 0};
    if (S->set.work_account)
        axi_power(S, fv);
    const double gv0 = S->grav.fgrav ? axi_gravity_power(S) : 0;
    fem_contact_begin(&S->C, v);
    if (S->grav.fgrav)
        for (long d = 0; d < S->sys.ndof; d++) {
            v[d] += dt * S->sys.invm[d] * (S->sys.fext[d] + S->grav.fgrav[d] - S->sys.f[d]);
            u[d] += dt * v[d];
        }
    else
        for (long d = 0; d < S->sys.ndof; d++) {
            v[d] += dt * S->sys.invm[d] * (S->sys.fext[d] - S->sys.f[d]);
            u[d] += dt * v[d];
        }
    for (long k = 0; k < S->sys.nouter; k++) { /* the other half of the dashpot work, with v_{n+1/2} */
        int i = S->sys.outer[k];
        W_abs_inc -= 0.5 * dt * (S->sys.fext[2 * i] * v[2 * i] + S->sys.fext[2 * i + 1] * v[2 * i + 1]);
    }
    if (S->set.large) /* the pairs on the predicted surfaces */
        fem_contact_update(&S->C, u);
    st = S->set.no_contact ? (*Fc = 0, RF_OK) : fem_contact_step(&S->C, S->sys.invm, dt, u, v, Fc, err);
    if (st != RF_OK)
        return st;
    S->acc.W_abs += W_abs_inc;
    if (S->grav.fgrav) /* fgrav' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        S->grav.W_grav += 0.5 * dt * (gv0 + axi_gravity_power(S));
    if (S->set.work_account) { /* f_int(u_n)' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        double fv1[2] = {0, 0};
        axi_power(S, fv1);
        S->acc.W_int[0] += 0.5 * dt * (fv[0] + fv1[0]), S->acc.W_int[1] += 0.5 * dt * (fv[1] + fv1[1]);
    }
    const long nb = S->mesh.bsurf[0]; /* the boulder's lowest point (on the axis) */
    const double pen = -(S->mesh.z[nb] + u[2 * nb + 1]);
    if (pen > S->acc.pen_max)
        S->acc.pen_max = pen;
    *rad = fem_contact_measure(&S->C, u);
    return RF_OK;
}
