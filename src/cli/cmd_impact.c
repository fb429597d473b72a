/* cmd_impact.c - `rockfuzz impact`: one boulder-on-slope impact.
 *
 * Options are read by a table-driven loop (--name VALUE or --name=VALUE,
 * exact names only, no abbreviations) into an rf_impact_model_spec, which
 * rf_impact_solve runs.  Errors in the command line exit with 2, solver
 * failures with 1; both print one message on stderr naming the option and
 * value.  Output: a readable summary with units, or one JSON object. */
#include "cli/cli.h"
#include "core/json.h"
#include "core/util.h"
#include "rockfuzz/impact_model.h"
#include "rockfuzz/report.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define EXIT_USAGE 2
#define EXIT_FAILED 1

/* The options that are neither impact inputs nor FE options; every impact
 * input is an option named after its row of rf_impact_fields (impact.h) with
 * '-' for '_' (--slope-friction-angle), read by read_input, and so is every FE
 * option after its row of rf_fem_option_fields (fem.h; --domain-factor), read
 * by read_fem_option. */
typedef enum {
    O_SOLVER, O_EN, O_HUNTER_A, O_VTK, O_MAX_STEPS, O_JSON, O_PROGRESS, O_MAT_B, O_MAT_S, O_MAT_L, O_HELP, O_COUNT
} opt_id;

/* Short names of two inputs (the spheroid's semi-axes c and d). */
static const char *const input_alias[][2] = {{"c", "horizontal_axis"}, {"d", "vertical_axis"}};

static const struct {
    opt_id id;
    const char *name;   /* without the leading dashes */
} options[] = {
    {O_MAT_B, "boulder-material"},
    {O_MAT_S, "slope-material"},
    {O_MAT_L, "layer-material"},
    {O_SOLVER, "solver"},
    {O_EN, "e-n"},
    {O_HUNTER_A, "hunter-A"},
    {O_VTK, "vtk"},
    {O_MAX_STEPS, "max-steps"},
    {O_JSON, "json"},
    {O_PROGRESS, "progress"},
    {O_HELP, "help"},
};
#define N_OPTIONS (sizeof options / sizeof options[0])

/* The placeholder of an input's value in the usage text, from its unit. */
static const char *value_name(const rf_impact_field *r)
{
    static const char *const names[][2] = {{"m", "M"}, {"Pa", "PA"}, {"deg", "DEG"}, {"kg/m^3", "KGM3"},
                                           {"m/s", "MS"}, {"m/s^2", "G"}};
    for (size_t k = 0; k < sizeof names / sizeof *names; k++)
        if (!strcmp(r->unit, names[k][0]))
            return names[k][1];
    return "X";
}

/* One option of the usage: "--name VALUE" (with '-' for '_' in the name),
 * then text wrapped at 90 columns. */
static void usage_row(FILE *f, const char *name, const char *value, const char *text)
{
    char opt[80];
    int n = snprintf(opt, sizeof opt, "--%s %s", name, value);
    for (int q = 2; q < n && opt[q] != ' '; q++)
        opt[q] = opt[q] == '_' ? '-' : opt[q];
    fprintf(f, "  %-26s", opt);
    if (n > 25) /* a long option: its help on the next line */
        fprintf(f, "\n%28s", "");
    int col = 28;
    for (const char *w = text; *w;) {
        size_t len = strcspn(w, " ");
        if (col + (int)len > 90 && col > 28) {
            fprintf(f, "\n%28s", "");
            col = 28;
        }
        fprintf(f, "%s%.*s", col > 28 ? " " : "", (int)len, w);
        col += (int)len + (col > 28);
        w += len;
        while (*w == ' ')
            w++;
    }
    fputc('\n', f);
}

/* The usage of every impact input, from rf_impact_fields: option and value,
 * then its help, unit and default. */
static void input_usage(FILE *f)
{
    for (size_t k = 0; k < rf_impact_n_fields; k++) {
        const rf_impact_field *r = &rf_impact_fields[k];
        char text[400], def[48];
        if (r->kind == RF_FIELD_GRAVITY && r->def < 0)
            snprintf(def, sizeof def, "auto");
        else
            snprintf(def, sizeof def, "%g", r->def);
        snprintf(text, sizeof text, "%s%s%s%s (default %s)", r->help, r->unit[0] ? " [" : "", r->unit,
                 r->unit[0] ? "]" : "", def);
        usage_row(f, r->name, value_name(r), text);
    }
}

