/* cmd_material.c - `rockfuzz material`: the material-point driver (a single
 * integration point driven along a strain path, as the "single-element
 * tests" of geotechnical and impact codes) so that users can check their
 * constitutive parameters against what they expect.
 *
 * The point starts from an isotropic stress (--initial-mean-stress) and
 * follows one of three strain paths in equal increments through
 * rf_material_update (include/rockfuzz/material.h, docs/materials.md).
 * Every option is validated; a bad one exits with 2 and a message naming it
 * and its value. */
#include "cli/cli.h"
#include "core/json.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"
#include "rockfuzz/material.h"

#define EXIT_USAGE 2

typedef enum { PATH_UNIAXIAL, PATH_SHEAR, PATH_HYDROSTATIC } strain_path;
static const char *const path_names[] = {"uniaxial_strain", "simple_shear", "hydrostatic"};

typedef enum {
    O_MODEL, O_E, O_NU, O_YIELD, O_HARDENING, O_COHESION, O_PHI, O_PSI, O_CAP_P, O_CAP_H, O_DCUT,
    O_PATH, O_STRAIN, O_P0, O_INCREMENTS, O_JSON, O_HISTORY, O_HELP, O_COUNT
} opt_id;

/* owner: the model an option belongs to (-1: any). */
static const struct {
    opt_id id;
    const char *name;
    int owner;
} options[] = {
    {O_MODEL, "model", -1},
    {O_E, "E", -1},
    {O_NU, "poisson", -1},
    {O_YIELD, "yield", RF_MATERIAL_VON_MISES},
    {O_HARDENING, "hardening", RF_MATERIAL_VON_MISES},
    {O_COHESION, "cohesion", RF_MATERIAL_DRUCKER_PRAGER},
    {O_PHI, "friction-angle", RF_MATERIAL_DRUCKER_PRAGER},
    {O_PSI, "dilatancy-angle", RF_MATERIAL_DRUCKER_PRAGER},
    {O_CAP_P, "cap-pressure", RF_MATERIAL_DRUCKER_PRAGER},
    {O_CAP_H, "cap-hardening", RF_MATERIAL_DRUCKER_PRAGER},
    {O_DCUT, "dilatancy-cutoff", RF_MATERIAL_DRUCKER_PRAGER},
    {O_PATH, "path", -1},
    {O_STRAIN, "strain", -1},
    {O_P0, "initial-mean-stress", -1},
    {O_INCREMENTS, "increments", -1},
    {O_JSON, "json", -1},
    {O_HISTORY, "history", -1},
    {O_HELP, "help", -1},
};
#define N_OPTIONS (sizeof options / sizeof options[0])

