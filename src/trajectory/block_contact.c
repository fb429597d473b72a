/* block_contact.c - non-smooth contact dynamics of a rigid block (issue 30):
 * Moreau's midpoint time stepping with Newton's impact law and set-valued
 * Coulomb friction, solved per step by a prox Gauss-Seidel over the contact
 * points (Leine et al. 2014, Multibody Syst. Dyn. 32:241; Studer 2009,
 * LNACM 47).
 *
 * One step of h from state A:
 *   1. midpoint M: x_M = x_A + h/2 v_A; the orientation and body angular
 *      velocity by the free rotor over h/2 (block_body.c: the gyroscopic
 *      term, exact in the space angular momentum);
 *   2. the contacts active at M: gap <= 1e-9 m (a polyhedron's vertices; a
 *      smooth block's support point along the ground's -n), each with the
 *      frame (n, t1, t2) and W_c (3 x 6: the contact point's velocity along
 *      n, t1, t2 as a function of u = (v in space, w in the body): d . v +
 *      (r_b x d_b) . w), the Delassus block G_cc = W_c M^-1 W_c^T and the
 *      velocities before the step gamma_A = W_c u_M;
 *   3. u_E = u_M + M^-1 (h f + sum W_c^T Lambda_c), f = gravity, with the
 *      impulses solving, per contact,
 *        xi_N = gamma_N,E + e_n min(gamma_N,A, 0)   (Newton; no restitution of
 *               a contact that was already opening),
 *        xi_T = gamma_T,E + e_t gamma_T,A,
 *        Lambda_N = prox_{R+}(Lambda_N - r_N xi_N),
 *        Lambda_T = prox_{disk mu Lambda_N}(Lambda_T - r_T xi_T),
 *      r_N = 1/G_NN, r_T = 1/max(G_T1T1, G_T2T2), swept over the contacts
 *      (Gauss-Seidel, u updated after each contact) until the largest
 *      change of an impulse is below tol x the largest impulse;
 *   4. x_E = x_M + h/2 v_E, the rotor over h/2 with w_E.
 * Without contact the step is exact in translation (x_E = x_A + h v_A -
 * g h^2/2) and the rotor's Strang splitting in rotation.
 *
 * Energy.  The velocity jump alone never gains kinetic energy, but the
 * step's energy change is sum Lambda . (gamma_A + gamma_E) / 2, and on a
 * contact that persists while the block turns (a box pivoting on its edge)
 * gamma_N,A at the new midpoint is slightly positive (O(h omega^2 r)) with
 * Lambda_N > 0: Moreau's scheme then gains O(h^2) per step, O(h) per unit
 * time (measured: a box tipping over its edge gains 0.88 J of its 1.3 kJ at
 * h = 1 ms, 0.44 J at 0.5 ms).  A step with contacts therefore caps the
 * energy at the start's: it scales the step's end velocities (v and w alike,
 * which keeps the contact velocities' signs) and the centre's displacement
 * by one factor (cap_energy); the energy removed is reported
 * (rf_block_step_info.energy_cap).  Flight
 * steps are not capped (the rotor's bounded O(h^2) oscillation would be
 * ratcheted down).
 *
 * Speed (docs/block-shape.md, "Adaptive steps"): with the world's ground
 * bound (rf_block_ground_bound_fn: the ground's height above a plane over a
 * rectangle) the ground is evaluated only at the vertices within the bound;
 * rf_block_advance takes exact flight steps of up to h_max while the
 * bounding sphere or every vertex provably clears planes and ground; the
 * prox sweeps start from the last step's impulses when the step continues
 * it (warm start, per thread). */
#include "trajectory/block_internal.h"

#include <string.h>

#define MAX_CONTACTS 128
/* A contact is active at gap <= GAP_ACTIVE [m]: above the round-off of map
 * coordinates (1e5 m x 1e-16), so that a block set down exactly on the
 * ground does not fall a step at the points whose gap rounds to +1e-17. */
#define GAP_ACTIVE 1e-9
/* A point higher than CAP_MARGIN [m] above the ground's bound (or the
 * bounding sphere farther than that from a plane) is not tested: its gap
 * along the ground's normal exceeds GAP_ACTIVE wherever n_z >= 1e-3. */
