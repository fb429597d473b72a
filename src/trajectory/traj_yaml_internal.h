/* traj_yaml_internal.h - shared by the trajectory-file reader's files
 * (traj_yaml.c, traj_yaml_value.c, traj_yaml_profile.c, traj_yaml_release.c,
 * traj_yaml_terrain.c): the parse context,
 * with the line of every value read so that a validation failure found
 * after parsing can still be located. */
#ifndef ROCKFUZZ_TRAJ_YAML_INTERNAL_H
#define ROCKFUZZ_TRAJ_YAML_INTERNAL_H

#include "trajectory/traj_internal.h"
#include "core/yaml.h"

typedef struct {
    char path[160];
    int line;
} ty_line;

typedef struct {
    yr_ctx sp;
    rf_traj_spec *spec;
    struct fy_node *profile;
    unsigned char setting_given[32]; /* rf_traj_settings[k] was given in the file */
    struct fy_node *release;     /* the release: mapping (its line/zone are read after the profile) */
    int csv_named;               /* the CSV profile named the segment materials */
    struct fy_node *terrain;     /* terrain: (read after the materials: it names them) */
    int terrain_p95;             /* rasters.statistics asked for energy_p95 / height_p95 */
    ty_line *lines;
    size_t n_lines, cap_lines;
} ty_ctx;

/* Remember that `path` was given at the line of node n. */
void ty_remember(ty_ctx *c, const char *path, struct fy_node *n);
void ty_ctx_free(ty_ctx *c);

/* A number, or (allow_random) {uniform: [lo, hi]} / {normal: [mean, sd], min:, max:}
 * added to spec->random under `path`; *dst gets the nominal value. */
rf_status ty_value(ty_ctx *c, struct fy_node *n, const char *path, double *dst, int allow_random);

/* The number at `path`, a row of the input tables (traj_fields.c): random
 * if the row allows it; stored in the row's units (radians for an angle). */
rf_status ty_row_value(ty_ctx *c, struct fy_node *n, const char *path);

/* The setting g (traj_fields.c, rf_traj_settings) from node v, checked
 * against its range or names here, at load, with file:line. */
rf_status ty_setting(ty_ctx *c, struct fy_node *v, const rf_traj_setting *g);

/* The mapping n under `prefix`: every key is a row of the input tables
 * (prefix.key), a setting (rf_traj_settings: stop.max_steps, bounce.law,
 * the mapping bounce.impact of settings) or one of the space-separated
 * `extra` keys (read by the caller). */
rf_status ty_fields(ty_ctx *c, struct fy_node *n, const char *prefix, const char *extra);

/* materials.NAME: PRESET, or materials.NAME.preset of a mapping, applied to m
 * (traj_presets_yaml.c); *whole: the material is the preset as it is (no mapping). */
rf_status ty_material_preset(ty_ctx *c, struct fy_node *v, const char *path, rf_traj_material *m, int *whole);

/* materials.NAME.impact of the material mapping `mat` (traj_impact_yaml.c), if given. */
rf_status traj_impact_yaml(ty_ctx *c, struct fy_node *mat, const char *path, rf_traj_material *m);

/* The defaults of the rows of the tables owned by `owner` into obj (an
 * rf_traj_spec, rf_traj_material or rf_traj_collector). */
void ty_row_defaults(rf_traj_field_owner owner, void *obj);

/* release: {x, y | line: [[x, y], ...] | zone: {x: [x0, x1]} | {polygon: [[x, y], ...]},
 * vx, vy | speed, angle, omega} (traj_yaml_release.c) */
rf_status ty_parse_release(ty_ctx *c, struct fy_node *n);
/* x0, y0 of a line or zone release set to its point at u = 0.5 (the nominal
 * release, e.g. of a single trajectory); left as they are when the profile
 * is invalid (the validation reports it). */
void ty_release_nominal(rf_traj_spec *s);

/* profile: {points: [[x, y], ...] | csv: FILE | dem: {...}, materials: [..] | NAME} */
rf_status ty_parse_profile(ty_ctx *c, struct fy_node *n);

/* dem.c: profile: {dem: {file: F, line: [[x, y], ...], step: h, origin: [x, y]}} */
rf_status ty_dem_profile(ty_ctx *c, struct fy_node *n);

/* traj_yaml_terrain.c: a terrain file (docs/terrain-file.md).  begin: the
 * terrain part's defaults (before any key is read); terrain: {dem, band,
 * materials: {raster, band, classes} | material, roughness: {raster, band}};
 * release: {points | lines | polygons | file | raster, blocks, height,
 * velocity | vx, vy, vz | speed, azimuth, dip, spin}; a barrier's line
 * [[x, y], ...] under `path` appended to spec->terrain's lines; rasters:
 * {cell, statistics}; end: p95 among the percentiles when asked for. */
rf_status ty_terrain_begin(ty_ctx *c);
rf_status ty_parse_terrain(ty_ctx *c, struct fy_node *n);
rf_status ty_parse_terrain_release(ty_ctx *c, struct fy_node *n);
rf_status ty_barrier_line(ty_ctx *c, struct fy_node *n, const char *path);
rf_status ty_parse_rasters(ty_ctx *c, struct fy_node *n);
rf_status ty_terrain_end(ty_ctx *c, struct fy_node *root);

/* block_traj_yaml.c: the kind of a rigid block's shape name (0: none of
 * them); its own keys (axes, edges, points, points_file, axis_ratios,
 * orientation, spin) from the block mapping n, after its rows are read. */
int traj_block_kind_of(const char *str, size_t len);
rf_status ty_parse_block_shape(ty_ctx *c, struct fy_node *n);

/* Validate the finished spec (and the ranges of the random inputs); the
 * message gets the file and line of the field it names. */
rf_status ty_validate(ty_ctx *c);

#endif
