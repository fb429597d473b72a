/* impact_fields.c - the one table of the impact inputs (impact.h,
 * rf_impact_field): name, place, unit, default, rule and help of every
 * numeric field of rf_impact_input.  Defaults: the nominal granite of
 * SYSTEM.md (r0 = 1 m, rho 2600 kg/m^3, E 68.2 GPa, nu 0.25, 10 m/s onto a
 * horizontal slope, no friction, elastic bodies, no layer). */
#include "core/util.h"
#include "rockfuzz/impact.h"

#include <math.h>
#include <stdio.h>
#include <stddef.h>
#include <string.h>

#define ROW(field, kind, unit, def, probe, check, bind, help) \
    {#field, offsetof(rf_impact_input, field), kind, unit, def, probe, check, bind, help}
#define P RF_FIELD_PLAIN
#define DEG RF_FIELD_DEGREES

const rf_impact_field rf_impact_fields[] = {
    ROW(radius, P, "m", 1.0, 1.0, RF_CHECK_POSITIVE, 1,
        "boulder radius (of the volume-equivalent sphere for a spheroid)"),
    ROW(horizontal_axis, P, "m", 0.0, 0.0, RF_CHECK_NONNEGATIVE, 1,
        "spheroid's horizontal semi-axis c; 0 = sphere (binding it keeps the volume: d = r^3/c^2)"),
    ROW(vertical_axis, P, "m", 0.0, 0.0, RF_CHECK_NONNEGATIVE, 0,
        "spheroid's vertical semi-axis d; 0 = from the constant volume, r^3/c^2"),
    ROW(boulder_density, P, "kg/m^3", 2600.0, 2600.0, RF_CHECK_POSITIVE, 1, "boulder density"),
    ROW(slope_density, P, "kg/m^3", 2600.0, 2600.0, RF_CHECK_POSITIVE, 1, "slope density"),
    ROW(boulder_E, P, "Pa", 68.2e9, 68.2e9, RF_CHECK_POSITIVE, 1, "boulder Young's modulus"),
    ROW(slope_E, P, "Pa", 68.2e9, 68.2e9, RF_CHECK_POSITIVE, 1, "slope Young's modulus"),
    ROW(boulder_poisson, P, "", 0.25, 0.25, RF_CHECK_POISSON, 1, "boulder Poisson's ratio, in (-1, 0.5)"),
    ROW(slope_poisson, P, "", 0.25, 0.25, RF_CHECK_POISSON, 1, "slope Poisson's ratio, in (-1, 0.5)"),
    ROW(velocity, P, "m/s", 10.0, 10.0, RF_CHECK_POSITIVE, 1, "vertical impact speed"),
    ROW(slope_angle, DEG, "deg", 0.0, 0.0, RF_CHECK_INCLINATION, 1, "slope inclination, in [0, 90)"),
    ROW(friction, P, "", 0.0, 0.0, RF_CHECK_NONNEGATIVE, 1, "Coulomb friction coefficient boulder-slope"),
    ROW(boulder_yield, P, "Pa", 0.0, 1e8, RF_CHECK_NONE, 1, "von_mises boulder: initial yield stress Y"),
    ROW(boulder_hardening, P, "Pa", 0.0, 0.0, RF_CHECK_NONE, 1, "von_mises boulder: hardening modulus H"),
    ROW(slope_yield, P, "Pa", 0.0, 1e8, RF_CHECK_NONE, 1, "von_mises slope: initial yield stress Y"),
    ROW(slope_hardening, P, "Pa", 0.0, 0.0, RF_CHECK_NONE, 1, "von_mises slope: hardening modulus H"),
    ROW(slope_cohesion, P, "Pa", 0.0, 1e4, RF_CHECK_NONE, 1, "drucker_prager slope: cohesion c"),
    ROW(slope_friction_angle, DEG, "deg", 0.0, 30.0, RF_CHECK_NONE, 1, "drucker_prager slope: friction angle phi"),
    ROW(slope_dilatancy_angle, DEG, "deg", 0.0, 0.0, RF_CHECK_NONE, 1,
        "drucker_prager slope: dilatancy angle psi, in [0, phi]"),
    ROW(slope_cap_pressure, P, "Pa", 0.0, 0.0, RF_CHECK_NONE, 1, "drucker_prager slope: cap crush pressure; 0 = no cap"),
    ROW(slope_cap_hardening, P, "Pa", 0.0, 0.0, RF_CHECK_NONE, 1, "drucker_prager slope: cap compaction modulus"),
    ROW(slope_dilatancy_cutoff, P, "", 0.0, 0.0, RF_CHECK_NONE, 1,
        "drucker_prager slope: plastic volume change at which dilatancy stops; 0 = none"),
    ROW(layer_thickness, P, "m", 0.0, 0.1, RF_CHECK_NONNEGATIVE, 1, "soil layer on the slope; 0 = homogeneous slope"),
    ROW(layer_density, P, "kg/m^3", 2600.0, 2600.0, RF_CHECK_NONE, 1, "layer density"),
    ROW(layer_E, P, "Pa", 68.2e9, 68.2e9, RF_CHECK_NONE, 1, "layer Young's modulus"),
    ROW(layer_poisson, P, "", 0.25, 0.25, RF_CHECK_NONE, 1, "layer Poisson's ratio, in (-1, 0.5)"),
    ROW(layer_yield, P, "Pa", 0.0, 1e8, RF_CHECK_NONE, 1, "von_mises layer: initial yield stress Y"),
    ROW(layer_hardening, P, "Pa", 0.0, 0.0, RF_CHECK_NONE, 1, "von_mises layer: hardening modulus H"),
    ROW(layer_cohesion, P, "Pa", 0.0, 1e4, RF_CHECK_NONE, 1, "drucker_prager layer: cohesion c"),
    ROW(layer_friction_angle, DEG, "deg", 0.0, 30.0, RF_CHECK_NONE, 1, "drucker_prager layer: friction angle phi"),
    ROW(layer_dilatancy_angle, DEG, "deg", 0.0, 0.0, RF_CHECK_NONE, 1,
        "drucker_prager layer: dilatancy angle psi, in [0, phi]"),
    ROW(layer_cap_pressure, P, "Pa", 0.0, 0.0, RF_CHECK_NONE, 1, "drucker_prager layer: cap crush pressure; 0 = no cap"),
    ROW(layer_cap_hardening, P, "Pa", 0.0, 0.0, RF_CHECK_NONE, 1, "drucker_prager layer: cap compaction modulus"),
    ROW(layer_dilatancy_cutoff, P, "", 0.0, 0.0, RF_CHECK_NONE, 1,
        "drucker_prager layer: plastic volume change at which dilatancy stops; 0 = none"),
    ROW(gravity, RF_FIELD_GRAVITY, "m/s^2", RF_GRAVITY_AUTO, 0.0, RF_CHECK_GRAVITY, 1,
        "gravity's magnitude (acts along -z); auto = 9.81 with a plastic body, else 0"),
};
const size_t rf_impact_n_fields = sizeof rf_impact_fields / sizeof rf_impact_fields[0];

const rf_impact_field *rf_impact_field_find(const char *name)
{
    for (size_t k = 0; name && k < rf_impact_n_fields; k++)
        if (!strcmp(name, rf_impact_fields[k].name))
            return &rf_impact_fields[k];
    return NULL;
}

void rf_impact_bindable_list(char *buf, size_t size)
{
    size_t len = 0;
    buf[0] = '\0';
    for (size_t k = 0; k < rf_impact_n_fields && len < size; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        if (f->bindable)
            len += (size_t)snprintf(buf + len, size - len, "%s%s%s%s%s", len ? ", " : "", f->name,
                                    f->unit[0] ? " [" : "", f->unit, f->unit[0] ? "]" : "");
    }
}

static double *place(rf_impact_input *in, const rf_impact_field *f)
{
    return (double *)((char *)in + f->offset);
}

void rf_impact_field_store(rf_impact_input *in, const rf_impact_field *f, double given)
{
    *place(in, f) = f->kind == RF_FIELD_DEGREES ? given * (RF_PI / 180.0) : given;
}

void rf_impact_field_set(rf_impact_input *in, const rf_impact_field *f, double given)
{
    rf_impact_field_store(in, f, given);
    if (f->offset == offsetof(rf_impact_input, horizontal_axis))
        in->vertical_axis = 0.0; /* d = radius^3 / c^2: constant volume */
}

double rf_impact_field_get(const rf_impact_input *in, const rf_impact_field *f)
{
    double x = *(const double *)((const char *)in + f->offset);
    return f->kind == RF_FIELD_DEGREES ? x * (180.0 / RF_PI) : x;
}

int rf_impact_field_ok(const rf_impact_field *f, double x)
{
    switch (f->check) {
    case RF_CHECK_NONE: return 1;
    case RF_CHECK_POSITIVE: return isfinite(x) && x > 0.0;
    case RF_CHECK_NONNEGATIVE: return isfinite(x) && x >= 0.0;
    case RF_CHECK_POISSON: return isfinite(x) && x > -1.0 && x < 0.5;
    case RF_CHECK_INCLINATION: return isfinite(x) && x >= 0.0 && x < 0.5 * RF_PI;
    case RF_CHECK_GRAVITY: return (isfinite(x) && x >= 0.0) || x == RF_GRAVITY_AUTO;
    }
    return 0;
}

#define OUT(field, unit, help) {#field, offsetof(rf_impact_output, field), unit, help}

const rf_impact_output_field rf_impact_output_fields[RF_IMPACT_N_OUTPUTS] = {
    OUT(contact_force_max, "N", "largest contact force"),
    OUT(compression_max, "m", "largest approach of the boulder's centre of mass after first contact"),
    OUT(contact_duration, "s", "contact duration"),
    OUT(contact_radius, "m", "contact radius at the peak force"),
    OUT(R_n, "", "normal coefficient of restitution"),
    OUT(R_t, "", "tangential coefficient of restitution (undefined at normal incidence)"),
    OUT(R_ke, "", "kinetic-energy coefficient of restitution"),
    OUT(plastic_work, "", "plastic dissipation, fraction of the initial kinetic energy (FE only)"),
    OUT(penetration_max, "m", "deepest position of the boulder's lowest point below the undeformed surface (FE only)"),
    OUT(indentation_depth, "m", "permanent depth of the slope surface at the first-contact point (FE only)"),
    OUT(equivalent_plastic_strain_max, "", "largest equivalent plastic strain over both bodies (FE only)"),
};
