/* fem3d_step.c - one step of a 3D impact run (fem3d_run.h) and its energy
 * account: dashpot forces from v_{n-1/2}; the internal force at u_n with the
 * contact's pairing and the contact-free predictor in one parallel region;
 * the rigid boulder's predictor; the contact with friction
 * (fem3d_contact.c) and its correction; the account of the contact's work,
 * radius and statistics, of the dashpots', gravity's and the internal work.
 *
 * Energy: with K symmetric, E_n = 1/2 v_{n+1/2}' M v_{n+1/2} + 1/2 u_n' K u_{n+1}
 * changes only by the work f_n' (u_{n+1} - u_{n-1}) / 2 of the forces applied at
 * step n.  The tangential contact work is the frictional dissipation and
 * enters the closure; the normal contact work (ideally 0) and round-off are
 * the closure error.  With a plastic body, large deformation or gravity the
 * strain energy is replaced by the internal work
 * dt/2 f_int(u_n)' (v_{n-1/2} + v_{n+1/2}) summed over the steps, and the
 * kernels book the plastic dissipation. */
#include "fem3d_prof.h"
#include "fem3d_run.h"

#include <math.h>
#include <string.h>

/* Dashpot forces from v_{n-1/2}: normal rho c_p v_n, shear rho c_s v_s,
 * radial normal; returns half of their work with v_{n-1/2}. */
static double solid_dashpot_forces(solid_run *R)
{
    double W = 0;
    if (R->set.fixed_outer)
        return 0;
    const solid_boundary *D = &R->bound;
    const f3_mesh *mesh = &R->grid.mesh;
    const double rho = R->body.mat[1].rho, cp = R->body.w[1].p, cs = R->body.w[1].s;
    const double rl = R->body.mat[2].rho, cpl = R->body.w[2].p, csl = R->body.w[2].s;
    for (long k = 0; k < D->nouter; k++) {
        int i = D->outer[k];
        const double *x = mesh->extruded ? D->dnrm + 3 * i : mesh->x + 3 * i, *v = R->sys.v + 3 * i;
        double *fx = R->sys.fext + 3 * i;
        double rr = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        double nv[3] = {x[0] / rr, x[1] / rr, x[2] / rr};
        double vn = v[0] * nv[0] + v[1] * nv[1] + v[2] * nv[2];
        for (int q = 0; q < 3; q++)
            fx[q] = -D->dash[i] * rho * (cp * vn * nv[q] + cs * (v[q] - vn * nv[q]));
        if (R->body.layer)
            for (int q = 0; q < 3; q++)
                fx[q] -= D->dashl[i] * rl * (cpl * vn * nv[q] + csl * (v[q] - vn * nv[q]));
        for (int q = 0; q < 3; q++)
            if (R->sys.fixed[3 * i + q])
                fx[q] = 0;
        for (int q = 0; q < 3; q++)
            W -= 0.5 * R->step.dt * fx[q] * v[q];
    }
    return W;
}

/* 1 if slave k (top_b order) is on the edge of the boulder's fine box: soil
 * beyond it would meet no slave (the contact has outgrown the fine zone). */
static int slave_on_edge(const f3_mesh *mesh, int full, int sphere, long k)
{
    const long nx = sphere ? mesh->nxt_s : mesh->nxt_b, ny = sphere ? mesh->nyt_s : mesh->nyt_b;
    const long i = k / ny, j = k % ny;
    return i == 0 || i == nx - 1 || j == ny - 1 || (full && j == 0);
}

/* Contact force, work, radius (force-weighted second moment: <rho^2> = 0.4 a^2
 * for Hertz) and the statistics of the step's closed pairs. */
