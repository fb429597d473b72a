/* traj_bind.c - what a study may bind in a trajectory file, from the input
 * tables (traj_fields.c): the bindable paths of a spec, their list with
 * units for messages, the reason a path is refused with the nearest bindable
 * path (a typo), the key table of the docs and the hash of every value a run
 * reads (the model identity). */
#include "trajectory/traj_internal.h"
#include "rockfuzz/terrain.h"
#include "core/hash.h"
#include "trajectory/block_traj.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int is_random(const rf_traj_spec *s, const char *path)
{
    for (size_t r = 0; r < s->n_random; r++)
        if (!strcmp(s->random[r].path, path))
            return 1;
    return 0;
}

static int bindable_row(const rf_traj_spec *s, const char *path, const rf_traj_field *f)
{
    return !f || (f->bindable && traj_field_used(s, f) && !is_random(s, path));
}

typedef struct {
    const rf_traj_spec *s;
    char *buf;
    size_t size, len;
    const char *want;        /* suggestion: the path asked for */
    char near[300];
    size_t best;
} path_walk;

static void add_to_list(void *ctx, const char *path, const rf_traj_field *f)
{
    path_walk *w = ctx;
    if (!bindable_row(w->s, path, f) || w->len >= w->size)
        return;
    const char *unit = f ? f->unit : "";
    w->len += (size_t)snprintf(w->buf + w->len, w->size - w->len, "%s%s%s%s%s", w->len ? ", " : "", path,
                               unit[0] ? " [" : "", unit, unit[0] ? "]" : "");
}

void rf_traj_bindable_list(const rf_traj_spec *s, char *buf, size_t size)
{
    path_walk w = {s, buf, size, 0, NULL, "", 0};
    buf[0] = '\0';
    traj_each_path(s, add_to_list, &w);
    if (s->n_points && w.len < size)
        snprintf(buf + w.len, size - w.len, "%sprofile.points.I.x|y [m] (I < %zu)", w.len ? ", " : "", s->n_points);
}

static void nearest(void *ctx, const char *path, const rf_traj_field *f)
{
    path_walk *w = ctx;
    size_t d = rf_name_distance(w->want, path);
    if (bindable_row(w->s, path, f) && d < w->best)
        w->best = d, snprintf(w->near, sizeof w->near, "%s", path);
}

const char *traj_field_unused_reason(const rf_traj_field *f)
{
    switch (f->when) {
    case RF_TRAJ_WHEN_POINT: return "only a point block has it (a sphere's mass comes from radius and density)";
    case RF_TRAJ_WHEN_SPHERE: return "only a sphere has it";
    case RF_TRAJ_WHEN_BLOCK: return "only a rigid block (shape ellipsoid, box, polyhedron, eota_cube, eota_wheel) has it";
    case RF_TRAJ_WHEN_RIGID: return "a point block has a mass, no density";
    case RF_TRAJ_WHEN_VXVY: return "the release velocity is given by speed and angle";
    case RF_TRAJ_WHEN_SPEED: return "the release velocity is given by vx and vy";
    case RF_TRAJ_WHEN_AT_POINT: return "the release is drawn along a line or in a zone";
    case RF_TRAJ_WHEN_PROFILE: return "only a profile file has it (on terrain: see docs/terrain.md)";
    case RF_TRAJ_WHEN_PROFILE_SPEED: return "only a profile file released by speed has it (on terrain: azimuth, dip)";
    case RF_TRAJ_WHEN_TERRAIN: return "only a terrain file has it";
    case RF_TRAJ_WHEN_TERRAIN_VXVY: return "only a terrain file released by vx, vy, vz has it";
    case RF_TRAJ_WHEN_TERRAIN_SPEED: return "only a terrain file released by speed, azimuth and dip has it";
    case RF_TRAJ_WHEN_ALWAYS: break;
    }
    return "";
}

