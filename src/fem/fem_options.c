/* fem_options.c - the settings of the FE solvers: the one table of the public
 * options (rf_fem_option_fields: name, place, kind, unit, default, range,
 * help) and what loops over it (defaults, parsing, validation, formatting),
 * the internal tuning's defaults and checks (fem_tuning.h), the resolution of
 * the automatic settings (refinement, domain radius, boundary, kinematics,
 * ALE), and the choice between the axisymmetric and the 3D model. */
#include "fem_tuning.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"

_Static_assert(sizeof(rf_fem_boundary) == sizeof(int) && sizeof(rf_fem_kinematics) == sizeof(int) &&
                   sizeof(rf_fem_ale) == sizeof(int) && sizeof(rf_fem_sizing) == sizeof(int) &&
                   sizeof(rf_fem_ground) == sizeof(int),
               "a CHOICE row is stored as an int");

/* Names indexed by the enum values. */
static const char *const boundary_names[] = {"fixed", "absorbing", "auto", NULL};
static const char *const kinematics_names[] = {"auto", "off", "on", NULL};
static const char *const ale_names[] = {"off", "on", NULL};
static const char *const sizing_names[] = {"hertz", "soil", NULL};
static const char *const ground_names[] = {"incidence", "stable", NULL};

#define ROW(field, kind, unit, vname, def, lo, hi, lo3, hi3, zero_auto, choices, help) \
    {#field, offsetof(rf_fem_options, field), kind, unit, vname, def, lo, hi, lo3, hi3, zero_auto, choices, help}
#define REAL RF_FEM_OPTION_REAL
#define CHOICE RF_FEM_OPTION_CHOICE

const rf_fem_option_field rf_fem_option_fields[] = {
    ROW(refinement, REAL, "", "A_OVER_H", 0, 2, 400, 2, 100, 1, NULL,
        "elements across the Hertz contact radius a (a/h); 0 = automatic: 10 axisymmetric (converged to "
        "< 0.1 %), 3 in the 3D model"),
    ROW(domain_factor, REAL, "", "F", 0, 3, 1e4, 3, 1e4, 1, NULL,
        "slope domain radius / r0; 0 = automatic: sized so that 2 L / c_p >= 1.25 Hertz t_c, at least 10 "
        "(no reflected wave returns into the elastic contact); boundary fixed with domain_factor 10 is the "
        "seed paper's model"),
    ROW(boundary, CHOICE, "", "KIND", RF_FEM_BOUNDARY_AUTO, 0, 0, 0, 0, 0, boundary_names,
        "outer boundary of the slope domain; auto: absorbing dashpots with a layer or a plastic body, whose "
        "contact outlasts the P wave's round trip in the automatic domain, fixed for elastic bodies"),
    ROW(large_deformation, CHOICE, "", "K", RF_FEM_KINEMATICS_AUTO, 0, 0, 0, 0, 0, kinematics_names,
        "auto: on when a body is elasto-plastic.  on: updated Lagrangian (current geometry, objective "
        "Hughes-Winget stress rotation, contact on the deformed surfaces); off: small strain on the "
        "reference geometry (docs/validation-plastic.md sections 6e, 9c)"),
    ROW(ale, CHOICE, "", "K", RF_FEM_ALE_OFF, 0, 0, 0, 0, 0, ale_names,
        "axisymmetric large deformation: ALE rezoning of the soil.  on: where an element's size falls below "
        "half its reference size, the interior nodes around it are smoothed and the stresses, internal "
        "variables and velocities remapped (conservative donor cell; the energy it changes is reported as "
        "its own term).  Use it when a run fails with \"element N was compressed below the stability bound\" "
        "(soil squeezed under the block's tip; docs/validation-plastic.md 8b)"),
    ROW(end_time, REAL, "s", "S", 0, 0, INFINITY, 0, INFINITY, 0, NULL,
        "simulated time; 0 = automatic: until the contact is open and the boulder moves away, at least 1.3 "
        "Hertz durations; past 3 durations up to a bound scaled by the contact's progress, then the run "
        "fails rather than report an unfinished rebound.  A given end time stops there (a warning if the "
        "impact has not ended)"),
    ROW(mesh_sizing, CHOICE, "", "KIND", RF_FEM_SIZING_HERTZ, 0, 0, 0, 0, 0, sizing_names,
        "axisymmetric, a thick soil layer: what a/h counts elements across.  hertz: the finer of the rock's and "
        "the layer's elastic Hertz contact radii (as every impact); soil: the layer's own contact, estimated "
        "from its crush pressure and hardening, with the uniform zone over it (the impact tables' sizing, "
        "with refinement 6: docs/soil-impacts.md section 4).  A thin layer and the 3D model ignore it"),
    ROW(rock_mass_scale, REAL, "", "K", 1, 1, 1e4, 1, 1e4, 0, NULL,
        "a layer over rock: the rock's inertia (its density in the masses and the dashpots, not "
        "its weight) times K.  Under a soft layer the stiff rock sets the explicit time step; K > 1 lengthens "
        "it by sqrt(K) up to the bound of the layer's contact face (about 3-4x: docs/soil-impacts.md section "
        "3, where it holds).  1 = the rock itself; ignored without a layer"),
    ROW(ground, CHOICE, "", "KIND", RF_FEM_GROUND_INCIDENCE, 0, 0, 0, 0, 0, ground_names,
        "3D model with gravity: the ground's inclination under an oblique impact.  incidence: the slope is "
        "inclined at the incidence (the boulder falls vertically).  stable: at the incidence, but no steeper "
        "than the layer (and an elasto-plastic slope) stands with an infinite-slope factor of safety of 1.25; "
        "steeper incidences come at their angle onto that ground (the impact tables' setting on a soil layer: "
        "docs/soil-impacts.md section 4b).  The axisymmetric model ignores it"),
    ROW(threads, RF_FEM_OPTION_COUNT, "", "N", 1, 0, 1024, 0, 1024, 0, NULL,
        "threads of one impact, 0..1024 (0 = 1; rockfuzz impact without it, or with 0: all cores for the "
        "3D model, 1 for the axisymmetric one); the results are the same bit for bit"),
};
const size_t rf_fem_n_option_fields = sizeof rf_fem_option_fields / sizeof rf_fem_option_fields[0];

static void *member(rf_fem_options *o, const rf_fem_option_field *f)
{
    return (char *)o + f->offset;
}

static const void *cmember(const rf_fem_options *o, const rf_fem_option_field *f)
{
    return (const char *)o + f->offset;
}

static int n_choices(const rf_fem_option_field *f)
{
    int n = 0;
    while (f->choices && f->choices[n])
        n++;
    return n;
}

void rf_fem_options_default(rf_fem_options *opt)
{
    memset(opt, 0, sizeof *opt);
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *f = &rf_fem_option_fields[k];
        if (f->kind == RF_FEM_OPTION_REAL)
            *(double *)member(opt, f) = f->def;
        else
            *(int *)member(opt, f) = (int)f->def;
    }
}

