/* traj_yaml.c - the trajectory file (docs/trajectories.md sec. 2): YAML read
 * with the core's located accessors (core/yaml.h), so a
 * bad value is reported as "file:line: field = value: reason".  Numbers that
 * may be random are read by traj_yaml_value.c; the profile by
 * traj_yaml_profile.c.  After parsing, the spec is validated and a failing
 * field is located through the lines recorded while reading. */
#include "trajectory/traj_yaml_internal.h"
#include "rockfuzz/terrain.h"
#include "core/textfile.h"
#include "core/hash.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_TRAJ_BYTES (16u << 20)

static rf_status parse_materials(ty_ctx *c, struct fy_node *n)
{
    rf_status st = yr_mapping(&c->sp, n, "materials");
    if (st != RF_OK)
        return st;
    int cnt = fy_node_mapping_item_count(n);
    if (cnt < 1 || cnt > 1000)
        return yr_fail(&c->sp, n, "materials", "expected 1 to 1000 materials");
    c->spec->materials = calloc((size_t)cnt, sizeof *c->spec->materials);
    if (!c->spec->materials)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    for (;;) {
        if ((st = yr_next(&c->sp, &it, "materials", &key, &k, &v)) != RF_OK || !key)
            return st;
        if (!rf_traj_name_valid(key))
            return yr_fail(&c->sp, k, "materials", "%s is not a name: %s", key, RF_TRAJ_NAME_RULE);
        rf_traj_material *m = &c->spec->materials[c->spec->n_materials++];
        char mp[300];
        yr_pathf(mp, sizeof mp, "materials.%s", key);
        ty_remember(c, mp, k); /* locates a message about the material as a whole */
        if (!(m->name = rf_strdup(key)))
            return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
        ty_row_defaults(RF_TRAJ_OWNER_MATERIAL, m);
        char p[300];
        yr_pathf(p, sizeof p, "materials.%s", key);
        int whole; /* NAME: PRESET (else a mapping, maybe with preset: and overrides) */
        if ((st = ty_material_preset(c, v, p, m, &whole)) != RF_OK)
            return st;
        if (whole)
            continue;
        if ((st = ty_fields(c, v, p, "impact preset")) != RF_OK || (st = traj_impact_yaml(c, v, p, m)) != RF_OK)
            return st;
        m->impact.rolling_given = fy_node_mapping_lookup_by_string(v, "rolling_resistance", FY_NT) != NULL;
        if (isnan(m->R_n) || isnan(m->R_t))
            return yr_fail(&c->sp, v, p, "R_n and R_t are required (or a preset: rockfuzz presets)");
    }
}

/* block: {shape: point | sphere | ellipsoid | box | polyhedron | eota_cube |
 * eota_wheel, ...}: the rows here (ty_fields), a rigid block's own keys in
 * block_traj_yaml.c. */
static rf_status parse_block(ty_ctx *c, struct fy_node *n)
{
    rf_status st = yr_mapping(&c->sp, n, "block");
    if (st != RF_OK)
        return st;
    struct fy_node *shape = fy_node_mapping_lookup_by_string(n, "shape", FY_NT);
    rf_traj_spec *s = c->spec;
    if (shape) {
        const char *str;
        size_t len;
        if ((st = yr_string(&c->sp, shape, "block.shape", &str, &len)) != RF_OK)
            return st;
        if (len == 6 && !strncmp(str, "sphere", 6))
            s->sphere = 1;
        else if ((s->block_kind = traj_block_kind_of(str, len)) != RF_TRAJ_BLOCK_NONE) {
            s->block_q0[0] = 1, s->block_q0[1] = s->block_q0[2] = s->block_q0[3] = 0;
            ty_remember(c, "block.shape", shape);
        } else if (!(len == 5 && !strncmp(str, "point", 5)))
            return yr_fail(&c->sp, shape, "block.shape",
                           "expected point, sphere, ellipsoid, box, polyhedron, eota_cube or eota_wheel");
    }
    const char *extra = s->block_kind ? "shape axes edges points points_file axis_ratios orientation spin" : "shape";
    if ((st = ty_fields(c, n, "block", extra)) != RF_OK)
        return st;
    if (s->block_kind)
        return ty_parse_block_shape(c, n);
    if (!s->sphere && isnan(s->mass))
        return yr_fail(&c->sp, n, "block", "a point block needs mass [kg]");
    if (s->sphere && (isnan(s->radius) || isnan(s->density)))
        return yr_fail(&c->sp, n, "block", "a sphere needs radius [m] and density [kg/m^3]");
    return RF_OK;
}

