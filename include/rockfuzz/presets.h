/* presets.h - named materials a practitioner can start from (issue 29 item 6;
 * docs/presets.md): bedrock, talus, colluvium, loose_soil.  Each preset is a
 * list of rows of the trajectory file's material table (traj_fields.c:
 * "R_n", "friction_angle", "impact.layer_E", ...) with its nominal value and
 * a triangular fuzzy number (support [lo, hi], peak the nominal value), in
 * the units the row is given in (degrees for angles), plus the words of its
 * impact model.  A trajectory file names one with `materials: {NAME: PRESET}`
 * or `materials: {NAME: {preset: PRESET, R_n: 0.3, ...}}` (traj_yaml.c);
 * `rockfuzz presets` lists them (cmd_presets.c). */
#ifndef ROCKFUZZ_PRESETS_H
#define ROCKFUZZ_PRESETS_H

#include "rockfuzz/trajectory.h"

#include <stddef.h>

typedef struct {
    const char *key;            /* a row of the material table, below materials.NAME. */
    double value;               /* nominal, the fuzzy peak, as given (degrees for angles) */
    double lo, hi;              /* the fuzzy support (triangular), lo <= value <= hi */
    const char *source;         /* where the value and its range come from (docs/presets.md) */
} rf_traj_preset_value;

typedef struct {
    const char *name;
    const char *help;           /* one line: what ground it stands for */
    const char *solver;         /* impact model of the ground (rockfuzz impact --solver) */
    const char *boulder_material, *slope_material, *layer_material; /* "" = the impact model's default */
    const rf_traj_preset_value *values;
    size_t n_values;
} rf_traj_preset;

/* The k-th preset, NULL past the last. */
const rf_traj_preset *rf_traj_preset_at(size_t k);
/* The preset called `name`, or NULL. */
const rf_traj_preset *rf_traj_preset_named(const char *name);
/* "bedrock, talus, ..." into buf[size]. */
void rf_traj_preset_names(char *buf, size_t size);
/* The material-table row (traj_fields.c) of a preset value: its unit, check,
 * and whether a study may bind it; NULL if the key is no row. */
const rf_traj_field *rf_traj_preset_row(const rf_traj_preset_value *v);
/* Material m (its name already set) takes the preset's values, stored as the
 * material table stores them, and its impact model (m->impact.given = 1). */
void rf_traj_preset_apply(const rf_traj_preset *p, rf_traj_material *m);
/* The steepest slope [deg] on which the preset's layer stands under gravity g
 * [m/s^2] (infinite slope, Mohr-Coulomb at the layer's base, as the 3D FE
 * checks it); 90 without a layer or without gravity.  The impact model takes
 * an incidence theta as a slope of theta, so with gravity a table of the
 * preset's impact model holds incidences below it (docs/presets.md 4b). */
double rf_traj_preset_steepest_slope(const rf_traj_preset *p, double g);

#endif