#define CAP_MARGIN 1e-6

typedef struct {
    double rb[3];      /* contact point - centre, body frame */
    double d[3][3];    /* n, t1, t2 in space */
    double a[3][3];    /* r_b x d_b for each direction */
    double G[9];       /* Delassus block */
    double rn, rt;     /* prox factors 1/G_NN, 1/max(G_T1T1, G_T2T2) */
    double Gi[9];      /* G^-1 (the local sticking solve) */
    double md[3][3];   /* d_k / m and a_k / I: u += dl_k (md_k, ma_k) */
    double ma[3][3];
    double gA[3];      /* velocities before the step */
    double lam[3];     /* impulses [N s] */
    long key;          /* which point against which surface (warm start) */
} contact;

/* The ground near the block: below the plane z = p[0] + p[1] x + p[2] y +
 * dev over a rectangle that covers the bounding sphere (w->ground_bound). */
typedef struct {
    /* no ground there; bounded; no bound (test every point); not looked at */
    enum { GB_NONE, GB_BOUNDED, GB_UNKNOWN, GB_UNSET } state;
    double p[3], dev;
    double len;        /* sqrt(1 + p1^2 + p2^2): vertical height / len = distance along the plane's normal */
} ground_bound;

/* The height of q above the bound's plane (its vertical distance, m). */
static double above(const ground_bound *gb, const double q[3])
{
    return q[2] - gb->p[0] - gb->p[1] * q[0] - gb->p[2] * q[1] - gb->dev;
}

typedef struct {
    const rf_block_shape *s;
    double r[9];       /* R(q_M) */
    double x[3];       /* x_M */
    contact c[MAX_CONTACTS];
    int n;
    unsigned char far[64]; /* plane k farther than the bounding sphere (k < 64) */
    ground_bound gb;   /* the ground under the bounding sphere */
} contact_set;

int rf_block_ground_profile(void *profile, double x, double y, double *z, double normal[3])
{
    (void)y;
    const rf_block_profile *p = profile;
    if (p->n < 2 || !(x >= p->x[0]) || !(x <= p->x[p->n - 1]))
        return 0;
    size_t lo = 0, hi = p->n - 1;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (x < p->x[mid])
            hi = mid;
        else
            lo = mid;
    }
    double slope = (p->z[hi] - p->z[lo]) / (p->x[hi] - p->x[lo]);
    *z = p->z[lo] + slope * (x - p->x[lo]);
    double len = sqrt(1 + slope * slope);
    normal[0] = -slope / len, normal[1] = 0, normal[2] = 1 / len;
    return 1;
}

static void tangents(const double n[3], double t1[3], double t2[3])
{
    double e[3] = {0, 0, 0};
    int k = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : fabs(n[1]) <= fabs(n[2]) ? 1 : 2;
    e[k] = 1;
    bk_cross(n, e, t1);
    double il = 1 / bk_norm(t1);
    t1[0] *= il, t1[1] *= il, t1[2] *= il;
    bk_cross(n, t1, t2);
}

/* The inverse of a symmetric positive definite 3x3 matrix (adjugate). */
static void invert3(const double a[9], double b[9])
{
    b[0] = a[4] * a[8] - a[5] * a[7], b[1] = a[2] * a[7] - a[1] * a[8], b[2] = a[1] * a[5] - a[2] * a[4];
    b[3] = a[5] * a[6] - a[3] * a[8], b[4] = a[0] * a[8] - a[2] * a[6], b[5] = a[2] * a[3] - a[0] * a[5];
    b[6] = a[3] * a[7] - a[4] * a[6], b[7] = a[1] * a[6] - a[0] * a[7], b[8] = a[0] * a[4] - a[1] * a[3];
    double id = 1 / (a[0] * b[0] + a[1] * b[3] + a[2] * b[6]); /* one division, not nine */
    for (int i = 0; i < 9; i++)
        b[i] *= id;
}