typedef struct {
    rf_material_params params;
    strain_path path;
    double strain, p0;
    int increments, json, history;
    const char *given[O_COUNT]; /* the value text the user gave */
} driver_args;

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz material --model MODEL --E PA --poisson NU [MODEL OPTIONS]\n"
        "                         --path PATH --strain S [OPTIONS]\n"
        "\n"
        "Drive one material point along a strain path from an isotropic stress state and\n"
        "print the final stress (single-element test; models and equations in\n"
        "docs/materials.md).  Units SI (Pa), angles in degrees, tension positive.\n"
        "\n"
        "Model:\n"
        "  --model NAME             elastic | von_mises | drucker_prager (required)\n"
        "  --E PA                   Young's modulus > 0 (required)\n"
        "  --poisson NU             Poisson's ratio in (-1, 0.5) (required)\n"
        "  von_mises:\n"
        "  --yield PA               initial yield stress Y > 0 (required)\n"
        "  --hardening PA           H >= 0, sigma_eq = Y + H eps_p_eq (default 0)\n"
        "  drucker_prager (cone matched to Mohr-Coulomb in triaxial compression):\n"
        "  --cohesion PA            c >= 0 (required)\n"
        "  --friction-angle DEG     phi in [0, 90) (required)\n"
        "  --dilatancy-angle DEG    psi in [0, phi] (default 0; < phi: non-associated)\n"
        "  --cap-pressure PA        crush pressure X0 > 0: the compressive mean stress\n"
        "                           where plastic compaction starts (flat cap)\n"
        "  --cap-hardening PA       H_c >= 0: X = X0 + H_c eps_c, eps_c the plastic\n"
        "                           compaction; the cap is on only when both are given\n"
        "  --dilatancy-cutoff EPS   > 0: the plastic volumetric strain at which the\n"
        "                           dilatancy stops (critical state); from void ratios,\n"
        "                           (e_cs - e0) / (1 + e0), e_cs the critical-state\n"
        "                           void ratio (default: no cutoff)\n"
        "\n"
        "Path:\n"
        "  --path NAME              uniaxial_strain: eps_xx = S, other strains zero\n"
        "                           simple_shear:    gamma_xy = S at constant volume\n"
        "                           hydrostatic:     eps_xx = eps_yy = eps_zz = S\n"
        "  --strain S               final strain, |S| <= 1 (S < 0 compresses) (required)\n"
        "  --initial-mean-stress PA start: isotropic stress, tension > 0 (default 0)\n"
        "  --increments N           equal strain increments, 1..10000000 (default 100)\n"
        "\n"
        "Output:\n"
        "  --json                   one JSON object: stress_xx, stress_yy, stress_zz,\n"
        "                           stress_xy, mean_stress [Pa],\n"
        "                           equivalent_plastic_strain,\n"
        "                           plastic_volumetric_strain [-], plastic_work [J/m^3]\n"
        "  --history                CSV, one row per increment (the stress path)\n"
        "  -h, --help               show this help\n"
        "\n"
        "Example (loose sand, docs/materials.md, confined compression under a block):\n"
        "  rockfuzz material --model drucker_prager --E 45e6 --poisson 0.3 \\\n"
        "    --cohesion 1e3 --friction-angle 31 --cap-pressure 20e3 --cap-hardening 10e6 \\\n"
        "    --path uniaxial_strain --strain -0.05 --json\n"
        "\n"
        "Exit status: 0 success, 2 invalid command line or input.\n");
}

static int parse_double(const char *opt, const char *s, double *x)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v)) {
        fprintf(stderr, "rockfuzz material: --%s '%s': not a finite number\n", opt, s);
        return 0;
    }
    *x = v;
    return 1;
}

static int parse_increments(const char *s, int *n)
{
    char *end = NULL;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < 1 || v > 10000000) {
        fprintf(stderr, "rockfuzz material: --increments '%s': not an integer in 1..10000000\n", s);
        return 0;
    }
    *n = (int)v;
    return 1;
}

static int parse_path(const char *s, strain_path *path)
{
    const int i = rf_name_index(s, path_names, 3);
    if (i >= 0) {
        *path = (strain_path)i;
        return 1;
    }
    fprintf(stderr, "rockfuzz material: --path '%s': not one of uniaxial_strain, simple_shear, "
                    "hydrostatic\n", s);
    return 0;
}

/* Stores one valued option; 0 on a bad value (message printed). */
static int set_option(driver_args *a, opt_id id, const char *name, const char *val)
{
    rf_material_params *p = &a->params;
    double x = 0.0, deg = RF_PI / 180.0;
    if (id == O_MODEL) {
        rf_error err = {0};
        if (rf_material_model_parse(val, &p->model, &err) == RF_OK)
            return 1;
        fprintf(stderr, "rockfuzz material: --model: %s\n", err.msg);
        return 0;
    }
    if (id == O_PATH)
        return parse_path(val, &a->path);
    if (id == O_INCREMENTS)
        return parse_increments(val, &a->increments);
    if (!parse_double(name, val, &x))
        return 0;
    switch (id) {
    case O_E: p->E = x; break;
    case O_NU: p->poisson = x; break;
    case O_YIELD: p->yield = x; break;
    case O_HARDENING: p->hardening = x; break;
    case O_COHESION: p->cohesion = x; break;
    case O_PHI: p->friction_angle = x * deg; break;
    case O_PSI: p->dilatancy_angle = x * deg; break;
    case O_CAP_P: p->cap_pressure = x; break;
    case O_CAP_H: p->cap_hardening = x; break;
    case O_DCUT: p->dilatancy_cutoff = x; break;
    case O_STRAIN: a->strain = x; break;
    case O_P0: a->p0 = x; break;
    default: break;
    }
    return 1;
}