/* A list of numbers under `path`: at most `max`, finite, and increasing if `increasing`. */
static rf_status number_list(ty_ctx *c, struct fy_node *v, const char *path, size_t max, int increasing,
                             double *out, size_t *count)
{
    rf_status st = yr_numbers(&c->sp, v, path, 1, max, out, count);
    for (size_t k = 0; st == RF_OK && k < *count; k++) {
        if (!isfinite(out[k]))
            return yr_fail(&c->sp, v, path, "every value must be finite");
        if (increasing && k && !(out[k] > out[k - 1]))
            return yr_fail(&c->sp, v, path, "the values must increase");
    }
    return st;
}

/* collectors[i].energy_thresholds [J] / height_thresholds [m]: read here, not by ty_fields. */
static rf_status parse_thresholds(ty_ctx *c, struct fy_node *e, const char *p, rf_traj_collector *col)
{
    const char *keys[2] = {"energy_thresholds", "height_thresholds"};
    double *dst[2] = {col->energy_thresholds, col->height_thresholds};
    size_t *n[2] = {&col->n_energy_thresholds, &col->n_height_thresholds};
    for (int k = 0; k < 2; k++) {
        struct fy_node *v = fy_node_mapping_lookup_by_string(e, keys[k], FY_NT);
        char path[400];
        yr_pathf(path, sizeof path, "%s.%s", p, keys[k]);
        rf_status st = v ? number_list(c, v, path, RF_TRAJ_MAX_THRESHOLDS - 1, 1, dst[k], n[k]) : RF_OK;
        if (st != RF_OK)
            return st;
        if (*n[k] && !(dst[k][0] >= 0))
            return yr_fail(&c->sp, v, path, "thresholds must be >= 0");
    }
    return RF_OK;
}

/* outputs: {percentiles: [..] in (0, 100), runout_thresholds: [..] m, runout_bins: N} */
static rf_status parse_outputs(ty_ctx *c, struct fy_node *n)
{
    rf_traj_outputs *o = &c->spec->outputs;
    rf_status st = yr_mapping(&c->sp, n, "outputs");
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    long long bins;
    while (st == RF_OK) {
        if ((st = yr_next(&c->sp, &it, "outputs", &key, &k, &v)) != RF_OK || !key)
            return st;
        if (!strcmp(key, "percentiles")) {
            st = number_list(c, v, "outputs.percentiles", RF_TRAJ_MAX_PERCENTILES, 1, o->percentiles,
                             &o->n_percentiles);
            if (st == RF_OK && !(o->percentiles[0] > 0 && o->percentiles[o->n_percentiles - 1] < 100))
                st = yr_fail(&c->sp, v, "outputs.percentiles", "percentiles lie in (0, 100); max is always given");
        } else if (!strcmp(key, "runout_thresholds")) {
            st = number_list(c, v, "outputs.runout_thresholds", RF_TRAJ_MAX_THRESHOLDS, 1, o->runout_thresholds,
                             &o->n_runout_thresholds);
        } else if (!strcmp(key, "runout_bins")) {
            if ((st = yr_integer(&c->sp, v, "outputs.runout_bins", 1, RF_TRAJ_MAX_BINS, &bins)) == RF_OK)
                o->runout_bins = (size_t)bins;
        } else if (!strcmp(key, "vtk")) { /* a rigid block's hull along its recorded paths (block_traj_vtk.c) */
            st = yr_bool(&c->sp, v, "outputs.vtk", &o->vtk);
        } else if (!strcmp(key, "max_paths") && c->spec->terrain) {
            if ((st = yr_integer(&c->sp, v, "outputs.max_paths", 0, 1000000, &bins)) == RF_OK)
                c->spec->terrain->max_paths = (size_t)bins;
        } else {
            char p[300];
            yr_pathf(p, sizeof p, "outputs.%s", key);
            st = yr_fail(&c->sp, k, p, "unknown key; outputs takes percentiles, runout_thresholds, runout_bins, vtk%s",
                         c->spec->terrain ? ", max_paths" : "");
        }
    }
    return st;
}

