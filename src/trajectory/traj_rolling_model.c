/* traj_rolling_model.c - the reduced model of the rolling resistance of a
 * rigid sphere on a layer of given static indentation curve (traj_rolling.h):
 * Bekker's compaction resistance (the work of making the rut per metre)
 * for a sphere on a bed of independent columns with no rebound, and its
 * closed form for a power-law curve.  Sources: M. G. Bekker, Theory of
 * Land Locomotion (1956) and Introduction to Terrain-Vehicle Systems (1969)
 * (compaction resistance R_c = b integral_0^z0 p dz of a rigid wheel, the
 * sinkage from the vertical balance over the front of the contact); J. Y.
 * Wong, Theory of Ground Vehicles (4th ed. 2008), ch. 2.  Here the wheel of
 * width b is a sphere: each strip of the rut (lateral offset y) is pressed
 * to its own depth z0 - y^2/(2R). */
#include "trajectory/traj_rolling.h"

#include <math.h>

double traj_rolling_curve_force(const traj_rolling_curve *c, double d)
{
    if (!(d > 0))
        return 0;
    double d0 = 0, f0 = 0;
    for (size_t i = 0; i < c->n; i++) {
        if (d <= c->depth[i])
            return f0 + (c->force[i] - f0) * (d - d0) / (c->depth[i] - d0);
        d0 = c->depth[i], f0 = c->force[i];
    }
    return NAN;
}

/* The depth where the curve reaches force f (the curve is non-decreasing). */
static double depth_at(const traj_rolling_curve *c, double f)
{
    double d0 = 0, f0 = 0;
    for (size_t i = 0; i < c->n; i++) {
        if (c->force[i] >= f)
            return c->force[i] > f0 ? d0 + (c->depth[i] - d0) * (f - f0) / (c->force[i] - f0) : c->depth[i];
        d0 = c->depth[i], f0 = c->force[i];
    }
    return NAN;
}

/* integral_0^1 F(z0 (1 - t^2)) dt by composite Simpson on 2000 intervals
 * (exact for a linear F; F piecewise linear: its kinks cost O(h^2)). */
static double rut_integral(const traj_rolling_curve *c, double z0)
{
    const int n = 2000;
    double h = 1.0 / n, sum = 0;
    for (int i = 0; i <= n; i++) {
        double t = i * h, w = i == 0 || i == n ? 1 : i % 2 ? 4 : 2;
        sum += w * traj_rolling_curve_force(c, z0 * (1 - t * t));
    }
    return sum * h / 3;
}

rf_status traj_rolling_solve(const traj_rolling_curve *c, double radius, double weight, traj_rolling_result *r,
                             rf_error *err)
{
    if (!c->n || !(radius > 0) || !(weight > 0))
        return rf_fail(err, RF_EINVAL, "rolling resistance: empty indentation curve, or radius %g m / weight %g N "
                                       "not > 0", radius, weight);
    double z0 = depth_at(c, 2 * weight);
    if (!isfinite(z0))
        return rf_fail(err, RF_EMODEL, "rolling resistance: the indentation curve ends at %g N (depth %g m) below "
                                       "2 W = %g N, the load of the front half-contact of the rolling block",
                       c->force[c->n - 1], c->depth[c->n - 1], 2 * weight);
    r->sinkage = z0;
    r->half_width = sqrt(2 * radius * z0);
    r->force = r->half_width / (RF_PI * radius) * rut_integral(c, z0);
    r->weight = weight;
    r->mu_r = r->force / weight;
    return RF_OK;
}

double traj_rolling_power_mu(double A, double m, double radius, double weight, double *sinkage)
{
    double z0 = pow(2 * weight / A, 1 / m);
    double B = sqrt(RF_PI) * exp(lgamma(m + 1) - lgamma(m + 1.5));
    if (sinkage)
        *sinkage = z0;
    return B * sqrt(2 * z0 / radius) / RF_PI;
}

double traj_rolling_power_fit(const traj_rolling_curve *c, double from, double *A, double *m)
{
    double dmax = c->n ? c->depth[c->n - 1] : 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    size_t n = 0;
    for (size_t i = 0; i < c->n; i++)
        if (c->depth[i] >= from * dmax && c->force[i] > 0) {
            double x = log(c->depth[i]), y = log(c->force[i]);
            sx += x, sy += y, sxx += x * x, sxy += x * y, n++;
        }
    double det = n * sxx - sx * sx;
    if (n < 2 || !(fabs(det) > 0)) {
        *A = *m = NAN;
        return NAN;
    }
    *m = (n * sxy - sx * sy) / det;
    *A = exp((sy - *m * sx) / n);
    double ss = 0;
    for (size_t i = 0; i < c->n; i++)
        if (c->depth[i] >= from * dmax && c->force[i] > 0) {
            double e = log(c->force[i]) - log(*A) - *m * log(c->depth[i]);
            ss += e * e;
        }
    return sqrt(ss / n);
}
