/* traj_yaml_terrain.c - what a terrain file (`terrain:` instead of
 * `profile:`, docs/terrain-file.md) adds to the trajectory file: the terrain
 * (DEM, material classes or the one material, roughness raster), the release
 * on the map (points, lines, polygons inline or from a vector file, or a
 * release raster; height, velocity as a vector or speed, azimuth, dip; spin
 * vector), the barrier lines, and the hazard rasters.  The numbers that are
 * inputs (release.height, vx, vy, vz, speed, azimuth, dip) go through the
 * rows of the input tables, so they may be random and bound; files are named
 * relative to the trajectory file's folder. */
#include "trajectory/traj_yaml_internal.h"
#include "trajectory/terrain_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_VERTICES 10000000

static struct fy_node *key_node(struct fy_node *n, const char *key)
{
    return fy_node_mapping_lookup_by_string(n, key, FY_NT);
}

/* The file named by scalar n, relative to the trajectory file's folder. */
static rf_status file_path(ty_ctx *c, struct fy_node *n, const char *path, char **out)
{
    char *name = NULL;
    rf_status st = yr_string_dup(&c->sp, n, path, &name);
    if (st != RF_OK)
        return st;
    if (!name[0]) {
        free(name);
        return yr_fail(&c->sp, n, path, "expected a file name");
    }
    size_t len = strlen(c->sp.dir) + strlen(name) + 2;
    *out = malloc(len);
    if (*out && (name[0] == '/' || !strcmp(c->sp.dir, ".")))
        snprintf(*out, len, "%s", name);
    else if (*out)
        snprintf(*out, len, "%s/%s", c->sp.dir, name);
    free(name);
    ty_remember(c, path, n);
    return *out ? RF_OK : rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
}

static rf_status band_of(ty_ctx *c, struct fy_node *n, const char *path, int *band)
{
    long long b = 1;
    rf_status st = n ? yr_integer(&c->sp, n, path, 1, 100000, &b) : RF_OK;
    *band = (int)b;
    return st;
}

static size_t material_named(const rf_traj_spec *s, const char *name, size_t len)
{
    for (size_t m = 0; m < s->n_materials; m++)
        if (strlen(s->materials[m].name) == len && !strncmp(s->materials[m].name, name, len))
            return m;
    return TRAJ_NONE;
}

static rf_status material_of(ty_ctx *c, struct fy_node *n, const char *path, size_t *m)
{
    const char *str;
    size_t len;
    rf_status st = yr_string(&c->sp, n, path, &str, &len);
    if (st == RF_OK && (*m = material_named(c->spec, str, len)) == TRAJ_NONE)
        return yr_fail(&c->sp, n, path, "no such material (define it under materials:)");
    return st;
}

/* classes: {VALUE: NAME, ...}: integer raster values to materials. */
static rf_status parse_classes(ty_ctx *c, struct fy_node *n, rf_terrain_def *d)
{
    const char *path = "terrain.materials.classes";
    rf_status st = yr_mapping(&c->sp, n, path);
    int cnt = st == RF_OK ? fy_node_mapping_item_count(n) : 0;
    if (st == RF_OK && (cnt < 1 || cnt > 65535))
        return yr_fail(&c->sp, n, path, "expected 1 to 65535 classes {value: material}");
    d->class_value = calloc((size_t)cnt + 1, sizeof *d->class_value);
    d->class_material = calloc((size_t)cnt + 1, sizeof *d->class_material);
    if (st == RF_OK && (!d->class_value || !d->class_material))
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    while (st == RF_OK) {
        if ((st = yr_next(&c->sp, &it, path, &key, &k, &v)) != RF_OK || !key)
            return st;
        char p[300], *end;
        yr_pathf(p, sizeof p, "%s.%s", path, key);
        errno = 0;
        long val = strtol(key, &end, 10);
        if (errno || end == key || *end)
            return yr_fail(&c->sp, k, p, "a class is an integer value of the class raster");
        for (size_t i = 0; i < d->n_classes; i++)
            if (d->class_value[i] == val)
                return yr_fail(&c->sp, k, p, "the class %ld is given twice", val);
        if ((st = material_of(c, v, p, &d->class_material[d->n_classes])) == RF_OK)
            d->class_value[d->n_classes++] = val;
    }
    return st;
}