/* On terrain a barrier's line (barriers[i].line); on a profile its x. */
static rf_status collector_place(ty_ctx *c, struct fy_node *e, const char *what, const rf_traj_collector *col)
{
    struct fy_node *line = fy_node_mapping_lookup_by_string(e, "line", FY_NT);
    char lp[400];
    yr_pathf(lp, sizeof lp, "%s.%s", what, col->name);
    if (!c->spec->terrain)
        return isnan(col->x) ? yr_fail(&c->sp, e, lp, "a collector needs x [m]") : RF_OK;
    if (!line)
        return yr_fail(&c->sp, e, lp, "a barrier needs line: [[x, y], ...] (its trace on the map [m])");
    yr_pathf(lp, sizeof lp, "barriers.%s.line", col->name);
    return ty_barrier_line(c, line, lp);
}

/* collectors: (or barriers: on terrain) [{name, x | line, capacity, height, thresholds}] */
static rf_status parse_collectors(ty_ctx *c, const char *what, struct fy_node *n)
{
    size_t cnt;
    if (c->spec->collectors)
        return yr_fail(&c->sp, n, what, "barriers and collectors are the same list: give one of them");
    rf_status st = yr_sequence(&c->sp, n, what, 0, 1000, &cnt);
    if (st != RF_OK)
        return st;
    c->spec->collectors = calloc(cnt ? cnt : 1, sizeof *c->spec->collectors);
    if (!c->spec->collectors)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < cnt; i++) {
        struct fy_node *e = fy_node_sequence_get_by_index(n, (int)i);
        char p[300];
        yr_pathf(p, sizeof p, "%s[%zu]", what, i);
        if ((st = yr_mapping(&c->sp, e, p)) != RF_OK)
            return st;
        struct fy_node *nm = fy_node_mapping_lookup_by_string(e, "name", FY_NT);
        rf_traj_collector *col = &c->spec->collectors[c->spec->n_collectors++];
        if (!nm)
            return yr_fail(&c->sp, e, p, "a collector needs a name");
        if ((st = yr_string_dup(&c->sp, nm, p, &col->name)) != RF_OK)
            return st;
        if (!rf_traj_name_valid(col->name)) {
            yr_pathf(p, sizeof p, "%s[%zu].name", what, i);
            return yr_fail(&c->sp, nm, p, "%s", RF_TRAJ_NAME_RULE);
        }
        for (size_t j = 0; j < i; j++)
            if (!strcmp(c->spec->collectors[j].name, col->name))
                return yr_fail(&c->sp, nm, p, "a second collector with this name");
        ty_row_defaults(RF_TRAJ_OWNER_COLLECTOR, col);
        yr_pathf(p, sizeof p, "collectors.%s", col->name);
        const char *extra = c->spec->terrain ? "name line energy_thresholds height_thresholds"
                                             : "name energy_thresholds height_thresholds";
        if ((st = ty_fields(c, e, p, extra)) != RF_OK || (st = parse_thresholds(c, e, p, col)) != RF_OK ||
            (st = collector_place(c, e, what, col)) != RF_OK)
            return st;
    }
    return RF_OK;
}