/* The usage of every FE option, from rf_fem_option_fields: fem, its choices,
 * help, unit and default. */
static void fem_usage(FILE *f)
{
    rf_fem_options defaults;
    rf_fem_options_default(&defaults);
    for (size_t k = 0; k < rf_fem_n_option_fields; k++) {
        const rf_fem_option_field *r = &rf_fem_option_fields[k];
        char text[1200], choices[128] = "", def[64];
        if (r->kind == RF_FEM_OPTION_CHOICE) {
            rf_fem_option_choices(r, choices, sizeof choices - 2);
            strcat(choices, "; ");
        }
        rf_fem_option_format(&defaults, r, def, sizeof def);
        snprintf(text, sizeof text, "fem: %s%s%s%s%s (default %s)", choices, r->help, r->unit[0] ? " [" : "",
                 r->unit, r->unit[0] ? "]" : "", def);
        usage_row(f, r->name, r->value_name, text);
    }
}

/* --solver's lines, from the solver registry (impact_model.h). */
static void solver_usage(FILE *f)
{
    fprintf(f, "  --solver NAME            ");
    for (size_t k = 0; k < rf_impact_n_solvers(); k++)
        fprintf(f, "%s%s", k ? " | " : "", rf_impact_solver_name((rf_impact_solver)k));
    fprintf(f, " (default %s)\n", rf_impact_solver_name(RF_IMPACT_FEM));
    for (size_t k = 0; k < rf_impact_n_solvers(); k++) {
        const rf_impact_law *law = rf_impact_solver_law((rf_impact_solver)k);
        char head[32];
        snprintf(head, sizeof head, "%s:", law->name);
        fprintf(f, "%27s%-8s", "", head);
        for (const char *c = law->help; *c; c++)
            if (*c == '\n')
                fprintf(f, "\n%35s", "");
            else
                fputc(*c, f);
        fputc('\n', f);
    }
}

