/* fem3d_large.c - the large-deformation step check of the 3D solver
 * (fem3d_large.h).  The central-difference step is set by the stiffest
 * element of the reference mesh; in updated Lagrangian an element compressed
 * under the contact becomes stiffer per unit mass and its bound falls with
 * its size.  The solver compares the step with every watched element's bound
 * after every step and, on a violation, makes the run again with half the step
 * (fem_run_halving, fem_core.c), as the axisymmetric solver does. */
#include "fem3d_large.h"

#include <math.h>
#include <stdlib.h>

static const double XI[8] = {-1, 1, 1, -1, -1, 1, 1, -1};
static const double ETA[8] = {-1, -1, 1, 1, -1, -1, 1, 1};
static const double ZETA[8] = {-1, -1, -1, -1, 1, 1, 1, 1};

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

double f3_element_size(const f3_mesh *mesh, long e, const double *u)
{
    const int *cn = mesh->conn + 8 * e;
    double t[3][3] = {{0}}; /* t[i] = d x / d xi_i at the centre */
    for (int a = 0; a < 8; a++) {
        const double s[3] = {XI[a], ETA[a], ZETA[a]};
        for (int j = 0; j < 3; j++) {
            const double x = mesh->x[3 * (long)cn[a] + j] + (u ? u[3 * (long)cn[a] + j] : 0);
            for (int i = 0; i < 3; i++)
                t[i][j] += 0.125 * s[i] * x;
        }
    }
    double c[3][3], amax = 0;
    cross(t[1], t[2], c[0]), cross(t[2], t[0], c[1]), cross(t[0], t[1], c[2]);
    const double det = t[0][0] * c[0][0] + t[0][1] * c[0][1] + t[0][2] * c[0][2];
    for (int i = 0; i < 3; i++)
        amax = fmax(amax, sqrt(c[i][0] * c[i][0] + c[i][1] * c[i][1] + c[i][2] * c[i][2]));
    return det > 0 && amax > 0 ? det / amax : 0;
}

rf_status f3_step_check_init(f3_step_check *c, const f3_mesh *mesh, long ne, const unsigned char *check,
                             const double *lam_upper, hex8_element_fn fn, void *ctx, rf_error *err)
{
    *c = (f3_step_check){ne, mesh, fn, ctx, NULL, NULL, 0};
    c->lower = calloc((size_t)(ne > 0 ? ne : 1), sizeof *c->lower);
    c->exact = calloc((size_t)(ne > 0 ? ne : 1), sizeof *c->exact);
    if (!c->lower || !c->exact)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory for the step check of %ld elements", ne);
    for (long e = 0; e < ne; e++) {
        const double h = f3_element_size(mesh, e, NULL);
        if ((!check || check[e]) && lam_upper[e] > 0 && h > 0)
            c->lower[e] = 2 / sqrt(lam_upper[e] * (1 + 1e-9)) / h;
    }
    return RF_OK;
}

void f3_step_check_free(f3_step_check *c)
{
    free(c->lower), free(c->exact);
    c->lower = c->exact = NULL;
}

/* The exact bound of element e per unit of reference size, found once. */
static double exact_bound(f3_step_check *c, long e)
{
    if (c->exact[e] == 0) {
        double K[576], m[8];
        unsigned char fr[24];
        c->fn(c->ctx, e, K, m, fr);
        const double lam = f3_hex_lambda_max(K, m, fr);
        c->exact[e] = lam > 0 ? 2 / sqrt(lam) / f3_element_size(c->mesh, e, NULL) : INFINITY;
        c->n_exact++;
    }
    return c->exact[e];
}

long f3_step_violation(f3_step_check *c, double dt, const double *u)
{
    for (long e = 0; e < c->ne; e++) {
        if (c->lower[e] == 0)
            continue;
        const double h = f3_element_size(c->mesh, e, u);
        if (dt > c->lower[e] * h && dt > exact_bound(c, e) * h)
            return e;
    }
    return -1;
}
