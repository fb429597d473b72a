/* block_traj_setup.c - a rigid block of a trajectory file made ready to run
 * (docs/block-shape.md "Wiring"): its shape with the spec's values, initial
 * orientation and spin, the contact material of a trajectory material, its
 * placement on the ground, the planar constraint of a profile run, and the
 * identity of what the spec holds outside the rows. */
#include "trajectory/block_traj.h"
#include "core/hash.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

uint64_t traj_block_hash(uint64_t h, const rf_traj_spec *s)
{
    int ints[3] = {s->block_kind, s->block_random_orientation, s->block_spin_given};
    h = rf_fnv1a(h, ints, sizeof ints);
    h = rf_fnv1a(h, s->block_dims, sizeof s->block_dims);
    h = rf_fnv1a(h, s->block_q0, sizeof s->block_q0);
    h = rf_fnv1a(h, s->block_spin0, sizeof s->block_spin0);
    h = rf_fnv1a(h, &s->block_n_points, sizeof s->block_n_points);
    return rf_fnv1a(h, s->block_points, 3 * s->block_n_points * sizeof(double));
}

/* The polyhedron of the spec's points stretched by (1, rb, rc) in the frame they are given in. */
static rf_status polyhedron(const rf_traj_spec *s, double rb, double rc, rf_block_shape *shape, rf_error *err)
{
    size_t n = s->block_n_points;
    double *p = malloc(3 * n * sizeof *p);
    if (!p)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; i++)
        p[3 * i] = s->block_points[3 * i], p[3 * i + 1] = rb * s->block_points[3 * i + 1],
        p[3 * i + 2] = rc * s->block_points[3 * i + 2];
    rf_status st = rf_block_polyhedron(n, p, s->density, shape, err);
    free(p);
    return st;
}

rf_status traj_block_shape(const rf_traj_spec *s, rf_block_shape *shape, rf_error *err)
{
    double rb = s->block_ratio_b, rc = s->block_ratio_c, V = s->block_volume;
    const double *d = s->block_dims;
    int stretched = rb != 1 || rc != 1;
    rf_status st;
    memset(shape, 0, sizeof *shape);
    switch (s->block_kind) {
    case RF_TRAJ_BLOCK_ELLIPSOID: st = rf_block_ellipsoid(d[0], rb * d[1], rc * d[2], s->density, shape, err); break;
    case RF_TRAJ_BLOCK_BOX: st = rf_block_box(d[0], rb * d[1], rc * d[2], s->density, shape, err); break;
    case RF_TRAJ_BLOCK_POLYHEDRON: st = polyhedron(s, rb, rc, shape, err); break;
    case RF_TRAJ_BLOCK_EOTA_CUBE:
    case RF_TRAJ_BLOCK_EOTA_WHEEL: /* stretched along its body axes, at the volume asked for */
        st = (s->block_kind == RF_TRAJ_BLOCK_EOTA_CUBE ? rf_block_eota_cube : rf_block_eota_wheel)(V, s->density, shape,
                                                                                                  err);
        if (st == RF_OK && stretched)
            st = rf_block_stretch(shape, 1, rb, rc, V, err);
        return st;
    default: return rf_fail(err, RF_EINVAL, "block.shape: not a rigid block (kind %d)", s->block_kind);
    }
    if (st != RF_OK || !(V > 0 || stretched))
        return st;
    /* A linear stretch multiplies the volume by rb rc: back to the given one (S3), or to block.volume. */
    st = rf_block_scale_to_volume(shape, V > 0 ? V : shape->volume / (rb * rc), err);
    if (st != RF_OK)
        rf_block_shape_free(shape);
    return st;
}