/* The contact of body point rb (body frame) with normal n; u = (v, w). */
static void add_contact(contact_set *cs, const double rb[3], const double n[3], const double v[3], const double w[3],
                        long key)
{
    if (cs->n >= MAX_CONTACTS)
        return;
    contact *c = &cs->c[cs->n++];
    c->key = key;
    memcpy(c->rb, rb, sizeof c->rb);
    memcpy(c->d[0], n, sizeof c->d[0]);
    tangents(n, c->d[1], c->d[2]);
    /* M^-1 once per contact: the products below by reciprocals (a division costs as much as ten products) */
    const double *I = cs->s->inertia, iI[3] = {1 / I[0], 1 / I[1], 1 / I[2]}, im = 1 / cs->s->mass;
    for (int k = 0; k < 3; k++) {
        double db[3];
        bk_mat_tvec(cs->r, c->d[k], db);
        bk_cross(rb, db, c->a[k]);
        c->gA[k] = bk_dot(c->d[k], v) + bk_dot(c->a[k], w);
        c->lam[k] = 0;
    }
    for (int j = 0; j < 3; j++)
        for (int k = 0; k < 3; k++)
            c->G[3 * j + k] = (j == k) * im + c->a[j][0] * c->a[k][0] * iI[0] + c->a[j][1] * c->a[k][1] * iI[1] +
                              c->a[j][2] * c->a[k][2] * iI[2];
    c->rn = 1 / c->G[0], c->rt = 1 / bk_max(c->G[4], c->G[8]);
    invert3(c->G, c->Gi);
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 3; i++)
            c->md[k][i] = c->d[k][i] * im, c->ma[k][i] = c->a[k][i] * iI[i];
}

/* Vertex i against the planes and the ground. */
static void test_point(contact_set *cs, const rf_block_world *wd, size_t i, const double v[3], const double w[3])
{
    const double *rb = cs->s->vertices + 3 * i;
    long key = (long)(i * (wd->n_planes + 1));
    double p[3];
    bk_mat_vec(cs->r, rb, p);
    for (int i = 0; i < 3; i++)
        p[i] += cs->x[i];
    for (size_t k = 0; k < wd->n_planes; k++) {
        double d[3];
        if (k < 64 && cs->far[k])
            continue;
        bk_sub(p, wd->planes[k].point, d);
        if (bk_dot(wd->planes[k].normal, d) <= GAP_ACTIVE)
            add_contact(cs, rb, wd->planes[k].normal, v, w, key + (long)k);
    }
    double z, n[3];
    if (wd->ground && (cs->gb.state == GB_UNKNOWN || (cs->gb.state == GB_BOUNDED && above(&cs->gb, p) <= CAP_MARGIN)) &&
        wd->ground(wd->ground_ctx, p[0], p[1], &z, n) &&
        (p[2] - z) * n[2] <= GAP_ACTIVE)
        add_contact(cs, rb, n, v, w, key + (long)wd->n_planes);
}

/* A smooth block: its support point along -n of each plane and of the
 * ground below its centre. */
static void smooth_contacts(contact_set *cs, const rf_block_world *wd, const double v[3], const double w[3])
{
    double rb[3], db[3], p[3], d[3];
    for (size_t k = 0; k < wd->n_planes; k++) {
        const double *n = wd->planes[k].normal;
        if (k < 64 && cs->far[k])
            continue;
        double m[3] = {-n[0], -n[1], -n[2]};
        bk_mat_tvec(cs->r, m, db);
        rf_block_support(cs->s, db, rb);
        bk_mat_vec(cs->r, rb, p);
        for (int i = 0; i < 3; i++)
            p[i] += cs->x[i];
        bk_sub(p, wd->planes[k].point, d);
        if (bk_dot(n, d) <= GAP_ACTIVE)
            add_contact(cs, rb, n, v, w, (long)k);
    }
    double z, n[3];
    if (!wd->ground || !wd->ground(wd->ground_ctx, cs->x[0], cs->x[1], &z, n))
        return;
    double m[3] = {-n[0], -n[1], -n[2]};
    bk_mat_tvec(cs->r, m, db);
    rf_block_support(cs->s, db, rb);
    bk_mat_vec(cs->r, rb, p);
    for (int i = 0; i < 3; i++)
        p[i] += cs->x[i];
    if (wd->ground(wd->ground_ctx, p[0], p[1], &z, n) && (p[2] - z) * n[2] <= GAP_ACTIVE)
        add_contact(cs, rb, n, v, w, (long)wd->n_planes);
}