static double solid_contact_account(solid_run *R, double *rad)
{
    const f3_contact *C = &R->C;
    const f3_mesh *mesh = &R->grid.mesh;
    solid_account *A = &R->acc;
    const double dt = R->step.dt, *u = R->sys.u;
    double Fc = 0, sx = 0, sy = 0, sxx = 0;
    for (long q = 0; q < C->ncand; q++) {
        long k = C->cand[q];
        const double *lam = C->lam + 3 * k;
        if (lam[0] <= 0)
            continue;
        int s = C->slave[k];
        double gvn[3];
        double gvo[3];
        f3_contact_gv(C, k, R->sys.v, gvn);
        f3_contact_gvo(C, k, gvo);
        A->W_n += lam[0] * dt * (gvn[0] + gvo[0]) / 2;
        A->W_fric -= (lam[1] * (gvn[1] + gvo[1]) + lam[2] * (gvn[2] + gvo[2])) * dt / 2;
        double slip = hypot(gvn[1], gvn[2]) * dt;
        if (slip > A->slip_max)
            A->slip_max = slip;
        A->pair_steps++;
        double Fn, Ft;
        f3_contact_forces(C, k, &Fn, &Ft);
        if (Ft < (1 - 1e-9) * C->solve.friction * Fn)
            A->stick_steps++;
        if (C->outside[k] == 1 || slave_on_edge(mesh, R->grid.ms.full, C->sphere, k))
            A->outside_contact = 1;
        if (C->outside[k] == 2)
            A->unlocated_steps++;
        double X = mesh->x[3 * s] + u[3 * s], Y = mesh->x[3 * s + 1] + u[3 * s + 1];
        Fc += lam[0];
        sx += lam[0] * X;
        sy += lam[0] * Y;
        sxx += lam[0] * (X * X + Y * Y);
    }
    *rad = 0;
    if (Fc > 0) {
        double mx = sx / Fc, my = R->grid.ms.full ? sy / Fc : 0;
        double var = sxx / Fc - mx * mx - my * my;
        *rad = sqrt(fmax(0, 2.5 * var));
    }
    for (long q = 0; q < C->ncand; q++) { /* penetration after the correction */
        const double g = f3_contact_gap_now(C, mesh, C->cand[q], u);
        if (-g > A->pen_max)
            A->pen_max = -g;
    }
    return Fc;
}

/* f_int' v of each body (boulder dofs first). */
static void solid_power(const solid_run *R, double fv[2])
{
    const long nb3 = 3 * R->grid.nbn;
    for (long dd = 0; dd < nb3; dd++)
        fv[0] += R->sys.f[dd] * R->sys.v[dd];
    for (long dd = nb3; dd < R->grid.ndof; dd++)
        fv[1] += R->sys.f[dd] * R->sys.v[dd];
}

/* The boulder's lowest point (its contact-face nodes) below the undeformed slope surface z = 0. */
static void solid_depth(solid_run *R)
{
    if (R->C.sphere) { /* the exact sphere's */
        const double d = R->C.radius - R->C.rigid_c[1];
        if (d > R->acc.depth_max)
            R->acc.depth_max = d;
        return;
    }
    for (long k = 0; k < R->C.nslave; k++) {
        const long s = R->C.slave[k];
        const double d = -(R->grid.mesh.x[3 * s + 2] + R->sys.u[3 * s + 2]);
        if (d > R->acc.depth_max)
            R->acc.depth_max = d;
    }
}

/* Plastic dissipation of body b so far [J] (model). */
double f3_run_plastic_work(const solid_run *R, int b)
{
    fem_kernel_report r;
    fem_kernel_report_get(&R->sys.S.kernel[b], &r);
    return r.plastic_work;
}

/* Pairing at step n (u_n, G v_{n-1/2}): the slaves shared among the force's threads. */
static void pairing_share(void *ctx)
{
    solid_run *R = ctx;
    F3P_MARK(m);
    f3_contact_locate(&R->C, &R->grid.mesh, R->sys.u, R->sys.v, R->set.threads, 1);
    F3P_LAP(F3P_LOCATE, m);
}

/* The contact-free predictor v += dt M^-1 (f_ext - f_int), u += dt v of dofs [d0, d1). */
static inline void predict_dofs(solid_run *R, long d0, long d1)
{
    const double dt = R->step.dt, *invm = R->sys.invm, *fext = R->sys.fext, *f = R->sys.f, *fg = R->grav.fgrav;
    double *u = R->sys.u, *v = R->sys.v;
    if (fg) /* gravity's body load */
        for (long dd = d0; dd < d1; dd++) {
            v[dd] += dt * invm[dd] * (fext[dd] + fg[dd] - f[dd]);
            u[dd] += dt * v[dd];
        }
    else
        for (long dd = d0; dd < d1; dd++) {
            v[dd] += dt * invm[dd] * (fext[dd] - f[dd]);
            u[dd] += dt * v[dd];
        }
}

/* The predictor shared among the threads: the boulder's node chunks in the loop form that
   f3_force_hooks asks for (no barrier after the force), then the slope's. */