static void usage(FILE *f)
{
    fprintf(f,
        "Usage: rockfuzz impact [OPTIONS]\n"
        "\n"
        "Simulate one impact of a boulder (sphere, or spheroid with horizontal semi-axis c\n"
        "and vertical semi-axis d) falling vertically onto an elastic slope (half-space).\n"
        "Units are SI except the angles (degrees).  Defaults: nominal granite, elastic.\n"
        "\n"
        "Inputs (each also a key of a study's impact block and, but vertical_axis, a fuzzy\n"
        "parameter; docs/impact.md):\n");
    input_usage(f);
    fprintf(f,
        "  --c, --d                 short for --horizontal-axis, --vertical-axis\n"
        "  Gravity: with fem, the boulder's weight and the geostatic stress of the slope and\n"
        "  layer (K0 = 1 - sin phi for drucker_prager, nu/(1 - nu) otherwise; 3D: of an infinite\n"
        "  slope, a layer that cannot stand on it is refused); R_n is the velocity at\n"
        "  separation, 0 when the boulder comes to rest (docs/validation-plastic.md section 11).\n"
        "  A layer (--layer-thickness > 0, fem only) lies over the slope (the bedrock); the 3D\n"
        "  model meshes it with a node plane at its bottom, at least one contact element thick.\n"
        "\n"
        "Materials (docs/materials.md; fem solver only when not elastic; axisymmetric and 3D):\n"
        "  --boulder-material M     elastic | von_mises | rigid (default elastic; rigid: exact\n"
        "                           mass and inertia, no deformation, E* from the slope alone,\n"
        "                           the time step from the slope)\n"
        "  --slope-material M       elastic | von_mises | drucker_prager (default elastic)\n"
        "  --layer-material M       as the slope's (default elastic)\n"
        "  The dilatancy cutoff is the critical state: (e_cs - e0) / (1 + e0) from void ratios.\n"
        "\n"
        "Model:\n");
    solver_usage(f);
    fprintf(f,
        "  --e-n EN                 rigid, mdr: normal COR in [0, 1] (default: Hunter's\n"
        "                           e_n; --e-n 1 makes the mdr impact purely elastic)\n"
        "  --hunter-A A             Hunter coefficient A (default 1.04; band 1.112-1.171)\n"
        );
    fem_usage(f);
    fprintf(f,
        "  --vtk DIR                fem: write VTK snapshots into DIR (fem.pvd + fem_NNNN.vtu;\n"
        "                           the 3D model writes its half model); DIR and its\n"
        "                           parents are created if missing\n");
    fprintf(f,
        "  --max-steps N            fem: the step budget (default %.0f; 0 = no limit).  After\n"
        "                           assembly the time step and the least simulated time give\n"
        "                           the step count: a run needing more is refused before it\n"
        "                           starts, naming the count; no run takes more steps.  A run\n"
        "                           estimated (from its first steps) to take over 30 s says\n"
        "                           its steps and time on stderr first\n", RF_FEM_DEFAULT_MAX_STEPS);
    fprintf(f,
        "\n"
        "Output:\n"
        "  --json                   print one JSON object: contact_force_max [N],\n"
        "                           compression_max [m], contact_duration [s],\n"
        "                           contact_radius [m], R_n, R_t, R_ke, energy_error [-],\n"
        "                           plastic_work [-, of the initial KE], penetration_max [m],\n"
        "                           indentation_depth [m], equivalent_plastic_strain_max [-],\n"
        "                           nodes, elements, steps, gravity [m/s^2, the value used],\n"
        "                           at_rest (1: the block came to rest, R_n = 0),\n"
        "                           with friction > 0: friction_work [-, of the initial\n"
        "                           KE; a term of the energy account],\n"
        "                           with --ale on when it rezoned: ale_rezones and\n"
        "                           ale_remap_energy [-, of the initial KE; not in the\n"
        "                           energy error], wall_seconds [s]; NaN -> null\n"
        "  --progress               fem: the progress line on stderr (simulated time, expected\n"
        "                           end, time left; redrawn up to 4 times a second, erased at\n"
        "                           the end) also with --json or when stderr is not a terminal;\n"
        "                           by default it is drawn on a terminal without --json, from\n"
        "                           1 s into the run\n"
        "  -h, --help               show this help\n"
        "\n"
        "Exit status: 0 success, 1 the model failed, 2 invalid command line or input.\n");
}

/* The value of option --NAME (len characters of name): after '=' (eq) or the
 * next argument (then *i points at it); NULL with the message when it has none. */
static const char *option_value(const char *name, size_t len, const char *eq, int argc, char **argv, int *i)
{
    const char *val = eq ? eq + 1 : *i + 1 < argc ? argv[++*i] : NULL;
    if (!val)
        fprintf(stderr, "rockfuzz impact: option '--%.*s' needs a value\n", (int)len, name);
    return val;
}

static void json_number(const char *key, double x, int last)
{
    printf("\"%s\": ", key);
    rf_json_number(stdout, x);
    fputs(last ? "" : ", ", stdout);
}

/* friction_work: of the initial KE, NaN (left out) when the run had no friction. */
static void print_json(const rf_impact_output *o, double gravity, int at_rest, const rf_fem_history *h,
                       double friction_work)
{
    printf("{");
    json_number("contact_force_max", o->contact_force_max, 0);
    json_number("compression_max", o->compression_max, 0);
    json_number("contact_duration", o->contact_duration, 0);
    json_number("contact_radius", o->contact_radius, 0);
    json_number("R_n", o->R_n, 0);
    json_number("R_t", o->R_t, 0);
    json_number("R_ke", o->R_ke, 0);
    json_number("energy_error", o->energy_error, 0);
    json_number("plastic_work", o->plastic_work, 0);
    json_number("penetration_max", o->penetration_max, 0);
    json_number("indentation_depth", o->indentation_depth, 0);
    json_number("equivalent_plastic_strain_max", o->equivalent_plastic_strain_max, 0);
    json_number("nodes", o->nodes, 0);
    json_number("elements", o->elements, 0);
    json_number("steps", o->steps, 0);
    json_number("gravity", gravity, 0);
    printf("\"at_rest\": %d, ", at_rest);
    if (!isnan(friction_work))
        json_number("friction_work", friction_work, 0);
    if (h && h->ale_rezones > 0 && h->ke0 > 0) { /* ALE: the rezones and the energy they added, of KE0 */
        json_number("ale_rezones", (double)h->ale_rezones, 0);
        json_number("ale_remap_energy", (h->ale_kinetic + h->ale_elastic + h->ale_potential) / h->ke0, 0);
    }
    json_number("wall_seconds", o->wall_seconds, 1);
    printf("}\n");
}

