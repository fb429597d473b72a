/* traj_presets.c - the named materials of presets.h (docs/presets.md): per
 * preset, rows of the material table (traj_fields.c) with a nominal value
 * and a triangular fuzzy support, in the units the row is given in, each
 * with its source.  Sources (docs/presets.md, "Sources"):
 *   RF3D   Dorren 2016, Rockyfor3D (v5.2) revealed, the soil-type table of R_n
 *   ROCF   RocFall's slope material library (Rocscience), "Common Types"
 *   STONE  Guzzetti, Crosta, Detti & Agliardi 2002 (the GRASS r.stone table)
 *   MAT    docs/materials.md, "Parameters and typical ranges"
 *   S5     docs/studies.md S5 (the dense gravelly colluvium, its fuzzy ranges)
 *   JUDG   engineering judgement, no source: a wide range, to be replaced by site data */
#include "rockfuzz/presets.h"
#include "trajectory/traj_internal.h"

#include <stdio.h>
#include <string.h>

#define V(key, value, lo, hi, source) {key, value, lo, hi, source}
#define N(a) (sizeof a / sizeof a[0])

static const rf_traj_preset_value bedrock[] = {
    V("R_n", 0.53, 0.35, 0.65, "RF3D bedrock 0.48-0.58; ROCF bedrock outcrops 0.35; STONE carbonate rocks 0.65"),
    V("R_t", 0.85, 0.75, 0.99, "ROCF bedrock outcrops 0.85, clean hard bedrock 0.99; STONE carbonate rocks 0.75"),
    V("friction_angle", 30, 25, 35, "JUDG (basic friction angle of rock joints)"),
    V("rolling_resistance", 0.30, 0.15, 0.45, "STONE carbonate rocks 0.30"),
    V("roughness", 3, 1, 6, "JUDG"),
    V("impact.slope_E", 50e9, 20e9, 70e9, "MAT rock: intact granite 50-70 GPa, weathered 1-20 GPa"),
    V("impact.slope_poisson", 0.25, 0.2, 0.3, "MAT rock"),
    V("impact.slope_density", 2650, 2500, 2800, "JUDG (common rocks)"),
    V("impact.slope_yield", 150e6, 100e6, 200e6, "MAT rock: von_mises Y 100-200 MPa for local crushing"),
};

static const rf_traj_preset_value talus[] = {
    V("R_n", 0.38, 0.25, 0.50, "RF3D talus (blocks > 10 cm) 0.34-0.42; ROCF talus cover 0.32"),
    V("R_t", 0.80, 0.65, 0.90, "ROCF talus cover 0.82"),
    V("friction_angle", 35, 30, 45, "MAT gravel / talus, scree phi 35-45 deg"),
    V("rolling_resistance", 0.55, 0.30, 0.80, "STONE, carbonate rocks 0.30 to alluvial deposits 0.80 (as examples/default.yaml)"),
    V("roughness", 6, 3, 10, "JUDG (blocks of 0.1-1 m on the surface)"),
    V("impact.layer_thickness", 1.0, 0.5, 2.0, "JUDG"),
    V("impact.layer_E", 100e6, 50e6, 200e6, "MAT gravel / talus, scree E 50-200 MPa"),
    V("impact.layer_poisson", 0.3, 0.25, 0.35, "MAT gravel / talus, scree"),
    V("impact.layer_density", 1900, 1800, 2100, "MAT gravel / talus, scree"),
    V("impact.layer_cohesion", 2e3, 0.5e3, 10e3, "MAT gravel / talus, scree c 0-10 kPa (0.5-2 kPa off the apex)"),
    V("impact.layer_friction_angle", 40, 35, 45, "MAT gravel / talus, scree phi 35-45 deg"),
    V("impact.layer_dilatancy_angle", 8, 5, 15, "MAT gravel / talus, scree psi 5-15 deg"),
    V("impact.layer_cap_pressure", 20e3, 5e3, 50e3, "MAT cap: near-surface scree X0 5-50 kPa"),
    V("impact.layer_cap_hardening", 20e6, 6.4e6, 48e6, "MAT cap: D of loose to dense sand (no scree data), H_c 6.4-48 MPa"),
};

static const rf_traj_preset_value colluvium[] = {
    V("R_n", 0.33, 0.25, 0.45, "RF3D medium compact soil with small rock fragments 0.30-0.36"),
    V("R_t", 0.80, 0.65, 0.90, "ROCF soil with vegetation 0.80"),
    V("friction_angle", 33, 28, 38, "MAT colluvium / debris phi 30-38 deg"),
    V("rolling_resistance", 0.40, 0.25, 0.60, "STONE range (as examples/default.yaml), JUDG inside it"),
    V("roughness", 3, 1, 6, "JUDG"),
    V("impact.layer_thickness", 1.0, 0.5, 2.0, "S5"),
    V("impact.layer_E", 100e6, 50e6, 200e6, "S5"),
    V("impact.layer_poisson", 0.3, 0.25, 0.35, "S5; MAT"),
    V("impact.layer_density", 1900, 1800, 2100, "S5; MAT colluvium / debris"),
    V("impact.layer_cohesion", 10e3, 5e3, 20e3, "S5"),
    V("impact.layer_friction_angle", 40, 35, 45, "S5"),
    V("impact.layer_dilatancy_angle", 5, 0, 8, "S5; MAT colluvium / debris psi 0-8 deg"),
    V("impact.layer_cap_pressure", 200e3, 100e3, 500e3, "S5 (crisp 40 MPa H_c); MAT cap: compacted soils X0 100-500 kPa"),
    V("impact.layer_cap_hardening", 40e6, 27e6, 48e6, "S5 40 MPa; MAT cap: dense sand H_c 27-48 MPa"),
};

