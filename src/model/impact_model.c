/* impact_model.c - the impact model behind the rf_model interface: a spec
 * (solver + crisp base input + the FE solvers' own options), the binding of
 * study parameter names to the physical inputs, and rf_impact_solve, the one
 * dispatch to the analytic models or the FE solvers (rf_fem_solve).  It sits
 * above src/impact (the problem) and src/fem (the solvers).  The model's
 * spec is read-only after creation; the warning counters and the pool of
 * idle FE workspaces (reused by the evaluations of any worker thread, one
 * workspace per running evaluation) are behind one mutex, so eval is
 * thread-safe. */
#include "rockfuzz/impact_model.h"
#include "core/util.h"
#include "rockfuzz/mdr.h"

#include <math.h>
#include <stddef.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const rf_impact_law fem_law; /* below */

/* The solvers, in rf_impact_solver order: adding one is its rf_impact_law (its
 * own file in src/impact) and its line here (and its name in rf_impact_solver). */
static const rf_impact_law *const solvers[] = {
    &fem_law,              /* RF_IMPACT_FEM */
    &rf_impact_law_hertz,  /* RF_IMPACT_HERTZ */
    &rf_impact_law_hunter, /* RF_IMPACT_HUNTER */
    &rf_impact_law_rigid,  /* RF_IMPACT_RIGID */
    &rf_impact_law_mdr,    /* RF_IMPACT_MDR */
};
#define N_SOLVERS (sizeof solvers / sizeof solvers[0])

size_t rf_impact_n_solvers(void)
{
    return N_SOLVERS;
}

const rf_impact_law *rf_impact_solver_law(rf_impact_solver s)
{
    return (unsigned)s < N_SOLVERS ? solvers[s] : NULL;
}

const char *rf_impact_solver_name(rf_impact_solver s)
{
    return (unsigned)s < N_SOLVERS ? solvers[s]->name : "unknown";
}

static const char *solver_name(size_t k)
{
    return solvers[k]->name;
}

rf_status rf_impact_solver_parse(const char *name, rf_impact_solver *s, rf_error *err)
{
    int k = 0;
    rf_status st = rf_name_parse("solver", name, solver_name, N_SOLVERS, &k, err);
    *s = st == RF_OK ? (rf_impact_solver)k : *s;
    return st;
}

void rf_impact_model_spec_default(rf_impact_model_spec *spec)
{
    memset(spec, 0, sizeof *spec);
    spec->solver = RF_IMPACT_FEM;
    rf_impact_input_default(&spec->base);
    spec->e_n = NAN;
    spec->hunter_coefficient = RF_HUNTER_A_JOHNSON;
    rf_fem_options_default(&spec->fem);
}

/* warning (may be NULL, else RF_FEM_WARNING_MAX bytes) receives the FE
 * solver's warning, "" if none; it needs the solver's history. */
#define RF_FEM_WARNING_MAX 512
static rf_status solve_fem(const rf_impact_model_spec *spec, rf_fem_workspace *ws, const rf_impact_input *in,
                           rf_impact_output *out, char *warning, rf_error *err)
{
    if (!warning)
        return rf_fem_solve_ws(ws, in, &spec->fem, out, NULL, NULL, NULL, err);
    rf_fem_history hist;
    memset(&hist, 0, sizeof hist);
    rf_status st = rf_fem_solve_ws(ws, in, &spec->fem, out, &hist, NULL, NULL, err);
    snprintf(warning, RF_FEM_WARNING_MAX, "%s", st == RF_OK ? hist.warning : "");
    rf_fem_history_free(&hist);
    return st;
}

