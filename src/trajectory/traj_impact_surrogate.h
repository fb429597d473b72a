/* traj_impact_surrogate.h - the impact model's tables over the bound
 * material parameters of a study (traj_impact_surrogate.c: the grid and the
 * blend, and its error at independent runs). */
#ifndef ROCKFUZZ_TRAJ_IMPACT_SURROGATE_H
#define ROCKFUZZ_TRAJ_IMPACT_SURROGATE_H

#include "trajectory/traj_internal.h"

#include <stdio.h>

typedef struct traj_impact_surrogate traj_impact_surrogate;

/* The independent impact-model runs of a study's surrogate (its error estimate). */
#define TRAJ_SURROGATE_CHECKS 16

typedef struct {
    size_t dim, nodes[4];       /* bound inputs, nodes per axis */
    size_t tables;              /* (v_n, theta, radius) tables built (nodes and tested midpoints) */
    size_t computed, from_store; /* impacts of those tables: computed by the model, taken from the store */
    double table_error;         /* largest error estimate of a table (traj_impact_table.c) */
    double midpoint_miss;       /* the last refinement round's largest midpoint miss */
    size_t check_runs, check_computed, check_from_store; /* the independent runs */
    double err_rn, err_rt;      /* largest |surrogate - model| at the independent runs */
    double seconds;             /* the build's wall time */
} traj_impact_surrogate_info;

/* A surrogate over the d (1..4) inputs paths[] of spec (materials.NAME.impact.X)
 * in [lo, hi] (as given: angles in degrees), with `checks` independent runs;
 * nothing is computed yet. */
rf_status traj_impact_surrogate_create(const rf_traj_spec *spec, size_t d, const char *const *paths, const double *lo,
                                       const double *hi, size_t checks, traj_impact_surrogate **out, rf_error *err);
void traj_impact_surrogate_free(traj_impact_surrogate *s);
/* Build the grid, then the error check, once (later calls return the first
 * build's status; an interrupted build is resumed by the next call).  The
 * watch's store, stop flag and model are those of traj_impact_table_build_watched;
 * log (may be NULL) gets a line per table and the error. */
rf_status traj_impact_surrogate_build(traj_impact_surrogate *s, const traj_table_watch *w, FILE *log, rf_error *err);
/* The table at the bound inputs' values in spec `at` (a blend of node tables,
 * valid while s lives; freed by the caller).  A value outside the box: an error. */
rf_status traj_impact_surrogate_table(const traj_impact_surrogate *s, const rf_traj_spec *at, traj_impact_table **out,
                                      rf_error *err);
/* The same, owned by the surrogate (freed with it). */
rf_status traj_impact_surrogate_table_lent(traj_impact_surrogate *s, const rf_traj_spec *at,
                                           const traj_impact_table **out, rf_error *err);
/* R_n, R_t, spin of the surrogate at parameter point x (d values). */
rf_status traj_impact_surrogate_lookup_at(const traj_impact_surrogate *s, const double *x, size_t material,
                                          double radius, double vn, double theta, double c[3], rf_error *err);
void traj_impact_surrogate_get(const traj_impact_surrogate *s, traj_impact_surrogate_info *info);
/* "impact surrogate error R_n .., R_t .. (...)": the line every result carries. */
void traj_impact_surrogate_describe(const traj_impact_surrogate *s, char *buf, size_t size);

/* For the trajectory model: a surrogate over the paths among paths[0..n) that
 * are inputs of a material's impact model (*out = NULL when none), each over
 * [lo, hi] of its index. */
rf_status traj_impact_surrogate_for_model(const rf_traj_spec *spec, size_t n, char *const *paths, const double *lo,
                                          const double *hi, size_t checks, traj_impact_surrogate **out, rf_error *err);
/* Why binding path (an input of a material's impact model) would change
 * nothing or is not supported in spec, or NULL. */
const char *traj_impact_surrogate_unused(const rf_traj_spec *spec, const char *path);
/* Whether path is an input of a material's impact model (materials.NAME.impact.X). */
int traj_impact_surrogate_path(const char *path);

#endif