void rf_fem_soil_table_preset(rf_fem_options *opt)
{
    opt->mesh_sizing = RF_FEM_SIZING_SOIL;
    opt->refinement = RF_FEM_SOIL_PRESET_REFINEMENT;
    opt->rock_mass_scale = RF_FEM_SOIL_PRESET_ROCK_SCALE;
}

const rf_fem_option_field *rf_fem_option_find(const char *name)
{
    for (size_t k = 0; name && k < rf_fem_n_option_fields; k++)
        if (!strcmp(name, rf_fem_option_fields[k].name))
            return &rf_fem_option_fields[k];
    return NULL;
}

void rf_fem_option_choices(const rf_fem_option_field *f, char *buf, size_t size)
{
    size_t len = 0;
    buf[0] = '\0';
    for (int i = 0; i < n_choices(f) && len < size; i++)
        len += (size_t)snprintf(buf + len, size - len, "%s%s", i ? " | " : "", f->choices[i]);
}

/* The row's check of a number x (three_d: the 3D limits). */
static rf_status check_number(const rf_fem_option_field *f, double x, int three_d, rf_error *err)
{
    const double lo = three_d ? f->lo3 : f->lo, hi = three_d ? f->hi3 : f->hi;
    const char *model = three_d ? "3d" : "";
    if (f->zero_auto && x == 0)
        return RF_OK;
    if (!isfinite(x))
        return rf_fail(err, RF_EINVAL, "fem%s: %s = %g must be a finite number", model, f->name, x);
    if (f->kind == RF_FEM_OPTION_COUNT && x != floor(x))
        return rf_fail(err, RF_EINVAL, "fem%s: %s = %g must be an integer", model, f->name, x);
    if (!(x >= lo && x <= hi))
        return rf_fail(err, RF_EINVAL, "fem%s: %s = %g must lie in [%g, %g]%s%s%s%s", model, f->name, x, lo, hi,
                       f->unit[0] ? " [" : "", f->unit, f->unit[0] ? "]" : "", f->zero_auto ? " (0 = automatic)" : "");
    return RF_OK;
}

