/* report_internal.h - helpers shared by the report writers (report_util.c). */
#ifndef ROCKFUZZ_REPORT_INTERNAL_H
#define ROCKFUZZ_REPORT_INTERNAL_H

#include <stddef.h>
#include <stdio.h>

#include "rockfuzz/study.h"
#include "rockfuzz/tm.h"

/* A name made safe for a file name: [A-Za-z0-9_.-], others become '_'. */
void rp_safe_name(const char *name, char *buf, size_t size);

/* Output k is NaN at every level and at the nominal point (e.g. R_t of a normal impact). */
int rp_output_undefined(const rf_tm_result *res, size_t k);

/* How an output is reported.  SHOWN: table, measures, plots.  The others get one
 * line: UNDEFINED (NaN everywhere, e.g. R_t of a normal impact), ZERO (exactly 0
 * at every point, e.g. plastic_work of elastic bodies) and BELOW_FLOOR
 * (indentation_depth of elastic bodies, plastic_work 0 at every point, or
 * smaller than RP_INDENTATION_FLOOR x the smallest penetration_max of the
 * study: the elastic spring-back residual, numerical noise; docs/user-guide.md
 * section 3). */
typedef enum { RP_OUTPUT_SHOWN, RP_OUTPUT_UNDEFINED, RP_OUTPUT_ZERO, RP_OUTPUT_BELOW_FLOOR } rp_output_kind;

#define RP_INDENTATION_FLOOR 0.01

/* The kind of output k, and in why (size bytes) the reason if it is not SHOWN. */
rp_output_kind rp_output_classify(const rf_study *s, const rf_tm_result *res, size_t k, char *why, size_t size);

/* The output the report's headline answers and a trajectory study reruns at
 * the bounds of: `main_output:` if the study names it, else the first SHOWN
 * output called *_total_energy_p95 (a barrier's design energy), else the
 * first SHOWN output; -1 if none is shown. */
long rp_main_output(const rf_study *s, const rf_tm_result *res);

/* "shown", "undefined", "zero", "below_floor" (result.json's outputs.NAME.status). */
const char *rp_output_kind_name(rp_output_kind kind);

/* One model setting, its value printed %.6g (lists: each number). */
typedef struct {
    char key[64];
    char value[192];
} rp_setting;

/* The key=value settings of the model identity (at most max): for the impact
 * model those that differ from its defaults (*vs_defaults = 1), for the
 * trajectory model all of them, for formula and program models none (their
 * description says it all).  The raw identity stays in result.json. */
size_t rp_model_settings(const rf_study *s, rp_setting *out, size_t max, int *vs_defaults);

/* The unit to show a value of this unit and size in: kJ for J from 1e4 J on
 * (*factor = 1e-3), else the unit itself (*factor = 1). */
const char *rp_display_unit(const char *unit, double max_abs, double *factor);

/* The input with the largest finite rho[0..n-1] (relative influence), or -1. */
int rp_main_input(const double *rho, size_t n);


/* <img> with the PNG at dir/stem.png as a data URI; a note if it is missing. */
void rp_embed_png(FILE *f, const char *dir, const char *stem, const char *alt);

/* report_fuzzy_maps.c: the section of a terrain study's fuzzy hazard maps
 * (DIR/fuzzy_map_nominal.png, fuzzy_map_upper.png side by side,
 * fuzzy_map_blame.png; study_fuzzy_raster.c draws them); nothing when the
 * run drew none. */
void rp_fuzzy_maps_html(FILE *f, const char *dir);

#endif
