/* traj_presets_slope.c - the steepest slope a preset's layer stands on under
 * gravity (presets.h, docs/presets.md section 4b).  The impact model runs an
 * impact at incidence theta as a vertical impact on a slope inclined at theta
 * (traj_impact_adapter.c), and with gravity the 3D FE refuses a layer that
 * cannot stand on that slope; so a table of the preset's impact model can
 * hold incidences up to this angle only.  Mohr-Coulomb on the slope-parallel
 * plane at the layer's base, as the FE checks it (fem3d_gravity.c):
 *   FS(theta) = c / (rho g d sin theta) + tan phi / tan theta,
 * which falls monotonically on (0, 90] deg; the angle where FS = 1 is found
 * by bisection. */
#include "rockfuzz/presets.h"

#include <math.h>
#include <string.h>

#define PRESET_PI 3.14159265358979323846

/* The preset's nominal value of key; NAN when it has none. */
static double value(const rf_traj_preset *p, const char *key)
{
    for (size_t i = 0; i < p->n_values; i++)
        if (!strcmp(p->values[i].key, key))
            return p->values[i].value;
    return NAN;
}

static double safety(double c, double w, double phi, double th)
{
    return c / (w * sin(th)) + tan(phi) / tan(th);
}

double rf_traj_preset_steepest_slope(const rf_traj_preset *p, double g)
{
    const double d = value(p, "impact.layer_thickness"), rho = value(p, "impact.layer_density");
    const double c = value(p, "impact.layer_cohesion"), phi = value(p, "impact.layer_friction_angle") * PRESET_PI / 180;
    if (!(d > 0) || !(g > 0) || !(rho > 0) || isnan(c) || isnan(phi))
        return 90; /* no layer, or no weight: nothing slides */
    const double w = rho * g * d; /* the layer's weight per unit area [Pa] */
    double lo = 1e-9, hi = PRESET_PI / 2;
    if (safety(c, w, phi, hi) >= 1)
        return 90;
    for (int it = 0; it < 100; it++) {
        const double mid = 0.5 * (lo + hi);
        if (safety(c, w, phi, mid) >= 1)
            lo = mid;
        else
            hi = mid;
    }
    return lo * 180 / PRESET_PI;
}
