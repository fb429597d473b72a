/* fem3d_gravity_run.c - fem3d_gravity_free_run (fem3d_gravity.h), the test
 * hook of gravity in the 3D model: the run's own preparation, assembly and
 * steps without the contact, and the checks of the state after them (the
 * body load against the lumped weight, the boulder's free flight, the
 * slope's geostatic cells). */
#include "fem3d_run.h"

#include <math.h>
#include <string.h>

/* 1 if element e is an axis-aligned box (two values of each coordinate). */
static int element_is_box(const f3_mesh *m, long e)
{
    const int *c = m->conn + 8 * e;
    for (int q = 0; q < 3; q++) {
        const double lo = m->x[3 * (long)c[0] + q];
        double hi = lo;
        for (int a = 1; a < 8; a++) {
            const double x = m->x[3 * (long)c[a] + q];
            if (x != lo && hi != lo && x != hi)
                return 0;
            if (x != lo)
                hi = x;
        }
    }
    return 1;
}

/* The body load against the lumped weight at the nodes of the fine box's boxes. */
static void gravity_load_check(const solid_run *R, f3_gravity_check *chk)
{
    const f3_mesh *m = &R->grid.mesh;
    const f3_system *S = &R->sys.S;
    const double *fg = R->grav.fgrav;
    for (long i = R->grid.nbn; fg && i < R->grid.nn; i++) {
        int box = !(m->flags[i] & (F3_OUTER | F3_SYM));
        for (long p = S->inc_ptr[i]; box && p < S->inc_ptr[i + 1]; p++)
            box = element_is_box(m, S->inc[p] / 8);
        if (!box)
            continue;
        chk->box_nodes++;
        for (int q = 0; q < 3; q++) {
            /* its own weight */
            const double w = (R->sys.mass[3 * i] - (R->sys.mshift ? R->sys.mshift[i] : 0)) * R->grav.g;
            chk->load_err = fmax(chk->load_err, fabs(fg[3 * i + q] - w * R->grav.dir[q]) / w);
        }
    }
}

/* What fem3d_gravity_free_run reports of the state after its steps. */
static void gravity_free_report(solid_run *R, f3_gravity_check *chk, double closure)
{
    const double *u = R->sys.u, *v = R->sys.v, *m = R->sys.mass, Mb = R->sys.Mb;
    const long nbn = R->grid.nbn;
    for (long d = 3 * nbn; d < R->grid.ndof; d++)
        chk->slope_u_max = fmax(chk->slope_u_max, fabs(u[d])), chk->slope_v_max = fmax(chk->slope_v_max, fabs(v[d]));
    for (long i = 0; i < nbn; i++)
        for (int q = 0; q < 3; q++)
            chk->cm_u[q] += m[3 * i] * u[3 * i + q] / Mb, chk->cm_v[q] += m[3 * i] * v[3 * i + q] / Mb;
    for (long i = 0; i < nbn; i++)
        for (int q = 0; q < 3; q++)
            chk->spread_u = fmax(chk->spread_u, fabs(u[3 * i + q] - chk->cm_u[q]));
    chk->dt = R->step.dt, chk->closure = closure, chk->gravity_work = R->grav.W, chk->outside = R->grav.outside;
    chk->ground_angle = R->set.ground.slope_angle;
    gravity_load_check(R, chk);
    const f3_mesh *mesh = &R->grid.mesh;
    for (long e = mesh->boulder_elems; chk->cell && e < R->grid.ne; e++) {
        double sig[6], ep, zc = 0;
        if (!fem_kernel_points_hex_cell(&R->sys.S.kernel[F3_SLOPE], e, sig, &ep))
            return;
        for (int a = 0; a < 8; a++)
            zc += mesh->x[3 * (long)mesh->conn[8 * e + a] + 2] / 8;
        chk->cell(chk->ctx, -zc, R->grid.emat[e] == 2, sig);
    }
}

rf_status fem3d_gravity_free_run(const rf_impact_input *in, const rf_fem_options *opt, const rf_fem3d_options *o3,
                                 long steps, f3_gravity_check *chk, rf_error *err)
{
    rf_fem_workspace *ws = rf_fem_workspace_alloc();
    if (!ws)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    solid_run R;
    memset(&R, 0, sizeof R);
    R.pool = &ws->solid, R.set.no_contact = 1;
    rf_status st = f3_run_prepare(&R, in, opt, o3, err);
    if (st == RF_OK)
        st = f3_run_mesh(&R, err);
    if (st == RF_OK)
        st = f3_run_assemble(&R, err);
    double closure = 0;
    for (long n = 0; st == RF_OK && n < steps; n++) {
        double Fc, rad, row[13], comp;
        if ((st = f3_run_step(&R, &Fc, &rad, err)) == RF_OK)
            f3_run_energy(&R, (double)n * R.step.dt, Fc, rad, row, &comp, &closure);
    }
    if (st == RF_OK)
        gravity_free_report(&R, chk, closure);
    f3_run_release(&R);
    rf_fem_workspace_free(ws);
    return st;
}