/* -1: error (printed), 0: go on, 1: --help shown. */
static int parse_args(int argc, char **argv, driver_args *a)
{
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h"))
            return usage(stdout), 1;
        if (strncmp(arg, "--", 2) != 0 || arg[2] == '\0') {
            fprintf(stderr, "rockfuzz material: unexpected argument '%s' (try --help)\n", arg);
            return -1;
        }
        const char *name = arg + 2, *eq = strchr(name, '=');
        size_t len = eq ? (size_t)(eq - name) : strlen(name), k = 0;
        while (k < N_OPTIONS && !(strlen(options[k].name) == len && !strncmp(options[k].name, name, len)))
            k++;
        if (k == N_OPTIONS) {
            fprintf(stderr, "rockfuzz material: unknown option '--%.*s' (try --help)\n", (int)len, name);
            return -1;
        }
        opt_id id = options[k].id;
        if (id == O_HELP || id == O_JSON || id == O_HISTORY) {
            if (eq) {
                fprintf(stderr, "rockfuzz material: option '--%s' takes no value\n", options[k].name);
                return -1;
            }
            if (id == O_HELP)
                return usage(stdout), 1;
            *(id == O_JSON ? &a->json : &a->history) = 1;
            continue;
        }
        const char *val = eq ? eq + 1 : (i + 1 < argc ? argv[++i] : NULL);
        if (!val) {
            fprintf(stderr, "rockfuzz material: option '--%s' needs a value\n", options[k].name);
            return -1;
        }
        a->given[id] = val;
        if (!set_option(a, id, options[k].name, val))
            return -1;
    }
    return 0;
}

static const char *option_name(opt_id id)
{
    for (size_t k = 0; k < N_OPTIONS; k++)
        if (options[k].id == id)
            return options[k].name;
    return "?";
}

/* 0 (message printed) when the option a model needs is missing. */
static int require(const driver_args *a, opt_id id)
{
    if (a->given[id])
        return 1;
    fprintf(stderr, "rockfuzz material: --%s is required with --model %s\n", option_name(id),
            rf_material_model_name(a->params.model));
    return 0;
}

/* Required options present, no option of another model. */
static int check_presence(const driver_args *a)
{
    const opt_id required[] = {O_MODEL, O_E, O_NU, O_PATH, O_STRAIN};
    for (size_t i = 0; i < sizeof required / sizeof required[0]; i++)
        if (!a->given[required[i]]) {
            fprintf(stderr, "rockfuzz material: --%s is required (try --help)\n", option_name(required[i]));
            return 0;
        }
    rf_material_model model = a->params.model;
    for (size_t k = 0; k < N_OPTIONS; k++)
        if (options[k].owner >= 0 && a->given[options[k].id] && options[k].owner != (int)model) {
            fprintf(stderr, "rockfuzz material: --%s %s: not an option of --model %s\n", options[k].name,
                    a->given[options[k].id], rf_material_model_name(model));
            return 0;
        }
    int ok = 1;
    if (model == RF_MATERIAL_VON_MISES)
        ok = require(a, O_YIELD);
    else if (model == RF_MATERIAL_DRUCKER_PRAGER)
        ok = require(a, O_COHESION) && require(a, O_PHI);
    if (!ok)
        return 0;
    if (!a->given[O_CAP_P] != !a->given[O_CAP_H]) {
        opt_id id = a->given[O_CAP_P] ? O_CAP_P : O_CAP_H;
        fprintf(stderr, "rockfuzz material: --%s %s: the cap needs both --cap-pressure and "
                        "--cap-hardening\n", option_name(id), a->given[id]);
        return 0;
    }
    if (a->given[O_DCUT] && !(a->params.dilatancy_cutoff > 0.0)) {
        fprintf(stderr, "rockfuzz material: --dilatancy-cutoff %s: must be a plastic volumetric strain > 0 "
                        "(leave the option out for no cutoff)\n", a->given[O_DCUT]);
        return 0;
    }
    return 1;
}