static void find_contacts(contact_set *cs, const rf_block_world *wd, const double v[3], const double w[3])
{
    cs->n = 0;
    const ground_bound *gb = &cs->gb;
    int ground_near = gb->state == GB_UNKNOWN ||
                      (gb->state == GB_BOUNDED && above(gb, cs->x) <= (cs->s->bound_radius + CAP_MARGIN) * gb->len);
    int near = ground_near || wd->n_planes > 64;
    for (size_t k = 0; k < wd->n_planes && k < 64; k++) {
        double d[3];
        bk_sub(cs->x, wd->planes[k].point, d);
        cs->far[k] = bk_dot(wd->planes[k].normal, d) > cs->s->bound_radius + GAP_ACTIVE;
        near |= !cs->far[k];
    }
    if (!near)
        return;
    if (cs->s->kind != RF_BLOCK_POLYHEDRON) {
        smooth_contacts(cs, wd, v, w);
        return;
    }
    for (size_t i = 0; i < cs->s->n_vertices; i++)
        test_point(cs, wd, i, v, w);
}

/* u += M^-1 W_c^T dl */
static void apply(const contact *c, const double dl[3], double v[3], double w[3])
{
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 3; i++) {
            v[i] += dl[k] * c->md[k][i];
            w[i] += dl[k] * c->ma[k][i];
        }
}

/* Sets the contact's impulses to lam; returns the largest change. */
static double update(contact *c, const double lam[3], double v[3], double w[3])
{
    double dl[3], change = 0;
    for (int k = 0; k < 3; k++) {
        dl[k] = lam[k] - c->lam[k];
        change = bk_max(change, fabs(dl[k]));
        c->lam[k] = lam[k];
    }
    apply(c, dl, v, w);
    return change;
}

/* One contact's update (block Gauss-Seidel): the local sticking solution
 * when it lies in the friction cone, else the prox step; returns the
 * largest change of its impulses. */
static double prox_contact(const rf_block_world *wd, contact *c, double v[3], double w[3])
{
    double g[3], lam[3];
    for (int k = 0; k < 3; k++)
        g[k] = bk_dot(c->d[k], v) + bk_dot(c->a[k], w);
    double xn = g[0] + wd->e_n * (c->gA[0] < 0 ? c->gA[0] : 0);
    /* the local sticking solution, xi = 0: exact for this contact if it is in the friction cone */
    double xi[3] = {xn, g[1] + wd->e_t * c->gA[1], g[2] + wd->e_t * c->gA[2]};
    for (int k = 0; k < 3; k++)
        lam[k] = c->lam[k] - (c->Gi[3 * k] * xi[0] + c->Gi[3 * k + 1] * xi[1] + c->Gi[3 * k + 2] * xi[2]);
    if (lam[0] > 0 && lam[1] * lam[1] + lam[2] * lam[2] <= wd->mu * wd->mu * lam[0] * lam[0])
        return update(c, lam, v, w);
    lam[0] = bk_max(0, c->lam[0] - xn * c->rn);
    double rt = c->rt;
    /* the normal change first enters the tangential velocities (Gauss-Seidel within the contact) */
    double dn = lam[0] - c->lam[0];
    for (int k = 1; k < 3; k++) {
        double gk = g[k] + c->G[3 * k] * dn;
        lam[k] = c->lam[k] - rt * (gk + wd->e_t * c->gA[k]);
    }
    double lt = sqrt(lam[1] * lam[1] + lam[2] * lam[2]), cap = wd->mu * lam[0];
    if (lt > cap)
        lam[1] *= cap / lt, lam[2] *= cap / lt;
    return update(c, lam, v, w);
}