/* The row's check of the value in o. */
static rf_status check_row(const rf_fem_options *o, const rf_fem_option_field *f, int three_d, rf_error *err)
{
    if (f->kind == RF_FEM_OPTION_REAL)
        return check_number(f, *(const double *)cmember(o, f), three_d, err);
    const int v = *(const int *)cmember(o, f);
    if (f->kind == RF_FEM_OPTION_COUNT)
        return check_number(f, v, three_d, err);
    if (v < 0 || v >= n_choices(f)) {
        char list[128];
        rf_fem_option_choices(f, list, sizeof list);
        return rf_fail(err, RF_EINVAL, "fem%s: %s = %d is unknown (accepted: %s)", three_d ? "3d" : "", f->name, v,
                       list);
    }
    return RF_OK;
}

rf_status rf_fem_option_set(rf_fem_options *o, const rf_fem_option_field *f, double x, rf_error *err)
{
    if (f->kind == RF_FEM_OPTION_CHOICE)
        return rf_fail(err, RF_EINVAL, "fem: %s takes a name, not the number %g", f->name, x);
    rf_status st = check_number(f, x, 0, err);
    if (st != RF_OK)
        return st;
    if (f->kind == RF_FEM_OPTION_REAL)
        *(double *)member(o, f) = x;
    else
        *(int *)member(o, f) = (int)x;
    return RF_OK;
}

rf_status rf_fem_option_parse(rf_fem_options *o, const rf_fem_option_field *f, const char *text, rf_error *err)
{
    if (!text)
        text = "(null)";
    if (f->kind == RF_FEM_OPTION_CHOICE) {
        const int i = rf_name_index(text, f->choices, n_choices(f));
        char list[128];
        rf_fem_option_choices(f, list, sizeof list);
        if (i < 0)
            return rf_fail(err, RF_EINVAL, "%s '%s' is unknown (accepted: %s)", f->name, text, list);
        *(int *)member(o, f) = i;
        return RF_OK;
    }
    char *end = NULL;
    errno = 0;
    const double x = strtod(text, &end);
    if (end == text || *end != '\0' || errno == ERANGE)
        return rf_fail(err, RF_EINVAL, "%s '%s' is not a%s number", f->name, text,
                       f->kind == RF_FEM_OPTION_COUNT ? "n integer" : "");
    return rf_fem_option_set(o, f, x, err);
}

void rf_fem_option_format(const rf_fem_options *o, const rf_fem_option_field *f, char *buf, size_t size)
{
    if (f->kind == RF_FEM_OPTION_REAL) {
        snprintf(buf, size, "%.17g", *(const double *)cmember(o, f));
        return;
    }
    const int v = *(const int *)cmember(o, f);
    if (f->kind == RF_FEM_OPTION_COUNT || v < 0 || v >= n_choices(f))
        snprintf(buf, size, "%d", v);
    else
        snprintf(buf, size, "%s", f->choices[v]);
}

/* The validated numerics (docs/validation*.md, docs/fem-speed.md). */
static const rf_fem_tuning tuning_defaults = {
    .boulder_mesh_ratio = 1, .fine_zone_factor = 2.5, .grading = 1.15, .dt_safety = 0.9,
    .surface_mass_kappa = 0.1, .surface_mass_3d = 1, .sphere_contact_3d = 1, .vtk_frames = 60,
    .history_stride = 0, .max_elements = 2000000, .duration_threshold = 1e-6,
    .kernel = {RF_FEM_KERNEL_STIFFNESS, RF_FEM_KERNEL_STIFFNESS}, .contact_single_pivot = 0,
    .ale_trigger = 0.5, .ale_sweeps = 10,
};

void fem_tuning_default(rf_fem_tuning *t)
{
    *t = tuning_defaults;
}

const rf_fem_tuning *fem_tuning_of(const rf_fem_options *opt)
{
    return opt && opt->tuning ? opt->tuning : &tuning_defaults;
}

void rf_fem3d_options_default(rf_fem3d_options *o3)
{
    memset(o3, 0, sizeof *o3);
    o3->full_model = 0;
    o3->fine_box_factor = 1.3;
    o3->elongation = 1.0;
    o3->layer_aspect = 1.6;
    o3->boulder_inner = 4.0;
}