static void predictor_share(void *ctx)
{
    solid_run *R = ctx;
    const long nbn = R->grid.nbn, nd = R->grid.ndof;
    F3P_MARK(m);
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < F3_CHUNKS; k++)
        predict_dofs(R, 3 * f3_chunk_begin(nbn, k), 3 * f3_chunk_begin(nbn, k + 1));
    const long ns = nd / 3 - nbn;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
    for (int k = 0; k < F3_CHUNKS; k++)
        predict_dofs(R, 3 * (nbn + f3_chunk_begin(ns, k)), 3 * (nbn + f3_chunk_begin(ns, k + 1)));
    F3P_LAP(F3P_UPDATE, m);
}

/* Internal force at u_n, pairing and predictor in the force's parallel region; with a plastic
   body the power f_int(u_n)' v_{n-1/2} is summed (serially) before the predictor. */
static void solid_force_predict(solid_run *R, double fv[2])
{
    const f3_force_hooks hooks = {pairing_share, R->body.work_account ? NULL : predictor_share, R};
    f3_internal_force_hooked(&R->sys.S, R->sys.u, R->sys.f, &hooks);
    if (!R->body.work_account)
        return;
    solid_power(R, fv);
#ifdef _OPENMP
#pragma omp parallel num_threads(R->set.threads) if (R->set.threads > 1)
#endif
    predictor_share(R);
}

/* The rigid boulder's centre (x, z) for the contact: its CM, or in sphere mode the exact sphere's
   centre (the first-contact point + r0 along z at rest; the same point as the CM to round-off). */
static void solid_rigid_centre(solid_run *R)
{
    const double *c = R->C.sphere ? (const double[3]){0, 0, R->C.radius} : R->B.c0;
    R->C.rigid_c[0] = c[0] + R->B.X[0], R->C.rigid_c[1] = c[2] + R->B.X[1];
}

/* The dashpots' work with v_{n+1/2} added to w, the half with v_{n-1/2}
 * (solid_dashpot_forces), term by term. */
static double solid_dashpot_work(const solid_run *R, double w)
{
    if (R->set.fixed_outer)
        return w;
    const double dt = R->step.dt, *fext = R->sys.fext, *v = R->sys.v;
    for (long k = 0; k < R->bound.nouter; k++) {
        int i = R->bound.outer[k];
        for (int q = 0; q < 3; q++)
            w -= 0.5 * dt * fext[3 * i + q] * v[3 * i + q];
    }
    return w;
}

/* The rigid boulder's predicted state (its nodes moved along straight lines by the predictor). */
static void solid_rigid_predict(solid_run *R)
{
    f3_rigid *B = &R->B;
    f3_contact *C = &R->C;
    const double dt = R->step.dt;
    const double Xn[3] = {B->X[0], B->X[1], B->th};
    C->body_vo[0] = B->V[0], C->body_vo[1] = B->V[1], C->body_vo[2] = B->w;
    if (R->grav.fgrav) /* its weight M g at the centre of mass */
        B->V[0] += dt * R->grav.g * R->grav.dir[0], B->V[1] += dt * R->grav.g * R->grav.dir[2];
    f3_rigid_predict(B, dt);
    f3_rigid_place(B, &R->grid.mesh, R->grid.nbn, R->sys.u, R->sys.v);
    C->body_d[0] = B->X[0] - Xn[0], C->body_d[1] = B->X[1] - Xn[1], C->body_d[2] = B->th - Xn[2];
    solid_rigid_centre(R);
}

/* The contact's impulse on the rigid boulder's dofs. */
static void solid_rigid_correct(solid_run *R)
{
    f3_rigid *B = &R->B;
    f3_contact *C = &R->C;
    f3_rigid_correct(B, C->rigid_du, R->step.dt);
    f3_rigid_place(B, &R->grid.mesh, R->grid.nbn, R->sys.u, R->sys.v);
    if (C->sphere) { /* the account's and the depth's body */
        solid_rigid_centre(R);
        C->body_v[0] = B->V[0], C->body_v[1] = B->V[1], C->body_v[2] = B->w;
    }
}

/* The account of a step after the contact: the solver's statistics, the
 * contact's force and radius, the dashpots' (W_abs_inc), gravity's (from
 * its power gv0 at v_{n-1/2}) and the internal work (from the power fv). */