static void solve(contact_set *cs, const rf_block_world *wd, double v[3], double w[3], rf_block_step_info *info)
{
    info->iterations = 0, info->converged = 1;
    if (!cs->n)
        return;
    info->converged = 0;
    for (int it = 0; it < wd->max_iter; it++) {
        double change = 0, big = 0;
        for (int k = 0; k < cs->n; k++) {
            const double *l = cs->c[k].lam;
            change = bk_max(change, prox_contact(wd, &cs->c[k], v, w));
            big = bk_max(big, bk_max(l[0], sqrt(l[1] * l[1] + l[2] * l[2])));
        }
        info->iterations = it + 1;
        if (change <= wd->tol * big) {
            info->converged = 1;
            break;
        }
    }
}

/* The energy cap of a contact step from A (x_A, total energy e_A) to E (see
 * the header): when E holds more energy than A, the step's motion is scaled
 * by the largest f in [0, 1] that gains none, the end velocities u_E and the
 * centre's displacement x_E - x_A alike: f^2 K_E + m g (z_A + f dz) = e_A,
 * whose root in [0, 1] exists because f = 0 (A's position, no velocity) holds
 * e_A - K_A <= e_A.  Scaling the velocities alone (as before) left the
 * position moved by the uncapped ones: a block coming to rest was lifted by
 * up to h dz_E / 2 with its kinetic energy set to 0.  The orientation is not
 * scaled (it holds no energy).  Returns the energy removed [J]. */
static double cap_energy(const rf_block_shape *s, const rf_block_world *w, rf_block_state *st, const double xa[3],
                         double e_a)
{
    double mg = s->mass * w->g, ke = rf_block_kinetic_energy(s, st, NULL), e_e = ke + mg * st->x[2];
    if (e_e <= e_a)
        return 0;
    double b = mg * (st->x[2] - xa[2]), c = bk_max(e_a - mg * xa[2], 0), f; /* c: A's kinetic energy */
    if (!(ke > 0) || (b >= 0 && !(c > 0)))
        f = 0;
    else if (b >= 0) /* the root's stable forms */
        f = 2 * c / (b + sqrt(b * b + 4 * ke * c));
    else
        f = (-b + sqrt(b * b + 4 * ke * c)) / (2 * ke);
    f = f < 1 ? f : 1;
    for (int i = 0; i < 3; i++)
        st->x[i] = xa[i] + f * (st->x[i] - xa[i]), st->v[i] *= f, st->w[i] *= f;
    return e_e - rf_block_energy(s, st, w->g);
}

/* The ground's bound over [lo, hi] (x, y): the plane through the ground
 * under x (horizontal if there is none there) raised by the callback's
 * bound of the ground above it. */
static void bound_ground(const rf_block_world *w, const double x[3], const double lo[2], const double hi[2],
                         ground_bound *gb)
{
    double z, n[3];
    gb->state = !w->ground ? GB_NONE : !w->ground_bound ? GB_UNKNOWN : GB_BOUNDED;
    if (gb->state != GB_BOUNDED)
        return;
    if (w->ground(w->ground_ctx, x[0], x[1], &z, n) && n[2] > 1e-3) {
        gb->p[1] = -n[0] / n[2], gb->p[2] = -n[1] / n[2];
        gb->p[0] = z - gb->p[1] * x[0] - gb->p[2] * x[1];
    } else {
        gb->p[0] = gb->p[1] = gb->p[2] = 0;
    }
    gb->len = sqrt(1 + gb->p[1] * gb->p[1] + gb->p[2] * gb->p[2]);
    if (!w->ground_bound(w->ground_ctx, lo[0], lo[1], hi[0], hi[1], gb->p, &gb->dev))
        gb->state = GB_NONE;
}

/* Warm start: the impulses (in space) of the last step's contacts, used as
 * the first guess of this step's when it continues that step (same shape,
 * same world, this step starts where that one ended: a trajectory stepped
 * through, so the result does not depend on what else the thread ran). */
typedef struct {
    const rf_block_shape *s;
    const rf_block_world *w;
    rf_block_state end;
    int n;
    long key[MAX_CONTACTS];
    double lam[MAX_CONTACTS][3];
} warm_cache;