/* materials: {raster: F, band: N, classes: {...}} */
static rf_status parse_class_raster(ty_ctx *c, struct fy_node *n, rf_terrain_def *d)
{
    const char *path = "terrain.materials";
    rf_status st = yr_mapping(&c->sp, n, path);
    struct fy_node *raster = st == RF_OK ? key_node(n, "raster") : NULL, *classes = raster ? key_node(n, "classes")
                                                                                             : NULL;
    if (st == RF_OK && (!raster || !classes))
        return yr_fail(&c->sp, n, path, "expected {raster: FILE, band: N, classes: {value: material, ...}}");
    if (st == RF_OK && fy_node_mapping_item_count(n) != 2 + !!key_node(n, "band"))
        return yr_fail(&c->sp, n, path, "unknown key; terrain.materials takes raster, band, classes");
    if (st == RF_OK)
        st = file_path(c, raster, "terrain.materials.raster", &d->classes);
    if (st == RF_OK)
        st = band_of(c, key_node(n, "band"), "terrain.materials.band", &d->classes_band);
    return st == RF_OK ? parse_classes(c, classes, d) : st;
}

/* roughness: {raster: F, band: N} */
static rf_status parse_roughness(ty_ctx *c, struct fy_node *n, rf_terrain_def *d)
{
    const char *path = "terrain.roughness";
    rf_status st = yr_mapping(&c->sp, n, path);
    struct fy_node *raster = st == RF_OK ? key_node(n, "raster") : NULL;
    if (st == RF_OK && (!raster || fy_node_mapping_item_count(n) != 1 + !!key_node(n, "band")))
        return yr_fail(&c->sp, n, path, "expected {raster: FILE, band: N} (roughness SD per cell [deg])");
    if (st == RF_OK)
        st = file_path(c, raster, "terrain.roughness.raster", &d->roughness);
    return st == RF_OK ? band_of(c, key_node(n, "band"), "terrain.roughness.band", &d->roughness_band) : st;
}

/* window: [xmin, ymin, xmax, ymax] in map metres: the part of the DEM read. */
static rf_status window_of(ty_ctx *c, struct fy_node *n, const char *path, rf_terrain_def *d)
{
    rf_status st = yr_numbers(&c->sp, n, path, 4, 4, d->window, NULL);
    if (st != RF_OK)
        return st;
    for (int k = 0; k < 4; k++)
        if (!(fabs(d->window[k]) <= RF_TRAJ_MAX_COORD))
            return yr_fail(&c->sp, n, path, "%g is not a map coordinate within +-%g m", d->window[k],
                           RF_TRAJ_MAX_COORD);
    if (!(d->window[0] < d->window[2] && d->window[1] < d->window[3]))
        return yr_fail(&c->sp, n, path, "expected [xmin, ymin, xmax, ymax] [m] with xmin < xmax and ymin < ymax");
    d->has_window = 1;
    return RF_OK;
}

static rf_status terrain_key(ty_ctx *c, const char *key, struct fy_node *k, struct fy_node *v, rf_terrain_def *d)
{
    char p[300];
    yr_pathf(p, sizeof p, "terrain.%s", key);
    if (!strcmp(key, "dem"))
        return file_path(c, v, p, &d->dem);
    if (!strcmp(key, "band"))
        return band_of(c, v, p, &d->band);
    if (!strcmp(key, "materials"))
        return parse_class_raster(c, v, d);
    if (!strcmp(key, "material"))
        return material_of(c, v, p, &d->material);
    if (!strcmp(key, "roughness"))
        return parse_roughness(c, v, d);
    if (!strcmp(key, "window"))
        return window_of(c, v, p, d);
    return yr_fail(&c->sp, k, p, "unknown key; terrain takes dem, band, window, materials | material, roughness");
}