rf_status rf_impact_model_spec_validate(const rf_impact_model_spec *spec, rf_error *err)
{
    if (!rf_impact_solver_law(spec->solver))
        return rf_fail(err, RF_EINVAL, "impact solver %d is unknown", (int)spec->solver);
    if (!isnan(spec->e_n) && !(spec->e_n >= 0.0 && spec->e_n <= 1.0))
        return rf_fail(err, RF_EINVAL, "e_n = %g: the normal COR must lie in [0, 1] "
                                       "(or be unset to take Hunter's)", spec->e_n);
    if (!(isfinite(spec->hunter_coefficient) && spec->hunter_coefficient >= 0.0))
        return rf_fail(err, RF_EINVAL, "hunter_coefficient = %g: must be finite and >= 0",
                       spec->hunter_coefficient);
    if (spec->solver != RF_IMPACT_FEM)
        return RF_OK;
    if (spec->fem.tuning) /* its identity covers the table's options only */
        return rf_fail(err, RF_EINVAL, "impact model: fem.tuning must be NULL (the model runs the validated numerics)");
    rf_fem_options o = spec->fem;
    o.vtk_dir = NULL; /* the model ignores it (a study writes no VTK frames) */
    return rf_fem_options_validate(&o, 0, err); /* the 3D limits are checked when a 3D impact runs */
}

/* The FE solver as a registry entry: its context is the spec, a workspace and the warning buffer. */
typedef struct {
    const rf_impact_model_spec *spec;
    rf_fem_workspace *ws;
    char *warning;
} fem_context;

static rf_status fem_validate(const rf_impact_law *law, const rf_impact_input *in, const rf_impact_law_settings *s,
                              rf_error *err)
{
    (void)law, (void)in, (void)s, (void)err;
    return RF_OK; /* the FE solver takes every valid input */
}

static rf_status fem_law_solve(const rf_impact_input *in, const rf_impact_law_settings *s, rf_impact_output *out,
                               rf_error *err)
{
    const fem_context *c = s->context;
    return solve_fem(c->spec, c->ws, in, out, c->warning, err);
}

static int fem_law_identity(const rf_impact_law_settings *s, char *buf, size_t size);
static const rf_impact_law fem_law = {
    "fem",
    "explicit FE; axisymmetric for a normal impact\n(Coulomb friction on a plastic body), 3D half\n"
    "model for a slope or friction between elastic\ndissimilar bodies (docs/impact.md)",
    fem_validate, fem_law_solve, fem_law_identity};

/* A result every solver defines (the COR, the rebound velocities; R_t only with a tangential
 * velocity; the Hertz quantities for hertz, hunter and mdr) that is not finite is an error
 * naming the inputs: they exceed what the arithmetic holds (e.g. radius = 1e300 m). */
static rf_status check_finite(const rf_impact_model_spec *spec, const rf_impact_input *in,
                              const rf_impact_output *o, rf_error *err)
{
    if (spec->solver == RF_IMPACT_FEM)
        return RF_OK; /* the FE solvers check their own state as they go */
    const int hertz = spec->solver == RF_IMPACT_HERTZ || spec->solver == RF_IMPACT_HUNTER ||
                      spec->solver == RF_IMPACT_MDR;
    const double v[9] = {o->R_n, o->R_ke, o->v_n_after, o->omega_after, o->v_t_before != 0 ? o->R_t : 0,
                         hertz ? o->contact_force_max : 0, hertz ? o->compression_max : 0,
                         hertz ? o->contact_duration : 0, hertz ? o->contact_radius : 0};
    static const char *const names[9] = {"R_n", "R_ke", "v_n_after [m/s]", "omega_after [rad/s]", "R_t",
                                         "contact_force_max [N]", "compression_max [m]", "contact_duration [s]",
                                         "contact_radius [m]"};
    for (int k = 0; k < 9; k++)
        if (!isfinite(v[k]))
            return rf_fail(err, RF_EMODEL, "the %s result %s = %g is not finite: the inputs exceed what the "
                           "arithmetic holds (radius = %g m, velocity = %g m/s, boulder_density = %g kg/m^3, "
                           "boulder_E = %g Pa, slope_E = %g Pa)", rf_impact_solver_name(spec->solver), names[k],
                           v[k], in->radius, in->velocity, in->boulder_density, in->boulder_E, in->slope_E);
    return RF_OK;
}