static const rf_traj_preset_value loose_soil[] = {
    V("R_n", 0.23, 0.10, 0.30, "RF3D fine soil deeper than 1 m 0.21-0.25; STONE alluvial deposits 0.15"),
    V("R_t", 0.70, 0.40, 0.85, "STONE alluvial deposits 0.40; ROCF soil with vegetation 0.80"),
    V("friction_angle", 30, 25, 35, "MAT loose sand phi 28-33 deg"),
    V("rolling_resistance", 0.70, 0.50, 0.90, "STONE alluvial deposits 0.80"),
    V("roughness", 1, 0, 3, "JUDG"),
    V("impact.layer_thickness", 1.5, 0.5, 3.0, "JUDG"),
    V("impact.layer_E", 45e6, 20e6, 60e6, "MAT loose sand: E 10-25 MPa loading, E_ur ~ 3x (example 45 MPa)"),
    V("impact.layer_poisson", 0.3, 0.25, 0.35, "MAT loose sand"),
    V("impact.layer_density", 1600, 1500, 1700, "MAT loose sand"),
    V("impact.layer_cohesion", 1e3, 0.5e3, 2e3, "MAT loose sand c 0-2 kPa (0.5-2 kPa off the apex)"),
    V("impact.layer_friction_angle", 31, 28, 33, "MAT loose sand"),
    V("impact.layer_dilatancy_angle", 2, 0, 3, "MAT loose sand"),
    V("impact.layer_cap_pressure", 10e3, 5e3, 50e3, "MAT cap: near-surface X0 5-50 kPa"),
    V("impact.layer_cap_hardening", 10e6, 6.4e6, 14.6e6, "MAT cap: loose sand H_c 6.4-14.6 MPa"),
};

static const rf_traj_preset presets[] = {
    {"bedrock", "bedrock outcrop: von Mises rock (local crushing), no layer", "fem", "", "von_mises", "", bedrock,
     N(bedrock)},
    {"talus", "talus / scree: loose coarse layer (Drucker-Prager with cap) over rock", "fem", "rigid", "elastic",
     "drucker_prager", talus, N(talus)},
    {"colluvium", "dense gravelly colluvium over rock (the S5 layer)", "fem", "rigid", "elastic", "drucker_prager",
     colluvium, N(colluvium)},
    {"loose_soil", "loose sandy soil, thick, over rock", "fem", "rigid", "elastic", "drucker_prager", loose_soil,
     N(loose_soil)},
};

const rf_traj_preset *rf_traj_preset_at(size_t k)
{
    return k < N(presets) ? &presets[k] : NULL;
}

const rf_traj_preset *rf_traj_preset_named(const char *name)
{
    for (size_t k = 0; name && k < N(presets); k++)
        if (!strcmp(presets[k].name, name))
            return &presets[k];
    return NULL;
}

void rf_traj_preset_names(char *buf, size_t size)
{
    size_t used = 0;
    if (size)
        buf[0] = '\0';
    for (size_t k = 0; k < N(presets) && used < size; k++) {
        int n = snprintf(buf + used, size - used, "%s%s", k ? ", " : "", presets[k].name);
        used += n > 0 ? (size_t)n : 0;
    }
}

/* The material table's row `key`, or NULL. */
static const rf_traj_field *material_row(const char *key)
{
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        if (tb->owner != RF_TRAJ_OWNER_MATERIAL)
            continue;
        for (size_t i = 0; i < tb->n_rows; i++)
            if (!strcmp(tb->rows[i].key, key))
                return &tb->rows[i];
    }
    return NULL;
}

const rf_traj_field *rf_traj_preset_row(const rf_traj_preset_value *v)
{
    return material_row(v->key);
}

static void word(char dst[16], const char *src)
{
    snprintf(dst, 16, "%s", src ? src : "");
}

void rf_traj_preset_apply(const rf_traj_preset *p, rf_traj_material *m)
{
    for (size_t i = 0; i < p->n_values; i++) {
        const rf_traj_field *f = material_row(p->values[i].key);
        if (f) /* every key is a row: test_traj_presets */
            *(double *)((char *)m + f->offset) = traj_field_store(f, p->values[i].value);
    }
    word(m->impact.solver, p->solver);
    word(m->impact.boulder_material, p->boulder_material);
    word(m->impact.slope_material, p->slope_material);
    word(m->impact.layer_material, p->layer_material);
    m->impact.given = 1;
}
