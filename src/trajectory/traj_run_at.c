/* traj_run_at.c - a trajectory model's Monte Carlo at one point of its
 * parameters (100 trajectories recorded), written to a folder as `rockfuzz
 * trajectory --out` writes a run (result.json, CSV files, figures,
 * report.html): the trajectories behind a fuzzy trajectory study
 * (src/study/study_traj.c reruns its nominal point). */
#include "trajectory/traj_internal.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

static rf_status write_run(const char *sub, const rf_traj_spec *spec, const rf_traj_ensemble *e, int plots,
                           rf_error *err)
{
    rf_traj_stats t;
    rf_status st = rf_traj_stats_compute_spec(spec, e, &t, err);
    if (st != RF_OK)
        return st;
    char path[4200];
    snprintf(path, sizeof path, "%s/result.json", sub);
    FILE *f = fopen(path, "w");
    if (!f)
        st = rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
    else {
        rf_traj_write_json(f, spec, e, &t, 100);
        if (fclose(f) != 0)
            st = rf_fail(err, RF_EIO, "cannot write %s", path);
    }
    if (st == RF_OK)
        st = rf_traj_write_csv(sub, spec, e, &t, err);
    if (st == RF_OK && plots)
        st = rf_traj_write_plots(sub, spec, e, &t, err);
    rf_traj_stats_free(&t);
    return st;
}

rf_status rf_traj_model_write_run(const rf_model *m, const double *x, const char *dir, int threads, int plots,
                                  rf_error *err)
{
    rf_traj_spec spec;
    void *table;
    rf_status st = traj_model_spec_at(m, x, &spec, &table, err);
    if (st != RF_OK)
        return st;
    spec.record = spec.samples < 100 ? spec.samples : 100;
    rf_traj_ensemble e;
    if ((st = traj_run_shared(&spec, threads, table, &e, err)) == RF_OK) {
        st = write_run(dir, &spec, &e, plots, err);
        rf_traj_ensemble_free(&e);
    }
    rf_traj_spec_free(&spec);
    return st;
}
