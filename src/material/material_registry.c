/* material_registry.c - the one list of material laws (in rf_material_model
 * order), their names, the parameters every law takes (E, poisson), the
 * defaults and the check of a single value against its rule.  Adding a law:
 * its file (parameter table, validate, init, return map, yield function)
 * and its line in `laws` below (and its name in rf_material_model). */
#include "material/material_internal.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "core/util.h"

static const mat_law *const laws[] = {
    &mat_law_elastic,        /* RF_MATERIAL_ELASTIC */
    &mat_law_von_mises,      /* RF_MATERIAL_VON_MISES */
    &mat_law_drucker_prager, /* RF_MATERIAL_DRUCKER_PRAGER */
};
#define N_LAWS (sizeof laws / sizeof laws[0])

const rf_material_param rf_material_common_params[2] = {
    {.name = "E", .offset = offsetof(rf_material_params, E), .unit = "Pa", .metavar = "PA",
     .default_value = 68.2e9, .rule = RF_MATERIAL_RULE_POSITIVE, .flags = RF_MATERIAL_PARAM_REQUIRED,
     .help = "Young's modulus {}"},
    {.name = "poisson", .offset = offsetof(rf_material_params, poisson), .unit = "-", .metavar = "NU",
     .default_value = 0.25, .rule = RF_MATERIAL_RULE_POISSON, .flags = RF_MATERIAL_PARAM_REQUIRED,
     .help = "Poisson's ratio {}"},
};

size_t rf_material_n_laws(void)
{
    return N_LAWS;
}

const mat_law *mat_law_of(rf_material_model model)
{
    return (unsigned)model < N_LAWS ? laws[model] : NULL;
}

const rf_material_law_info *rf_material_law(rf_material_model model)
{
    const mat_law *law = mat_law_of(model);
    return law ? &law->info : NULL;
}

const char *rf_material_model_name(rf_material_model model)
{
    const mat_law *law = mat_law_of(model);
    return law ? law->info.name : "unknown";
}

static const char *law_name(size_t k)
{
    return laws[k]->info.name;
}

rf_status rf_material_model_parse(const char *name, rf_material_model *model, rf_error *err)
{
    int k = 0;
    rf_status st = rf_name_parse("material model", name, law_name, N_LAWS, &k, err);
    *model = st == RF_OK ? (rf_material_model)k : *model;
    return st;
}

double *rf_material_param_field(rf_material_params *p, const rf_material_param *param)
{
    return (double *)((char *)p + param->offset);
}

const rf_material_param *rf_material_param_find(const char *name)
{
    for (size_t i = 0; name && i < 2; i++)
        if (!strcmp(name, rf_material_common_params[i].name))
            return &rf_material_common_params[i];
    for (size_t k = 0; name && k < N_LAWS; k++)
        for (size_t i = 0; i < laws[k]->info.n_params; i++)
            if (!strcmp(name, laws[k]->info.params[i].name))
                return &laws[k]->info.params[i];
    return NULL;
}

void rf_material_params_default(rf_material_params *p)
{
    memset(p, 0, sizeof *p);
    p->model = RF_MATERIAL_ELASTIC;
    for (size_t i = 0; i < 2; i++)
        *rf_material_param_field(p, &rf_material_common_params[i]) = rf_material_common_params[i].default_value;
    for (size_t k = 0; k < N_LAWS; k++)
        for (size_t i = 0; i < laws[k]->info.n_params; i++)
            *rf_material_param_field(p, &laws[k]->info.params[i]) = laws[k]->info.params[i].default_value;
}

rf_status rf_material_param_check(const rf_material_param *param, double x, rf_error *err)
{
    const char *unit = strcmp(param->unit, "-") ? param->unit : "";
    const char *sp = *unit ? " " : "", *off = param->flags & RF_MATERIAL_PARAM_SWITCH ? " (0 = off)" : "";
    switch (param->rule) {
    case RF_MATERIAL_RULE_POSITIVE:
        if (x > 0.0 && isfinite(x))
            return RF_OK;
        return rf_fail(err, RF_EINVAL, "%s = %g%s%s: must be a finite number > 0", param->name, x, sp, unit);
    case RF_MATERIAL_RULE_NONNEGATIVE:
        if (x >= 0.0 && isfinite(x))
            return RF_OK;
        return rf_fail(err, RF_EINVAL, "%s = %g%s%s: must be finite and >= 0%s", param->name, x, sp, unit, off);
    case RF_MATERIAL_RULE_POISSON:
        if (x > -1.0 && x < 0.5)
            return RF_OK;
        return rf_fail(err, RF_EINVAL, "%s = %g: must lie in (-1, 0.5)", param->name, x);
    case RF_MATERIAL_RULE_ANGLE:
        if (x >= 0.0 && x < 0.5 * RF_PI)
            return RF_OK;
        return rf_fail(err, RF_EINVAL, "%s = %g deg: must lie in [0, 90) degrees", param->name, x * 180.0 / RF_PI);
    }
    return rf_fail(err, RF_EINTERNAL, "%s: no rule %d", param->name, (int)param->rule);
}

static double value_of(const rf_material_params *p, const rf_material_param *param)
{
    return *(const double *)((const char *)p + param->offset);
}

/* Every value of p that the law reads, against its rule (E and poisson first). */
rf_status mat_check_values(const mat_law *law, const rf_material_params *p, rf_error *err)
{
    rf_status st = RF_OK;
    for (size_t i = 0; i < 2 && st == RF_OK; i++)
        st = rf_material_param_check(&rf_material_common_params[i], value_of(p, &rf_material_common_params[i]), err);
    for (size_t i = 0; i < law->info.n_params && st == RF_OK; i++)
        st = rf_material_param_check(&law->info.params[i], value_of(p, &law->info.params[i]), err);
    return st;
}