/* rf_impact_solve with the FE warning (see solve_fem). */
static rf_status solve_any(const rf_impact_model_spec *spec, rf_fem_workspace *ws, const rf_impact_input *in,
                       rf_impact_output *out, char *warning, rf_error *err)
{
    if (warning)
        warning[0] = '\0';
    rf_status st = rf_impact_model_spec_validate(spec, err);
    if (st == RF_OK)
        st = rf_impact_input_validate(in, err);
    fem_context fc = {spec, ws, warning};
    const rf_impact_law_settings settings = {spec->e_n, spec->hunter_coefficient, &fc};
    const rf_impact_law *law = solvers[st == RF_OK ? spec->solver : 0];
    if (st == RF_OK)
        st = law->validate(law, in, &settings, err);
    if (st != RF_OK) {
        rf_impact_output_clear(out);
        return st;
    }
    return law->solve(in, &settings, out, err);
}

static rf_status solve(const rf_impact_model_spec *spec, rf_fem_workspace *ws, const rf_impact_input *in,
                       rf_impact_output *out, char *warning, rf_error *err)
{
    rf_status st = solve_any(spec, ws, in, out, warning, err);
    return st == RF_OK ? check_finite(spec, in, out, err) : st;
}

rf_status rf_impact_solve(const rf_impact_model_spec *spec, const rf_impact_input *in,
                          rf_impact_output *out, rf_error *err)
{
    return solve(spec, NULL, in, out, NULL, err);
}

/* --- the rf_model --- */

#define MAX_BOUND 64 /* > the number of bindable inputs */

typedef struct {
    rf_impact_model_spec spec;  /* fem.vtk_dir cleared: evaluations must not share a directory */
    size_t n_params;
    const rf_impact_field *field[MAX_BOUND]; /* the input each x[i] drives */
    /* FE warnings (e.g. reflected waves) of the evaluations so far, and the
       idle FE workspaces that evaluations (on any worker thread) reuse */
    pthread_mutex_t lock;
    rf_fem_workspace *idle[64];
    int n_idle;
    size_t evaluations, warned;
    char first_warning[RF_FEM_WARNING_MAX];
} impact_ctx;

static void ctx_destroy(void *p)
{
    impact_ctx *c = p;
    if (c) {
        for (int k = 0; k < c->n_idle; k++)
            rf_fem_workspace_free(c->idle[k]);
        pthread_mutex_destroy(&c->lock);
    }
    free(c);
}

/* An idle workspace (or a new one; NULL if out of memory: the solver then
 * allocates its own), and its return after the evaluation. */
static rf_fem_workspace *workspace_take(impact_ctx *c)
{
    rf_fem_workspace *ws = NULL;
    pthread_mutex_lock(&c->lock);
    if (c->n_idle > 0)
        ws = c->idle[--c->n_idle];
    pthread_mutex_unlock(&c->lock);
    return ws ? ws : rf_fem_workspace_alloc();
}

static void workspace_give(impact_ctx *c, rf_fem_workspace *ws)
{
    if (!ws)
        return;
    pthread_mutex_lock(&c->lock);
    if (c->n_idle < (int)(sizeof c->idle / sizeof c->idle[0])) {
        c->idle[c->n_idle++] = ws;
        ws = NULL;
    }
    pthread_mutex_unlock(&c->lock);
    rf_fem_workspace_free(ws);
}

static void note_evaluation(impact_ctx *c, const char *warning)
{
    pthread_mutex_lock(&c->lock);
    c->evaluations++;
    if (warning && warning[0] && c->warned++ == 0)
        snprintf(c->first_warning, sizeof c->first_warning, "%s", warning);
    pthread_mutex_unlock(&c->lock);
}

