/* terrain_invariants.c - what every recorded 3D trajectory must satisfy,
 * whatever the input (as traj_invariants.c in 2D): no event lies below the
 * ground beyond round-off, and the mechanical energy per unit mass
 * (|v|^2 / 2 + (I/m) |omega|^2 / 2 + g z) never rises from one event to the
 * next.  The ground comes from rf_terrain_height (the public evaluation of
 * the surface), not from the flight's cell walk.  Used by the tests. */
#include "trajectory/terrain_internal.h"

#include <math.h>

#define TERRAIN_INV_REL 1e-9 /* relative round-off over many events */

static double tolerance(const double p[3]) { return TERRAIN_INV_REL * (1 + fabs(p[0]) + fabs(p[1]) + fabs(p[2])); }

static rf_status check_point(const rf_terrain *t, size_t k, const double p[3], rf_error *err)
{
    double zg;
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
        return rf_fail(err, RF_EINVAL, "event %zu: the block at (%g, %g, %g) is not finite", k, p[0], p[1], p[2]);
    if (rf_terrain_height(t, p[0], p[1], &zg, NULL) && p[2] < zg - tolerance(p))
        return rf_fail(err, RF_EINVAL, "event %zu: the block at (%.17g, %.17g, %.17g) lies %.3g m below the ground",
                       k, p[0], p[1], p[2], zg - p[2]);
    return RF_OK;
}

/* Mechanical energy per unit mass [J/kg]; *size: the magnitude of its terms. */
static double energy(const rf_traj_spec *s, const rf_terrain_event *e, double *size)
{
    double i_m = s->sphere ? 0.4 * s->radius * s->radius : 0;
    double v2 = e->v[0] * e->v[0] + e->v[1] * e->v[1] + e->v[2] * e->v[2];
    double w2 = e->omega[0] * e->omega[0] + e->omega[1] * e->omega[1] + e->omega[2] * e->omega[2];
    double kin = 0.5 * v2 + 0.5 * i_m * w2;
    *size = kin + s->gravity * fabs(e->p[2]);
    return kin + s->gravity * e->p[2];
}

rf_status terrain_check_invariants(const rf_traj_spec *s, const rf_terrain *t, const rf_terrain_result *res,
                                   rf_error *err)
{
    const rf_terrain_event *ev = res->events;
    for (size_t k = 0; ev && k < res->n_events; k++) {
        rf_status st = check_point(t, k, ev[k].p, err);
        if (st != RF_OK)
            return st;
        if (k == 0)
            continue;
        double s0, s1, e0 = energy(s, &ev[k - 1], &s0), e1 = energy(s, &ev[k], &s1);
        double tol = TERRAIN_INV_REL * fmax(s0, s1) + s->gravity * tolerance(ev[k].p);
        if (!(e1 <= e0 + tol))
            return rf_fail(err, RF_EINVAL, "events %zu-%zu: mechanical energy rises from %.17g to %.17g J/kg", k - 1,
                           k, e0, e1);
    }
    return RF_OK;
}