static rf_status parse_top_scalar(ty_ctx *c, const char *key, struct fy_node *k, struct fy_node *v)
{
    rf_traj_spec *s = c->spec;
    if (!strcmp(key, "name")) {
        free(s->name);
        s->name = NULL;
        return yr_string_dup(&c->sp, v, "name", &s->name);
    }
    if (!strcmp(key, "description"))
        return RF_OK;
    if (!strcmp(key, "gravity"))
        return ty_row_value(c, v, "gravity");
    const rf_traj_setting *g = strchr(key, '.') ? NULL : rf_traj_setting_named(key); /* samples, seed, ... */
    if (g)
        return ty_setting(c, v, g);
    if (c->spec->terrain)
        return yr_fail(&c->sp, k, key, "unknown key; a terrain file takes name, description, gravity, terrain, "
                                       "materials, block, release, bounce, stop, barriers (or collectors), rasters, "
                                       "outputs, samples, seed, sampling, record");
    return yr_fail(&c->sp, k, key, "unknown key; a trajectory file takes name, description, gravity, profile, "
                                   "materials, block, release, bounce, stop, collectors, outputs, samples, seed, "
                                   "sampling, record (or terrain: a terrain file)");
}

static rf_status parse_top(ty_ctx *c, const char *key, struct fy_node *k, struct fy_node *v)
{
    if (!strcmp(key, "materials"))
        return parse_materials(c, v);
    if (!strcmp(key, "block"))
        return parse_block(c, v);
    if (!strcmp(key, "release"))
        return c->spec->terrain ? ty_parse_terrain_release(c, v) : ty_parse_release(c, v);
    if (!strcmp(key, "stop"))
        return ty_fields(c, v, "stop", "");
    if (!strcmp(key, "collectors") || (c->spec->terrain && !strcmp(key, "barriers")))
        return parse_collectors(c, key, v);
    if (c->spec->terrain && !strcmp(key, "rasters"))
        return ty_parse_rasters(c, v);
    if (!strcmp(key, "terrain")) {
        c->terrain = v;
        return RF_OK; /* after the materials: it names them */
    }
    if (!strcmp(key, "outputs"))
        return parse_outputs(c, v);
    if (!strcmp(key, "bounce"))
        return ty_fields(c, v, "bounce", "impact"); /* law and impact.*: settings */
    if (!strcmp(key, "profile")) {
        c->profile = v;
        return RF_OK; /* after the materials: it names them */
    }
    return parse_top_scalar(c, key, k, v);
}

static void spec_defaults(rf_traj_spec *s)
{
    memset(s, 0, sizeof *s);
    ty_row_defaults(RF_TRAJ_OWNER_SPEC, s); /* gravity, block, release, bounce and stop numbers */
    traj_settings_default(s);               /* samples, seed, stop.max_steps, bounce.law, bounce.impact */
    s->outputs.n_percentiles = 3;
    s->outputs.percentiles[0] = 50, s->outputs.percentiles[1] = 95, s->outputs.percentiles[2] = 99;
    s->outputs.runout_bins = 20;
}

/* A profile file or a terrain file: exactly one of profile: and terrain:. */
static rf_status file_kind(ty_ctx *c, struct fy_node *root)
{
    struct fy_node *profile = fy_node_mapping_lookup_by_string(root, "profile", FY_NT);
    struct fy_node *terrain = fy_node_mapping_lookup_by_string(root, "terrain", FY_NT);
    if (profile && terrain)
        return yr_fail(&c->sp, terrain, "terrain", "a file has a profile (2D) or a terrain (3D on a DEM): not both");
    if (!profile && !terrain)
        return rf_fail(c->sp.err, RF_EINVAL, "%s:1: profile: missing (a 2D profile; or terrain: a DEM)",
                       c->sp.file);
    return terrain ? ty_terrain_begin(c) : RF_OK;
}

/* outputs.vtk draws a rigid block's hull (block_traj_vtk.c): a point or a sphere of the sphere engines
 * (no orientation) is refused, instead of writing nothing. */
static rf_status vtk_needs_block(ty_ctx *c, struct fy_node *root)
{
    struct fy_node *o = fy_node_mapping_lookup_by_string(root, "outputs", FY_NT);
    struct fy_node *v = o && fy_node_is_mapping(o) ? fy_node_mapping_lookup_by_string(o, "vtk", FY_NT) : NULL;
    if (!v || !c->spec->outputs.vtk || c->spec->block_kind)
        return RF_OK;
    return yr_fail(&c->sp, v, "outputs.vtk", "ParaView frames draw a rigid block's hull; a %s has none (the "
                   "sphere engine carries no orientation): set block.shape to box, ellipsoid (a rigid sphere: "
                   "three equal semi-axes), polyhedron, eota_cube or eota_wheel, or drop outputs.vtk",
                   c->spec->sphere ? "sphere" : "point block");
}