static size_t impact_warnings(void *p, char *buf, size_t size)
{
    impact_ctx *c = p;
    pthread_mutex_lock(&c->lock);
    size_t warned = c->warned;
    if (size > 0) {
        if (warned)
            snprintf(buf, size, "%zu of the %zu FE evaluations made in this process warned; the first: %s", warned,
                     c->evaluations, c->first_warning);
        else
            buf[0] = '\0';
    }
    pthread_mutex_unlock(&c->lock);
    return warned;
}

static rf_status impact_eval(void *p, const double *x, double *y, rf_error *err)
{
    impact_ctx *c = p;
    rf_impact_input in = c->spec.base;
    for (size_t i = 0; i < c->n_params; i++)
        rf_impact_field_set(&in, c->field[i], x[i]);
    rf_error local;
    rf_status st = rf_impact_input_validate(&in, &local);
    if (st != RF_OK)
        return rf_fail(err, RF_EMODEL, "impact model: %s", local.msg);
    rf_impact_output out;
    char warning[RF_FEM_WARNING_MAX];
    const int fem = c->spec.solver == RF_IMPACT_FEM;
    rf_fem_workspace *ws = fem ? workspace_take(c) : NULL;
    st = solve(&c->spec, ws, &in, &out, fem ? warning : NULL, &local);
    workspace_give(c, ws);
    if (st == RF_OK && c->spec.solver == RF_IMPACT_FEM)
        note_evaluation(c, warning);
    if (st != RF_OK)
        return rf_fail(err, st == RF_EINVAL ? RF_EMODEL : st, "impact model (%s): %s",
                       rf_impact_solver_name(c->spec.solver), local.msg);
    for (size_t k = 0; k < RF_IMPACT_N_OUTPUTS; k++)
        y[k] = *(const double *)((const char *)&out + rf_impact_output_fields[k].offset);
    return RF_OK;
}

static void append(char *buf, size_t cap, size_t *len, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static void append(char *buf, size_t cap, size_t *len, const char *fmt, ...)
{
    if (*len >= cap)
        return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(buf + *len, cap - *len, fmt, ap);
    va_end(ap);
    if (n > 0)
        *len += (size_t)n;
}

/* 1 when the input `name` is bound, i.e. fuzzy in a study. */
static int param_bound(const impact_ctx *c, const char *name)
{
    for (size_t i = 0; i < c->n_params; i++)
        if (!strcmp(c->field[i]->name, name))
            return 1;
    return 0;
}

/* A layer in the base input, or its thickness bound: a layer may appear at some points. */
static int layer_possible(const impact_ctx *c)
{
    return c->spec.base.layer_thickness > 0 || param_bound(c, "layer_thickness");
}

/* 1 if some evaluation may run in large deformation (rf_fem_large_deformation
 * with the layer present wherever it may be). */
static int large_possible(const impact_ctx *c)
{
    rf_impact_input probe = c->spec.base;
    if (layer_possible(c) && !(probe.layer_thickness > 0))
        probe.layer_thickness = 1;
    return rf_fem_large_deformation(&c->spec.fem, &probe);
}
static int may_run_3d(const impact_ctx *c);

/* 1 if some evaluation may have an elasto-plastic body (the auto rule of
 * rf_fem_large_deformation, whatever the kinematics option). */
static int plastic_possible(const impact_ctx *c)
{
    rf_impact_input probe = c->spec.base;
    if (layer_possible(c) && !(probe.layer_thickness > 0))
        probe.layer_thickness = 1;
    rf_fem_options o = c->spec.fem;
    o.large_deformation = RF_FEM_KINEMATICS_AUTO;
    return rf_fem_large_deformation(&o, &probe);
}

/* The boundary in the identity: auto is named by its rule where some evaluation
 * may resolve it to absorbing (a layer or a plastic body), and as "fixed"
 * otherwise, where its results are those of the old default (fixed): the
 * elastic identities stay as they were, and a soil study's store never mixes
 * results of the old fixed default with the new one. */
static const char *boundary_identity(const impact_ctx *c)
{
    if (c->spec.fem.boundary != RF_FEM_BOUNDARY_AUTO)
        return rf_fem_boundary_name(c->spec.fem.boundary);
    return layer_possible(c) || plastic_possible(c) ? "auto_absorbing_if_layer_or_plastic" : "fixed";
}

/* Every input of the base, from the one table (rf_impact_fields: SI, angles in
 * radians as stored) and the three materials: a field cannot be forgotten, so
 * a store never serves a result computed for other inputs. */
static void base_identity(const impact_ctx *c, char *buf, size_t cap, size_t *len)
{
    const rf_impact_input *b = &c->spec.base;
    append(buf, cap, len, " base: boulder_material=%s slope_material=%s layer_material=%s",
           rf_impact_material_name(b->boulder_material), rf_material_model_name(b->slope_material),
           rf_material_model_name(b->layer_material));
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *f = &rf_impact_fields[k];
        double x = *(const double *)((const char *)b + f->offset);
        append(buf, cap, len, " %s=%.17g", f->name, x);
    }
}

