/* fem_axi_account.c - the axisymmetric run's energy account (fem_axi_run.h):
 * a step's kinetic and stored energies, the history row, the compression and
 * the closure error; and the outputs and diagnostics of the final state. */
#include "fem_axi_run.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Plastic dissipation of body b so far [J]. */
static double axi_plastic_work(const axi_run *S, int b)
{
    fem_kernel_report r;
    fem_kernel_report_get(&S->body.kernel[b], &r);
    return r.plastic_work;
}

/* A body's running sums: kinetic (m v v), strain (f u), and for the boulder the z momentum and the
 * mass-weighted z displacement; each accumulates its dofs in dof order. */
typedef struct {
    double ke, se, pz, uz;
} axi_sums;

static inline void axi_sums_node(const axi_run *S, long i, int boulder, axi_sums *s)
{
    const double *u = S->sys.u, *v = S->sys.v, *f = S->sys.f, *m = S->sys.mass;
    for (long d = 2 * i; d < 2 * i + 2; d++) {
        s->ke += m[d] * v[d] * v[d];
        s->se += f[d] * u[d];
    }
    if (boulder) {
        s->pz += m[2 * i + 1] * v[2 * i + 1];
        s->uz += m[2 * i + 1] * u[2 * i + 1];
    }
}

/* The sums of both bodies, their nodes interleaved: six independent dependency chains instead of
 * two after two (the time was the latency of the additions), each in the same order as before, so
 * the same bits. */
static void axi_body_sums(const axi_run *S, axi_sums *b, axi_sums *sl)
{
    const long nb = S->sys.nbd / 2, ns = S->sys.nn - nb, common = nb < ns ? nb : ns;
    *b = *sl = (axi_sums){0, 0, 0, 0};
    for (long k = 0; k < common; k++) {
        axi_sums_node(S, k, 1, b);
        axi_sums_node(S, nb + k, 0, sl);
    }
    for (long k = common; k < nb; k++)
        axi_sums_node(S, k, 1, b);
    for (long k = common; k < ns; k++)
        axi_sums_node(S, nb + k, 0, sl);
}

/* Energies at t_{n+1/2} (KE with v_{n+1/2}, strain 1/2 u_n' f_int(u_n) ...
 * with u_{n+1}), the history row, the compression and the closure error. */
void axi_energy(const axi_run *S, double t, double Fc, double rad, double row[13], double *comp,
                       double *closure)
{
    axi_sums sb, ss;
    axi_body_sums(S, &sb, &ss);
    double ke[2] = {sb.ke, ss.ke}, se[2] = {sb.se, ss.se}, pz = sb.pz, uz = sb.uz;
    ke[0] *= 0.5, ke[1] *= 0.5, se[0] *= 0.5, se[1] *= 0.5;
    if (S->set.work_account) /* stored elastically: the internal work less the dissipation */
        for (int b = 0; b < 2; b++)
            se[b] = S->acc.W_int[b] - axi_plastic_work(S, b);
    *comp = -uz / S->sys.Mb;
    *closure = ke[0] + ke[1] + se[0] + se[1] + S->acc.W_abs - S->acc.ke0;
    if (S->set.work_account)
        *closure = ke[0] + ke[1] + S->acc.W_int[0] + S->acc.W_int[1] + S->acc.W_abs - S->acc.ke0;
    if (S->grav.fgrav) /* gravity's work: the potential energy released */
        *closure -= S->grav.W_grav;
    *closure += S->C.W_fric; /* dissipated by friction (0 without) */
    /* ALE: the energy the remaps added (kinetic, elastic, the potential of
       the moved masses, which W_grav does not see) is its own term */
    const fem_ale_account *a = &S->ale.acc;
    *closure -= a->kinetic + a->elastic;
    const double remap = a->kinetic + a->elastic + a->potential;
    const double r[13] = {t, Fc, *comp, rad, ke[0], se[0], ke[1], se[1],
                          S->C.work, S->acc.W_abs, *closure, pz / S->sys.Mb, remap};
    memcpy(row, r, sizeof r);
}