static rf_status parse_document(ty_ctx *c, struct fy_node *root)
{
    rf_status st = yr_mapping(&c->sp, root, "");
    if (st != RF_OK)
        return st;
    yr_iter it = {root, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v, *materials = fy_node_mapping_lookup_by_string(root, "materials", FY_NT);
    if (!materials)
        return rf_fail(c->sp.err, RF_EINVAL, "%s:1: materials: missing (name: {R_n, R_t, ...})", c->sp.file);
    if ((st = file_kind(c, root)) != RF_OK)
        return st;
    for (;;) {
        if ((st = yr_next(&c->sp, &it, "", &key, &k, &v)) != RF_OK)
            return st;
        if (!key)
            break;
        if ((st = parse_top(c, key, k, v)) != RF_OK)
            return st;
    }
    const char *need[] = {c->spec->terrain ? "terrain" : "profile", "block", "release"};
    for (int i = 0; i < 3; i++)
        if (!fy_node_mapping_lookup_by_string(root, need[i], FY_NT))
            return rf_fail(c->sp.err, RF_EINVAL, "%s:1: %s: missing", c->sp.file, need[i]);
    if ((st = vtk_needs_block(c, root)) != RF_OK)
        return st;
    if (c->spec->terrain) {
        if ((st = ty_parse_terrain(c, c->terrain)) != RF_OK)
            return st;
        return ty_terrain_end(c, root);
    }
    if (c->spec->release_kind == RF_TRAJ_RELEASE_POINT && (isnan(c->spec->x0) || isnan(c->spec->y0)))
        return yr_fail(&c->sp, fy_node_mapping_lookup_by_string(root, "release", FY_NT), "release",
                       "x and y are required (or a line or zone)");
    if ((st = ty_parse_profile(c, c->profile)) == RF_OK)
        ty_release_nominal(c->spec);
    return st;
}

/* record left out: min(samples, the row's default). */
static void record_default(ty_ctx *c)
{
    const rf_traj_setting *g = rf_traj_setting_named("record");
    size_t k = (size_t)(g - rf_traj_settings), cap = (size_t)g->count_def;
    if (!c->setting_given[k])
        c->spec->record = c->spec->samples < cap ? c->spec->samples : cap;
}

static rf_status load(const char *name, const char *buf, size_t len, rf_traj_spec *s, rf_error *err)
{
    spec_defaults(s);
    ty_ctx c;
    memset(&c, 0, sizeof c);
    c.spec = s;
    char *dir = rf_strdup(name);
    char *slash = dir ? strrchr(dir, '/') : NULL;
    if (slash)
        *slash = '\0';
    c.sp = (yr_ctx){name, slash ? dir : ".", err, NULL};
    s->file = rf_strdup(name);
    s->text_hash = rf_fnv1a(RF_FNV1A_OFFSET, buf, len);
    yr_doc d = {0};
    rf_status st = yr_doc_load(&d, name, buf, len, "trajectory file", err);
    if (st == RF_OK)
        st = parse_document(&c, fy_document_root(d.doc));
    if (st == RF_OK)
        record_default(&c);
    if (st == RF_OK)
        st = ty_validate(&c);
    yr_doc_free(&d);
    ty_ctx_free(&c);
    free(dir);
    if (st != RF_OK)
        rf_traj_spec_free(s);
    return st;
}

rf_status rf_traj_load_buffer(const char *name, const char *buf, size_t len, rf_traj_spec *s, rf_error *err)
{
    return load(name ? name : "<buffer>", buf ? buf : "", buf ? len : 0, s, err);
}

rf_status rf_traj_load(const char *path, rf_traj_spec *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    char *buf = NULL;
    size_t len = 0;
    rf_status st = rf_read_text_file(path, "trajectory file", MAX_TRAJ_BYTES, &buf, &len, err);
    if (st == RF_OK)
        st = load(path, buf, len, s, err);
    free(buf);
    return st;
}
