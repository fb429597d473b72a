/* fem3d_solver.c - rf_fem3d_impact: the 3D impact run, as the stages of
 * the FE driver (fem_driver.h) applied to this geometry: the table of stage
 * functions over a solid_run (fem3d_run.h) and the public entries.  The
 * stages: check, automatic settings and meshing (fem3d_prepare.c,
 * fem3d_mesh.c); assembly of masses, constraints, dashpots, the material
 * kernels (fem_kernel.h), the contact and the time step
 * (fem3d_assemble.c); the time loop (fem3d_step.c: dashpots -> internal
 * force, pairing and predictor in one parallel region -> contact with
 * friction (fem3d_contact.c) -> energy account; the driver's stop test);
 * the rigid-body outputs of an oblique impact, history and report
 * (fem3d_extract.c).
 *
 * Time integration (lumped mass M, internal force f_int, forces f):
 *   v_{n+1/2} = v_{n-1/2} + dt M^-1 (f_n - f_int(u_n) + G^T lambda_n),  u_{n+1} = u_n + dt v_{n+1/2}.
 * The energy account is described in fem3d_step.c.  With a plastic body
 * (fem_kernel_points3d.c) the kernels' state is committed after each
 * internal force.  In large deformation (rf_fem_large_deformation) the
 * plastic bodies (every deformable one with `on`) take the
 * updated-Lagrangian kernel (fem_kernel_points3d_large.c), the energy is
 * always the internal work, and a run whose compressed elements outgrow the
 * step is made again with half the step (fem3d_large.c, fem_run_halving).
 * A layer (fem3d_layer.c mesh) is a second law in the slope's point kernel,
 * its elements found by their centres above the node plane at its bottom; a
 * rigid boulder (fem3d_rigid.c) has no force, no part in the time step, and
 * takes the contact's impulses on its three planar dofs.
 * Determinism: every element writes its own 24 forces; every node then sums
 * its elements in element order; sums over nodes run in fixed chunks added in
 * a fixed order (fem3d_force.c).  The result is the same bit for bit for any
 * thread count (test_fem3d_threads). */
#include "rockfuzz/fem3d.h"
#include "fem3d_prof.h"
#include "fem3d_run.h"
#include "fem_driver.h"

#include <string.h>

/* The driver's stages (fem_driver.h) over a solid_run. */
static rf_status solid_stage_prepare(void *run, const fem_attempt *a, rf_error *err)
{
    return f3_run_prepare(run, a->in, a->opt, a->o3, err);
}

static rf_status solid_stage_mesh(void *run, rf_error *err)
{
    return f3_run_mesh(run, err);
}

static rf_status solid_stage_assemble(void *run, rf_error *err)
{
    return f3_run_assemble(run, err);
}

static void solid_params(const void *run, fem_drive_params *p)
{
    const solid_run *R = run;
    *p = (fem_drive_params){R->step.dt, R->set.H.duration, R->sys.ke0, R->grav.g, 13};
}

/* A step, its stability in large deformation, and the energy account's row. */
static rf_status solid_stage_step(void *run, double t, fem_step_row *r, rf_error *err)
{
    solid_run *R = run;
    rf_status st = f3_run_step(R, &r->Fc, &r->rad, err);
    if (st != RF_OK)
        return st;
    solid_timestep *T = &R->step;
    if (R->body.large && (T->unstable = f3_step_violation(&T->check, T->dt, R->sys.u)) >= 0)
        return rf_fail(err, RF_EMODEL, "fem3d: element %ld was compressed below the stability bound of the time "
                       "step dt = %g s (dt_safety = %g) at t = %g s", T->unstable, T->dt, R->set.t.dt_safety, t);
    F3P_MARK(m);
    f3_run_energy(R, t, r->Fc, r->rad, r->row, &r->comp, &r->closure);
    r->travel = R->body.rigid ? R->B.X[0] : 0; /* the roll rule: a rigid boulder's CM along the slope */
    F3P_LAP(F3P_ENERGY, m);
    return RF_OK;
}

/* Gravity: the boulder leaves the contact (f3_run_separation). */
static void solid_accounted(void *run, int was_in_contact, int in_contact)
{
    solid_run *R = run;
    if (R->grav.g > 0 && was_in_contact && !in_contact)
        f3_run_separation(R);
}

static rf_status solid_frame(void *run, int k, double t, rf_error *err)
{
    return f3_run_vtk(run, k, t, err);
}

static void solid_stage_extract(void *run, fem_run *F, long nsteps, const fem_attempt *a)
{
    solid_run *R = run;
    F3P_REPORT(nsteps, R->grid.ne, R->grid.nn, R->grid.nbn);
    f3_run_extract(R, F, nsteps, a->out, a->hist, a->rep);
}

static long solid_stage_release(void *run)
{
    solid_run *R = run;
    f3_run_release(R);
    return R->step.unstable;
}

static const fem_geometry solid_geometry = {"fem3d", solid_stage_prepare, solid_stage_mesh, solid_stage_assemble,
                                            solid_params, solid_stage_step, solid_accounted, solid_frame,
                                            solid_stage_extract, NULL, solid_stage_release};

/* One attempt of rf_fem3d_impact_ws (fem_run_halving): a fresh run through the driver. */
static rf_status solid_attempt_fn(void *ctx, const rf_fem_options *o, long *unstable, rf_error *err)
{
    fem_attempt a = *(const fem_attempt *)ctx;
    a.opt = o;
    solid_run R;
    memset(&R, 0, sizeof R);
    R.pool = &a.ws->solid, R.step.unstable = -1;
    return fem_drive(&solid_geometry, &R, &a, unstable, err);
}

rf_status rf_fem3d_impact_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                             const rf_fem3d_options *o3, rf_impact_output *out, rf_fem_history *hist,
                             rf_fem3d_report *rep, rf_error *err)
{
    fem_attempt a = {ws, in, opt, o3, out, hist, rep};
    return fem_drive_impact(solid_attempt_fn, &a, "fem3d", err);
}

rf_status rf_fem3d_impact_ex(const rf_impact_input *in, const rf_fem_options *opt, const rf_fem3d_options *o3,
                             rf_impact_output *out, rf_fem_history *hist, rf_fem3d_report *rep, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    rf_status st = rf_fem3d_impact_ws(ws, in, opt, o3, out, hist, rep, err);
    rf_fem_workspace_free(ws);
    return st;
}

rf_status rf_fem3d_impact(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                          rf_fem_history *hist, rf_error *err)
{
    return rf_fem3d_impact_ex(in, opt, NULL, out, hist, NULL, err);
}