/* The enum parsers: the table's CHOICE rows. */
static rf_status parse_choice(const char *option, const char *name, int *v, rf_error *err)
{
    rf_fem_options o;
    const rf_fem_option_field *f = rf_fem_option_find(option);
    rf_status st = rf_fem_option_parse(&o, f, name, err);
    if (st == RF_OK)
        *v = *(const int *)cmember(&o, f);
    return st;
}

const char *rf_fem_boundary_name(rf_fem_boundary b)
{
    return (unsigned)b < 3 ? boundary_names[b] : "unknown";
}

rf_status rf_fem_boundary_parse(const char *name, rf_fem_boundary *b, rf_error *err)
{
    int v = 0;
    rf_status st = parse_choice("boundary", name, &v, err);
    if (st == RF_OK)
        *b = (rf_fem_boundary)v;
    return st;
}

const char *rf_fem_kinematics_name(rf_fem_kinematics k)
{
    return (unsigned)k < 3 ? kinematics_names[k] : "unknown";
}

rf_status rf_fem_kinematics_parse(const char *name, rf_fem_kinematics *k, rf_error *err)
{
    int v = 0;
    rf_status st = parse_choice("large_deformation", name, &v, err);
    if (st == RF_OK)
        *k = (rf_fem_kinematics)v;
    return st;
}

const char *rf_fem_ale_name(rf_fem_ale a)
{
    return (unsigned)a < 2 ? ale_names[a] : "unknown";
}

rf_status rf_fem_ale_parse(const char *name, rf_fem_ale *a, rf_error *err)
{
    int v = 0;
    rf_status st = parse_choice("ale", name, &v, err);
    if (st == RF_OK)
        *a = (rf_fem_ale)v;
    return st;
}

/* A layer or a plastic body makes the contact last many times the P wave's
 * round trip in the automatic domain (sized from the elastic Hertz duration of
 * boulder and bedrock: S5's soil contact 26 ms against 2.5 ms); only the
 * dashpots keep the reflections out of it.  Elastic bodies on the half-space
 * keep the fixed boundary of the seed paper (docs/validation-plastic.md
 * section 10b). */
rf_fem_boundary rf_fem_boundary_resolve(rf_fem_boundary b, const rf_impact_input *in)
{
    if (b != RF_FEM_BOUNDARY_AUTO)
        return b;
    return in->layer_thickness > 0 || rf_impact_has_plastic_body(in) ? RF_FEM_BOUNDARY_ABSORBING
                                                                      : RF_FEM_BOUNDARY_FIXED;
}

int rf_fem_large_deformation(const rf_fem_options *opt, const rf_impact_input *in)
{
    if (opt->large_deformation != RF_FEM_KINEMATICS_AUTO)
        return opt->large_deformation == RF_FEM_LARGE_DEFORMATION;
    return rf_impact_has_plastic_body(in);
}

/* On when asked for, and only in large deformation (docs/validation-plastic.md section 8b). */
int rf_fem_ale_enabled(const rf_fem_options *opt, const rf_impact_input *in)
{
    return opt->ale == RF_FEM_ALE_ON && rf_fem_large_deformation(opt, in);
}

/* Closed ranges of the tuning's real-valued settings; lo3/hi3 are the 3D limits. */
static const struct {
    const char *name;
    size_t offset;
    double lo, hi, lo3, hi3;
    const char *why;
} tuning_rules[] = {
    {"boulder_mesh_ratio", offsetof(rf_fem_tuning, boulder_mesh_ratio), 0.25, 1.25, 0.25, 4,
     "(the boulder surface carries the contact nodes and must not be much coarser than the slope)"},
    {"fine_zone_factor", offsetof(rf_fem_tuning, fine_zone_factor), 1.5, 10, 1.5, 10, "(fine zone / a)"},
    {"grading", offsetof(rf_fem_tuning, grading), 1, 2, 1, 2, "(element-size growth)"},
    {"dt_safety", offsetof(rf_fem_tuning, dt_safety), 1e-6, 4, 1e-6, 1, "(time step / eigenvalue bound)"},
    {"surface_mass_kappa", offsetof(rf_fem_tuning, surface_mass_kappa), 0, 1, 0, 1,
     "(contact-face element eigenvalue / the mesh's largest after the mass redistribution; 0 = off)"},
    {"duration_threshold", offsetof(rf_fem_tuning, duration_threshold), 0, 0.4999999, 0, 0.4999999,
     "(share of F_max)"},
};

static rf_status switch_check(const char *name, int v, rf_error *err)
{
    if (v != 0 && v != 1)
        return rf_fail(err, RF_EINVAL, "fem: %s = %d must be 0 (off) or 1 (on)", name, v);
    return RF_OK;
}

