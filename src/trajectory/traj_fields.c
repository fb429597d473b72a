/* traj_fields.c - the tables of the trajectory inputs (trajectory.h,
 * rf_traj_field): one per family (block, release, material, run settings,
 * collector), each row a numeric input with its key, place, unit as given,
 * default, check, whether it may be random or bound, and a help line.  The
 * reader (traj_yaml*.c), the defaults, the validation (spec.c), the study
 * binding and its messages, the model identity (traj_model.c) and the key
 * table of docs/trajectories.md loop over them; every input is addressed by
 * its path here (rf_traj_spec_field, _set, _get).  Angles are given in
 * degrees and stored in radians: converted here, once. */
#include "trajectory/traj_internal.h"
#include "core/hash.h"
#include "trajectory/traj_impact.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define ROW(key, field, deg, unit, def, probe, check, when, random, bind, help) \
    {key, offsetof(rf_traj_spec, field), deg, unit, def, probe, check, when, random, bind, help}
#define MAT(field, deg, unit, def, probe, check, help) \
    {#field, offsetof(rf_traj_material, field), deg, unit, def, probe, check, RF_TRAJ_WHEN_ALWAYS, 1, 1, help}
/* A number of materials.NAME.impact: stored as given (angles in degrees: the impact model converts them). */
#define IMP(k, name, unit, def, probe, check, help) \
    {"impact." #name, offsetof(rf_traj_material, impact.v[k]), 0, unit, def, probe, check, RF_TRAJ_WHEN_ALWAYS, 0, 1, help}
#define COL(field, unit, def, probe, check, help) \
    {#field, offsetof(rf_traj_collector, field), 0, unit, def, probe, check, RF_TRAJ_WHEN_ALWAYS, 0, 1, help}

static const rf_traj_field block_rows[] = {
    ROW("mass", mass, 0, "kg", NAN, 1234.0, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_POINT, 1, 1,
        "mass of a point block (required with shape: point)"),
    ROW("radius", radius, 0, "m", NAN, 0.7, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_SPHERE, 1, 1,
        "radius of a sphere (required with shape: sphere)"),
    ROW("density", density, 0, "kg/m^3", NAN, 2700.0, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_RIGID, 1, 1,
        "density of a sphere or a rigid block (required with every shape but point)"),
    ROW("volume", block_volume, 0, "m^3", 0.0, 2.0, RF_TRAJ_CHECK_NONNEGATIVE, RF_TRAJ_WHEN_BLOCK, 1, 1,
        "rigid block: scale it to this volume (0: as given; required by eota_cube, eota_wheel)"),
    ROW("axis_ratio_b", block_ratio_b, 0, "", 1.0, 0.6, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_BLOCK, 1, 1,
        "rigid block: stretch of its y axis against x at constant volume (axis_ratios: [1, b/a, c/a])"),
    ROW("axis_ratio_c", block_ratio_c, 0, "", 1.0, 0.4, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_BLOCK, 1, 1,
        "rigid block: stretch of its z axis against x at constant volume"),
    ROW("time_step", block_time_step, 0, "s", 1e-3, 5e-4, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_BLOCK, 0, 1,
        "rigid block: time step of the rigid-body dynamics (Moreau midpoint)"),
    ROW("max_time", block_max_time, 0, "s", 120.0, 30.0, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_BLOCK, 0, 1,
        "rigid block: a block still moving then ends as step_limit"),
    ROW("rest_time", block_rest_time, 0, "s", 0.5, 0.3, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_BLOCK, 0, 1,
        "rigid block: at rest when its kinetic energy stays below m v_stop^2 / 2 this long"),
};

static const rf_traj_field release_rows[] = {
    ROW("x", x0, 0, "m", NAN, 1.5, RF_TRAJ_CHECK_FINITE, RF_TRAJ_WHEN_AT_POINT, 1, 1,
        "release point (required unless `line` or `zone` is given)"),
    ROW("y", y0, 0, "m", NAN, 25.0, RF_TRAJ_CHECK_HEIGHT, RF_TRAJ_WHEN_AT_POINT, 1, 1,
        "release height, on or above the ground (required with x)"),
    ROW("vx", vx0, 0, "m/s", 0.0, 1.5, RF_TRAJ_CHECK_FINITE, RF_TRAJ_WHEN_VXVY, 1, 1, "release velocity, horizontal"),
    ROW("vy", vy0, 0, "m/s", 0.0, 0.5, RF_TRAJ_CHECK_FINITE, RF_TRAJ_WHEN_VXVY, 1, 1,
        "release velocity, vertical (up)"),
    ROW("speed", speed0, 0, "m/s", NAN, 3.0, RF_TRAJ_CHECK_NONNEGATIVE, RF_TRAJ_WHEN_SPEED, 1, 1,
        "release speed, instead of vx and vy (with angle)"),
    ROW("angle", angle0, 1, "deg", 0.0, 20.0, RF_TRAJ_CHECK_ANGLE_180, RF_TRAJ_WHEN_PROFILE_SPEED, 1, 1,
        "direction of the release speed from the horizontal, up positive: vx = speed cos, vy = speed sin"),
    ROW("vz", vz0, 0, "m/s", 0.0, -0.5, RF_TRAJ_CHECK_FINITE, RF_TRAJ_WHEN_TERRAIN_VXVY, 1, 1,
        "terrain: release velocity, vertical (up); vx east, vy north"),
    ROW("azimuth", azimuth0, 1, "deg", 0.0, 135.0, RF_TRAJ_CHECK_ANGLE_180, RF_TRAJ_WHEN_TERRAIN_SPEED, 1, 1,
        "terrain: direction of the release speed on the map, clockwise from north"),
    ROW("dip", dip0, 1, "deg", 0.0, 10.0, RF_TRAJ_CHECK_ANGLE_180, RF_TRAJ_WHEN_TERRAIN_SPEED, 1, 1,
        "terrain: direction of the release speed below the horizontal (down positive)"),
    ROW("height", height0, 0, "m", 0.0, 1.0, RF_TRAJ_CHECK_NONNEGATIVE, RF_TRAJ_WHEN_TERRAIN, 1, 1,
        "terrain: height of the block's lowest point above the ground at release"),
    ROW("omega", omega0, 0, "rad/s", 0.0, 1.0, RF_TRAJ_CHECK_FINITE, RF_TRAJ_WHEN_ALWAYS, 1, 1, "release spin"),
};

static const rf_traj_field material_rows[] = {
    MAT(R_n, 0, "", NAN, 0.45, RF_TRAJ_CHECK_UNIT, "normal coefficient of restitution (required)"),
    MAT(R_t, 0, "", NAN, 0.75, RF_TRAJ_CHECK_UNIT, "tangential coefficient of restitution (required)"),
    MAT(friction_angle, 1, "deg", 0.0, 33.0, RF_TRAJ_CHECK_ANGLE_90,
        "sliding friction mu = tan(phi); the impact friction of rigid_sphere"),
    MAT(rolling_resistance, 0, "", 0.0, 0.07, RF_TRAJ_CHECK_NONNEGATIVE,
        "rolling resistance coefficient mu_r (force mu_r N)"),
    MAT(roughness, 1, "deg", 0.0, 4.0, RF_TRAJ_CHECK_ANGLE_45, "SD of the slope-angle tilt drawn at each impact"),
    /* impact_model law: the material's own impact model (impact: {...}), the
     * ground inputs of `rockfuzz impact` with its names, units and defaults
     * (traj_impact_yaml.c reads them, traj_impact_adapter.c applies them by name) */
    IMP(0, slope_E, "Pa", 68.2e9, 30e9, RF_TRAJ_CHECK_POSITIVE, "Young's modulus of the rock (under a layer)"),
    IMP(1, slope_poisson, "", 0.25, 0.3, RF_TRAJ_CHECK_FINITE, "Poisson's ratio of the rock, in (-1, 0.5)"),
    IMP(2, slope_density, "kg/m^3", 2600.0, 2400.0, RF_TRAJ_CHECK_POSITIVE, "density of the rock"),
    IMP(3, slope_yield, "Pa", 0.0, 1e8, RF_TRAJ_CHECK_NONNEGATIVE, "von_mises rock: initial yield stress Y"),
    IMP(4, slope_hardening, "Pa", 0.0, 1e9, RF_TRAJ_CHECK_NONNEGATIVE, "von_mises rock: hardening modulus H"),
    IMP(5, layer_thickness, "m", 0.0, 0.5, RF_TRAJ_CHECK_NONNEGATIVE, "soil layer on the rock; 0 = rock only"),
    IMP(6, layer_E, "Pa", 68.2e9, 50e6, RF_TRAJ_CHECK_POSITIVE, "layer Young's modulus"),
    IMP(7, layer_poisson, "", 0.25, 0.3, RF_TRAJ_CHECK_FINITE, "layer Poisson's ratio, in (-1, 0.5)"),
    IMP(8, layer_density, "kg/m^3", 2600.0, 1900.0, RF_TRAJ_CHECK_POSITIVE, "layer density"),
    IMP(9, layer_yield, "Pa", 0.0, 1e6, RF_TRAJ_CHECK_NONNEGATIVE, "von_mises layer: initial yield stress Y"),
    IMP(10, layer_hardening, "Pa", 0.0, 1e6, RF_TRAJ_CHECK_NONNEGATIVE, "von_mises layer: hardening modulus H"),
    IMP(11, layer_cohesion, "Pa", 0.0, 1e4, RF_TRAJ_CHECK_NONNEGATIVE, "drucker_prager layer: cohesion c"),
    IMP(12, layer_friction_angle, "deg", 0.0, 35.0, RF_TRAJ_CHECK_ANGLE_90, "drucker_prager layer: friction angle"),
    IMP(13, layer_dilatancy_angle, "deg", 0.0, 5.0, RF_TRAJ_CHECK_ANGLE_90,
        "drucker_prager layer: dilatancy angle, in [0, friction_angle]"),
    IMP(14, layer_cap_pressure, "Pa", 0.0, 2e5, RF_TRAJ_CHECK_NONNEGATIVE,
        "drucker_prager layer: cap crush pressure; 0 = no cap"),
    IMP(15, layer_cap_hardening, "Pa", 0.0, 4e7, RF_TRAJ_CHECK_NONNEGATIVE,
        "drucker_prager layer: cap compaction modulus"),
};
_Static_assert(RF_TRAJ_IMPACT_N == 16, "one row per impact ground number");

static const rf_traj_field run_rows[] = {
    ROW("gravity", gravity, 0, "m/s^2", 9.81, 9.7, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_ALWAYS, 1, 1, "gravity g"),
    ROW("bounce.scale_speed", scale_speed, 0, "m/s", RF_TRAJ_PFEIFFER_BOWEN_K, 8.0, RF_TRAJ_CHECK_POSITIVE,
        RF_TRAJ_WHEN_ALWAYS, 0, 1, "K of velocity_scaled (Pfeiffer & Bowen 1989: 30 ft/s)"),
    ROW("bounce.contact_speed", contact_speed, 0, "m/s", 0.1, 0.2, RF_TRAJ_CHECK_NONNEGATIVE, RF_TRAJ_WHEN_ALWAYS, 0, 1,
        "rebound normal speed below which the block stays on the ground"),
    ROW("stop.v_stop", v_stop, 0, "m/s", 0.1, 0.15, RF_TRAJ_CHECK_NONNEGATIVE, RF_TRAJ_WHEN_ALWAYS, 0, 1,
        "speed after an impact below which the block stops"),
};

static const rf_traj_field collector_rows[] = {
    {"x", offsetof(rf_traj_collector, x), 0, "m", NAN, 50.0, RF_TRAJ_CHECK_FINITE, RF_TRAJ_WHEN_PROFILE, 0, 1,
     "the line x = const (required on a profile; on terrain the barrier is a `line`)"},
    COL(capacity, "J", 0.0, 1e5, RF_TRAJ_CHECK_NONNEGATIVE, "barrier energy capacity; 0 = a pure collector"),
    COL(height, "m", 0.0, 2.0, RF_TRAJ_CHECK_NONNEGATIVE, "barrier height; 0 = unlimited"),
};

#define TABLE(family, prefix, owner, rows) {family, prefix, owner, rows, sizeof rows / sizeof rows[0]}
const rf_traj_field_table rf_traj_field_tables[] = {
    TABLE("block", "block.", RF_TRAJ_OWNER_SPEC, block_rows),
    TABLE("release", "release.", RF_TRAJ_OWNER_SPEC, release_rows),
    TABLE("material", "materials.NAME.", RF_TRAJ_OWNER_MATERIAL, material_rows),
    TABLE("run", "", RF_TRAJ_OWNER_SPEC, run_rows),
    TABLE("collector", "collectors.NAME.", RF_TRAJ_OWNER_COLLECTOR, collector_rows),
};
const size_t rf_traj_n_field_tables = sizeof rf_traj_field_tables / sizeof rf_traj_field_tables[0];

/* ---- the run settings that are not bindable numbers (rf_traj_setting) ---- */

_Static_assert(sizeof(rf_bounce_law) == sizeof(int), "a NAME setting is stored as an int");

static const char *sampling_name(size_t k)
{
    static const char *const names[] = {"random", "lhs"}; /* the value of spec->lhs */
    return k < 2 ? names[k] : NULL;
}

static const char *law_name(size_t k) { return k < RF_BOUNCE_N_LAWS ? rf_traj_bounce_law_names[k] : NULL; }

#define MEMBER(field) .offset = offsetof(rf_traj_spec, field), .size = sizeof(((rf_traj_spec *)0)->field)
#define COUNT(k, field, lo, hi, d, probe_, help_)                                                              \
    {.key = k, .kind = RF_TRAJ_SETTING_COUNT, MEMBER(field), .unit = "", .count_min = lo, .count_max = hi,        \
     .count_def = d, .probe = probe_, .help = help_}

const rf_traj_setting rf_traj_settings[] = {
    COUNT("samples", samples, 1, 100000000, 1, "7", "Monte Carlo samples (trajectories)"),
    COUNT("seed", seed, 0, 9007199254740992LL, 1, "9007199254740992",
          "seed of the counter-based random streams (integers up to 2^53, written in plain digits)"),
    {.key = "sampling", .kind = RF_TRAJ_SETTING_NAME, MEMBER(lhs), .unit = "", .names = sampling_name,
     .def_name = "random", .note = "Latin hypercube", .probe = "lhs",
     .help = "how the random inputs are drawn: independently, or a Latin hypercube over the samples"},
    {.key = "record", .kind = RF_TRAJ_SETTING_COUNT, MEMBER(record), .unit = "", .count_min = 0, .count_max = 100000,
     .count_def = 200, .def_text = "min(samples, 200)", .probe = "3",
     .help = "trajectories kept with their events (the paths of the outputs)"},
    COUNT("stop.max_steps", max_steps, 1, 100000000, 10000, "50",
          "events per trajectory before it ends as step_limit"),
    {.key = "bounce.law", .kind = RF_TRAJ_SETTING_NAME, MEMBER(law), .unit = "", .names = law_name,
     .def_name = "constant", .probe = "velocity_scaled", .help = "the bounce law (docs/trajectories.md sec. 3)"},
    {.key = "bounce.impact.solver", .kind = RF_TRAJ_SETTING_WORD, MEMBER(impact_solver), .unit = "",
     .names = traj_impact_solver_name, .def_name = "rigid", .probe = "hunter",
     .help = "impact_model: the impact model tabulated (`rockfuzz impact --solver`)"},
    {.key = "bounce.impact.tolerance", .kind = RF_TRAJ_SETTING_NUMBER, MEMBER(impact_tolerance), .unit = "",
     .lo = 0, .hi = 1, .lo_open = 1, .hi_open = 1, .def = 0.01, .probe = "0.05",
     .help = "impact_model: target interpolation error of R_n and R_t"},
    {.key = "bounce.impact.friction", .kind = RF_TRAJ_SETTING_NUMBER, MEMBER(impact_friction), .unit = "",
     .lo = 0, .hi = INFINITY, .def = NAN, .def_text = "tan(friction_angle)", .probe = "0.6",
     .help = "impact_model: Coulomb coefficient inside the impact model (default: of the first material)"},
    {.key = "bounce.impact.refinement", .kind = RF_TRAJ_SETTING_NUMBER, MEMBER(impact_refinement), .unit = "",
     .lo = 0, .hi = INFINITY, .def = 0, .note = "0: the FE solver's default", .probe = "3",
     .help = "impact_model, solver fem: elements across the contact radius a/h (0: the FE solver's default); on a "
             "soil layer the rock's inertia x100 at any a/h (docs/soil-impacts.md)"},
    {.key = "bounce.impact.speeds", .kind = RF_TRAJ_SETTING_PAIR, .offset = offsetof(rf_traj_spec, impact_speed_min),
     .size = 2 * sizeof(double), .unit = "m/s", .lo = 0, .def = 0.25, .def2 = 40, .note = "normal speeds",
     .probe = "[1, 15]", .help = "impact_model: the range of normal speeds tabulated [lo, hi]"},
    {.key = "bounce.impact.max_incidence", .kind = RF_TRAJ_SETTING_NUMBER, MEMBER(impact_max_incidence),
     .unit = "deg", .degrees = 1, .lo = 0, .hi = 80, .lo_open = 1, .def = 80, .probe = "60",
     .help = "impact_model: the largest incidence tabulated, from the normal"},
    {.key = "bounce.impact.cache", .kind = RF_TRAJ_SETTING_PATH, MEMBER(impact_cache), .unit = "",
     .def_text = "none", .probe = "impacts.txt",
     .help = "impact_model: file of impacts already computed (read, then appended), relative to the trajectory file"},
    COUNT("bounce.impact.start_nodes", impact_start_nodes, 2, 17, 5, "3",
          "impact_model: nodes per axis (normal speed, incidence) of a table's first grid, before its refinement"),
    COUNT("bounce.impact.surrogate_nodes", impact_surrogate_nodes, 2, 17, 3, "2",
          "impact_model, fuzzy impact inputs: nodes per bound input of the surrogate's first grid "
          "(docs/soil-surrogate.md)"),
};
const size_t rf_traj_n_settings = sizeof rf_traj_settings / sizeof rf_traj_settings[0];
_Static_assert(offsetof(rf_traj_spec, impact_speed_max) == offsetof(rf_traj_spec, impact_speed_min) + sizeof(double),
               "bounce.impact.speeds: the pair is stored in two adjacent doubles");

const rf_traj_setting *rf_traj_setting_named(const char *path)
{
    for (size_t k = 0; path && k < rf_traj_n_settings; k++)
        if (!strcmp(path, rf_traj_settings[k].key))
            return &rf_traj_settings[k];
    return NULL;
}

/* "a, b or c" */
static void name_list(const rf_traj_setting *g, char *buf, size_t size)
{
    size_t n = 0, count = 0;
    while (g->names(count))
        count++;
    buf[0] = '\0';
    for (size_t k = 0; k < count && n < size; k++)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", k ? (k + 1 < count ? ", " : " or ") : "", g->names(k));
}

void rf_traj_setting_rule(const rf_traj_setting *g, char *buf, size_t size)
{
    char list[200], note[120] = "";
    if (g->note && g->kind != RF_TRAJ_SETTING_PAIR)
        snprintf(note, sizeof note, " (%s)", g->note);
    switch (g->kind) {
    case RF_TRAJ_SETTING_COUNT:
        snprintf(buf, size, "must lie in [%lld, %lld]", g->count_min, g->count_max);
        return;
    case RF_TRAJ_SETTING_NAME:
    case RF_TRAJ_SETTING_WORD:
        name_list(g, list, sizeof list);
        snprintf(buf, size, "expected %s%s", list, note);
        return;
    case RF_TRAJ_SETTING_NUMBER:
        if (isinf(g->hi))
            snprintf(buf, size, "must be %s %g%s", g->lo_open ? ">" : ">=", g->lo, note);
        else
            snprintf(buf, size, "must lie in %c%g, %g%c%s%s", g->lo_open ? '(' : '[', g->lo, g->hi,
                     g->hi_open ? ')' : ']', g->degrees ? " degrees" : "", note);
        return;
    case RF_TRAJ_SETTING_PAIR:
        snprintf(buf, size, "expected [lo, hi] %s [%s] with %g < lo < hi", g->note, g->unit, g->lo);
        return;
    case RF_TRAJ_SETTING_PATH:
        snprintf(buf, size, "expected a file name");
        return;
    }
    snprintf(buf, size, "unknown setting");
}

static void setting_default(const rf_traj_setting *g, char *dst)
{
    const char *name;
    switch (g->kind) {
    case RF_TRAJ_SETTING_COUNT:
        if (g->size == sizeof(uint64_t)) {
            uint64_t u = (uint64_t)g->count_def;
            memcpy(dst, &u, sizeof u);
        } else {
            size_t z = (size_t)g->count_def;
            memcpy(dst, &z, sizeof z);
        }
        return;
    case RF_TRAJ_SETTING_NAME:
    case RF_TRAJ_SETTING_WORD:
        for (size_t k = 0; (name = g->names(k)); k++)
            if (!strcmp(name, g->def_name)) {
                int i = (int)k;
                if (g->kind == RF_TRAJ_SETTING_NAME)
                    memcpy(dst, &i, sizeof i);
                else
                    snprintf(dst, g->size, "%s", name);
            }
        return;
    case RF_TRAJ_SETTING_NUMBER:
    case RF_TRAJ_SETTING_PAIR: {
        double x[2] = {g->degrees ? g->def * (RF_PI / 180) : g->def, g->def2}; /* an angle: radians */
        memcpy(dst, x, g->kind == RF_TRAJ_SETTING_PAIR ? 2 * sizeof(double) : sizeof(double));
        return;
    }
    case RF_TRAJ_SETTING_PATH:
        return; /* none: NULL (the spec was zeroed; never freed here) */
    }
}

void traj_settings_default(rf_traj_spec *s)
{
    for (size_t k = 0; k < rf_traj_n_settings; k++)
        setting_default(&rf_traj_settings[k], (char *)s + rf_traj_settings[k].offset);
}

double traj_field_store(const rf_traj_field *f, double given) { return f->degrees ? given * (RF_PI / 180) : given; }
double traj_field_given(const rf_traj_field *f, double stored) { return f->degrees ? stored * (180 / RF_PI) : stored; }

static const rf_traj_field *row_named(const rf_traj_field_table *t, const char *key)
{
    for (size_t k = 0; k < t->n_rows; k++)
        if (!strcmp(key, t->rows[k].key))
            return &t->rows[k];
    return NULL;
}

/* "prefix.NAME.field": the field after NAME. */
static const char *after_name(const char *path, const char *prefix, const char *name)
{
    size_t lp = strlen(prefix), ln = strlen(name);
    if (strncmp(path, prefix, lp) || strncmp(path + lp, name, ln) || path[lp + ln] != '.')
        return NULL;
    return path + lp + ln + 1;
}

static const rf_traj_field *named_row(rf_traj_spec *s, const rf_traj_field_table *t, const char *path,
                                      double **place)
{
    int mat = t->owner == RF_TRAJ_OWNER_MATERIAL;
    size_t n = mat ? s->n_materials : s->n_collectors;
    for (size_t i = 0; i < n; i++) {
        const char *key = after_name(path, mat ? "materials." : "collectors.",
                                     mat ? s->materials[i].name : s->collectors[i].name);
        const rf_traj_field *f = key ? row_named(t, key) : NULL;
        if (f) {
            char *base = mat ? (char *)&s->materials[i] : (char *)&s->collectors[i];
            *place = (double *)(base + f->offset);
            return f;
        }
    }
    return NULL;
}

const rf_traj_field *rf_traj_field_at(rf_traj_spec *s, const char *path, double **place)
{
    double *dummy;
    place = place ? place : &dummy;
    for (size_t t = 0; path && t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        if (tb->owner != RF_TRAJ_OWNER_SPEC) {
            const rf_traj_field *f = named_row(s, tb, path, place);
            if (f)
                return f;
            continue;
        }
        size_t lp = strlen(tb->prefix);
        const rf_traj_field *f = strncmp(path, tb->prefix, lp) ? NULL : row_named(tb, path + lp);
        if (f) {
            *place = (double *)((char *)s + f->offset);
            return f;
        }
    }
    return NULL;
}

static double *random_field(rf_traj_spec *s, const char *path)
{
    for (size_t i = 0; i < s->n_random; i++) {
        const char *f = after_name(path, "", s->random[i].path);
        if (!f)
            continue;
        rf_traj_random *r = &s->random[i];
        if (r->dist == RF_DIST_UNIFORM)
            return !strcmp(f, "lo") ? &r->a : !strcmp(f, "hi") ? &r->b : NULL;
        if (r->dist == RF_DIST_NORMAL)
            return !strcmp(f, "mean") ? &r->a : !strcmp(f, "sd") ? &r->b : NULL;
    }
    return NULL;
}

double *rf_traj_spec_field(rf_traj_spec *s, const char *path)
{
    double *place;
    if (rf_traj_field_at(s, path, &place))
        return place;
    size_t idx;
    char xy[3];
    int n = 0;
    if (sscanf(path, "profile.points.%zu.%2[xy]%n", &idx, xy, &n) == 2 && path[n] == '\0' &&
        idx < s->n_points)
        return xy[0] == 'x' ? &s->px[idx] : &s->py[idx];
    return random_field(s, path);
}

int rf_traj_spec_set(rf_traj_spec *s, const char *path, double given)
{
    double *p;
    const rf_traj_field *f = rf_traj_field_at(s, path, &p);
    if (!f && !(p = rf_traj_spec_field(s, path)))
        return 0;
    *p = f ? traj_field_store(f, given) : given;
    return 1;
}

int rf_traj_spec_get(const rf_traj_spec *s, const char *path, double *given)
{
    double *p;
    rf_traj_spec *w = (rf_traj_spec *)s; /* looked up, not written */
    const rf_traj_field *f = rf_traj_field_at(w, path, &p);
    if (!f && !(p = rf_traj_spec_field(w, path)))
        return 0;
    *given = f ? traj_field_given(f, *p) : *p;
    return 1;
}

/* The check on a value as stored: an angle against its limits converted the
 * same way (conversion is monotonic, so a value given inside the limits is
 * never refused by round-off, and one given outside never passes). */
const char *traj_field_rule_stored(const rf_traj_field *f, double x)
{
    double d90 = traj_field_store(f, 90), d45 = traj_field_store(f, 45), d180 = traj_field_store(f, 180);
    switch (f->check) {
    case RF_TRAJ_CHECK_NONE: return NULL;
    case RF_TRAJ_CHECK_FINITE: return isfinite(x) ? NULL : "must be finite";
    case RF_TRAJ_CHECK_POSITIVE: return isfinite(x) && x > 0 ? NULL : "must be > 0";
    case RF_TRAJ_CHECK_NONNEGATIVE: return isfinite(x) && x >= 0 ? NULL : "must be >= 0";
    case RF_TRAJ_CHECK_UNIT: return x >= 0 && x <= 1 ? NULL : "must lie in [0, 1]";
    case RF_TRAJ_CHECK_ANGLE_90: return x >= 0 && x < d90 ? NULL : "must lie in [0, 90) degrees";
    case RF_TRAJ_CHECK_ANGLE_45: return x >= 0 && x <= d45 ? NULL : "must lie in [0, 45] degrees";
    case RF_TRAJ_CHECK_ANGLE_180: return x >= -d180 && x <= d180 ? NULL : "must lie in [-180, 180] degrees";
    case RF_TRAJ_CHECK_HEIGHT:
        if (!isfinite(x))
            return "must be finite";
        return fabs(x) <= RF_TRAJ_MAX_COORD ? NULL : "beyond 1e+07 m; heights must lie within +-1e+07 m";
    }
    return "unknown check";
}

const char *rf_traj_field_rule(const rf_traj_field *f, double given)
{
    return traj_field_rule_stored(f, traj_field_store(f, given));
}

int traj_field_used(const rf_traj_spec *s, const rf_traj_field *f)
{
    switch (f->when) {
    case RF_TRAJ_WHEN_ALWAYS: return 1;
    case RF_TRAJ_WHEN_POINT: return !s->sphere && !s->block_kind;
    case RF_TRAJ_WHEN_SPHERE: return s->sphere;
    case RF_TRAJ_WHEN_BLOCK: return s->block_kind != RF_TRAJ_BLOCK_NONE;
    case RF_TRAJ_WHEN_RIGID: return s->sphere || s->block_kind != RF_TRAJ_BLOCK_NONE;
    case RF_TRAJ_WHEN_VXVY: return !s->release_by_speed;
    case RF_TRAJ_WHEN_SPEED: return s->release_by_speed;
    case RF_TRAJ_WHEN_AT_POINT: return s->release_kind == RF_TRAJ_RELEASE_POINT;
    case RF_TRAJ_WHEN_PROFILE: return !s->terrain;
    case RF_TRAJ_WHEN_PROFILE_SPEED: return !s->terrain && s->release_by_speed;
    case RF_TRAJ_WHEN_TERRAIN: return s->terrain != NULL;
    case RF_TRAJ_WHEN_TERRAIN_VXVY: return s->terrain && !s->release_by_speed;
    case RF_TRAJ_WHEN_TERRAIN_SPEED: return s->terrain && s->release_by_speed;
    }
    return 0;
}

static const char *owner_name(const rf_traj_spec *s, rf_traj_field_owner o, size_t i)
{
    return o == RF_TRAJ_OWNER_MATERIAL ? s->materials[i].name : s->collectors[i].name;
}

/* Every input path of the spec: the rows (per material and collector) and
 * the random inputs' parameters; fn gets the path and its row (NULL for a
 * random parameter). */
void traj_each_path(const rf_traj_spec *s, void (*fn)(void *, const char *, const rf_traj_field *), void *ctx)
{
    char p[300];
    for (size_t t = 0; t < rf_traj_n_field_tables; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        size_t n = tb->owner == RF_TRAJ_OWNER_SPEC ? 1
                 : tb->owner == RF_TRAJ_OWNER_MATERIAL ? s->n_materials : s->n_collectors;
        for (size_t i = 0; i < n; i++)
            for (size_t k = 0; k < tb->n_rows; k++) {
                if (tb->owner == RF_TRAJ_OWNER_SPEC)
                    snprintf(p, sizeof p, "%s%s", tb->prefix, tb->rows[k].key);
                else
                    snprintf(p, sizeof p, "%s.%s.%s", tb->owner == RF_TRAJ_OWNER_MATERIAL ? "materials" : "collectors",
                             owner_name(s, tb->owner, i), tb->rows[k].key);
                fn(ctx, p, &tb->rows[k]);
            }
    }
    for (size_t r = 0; r < s->n_random; r++) {
        const char *q[2][2] = {{"lo", "hi"}, {"mean", "sd"}};
        int d = s->random[r].dist == RF_DIST_NORMAL;
        for (int e = 0; e < 2; e++) {
            snprintf(p, sizeof p, "%s.%s", s->random[r].path, q[d][e]);
            fn(ctx, p, NULL);
        }
    }
}
