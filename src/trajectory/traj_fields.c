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

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define ROW(key, field, deg, unit, def, probe, check, when, random, bind, help) \
    {key, offsetof(rf_traj_spec, field), deg, unit, def, probe, check, when, random, bind, help}
#define MAT(field, deg, unit, def, probe, check, help) \
    {#field, offsetof(rf_traj_material, field), deg, unit, def, probe, check, RF_TRAJ_WHEN_ALWAYS, 1, 1, help}
#define COL(field, unit, def, probe, check, help) \
    {#field, offsetof(rf_traj_collector, field), 0, unit, def, probe, check, RF_TRAJ_WHEN_ALWAYS, 0, 1, help}

static const rf_traj_field block_rows[] = {
    ROW("mass", mass, 0, "kg", NAN, 1234.0, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_POINT, 1, 1,
        "mass of a point block (required with shape: point)"),
    ROW("radius", radius, 0, "m", NAN, 0.7, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_SPHERE, 1, 1,
        "radius of a sphere (required with shape: sphere)"),
    ROW("density", density, 0, "kg/m^3", NAN, 2700.0, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_WHEN_SPHERE, 1, 1,
        "density of a sphere (required with shape: sphere)"),
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
};

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
    case RF_TRAJ_WHEN_POINT: return !s->sphere;
    case RF_TRAJ_WHEN_SPHERE: return s->sphere;
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
