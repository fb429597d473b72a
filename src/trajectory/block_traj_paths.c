/* block_traj_paths.c - a rigid block's recorded paths on terrain as CSV
 * (DIR/trajectories.csv of `rockfuzz trajectory --out` on a terrain; the
 * profile engine's is traj_csv.c's): one row per event of each recorded
 * trajectory, with the block's lowest point, the centre's velocity, the
 * space angular velocity and the orientation (docs/block-shape.md
 * "Wiring").  paths.gpkg carries the same paths as lines, without q. */
#include "trajectory/block_traj.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

static const char *kind_name(rf_traj_event_kind k)
{
    static const char *const names[] = {"release", "impact", "launch", "contact", "vertex",
                                        "rest",    "exit",   "step_limit", "barrier"};
    return (unsigned)k < sizeof names / sizeof *names ? names[k] : "unknown";
}

static void write_rows(FILE *f, size_t k, const rf_terrain_result *r)
{
    for (size_t i = 0; i < r->n_events; i++) {
        const rf_terrain_event *v = &r->events[i];
        fprintf(f, "%zu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%s,%.17g,%.17g,%.17g,%.17g\n", k,
                v->t, v->p[0], v->p[1], v->p[2], v->v[0], v->v[1], v->v[2], v->omega[0], v->omega[1], v->omega[2],
                kind_name(v->kind), v->q[0], v->q[1], v->q[2], v->q[3]);
    }
}

rf_status traj_block_write_terrain_paths(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                         rf_error *err)
{
    if (!s->block_kind || !e->terrain)
        return RF_OK;
    char path[4096];
    if ((size_t)snprintf(path, sizeof path, "%s/trajectories.csv", dir) >= sizeof path)
        return rf_fail(err, RF_EINVAL, "output folder name too long: %s", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
    fputs("sample,t_s,x_m,y_m,z_m,vx_m_s,vy_m_s,vz_m_s,omega_x_rad_s,omega_y_rad_s,omega_z_rad_s,event,"
          "q_w,q_x,q_y,q_z\n", f);
    for (size_t k = 0; k < e->terrain->n_recorded; k++)
        write_rows(f, k, &e->terrain->recorded[k]);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad)
        return rf_fail(err, RF_EIO, "cannot write %s", path);
    return RF_OK;
}
