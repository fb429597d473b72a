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

typedef enum { O_MODEL, O_PATH, O_STRAIN, O_P0, O_INCREMENTS, O_JSON, O_HISTORY, O_HELP, O_COUNT } opt_id;
static const char *const option_names[O_COUNT] = {"model", "path", "strain", "initial-mean-stress",
                                                  "increments", "json", "history", "help"};

/* The material parameters of every law (material.h's registry): their
 * options are their names with '-' for '_'. */
#define MAX_PARAMS 64
typedef struct {
    const rf_material_param *param[MAX_PARAMS];
    int owner[MAX_PARAMS];     /* the law (-1: every law) */
    const char *given[MAX_PARAMS]; /* the value text the user gave */
    double value[MAX_PARAMS];      /* and its value (SI, radians) */
    size_t n;
} param_options;

typedef struct {
    rf_material_params params;
    strain_path path;
    double strain, p0;
    int increments, json, history;
    const char *given[O_COUNT]; /* the value text the user gave */
    param_options mp;
} driver_args;

static void collect_params(param_options *o)
{
    o->n = 0;
    for (size_t i = 0; i < 2; i++)
        o->param[o->n] = &rf_material_common_params[i], o->owner[o->n++] = -1;
    for (size_t k = 0; k < rf_material_n_laws(); k++) {
        const rf_material_law_info *law = rf_material_law((rf_material_model)k);
        for (size_t i = 0; i < law->n_params && o->n < MAX_PARAMS; i++)
            o->param[o->n] = &law->params[i], o->owner[o->n++] = (int)k;
    }
}

/* The option of a parameter: "friction_angle" -> "friction-angle". */
static const char *option_text(const rf_material_param *p, char *buf, size_t size)
{
    size_t i = 0;
    for (; p->name[i] && i + 1 < size; i++)
        buf[i] = p->name[i] == '_' ? '-' : p->name[i];
    buf[i] = '\0';
    return buf;
}

/* The index of the parameter an option (len characters of name) sets, of the
 * law `owner` or any (-2), or -1. */
static int param_index(const param_options *o, const char *name, size_t len, int owner)
{
    char buf[64];
    for (size_t k = 0; k < o->n; k++) {
        const char *t = option_text(o->param[k], buf, sizeof buf);
        if (strlen(t) == len && !strncmp(t, name, len) && (owner == -2 || o->owner[k] < 0 || o->owner[k] == owner))
            return (int)k;
    }
    return -1;
}

/* The help text of one parameter: its help with the rule at "{}", then required or its default. */
static void param_usage(FILE *f, const rf_material_param *p)
{
    static const char *const rules[] = {"> 0", ">= 0", "in (-1, 0.5)", "in [0, 90)"};
    const int sw = p->flags & RF_MATERIAL_PARAM_SWITCH;
    char opt[64], head[96];
    snprintf(head, sizeof head, "--%s %s", option_text(p, opt, sizeof opt), p->metavar);
    fprintf(f, "  %-24s ", head);
    for (const char *c = p->help; *c; c++)
        if (c[0] == '{' && c[1] == '}')
            fputs(sw ? "> 0" : rules[p->rule], f), c++;
        else if (*c == '\n')
            fprintf(f, "\n%27s", "");
        else
            fputc(*c, f);
    if (p->flags & RF_MATERIAL_PARAM_REQUIRED)
        fprintf(f, " (required)\n");
    else if (sw)
        fprintf(f, " (default: no %s)\n", p->feature);
    else
        fprintf(f, " (default %g)\n", p->default_value * (p->rule == RF_MATERIAL_RULE_ANGLE ? 180.0 / RF_PI : 1.0));
}