/* The final state's boulder z momentum, and each body's kinetic and stored elastic energies [J]. */
typedef struct {
    double pz, ekb, seb, eks, ses;
} axi_final;

static void axi_final_energies(axi_run *S, axi_final *e)
{
    const double *u = S->sys.u, *v = S->sys.v, *m = S->sys.mass;
    double pz = 0, ekb = 0, seb = 0, eks = 0, ses = 0;
    for (long d = 1; d < S->sys.nbd; d += 2)
        pz += m[d] * v[d];
    for (long d = 0; d < S->sys.nbd; d++)
        ekb += 0.5 * m[d] * v[d] * v[d];
    for (long d = S->sys.nbd; d < S->sys.ndof; d++)
        eks += 0.5 * m[d] * v[d] * v[d];
    if (S->set.work_account) { /* stored elastic energy: internal work less dissipation */
        seb = S->acc.W_int[0] - axi_plastic_work(S, 0), ses = S->acc.W_int[1] - axi_plastic_work(S, 1);
    } else {
        axi_internal_force(S, u, S->sys.f); /* strain energy of the final state, 1/2 u' K u */
        for (long d = 0; d < S->sys.nbd; d++)
            seb += 0.5 * S->sys.f[d] * u[d];
        for (long d = S->sys.nbd; d < S->sys.ndof; d++)
            ses += 0.5 * S->sys.f[d] * u[d];
    }
    *e = (axi_final){pz, ekb, seb, eks, ses};
}

/* The plastic bodies' elastic energies, from the stresses and from the work, and where the
 * largest plastic strain is. */
static void axi_plastic_diagnostics(const axi_run *S, const fem_kernel_report rep[2], rf_fem_history *hist)
{
    hist->plastic_work_boulder = rep[0].plastic_work, hist->plastic_work_slope = rep[1].plastic_work;
    for (int b = 0; b < 2; b++) {
        const int pl = S->body.plastic[b] || (b == FEM_SLOPE && S->body.plastic[2]);
        const double Ee = pl ? fem_kernel_elastic_energy(&S->body.kernel[b]) : -1;
        if (Ee >= 0) { /* less the geostatic stress's energy (0 without gravity) */
            hist->elastic_energy_stress += b == FEM_SLOPE ? Ee - S->grav.E0 : Ee;
            hist->elastic_energy_work += S->acc.W_int[b] - rep[b].plastic_work;
        }
    }
    const int bm = rep[1].plastic_strain_max > rep[0].plastic_strain_max ? 1 : 0;
    hist->plastic_strain_max_in = rep[bm].element_max < 0 ? 0 : 1 + bm;
    if (rep[bm].element_max >= 0) {
        const int *c = S->mesh.conn + 4 * rep[bm].element_max;
        for (int a = 0; a < 4; a++) {
            hist->plastic_strain_max_r += 0.25 * S->mesh.r[c[a]];
            hist->plastic_strain_max_z += 0.25 * S->mesh.z[c[a]];
        }
    }
}