rf_status fem_tuning_validate(const rf_fem_tuning *t, int three_d, rf_error *err)
{
    for (size_t k = 0; k < sizeof tuning_rules / sizeof tuning_rules[0]; k++) {
        const double x = *(const double *)((const char *)t + tuning_rules[k].offset);
        const double lo = three_d ? tuning_rules[k].lo3 : tuning_rules[k].lo;
        const double hi = three_d ? tuning_rules[k].hi3 : tuning_rules[k].hi;
        if (!(x >= lo && x <= hi))
            return rf_fail(err, RF_EINVAL, "fem%s: %s = %g must lie in [%g, %g] %s", three_d ? "3d" : "",
                           tuning_rules[k].name, x, lo, hi, tuning_rules[k].why);
    }
    rf_status st;
    if ((st = switch_check("surface_mass_3d", t->surface_mass_3d, err)) != RF_OK ||
        (st = switch_check("sphere_contact_3d", t->sphere_contact_3d, err)) != RF_OK ||
        (st = switch_check("contact_single_pivot", t->contact_single_pivot, err)) != RF_OK ||
        (st = switch_check("end_at_separation", t->end_at_separation, err)) != RF_OK)
        return st;
    if (!(t->ale_trigger > 0 && t->ale_trigger < 1))
        return rf_fail(err, RF_EINVAL, "fem: ale_trigger = %g must lie in (0, 1) (share of the reference element size)",
                       t->ale_trigger);
    if (t->ale_sweeps < 0 || t->ale_sweeps > 1000)
        return rf_fail(err, RF_EINVAL, "fem: ale_sweeps = %d must lie in [0, 1000]", t->ale_sweeps);
    if (t->max_elements < 1)
        return rf_fail(err, RF_EINVAL, "fem: max_elements = %ld must be >= 1", t->max_elements);
    for (int b = 0; b < 2; b++)
        if ((unsigned)t->kernel[b] > RF_FEM_KERNEL_POINTS)
            return rf_fail(err, RF_EINVAL, "fem%s: kernel[%d] = %d is not available (0 stiffness, 1 points)",
                           three_d ? "3d" : "", b, (int)t->kernel[b]);
    return RF_OK;
}

rf_status rf_fem_options_validate(const rf_fem_options *o, int three_d, rf_error *err)
{
    if (!o)
        return rf_fail(err, RF_EINVAL, "fem: NULL options");
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        rf_status st = check_row(o, &rf_fem_option_fields[k], three_d, err);
        if (st != RF_OK)
            return st;
    }
    return o->tuning ? fem_tuning_validate(o->tuning, three_d, err) : RF_OK;
}

double rf_fem_refinement(const rf_fem_options *opt, int three_d)
{
    if (opt->refinement > 0)
        return opt->refinement;
    return three_d ? RF_FEM_REFINEMENT_3D : RF_FEM_REFINEMENT_AXI;
}

/* Automatic: the P wave reflected at distance L returns to the contact after
 * 2 L / c_p; it must not arrive before the contact ends (Hertz t_c with a
 * margin for the finite-body lengthening of the contact). */
double rf_fem_domain_factor(const rf_fem_options *opt, const rf_impact_input *in)
{
    if (opt->domain_factor > 0)
        return opt->domain_factor;
    rf_hertz_reference H;
    rf_wave_speeds w;
    rf_impact_hertz_reference(in, &H);
    rf_impact_wave_speeds(in, 1, &w);
    double L = 0.5 * RF_FEM_DOMAIN_MARGIN * w.p * H.duration;
    return fmax(RF_FEM_DOMAIN_MIN, ceil(L / in->radius));
}

int rf_fem_needs_3d(const rf_impact_input *in)
{
    if (in->slope_angle != 0.0)
        return 1;
    if (!(in->friction > 0.0))
        return 0;
    if (rf_impact_has_plastic_body(in))
        return 0; /* the axisymmetric model (large deformation, gravity), with Coulomb friction */
    const int layer = in->layer_thickness > 0;
    /* Dundurs' beta of the boulder (a rigid one: E -> infinity) and the
     * surface it meets, the layer's when there is one */
    const double Eb = in->boulder_material == RF_MATERIAL_RIGID_BODY ? INFINITY : in->boulder_E;
    const double Es = layer ? in->layer_E : in->slope_E, nus = layer ? in->layer_poisson : in->slope_poisson;
    return fabs(rf_dundurs_beta(Eb, in->boulder_poisson, Es, nus)) > 1e-12;
}
