/* traj_study_report.c - the trajectories behind a fuzzy trajectory study:
 * at its end the Monte Carlo is rerun with every fuzzy parameter at its
 * nominal value (100 trajectories recorded) and written to DIR/nominal/ as
 * `rockfuzz trajectory --out` writes a run (result.json, CSV files, figures,
 * report.html); the study report embeds its profile figure. */
#include "trajectory/traj_yaml_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static rf_status write_run(const char *sub, const rf_traj_spec *spec, const rf_traj_ensemble *e, int plots,
                           rf_error *err)
{
    rf_traj_stats t;
    rf_status st = rf_traj_stats_compute(e, &t, err);
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

rf_status rf_traj_study_nominal(const char *dir, const rf_study *s, int threads, int plots, rf_error *err)
{
    if (s->model_kind != RF_STUDY_MODEL_TRAJECTORY)
        return RF_OK;
    char sub[4096], old[4200];
    snprintf(sub, sizeof sub, "%s/nominal", dir);
    snprintf(old, sizeof old, "%s/trajectory_profile.png", sub);
    if (mkdir(sub, 0777) != 0 && errno != EEXIST)
        return rf_fail(err, RF_EIO, "cannot create %s: %s", sub, strerror(errno));
    unlink(old); /* the study report embeds it only if this run wrote it */
    double *x = malloc((s->n_params ? s->n_params : 1) * sizeof *x);
    if (!x)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < s->n_params; i++)
        x[i] = rf_fuzzy_nominal(&s->inputs[i]);
    rf_traj_spec spec;
    void *table;
    rf_status st = traj_model_spec_at(&s->model, x, &spec, &table, err);
    free(x);
    if (st != RF_OK)
        return st;
    spec.record = spec.samples < 100 ? spec.samples : 100;
    rf_traj_ensemble e;
    if ((st = traj_run_shared(&spec, threads, table, &e, err)) == RF_OK) {
        st = write_run(sub, &spec, &e, plots, err);
        rf_traj_ensemble_free(&e);
    }
    rf_traj_spec_free(&spec);
    return st;
}
