/* impact_input.c - the impact input and output: nominal values, validation
 * (one rule table), the cleared output, and the geometry and material
 * quantities every impact solver shares (mass, inertia, contact curvature,
 * effective modulus, wave speeds).  Geometry follows impact_refs.md sec. 1.1. */
#include "core/util.h"
#include "impact/impact_internal.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void rf_impact_input_default(rf_impact_input *in)
{
    memset(in, 0, sizeof *in);
    for (size_t k = 0; k < rf_impact_n_fields; k++)
        rf_impact_field_store(in, &rf_impact_fields[k], rf_impact_fields[k].def);
    in->boulder_material = in->slope_material = in->layer_material = RF_MATERIAL_ELASTIC;
}

double rf_impact_gravity(const rf_impact_input *in, int three_d)
{
    if (in->gravity >= 0.0)
        return in->gravity;
    (void)three_d; /* both FE models resolve auto alike (the 3D model has gravity since issue 10) */
    return rf_impact_has_plastic_body(in) ? RF_GRAVITY_STANDARD : 0.0;
}

int rf_impact_has_plastic_body(const rf_impact_input *in)
{
    const int boulder = in->boulder_material != RF_MATERIAL_ELASTIC && in->boulder_material != RF_MATERIAL_RIGID_BODY;
    const int layer = in->layer_thickness > 0.0 && in->layer_material != RF_MATERIAL_ELASTIC;
    return boulder || layer || in->slope_material != RF_MATERIAL_ELASTIC;
}

rf_status rf_impact_gravity_parse(const char *text, double *gravity, rf_error *err)
{
    if (text && !strcmp(text, "auto")) {
        *gravity = RF_GRAVITY_AUTO;
        return RF_OK;
    }
    char *end = NULL;
    double g = text ? strtod(text, &end) : NAN;
    if (!text || end == text || *end || !isfinite(g) || g < 0.0)
        return rf_fail(err, RF_EINVAL, "gravity '%s' must be auto or a finite value >= 0 [m/s^2]",
                       text ? text : "(null)");
    *gravity = g;
    return RF_OK;
}

rf_status rf_impact_boulder_material_parse(const char *name, rf_material_model *m, rf_error *err)
{
    if (name && !strcmp(name, "rigid")) {
        *m = RF_MATERIAL_RIGID_BODY;
        return RF_OK;
    }
    rf_material_model x;
    if (rf_material_model_parse(name, &x, NULL) == RF_OK && x != RF_MATERIAL_DRUCKER_PRAGER) {
        *m = x;
        return RF_OK;
    }
    return rf_fail(err, RF_EINVAL, "boulder material '%s' is not one of elastic, von_mises, rigid",
                   name ? name : "(null)");
}

const char *rf_impact_material_name(rf_material_model m)
{
    return m == RF_MATERIAL_RIGID_BODY ? "rigid" : rf_material_model_name(m);
}

static const char *const body_names[3] = {"boulder", "slope", "layer"};
static const rf_material_model *body_model(const rf_impact_input *in, int body)
{
    return body == 0 ? &in->boulder_material : body == 2 ? &in->layer_material : &in->slope_material;
}

/* The input field "<body>_<parameter>" of a material parameter, or NULL (the
 * boulder has no soil parameters). */
static const rf_impact_field *body_field(int body, const rf_material_param *param)
{
    char name[64];
    snprintf(name, sizeof name, "%s_%s", body_names[body], param->name);
    return rf_impact_field_find(name);
}

/* Copies the body's value of each parameter into p (a parameter every law takes, or of any law). */
static void copy_param(const rf_impact_input *in, int body, const rf_material_param *param, rf_material_params *p)
{
    const rf_impact_field *f = body_field(body, param);
    if (f)
        *rf_material_param_field(p, param) = *(const double *)((const char *)in + f->offset);
}

/* The fields "<body>_<name>" of rf_impact_fields, for every parameter of the material registry. */
void rf_impact_material_params(const rf_impact_input *in, int body, rf_material_params *p)
{
    rf_material_params_default(p);
    const rf_material_model model = *body_model(in, body);
    p->model = body == 0 && model == RF_MATERIAL_RIGID_BODY ? RF_MATERIAL_ELASTIC : model;
    for (size_t i = 0; i < 2; i++)
        copy_param(in, body, &rf_material_common_params[i], p);
    for (size_t k = 0; k < rf_material_n_laws(); k++) {
        const rf_material_law_info *law = rf_material_law((rf_material_model)k);
        for (size_t i = 0; i < law->n_params; i++)
            copy_param(in, body, &law->params[i], p);
    }
}

/* The input field a material message ("name = ...", rf_material_init) names:
 * "<body>_<name>", or "<body>_material". */
static const char *field_of_message(int body, const char *msg)
{
    const rf_material_param *param = NULL;
    char name[64];
    size_t n = strcspn(msg, " ");
    snprintf(name, sizeof name, "%.*s", (int)n, msg);
    param = rf_material_param_find(name);
    const rf_impact_field *f = param ? body_field(body, param) : NULL;
    return f ? f->name : body == 0 ? "boulder_material" : body == 1 ? "slope_material" : "layer_material";
}