int rf_traj_path_bindable(const rf_traj_spec *s, const char *path, char *why, size_t size)
{
    rf_traj_spec *w = (rf_traj_spec *)s; /* looked up, not written */
    const rf_traj_field *f = rf_traj_field_at(w, path, NULL);
    if (f && !f->bindable)
        return snprintf(why, size, "%s cannot be bound", path), 0;
    if (f && !traj_field_used(s, f))
        return snprintf(why, size, "%s is not used by this file: %s", path, traj_field_unused_reason(f)), 0;
    if (is_random(s, path))
        return snprintf(why, size, "this input is random in the trajectory file; bind its distribution "
                        "(%s.lo/.hi or .mean/.sd)", path), 0;
    if (f || rf_traj_spec_field(w, path))
        return 1;
    path_walk pw = {s, NULL, 0, 0, path, "", 4}; /* at most three edits: a typo */
    traj_each_path(s, nearest, &pw);
    char list[2048];
    rf_traj_bindable_list(s, list, sizeof list);
    snprintf(why, size, "not a numeric input of the trajectory file; %s%s%sit takes: %s",
             pw.near[0] ? "did you mean '" : "", pw.near, pw.near[0] ? "'? " : "", list);
    return 0;
}

static const char *check_text(rf_traj_check c)
{
    static const char *const text[] = {"", "finite", "> 0", ">= 0", "[0, 1]", "[0, 90)", "[0, 45]", "[-180, 180]",
                                       "\\|y\\| <= 1e7"};
    return (unsigned)c < sizeof text / sizeof text[0] ? text[c] : "";
}

/* A setting's default and range as the key table writes them. */
static void setting_texts(const rf_traj_setting *g, char *def, size_t dsize, char *range, size_t rsize)
{
    size_t n = 0;
    const char *name;
    switch (g->kind) {
    case RF_TRAJ_SETTING_COUNT:
        snprintf(def, dsize, "%lld", g->count_def);
        snprintf(range, rsize, "integer in [%lld, %lld]", g->count_min, g->count_max);
        break;
    case RF_TRAJ_SETTING_NAME:
    case RF_TRAJ_SETTING_WORD:
        snprintf(def, dsize, "%s", g->def_name);
        range[0] = '\0';
        for (size_t i = 0; (name = g->names(i)) && n < rsize; i++)
            n += (size_t)snprintf(range + n, rsize - n, "%s%s", i ? ", " : "", name);
        break;
    case RF_TRAJ_SETTING_NUMBER:
        snprintf(def, dsize, "%g", g->def);
        if (isinf(g->hi))
            snprintf(range, rsize, "%s %g", g->lo_open ? ">" : ">=", g->lo);
        else
            snprintf(range, rsize, "%c%g, %g%c", g->lo_open ? '(' : '[', g->lo, g->hi, g->hi_open ? ')' : ']');
        break;
    case RF_TRAJ_SETTING_PAIR:
        snprintf(def, dsize, "[%g, %g]", g->def, g->def2);
        snprintf(range, rsize, "[lo, hi], %g < lo < hi", g->lo);
        break;
    case RF_TRAJ_SETTING_PATH:
        snprintf(def, dsize, "none");
        snprintf(range, rsize, "a file");
        break;
    }
    if (g->def_text)
        snprintf(def, dsize, "%s", g->def_text);
}

static void setting_markdown(FILE *f, const rf_traj_setting *g)
{
    char def[64], range[200];
    setting_texts(g, def, sizeof def, range, sizeof range);
    fprintf(f, "| `%s` | %s | %s | %s | no | no | %s |\n", g->key, g->unit[0] ? g->unit : "-", def, range, g->help);
}

void rf_traj_fields_markdown(FILE *f)
{
    fprintf(f, "| key | unit | default | range | random | bindable | meaning |\n|---|---|---|---|---|---|---|\n");
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        for (size_t k = 0; k < tb->n_rows; k++) {
            const rf_traj_field *r = &tb->rows[k];
            char def[32] = "required";
            if (!isnan(r->def))
                snprintf(def, sizeof def, "%g", r->def);
            fprintf(f, "| `%s%s` | %s | %s | %s | %s | %s | %s |\n", tb->prefix, r->key,
                    r->unit[0] ? r->unit : "-", def, check_text(r->check), r->random ? "yes" : "no",
                    r->bindable ? "yes" : "no", r->help);
        }
    }
    for (size_t k = 0; k < rf_traj_n_settings; k++)
        setting_markdown(f, &rf_traj_settings[k]);
}