static void print_value(const char *what, double x, const char *unit)
{
    if (isnan(x))
        printf("  %-21s undefined by this model\n", what);
    else
        printf("  %-21s %.6g %s\n", what, x, unit);
}

static void print_summary(const rf_impact_model_spec *spec, const rf_impact_input *in,
                          const rf_impact_output *o)
{
    double d = rf_impact_vertical_semi_axis(in);
    printf("rockfuzz impact (solver %s)\n\n", rf_impact_solver_name(spec->solver));
    printf("Inputs\n");
    if (in->horizontal_axis > 0.0)
        printf("  boulder           spheroid c = %g m, d = %g m (r0 = %g m)\n", in->horizontal_axis,
               d, in->radius);
    else
        printf("  boulder           sphere r0 = %g m\n", in->radius);
    printf("  boulder material  rho = %g kg/m^3, E = %g Pa, nu = %g\n", in->boulder_density,
           in->boulder_E, in->boulder_poisson);
    printf("  slope material    rho = %g kg/m^3, E = %g Pa, nu = %g\n", in->slope_density,
           in->slope_E, in->slope_poisson);
    if (in->boulder_material == RF_MATERIAL_RIGID_BODY)
        printf("  boulder           rigid (its E and nu are not used)\n");
    if (in->boulder_material == RF_MATERIAL_VON_MISES)
        printf("  boulder plasticity von_mises Y = %g Pa, H = %g Pa\n", in->boulder_yield, in->boulder_hardening);
    if (in->slope_material == RF_MATERIAL_VON_MISES)
        printf("  slope plasticity  von_mises Y = %g Pa, H = %g Pa\n", in->slope_yield, in->slope_hardening);
    if (in->layer_thickness > 0)
        printf("  layer             %g m thick: rho = %g kg/m^3, E = %g Pa, nu = %g, %s\n", in->layer_thickness,
               in->layer_density, in->layer_E, in->layer_poisson, rf_material_model_name(in->layer_material));
    if (in->slope_material == RF_MATERIAL_DRUCKER_PRAGER)
        printf("  slope plasticity  drucker_prager c = %g Pa, phi = %g deg, psi = %g deg, cap X0 = %g Pa, "
               "H_c = %g Pa\n", in->slope_cohesion, in->slope_friction_angle * 180.0 / RF_PI,
               in->slope_dilatancy_angle * 180.0 / RF_PI, in->slope_cap_pressure, in->slope_cap_hardening);
    if (in->slope_material == RF_MATERIAL_DRUCKER_PRAGER && in->slope_dilatancy_cutoff > 0)
        printf("  slope dilatancy   stops at a plastic volumetric strain of %g\n", in->slope_dilatancy_cutoff);
    if (in->layer_thickness > 0 && in->layer_material == RF_MATERIAL_DRUCKER_PRAGER && in->layer_dilatancy_cutoff > 0)
        printf("  layer dilatancy   stops at a plastic volumetric strain of %g\n", in->layer_dilatancy_cutoff);
    printf("  impact            V = %g m/s vertical, slope angle = %g deg, friction = %g\n",
           in->velocity, in->slope_angle * 180.0 / RF_PI, in->friction);
    printf("  mass              %.6g kg\n", rf_impact_mass(in));
    printf("  gravity           %g m/s^2%s\n", spec->solver == RF_IMPACT_FEM ? rf_impact_gravity(in, rf_fem_needs_3d(in)) : 0.0,
           in->gravity < 0 ? " (auto)" : "");
    if (spec->solver == RF_IMPACT_FEM) {
        int three_d = rf_fem_needs_3d(in);
        printf("  FE settings       %s, refinement a/h = %g, domain = %g r0%s, boundary %s%s, threads %d, "
               "large deformation %s, ale %s\n",
               three_d ? "3D half model (inclined slope or friction)" : "axisymmetric",
               rf_fem_refinement(&spec->fem, three_d), rf_fem_domain_factor(&spec->fem, in),
               spec->fem.domain_factor > 0 ? "" : " (automatic)",
               rf_fem_boundary_name(rf_fem_boundary_resolve(spec->fem.boundary, in)),
               spec->fem.boundary == RF_FEM_BOUNDARY_AUTO ? " (automatic)" : "", spec->fem.threads,
               rf_fem_kinematics_name(spec->fem.large_deformation), rf_fem_ale_name(spec->fem.ale));
    }
    printf("\nResults\n");
    print_value("max contact force", o->contact_force_max, "N");
    print_value("max compression", o->compression_max, "m");
    print_value("contact duration", o->contact_duration, "s");
    print_value("contact radius", o->contact_radius, "m");
    printf("  R_n                   %.6g\n", o->R_n);
    if (isnan(o->R_t))
        printf("  R_t                   undefined (no tangential velocity)\n");
    else
        printf("  R_t                   %.6g\n", o->R_t);
    printf("  R_ke                  %.6g (rotation included)\n", o->R_ke);
    printf("  velocity after        v_n = %.6g m/s, v_t = %.6g m/s, omega = %.6g rad/s\n",
           o->v_n_after, o->v_t_after, o->omega_after);
    if (spec->solver == RF_IMPACT_FEM) {
        print_value("plastic work", o->plastic_work, "of the initial KE");
        print_value("penetration max", o->penetration_max, "m (lowest boulder point below the surface)");
        print_value("indentation depth", o->indentation_depth, "m (crater at the first-contact point)");
        print_value("plastic strain max", o->equivalent_plastic_strain_max, "");
    }
    if (spec->solver == RF_IMPACT_FEM)
        printf("  FE                    energy error %.3g, %g nodes, %g elements, %g steps, "
               "%.3g s\n", o->energy_error, o->nodes, o->elements, o->steps, o->wall_seconds);
}