static void warm_start(const warm_cache *wc, contact_set *cs, const rf_block_world *w, double v[3], double u[3])
{
    for (int k = 0; k < cs->n; k++) {
        contact *c = &cs->c[k];
        int j = 0;
        while (j < wc->n && wc->key[j] != c->key)
            j++;
        if (j == wc->n)
            continue;
        for (int i = 0; i < 3; i++)
            c->lam[i] = bk_dot(c->d[i], wc->lam[j]);
        c->lam[0] = bk_max(c->lam[0], 0);
        double lt = sqrt(c->lam[1] * c->lam[1] + c->lam[2] * c->lam[2]), cap = w->mu * c->lam[0];
        if (lt > cap)
            c->lam[1] *= cap / lt, c->lam[2] *= cap / lt;
        apply(c, c->lam, v, u);
    }
}

static void warm_store(warm_cache *wc, const contact_set *cs, const rf_block_world *w, const rf_block_state *st)
{
    wc->s = cs->s, wc->w = w, wc->end = *st, wc->n = cs->n;
    for (int k = 0; k < cs->n; k++) {
        const contact *c = &cs->c[k];
        wc->key[k] = c->key;
        for (int i = 0; i < 3; i++)
            wc->lam[k][i] = c->lam[0] * c->d[0][i] + c->lam[1] * c->d[1][i] + c->lam[2] * c->d[2][i];
    }
}

/* rf_block_step with the ground's bound gb over the midpoint's bounding
 * sphere (NULL: find it). */
static void contact_step(const rf_block_shape *s, const rf_block_world *w, rf_block_state *st,
                         rf_block_step_info *info, const ground_bound *gb)
{
    static _Thread_local contact_set cs;
    static _Thread_local warm_cache wc;
    int warm = wc.s == s && wc.w == w && !memcmp(&wc.end, st, sizeof *st);
    double h = w->h, e_start = rf_block_energy(s, st, w->g), xa[3] = {st->x[0], st->x[1], st->x[2]};
    for (int i = 0; i < 3; i++)
        st->x[i] += 0.5 * h * st->v[i];
    rf_block_rotor_step(s->inertia, st->q, st->w, 0.5 * h);
    cs.s = s;
    if (gb) {
        cs.gb = *gb;
    } else {
        double r = s->bound_radius, lo[2] = {st->x[0] - r, st->x[1] - r}, hi[2] = {st->x[0] + r, st->x[1] + r};
        bound_ground(w, st->x, lo, hi, &cs.gb);
    }
    bk_quat_matrix(st->q, cs.r);
    memcpy(cs.x, st->x, sizeof cs.x);
    find_contacts(&cs, w, st->v, st->w);
    st->v[2] -= w->g * h;
    if (warm)
        warm_start(&wc, &cs, w, st->v, st->w);
    solve(&cs, w, st->v, st->w, info);
    info->n_contacts = cs.n;
    info->impulse_n = 0;
    for (int k = 0; k < cs.n; k++)
        info->impulse_n += cs.c[k].lam[0];
    for (int i = 0; i < 3; i++)
        st->x[i] += 0.5 * h * st->v[i];
    rf_block_rotor_step(s->inertia, st->q, st->w, 0.5 * h);
    info->energy_cap = cs.n ? cap_energy(s, w, st, xa, e_start) : 0;
    warm_store(&wc, &cs, w, st);
}

void rf_block_step(const rf_block_shape *s, const rf_block_world *w, rf_block_state *st, rf_block_step_info *info)
{
    rf_block_step_info local;
    contact_step(s, w, st, info ? info : &local, NULL);
}

/* The lowest value over [0, tau] of d0 + d1 t - d2 t^2 / 2. */
static double quad_min(double d0, double d1, double d2, double tau)
{
    double m = fmin(d0, d0 + d1 * tau - 0.5 * d2 * tau * tau);
    if (d2 < 0 && d1 < 0 && d1 / d2 < tau) /* convex: an interior minimum at t = d1 / d2 */
        m = fmin(m, d0 + 0.5 * d1 * d1 / d2);
    return m;
}