static uint64_t hash_rows(uint64_t h, const rf_traj_field_table *tb, const void *base)
{
    for (size_t k = 0; k < tb->n_rows; k++)
        h = rf_fnv1a(h, (const char *)base + tb->rows[k].offset, sizeof(double));
    return h;
}

static uint64_t hash_str(uint64_t h, const char *s) { return rf_fnv1a(h, s ? s : "", s ? strlen(s) + 1 : 1); }

/* The bytes of every setting's value (a name as its index or text, a path as given). */
uint64_t traj_settings_hash(uint64_t h, const rf_traj_spec *s)
{
    for (size_t k = 0; k < rf_traj_n_settings; k++) {
        const rf_traj_setting *g = &rf_traj_settings[k];
        const char *at = (const char *)s + g->offset;
        h = rf_fnv1a(h, g->key, strlen(g->key) + 1);
        if (g->kind == RF_TRAJ_SETTING_PATH)
            h = hash_str(h, *(char *const *)at);
        else if (g->kind == RF_TRAJ_SETTING_WORD)
            h = rf_fnv1a(h, at, strnlen(at, g->size));
        else
            h = rf_fnv1a(h, at, g->size);
    }
    return h;
}

static uint64_t hash_release_and_outputs(uint64_t h, const rf_traj_spec *s)
{
    int ints[3] = {s->sphere, s->release_by_speed, (int)s->release_kind};
    h = rf_fnv1a(h, ints, sizeof ints);
    h = rf_fnv1a(h, s->release_px, s->n_release * sizeof *s->release_px);
    h = rf_fnv1a(h, s->release_py, s->n_release * sizeof *s->release_py);
    double z[2] = {s->zone_x0, s->zone_x1};
    h = rf_fnv1a(h, z, sizeof z);
    const rf_traj_outputs *o = &s->outputs;
    h = rf_fnv1a(h, o->percentiles, o->n_percentiles * sizeof(double));
    h = rf_fnv1a(h, o->runout_thresholds, o->n_runout_thresholds * sizeof(double));
    return rf_fnv1a(h, &o->runout_bins, sizeof o->runout_bins);
}

uint64_t rf_traj_spec_values_hash(const rf_traj_spec *s)
{
    uint64_t h = RF_FNV1A_OFFSET;
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        if (tb->owner == RF_TRAJ_OWNER_SPEC)
            h = hash_rows(h, tb, s);
        for (size_t i = 0; tb->owner == RF_TRAJ_OWNER_MATERIAL && i < s->n_materials; i++) {
            const rf_traj_impact_ground *g = &s->materials[i].impact;
            h = hash_rows(hash_str(h, s->materials[i].name), tb, &s->materials[i]);
            if (g->given) /* its impact model's words (its numbers are rows) */
                h = hash_str(hash_str(hash_str(hash_str(hash_str(h, "impact"), g->solver), g->boulder_material),
                                      g->slope_material), g->layer_material);
        }
        for (size_t i = 0; tb->owner == RF_TRAJ_OWNER_COLLECTOR && i < s->n_collectors; i++) {
            const rf_traj_collector *c = &s->collectors[i];
            h = hash_rows(hash_str(h, c->name), tb, c);
            h = rf_fnv1a(h, c->energy_thresholds, c->n_energy_thresholds * sizeof(double));
            h = rf_fnv1a(h, c->height_thresholds, c->n_height_thresholds * sizeof(double));
        }
    }
    for (size_t r = 0; r < s->n_random; r++) {
        const rf_traj_random *q = &s->random[r];
        double v[5] = {(double)q->dist, q->a, q->b, q->lo, q->hi};
        h = rf_fnv1a(hash_str(h, q->path), v, sizeof v);
    }
    h = traj_settings_hash(hash_release_and_outputs(h, s), s);
    if (s->block_kind) /* a rigid block's shape, orientation and spin (not rows); a profile's hash as before */
        h = traj_block_hash(h, s);
    return s->terrain ? rf_terrain_def_hash(s->terrain, h) : h; /* a profile's hash as before */
}