/* Every public FE option, from the one table (rf_fem_option_fields: a row
 * cannot be forgotten), and the automatic settings resolved where they depend
 * on constants of the code.  The numerics of fem_tuning.h are the code's own
 * (a model runs them at their defaults): a change of them is named below. */
static void fem_identity(const impact_ctx *c, char *buf, size_t cap, size_t *len)
{
    const rf_fem_options *o = &c->spec.fem;
    append(buf, cap, len, " fem:");
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *f = &rf_fem_option_fields[k];
        char value[64];
        rf_fem_option_format(o, f, value, sizeof value);
        /* the boundary by its rule: auto where it can only be fixed gives the fixed boundary's results */
        append(buf, cap, len, " %s=%s", f->name,
               f->offset == offsetof(rf_fem_options, boundary) ? boundary_identity(c) : value);
    }
    append(buf, cap, len, " refinement_axi=%.17g refinement_3d=%.17g", rf_fem_refinement(o, 0), rf_fem_refinement(o, 1));
    if (o->domain_factor == 0)
        append(buf, cap, len, " domain_margin=%.17g domain_min=%.17g", RF_FEM_DOMAIN_MARGIN, RF_FEM_DOMAIN_MIN);
}

/* The FE solver's identity (its rf_impact_law.identity; at identity time
 * its context is the impact model, whose bound inputs say which kinematics,
 * boundaries and contacts an evaluation may run): the options and every
 * change of the code's results, named where an evaluation may meet it. */
