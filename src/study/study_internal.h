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
 * DIR/nominal/ (study_traj.c; RF_OK and nothing for other models), and with
 * the TM's result res (NULL: the nominal point only) the reruns at the points giving the
 * lower and upper bound of the main output (rp_main_output) at membership 0,
 * in DIR/bound_lower/ and DIR/bound_upper/, the figures of the three on
 * common axes; a folder complete for the same model and point is kept.
 * A non-zero *interrupt (may be NULL) stops it before the next Monte Carlo
 * or figure (RF_EINTERRUPTED; an unfinished folder has no mark). */
rf_status rf_traj_study_reruns(const char *dir, const rf_study *s, const rf_tm_result *res, int threads, int plots,
                               const atomic_int *interrupt, rf_error *err);

/* The fuzzy hazard rasters of a trajectory study on a terrain file
 * (study_fuzzy_raster.c, docs/fuzzy-hazard.md).  begin (before the TM):
 * OUT/rasters becomes the trajectory model's raster sink (*f NULL and RF_OK
 * when the study has no fuzzy rasters); write (after it): every point's
 * raster present (missing ones rebuilt by evaluating the point again), the
 * bands of s->fuzzy_rasters retransformed per cell, OUT/fuzzy_rasters.tif
 * and with plots the maps of the first one (OUT/fuzzy_map_*.png, shown in
 * report.html); end: the sink cleared. */
typedef struct rf_fuzzy_rasters rf_fuzzy_rasters;
rf_status rf_study_fuzzy_rasters_begin(const char *out_dir, rf_study *s, rf_fuzzy_rasters **f, rf_error *err);
rf_status rf_study_fuzzy_rasters_write(const char *out_dir, const rf_study *s, rf_fuzzy_rasters *f,
                                       const rf_tm_result *res, int plots, rf_error *err);
void rf_study_fuzzy_rasters_end(rf_fuzzy_rasters *f);

#endif