/* The option whose value an rf_material_init message names ("field = ..."). */
static opt_id option_of_field(const char *msg)
{
    static const struct { const char *field; opt_id id; } map[] = {
        {"E =", O_E}, {"poisson =", O_NU}, {"yield =", O_YIELD}, {"hardening =", O_HARDENING},
        {"cohesion =", O_COHESION}, {"friction_angle =", O_PHI}, {"dilatancy_angle =", O_PSI},
        {"cap_pressure =", O_CAP_P}, {"cap_hardening =", O_CAP_H}, {"dilatancy_cutoff =", O_DCUT}};
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (!strncmp(msg, map[i].field, strlen(map[i].field)))
            return map[i].id;
    return O_COUNT;
}

static int check_values(const driver_args *a, rf_material *m)
{
    rf_error err = {0};
    if (rf_material_init(m, &a->params, &err) != RF_OK) {
        opt_id id = option_of_field(err.msg);
        if (id != O_COUNT && a->given[id])
            fprintf(stderr, "rockfuzz material: --%s %s: %s\n", option_name(id), a->given[id], err.msg);
        else
            fprintf(stderr, "rockfuzz material: %s\n", err.msg);
        return 0;
    }
    if (a->given[O_CAP_P] && !(a->params.cap_pressure > 0.0)) {
        fprintf(stderr, "rockfuzz material: --cap-pressure %s: must be > 0 Pa\n", a->given[O_CAP_P]);
        return 0;
    }
    if (!(fabs(a->strain) <= 1.0)) {
        fprintf(stderr, "rockfuzz material: --strain %s: must lie in [-1, 1] (small strain)\n",
                a->given[O_STRAIN]);
        return 0;
    }
    double sig[6] = {a->p0, a->p0, a->p0, 0, 0, 0};
    rf_material_state st = {0};
    if (!rf_material_admissible(m, sig, &st, 1e-12)) {
        fprintf(stderr, "rockfuzz material: --initial-mean-stress %s: outside the elastic domain of "
                        "the material (beyond the cone apex or the cap)\n", a->given[O_P0] ? a->given[O_P0] : "0");
        return 0;
    }
    return 1;
}

static void path_increment(strain_path path, double ds, double deps[6])
{
    memset(deps, 0, 6 * sizeof deps[0]);
    if (path == PATH_UNIAXIAL)
        deps[0] = ds;
    else if (path == PATH_SHEAR)
        deps[3] = ds;
    else
        deps[0] = deps[1] = deps[2] = ds;
}

/* One "key": number pair of the JSON line (null where the value is not finite). */
static void json_pair(const char *key, double v, const char *after)
{
    printf("\"%s\": ", key);
    rf_json_number(stdout, v);
    fputs(after, stdout);
}