/* Analytic references for comparison with any solver. */
static void print_references(const rf_impact_model_spec *spec, const rf_impact_input *in)
{
    rf_impact_output ref;
    if (spec->solver != RF_IMPACT_HERTZ && rf_impact_hertz(in, &ref, NULL) == RF_OK)
        printf("\nHertz reference       F = %.6g N, delta = %.6g m, t_c = %.6g s, a = %.6g m\n",
               ref.contact_force_max, ref.compression_max, ref.contact_duration,
               ref.contact_radius);
    double lo = rf_hunter_loss(in, RF_HUNTER_A_JOHNSON), hi = rf_hunter_loss(in, RF_HUNTER_A_HALF_SINE);
    if (hi < 1.0)
        printf("Hunter e_n band       %.5f (A = 1.04, Johnson 1985) .. %.5f (A = 1.171)\n",
               sqrt(1 - lo), sqrt(1 - hi));
}

/* A long FE run says its steps and the time it will take (rf_fem_options.say). */
static void say_long_run(void *ctx, const char *text)
{
    (void)ctx;
    fprintf(stderr, "rockfuzz impact: %s\n", text);
    fflush(stderr);
}

/* The FE run with its history, for the diagnostics the summary shows. */
static int run_fem(const rf_impact_model_spec *spec_in, rf_impact_output *out, int json, int progress)
{
    rf_impact_model_spec sp = *spec_in;
    const rf_impact_model_spec *spec = &sp;
    rf_cli_progress line;
    rf_cli_progress_begin(&line, progress || (!json && isatty(STDERR_FILENO)), "fem impact");
    sp.fem.progress = rf_cli_progress_fem, sp.fem.progress_ctx = &line;
    sp.fem.say = say_long_run, sp.fem.say_ctx = NULL;
    rf_fem_history hist = {0};
    rf_error err = {0};
    double friction_work = 0.0;
    int three_d = 0;
    /* --vtk DIR: created with its parents if missing (mkdir -p), for either geometry */
    if (spec->fem.vtk_dir && rf_report_make_dir(spec->fem.vtk_dir, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz impact: --vtk: %s\n", err.msg);
        return EXIT_FAILED;
    }
    const rf_status solved = rf_fem_solve(&spec->base, &spec->fem, out, &hist, &friction_work, &three_d, &err);
    rf_cli_progress_end(&line);
    if (solved != RF_OK) {
        fprintf(stderr, "rockfuzz impact: fem solver failed: %s\n", err.msg);
        rf_fem_history_free(&hist);
        return EXIT_FAILED;
    }
    if (json) {
        print_json(out, hist.gravity, hist.at_rest, &hist,
                   spec->base.friction > 0 && hist.ke0 > 0 ? friction_work / hist.ke0 : NAN);
    } else {
        print_summary(spec, &spec->base, out);
        printf("  FE mesh               boulder %ld nodes / %ld elements, slope %ld / %ld; "
               "h = %.3g m at the contact (Hertz a = %.3g m)\n",
               hist.boulder_nodes, hist.boulder_elements, hist.slope_nodes, hist.slope_elements,
               hist.h_contact, hist.hertz_radius);
        printf("  FE time step          %.3g s (eigenvalue bound %.3g s)\n", hist.dt, hist.dt_bound);
        if (hist.ke0 > 0.0)
            printf("  FE energy at the end  boulder vibration %.3g, slope %.3g of the initial KE\n",
                   hist.vibration_energy / hist.ke0, hist.slope_energy / hist.ke0);
        if (hist.ale_rezones > 0 && hist.ke0 > 0.0)
            printf("  FE ALE                %ld rezones, %ld node moves (largest %.3g m); energy the remaps added "
                   "%.3g of the initial KE (kinetic %.3g, elastic %.3g, potential %.3g), not in the closure\n",
                   hist.ale_rezones, hist.ale_nodes_moved, hist.ale_move_max,
                   (hist.ale_kinetic + hist.ale_elastic + hist.ale_potential) / hist.ke0, hist.ale_kinetic / hist.ke0,
                   hist.ale_elastic / hist.ke0, hist.ale_potential / hist.ke0);
        if (three_d && hist.ke0 > 0.0)
            printf("  FE friction work      %.3g of the initial KE (half model; energies of the full body)\n",
                   friction_work / hist.ke0);
        if (!three_d && spec->base.friction > 0 && hist.ke0 > 0.0)
            printf("  FE friction work      %.3g of the initial KE (axisymmetric contact: %.0f %% of the closed "
                   "pair-steps stuck, at most %d Gauss-Seidel sweeps, slip left on a sticking pair <= %.2g m "
                   "per step)\n", friction_work / hist.ke0, 100 * hist.stick_fraction, hist.friction_sweeps_max,
                   hist.stick_residual_max);
        print_references(spec, &spec->base);
    }
    if (hist.warning[0])
        fprintf(stderr, "warning: %s\n", hist.warning);
    rf_fem_history_free(&hist);
    return 0;
}

/* A model setting (not an impact input) given on the command line into spec;
 * 0, or EXIT_USAGE after a message naming the option and value. */
static int set_option(opt_id id, const char *oname, const char *val, rf_impact_model_spec *spec)
{
    double x = 0.0;
    rf_error err = {0};
    switch (id) {
    case O_SOLVER:
        if (rf_impact_solver_parse(val, &spec->solver, &err) != RF_OK) {
            fprintf(stderr, "rockfuzz impact: --solver: %s\n", err.msg);
            return EXIT_USAGE;
        }
        break;
    case O_VTK:
        spec->fem.vtk_dir = val;
        break;
    case O_MAX_STEPS: {
        long long n = 0;
        if (!rf_cli_count("impact", "--max-steps", val, 0, 1000000000000LL, &n))
            return EXIT_USAGE;
        spec->fem.max_steps = n ? (double)n : -1; /* 0: no limit */
        break;
    }
    case O_MAT_B:
    case O_MAT_S:
    case O_MAT_L: {
        if ((id == O_MAT_B ? rf_impact_boulder_material_parse(val, &spec->base.boulder_material, &err)
                           : rf_material_model_parse(val, id == O_MAT_S ? &spec->base.slope_material : &spec->base.layer_material,
                                                     &err)) != RF_OK) {
            fprintf(stderr, "rockfuzz impact: --%s '%s': expected %s\n", oname, val,
                    id == O_MAT_B ? "elastic, von_mises or rigid" : "elastic, von_mises or drucker_prager");
            return EXIT_USAGE;
        }
        break;
    }
    default:
        if (!rf_cli_parse_double("impact", oname, val, &x))
            return EXIT_USAGE;
        switch (id) {
        case O_EN:
            if (!(x >= 0.0 && x <= 1.0)) {
                fprintf(stderr, "rockfuzz impact: --e-n %s: the normal COR must lie in [0, 1]\n", val);
                return EXIT_USAGE;
            }
            spec->e_n = x;
            break;
        case O_HUNTER_A:
            if (!(x >= 0.0)) {
                fprintf(stderr, "rockfuzz impact: --hunter-A %s: must be >= 0\n", val);
                return EXIT_USAGE;
            }
            spec->hunter_coefficient = x;
            break;
        default: break;
        }
    }
    return 0;
}

#define RF_CLI_MAX_INPUTS 64 /* > rf_impact_n_fields */

/* The FE option an option names (--domain-factor), or NULL. */
static const rf_fem_option_field *fem_option(const char *name, size_t len)
{
    char key[64];
    if (len >= sizeof key || memchr(name, '_', len))
        return NULL; /* options are spelt with '-' only */
    for (size_t q = 0; q < len; q++)
        key[q] = name[q] == '-' ? '_' : name[q];
    key[len] = '\0';
    return rf_fem_option_find(key);
}

/* The value of an FE option, as its row says (the solvers' own rule, fem_options.c). */
static int read_fem_option(const char *oname, const rf_fem_option_field *row, const char *val, rf_fem_options *o)
{
    rf_error err = {0};
    if (rf_fem_option_parse(o, row, val, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz impact: --%s '%s': %s\n", oname, val, err.msg);
        return 0;
    }
    return 1;
}

/* The impact input an option names (--slope-E, or an alias such as --c), or NULL. */
static const rf_impact_field *input_option(const char *name, size_t len)
{
    char key[64];
    if (len >= sizeof key)
        return NULL;
    for (size_t q = 0; q < len; q++)
        key[q] = name[q] == '-' ? '_' : name[q];
    key[len] = '\0';
    for (size_t a = 0; a < sizeof input_alias / sizeof *input_alias; a++)
        if (!strcmp(key, input_alias[a][0]))
            return rf_impact_field_find(input_alias[a][1]);
    if (strchr(key, '-') || len == 0 || memchr(name, '_', len))
        return NULL; /* options are spelt with '-' only */
    return rf_impact_field_find(key);
}

/* The value of an input option, as its row says (degrees for angles, auto for gravity). */
static int read_input(const char *oname, const rf_impact_field *field, const char *val, rf_impact_input *in)
{
    double x;
    if (field->kind == RF_FIELD_GRAVITY) {
        rf_error err = {0};
        if (rf_impact_gravity_parse(val, &x, &err) != RF_OK) {
            fprintf(stderr, "rockfuzz impact: --%s: %s\n", oname, err.msg);
            return 0;
        }
    } else if (!rf_cli_parse_double("impact", oname, val, &x)) {
        return 0;
    }
    rf_impact_field_store(in, field, x);
    return 1;
}

/* The options given so far: where each impact input came from, for the messages. */
typedef struct {
    const char *input[RF_CLI_MAX_INPUTS];
    char input_name[RF_CLI_MAX_INPUTS][48];
    int threads_given;
} given_opts;

/* --NAME of an impact input or an FE option (their tables' rows): 1 read, 0 not one of them, -1 bad. */
static int table_option(const char *name, size_t len, const char *eq, int argc, char **argv, int *i,
                        rf_impact_model_spec *spec, given_opts *g)
{
    const rf_impact_field *field = input_option(name, len);
    const rf_fem_option_field *fem_row = field ? NULL : fem_option(name, len);
    if (!field && !fem_row)
        return 0;
    const char *val = option_value(name, len, eq, argc, argv, i);
    if (!val)
        return -1;
    if (field) {
        size_t f = (size_t)(field - rf_impact_fields);
        g->input[f] = val;
        snprintf(g->input_name[f], sizeof g->input_name[f], "%.*s", (int)len, name);
        return read_input(g->input_name[f], field, val, &spec->base) ? 1 : -1;
    }
    char oname[64];
    snprintf(oname, sizeof oname, "%.*s", (int)len, name);
    if (!read_fem_option(oname, fem_row, val, &spec->fem))
        return -1;
    g->threads_given |= fem_row->offset == offsetof(rf_fem_options, threads);
    return 1;
}

/* 1 if the inputs are valid together; else says why, naming the option given. */
static int inputs_valid(const rf_impact_input *in, const given_opts *g)
{
    rf_error err = {0};
    if (rf_impact_input_validate(in, &err) == RF_OK)
        return 1;
    const rf_impact_field *bad = rf_impact_field_find(rf_impact_input_first_invalid(in));
    size_t f = bad ? (size_t)(bad - rf_impact_fields) : 0;
    if (bad && g->input[f])
        fprintf(stderr, "rockfuzz impact: --%s %s: %s\n", g->input_name[f], g->input[f], err.msg);
    else
        fprintf(stderr, "rockfuzz impact: invalid input: %s\n", err.msg);
    return 0;
}

int rf_cli_impact(int argc, char **argv)
{
    rf_impact_model_spec spec;
    rf_impact_model_spec_default(&spec);
    rf_impact_input *in = &spec.base;
    int json = 0, progress = 0;
    given_opts g;
    memset(&g, 0, sizeof g);

    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h")) {
            usage(stdout);
            return 0;
        }
        if (strncmp(arg, "--", 2) != 0 || arg[2] == '\0') {
            fprintf(stderr, "rockfuzz impact: unexpected argument '%s' (try --help)\n", arg);
            return EXIT_USAGE;
        }
        const char *name = arg + 2, *eq = strchr(name, '=');
        size_t len = eq ? (size_t)(eq - name) : strlen(name);
        int t = table_option(name, len, eq, argc, argv, &i, &spec, &g);
        if (t < 0)
            return EXIT_USAGE;
        if (t > 0)
            continue;
        size_t k = 0;
        while (k < N_OPTIONS && !(strlen(options[k].name) == len && !strncmp(options[k].name, name, len)))
            k++;
        if (k == N_OPTIONS) {
            fprintf(stderr, "rockfuzz impact: unknown option '--%.*s' (try --help)\n", (int)len, name);
            return EXIT_USAGE;
        }
        opt_id id = options[k].id;
        const char *oname = options[k].name;
        if (id == O_HELP || id == O_JSON || id == O_PROGRESS) {
            if (eq) {
                fprintf(stderr, "rockfuzz impact: option '--%s' takes no value\n", oname);
                return EXIT_USAGE;
            }
            if (id == O_HELP) {
                usage(stdout);
                return 0;
            }
            *(id == O_JSON ? &json : &progress) = 1;
            continue;
        }
        const char *val = option_value(name, len, eq, argc, argv, &i);
        if (!val || set_option(id, oname, val, &spec) != 0)
            return EXIT_USAGE;
    }

    /* the 3D model on all cores (the solvers give the same bits for any count); the axisymmetric
       one on one: its steps (~0.1 ms) are shorter than a thread hand-off, and 2 threads were up to
       2x slower up to 12 600 elements (docs/fem-speed.md section 5) */
    if ((!g.threads_given || spec.fem.threads == 0) && rf_fem_needs_3d(in)) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        spec.fem.threads = cores < 1 ? 1 : cores > RF_CLI_MAX_THREADS ? RF_CLI_MAX_THREADS : (int)cores;
    }
    if (!inputs_valid(in, &g))
        return EXIT_USAGE;
    rf_error err = {0};

    rf_impact_output out;
    if (spec.solver == RF_IMPACT_FEM)
        return run_fem(&spec, &out, json, progress);
    if (rf_impact_solve(&spec, in, &out, &err) != RF_OK) {
        fprintf(stderr, "rockfuzz impact: %s solver failed: %s\n",
                rf_impact_solver_name(spec.solver), err.msg);
        return EXIT_FAILED;
    }
    if (json) {
        print_json(&out, 0.0, 0, NULL, NAN);
    } else {
        print_summary(&spec, in, &out);
        print_references(&spec, in);
    }
    return 0;
}