static void fem_model_identity(const impact_ctx *c, char *buf, size_t cap, size_t *len)
{
    const rf_impact_input *b = &c->spec.base;
    fem_identity(c, buf, cap, len);
    const rf_fem_options *o = &c->spec.fem;
    /* 3D results changed with the exact boulder I_yy, again with its exact centre of mass and
       with the C1 master face of the contact (issue 9, docs/fem-speed.md section 5): a store
       never mixes them */
    append(buf, cap, len, " fem3d_boulder_mass=mass_cm_Iyy_exact fem3d_master_face=catmull_rom");
    /* updated Lagrangian (on, or auto with a plastic body) is named: a store never mixes it with the
       small-strain results, whose identity stays as it was */
    if (large_possible(c))
        append(buf, cap, len, " kinematics=updated_lagrangian");
    /* the 3D model takes plastic bodies and measures penetration_max and indentation_depth (NaN
       before, issue 10): a store never mixes results from before and after */
    if (may_run_3d(c))
        append(buf, cap, len, " fem3d_materials=plastic_b_bar");
    /* the axisymmetric contact has Coulomb friction since issue 10 (it was frictionless): named
       where an evaluation may run it with friction, so a store never mixes the two */
    if ((b->slope_angle == 0 || param_bound(c, "slope_angle")) && (b->friction > 0 || param_bound(c, "friction")))
        append(buf, cap, len, " axi_contact=coulomb_friction");
    /* 3D results changed with the contact face's current slope (Newton-located master point)
       and the mass redistribution at the contact face (docs/validation-plastic.md 9e): granite
       by ~1e-5, soil by a few per cent */
    if (may_run_3d(c))
        append(buf, cap, len, " fem3d_face=current_slope");
    /* 3D friction acts along the deformed face's tangents, capped on the forces (it was along x
       and y, capped on the multipliers; docs/validation-plastic.md 9f) */
    if (may_run_3d(c))
        append(buf, cap, len, " fem3d_friction=face_tangent");
    /* the mass redistribution at the contact face of a soil (a layer or a plastic slope; elastic
       slopes are untouched, their identity stays); soil in 3D also changed with the master
       point's location (backtracking Newton from the previous point, where plain Newton had
       failed on unevenly stretched faces) */
    if (layer_possible(c) || plastic_possible(c)) {
        append(buf, cap, len, " surface_mass_kappa=0.1");
        if (may_run_3d(c))
            append(buf, cap, len, " fem3d_locate=warm_backtracking fem3d_surface_mass=on");
    }
    /* a rigid sphere's 3D contact against its exact surface (docs/validation-plastic.md 9g) */
    if (may_run_3d(c) && b->boulder_material == RF_MATERIAL_RIGID_BODY)
        append(buf, cap, len, " fem3d_contact=exact_sphere");
    /* the 3D model runs in large deformation too (on, or auto with a plastic body; it was small
       strain in every case before): a store never mixes 3D results of the two kinematics */
    if (may_run_3d(c) && large_possible(c))
        append(buf, cap, len, " fem3d_kinematics=updated_lagrangian");
    /* results that changed with the solver robustness for soils (docs/validation-plastic.md
       section 10) are named, the others keep their identity: the automatic end waits for the
       impact to end (plastic runs), the dashpots take each face's impedance, semi-implicitly */
    if (o->end_time == 0 && plastic_possible(c))
        append(buf, cap, len, " end=impact_ended");
    if (strcmp(boundary_identity(c), "fixed") != 0) /* some evaluation may have dashpots */
        append(buf, cap, len, " dashpots=face_impedance_semi_implicit");
}

static int fem_law_identity(const rf_impact_law_settings *s, char *buf, size_t size)
{
    size_t len = 0;
    fem_model_identity(s->context, buf, size, &len);
    return (int)len;
}

static void make_identity(const impact_ctx *c, char *buf, size_t cap)
{
    const rf_impact_model_spec *s = &c->spec;
    size_t len = 0;
    append(buf, cap, &len, "impact v3 solver=%s", rf_impact_solver_name(s->solver));
    const rf_impact_law *law = solvers[s->solver];
    const rf_impact_law_settings settings = {s->e_n, s->hunter_coefficient, (void *)c};
    int n = law->identity && len < cap ? law->identity(&settings, buf + len, cap - len) : 0;
    len = n > 0 && (size_t)n < cap - len ? len + (size_t)n : (n > 0 ? cap : len);
    base_identity(c, buf, cap, &len);
    append(buf, cap, &len, " params:");
    for (size_t i = 0; i < c->n_params; i++)
        append(buf, cap, &len, "%s%s", i ? "," : "", c->field[i]->name);
}

/* Whether an FE evaluation of this model may need the 3D solver, so that its
 * settings are checked against the 3D limits when the model is created
 * instead of failing at the first 3D evaluation. */
static int may_run_3d(const impact_ctx *c)
{
    if (c->spec.solver != RF_IMPACT_FEM)
        return 0;
    if (rf_fem_needs_3d(&c->spec.base))
        return 1;
    for (size_t i = 0; i < c->n_params; i++)
        if (!strcmp(c->field[i]->name, "slope_angle") || !strcmp(c->field[i]->name, "friction"))
            return 1;
    return 0;
}