static void solid_step_account(solid_run *R, double W_abs_inc, double gv0, const double fv[2], double *Fc,
                               double *rad)
{
    solid_account *A = &R->acc;
    const double dt = R->step.dt;
    if (R->C.solve.sweeps > A->pgs_sweeps_max)
        A->pgs_sweeps_max = R->C.solve.sweeps;
    if (R->C.solve.residual > A->pgs_res_max)
        A->pgs_res_max = R->C.solve.residual;
    *Fc = solid_contact_account(R, rad);
    A->W_abs += W_abs_inc;
    if (R->grav.fgrav) /* fgrav' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        R->grav.W += 0.5 * dt * (gv0 + f3_gravity_power(&R->grav, &R->B, R->sys.v, R->grid.nbn, R->grid.ndof));
    if (R->body.work_account) { /* f_int(u_n)' (v_{n-1/2} + v_{n+1/2}) dt / 2 */
        double fv1[2] = {0, 0};
        solid_power(R, fv1);
        A->W_int[0] += 0.5 * dt * (fv[0] + fv1[0]), A->W_int[1] += 0.5 * dt * (fv[1] + fv1[1]);
    }
    solid_depth(R);
}

/* One step: dashpots (v_{n-1/2}) -> internal force, pairing, predictor -> contact -> account. */
rf_status f3_run_step(solid_run *R, double *Fc, double *rad, rf_error *err)
{
    const double dt = R->step.dt;
    double *u = R->sys.u, *v = R->sys.v;
    F3P_MARK(m);
    double W_abs_inc = solid_dashpot_forces(R);
    F3P_LAP(F3P_DASH, m);
    double fv[2] = {0, 0};
    const double gv0 = R->grav.fgrav ? f3_gravity_power(&R->grav, &R->B, v, R->grid.nbn, R->grid.ndof) : 0;
    solid_force_predict(R, fv);
    F3P_SET(m, f3p_now()); /* (its phases are timed inside) */
    for (int b = 0; b < 2; b++) /* the state at u_n is accepted */
        if (R->sys.S.kernel[b].ops->commit)
            R->sys.S.kernel[b].ops->commit(&R->sys.S.kernel[b]);
    F3P_LAP(F3P_COMMIT, m);
    W_abs_inc = solid_dashpot_work(R, W_abs_inc);
    if (R->body.rigid)
        solid_rigid_predict(R);
    if (R->set.no_contact)
        R->C.ncand = 0;
    else
        f3_contact_predict(&R->C, &R->grid.mesh, u, R->sys.invm, dt, R->set.threads);
    F3P_LAP(F3P_PREDICT, m);
    rf_status st = R->set.no_contact ? RF_OK : f3_contact_solve(&R->C, R->sys.invm, dt, u, v, err);
    F3P_LAP(F3P_SOLVE, m);
    if (st != RF_OK)
        return st;
    if (R->body.rigid)
        solid_rigid_correct(R);
    solid_step_account(R, W_abs_inc, gv0, fv, Fc, rad);
    F3P_LAP(F3P_ACCOUNT, m);
    return RF_OK;
}

/* Energies at t_{n+1/2} (KE with v_{n+1/2}, strain 1/2 u_n' K u_{n+1}), the
 * history row (full-body energies), compression and closure error. */
void f3_run_energy(solid_run *R, double t, double Fc, double rad, double row[13], double *comp, double *closure)
{
    const solid_account *A = &R->acc;
    const double *u = R->sys.u, *v = R->sys.v, *f = R->sys.f;
    f3_state_sums sum; /* in parallel, fixed order */
    f3_state_sums_compute(&R->sys.S, u, v, f, &sum);
    double ke[2] = {sum.mv2[0], sum.mv2[1]}, se[2] = {2 * sum.boulder_strain, sum.slope_fu};
    const double pz = sum.boulder_pz, uz = sum.boulder_uz;
    ke[0] *= 0.5, ke[1] *= 0.5, se[0] *= 0.5, se[1] *= 0.5;
    if (R->body.rigid)
        ke[0] = f3_rigid_energy(&R->B);
    if (R->body.work_account) /* stored elastically: the internal work less the dissipation */
        for (int b = 0; b < 2; b++)
            se[b] = A->W_int[b] - f3_run_plastic_work(R, b);
    const double ke0 = R->sys.ke0, Mb = R->sys.Mb;
    *comp = -uz / Mb;
    *closure = ke[0] + ke[1] + se[0] + se[1] + A->W_abs + A->W_fric - ke0;
    if (R->body.work_account)
        *closure = ke[0] + ke[1] + A->W_int[0] + A->W_int[1] + A->W_abs + A->W_fric - ke0 - R->grav.W;
    const double sf = R->grid.sym_factor;
    const double r[13] = {t,          Fc * sf,         *comp,           rad,           ke[0] * sf,
                          se[0] * sf, ke[1] * sf,      se[1] * sf,      A->W_n * sf,   A->W_abs * sf,
                          *closure * sf, pz / Mb,      A->W_fric * sf};
    memcpy(row, r, sizeof r);
}
