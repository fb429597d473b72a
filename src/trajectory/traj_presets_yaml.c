/* traj_presets_yaml.c - a material of a trajectory file named by its preset
 * (presets.h, docs/presets.md):
 *   materials: {scree: talus}                       the preset as it is
 *   materials: {scree: {preset: talus, R_n: 0.3}}   the preset, then the keys given
 * The preset's values go in first; the keys given after it are read by the
 * caller (traj_yaml.c) as every material row is (file:line: path = value:
 * reason).  An unknown name is refused with its line and the list of names. */
#include "trajectory/traj_yaml_internal.h"
#include "rockfuzz/presets.h"

#include <stdio.h>

/* The preset named at node n (path for the messages), applied to m. */
static rf_status apply_named(ty_ctx *c, struct fy_node *n, const char *path, const char *mat_path,
                             rf_traj_material *m)
{
    char name[40], names[200];
    rf_status st = yr_word(&c->sp, n, path, name, sizeof name);
    if (st != RF_OK)
        return st;
    const rf_traj_preset *p = rf_traj_preset_named(name);
    if (!p) {
        rf_traj_preset_names(names, sizeof names);
        return yr_fail(&c->sp, n, path, "unknown preset; the presets are %s (rockfuzz presets)", names);
    }
    rf_traj_preset_apply(p, m);
    char ip[320];
    snprintf(ip, sizeof ip, "%s.impact", mat_path);
    ty_remember(c, path, n);
    ty_remember(c, ip, n); /* the ground's check (rf_traj_spec_validate) points at the preset */
    return RF_OK;
}

rf_status ty_material_preset(ty_ctx *c, struct fy_node *v, const char *path, rf_traj_material *m, int *whole)
{
    *whole = 0;
    if (v && fy_node_get_type(v) == FYNT_SCALAR) {
        *whole = 1;
        return apply_named(c, v, path, path, m);
    }
    struct fy_node *n = v && fy_node_is_mapping(v) ? fy_node_mapping_lookup_by_string(v, "preset", FY_NT) : NULL;
    if (!n)
        return RF_OK;
    char p[320];
    snprintf(p, sizeof p, "%s.preset", path);
    return apply_named(c, n, p, path, m);
}
