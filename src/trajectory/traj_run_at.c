/* traj_run_at.c - a trajectory model's Monte Carlo at one point of its
 * parameters (100 trajectories recorded), written to a folder as `rockfuzz
 * trajectory --out` writes a run (result.json, CSV files, figures,
 * report.html): the trajectories behind a fuzzy trajectory study
 * (src/study/study_traj.c reruns its nominal point and the points giving the
 * bounds of its main output, and draws their figures on common axes).  A
 * terrain model's point runs rf_terrain_run and is written as `rockfuzz
 * trajectory --out` writes a terrain run (its maps on their own scales). */
#include "trajectory/terrain_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct rf_traj_point_run {
    rf_traj_spec spec;
    rf_traj_ensemble ens;
    rf_traj_stats stats;
};

void rf_traj_point_run_free(rf_traj_point_run *r)
{
    if (!r)
        return;
    rf_traj_stats_free(&r->stats);
    rf_traj_ensemble_free(&r->ens);
    rf_traj_spec_free(&r->spec);
    free(r);
}

rf_status rf_traj_model_run_at(const rf_model *m, const double *x, int threads, double *y, rf_traj_point_run **out,
                               rf_error *err)
{
    *out = NULL;
    rf_traj_point_run *r = calloc(1, sizeof *r);
    if (!r)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    void *table;
    rf_status st = traj_model_spec_at(m, x, &r->spec, &table, err);
    if (st != RF_OK) {
        free(r);
        return st;
    }
    r->spec.record = r->spec.samples < 100 ? r->spec.samples : 100;
    st = r->spec.terrain ? rf_terrain_run(&r->spec, threads, NULL, NULL, &r->ens, err)
                         : traj_run_shared(&r->spec, threads, table, &r->ens, err);
    if (st == RF_OK &&
        (st = rf_traj_stats_compute_spec(&r->spec, &r->ens, &r->stats, err)) == RF_OK) {
        if (y)
            traj_model_outputs(m, &r->spec, &r->stats, y);
        *out = r;
        return RF_OK;
    }
    rf_traj_ensemble_free(&r->ens);
    rf_traj_spec_free(&r->spec);
    free(r);
    return st;
}

void rf_traj_plot_scales_add(rf_traj_plot_scales *sc, const rf_traj_point_run *r)
{
    if (!r->spec.terrain) /* the profile figures' axes; terrain maps keep their own */
        traj_plot_extent(&r->spec, &r->ens, sc);
}

rf_status rf_traj_point_run_write(const rf_traj_point_run *r, const char *dir, int plots,
                                  const rf_traj_plot_scales *sc, rf_error *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/result.json", dir);
    rf_status st = rf_traj_write_json_file(path, &r->spec, &r->ens, &r->stats, 100, err);
    if (st == RF_OK && r->spec.terrain)
        return rf_terrain_write_outputs(dir, &r->spec, &r->ens, &r->stats, plots, err);
    if (st == RF_OK)
        st = rf_traj_write_csv(dir, &r->spec, &r->ens, &r->stats, err);
    if (st == RF_OK && plots)
        st = traj_write_plots_scaled(dir, &r->spec, &r->ens, &r->stats, sc, err);
    return st;
}

rf_status rf_traj_model_write_run(const rf_model *m, const double *x, const char *dir, int threads, int plots,
                                  rf_error *err)
{
    rf_traj_point_run *r;
    rf_status st = rf_traj_model_run_at(m, x, threads, NULL, &r, err);
    if (st == RF_OK)
        st = rf_traj_point_run_write(r, dir, plots, NULL, err);
    rf_traj_point_run_free(r);
    return st;
}
