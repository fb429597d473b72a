/* block_traj_output.c - a rigid block's additions to the JSON of `rockfuzz
 * trajectory --json` (traj_output.c for a profile, terrain_output.c for a
 * terrain): per impact its orientation and rotational energy about each body
 * axis; per recorded trajectory the orientation at each event. */
#include "trajectory/block_traj.h"
#include "core/json.h"

void traj_block_json_impact(FILE *f, const double q[4], const double rot_energy[3])
{
    fputs(", \"q\": ", f), rf_json_array(f, q, 4, 1);
    fputs(", \"rotational_energy_axes\": ", f), rf_json_array(f, rot_energy, 3, 1);
}

/* "orientation": [[t, w, x, y, z], ...] from n events (t and q at stride bytes). */
static void orientation(FILE *f, const void *events, size_t n, size_t stride, size_t t_off, size_t q_off)
{
    fputs(", \"orientation\": [", f);
    for (size_t i = 0; i < n; i++) {
        const char *e = (const char *)events + i * stride;
        const double *t = (const double *)(e + t_off), *q = (const double *)(e + q_off);
        double row[5] = {*t, q[0], q[1], q[2], q[3]};
        fputs(i ? ", " : "", f), rf_json_array(f, row, 5, 1);
    }
    fputs("]", f);
}

void traj_block_json_orientation(FILE *f, const rf_traj_result *r)
{
    if (r->events)
        orientation(f, r->events, r->n_events, sizeof *r->events, offsetof(rf_traj_event, t),
                    offsetof(rf_traj_event, q));
}

void terrain_block_json_orientation(FILE *f, const rf_terrain_result *r)
{
    if (r->events)
        orientation(f, r->events, r->n_events, sizeof *r->events, offsetof(rf_terrain_event, t),
                    offsetof(rf_terrain_event, q));
}

void traj_block_describe(const rf_traj_spec *s, char *buf, size_t size)
{
    if (!s->block_kind) {
        if (s->sphere)
            snprintf(buf, size, "sphere, radius %g m, density %g kg/m^3, mass %.4g kg", s->radius, s->density,
                     traj_spec_mass(s));
        else
            snprintf(buf, size, "point, mass %.4g kg", s->mass);
        return;
    }
    rf_block_shape shape;
    rf_error err;
    if (traj_block_shape(s, &shape, &err) != RF_OK) {
        snprintf(buf, size, "%s", traj_block_kind_name(s->block_kind));
        return;
    }
    snprintf(buf, size, "rigid %s, volume %.4g m^3, density %g kg/m^3, mass %.4g kg (at the file's values)",
             traj_block_kind_name(s->block_kind), shape.volume, shape.density, shape.mass);
    rf_block_shape_free(&shape);
}