static void model_usage(FILE *f)
{
    fprintf(f, "Model:\n  --model NAME             ");
    for (size_t k = 0; k < rf_material_n_laws(); k++)
        fprintf(f, "%s%s", k ? " | " : "", rf_material_law((rf_material_model)k)->name);
    fprintf(f, " (required)\n");
    for (size_t i = 0; i < 2; i++)
        param_usage(f, &rf_material_common_params[i]);
    for (size_t k = 0; k < rf_material_n_laws(); k++) {
        const rf_material_law_info *law = rf_material_law((rf_material_model)k);
        if (law->n_params)
            fprintf(f, "  %s (%s):\n", law->name, law->help);
        for (size_t i = 0; i < law->n_params; i++)
            param_usage(f, &law->params[i]);
    }
}

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz material --model MODEL --E PA --poisson NU [MODEL OPTIONS]\n"
        "                         --path PATH --strain S [OPTIONS]\n"
        "\n"
        "Drive one material point along a strain path from an isotropic stress state and\n"
        "print the final stress (single-element test; models and equations in\n"
        "docs/materials.md).  Units SI (Pa), angles in degrees, tension positive.\n"
        "\n");
    model_usage(f);
    fprintf(f,
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

/* Stores one valued option of the fixed set; 0 on a bad value (message printed). */
static int set_option(driver_args *a, opt_id id, const char *val)
{
    double x = 0.0;
    if (id == O_MODEL) {
        rf_error err = {0};
        if (rf_material_model_parse(val, &a->params.model, &err) == RF_OK)
            return 1;
        fprintf(stderr, "rockfuzz material: --model: %s\n", err.msg);
        return 0;
    }
    if (id == O_PATH)
        return parse_path(val, &a->path);
    if (id == O_INCREMENTS)
        return parse_increments(val, &a->increments);
    if (!rf_cli_parse_double("material", option_names[id], val, &x))
        return 0;
    *(id == O_STRAIN ? &a->strain : &a->p0) = x;
    return 1;
}

/* Stores one material parameter (the same name in every law that has it). */
static int set_param(driver_args *a, const char *name, size_t len, const char *val)
{
    double x = 0.0;
    char opt[64];
    snprintf(opt, sizeof opt, "%.*s", (int)len, name);
    if (!rf_cli_parse_double("material", opt, val, &x))
        return 0;
    for (size_t k = 0; k < a->mp.n; k++) {
        char t[64];
        if (strlen(option_text(a->mp.param[k], t, sizeof t)) != len || strncmp(t, name, len))
            continue;
        const rf_material_param *p = a->mp.param[k];
        *rf_material_param_field(&a->params, p) = p->rule == RF_MATERIAL_RULE_ANGLE ? x * (RF_PI / 180.0) : x;
        a->mp.given[k] = val;
        a->mp.value[k] = *rf_material_param_field(&a->params, p);
    }
    return 1;
}

/* The option (len characters of name): a fixed one (its id), a material parameter (O_COUNT + 1) or
 * unknown (O_COUNT). */
static int find_option(const driver_args *a, const char *name, size_t len)
{
    for (int k = 0; k < O_COUNT; k++)
        if (strlen(option_names[k]) == len && !strncmp(option_names[k], name, len))
            return k;
    return param_index(&a->mp, name, len, -2) >= 0 ? O_COUNT + 1 : O_COUNT;
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
        size_t len = eq ? (size_t)(eq - name) : strlen(name);
        const int id = find_option(a, name, len);
        if (id == O_COUNT) {
            fprintf(stderr, "rockfuzz material: unknown option '--%.*s' (try --help)\n", (int)len, name);
            return -1;
        }
        if (id == O_HELP || id == O_JSON || id == O_HISTORY) {
            if (eq) {
                fprintf(stderr, "rockfuzz material: option '--%s' takes no value\n", option_names[id]);
                return -1;
            }
            if (id == O_HELP)
                return usage(stdout), 1;
            *(id == O_JSON ? &a->json : &a->history) = 1;
            continue;
        }
        const char *val = eq ? eq + 1 : (i + 1 < argc ? argv[++i] : NULL);
        if (!val) {
            fprintf(stderr, "rockfuzz material: option '--%.*s' needs a value\n", (int)len, name);
            return -1;
        }
        if (id < O_COUNT)
            a->given[id] = val;
        if (!(id < O_COUNT ? set_option(a, (opt_id)id, val) : set_param(a, name, len, val)))
            return -1;
    }
    return 0;
}

/* The value text and option of parameter k. */
static const char *param_option(const driver_args *a, size_t k, char *buf, size_t size)
{
    return option_text(a->mp.param[k], buf, size);
}

