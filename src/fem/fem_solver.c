/* fem_solver.c - rf_fem_impact: the axisymmetric impact run, as the stages of
 * the FE driver (fem_driver.h) over an axi_run (fem_axi_run.h, which lists
 * the files of each stage): check, sizing and meshing (fem_mesh.c), assembly
 * of masses, constraints, dashpots and the material kernels (fem_kernel.h),
 * the time step, the time loop (internal force -> dashpots -> predictor ->
 * contact (fem_contact.c) -> energy account -> stop test), and the output
 * extraction; and the slope alone under gravity (fem_axi_slope_at_rest).
 *
 * Time integration (lumped mass M, internal force f_int, external forces f):
 *   v_{n+1/2} = v_{n-1/2} + dt M^-1 (f_n - f_int(u_n) + G^T lambda_n),  u_{n+1} = u_n + dt v_{n+1/2}.
 * Energy: with K symmetric, E_n = 1/2 v_{n+1/2}' M v_{n+1/2} + 1/2 u_n' K u_{n+1}
 * changes only by the work f' (u_{n+1} - u_{n-1}) / 2 of the forces f
 * applied at step n (contact, dashpots), so the closure error measures the
 * contact scheme (its small inelastic node collisions) and round-off only.
 * With a plastic body the strain energy is replaced by the internal work
 * W_n = sum_k f_int(u_k)' (u_{k+1} - u_{k-1}) / 2, accumulated per step as
 * dt/2 f_int(u_n)' (v_{n-1/2} + v_{n+1/2}); for a linear material it equals
 * 1/2 u_n' K u_{n+1} exactly (the sum telescopes), so the closure means the
 * same; the plastic dissipation (integrated by the kernels from the return
 * maps) is the part of W that is not stored elastically.
 * Determinism: each element writes its own forces, each node sums its
 * elements in element order: the same bits for any thread count. */
#include "fem_axi_run.h"
#include "fem_driver.h"

#include <math.h>
#include <string.h>

/* The driver's stages (fem_driver.h) over an axi_run. */
static rf_status axi_stage_prepare(void *run, const fem_attempt *a, rf_error *err)
{
    return axi_prepare(run, a->in, a->opt, err);
}

static rf_status axi_stage_mesh(void *run, rf_error *err)
{
    return axi_mesh(run, err);
}

static rf_status axi_stage_assemble(void *run, rf_error *err)
{
    return axi_assemble(run, err);
}

static void axi_params(const void *run, fem_drive_params *p)
{
    const axi_run *S = run;
    *p = (fem_drive_params){S->ts.dt, S->set.H.duration, S->acc.ke0, S->grav.g, S->ale.on ? 13 : 12};
}

/* A step, its stability in large deformation, and the energy account's row. */
static rf_status axi_stage_step(void *run, double t, fem_step_row *r, rf_error *err)
{
    axi_run *S = run;
    rf_status st = axi_step(S, &r->Fc, &r->rad, err);
    if (st != RF_OK)
        return st;
    if (S->set.large && (S->ts.unstable = axi_step_violation(S)) >= 0)
        return rf_fail(err, RF_EMODEL, "fem: element %ld was compressed below the stability bound of the time "
                       "step dt = %g s (dt_safety = %g) at t = %g s: a mesh that follows the material cannot "
                       "follow this deformation (docs/validation-plastic.md section 8, JGGE24-L1)",
                       S->ts.unstable, S->ts.dt, S->set.t.dt_safety, t);
    axi_energy(S, t, r->Fc, r->rad, r->row, &r->comp, &r->closure);
    return RF_OK;
}

static rf_status axi_frame(void *run, int k, double t, rf_error *err)
{
    axi_run *S = run;
    return fem_vtk_frame(S->set.o.vtk_dir, k, t, &S->mesh, S->sys.u, S->sys.v, S->body.mat, S->body.kernel, err);
}

static void axi_stage_extract(void *run, fem_run *R, long nsteps, const fem_attempt *a)
{
    axi_extract(run, R, nsteps, a->out, a->hist);
}

/* With ALE, the history's energy column of the remaps. */
static void axi_history(void *run, fem_run *R, rf_fem_history *hist)
{
    const axi_run *S = run;
    if (S->ale.on)
        hist->remap = R->series.col[12], R->series.col[12] = NULL;
}

static long axi_release(void *run)
{
    axi_run *S = run;
    axi_free(S);
    return S->ts.unstable;
}