/* NULL if the materials are valid, else the impact field at fault; msg gets
 * the library's message prefixed with the body. */
static const char *material_invalid(const rf_impact_input *in, rf_error *err)
{
    if ((unsigned)in->boulder_material > RF_MATERIAL_VON_MISES && in->boulder_material != RF_MATERIAL_RIGID_BODY) {
        rf_fail(err, RF_EINVAL, "boulder_material = %s: the boulder may be elastic, von_mises or rigid",
                rf_impact_material_name(in->boulder_material));
        return "boulder_material";
    }
    if (in->layer_thickness > 0.0) { /* the layer's elasticity (the slope's is in the table) */
        const char *bad = !(isfinite(in->layer_density) && in->layer_density > 0.0) ? "layer_density"
                          : !(isfinite(in->layer_E) && in->layer_E > 0.0)           ? "layer_E"
                          : !(isfinite(in->layer_poisson) && in->layer_poisson > -1.0 && in->layer_poisson < 0.5) ? "layer_poisson"
                                                                                     : NULL;
        if (bad) {
            double x = bad[6] == 'd' ? in->layer_density : bad[6] == 'E' ? in->layer_E : in->layer_poisson;
            rf_fail(err, RF_EINVAL, "%s = %g: must be %s (layer_thickness = %g m)", bad, x,
                    bad[6] == 'p' ? "in (-1, 0.5)" : "finite and > 0", in->layer_thickness);
            return bad;
        }
    }
    for (int b = 0; b < 3; b++) {
        rf_material_params p;
        rf_material m;
        rf_error e = {0};
        if (b == 2 && !(in->layer_thickness > 0.0))
            continue;
        rf_impact_material_params(in, b, &p);
        if (p.model == RF_MATERIAL_ELASTIC || rf_material_init(&m, &p, &e) == RF_OK)
            continue;
        const char *name = field_of_message(b, e.msg);
        rf_fail(err, RF_EINVAL, "%s_%s (%s material %s)", body_names[b], e.msg, body_names[b],
                rf_material_model_name(p.model));
        return name;
    }
    return NULL;
}

/* The rule a field breaks, for messages. */
static void rule_text(const rf_impact_field *f, char *buf, size_t size)
{
    switch (f->check) {
    case RF_CHECK_POSITIVE: snprintf(buf, size, "must be finite and > 0 [%s]", f->unit); return;
    case RF_CHECK_NONNEGATIVE:
        snprintf(buf, size, f->unit[0] ? "must be finite and >= 0 [%s]" : "must be finite and >= 0", f->unit);
        return;
    case RF_CHECK_POISSON: snprintf(buf, size, "Poisson's ratio must lie in (-1, 0.5)"); return;
    case RF_CHECK_INCLINATION: snprintf(buf, size, "must lie in [0, 90) degrees"); return;
    case RF_CHECK_GRAVITY:
        snprintf(buf, size, "must be >= 0 [m/s^2] (its magnitude: it acts along -z), or RF_GRAVITY_AUTO (-1) for "
                 "auto (9.81 with a plastic body, else 0)");
        return;
    case RF_CHECK_NONE: break;
    }
    buf[0] = '\0';
}

static double stored(const rf_impact_input *in, const rf_impact_field *f)
{
    return *(const double *)((const char *)in + f->offset);
}

/* The first field that breaks its rule (table order), NULL if none.  A
 * vertical axis without a horizontal one is reported on vertical_axis. */
static const rf_impact_field *first_invalid(const rf_impact_input *in)
{
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        if (!rf_impact_field_ok(f, stored(in, f)))
            return f;
        if (f->offset == offsetof(rf_impact_input, vertical_axis) && in->vertical_axis > 0.0 &&
            !(in->horizontal_axis > 0.0))
            return f;
    }
    return NULL;
}

const char *rf_impact_input_first_invalid(const rf_impact_input *in)
{
    const rf_impact_field *f = first_invalid(in);
    return f ? f->name : material_invalid(in, NULL);
}

rf_status rf_impact_input_validate(const rf_impact_input *in, rf_error *err)
{
    if (!in)
        return rf_fail(err, RF_EINTERNAL, "impact input is NULL");
    const rf_impact_field *f = first_invalid(in);
    if (!f)
        return material_invalid(in, err) ? RF_EINVAL : RF_OK;
    double x = stored(in, f);
    char rule[200];
    rule_text(f, rule, sizeof rule);
    if (f->kind == RF_FIELD_DEGREES)
        return rf_fail(err, RF_EINVAL, "%s = %g rad (%g deg): %s", f->name, x, x * 180.0 / RF_PI, rule);
    if (f->offset == offsetof(rf_impact_input, vertical_axis) && rf_impact_field_ok(f, x))
        return rf_fail(err, RF_EINVAL,
                       "vertical_axis = %g: a spheroid needs horizontal_axis > 0 as well "
                       "(horizontal_axis = %g)", x, in->horizontal_axis);
    return rf_fail(err, RF_EINVAL, "%s = %g: %s", f->name, x, rule);
}

