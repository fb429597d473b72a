/* terrain_files.c - the run folder of a terrain run (rf_terrain_write_outputs):
 * samples.csv (per sample its state, start and end point, runout, reach
 * angle, rebound height), crossings.csv (per sample and barrier the crossing
 * with its map point and the energy left), statistics.csv (percentiles per
 * quantity), every header naming its unit; hazard.tif (one band per
 * statistic of the rasters, terrain_geotiff_write), paths.gpkg (end points
 * and recorded trajectories, terrain_gpkg_write), and with plots the maps
 * and report.html (terrain_write_maps). */
#include "trajectory/terrain_internal.h"
#include "trajectory/block_traj.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEG (180.0 / 3.14159265358979323846) /* degrees per radian */

static rf_status write_samples(FILE *f, const rf_traj_ensemble *e)
{
    const rf_terrain_samples *t = e->terrain;
    fputs("sample,state,start_x_m,start_y_m,start_z_m,end_x_m,end_y_m,end_z_m,runout_m,reach_angle_deg,"
          "rebound_height_m\n", f);
    for (size_t i = 0; i < e->samples; i++) {
        const double *a = &t->start[3 * i], *b = &t->end[3 * i];
        fprintf(f, "%zu,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", i,
                rf_traj_state_name(e->state[i]), a[0], a[1], a[2], b[0], b[1], b[2], t->runout[i],
                t->reach_angle[i] * DEG, e->rebound_height[i]);
    }
    return ferror(f) ? RF_EIO : RF_OK;
}

static rf_status write_crossings(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e)
{
    fputs("sample,state,runout_m,barrier,reached,t_s,x_m,y_m,along_m,height_lowest_m,height_centre_m,"
          "normal_height_m,speed_m_s,translational_energy_J,rotational_energy_J,total_energy_J,energy_after_J,"
          "stopped_by_barrier\n", f);
    for (size_t i = 0; i < e->samples; i++)
        for (size_t c = 0; c < s->n_collectors; c++) {
            const rf_traj_crossing *x = &e->crossings[i * s->n_collectors + c];
            fprintf(f, "%zu,%s,%.17g,%s,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                       "%d\n", i, rf_traj_state_name(e->state[i]), e->runout_x[i], s->collectors[c].name, x->reached,
                    x->t, x->x, x->y, x->along, x->height_lowest, x->height_centre, x->normal_height, x->speed,
                    x->translational_energy, x->rotational_energy, x->total_energy, x->energy_after,
                    x->stopped_by_barrier);
        }
    return ferror(f) ? RF_EIO : RF_OK;
}

/* One row per quantity (the profile's statistics.csv, with the runout and the reach angle). */
static rf_status write_stats(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st)
{
    traj_stats_header(f, st);
    traj_stats_row(f, NULL, "runout", "m", &st->runout_x, 1);
    traj_stats_row(f, NULL, "reach_angle", "deg", &st->reach_angle, DEG);
    traj_stats_row(f, NULL, "rebound_height", "m", &st->rebound_height, 1);
    traj_stats_collectors(f, s, st);
    return ferror(f) ? RF_EIO : RF_OK;
}

rf_status terrain_write_tables(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                               const rf_traj_stats *st, rf_error *err)
{
    static const char *const names[3] = {"samples.csv", "crossings.csv", "statistics.csv"};
    if (!e->terrain)
        return rf_fail(err, RF_EINVAL, "not a terrain run");
    for (int k = 0; k < 3; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        FILE *f = fopen(path, "w");
        if (!f)
            return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
        rf_status rc = k == 0 ? write_samples(f, e) : k == 1 ? write_crossings(f, s, e) : write_stats(f, s, st);
        if (fclose(f) != 0 || rc != RF_OK)
            return rf_fail(err, RF_EIO, "cannot write %s", path);
    }
    return RF_OK;
}

/* hazard.tif, paths.gpkg and (plots) the maps, on the run's surface. */
static rf_status write_geo(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st,
                           int plots, rf_error *err)
{
    const rf_terrain_samples *t = e->terrain;
    const char *crs = e->terrain_dem ? rf_terrain_crs_wkt(e->terrain_dem) : "";
    char path[4096];
    terrain_band *bands = NULL;
    size_t n = 0;
    rf_status rc = RF_OK;
    if (t->hazard && (rc = terrain_hazard_bands(t->hazard, s, e->samples, &bands, &n, err)) == RF_OK) {
        size_t nx, ny;
        double x0, y0, cell;
        terrain_hazard_grid(t->hazard, &nx, &ny, &x0, &y0, &cell);
        snprintf(path, sizeof path, "%s/hazard.tif", dir);
        rc = terrain_geotiff_write(path, crs, nx, ny, x0, y0, cell, bands, n, err);
    }
    if (rc == RF_OK) {
        snprintf(path, sizeof path, "%s/paths.gpkg", dir);
        rc = terrain_gpkg_write(path, crs, e, err);
    }
    if (rc == RF_OK && plots && e->terrain_dem)
        rc = terrain_write_maps(dir, s, e, st, e->terrain_dem, bands, n, err);
    terrain_bands_free(bands, n);
    return rc;
}

rf_status rf_terrain_write_outputs(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                   const rf_traj_stats *st, int plots, rf_error *err)
{
    rf_status rc = terrain_write_tables(dir, s, e, st, err);
    rc = rc == RF_OK ? write_geo(dir, s, e, st, plots, err) : rc;
    return rc == RF_OK ? traj_block_write_vtk_runs(dir, s, e, err) : rc; /* a rigid block: block_traj_vtk.c */
}
