/* block_traj_run.c - one running rigid block, shared by the profile and the
 * terrain engines (docs/block-shape.md "Wiring"): set-up, the one loop of
 * both engines (block_run_loop: the engine's ground lookup and records
 * through block_engine), and the step of block.h's Moreau midpoint scheme
 * (rf_block_advance) with what the engines record: impacts
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
    b->rest_time = s->block_rest_time, b->max_time = s->block_max_time;
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

int block_run_step(block_run *b, const rf_traj_material *m)
{
    traj_block_material(m, &b->bw.e_n, &b->bw.e_t, &b->bw.mu);
    b->prev = b->st;
    b->dt = rf_block_advance(&b->shape, &b->bw, &b->st, BLOCK_TRAJ_FLIGHT_MAX, &b->info);
    if (b->planar) { /* the projection never gains energy: its round-off neither (scaled back) */
        double k0 = rf_block_kinetic_energy(&b->shape, &b->st, NULL);
        traj_block_planar(&b->shape, b->q0, &b->st);
        double k1 = rf_block_kinetic_energy(&b->shape, &b->st, NULL);
        for (int k = 0; k1 > k0 && k < 3; k++)
            b->st.v[k] *= sqrt(k0 / k1), b->st.w[k] *= sqrt(k0 / k1);
    }
    b->t += b->dt;
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
        b->air += b->dt;
        double top = b->st.x[2]; /* the parabola's apex when it lies inside the step */
        if (b->prev.v[2] > 0 && b->st.v[2] < 0 && b->bw.g > 0)
            top = b->prev.x[2] + 0.5 * b->prev.v[2] * b->prev.v[2] / b->bw.g;
        if (b->after_impact && top - b->rise_z > *b->rebound_height)
            *b->rebound_height = top - b->rise_z;
    }
    double ke = rf_block_kinetic_energy(&b->shape, &b->st, NULL);
    b->calm = contact && ke < b->e_rest ? b->calm + b->dt : 0;
    if (b->calm >= b->rest_time - 1e-9 * b->bw.h)
        flags |= BLOCK_STEP_REST;
    if (b->obs)
        b->obs(b->obs_ctx, b->t, &b->shape, &b->st, &b->info);
    return flags;
}

/* The ground under the block's lowest point (e->locate); NULL: the run exits there. */
static const rf_traj_material *ground_under(block_run *b, const block_engine *e, void *eng, size_t *where)
{
    double lp[3];
    block_run_lowest(b, &b->st, lp);
    const rf_traj_material *m = e->locate(eng, lp, where);
    if (!m)
        e->finish(eng, RF_TRAJ_EXITED, RF_EV_EXIT);
    return m;
}

/* The exit is checked right after each step (the step's material is the
 * ground's under the lowest point at its start), before that step's events:
 * an exit is the one event at its time. */
void block_run_loop(block_run *b, const block_engine *e, void *eng)
{
    size_t where, at;
    const rf_traj_material *m = ground_under(b, e, eng, &where);
    while (m && !b->done) {
        int fl = block_run_step(b, m);
        ++*b->n_steps;
        e->after_step(eng);
        at = where;
        if (b->done || !(m = ground_under(b, e, eng, &where)))
            return;
        if (fl & BLOCK_STEP_IMPACT) {
            e->impact(eng, at);
            e->event(eng, RF_EV_IMPACT, 0);
        } else if (fl & BLOCK_STEP_LAUNCH)
            e->event(eng, RF_EV_LAUNCH, 1);
        else if (b->t >= b->next_event)
            e->event(eng, RF_EV_CONTACT, b->info.n_contacts == 0);
        if (b->done)
            return;
        if (fl & BLOCK_STEP_REST)
            e->finish(eng, RF_TRAJ_STOPPED, RF_EV_REST);
        else if (b->t >= b->max_time)
            e->finish(eng, RF_TRAJ_STEP_LIMIT, RF_EV_STEP_LIMIT);
    }
}

/* The rotor's largest turn per sub-step [rad] when a flight is re-run to a fraction of it. */
#define ROTOR_ANGLE 0.05

void block_run_state_at(const block_run *b, double f, rf_block_state *out)
{
    const rf_block_state *a = &b->prev, *e = &b->st;
    if (b->info.n_contacts > 0) {
        *out = *e;
        for (int k = 0; k < 3; k++)
            out->x[k] = a->x[k] + f * (e->x[k] - a->x[k]), out->v[k] = a->v[k] + f * (e->v[k] - a->v[k]);
        return;
    }
    *out = *a;
    const double *I = b->shape.inertia; /* |w_i| <= |L| / I1 all along a torque-free flight */
    double L = sqrt(pow(I[0] * a->w[0], 2) + pow(I[1] * a->w[1], 2) + pow(I[2] * a->w[2], 2)), tau = f * b->dt;
    int n = (int)ceil(L / I[0] * tau / ROTOR_ANGLE);
    n = n < 1 ? 1 : n;
    for (int k = 0; k < n; k++)
        rf_block_flight_step(&b->shape, out, b->bw.g, tau / n);
}