double rf_dundurs_beta(double E1, double nu1, double E2, double nu2)
{
    if (isinf(E1))
        return (1.0 - 2.0 * nu2) / (2.0 * (1.0 - nu2));
    const double G1 = E1 / (2.0 * (1.0 + nu1)), G2 = E2 / (2.0 * (1.0 + nu2));
    return (G1 * (1.0 - 2.0 * nu2) - G2 * (1.0 - 2.0 * nu1)) / (2.0 * (G1 * (1.0 - nu2) + G2 * (1.0 - nu1)));
}

double rf_impact_effective_modulus(const rf_impact_input *in)
{
    double xb = in->boulder_material == RF_MATERIAL_RIGID_BODY
                    ? 0.0
                    : (1.0 - in->boulder_poisson * in->boulder_poisson) / in->boulder_E;
    double xs = (1.0 - in->slope_poisson * in->slope_poisson) / in->slope_E;
    return 1.0 / (xb + xs);
}

static int is_spheroid(const rf_impact_input *in) { return in->horizontal_axis > 0.0; }

double rf_impact_vertical_semi_axis(const rf_impact_input *in)
{
    if (!is_spheroid(in))
        return in->radius;
    if (in->vertical_axis > 0.0)
        return in->vertical_axis;
    return in->radius * in->radius * in->radius / (in->horizontal_axis * in->horizontal_axis);
}

double rf_impact_mass(const rf_impact_input *in)
{
    if (!is_spheroid(in))
        return 4.0 / 3.0 * RF_PI * in->radius * in->radius * in->radius * in->boulder_density;
    double c = in->horizontal_axis, d = rf_impact_vertical_semi_axis(in);
    return 4.0 / 3.0 * RF_PI * c * c * d * in->boulder_density;
}

double rf_impact_moment_of_inertia(const rf_impact_input *in)
{
    double m = rf_impact_mass(in);
    if (!is_spheroid(in))
        return 0.4 * m * in->radius * in->radius;
    double c = in->horizontal_axis, d = rf_impact_vertical_semi_axis(in);
    return 0.2 * m * (c * c + d * d);
}

double rf_impact_contact_curvature_radius(const rf_impact_input *in)
{
    if (!is_spheroid(in))
        return in->radius;
    /* both principal radii at the lower pole of a spheroid (c, c, d) */
    double c = in->horizontal_axis;
    return c * c / rf_impact_vertical_semi_axis(in);
}

void rf_impact_wave_speeds(const rf_impact_input *in, int body, rf_wave_speeds *w)
{
    const double E = body ? in->slope_E : in->boulder_E, nu = body ? in->slope_poisson : in->boulder_poisson;
    const double rho = body ? in->slope_density : in->boulder_density;
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    w->p = sqrt((lam + 2 * mu) / rho);
    w->s = sqrt(mu / rho);
    w->rayleigh = w->s * (0.87 + 1.12 * nu) / (1 + nu); /* Viktorov */
}

void rf_impact_output_clear(rf_impact_output *out)
{
    *out = (rf_impact_output){0};
    out->contact_force_max = NAN;
    out->compression_max = NAN;
    out->contact_duration = NAN;
    out->contact_radius = NAN;
    out->R_n = out->R_t = out->R_ke = NAN;
    out->plastic_work = out->penetration_max = out->indentation_depth = NAN;
    out->equivalent_plastic_strain_max = NAN;
}

int rf_impact_en_identity(const rf_impact_law_settings *s, char *buf, size_t size)
{
    if (isnan(s->e_n))
        return snprintf(buf, size, " hunter_A=%.17g e_n=hunter", s->hunter_coefficient);
    return snprintf(buf, size, " e_n=%.17g", s->e_n);
}

/* The analytic models are elastic and homogeneous: a plastic body or a layer
 * needs the FE solver (a rigid boulder is E* = E_s/(1 - nu_s^2) for Hertz,
 * Hunter and rigid; MDR takes the boulder's own elastic constants). */
rf_status rf_impact_analytic_validate(const rf_impact_law *law, const rf_impact_input *in,
                                      const rf_impact_law_settings *s, rf_error *err)
{
    const char *solver = law->name;
    (void)s;
    if (in->layer_thickness > 0)
        return rf_fail(err, RF_EINVAL, "layer_thickness = %g m: the %s solver has no layer (use solver fem)",
                       in->layer_thickness, solver);
    if (in->slope_material != RF_MATERIAL_ELASTIC || in->boulder_material == RF_MATERIAL_VON_MISES)
        return rf_fail(err, RF_EINVAL, "%s = %s: the %s solver is elastic (use solver fem)",
                       in->slope_material != RF_MATERIAL_ELASTIC ? "slope_material" : "boulder_material",
                       in->slope_material != RF_MATERIAL_ELASTIC ? rf_material_model_name(in->slope_material)
                                                                 : "von_mises",
                       solver);
    if (in->gravity > 0)
        return rf_fail(err, RF_EINVAL, "gravity = %g m/s^2: the %s solver has no gravity (use solver fem, or "
                       "gravity auto or 0)", in->gravity, solver);
    return RF_OK;
}
