/* fem3d_extract.c - what a 3D impact run reports (fem3d_run.h): the
 * boulder's rigid-body state (CM velocity, spin from the angular momentum
 * with the lumped inertia), its state when the contact opens under gravity,
 * the VTK frames, the outputs (coefficients of restitution, plastic
 * quantities), the diagnostics of rf_fem_history and the 3D report. */
#include "fem3d_run.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* VTK frame of the state u_n (the kernels' committed state is that of u_{n-1}). */
rf_status f3_run_vtk(solid_run *R, int frame, double t, rf_error *err)
{
    /* the boulder's co-rotated field of u_n, for its elastic stresses */
    f3_internal_force(&R->sys.S, R->sys.u, R->sys.f);
    return f3_vtk_frame(R->set.o.vtk_dir, frame, t, &R->sys.S, R->sys.u, R->sys.v, R->body.mat, err);
}

/* omega solving I omega = L (Cramer's rule). */
static void solve3(const double I[3][3], const double L[3], double omega[3])
{
    double det = I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[2][1]) - I[0][1] * (I[1][0] * I[2][2] - I[1][2] * I[2][0]) +
                 I[0][2] * (I[1][0] * I[2][1] - I[1][1] * I[2][0]);
    for (int col = 0; col < 3; col++) {
        double M3[3][3];
        memcpy(M3, I, sizeof M3);
        for (int a = 0; a < 3; a++)
            M3[a][col] = L[a];
        omega[col] = (M3[0][0] * (M3[1][1] * M3[2][2] - M3[1][2] * M3[2][1]) -
                      M3[0][1] * (M3[1][0] * M3[2][2] - M3[1][2] * M3[2][0]) +
                      M3[0][2] * (M3[1][0] * M3[2][1] - M3[1][1] * M3[2][0])) /
                     det;
    }
}

/* Rigid-body state of the boulder after the impact: CM velocity P, angular
 * velocity omega from the angular momentum about the CM with the lumped
 * inertia tensor (current positions); *Iyy about the y axis. */
static void solid_rigid_state(const solid_run *R, double P[3], double omega[3], double *Iyy)
{
    const double *u = R->sys.u, *v = R->sys.v, *m = R->sys.mass, *x = R->grid.mesh.x;
    const long nbn = R->grid.nbn;
    double X[3] = {0, 0, 0};
    P[0] = P[1] = P[2] = 0;
    for (long i = 0; i < nbn; i++)
        for (int q = 0; q < 3; q++) {
            P[q] += m[3 * i] * v[3 * i + q];
            X[q] += m[3 * i] * (x[3 * i + q] + u[3 * i + q]);
        }
    for (int q = 0; q < 3; q++)
        P[q] /= R->sys.Mb, X[q] /= R->sys.Mb;
    double Lm[3] = {0, 0, 0}, I[3][3] = {{0}};
    for (long i = 0; i < nbn; i++) {
        double mi = m[3 * i], r[3], w[3];
        for (int q = 0; q < 3; q++)
            r[q] = x[3 * i + q] + u[3 * i + q] - X[q], w[q] = v[3 * i + q];
        Lm[0] += mi * (r[1] * w[2] - r[2] * w[1]);
        Lm[1] += mi * (r[2] * w[0] - r[0] * w[2]);
        Lm[2] += mi * (r[0] * w[1] - r[1] * w[0]);
        double rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                I[a][b] += mi * ((a == b ? rr : 0) - r[a] * r[b]);
    }
    omega[0] = omega[1] = omega[2] = 0;
    if (R->grid.ms.full) /* solve I omega = L */
        solve3((const double(*)[3])I, Lm, omega);
    else { /* mirror symmetry: only the y component survives in the full body */
        omega[1] = Lm[1] / I[1][1];
        P[1] = 0;
    }
    *Iyy = I[1][1];
}

/* With gravity: the boulder's CM velocity and spin when the contact opens
 * (the rebound's R_n, R_t, R_ke, before its weight turns it). */
void f3_run_separation(solid_run *R)
{
    solid_account *A = &R->acc;
    if (R->body.rigid) { /* its own dofs */
        A->sep_v[0] = R->B.V[0], A->sep_v[1] = 0, A->sep_v[2] = R->B.V[1], A->sep_w = R->B.w;
        return;
    }
    double omega[3], Iyy;
    solid_rigid_state(R, A->sep_v, omega, &Iyy);
    A->sep_w = omega[1];
}

/* The plastic diagnostics of hist (full body): dissipation per body, the
 * elastic energy of the committed stresses against the internal work less
 * the dissipation, and where the largest plastic strain is (r: distance
 * from the impact axis). */
