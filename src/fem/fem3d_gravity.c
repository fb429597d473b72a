/* fem3d_gravity.c - gravity in the 3D model (docs/validation-plastic.md
 * section 11, 3D part), the axisymmetric model's approach (fem_solver.c,
 * axi_gravity) in the slope frame.
 *
 * The boulder falls vertically onto a slope inclined at theta; the model's
 * frame has x down-slope and z along the outward slope normal, so gravity is
 * g (sin theta, 0, -cos theta), the direction of the incoming velocity.  The
 * boulder carries its lumped weight m_a g at every node (a rigid one M g at
 * its centre of mass, fem3d_solver.c) for the whole run.
 *
 * The slope starts at rest in the geostatic state of an infinite slope
 * (layer over bedrock, depth d along -z): equilibrium d sigma_zj / dz + rho
 * g_j = 0 with a traction-free surface gives sigma_zz = -g cos(theta) int
 * rho dd and sigma_zx = g sin(theta) int rho dd, exactly; the in-plane
 * normal stresses are statically indeterminate: K0 sigma_zz (K0 as in the
 * axisymmetric model: Jaky's 1 - sin phi for Drucker-Prager, nu / (1 - nu)
 * otherwise) where that state is inside the yield surface, else the
 * smallest admissible K > K0 (a steep slope's base), sigma_xy = sigma_yz =
 * 0.  The stress is set at the slope
 * kernel's integration points (fem_points_geostatic, shared with the
 * axisymmetric model) and the slope's body load is that stress's internal
 * force at u = 0, computed by the same kernel, so that the slope at rest
 * stays at rest to round-off with fixed and absorbing boundaries. */
#include "fem3d_gravity.h"
#include "fem_kernel.h"

#include <math.h>
#include <stdlib.h>

void f3_gravity_direction(double theta, double dir[3])
{
    dir[0] = sin(theta), dir[1] = 0, dir[2] = -cos(theta);
}

/* Infinite-slope factor of safety of law p at overburden q = int rho dd
 * [kg/m^2] (INFINITY for an elastic law or a level slope). */
static double slope_fs(const rf_material_params *p, double g, double theta, double q)
{
    const double tau = g * sin(theta) * q, sn = g * cos(theta) * q;
    if (!(tau > 0) || p->model == RF_MATERIAL_ELASTIC)
        return INFINITY;
    if (p->model == RF_MATERIAL_VON_MISES)
        return p->yield / (sqrt(3.0) * tau);
    return (p->cohesion + sn * tan(p->friction_angle)) / tau;
}

static rf_status unstable(const char *who, const rf_material_params *p, double theta, double depth, double fs,
                          rf_error *err)
{
    if (p->model == RF_MATERIAL_VON_MISES)
        return rf_fail(err, RF_EINVAL,
                       "fem3d: the %s cannot stand on this slope under gravity: slope_angle = %.4g deg, %s_yield = "
                       "%g Pa (von Mises), infinite-slope factor of safety Y / (sqrt 3 tau) = %.3g < 1 at depth %g "
                       "m; set gravity 0 for the gravity-free model", who, theta * 180 / RF_PI, who, p->yield, fs,
                       depth);
    return rf_fail(err, RF_EINVAL,
                   "fem3d: the %s cannot stand on this slope under gravity: slope_angle = %.4g deg, %s_cohesion = "
                   "%g Pa, %s_friction_angle = %.4g deg, infinite-slope factor of safety (c + sigma_n tan phi) / tau "
                   "= %.3g < 1 at depth %g m (a cohesionless %s needs phi >= the slope angle); set gravity 0 for "
                   "the gravity-free model", who, theta * 180 / RF_PI, who, p->cohesion, who,
                   p->friction_angle * 180 / RF_PI, fs, depth, who);
}

/* The smallest infinite-slope factor of safety at inclination th: the layer at
 * its base (*which 2) and the slope at depth max(depth_max, t) (*which 1). */
static double ground_fs(const rf_impact_input *in, double g, double depth_max, double th, int *which)
{
    const double t = in->layer_thickness > 0 ? in->layer_thickness : 0;
    rf_material_params ps, pl;
    rf_impact_material_params(in, 1, &ps);
    double fs = INFINITY;
    *which = 1;
    if (t > 0) { /* the layer at its base, where its cohesion counts least */
        rf_impact_material_params(in, 2, &pl);
        fs = slope_fs(&pl, g, th, in->layer_density * t);
        *which = 2;
    }
    const double d = fmax(depth_max, t), f = slope_fs(&ps, g, th, in->layer_density * t + in->slope_density * (d - t));
    if (f < fs)
        fs = f, *which = 1;
    return fs;
}

