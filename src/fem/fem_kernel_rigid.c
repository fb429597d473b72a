/* fem_kernel_rigid.c - the kernel of a rigid body (fem_kernel.h): its
 * elements carry no internal force.  The solver keeps the body rigid by
 * moving all its nodes with one velocity (the contact couples them through
 * the body's mass, fem_contact.c), so the mesh only gives the contact
 * surface and the exact mass. */
#include "fem_kernel.h"

#include <string.h>

static void rigid_forces(const fem_kernel *k, long e0, long e1, const double *ue, double *fe)
{
    (void)ue;
    memset(fe, 0, (size_t)(e1 - e0) * (size_t)k->ndofe * sizeof *fe);
}

static void rigid_assemble(const fem_kernel *k, long e0, long e1, const int *conn, const double *u, double *f)
{
    (void)k, (void)e0, (void)e1, (void)conn, (void)u, (void)f;
}

static const fem_kernel_ops rigid_ops = {.name = "rigid body (no internal force)", .forces = rigid_forces,
                                         .assemble = rigid_assemble};

void fem_kernel_rigid(fem_kernel *k, long first, long count, int ndofe)
{
    k->ops = &rigid_ops, k->first = first, k->count = count, k->ndofe = ndofe, k->data = NULL;
}