rf_status ty_parse_terrain(ty_ctx *c, struct fy_node *n)
{
    rf_terrain_def *d = c->spec->terrain;
    rf_status st = yr_mapping(&c->sp, n, "terrain");
    if (st != RF_OK)
        return st;
    ty_remember(c, "terrain", n);
    if (key_node(n, "materials") && key_node(n, "material"))
        return yr_fail(&c->sp, n, "terrain", "give materials (a class raster) or material (one for all), not both");
    if (!key_node(n, "dem"))
        return yr_fail(&c->sp, n, "terrain", "dem: FILE is required (the DEM)");
    yr_iter it = {n, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *v;
    for (;;) {
        if ((st = yr_next(&c->sp, &it, "terrain", &key, &k, &v)) != RF_OK || !key)
            break;
        if ((st = terrain_key(c, key, k, v, d)) != RF_OK)
            return st;
    }
    if (st == RF_OK && !key_node(n, "materials") && !key_node(n, "material") && c->spec->n_materials != 1)
        return yr_fail(&c->sp, n, "terrain", "name the material of every cell (material: NAME) or a class raster "
                                             "(materials: {raster: FILE, classes: {value: NAME}})");
    return st;
}

/* ---- release ---- */

/* Append vertex (x, y) to the release features. */
static rf_status push_vertex(ty_ctx *c, rf_terrain_release *r, size_t *cap, double x, double y)
{
    size_t n = r->start[r->n_features];
    if (n == *cap) {
        size_t nc = *cap ? 2 * *cap : 64;
        double *nx = realloc(r->x, nc * sizeof *nx), *ny = nx ? realloc(r->y, nc * sizeof *ny) : NULL;
        if (nx)
            r->x = nx;
        if (!ny)
            return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
        r->y = ny, *cap = nc;
    }
    r->x[n] = x, r->y[n] = y;
    r->start[r->n_features]++;
    return RF_OK;
}

static rf_status read_xy(ty_ctx *c, struct fy_node *e, const char *p, double xy[2])
{
    rf_status st = yr_numbers(&c->sp, e, p, 2, 2, xy, NULL);
    if (st == RF_OK && !(fabs(xy[0]) <= RF_TRAJ_MAX_COORD && fabs(xy[1]) <= RF_TRAJ_MAX_COORD))
        return yr_fail(&c->sp, e, p, "coordinates must be finite and within +-1e+07 m");
    return st;
}

/* One feature: a point [x, y] or a list of them (min vertices; a polygon's
 * repeated closing vertex dropped). */
static rf_status read_feature(ty_ctx *c, struct fy_node *n, const char *p, rf_terrain_release *r, size_t *cap)
{
    double xy[2];
    rf_status st;
    if (r->kind == RF_TERRAIN_POINTS) {
        if ((st = read_xy(c, n, p, xy)) == RF_OK)
            st = push_vertex(c, r, cap, xy[0], xy[1]);
        return st;
    }
    size_t min = r->kind == RF_TERRAIN_LINES ? 2 : 3, cnt;
    if ((st = yr_sequence(&c->sp, n, p, min, MAX_VERTICES, &cnt)) != RF_OK)
        return st;
    for (size_t i = 0; i < cnt && st == RF_OK; i++) {
        char q[320];
        yr_pathf(q, sizeof q, "%s[%zu]", p, i);
        if ((st = read_xy(c, fy_node_sequence_get_by_index(n, (int)i), q, xy)) == RF_OK)
            st = push_vertex(c, r, cap, xy[0], xy[1]);
    }
    size_t a = r->start[r->n_features - 1], e = r->start[r->n_features] - 1;
    if (st == RF_OK && r->kind == RF_TERRAIN_POLYGONS && r->x[e] == r->x[a] && r->y[e] == r->y[a])
        r->start[r->n_features]--;
    if (st == RF_OK && r->start[r->n_features] - a < min)
        return yr_fail(&c->sp, n, p, "a %s needs at least %zu distinct vertices", r->kind == RF_TERRAIN_LINES
                       ? "line" : "polygon", min);
    return st;
}

/* points | lines | polygons: the features listed inline. */
static rf_status inline_features(ty_ctx *c, struct fy_node *n, const char *key, rf_terrain_release *r)
{
    char path[64];
    size_t cnt, cap = 0;
    yr_pathf(path, sizeof path, "release.%s", key);
    rf_status st = yr_sequence(&c->sp, n, path, 1, MAX_VERTICES, &cnt);
    if (st != RF_OK)
        return st;
    ty_remember(c, path, n);
    r->kind = key[0] == 'p' && key[1] == 'o' && key[2] == 'i' ? RF_TERRAIN_POINTS
              : key[0] == 'l' ? RF_TERRAIN_LINES : RF_TERRAIN_POLYGONS;
    r->start = calloc(cnt + 1, sizeof *r->start);
    r->weight = malloc(cnt * sizeof *r->weight);
    if (!r->start || !r->weight)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    for (size_t f = 0; f < cnt && st == RF_OK; f++) {
        char p[96];
        struct fy_node *e = fy_node_sequence_get_by_index(n, (int)f);
        yr_pathf(p, sizeof p, "%s[%zu]", path, f);
        ty_remember(c, p, e);
        r->n_features = f + 1;
        r->start[f + 1] = r->start[f];
        r->weight[f] = 1;
        st = read_feature(c, e, p, r, &cap);
    }
    return st;
}

/* blocks: [n per feature]: the weights of inline features. */
static rf_status parse_blocks(ty_ctx *c, struct fy_node *n, rf_terrain_release *r)
{
    size_t cnt;
    rf_status st = yr_sequence(&c->sp, n, "release.blocks", r->n_features, r->n_features, &cnt);
    if (st != RF_OK)
        return yr_fail(&c->sp, n, "release.blocks", "expected one count per release feature (%zu)", r->n_features);
    for (size_t f = 0; f < cnt && st == RF_OK; f++) {
        char p[64];
        struct fy_node *e = fy_node_sequence_get_by_index(n, (int)f);
        yr_pathf(p, sizeof p, "release.blocks[%zu]", f);
        if ((st = yr_number(&c->sp, e, p, &r->weight[f])) == RF_OK && !(r->weight[f] >= 0 && isfinite(r->weight[f])))
            return yr_fail(&c->sp, e, p, "a count of blocks is finite and >= 0");
    }
    return st;
}

/* file: {path: F, layer: L, count: FIELD, per_area: bool} (terrain_io.c reads it). */
static rf_status release_file(ty_ctx *c, struct fy_node *n, rf_terrain_release *r)
{
    const char *path = "release.file";
    rf_status st = yr_mapping(&c->sp, n, path);
    struct fy_node *fp = st == RF_OK ? key_node(n, "path") : NULL, *layer = fp ? key_node(n, "layer") : NULL;
    struct fy_node *count = fp ? key_node(n, "count") : NULL, *area = fp ? key_node(n, "per_area") : NULL;
    if (st == RF_OK && (!fp || fy_node_mapping_item_count(n) != 1 + !!layer + !!count + !!area))
        return yr_fail(&c->sp, n, path, "expected {path: FILE, layer: NAME, count: FIELD, per_area: true|false}");
    char *file = NULL, *lname = NULL, *cname = NULL;
    int per_area = 0;
    if (st == RF_OK)
        st = file_path(c, fp, "release.file.path", &file);
    if (st == RF_OK && layer)
        st = yr_string_dup(&c->sp, layer, "release.file.layer", &lname);
    if (st == RF_OK && count)
        st = yr_string_dup(&c->sp, count, "release.file.count", &cname);
    if (st == RF_OK && area && (st = yr_bool(&c->sp, area, "release.file.per_area", &per_area)) == RF_OK &&
        per_area && !count)
        st = yr_fail(&c->sp, area, "release.file.per_area", "per_area needs count: FIELD (blocks per m^2)");
    if (st == RF_OK && (st = terrain_read_release_vector(file, lname, cname, per_area, r, c->sp.err)) != RF_OK)
        st = yr_prefix(&c->sp, fp, "release.file.path");
    if (st == RF_OK && !r->file)
        r->file = file, file = NULL;
    free(file), free(lname), free(cname);
    return st;
}

/* raster: F | {path: F, band: N} (cells with a count; terrain_io.c reads it). */
static rf_status release_raster(ty_ctx *c, struct fy_node *n, rf_terrain_release *r)
{
    struct fy_node *fp = n, *band = NULL;
    int b = 1;
    rf_status st = RF_OK;
    if (fy_node_get_type(n) == FYNT_MAPPING) {
        fp = key_node(n, "path"), band = key_node(n, "band");
        if (!fp || fy_node_mapping_item_count(n) != 1 + !!band)
            return yr_fail(&c->sp, n, "release.raster", "expected FILE or {path: FILE, band: N}");
    }
    char *file = NULL;
    if ((st = file_path(c, fp, "release.raster", &file)) == RF_OK)
        st = band_of(c, band, "release.raster.band", &b);
    if (st == RF_OK && (st = terrain_read_release_raster(file, b, r, c->sp.err)) != RF_OK)
        st = yr_prefix(&c->sp, fp, "release.raster");
    if (st == RF_OK && !r->file)
        r->file = file, file = NULL;
    free(file);
    return st;
}

/* spin: [wx, wy, wz] [rad/s] (constant). */
static rf_status parse_spin(ty_ctx *c, struct fy_node *n)
{
    double *w = c->spec->omega0_xyz;
    rf_status st = yr_numbers(&c->sp, n, "release.spin", 3, 3, w, NULL);
    ty_remember(c, "release.spin", n);
    if (st == RF_OK && !(isfinite(w[0]) && isfinite(w[1]) && isfinite(w[2])))
        return yr_fail(&c->sp, n, "release.spin", "expected [wx, wy, wz] finite [rad/s]");
    return st;
}

/* velocity: [vx, vy, vz], each through its row (may be random). */
static rf_status parse_velocity(ty_ctx *c, struct fy_node *n)
{
    static const char *const rows[3] = {"release.vx", "release.vy", "release.vz"};
    size_t cnt;
    rf_status st = yr_sequence(&c->sp, n, "release.velocity", 3, 3, &cnt);
    for (size_t k = 0; k < 3 && st == RF_OK; k++)
        st = ty_row_value(c, fy_node_sequence_get_by_index(n, (int)k), rows[k]);
    return st;
}

/* The velocity is a vector (velocity or vx, vy, vz) or speed, azimuth, dip: one form. */
static rf_status velocity_form(ty_ctx *c, struct fy_node *n)
{
    int vec = !!key_node(n, "velocity"), parts = key_node(n, "vx") || key_node(n, "vy") || key_node(n, "vz");
    int by_speed = key_node(n, "speed") || key_node(n, "azimuth") || key_node(n, "dip");
    if (vec && parts)
        return yr_fail(&c->sp, n, "release", "the velocity is velocity: [vx, vy, vz] or vx, vy, vz: not both");
    if (by_speed && (vec || parts))
        return yr_fail(&c->sp, n, "release", "the velocity is a vector or speed, azimuth, dip: not both");
    if (key_node(n, "omega"))
        return yr_fail(&c->sp, key_node(n, "omega"), "release.omega", "on terrain the spin is a vector: spin: "
                       "[wx, wy, wz] [rad/s]");
    c->spec->release_by_speed = by_speed;
    return RF_OK;
}

static rf_status release_features(ty_ctx *c, struct fy_node *n, rf_terrain_release *r)
{
    static const char *const kinds[5] = {"points", "lines", "polygons", "file", "raster"};
    struct fy_node *which = NULL;
    const char *key = NULL;
    for (int k = 0; k < 5; k++) {
        struct fy_node *v = key_node(n, kinds[k]);
        if (v && which)
            return yr_fail(&c->sp, n, "release", "give one of points, lines, polygons, file, raster");
        if (v)
            which = v, key = kinds[k];
    }
    if (!which)
        return yr_fail(&c->sp, n, "release", "where blocks start: points, lines, polygons, file or raster");
    if (key_node(n, "blocks") && (key[0] == 'f' || key[0] == 'r'))
        return yr_fail(&c->sp, key_node(n, "blocks"), "release.blocks", "the counts of a file or raster come from "
                       "it (file: {count: FIELD})");
    rf_status st = key[0] == 'f' ? release_file(c, which, r)
                   : key[0] == 'r' ? release_raster(c, which, r) : inline_features(c, which, key, r);
    if (st == RF_OK && key_node(n, "blocks"))
        st = parse_blocks(c, key_node(n, "blocks"), r);
    return st;
}

rf_status ty_parse_terrain_release(ty_ctx *c, struct fy_node *n)
{
    rf_traj_spec *s = c->spec;
    rf_status st = yr_mapping(&c->sp, n, "release");
    if (st != RF_OK)
        return st;
    ty_remember(c, "release", n);
    s->release_kind = RF_TRAJ_RELEASE_MAP;
    if ((st = velocity_form(c, n)) != RF_OK || (st = release_features(c, n, &s->terrain->release)) != RF_OK)
        return st;
    if (key_node(n, "velocity") && (st = parse_velocity(c, key_node(n, "velocity"))) != RF_OK)
        return st;
    if (key_node(n, "spin") && (st = parse_spin(c, key_node(n, "spin"))) != RF_OK)
        return st;
    st = ty_fields(c, n, "release", "points lines polygons file raster blocks velocity spin");
    if (st == RF_OK && s->release_by_speed && isnan(s->speed0))
        return yr_fail(&c->sp, n, "release", "speed [m/s] is required with azimuth and dip");
    return st;
}

/* ---- barriers and rasters ---- */

rf_status ty_barrier_line(ty_ctx *c, struct fy_node *n, const char *path)
{
    rf_terrain_def *d = c->spec->terrain;
    size_t cnt, b = d->n_barriers, at = d->barrier_start ? d->barrier_start[b] : 0;
    rf_status st = yr_sequence(&c->sp, n, path, 2, MAX_VERTICES, &cnt);
    if (st != RF_OK)
        return st;
    ty_remember(c, path, n);
    size_t *ns = realloc(d->barrier_start, (b + 2) * sizeof *ns);
    if (ns)
        d->barrier_start = ns, ns[b] = at;
    double *nx = ns ? realloc(d->barrier_x, (at + cnt) * sizeof *nx) : NULL;
    if (nx)
        d->barrier_x = nx;
    double *ny = nx ? realloc(d->barrier_y, (at + cnt) * sizeof *ny) : NULL;
    if (!ny)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    d->barrier_y = ny;
    for (size_t i = 0; i < cnt; i++) {
        char p[400];
        double xy[2];
        yr_pathf(p, sizeof p, "%s[%zu]", path, i);
        if ((st = read_xy(c, fy_node_sequence_get_by_index(n, (int)i), p, xy)) != RF_OK)
            return st;
        d->barrier_x[at + i] = xy[0], d->barrier_y[at + i] = xy[1];
    }
    d->barrier_start[b + 1] = at + cnt;
    d->n_barriers = b + 1;
    return RF_OK;
}

static rf_status statistic(ty_ctx *c, struct fy_node *e, const char *p)
{
    static const struct {
        const char *name;
        unsigned bit;
        int p95;
    } names[] = {{"passages", RF_TERRAIN_PASSAGES, 0}, {"reach_probability", RF_TERRAIN_REACH_PROBABILITY, 0},
                 {"deposits", RF_TERRAIN_DEPOSITS, 0}, {"energy", RF_TERRAIN_ENERGY, 0},
                 {"height", RF_TERRAIN_HEIGHT, 0}, {"energy_p95", RF_TERRAIN_ENERGY, 1},
                 {"height_p95", RF_TERRAIN_HEIGHT, 1}, {"energy_max", RF_TERRAIN_ENERGY, 0},
                 {"height_max", RF_TERRAIN_HEIGHT, 0}};
    const char *str;
    size_t len;
    rf_status st = yr_string(&c->sp, e, p, &str, &len);
    for (size_t k = 0; st == RF_OK && k < sizeof names / sizeof names[0]; k++)
        if (strlen(names[k].name) == len && !strncmp(str, names[k].name, len)) {
            c->spec->terrain->statistics |= names[k].bit;
            c->terrain_p95 |= names[k].p95;
            return RF_OK;
        }
    return st != RF_OK ? st : yr_fail(&c->sp, e, p, "expected passages, reach_probability, deposits, energy, "
                                                    "height (or energy_p95, height_p95, energy_max, height_max)");
}

/* rasters: {cell: m, statistics: [...]} */
rf_status ty_parse_rasters(ty_ctx *c, struct fy_node *n)
{
    rf_terrain_def *d = c->spec->terrain;
    rf_status st = yr_mapping(&c->sp, n, "rasters");
    struct fy_node *cell = st == RF_OK ? key_node(n, "cell") : NULL, *stats = st == RF_OK ? key_node(n, "statistics")
                                                                                       : NULL;
    if (st == RF_OK && fy_node_mapping_item_count(n) != !!cell + !!stats)
        return yr_fail(&c->sp, n, "rasters", "unknown key; rasters takes cell, statistics");
    ty_remember(c, "rasters", n);
    if (st == RF_OK && cell) {
        ty_remember(c, "rasters.cell", cell);
        if ((st = yr_number(&c->sp, cell, "rasters.cell", &d->raster_cell)) == RF_OK &&
            !(d->raster_cell > 0 && d->raster_cell <= RF_TRAJ_MAX_COORD))
            return yr_fail(&c->sp, cell, "rasters.cell", "the output cell must be > 0 [m]");
    }
    size_t cnt = 0;
    if (st == RF_OK && stats && (st = yr_sequence(&c->sp, stats, "rasters.statistics", 1, 64, &cnt)) == RF_OK)
        d->statistics = 0;
    for (size_t k = 0; k < cnt && st == RF_OK; k++) {
        char p[64];
        yr_pathf(p, sizeof p, "rasters.statistics[%zu]", k);
        st = statistic(c, fy_node_sequence_get_by_index(stats, (int)k), p);
    }
    return st;
}

/* The defaults of a terrain spec's own part (before reading). */
rf_status ty_terrain_begin(ty_ctx *c)
{
    rf_terrain_def *d = calloc(1, sizeof *d);
    if (!d)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    d->band = d->classes_band = d->roughness_band = 1;
    d->max_paths = 200;
    d->statistics = RF_TERRAIN_PASSAGES | RF_TERRAIN_REACH_PROBABILITY | RF_TERRAIN_DEPOSITS | RF_TERRAIN_ENERGY |
                    RF_TERRAIN_HEIGHT;
    c->spec->terrain = d;
    c->spec->release_kind = RF_TRAJ_RELEASE_MAP;
    return RF_OK;
}

/* After reading: energy_p95 / height_p95 put 95 among the percentiles. */
rf_status ty_terrain_end(ty_ctx *c, struct fy_node *root)
{
    rf_traj_outputs *o = &c->spec->outputs;
    size_t k = 0;
    while (k < o->n_percentiles && o->percentiles[k] < 95)
        k++;
    if (!c->terrain_p95 || (k < o->n_percentiles && o->percentiles[k] == 95))
        return RF_OK;
    if (o->n_percentiles == RF_TRAJ_MAX_PERCENTILES)
        return yr_fail(&c->sp, key_node(root, "rasters"), "rasters.statistics", "p95 asked for, but "
                       "outputs.percentiles already holds %d levels", RF_TRAJ_MAX_PERCENTILES);
    memmove(o->percentiles + k + 1, o->percentiles + k, (o->n_percentiles - k) * sizeof *o->percentiles);
    o->percentiles[k] = 95;
    o->n_percentiles++;
    return RF_OK;
}