/* The history's diagnostics of the final state (hist's series are the driver's). */
static void axi_diagnostics(const axi_run *S, const fem_run *R, const fem_kernel_report rep[2], const axi_final *e,
                            rf_fem_history *hist)
{
    hist->dt = S->ts.dt, hist->dt_bound = S->ts.dt_bound, hist->dt_edge = S->ts.dt_edge;
    hist->h_contact = S->sys.h;
    hist->hertz_radius = S->set.H.contact_radius, hist->hertz_duration = S->set.H.duration;
    hist->boulder_mass = S->set.H.mass, hist->boulder_mesh_mass = S->sys.mesh_mass_b;
    hist->penetration_max = S->C.pen_max, hist->slip_max = S->C.slip_max;
    hist->reflection_time = 2 * S->set.L / S->body.w[1].p;
    hist->vibration_energy = e->ekb + e->seb - 0.5 * e->pz * e->pz / S->sys.Mb; /* about the final rigid motion */
    hist->slope_energy = e->eks + e->ses;
    hist->ke0 = S->acc.ke0;
    axi_plastic_diagnostics(S, rep, hist);
    hist->gravity = S->grav.g, hist->gravity_work = S->grav.W_grav, hist->geostatic_outside = S->grav.geo_outside;
    hist->at_rest = R->at_rest;
    const fem_ale_account *a = &S->ale.acc;
    hist->ale_rezones = a->rezones, hist->ale_nodes_moved = a->nodes_moved;
    hist->ale_kinetic = a->kinetic, hist->ale_elastic = a->elastic, hist->ale_potential = a->potential;
    hist->ale_move_max = a->move_max, hist->ale_ratio_min = a->ratio_min;
    hist->friction_work = S->C.W_fric, hist->friction_sweeps_max = S->C.sweeps_max;
    hist->stick_residual_max = S->C.stick_residual_max;
    hist->stick_fraction = S->C.pair_steps > 0 ? (double)S->C.stick_steps / (double)S->C.pair_steps : 0;
    hist->boulder_nodes = S->mesh.boulder_nodes, hist->boulder_elements = S->mesh.boulder_elems;
    hist->slope_nodes = S->sys.nn - S->mesh.boulder_nodes, hist->slope_elements = S->sys.ne - S->mesh.boulder_elems;
    const double *u = S->sys.u, *v = S->sys.v;
    hist->state_hash = fem_hash(fem_hash(FEM_HASH_SEED, u, (size_t)S->sys.ndof * sizeof *u), v,
                                (size_t)S->sys.ndof * sizeof *v);
    char extra[160] = "";
    if (S->grav.geo_outside > 0)
        snprintf(extra, sizeof extra, "%ld integration points of the geostatic state lie outside the yield surface "
                 "(returned to it at the first step). ", S->grav.geo_outside);
    fem_run_warnings(R, S->set.fixed_outer, S->set.L, S->body.w[1].p, S->set.in->radius, hist->warning,
                     sizeof hist->warning, extra);
}

/* Outputs and diagnostics of the final state. */
void axi_extract(axi_run *S, const fem_run *R, long nsteps, rf_impact_output *out, rf_fem_history *hist)
{
    axi_final e;
    axi_final_energies(S, &e);
    const double V = S->set.V;
    double v_after = e.pz / S->sys.Mb;
    if (S->grav.g > 0) /* with gravity: the velocity at separation (0 at rest) */
        v_after = R->at_rest ? 0 : !R->in_contact && R->episodes > 0 ? R->v_sep : v_after;
    fem_run_outputs(R, nsteps, S->set.t.duration_threshold, S->acc.ke0, 1.0, S->sys.nn, S->sys.ne, out);
    out->v_n_before = -V;
    out->v_n_after = v_after;
    out->R_n = -v_after / -V;
    out->R_t = NAN;
    out->R_ke = (v_after * v_after) / (V * V);
    fem_kernel_report rep[2];
    for (int b = 0; b < 2; b++)
        fem_kernel_report_get(&S->body.kernel[b], &rep[b]);
    out->plastic_work = (rep[0].plastic_work + rep[1].plastic_work) / S->acc.ke0;
    out->equivalent_plastic_strain_max = fmax(rep[0].plastic_strain_max, rep[1].plastic_strain_max);
    out->penetration_max = S->acc.pen_max;
    const long ns0 = S->mesh.ssurf[0]; /* the slope's first-contact point */
    out->indentation_depth = -S->sys.u[2 * ns0 + 1];
    if (hist)
        axi_diagnostics(S, R, rep, &e, hist);
}