/* c->field[i] = the input param_names[i] names: a bindable row, each at most once. */
static rf_status bind_names(impact_ctx *c, const char *const *param_names, size_t n_params, rf_error *err)
{
    for (size_t i = 0; i < n_params; i++) {
        const rf_impact_field *f = rf_impact_field_find(param_names[i]);
        if (!f || !f->bindable) {
            char list[1024];
            rf_impact_bindable_list(list, sizeof list);
            return rf_fail(err, RF_EINVAL, "impact model: parameter '%s' is unknown (accepted: %s)",
                           param_names[i] ? param_names[i] : "(null)", list);
        }
        for (size_t j = 0; j < i; j++)
            if (c->field[j] == f)
                return rf_fail(err, RF_EINVAL, "impact model: parameter '%s' is bound twice", param_names[i]);
        c->field[i] = f;
    }
    c->n_params = n_params;
    return RF_OK;
}

rf_status rf_impact_model_create(const rf_impact_model_spec *spec, const char *const *param_names,
                                 size_t n_params, rf_model *model, rf_error *err)
{
    if (!spec || !model || (n_params && !param_names))
        return rf_fail(err, RF_EINTERNAL, "rf_impact_model_create: NULL argument");
    memset(model, 0, sizeof *model);
    rf_status st = rf_impact_model_spec_validate(spec, err);
    if (st != RF_OK)
        return st;
    if (n_params > MAX_BOUND)
        return rf_fail(err, RF_EINVAL, "impact model: %zu parameters given, at most %zu distinct ones exist",
                       n_params, rf_impact_n_fields);
    impact_ctx *c = calloc(1, sizeof *c);
    if (!c)
        return rf_fail(err, RF_ENOMEM, "out of memory for the impact model");
    pthread_mutex_init(&c->lock, NULL);
    c->spec = *spec;
    c->spec.fem.vtk_dir = NULL;
    if ((st = bind_names(c, param_names, n_params, err)) != RF_OK) {
        ctx_destroy(c);
        return st;
    }
    /* base must be valid except for the bound fields: checked at eval time,
     * but a base that is invalid in an unbound field is an error now. */
    rf_impact_input probe = c->spec.base;
    for (size_t i = 0; i < n_params; i++)
        rf_impact_field_set(&probe, c->field[i], c->field[i]->probe);
    rf_error local;
    if (rf_impact_input_validate(&probe, &local) != RF_OK) {
        ctx_destroy(c);
        return rf_fail(err, RF_EINVAL, "impact model base input: %s", local.msg);
    }
    const rf_impact_law_settings settings = {c->spec.e_n, c->spec.hunter_coefficient, NULL};
    const rf_impact_law *law = solvers[c->spec.solver];
    if (law->validate(law, &probe, &settings, &local) != RF_OK) {
        ctx_destroy(c);
        return rf_fail(err, RF_EINVAL, "impact model: %s", local.msg);
    }
    if (may_run_3d(c) && rf_fem_options_validate(&c->spec.fem, 1, &local) != RF_OK) {
        ctx_destroy(c);
        return rf_fail(err, RF_EINVAL, "%s (this model can run the 3D solver: the slope is inclined, or the "
                                       "slope angle or friction is a parameter)", local.msg);
    }

    model->n_inputs = n_params;
    model->eval = impact_eval;
    model->warnings = impact_warnings;
    model->ctx = c;
    model->destroy = ctx_destroy;
    model->threads_per_eval = spec->solver == RF_IMPACT_FEM && spec->fem.threads > 1 ? spec->fem.threads : 1;
    const char *names[RF_IMPACT_N_OUTPUTS], *units[RF_IMPACT_N_OUTPUTS];
    for (size_t k = 0; k < RF_IMPACT_N_OUTPUTS; k++)
        names[k] = rf_impact_output_fields[k].name, units[k] = rf_impact_output_fields[k].unit;
    st = rf_model_init_outputs(model, RF_IMPACT_N_OUTPUTS, names, units, err);
    if (st == RF_OK) {
        char buf[4096];
        make_identity(c, buf, sizeof buf);
        st = rf_model_set_identity(model, buf, err);
    }
    if (st != RF_OK)
        rf_model_free(model);
    return st;
}
