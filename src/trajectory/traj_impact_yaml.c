/* traj_impact_yaml.c - a material's own impact model in a trajectory file:
 *   materials: {NAME: {R_n: .., R_t: .., ..., impact: {solver: fem,
 *     layer_thickness: 1.0, layer_material: drucker_prager, layer_E: 50e6, ...}}}
 * The numbers are rows of the material table (materials.NAME.impact.<field>,
 * traj_fields.c) read and checked like every row (file:line: path = value:
 * reason); the words solver, boulder_material, slope_material and
 * layer_material are kept as written and checked, with the whole ground
 * against the impact model and its solver, by rf_traj_spec_validate
 * (traj_impact_ground_check), located at this mapping. */
#include "trajectory/traj_yaml_internal.h"
#include "trajectory/traj_impact.h"

#include <string.h>

#define IMPACT_WORDS "solver boulder_material slope_material layer_material"

/* The word at key `name` of mapping n (absent: left "") into buf[16]. */
static rf_status word(ty_ctx *c, struct fy_node *n, const char *path, const char *name, char *buf)
{
    struct fy_node *v = fy_node_mapping_lookup_by_string(n, name, FY_NT);
    if (!v)
        return RF_OK;
    char p[320];
    yr_pathf(p, sizeof p, "%s.%s", path, name);
    ty_remember(c, p, v);
    rf_status st = yr_word(&c->sp, v, p, buf, 16);
    if (st == RF_OK && !buf[0])
        return yr_fail(&c->sp, v, p, "not a name of the impact model (see rockfuzz impact --help)");
    return st;
}

rf_status traj_impact_yaml(ty_ctx *c, struct fy_node *mat, const char *path, rf_traj_material *m)
{
    struct fy_node *n = fy_node_mapping_lookup_by_string(mat, "impact", FY_NT);
    if (!n)
        return RF_OK;
    char p[300];
    yr_pathf(p, sizeof p, "%s.impact", path);
    ty_remember(c, p, n); /* locates the ground's check (rf_traj_spec_validate) */
    rf_status st = ty_fields(c, n, p, IMPACT_WORDS);
    rf_traj_impact_ground *g = &m->impact;
    if (st == RF_OK)
        st = word(c, n, p, "solver", g->solver);
    if (st == RF_OK)
        st = word(c, n, p, "boulder_material", g->boulder_material);
    if (st == RF_OK)
        st = word(c, n, p, "slope_material", g->slope_material);
    if (st == RF_OK)
        st = word(c, n, p, "layer_material", g->layer_material);
    g->given = st == RF_OK;
    return st;
}