rf_status f3_gravity_stability(const rf_impact_input *in, double g, double depth_max, double *fs, rf_error *err)
{
    int which;
    *fs = ground_fs(in, g, depth_max, in->slope_angle, &which);
    if (!(*fs < 1))
        return RF_OK;
    const double t = in->layer_thickness > 0 ? in->layer_thickness : 0;
    rf_material_params p;
    rf_impact_material_params(in, which, &p);
    return unstable(which == 2 ? "layer" : "slope", &p, in->slope_angle, which == 2 ? t : fmax(depth_max, t), *fs,
                    err);
}

double f3_ground_angle(const rf_impact_input *in, rf_fem_ground mode, double g, double depth_max)
{
    const double th = in->slope_angle, S = RF_FEM_GROUND_SAFETY;
    int which;
    if (mode != RF_FEM_GROUND_STABLE || !(g > 0) || !(ground_fs(in, g, depth_max, th, &which) < S))
        return th;
    double lo = 0, hi = th; /* FS falls with the angle: FS(lo) >= S (level ground: infinite) > FS(hi) */
    for (int it = 0; it < 64; it++) {
        const double mid = 0.5 * (lo + hi);
        if (ground_fs(in, g, depth_max, mid, &which) >= S)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Depths -z of the 8 Gauss points of element e (in f3_hex_gradients' order). */
static void point_depths(const f3_mesh *m, long e, double depth[8])
{
    static const double XI[8] = {-1, 1, 1, -1, -1, 1, 1, -1}, ETA[8] = {-1, -1, 1, 1, -1, -1, 1, 1},
                        ZETA[8] = {-1, -1, -1, -1, 1, 1, 1, 1};
    const double gp = 1 / sqrt(3.0);
    const int *c = m->conn + 8 * e;
    for (int q = 0; q < 8; q++) {
        double z = 0;
        for (int a = 0; a < 8; a++)
            z += 0.125 * (1 + XI[a] * XI[q] * gp) * (1 + ETA[a] * ETA[q] * gp) * (1 + ZETA[a] * ZETA[q] * gp) *
                 m->x[3 * (long)c[a] + 2];
        depth[q] = -z;
    }
}

/* The geostatic stress at the slope kernel's points; -1 if its kernel has none (matrix-free). */
static long slope_geostatic(f3_system *S, const rf_impact_input *in, const rf_material matl[3], const int plastic[3],
                            double g)
{
    fem_kernel *k = &S->kernel[F3_SLOPE];
    double *depth = malloc(((size_t)k->count * 8 + 1) * sizeof *depth);
    if (!depth)
        return -2;
    for (long e = 0; e < k->count; e++)
        point_depths(S->mesh, k->first + e, depth + 8 * e);
    const int layer = in->layer_thickness > 0;
    rf_material_params p[2];
    rf_impact_material_params(in, 1, &p[0]);
    rf_impact_material_params(in, layer ? 2 : 1, &p[1]);
    const fem_geostatic geo = {g, layer ? in->layer_thickness : 0, in->layer_density, in->slope_density,
                               {fem_geostatic_k0(&p[0]), fem_geostatic_k0(&p[1])},
                               {plastic[1] ? &matl[1] : NULL, plastic[2] ? &matl[2] : NULL}, in->slope_angle};
    const long outside = fem_kernel_points_hex_geostatic(k, depth, &geo);
    free(depth);
    return outside;
}

rf_status f3_gravity_setup(f3_gravity *G, f3_system *S, const rf_impact_input *in, const rf_material matl[3],
                           const int plastic[3], const double *u_zero, double *fgrav, rf_error *err)
{
    G->fgrav = fgrav, G->W = 0, G->E0 = 0, G->outside = 0;
    f3_gravity_direction(in->slope_angle, G->dir);
    const long outside = slope_geostatic(S, in, matl, plastic, G->g);
    if (outside == -2)
        return rf_fail(err, RF_ENOMEM, "fem3d: out of memory");
    if (outside >= 0) {
        G->outside = outside;
        G->E0 = fmax(fem_kernel_points_hex_energy(&S->kernel[F3_SLOPE]), 0);
        f3_internal_force(S, u_zero, fgrav); /* u = 0: the slope's geostatic force (the boulder's is 0) */
        for (int b = 0; b < 2; b++)
            if (S->kernel[b].ops && S->kernel[b].ops->commit)
                S->kernel[b].ops->commit(&S->kernel[b]);
    }
    for (long i = 0; i < S->nbn; i++)
        for (int q = 0; q < 3; q++)
            fgrav[3 * i + q] = S->mass[3 * i + q] * G->g * G->dir[q];
    return RF_OK;
}

double f3_gravity_power(const f3_gravity *G, const f3_rigid *B, const double *v, long nbn, long ndof)
{
    double p = 0;
    if (B && B->on)
        p = B->M * G->g * (G->dir[0] * B->V[0] + G->dir[2] * B->V[1]);
    else
        for (long d = 0; d < 3 * nbn; d++)
            p += G->fgrav[d] * v[d];
    for (long d = 3 * nbn; d < ndof; d++)
        p += G->fgrav[d] * v[d];
    return p;
}