static void solid_history_plastic(const solid_run *R, rf_fem_history *hist)
{
    const double sf = R->grid.sym_factor;
    const fem_kernel *kernel = R->sys.S.kernel;
    fem_kernel_report rep[2];
    for (int b = 0; b < 2; b++) {
        fem_kernel_report_get(&kernel[b], &rep[b]);
        const int points = R->body.plastic[b] || (b == 1 && R->body.plastic[2]);
        const double Ee = points ? fem_kernel_points_hex_energy(&kernel[b]) : -1;
        if (Ee >= 0) {
            hist->elastic_energy_stress += Ee * sf;
            hist->elastic_energy_work += (R->acc.W_int[b] - rep[b].plastic_work) * sf;
        }
    }
    hist->plastic_work_boulder = rep[0].plastic_work * sf, hist->plastic_work_slope = rep[1].plastic_work * sf;
    const int bm = rep[1].plastic_strain_max > rep[0].plastic_strain_max ? 1 : 0;
    hist->plastic_strain_max_in = rep[bm].element_max < 0 ? 0 : 1 + bm;
    if (rep[bm].element_max < 0)
        return;
    const int *c = R->grid.mesh.conn + 8 * rep[bm].element_max;
    double xc[3] = {0, 0, 0};
    for (int a = 0; a < 8; a++)
        for (int q = 0; q < 3; q++)
            xc[q] += R->grid.mesh.x[3 * c[a] + q] / 8;
    hist->plastic_strain_max_r = hypot(xc[0], xc[1]), hist->plastic_strain_max_z = xc[2];
}

/* The warnings of the run into hist: the driver's (fem_run_warnings) with
 * the 3D model's own. */
static void solid_warnings(const solid_run *R, const fem_run *run, rf_fem_history *hist)
{
    char extra[640] = "";
    if (R->acc.outside_contact)
        snprintf(extra, sizeof extra, "The contact reached the edge of the uniform fine zone (sized from the elastic "
                 "contact radius): its outer pairs lie on graded, coarser elements than refinement says. ");
    if (!R->body.large && (R->body.plastic[1] || R->body.plastic[2]))
        snprintf(extra + strlen(extra), sizeof extra - strlen(extra), "Small strain with an elasto-plastic slope "
                 "or layer: the 3D contact follows the deformed face, the soil its reference geometry; where the "
                 "soil yields the boulder sinks too deep (docs/validation-plastic.md 9d). Large deformation (auto, "
                 "the default) is consistent. ");
    if (R->grav.outside > 0)
        snprintf(extra + strlen(extra), sizeof extra - strlen(extra), "%ld integration points of the geostatic "
                 "state lie outside the yield surface (returned to it at the first step). ", R->grav.outside);
    fem_run_warnings(run, R->set.fixed_outer, R->set.L, R->body.w[1].p, R->set.in->radius, hist->warning,
                     sizeof hist->warning, extra[0] ? extra : NULL);
}

/* FNV-1a of the final u and v. */
static uint64_t solid_state_hash(const solid_run *R)
{
    const size_t n = (size_t)R->grid.ndof * sizeof(double);
    return fem_hash(fem_hash(FEM_HASH_SEED, R->sys.u, n), R->sys.v, n);
}

/* Diagnostics of the final state into hist (energies of the full body). */
static void solid_history(solid_run *R, const fem_run *run, double K_after, rf_fem_history *hist)
{
    const double *u = R->sys.u, *v = R->sys.v, *m = R->sys.mass, sf = R->grid.sym_factor;
    const f3_mesh *mesh = &R->grid.mesh;
    const solid_account *A = &R->acc;
    double seb = 0, ses = 0, eks = 0, ekb = 0;
    for (long dd = 0; dd < 3 * R->grid.nbn; dd++)
        ekb += 0.5 * m[dd] * v[dd] * v[dd];
    seb = f3_boulder_strain(&R->sys.S, u);
    if (R->body.rigid)
        ekb = K_after;
    for (long dd = 3 * R->grid.nbn; dd < R->grid.ndof; dd++)
        ses += 0.5 * R->sys.f[dd] * u[dd], eks += 0.5 * m[dd] * v[dd] * v[dd];
    if (R->body.work_account) /* stored elastic energy: internal work less dissipation */
        seb = A->W_int[0] - f3_run_plastic_work(R, 0), ses = A->W_int[1] - f3_run_plastic_work(R, 1);
    hist->dt = R->step.dt, hist->dt_bound = R->step.dt_bound, hist->dt_edge = R->step.dt_edge;
    hist->h_contact = R->grid.h;
    hist->hertz_radius = R->set.H.contact_radius, hist->hertz_duration = R->set.H.duration;
    hist->boulder_mass = R->set.H.mass, hist->boulder_mesh_mass = R->sys.mesh_mass_b * sf;
    hist->penetration_max = A->pen_max, hist->slip_max = A->slip_max;
    hist->reflection_time = 2 * R->set.L / R->body.w[1].p;
    hist->vibration_energy = (ekb + seb - K_after) * sf;
    hist->slope_energy = (eks + ses) * sf;
    hist->ke0 = R->sys.ke0 * sf;
    hist->boulder_nodes = mesh->boulder_nodes, hist->boulder_elements = mesh->boulder_elems;
    hist->slope_nodes = R->grid.nn - mesh->boulder_nodes, hist->slope_elements = R->grid.ne - mesh->boulder_elems;
    hist->state_hash = solid_state_hash(R);
    solid_warnings(R, run, hist);
    solid_history_plastic(R, hist);
    if (R->body.plastic[1] || R->body.plastic[2]) /* less the geostatic stress's energy (0 without gravity) */
        hist->elastic_energy_stress -= R->grav.E0 * sf;
    hist->gravity = R->grav.g, hist->gravity_work = R->grav.W * sf, hist->geostatic_outside = R->grav.outside;
    hist->at_rest = run->at_rest;
}

