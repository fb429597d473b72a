/* block_traj_run.c - one running rigid block, shared by the profile and the
 * terrain engines (docs/block-shape.md "Wiring"): set-up, and the step of
 * block.h's Moreau midpoint scheme with what the engines record: impacts
 * (a contact after at least BLOCK_TRAJ_IMPACT_FLIGHT in the air), launches,
 * the rebound height and rest (the kinetic energy below m v_stop^2 / 2 for
 * rest_time). */
#include "trajectory/block_traj.h"

#include <math.h>
#include <string.h>

rf_status block_run_init(block_run *b, const rf_traj_spec *s, uint64_t seed, uint64_t sample, int planar,
                         const double w_space[3], rf_error *err)
{
    memset(b, 0, sizeof *b);
    rf_status st = traj_block_shape(s, &b->shape, err);
    if (st != RF_OK)
        return st;
    traj_block_orientation(s, &b->shape, seed, sample, planar, b->st.q);
    memcpy(b->q0, b->st.q, sizeof b->q0);
    rf_block_to_body(b->st.q, w_space, b->st.w);
    b->planar = planar;
    b->bw.g = s->gravity;
    b->bw.h = s->block_time_step;
    b->bw.tol = 1e-10;
    b->bw.max_iter = 200;
    b->rest_time = s->block_rest_time;
    b->e_rest = 0.5 * b->shape.mass * s->v_stop * s->v_stop;
    b->air = INFINITY; /* a release in the air: the first touch is an impact */
    return RF_OK;
}

double block_run_lowest(const block_run *b, const rf_block_state *st, double p[3])
{
    const double up[3] = {0, 0, 1};
    return rf_block_lowest_point(&b->shape, st, up, p);
}

double block_run_energy(const block_run *b, const rf_block_state *st, double rot[3])
{
    return rf_block_kinetic_energy(&b->shape, st, rot);
}

int block_run_step(block_run *b, const rf_traj_material *m, double *rebound_height)
{
    traj_block_material(m, &b->bw.e_n, &b->bw.e_t, &b->bw.mu);
    b->prev = b->st;
    rf_block_step(&b->shape, &b->bw, &b->st, &b->info);
    if (b->planar) { /* the projection never gains energy: its round-off neither (scaled back) */
        double k0 = rf_block_kinetic_energy(&b->shape, &b->st, NULL);
        traj_block_planar(&b->shape, b->q0, &b->st);
        double k1 = rf_block_kinetic_energy(&b->shape, &b->st, NULL);
        for (int k = 0; k1 > k0 && k < 3; k++)
            b->st.v[k] *= sqrt(k0 / k1), b->st.w[k] *= sqrt(k0 / k1);
    }
    b->t += b->bw.h;
    int flags = 0, contact = b->info.n_contacts > 0;
    if (contact) {
        if (b->air >= BLOCK_TRAJ_IMPACT_FLIGHT) {
            flags |= BLOCK_STEP_IMPACT;
            b->rise_z = b->st.x[2], b->after_impact = 1;
        }
        b->air = 0;
    } else {
        if (b->air == 0)
            flags |= BLOCK_STEP_LAUNCH;
        b->air += b->bw.h;
        if (b->after_impact && b->st.x[2] - b->rise_z > *rebound_height)
            *rebound_height = b->st.x[2] - b->rise_z;
    }
    double ke = rf_block_kinetic_energy(&b->shape, &b->st, NULL);
    b->calm = contact && ke < b->e_rest ? b->calm + b->bw.h : 0;
    if (b->calm >= b->rest_time - 1e-9 * b->bw.h)
        flags |= BLOCK_STEP_REST;
    if (b->obs)
        b->obs(b->obs_ctx, b->t, &b->shape, &b->st, &b->info);
    return flags;
}
