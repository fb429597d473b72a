/* cmd_presets.c - `rockfuzz presets [NAME] [--study MATERIAL]`: the named
 * materials of a trajectory file (presets.h, docs/presets.md) with their
 * values, units, fuzzy ranges and sources; with --study, the parameters and
 * bindings of a study that makes the preset's bindable values fuzzy for the
 * material MATERIAL of its trajectory file. */
#include "cli/cli.h"

#include <stdio.h>
#include <string.h>

#include "rockfuzz/presets.h"

#define EXIT_USAGE 2

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz presets [NAME] [--study MATERIAL]\n"
        "\n"
        "Named materials for a trajectory file: `materials: {scree: talus}`, or with\n"
        "overrides `materials: {scree: {preset: talus, R_n: 0.3}}` (docs/presets.md).\n"
        "\n"
        "  (no NAME)          list the presets\n"
        "  NAME               each value with its unit, its fuzzy number (triangular:\n"
        "                     support lo..hi, peak the value) and its source\n"
        "  --study MATERIAL   print a study's parameters: and bind: for the material\n"
        "                     MATERIAL of the trajectory file (the bindable values;\n"
        "                     the impact model's are listed as comments)\n"
        "  -h, --help         this help\n"
        "\n"
        "Units: as in a trajectory file (SI; angles in degrees).\n");
}

static void list(void)
{
    const rf_traj_preset *p;
    for (size_t k = 0; (p = rf_traj_preset_at(k)); k++)
        printf("%-12s %s\n", p->name, p->help);
}

static void show(const rf_traj_preset *p)
{
    printf("# %s: %s\n# impact model: solver %s, boulder %s, rock %s, layer %s\n", p->name, p->help, p->solver,
           p->boulder_material[0] ? p->boulder_material : "elastic",
           p->slope_material[0] ? p->slope_material : "elastic", p->layer_material[0] ? p->layer_material : "-");
    printf("%-28s %12s %-7s %12s %12s  %s\n", "key", "value", "unit", "fuzzy lo", "fuzzy hi", "source");
    for (size_t i = 0; i < p->n_values; i++) {
        const rf_traj_preset_value *v = &p->values[i];
        const rf_traj_field *f = rf_traj_preset_row(v);
        printf("%-28s %12g %-7s %12g %12g  %s\n", v->key, v->value, f && f->unit[0] ? f->unit : "-", v->lo, v->hi,
               v->source);
    }
}

/* A value the printed study binds: bindable, with a support, and not an
 * impact-model input (those are bound only under bounce.law impact_model,
 * through the impact surrogate: docs/soil-surrogate.md). */
static int study_binds(const rf_traj_preset_value *v, const rf_traj_field *f)
{
    return f && f->bindable && v->hi > v->lo && strncmp(v->key, "impact.", 7) != 0;
}

/* The study parameters: {tfn: [peak, left, right]} and bind: lines. */
static void study(const rf_traj_preset *p, const char *mat)
{
    printf("# preset %s for material %s (rockfuzz presets %s --study %s)\nparameters:\n", p->name, mat, p->name, mat);
    for (size_t i = 0; i < p->n_values; i++) {
        const rf_traj_preset_value *v = &p->values[i];
        const rf_traj_field *f = rf_traj_preset_row(v);
        if (study_binds(v, f))
            printf("  %s_%s: {tfn: [%g, %g, %g], unit: \"%s\"}\n", mat, v->key, v->value, v->value - v->lo,
                   v->hi - v->value, f->unit);
        else if (f && f->bindable && v->hi > v->lo)
            printf("  # %s: [%g, %g, %g] %s (bindable with bounce.law impact_model: docs/soil-surrogate.md)\n",
                   v->key, v->lo, v->value, v->hi, f->unit);
        else
            printf("  # %s: [%g, %g, %g] %s (not bindable in a study)\n", v->key, v->lo, v->value, v->hi,
                   f ? f->unit : "");
    }
    printf("# under model.trajectory:\n    bind:\n");
    for (size_t i = 0; i < p->n_values; i++)
        if (study_binds(&p->values[i], rf_traj_preset_row(&p->values[i])))
            printf("      %s_%s: materials.%s.%s\n", mat, p->values[i].key, mat, p->values[i].key);
}

int rf_cli_presets(int argc, char **argv)
{
    const char *name = NULL, *mat = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "--study") && i + 1 < argc) {
            mat = argv[++i];
        } else if (argv[i][0] != '-' && !name) {
            name = argv[i];
        } else {
            fprintf(stderr, "rockfuzz presets: unexpected argument '%s'\n", argv[i]);
            usage(stderr);
            return EXIT_USAGE;
        }
    }
    if (!name) {
        if (mat) {
            fprintf(stderr, "rockfuzz presets: --study needs a preset NAME\n");
            return EXIT_USAGE;
        }
        list();
        return 0;
    }
    const rf_traj_preset *p = rf_traj_preset_named(name);
    if (!p) {
        char names[200];
        rf_traj_preset_names(names, sizeof names);
        fprintf(stderr, "rockfuzz presets: unknown preset '%s'; the presets are %s\n", name, names);
        return EXIT_USAGE;
    }
    if (mat && !rf_traj_name_valid(mat)) {
        fprintf(stderr, "rockfuzz presets: --study %s: %s\n", mat, RF_TRAJ_NAME_RULE);
        return EXIT_USAGE;
    }
    mat ? study(p, mat) : show(p);
    return 0;
}