/* No option of another law. */
static int check_foreign(const driver_args *a)
{
    const rf_material_model model = a->params.model;
    char opt[64];
    for (size_t k = 0; k < a->mp.n; k++) {
        const int mine = a->mp.owner[k] < 0 || a->mp.owner[k] == (int)model;
        param_option(a, k, opt, sizeof opt);
        if (a->mp.given[k] && !mine && param_index(&a->mp, opt, strlen(opt), (int)model) < 0) {
            fprintf(stderr, "rockfuzz material: --%s %s: not an option of --model %s\n", opt, a->mp.given[k],
                    rf_material_model_name(model));
            return 0;
        }
    }
    return 1;
}

/* One parameter of the law: given when required, its partner given with it, a switch > 0. */
static int check_param(const driver_args *a, size_t k)
{
    const rf_material_param *p = a->mp.param[k];
    const char *given = a->mp.given[k];
    char opt[64], other[64];
    param_option(a, k, opt, sizeof opt);
    if (!given && (p->flags & RF_MATERIAL_PARAM_REQUIRED)) {
        if (a->mp.owner[k] < 0)
            fprintf(stderr, "rockfuzz material: --%s is required (try --help)\n", opt);
        else
            fprintf(stderr, "rockfuzz material: --%s is required with --model %s\n", opt,
                    rf_material_model_name(a->params.model));
        return 0;
    }
    if (!given)
        return 1;
    if (p->together) {
        option_text(rf_material_param_find(p->together), other, sizeof other);
        const int j = param_index(&a->mp, other, strlen(other), (int)a->params.model);
        if (j >= 0 && !a->mp.given[j]) {
            const int first = (p->flags & RF_MATERIAL_PARAM_SWITCH) != 0; /* the switch first */
            fprintf(stderr, "rockfuzz material: --%s %s: the %s needs both --%s and --%s\n", opt, given,
                    p->feature, first ? opt : other, first ? other : opt);
            return 0;
        }
    }
    if ((p->flags & RF_MATERIAL_PARAM_SWITCH) && !(a->mp.value[k] > 0.0)) {
        fprintf(stderr, "rockfuzz material: --%s %s: must be > 0 (leave the option out for no %s)\n", opt, given,
                p->feature);
        return 0;
    }
    return 1;
}

/* Required options present, no option of another law, switches > 0, partners given together. */
static int check_params(const driver_args *a)
{
    if (!check_foreign(a))
        return 0;
    for (size_t k = 0; k < a->mp.n; k++)
        if ((a->mp.owner[k] < 0 || a->mp.owner[k] == (int)a->params.model) && !check_param(a, k))
            return 0;
    return 1;
}

/* The fixed options required, then the material's. */
static int check_presence(const driver_args *a)
{
    const opt_id required[] = {O_MODEL, O_PATH, O_STRAIN};
    for (size_t i = 0; i < sizeof required / sizeof required[0]; i++)
        if (!a->given[required[i]]) {
            fprintf(stderr, "rockfuzz material: --%s is required (try --help)\n", option_names[required[i]]);
            return 0;
        }
    return check_params(a);
}

/* The parameter whose value an rf_material_init message names ("name = ..."): its index, or -1. */
static int param_of_message(const driver_args *a, const char *msg)
{
    const rf_material_law_info *law = rf_material_law(a->params.model);
    for (size_t k = 0; k < a->mp.n; k++) {
        const char *name = a->mp.param[k]->name;
        size_t n = strlen(name);
        if (!strncmp(msg, name, n) && msg[n] == ' ' && (a->mp.owner[k] < 0 || rf_material_law((rf_material_model)a->mp.owner[k]) == law))
            return (int)k;
    }
    return -1;
}

static int check_values(const driver_args *a, rf_material *m)
{
    rf_error err = {0};
    if (rf_material_init(m, &a->params, &err) != RF_OK) {
        const int k = param_of_message(a, err.msg);
        char opt[64];
        if (k >= 0 && a->mp.given[k])
            fprintf(stderr, "rockfuzz material: --%s %s: %s\n", param_option(a, (size_t)k, opt, sizeof opt),
                    a->mp.given[k], err.msg);
        else
            fprintf(stderr, "rockfuzz material: %s\n", err.msg);
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
    collect_params(&a.mp);
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
