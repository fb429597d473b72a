/* study_internal.h - shared by the study parser files (study.c,
 * study_model.c, study_traj.c); the located YAML access they use is
 * core/yaml.h. */
#ifndef ROCKFUZZ_STUDY_INTERNAL_H
#define ROCKFUZZ_STUDY_INTERNAL_H

#include "rockfuzz/study.h"

#include "core/yaml.h"

/* Build the model of `model:`; study->params are already parsed. */
rf_status sp_parse_model(yr_ctx *c, struct fy_node *n, rf_study *study);

/* The trajectory model block (study_traj.c). */
rf_status rf_traj_study_parse(yr_ctx *c, struct fy_node *n, rf_study *study);
/* A trajectory study's Monte Carlo rerun at the nominal point, written to
 * DIR/nominal/ (traj_study_report.c); RF_OK and nothing for other models. */
rf_status rf_traj_study_nominal(const char *dir, const rf_study *s, int threads, int plots, rf_error *err);

#endif