static const fem_geometry axi_geometry = {"fem", axi_stage_prepare, axi_stage_mesh, axi_stage_assemble, axi_params,
                                          axi_stage_step, NULL, axi_frame, axi_stage_extract, axi_history,
                                          axi_release};

/* One attempt of rf_fem_impact_ws (fem_run_halving): a fresh run through the driver. */
static rf_status axi_attempt_fn(void *ctx, const rf_fem_options *o, long *unstable, rf_error *err)
{
    fem_attempt a = *(const fem_attempt *)ctx;
    a.opt = o;
    axi_run S;
    memset(&S, 0, sizeof S);
    S.pool = &a.ws->axi, S.ts.unstable = -1;
    return fem_drive(&axi_geometry, &S, &a, unstable, err);
}

rf_status rf_fem_impact_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                           rf_impact_output *out, rf_fem_history *hist, rf_error *err)
{
    fem_attempt a = {ws, in, opt, NULL, out, hist, NULL};
    return fem_drive_impact(axi_attempt_fn, &a, "fem", err);
}

rf_status rf_fem_impact(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                        rf_fem_history *hist, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    rf_status st = rf_fem_impact_ws(ws, in, opt, out, hist, err);
    rf_fem_workspace_free(ws);
    return st;
}

/* The slope alone under gravity (fem_internal.h): the run's own assembly and
 * steps without the contact. */
rf_status fem_axi_slope_at_rest(const rf_impact_input *in, const rf_fem_options *opt, long steps,
                                fem_rest_check *chk, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem: out of memory");
    axi_run S;
    memset(&S, 0, sizeof S);
    memset(chk, 0, sizeof *chk);
    S.pool = &ws->axi, S.ts.unstable = -1, S.set.no_contact = 1;
    rf_status st = axi_prepare(&S, in, opt, err);
    if (st == RF_OK)
        st = axi_mesh(&S, err);
    if (st == RF_OK)
        st = axi_assemble(&S, err);
    for (long n = 0; st == RF_OK && n < steps; n++) {
        double Fc, rad;
        st = axi_step(&S, &Fc, &rad, err);
    }
    if (st == RF_OK) {
        const double *z = S.mesh.z;
        for (long i = S.mesh.boulder_nodes; i < S.sys.nn; i++)
            for (int c = 0; c < 2; c++) {
                chk->v_max = fmax(chk->v_max, fabs(S.sys.v[2 * i + c]));
                chk->u_max = fmax(chk->u_max, fabs(S.sys.u[2 * i + c]));
            }
        chk->elements = S.sys.ne - S.mesh.boulder_elems, chk->outside = S.grav.geo_outside;
        chk->load_ratio_min = INFINITY, chk->load_ratio_max = -INFINITY;
        for (long i = S.mesh.boulder_nodes; S.grav.fgrav && i < S.sys.nn; i++) {
            const double m = S.sys.mass[2 * i + 1] - (S.sys.mshift ? S.sys.mshift[i] : 0); /* the node's own mass */
            if (S.sys.invm[2 * i + 1] > 0)
                chk->load_sum += S.grav.fgrav[2 * i + 1], chk->weight_sum -= m * S.grav.g;
            if (S.mesh.flags[i] || m == 0)
                continue;
            const double ratio = S.grav.fgrav[2 * i + 1] / (-m * S.grav.g);
            chk->load_ratio_min = fmin(chk->load_ratio_min, ratio);
            chk->load_ratio_max = fmax(chk->load_ratio_max, ratio);
        }
        chk->dt = S.ts.dt;
        for (long e = S.mesh.boulder_elems; e < S.sys.ne; e++) {
            double sig[4], ep = 0, depth = 0;
            if (!fem_kernel_cell_state(&S.body.kernel[FEM_SLOPE], e, sig, &ep))
                break;
            for (int a = 0; a < 4; a++)
                depth -= 0.25 * z[S.mesh.conn[4 * e + a]];
            if (depth > chk->depth && (S.body.emat[e] == 2 || !S.set.layer)) {
                chk->depth = depth, memcpy(chk->sig, sig, sizeof sig), chk->layer_elem = S.body.emat[e] == 2;
                for (int a = 0; a < 4; a++)
                    chk->zn[a] = z[S.mesh.conn[4 * e + a]];
            }
            chk->plastic_strain_max = fmax(chk->plastic_strain_max, ep);
        }
    }
    axi_free(&S);
    rf_fem_workspace_free(ws);
    return st;
}
