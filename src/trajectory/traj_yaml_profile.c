/* traj_yaml_profile.c - the `profile:` block: vertices given inline
 * (points: [[x, y], ...]), read from a CSV file (csv: FILE, columns x, y and
 * optionally the material), or cut from a DEM along a polyline (dem: {...},
 * dem.c); and one material per segment (materials: [...]) or one for all
 * (material: NAME). */
#include "trajectory/traj_yaml_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static rf_status alloc_points(ty_ctx *c, size_t n)
{
    rf_traj_spec *s = c->spec;
    s->n_points = n;
    s->px = calloc(n ? n : 1, sizeof *s->px);
    s->py = calloc(n ? n : 1, sizeof *s->py);
    s->seg_material = calloc(n ? n : 1, sizeof *s->seg_material);
    if (!s->px || !s->py || !s->seg_material)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    return RF_OK;
}

static rf_status inline_points(ty_ctx *c, struct fy_node *n)
{
    size_t cnt;
    rf_status st = yr_sequence(&c->sp, n, "profile.points", 2, 1000000, &cnt);
    if (st != RF_OK || (st = alloc_points(c, cnt)) != RF_OK)
        return st;
    ty_remember(c, "profile.points", n);
    for (size_t i = 0; i < cnt; i++) {
        char p[64];
        double xy[2];
        struct fy_node *e = fy_node_sequence_get_by_index(n, (int)i);
        yr_pathf(p, sizeof p, "profile.points[%zu]", i);
        if ((st = yr_numbers(&c->sp, e, p, 2, 2, xy, NULL)) != RF_OK)
            return st;
        ty_remember(c, p, e);
        c->spec->px[i] = xy[0], c->spec->py[i] = xy[1];
    }
    return RF_OK;
}

static size_t material_index(const rf_traj_spec *s, const char *name, size_t len)
{
    for (size_t m = 0; m < s->n_materials; m++)
        if (strlen(s->materials[m].name) == len && !strncmp(s->materials[m].name, name, len))
            return m;
    return TRAJ_NONE;
}

static rf_status segment_materials(ty_ctx *c, struct fy_node *n, const char *path)
{
    rf_traj_spec *s = c->spec;
    size_t nseg = s->n_points - 1, cnt = 1;
    const char *str;
    size_t len;
    rf_status st;
    int single = fy_node_get_type(n) == FYNT_SCALAR;
    if (!single && (st = yr_sequence(&c->sp, n, path, nseg, nseg, &cnt)) != RF_OK)
        return yr_fail(&c->sp, n, path, "expected one material per segment (%zu segments)", nseg);
    for (size_t i = 0; i < nseg; i++) {
        struct fy_node *e = single ? n : fy_node_sequence_get_by_index(n, (int)i);
        char p[64];
        yr_pathf(p, sizeof p, single ? "%s" : "%s[%zu]", path, i);
        if ((st = yr_string(&c->sp, e, p, &str, &len)) != RF_OK)
            return st;
        size_t m = material_index(s, str, len);
        if (m == TRAJ_NONE)
            return yr_fail(&c->sp, e, p, "no such material (define it under materials:)");
        s->seg_material[i] = m;
    }
    return RF_OK;
}

/* "x,y[,material]" per line; '#' comments and one header line are skipped. */
static rf_status csv_points(ty_ctx *c, struct fy_node *n)
{
    char *name = NULL, path[4096];
    rf_status st = yr_string_dup(&c->sp, n, "profile.csv", &name);
    if (st != RF_OK)
        return st;
    if (name[0] == '/' || !strcmp(c->sp.dir, "."))
        snprintf(path, sizeof path, "%s", name);
    else
        snprintf(path, sizeof path, "%s/%s", c->sp.dir, name);
    free(name);
    st = traj_csv_read(path, c->spec, &c->csv_named, c->sp.err);
    if (st != RF_OK)
        return yr_prefix(&c->sp, n, "profile.csv");
    ty_remember(c, "profile.points", n);
    return RF_OK;
}

rf_status ty_parse_profile(ty_ctx *c, struct fy_node *n)
{
    rf_status st = yr_mapping(&c->sp, n, "profile");
    if (st != RF_OK)
        return st;
    struct fy_node *pts = fy_node_mapping_lookup_by_string(n, "points", FY_NT);
    struct fy_node *csv = fy_node_mapping_lookup_by_string(n, "csv", FY_NT);
    struct fy_node *dem = fy_node_mapping_lookup_by_string(n, "dem", FY_NT);
    struct fy_node *mats = fy_node_mapping_lookup_by_string(n, "materials", FY_NT);
    struct fy_node *mat = fy_node_mapping_lookup_by_string(n, "material", FY_NT);
    if (!!pts + !!csv + !!dem != 1)
        return yr_fail(&c->sp, n, "profile", "give exactly one of points, csv, dem");
    if (fy_node_mapping_item_count(n) != 1 + !!mats + !!mat)
        return yr_fail(&c->sp, n, "profile", "unknown key; profile takes points | csv | dem, and materials or "
                                             "material");
    if (pts)
        st = inline_points(c, pts);
    else if (csv)
        st = csv_points(c, csv);
    else
        st = ty_dem_profile(c, dem);
    if (st != RF_OK)
        return st;
    if (mats && mat)
        return yr_fail(&c->sp, mat, "profile.material", "give materials (one per segment) or material, not both");
    if (mats || mat)
        return segment_materials(c, mats ? mats : mat, mats ? "profile.materials" : "profile.material");
    if (c->csv_named)
        return RF_OK; /* the CSV's third column named them */
    if (c->spec->n_materials != 1)
        return yr_fail(&c->sp, n, "profile", "name the material of each segment (materials: [...]) or of all "
                                             "(material: NAME)");
    return RF_OK;
}