/* Whether the block stays clear of every plane (its bounding sphere) and of
 * the ground over [0, tau] of free flight; *gb the ground's bound over the
 * swept rectangle (it holds under the midpoint of a step up to tau).  The
 * distance along the bound plane's normal N of the centre is exact
 * (quadratic in t); a vertex at r_i from the centre turns by at most
 * |r_i| wmax t (wmax = |L| / I1), so its distance is at least its own plus
 * the centre's change minus R wmax t. */
static int flight_clear(const rf_block_shape *s, const rf_block_world *w, const rf_block_state *st, double tau,
                        ground_bound *gb)
{
    double R = s->bound_radius;
    gb->state = GB_UNSET;
    for (size_t k = 0; k < w->n_planes; k++) {
        const double *n = w->planes[k].normal;
        double d[3];
        bk_sub(st->x, w->planes[k].point, d);
        if (quad_min(bk_dot(n, d), bk_dot(n, st->v), n[2] * w->g, tau) <= R + CAP_MARGIN)
            return 0;
    }
    double lo[2], hi[2];
    for (int i = 0; i < 2; i++) {
        double x1 = st->x[i] + st->v[i] * tau;
        lo[i] = fmin(st->x[i], x1) - R, hi[i] = fmax(st->x[i], x1) + R;
    }
    bound_ground(w, st->x, lo, hi, gb);
    if (gb->state != GB_BOUNDED)
        return gb->state == GB_NONE;
    double dv = (st->v[2] - gb->p[1] * st->v[0] - gb->p[2] * st->v[1]) / gb->len, dg = w->g / gb->len;
    if (quad_min(above(gb, st->x) / gb->len, dv, dg, tau) > R + CAP_MARGIN)
        return 1;
    if (s->kind != RF_BLOCK_POLYHEDRON)
        return 0;
    const double *I = s->inertia;
    double wmax = sqrt(pow(I[0] * st->w[0], 2) + pow(I[1] * st->w[1], 2) + pow(I[2] * st->w[2], 2)) / I[0], r[9];
    bk_quat_matrix(st->q, r);
    for (size_t i = 0; i < s->n_vertices; i++) {
        double p[3];
        bk_mat_vec(r, s->vertices + 3 * i, p);
        for (int k = 0; k < 3; k++)
            p[k] += st->x[k];
        if (quad_min(above(gb, p) / gb->len, dv - R * wmax, dg, tau) <= CAP_MARGIN)
            return 0;
    }
    return 1;
}

/* Free flight over tau: exact parabola, the rotor in sub-steps of at most
 * ROTOR_ANGLE [rad] each. */
#define ROTOR_ANGLE 0.05
static void long_flight(const rf_block_shape *s, rf_block_state *st, double g, double tau)
{
    for (int i = 0; i < 3; i++)
        st->x[i] += st->v[i] * tau;
    st->x[2] -= 0.5 * g * tau * tau;
    st->v[2] -= g * tau;
    const double *I = s->inertia; /* |w_i| <= |L| / I1 all along */
    double wmax = sqrt(pow(I[0] * st->w[0], 2) + pow(I[1] * st->w[1], 2) + pow(I[2] * st->w[2], 2)) / I[0];
    int n = (int)ceil(wmax * tau / ROTOR_ANGLE);
    n = n < 1 ? 1 : n;
    for (int k = 0; k < n; k++)
        rf_block_rotor_step(s->inertia, st->q, st->w, tau / n);
}

double rf_block_advance(const rf_block_shape *s, const rf_block_world *w, rf_block_state *st, double h_max,
                        rf_block_step_info *info)
{
    rf_block_step_info local;
    if (!info)
        info = &local;
    double tau = 2 * w->h;
    ground_bound gb, gb2;
    if (tau > h_max || !flight_clear(s, w, st, tau, &gb)) {
        contact_step(s, w, st, info, tau > h_max || gb.state == GB_UNSET ? NULL : &gb);
        return w->h;
    }
    while (2 * tau <= h_max && flight_clear(s, w, st, 2 * tau, &gb2))
        tau *= 2;
    long_flight(s, st, w->g, tau);
    *info = (rf_block_step_info){.converged = 1};
    return tau;
}