static void print_json(const driver_args *a, const double sig[6], const rf_material_state *st, double work)
{
    printf("{\"model\": \"%s\", \"path\": \"%s\", ", rf_material_model_name(a->params.model), path_names[a->path]);
    json_pair("strain", a->strain, ", ");
    printf("\"increments\": %d, ", a->increments);
    static const char *const keys[4] = {"stress_xx", "stress_yy", "stress_zz", "stress_xy"};
    for (int k = 0; k < 4; k++)
        json_pair(keys[k], sig[k], ", ");
    json_pair("mean_stress", (sig[0] + sig[1] + sig[2]) / 3.0, ", ");
    json_pair("equivalent_plastic_strain", st->plastic_strain_eq, ", ");
    json_pair("plastic_volumetric_strain", st->plastic_volumetric, ", ");
    json_pair("plastic_work", work, "}\n");
}

static void print_summary(const driver_args *a, const double sig[6], const rf_material_state *st,
                          double work)
{
    printf("rockfuzz material (%s, %s to %g in %d increments, initial mean stress %g Pa)\n",
           rf_material_model_name(a->params.model), path_names[a->path], a->strain, a->increments, a->p0);
    printf("  stress_xx                  %.6g Pa\n  stress_yy                  %.6g Pa\n", sig[0], sig[1]);
    printf("  stress_zz                  %.6g Pa\n  stress_xy                  %.6g Pa\n", sig[2], sig[3]);
    printf("  mean_stress                %.6g Pa\n", (sig[0] + sig[1] + sig[2]) / 3.0);
    printf("  equivalent_plastic_strain  %.6g\n", st->plastic_strain_eq);
    printf("  plastic_volumetric_strain  %.6g (dilation > 0)\n", st->plastic_volumetric);
    printf("  plastic_work               %.6g J/m^3\n", work);
}

/* A non-finite state is an error naming the inputs (they exceed what the arithmetic holds). */
static int finite_state(const driver_args *a, const double sig[6], const rf_material_state *st, double work)
{
    int ok = isfinite(st->plastic_strain_eq) && isfinite(st->plastic_volumetric) && isfinite(work);
    for (int k = 0; k < 6; k++)
        ok = ok && isfinite(sig[k]);
    if (!ok)
        fprintf(stderr, "rockfuzz material: the stresses are not finite (stress_xx = %g Pa) for --E %g Pa, "
                "--strain %g, initial mean stress %g Pa: the inputs exceed what the arithmetic holds\n", sig[0],
                a->params.E, a->strain, a->p0);
    return ok;
}

static int run_path(const driver_args *a, const rf_material *m)
{
    double sig[6] = {a->p0, a->p0, a->p0, 0, 0, 0}, deps[6], work = 0.0, d = 0.0;
    rf_material_state st = {0};
    double ds = a->strain / a->increments;
    path_increment(a->path, ds, deps);
    if (a->history)
        printf("strain,stress_xx,stress_yy,stress_zz,stress_xy,mean_stress,equivalent_plastic_strain,"
               "plastic_work\n");
    for (int i = 1; i <= a->increments; i++) {
        rf_material_update(m, deps, sig, &st, &d);
        work += d;
        if (!finite_state(a, sig, &st, work))
            return 1;
        if (a->history)
            printf("%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", ds * i, sig[0], sig[1], sig[2],
                   sig[3], (sig[0] + sig[1] + sig[2]) / 3.0, st.plastic_strain_eq, work);
    }
    if (a->json)
        print_json(a, sig, &st, work);
    else if (!a->history)
        print_summary(a, sig, &st, work);
    return 0;
}

int rf_cli_material(int argc, char **argv)
{
    driver_args a;
    memset(&a, 0, sizeof a);
    rf_material_params_default(&a.params);
    a.increments = 100;
    int rc = parse_args(argc, argv, &a);
    if (rc != 0)
        return rc > 0 ? 0 : EXIT_USAGE;
    if (a.json && a.history) {
        fprintf(stderr, "rockfuzz material: --json and --history exclude each other\n");
        return EXIT_USAGE;
    }
    rf_material m;
    if (!check_presence(&a) || !check_values(&a, &m))
        return EXIT_USAGE;
    return run_path(&a, &m);
}
