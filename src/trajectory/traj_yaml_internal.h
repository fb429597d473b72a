/* traj_yaml_internal.h - shared by the trajectory-file reader's files
 * (traj_yaml.c, traj_yaml_value.c, traj_yaml_profile.c): the parse context,
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
    int record_given;
    int csv_named;               /* the CSV profile named the segment materials */
    ty_line *lines;
    size_t n_lines, cap_lines;
} ty_ctx;

/* Remember that `path` was given at the line of node n. */
void ty_remember(ty_ctx *c, const char *path, struct fy_node *n);
void ty_ctx_free(ty_ctx *c);

/* A number, or (allow_random) {uniform: [lo, hi]} / {normal: [mean, sd], min:, max:}
 * added to spec->random under `path`; *dst gets the nominal value. */
rf_status ty_value(ty_ctx *c, struct fy_node *n, const char *path, double *dst, int allow_random);

/* The mapping n under `prefix`: every key must be in the space-separated
 * list `keys`; numeric ones go to rf_traj_spec_field(prefix.key). */
rf_status ty_fields(ty_ctx *c, struct fy_node *n, const char *prefix, const char *keys, int allow_random);

/* profile: {points: [[x, y], ...] | csv: FILE | dem: {...}, materials: [..] | NAME} */
rf_status ty_parse_profile(ty_ctx *c, struct fy_node *n);

/* dem.c: profile: {dem: {file: F, line: [[x, y], ...], step: h, origin: [x, y]}} */
rf_status ty_dem_profile(ty_ctx *c, struct fy_node *n);

/* Validate the finished spec (and the ranges of the random inputs); the
 * message gets the file and line of the field it names. */
rf_status ty_validate(ty_ctx *c);

#endif