/* The 3D report (P, w_after, Iyy: the boulder's state after the impact);
 * takes the friction work's series from run. */
static void solid_report(solid_run *R, fem_run *run, const double P[3], double w_after, double Iyy,
                         rf_fem3d_report *rep)
{
    const solid_account *A = &R->acc;
    const double sf = R->grid.sym_factor, c = R->set.H.c, d = R->set.H.d;
    rep->friction_work = A->W_fric * sf;
    rep->normal_work = A->W_n * sf;
    rep->slip_max = A->slip_max;
    rep->contact_point_velocity = P[0] - w_after * d;
    rep->inertia_lumped = Iyy * sf;
    rep->inertia_exact = R->set.H.mass * (c * c + d * d) / 5;
    rep->v_y_after = P[1];
    rep->stick_fraction = A->pair_steps ? (double)A->stick_steps / (double)A->pair_steps : 0;
    rep->pgs_sweeps_max = A->pgs_sweeps_max;
    rep->pgs_residual_max = A->pgs_res_max;
    rep->unlocated_pair_steps = A->unlocated_steps;
    rep->state_hash = solid_state_hash(R);
    rep->n = run->series.n;
    rep->friction_series = run->series.col[12];
    run->series.col[12] = NULL;
}

/* plastic_work (/ KE0), the largest equivalent plastic strain, the deepest
 * position of the boulder's lowest point and the permanent depth of the slope
 * surface at the first-contact point (both normal to the slope). */
static void solid_plastic_outputs(const solid_run *R, rf_impact_output *out)
{
    fem_kernel_report rep[2];
    for (int b = 0; b < 2; b++)
        fem_kernel_report_get(&R->sys.S.kernel[b], &rep[b]);
    out->plastic_work = (rep[0].plastic_work + rep[1].plastic_work) / R->sys.ke0;
    out->equivalent_plastic_strain_max = fmax(rep[0].plastic_strain_max, rep[1].plastic_strain_max);
    out->penetration_max = R->acc.depth_max;
    out->indentation_depth = -R->sys.u[3 * R->grid.crater_node + 2];
}

/* Outputs, diagnostics and report of the final state. */
void f3_run_extract(solid_run *R, fem_run *run, long nsteps, rf_impact_output *out, rf_fem_history *hist,
                    rf_fem3d_report *rep)
{
    double P[3], omega[3], Iyy;
    solid_rigid_state(R, P, omega, &Iyy);
    if (R->body.rigid) { /* the rigid dofs themselves */
        P[0] = R->B.V[0], P[1] = 0, P[2] = R->B.V[1];
        omega[0] = omega[2] = 0, omega[1] = R->B.w, Iyy = R->B.I;
    }
    if (R->grav.g > 0 && run->at_rest) /* settled in contact: R_n = 0 (it may still slide or roll) */
        P[2] = 0;
    else if (R->grav.g > 0 && !run->in_contact && run->episodes > 0) /* the state at the last separation */
        memcpy(P, R->acc.sep_v, sizeof R->acc.sep_v), omega[1] = R->acc.sep_w;
    const double vn_after = P[2], vt_after = P[0], w_after = omega[1];
    const double K_after =
        0.5 * R->sys.Mb * (vn_after * vn_after + vt_after * vt_after) + 0.5 * Iyy * w_after * w_after;
    fem_run_outputs(run, nsteps, R->set.t.duration_threshold, R->sys.ke0, R->grid.sym_factor, R->grid.nn, R->grid.ne,
                    out);
    solid_plastic_outputs(R, out);
    out->v_n_before = -R->set.Vn;
    out->v_t_before = R->set.Vt;
    out->v_n_after = vn_after;
    out->v_t_after = vt_after;
    out->omega_after = w_after;
    out->R_n = vn_after / R->set.Vn;
    out->R_t = R->set.Vt > 0 ? vt_after / R->set.Vt : NAN;
    out->R_ke = K_after / R->sys.ke0;
    if (hist || rep)
        f3_internal_force(&R->sys.S, R->sys.u, R->sys.f);
    if (hist)
        solid_history(R, run, K_after, hist);
    if (rep)
        solid_report(R, run, P, w_after, Iyy, rep);
}
