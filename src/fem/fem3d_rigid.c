/* fem3d_rigid.c - a rigid boulder in the 3D model (boulder_material =
 * rigid): "for soft slopes its elasticity is irrelevant and its stiffness
 * sets a needlessly small time step; mass and inertia exact" (issue 10).
 *
 * The boulder keeps its mesh (the contact surface, and the lumped masses
 * whose mass, centre of mass and I_yy are the spheroid's, fem3d_mass.c) but
 * moves as one body in the plane of motion: CM translation (x, z) and
 * rotation theta about y, the normal of the symmetry plane y = 0.  The
 * problem is symmetric about that plane, so these are all the motions of the
 * full body too (the full model's y forces cancel pair by pair).  Its
 * elements carry no internal force (a kernel that writes nothing), its
 * nodes have no inverse mass of their own: the contact (fem3d_contact.c)
 * applies each multiplier's force and torque to the rigid dofs, and every
 * node is placed from the rigid state after the predictor and after the
 * contact, x = c0 + X + Rot_y(theta) (X0 - c0), v = V + omega x r, so that
 * a finite rotation stays exact (no drift of the radius). */
#include "fem3d_internal.h"

#include <math.h>
#include <string.h>

static void rigid_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    (void)ue;
    memset(fe, 0, (size_t)(e1 - e0) * (size_t)k->ndofe * sizeof *fe);
}

static void rigid_field(const fem_kernel *k, long w0, long w1, const double *u, double *fe)
{
    (void)k, (void)w0, (void)w1, (void)u, (void)fe; /* no work units: the forces stay zero */
}

static const fem_kernel_ops rigid3d_ops = {.name = "rigid body (no internal force)", .forces = rigid_forces,
                                           .forces_field = rigid_field};

void f3_rigid_kernel(fem_kernel *k, long first, long count, double *fe)
{
    memset(k, 0, sizeof *k);
    k->ops = &rigid3d_ops, k->first = first, k->count = count, k->ndofe = 24, k->units = 0;
    memset(fe + 24 * first, 0, (size_t)count * 24 * sizeof *fe);
}

void f3_rigid_place(const f3_rigid *B, const f3_mesh *mesh, long nbn, double *u, double *v)
{
    const double ct = cos(B->th), st = sin(B->th);
    for (long i = 0; i < nbn; i++) {
        const double *X = mesh->x + 3 * i;
        const double dx = X[0] - B->c0[0], dz = X[2] - B->c0[2];
        const double rx = ct * dx + st * dz, rz = -st * dx + ct * dz; /* Rot_y(theta) d */
        u[3 * i] = B->c0[0] + B->X[0] + rx - X[0];
        u[3 * i + 1] = 0;
        u[3 * i + 2] = B->c0[2] + B->X[1] + rz - X[2];
        v[3 * i] = B->V[0] + B->w * rz;
        v[3 * i + 1] = 0;
        v[3 * i + 2] = B->V[1] - B->w * rx;
    }
}

void f3_rigid_predict(f3_rigid *B, double dt)
{
    B->X[0] += dt * B->V[0], B->X[1] += dt * B->V[1], B->th += dt * B->w;
}

void f3_rigid_correct(f3_rigid *B, double du[3], double dt)
{
    B->X[0] += du[0], B->X[1] += du[1], B->th += du[2];
    B->V[0] += du[0] / dt, B->V[1] += du[1] / dt, B->w += du[2] / dt;
    du[0] = du[1] = du[2] = 0;
}

double f3_rigid_energy(const f3_rigid *B)
{
    return 0.5 * B->M * (B->V[0] * B->V[0] + B->V[1] * B->V[1]) + 0.5 * B->I * B->w * B->w;
}