/* a b (quaternion product, w first). */
static void qmul(const double a[4], const double b[4], double c[4])
{
    double r[4] = {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                   a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                   a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                   a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
    double n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    for (int k = 0; k < 4; k++)
        c[k] = r[k] / n;
}

/* Draws of the orientation: stream 2 sample + 1 (the roughness draws'), far above their indices. */
#define ORIENT_INDEX ((uint64_t)1 << 62)

void traj_block_orientation(const rf_traj_spec *s, const rf_block_shape *shape, uint64_t seed, uint64_t sample,
                            int planar, double q[4])
{
    double given[4], user[4] = {s->block_q0[0], s->block_q0[1], s->block_q0[2], s->block_q0[3]};
    rf_block_quat_from_matrix(shape->axes, given); /* body -> the frame the shape was given in */
    if (s->block_random_orientation) {
        double u[3];
        for (int k = 0; k < 3; k++)
            u[k] = rf_traj_uniform(seed, 2 * sample + 1, ORIENT_INDEX + (uint64_t)k);
        if (planar) { /* a turn about y, uniform (Shoemake would leave the plane) */
            double ry[4] = {cos(RF_PI * u[0]), 0, sin(RF_PI * u[0]), 0};
            qmul(ry, s->block_q0, user);
        } else { /* uniform on SO(3) (Shoemake 1992) */
            double a = sqrt(1 - u[0]), b = sqrt(u[0]);
            double r[4] = {a * sin(2 * RF_PI * u[1]), a * cos(2 * RF_PI * u[1]), b * sin(2 * RF_PI * u[2]),
                           b * cos(2 * RF_PI * u[2])};
            memcpy(user, r, sizeof user);
        }
    }
    qmul(user, given, q);
}

void traj_block_material(const rf_traj_material *m, double *e_n, double *e_t, double *mu)
{
    *e_n = m->R_n;
    /* A sphere without spin hitting with sticking keeps v_t' / v_t = 1 - (2/7)(1 + e_t)
     * of its tangential speed: e_t is the one that gives R_t, clamped to [0, 1]. */
    double et = 3.5 * (1 - m->R_t) - 1;
    *e_t = et < 0 ? 0 : et > 1 ? 1 : et;
    *mu = tan(m->friction_angle);
}

int traj_block_place(const rf_block_shape *shape, rf_block_ground_fn ground, void *ctx, const double p[3],
                     rf_block_state *st)
{
    const double up[3] = {0, 0, 1};
    double lp[3], z, n[3];
    memset(st->x, 0, sizeof st->x);
    rf_block_lowest_point(shape, st, up, lp);
    for (int k = 0; k < 3; k++)
        st->x[k] = p[k] - lp[k];
    for (int it = 0; it < 4; it++) { /* lift until nothing lies below the ground */
        double lift = 0, b[3], s[3];
        if (!ground(ctx, p[0], p[1], &z, n))
            return 0;
        size_t nv = shape->kind == RF_BLOCK_POLYHEDRON ? shape->n_vertices : 1;
        for (size_t i = 0; i < nv; i++) {
            if (shape->kind == RF_BLOCK_POLYHEDRON)
                memcpy(b, shape->vertices + 3 * i, sizeof b);
            else {
                double dn[3] = {-n[0], -n[1], -n[2]}, db[3];
                rf_block_to_body(st->q, dn, db);
                rf_block_support(shape, db, b);
            }
            rf_block_to_space(st->q, b, s);
            double zg, ng[3];
            if (ground(ctx, st->x[0] + s[0], st->x[1] + s[1], &zg, ng) && zg - (st->x[2] + s[2]) > lift)
                lift = zg - (st->x[2] + s[2]);
        }
        if (!(lift > 0))
            break;
        st->x[2] += lift;
    }
    return 1;
}

void traj_block_omega_space(const rf_block_state *st, double w[3]) { rf_block_to_space(st->q, st->w, w); }

void traj_block_planar(const rf_block_shape *shape, const double q0[4], rf_block_state *st)
{
    st->x[1] = 0, st->v[1] = 0;
    /* The orientation back to a turn about y of q0: the nearest such turn of R(q) R(q0)^T. */
    double c[4] = {q0[0], -q0[1], -q0[2], -q0[3]}, rel[4];
    qmul(st->q, c, rel);
    double th = 2 * atan2(rel[2], rel[0]); /* the y part of the relative turn */
    double ry[4] = {cos(th / 2), 0, sin(th / 2), 0};
    /* Angular momentum about y kept; the rest of the rotation removed (its energy, never more). */
    double ey[3] = {0, 1, 0}, eb[3];
    rf_block_to_body(st->q, ey, eb);
    double Ly = 0, Iyy = 0;
    for (int k = 0; k < 3; k++)
        Ly += shape->inertia[k] * st->w[k] * eb[k], Iyy += shape->inertia[k] * eb[k] * eb[k];
    qmul(ry, q0, st->q);
    rf_block_to_body(st->q, ey, eb);
    for (int k = 0; k < 3; k++)
        st->w[k] = Ly / Iyy * eb[k];
}
