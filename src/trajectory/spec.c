/* spec.c - the trajectory spec as data: free, deep copy, numeric inputs
 * addressed by path (for random inputs and for the fuzzy parameters of a
 * study), and validation of the values (the profile's geometry is checked in
 * profile.c). */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void rf_traj_spec_free(rf_traj_spec *s)
{
    if (!s)
        return;
    free(s->name);
    free(s->file);
    free(s->impact_cache);
    free(s->px);
    free(s->py);
    free(s->seg_material);
    for (size_t i = 0; i < s->n_materials; i++)
        free(s->materials[i].name);
    free(s->materials);
    for (size_t i = 0; i < s->n_collectors; i++)
        free(s->collectors[i].name);
    free(s->collectors);
    for (size_t i = 0; i < s->n_random; i++)
        free(s->random[i].path);
    free(s->random);
    memset(s, 0, sizeof *s);
}

static void *dup_mem(const void *p, size_t n)
{
    void *q = malloc(n ? n : 1);
    if (q && n)
        memcpy(q, p, n);
    return q;
}

rf_status rf_traj_spec_copy(const rf_traj_spec *src, rf_traj_spec *d, rf_error *err)
{
    *d = *src;
    d->name = rf_strdup(src->name);
    d->file = rf_strdup(src->file);
    d->impact_cache = rf_strdup(src->impact_cache);
    d->px = dup_mem(src->px, src->n_points * sizeof *d->px);
    d->py = dup_mem(src->py, src->n_points * sizeof *d->py);
    d->seg_material = dup_mem(src->seg_material, (src->n_points ? src->n_points - 1 : 0) * sizeof *d->seg_material);
    d->materials = dup_mem(src->materials, src->n_materials * sizeof *d->materials);
    d->collectors = dup_mem(src->collectors, src->n_collectors * sizeof *d->collectors);
    d->random = dup_mem(src->random, src->n_random * sizeof *d->random);
    int ok = (d->impact_cache || !src->impact_cache) && d->px && d->py && d->seg_material && d->materials && d->collectors && d->random;
    for (size_t i = 0; i < src->n_materials; i++)
        if (d->materials)
            ok &= (d->materials[i].name = rf_strdup(src->materials[i].name)) != NULL;
    for (size_t i = 0; i < src->n_collectors; i++)
        if (d->collectors)
            ok &= (d->collectors[i].name = rf_strdup(src->collectors[i].name)) != NULL;
    for (size_t i = 0; i < src->n_random; i++)
        if (d->random)
            ok &= (d->random[i].path = rf_strdup(src->random[i].path)) != NULL;
    if (!ok) {
        /* Null what failed so that free is safe. */
        if (!d->materials) d->n_materials = 0;
        if (!d->collectors) d->n_collectors = 0;
        if (!d->random) d->n_random = 0;
        rf_traj_spec_free(d);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    return RF_OK;
}

static double *material_field(rf_traj_material *m, const char *f)
{
    return !strcmp(f, "R_n") ? &m->R_n : !strcmp(f, "R_t") ? &m->R_t
         : !strcmp(f, "friction_angle") ? &m->friction_angle
         : !strcmp(f, "rolling_resistance") ? &m->rolling_resistance
         : !strcmp(f, "roughness") ? &m->roughness : NULL;
}

/* "prefix.NAME.field": the NAME part and the field after it. */
static int split_named(const char *path, const char *prefix, const char *name, const char **field)
{
    size_t lp = strlen(prefix), ln = strlen(name);
    if (strncmp(path, prefix, lp) || strncmp(path + lp, name, ln) || path[lp + ln] != '.')
        return 0;
    *field = path + lp + ln + 1;
    return 1;
}

static double *random_field(rf_traj_spec *s, const char *path)
{
    for (size_t i = 0; i < s->n_random; i++) {
        const char *f;
        if (!split_named(path, "", s->random[i].path, &f))
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
    struct { const char *name; double *field; } f[] = {
        {"gravity", &s->gravity}, {"block.mass", &s->mass}, {"block.radius", &s->radius},
        {"block.density", &s->density}, {"release.x", &s->x0}, {"release.y", &s->y0},
        {"release.vx", &s->vx0}, {"release.vy", &s->vy0}, {"release.omega", &s->omega0},
        {"bounce.scale_speed", &s->scale_speed}, {"bounce.contact_speed", &s->contact_speed},
        {"stop.v_stop", &s->v_stop},
    };
    for (size_t k = 0; k < sizeof f / sizeof f[0]; k++)
        if (!strcmp(path, f[k].name))
            return f[k].field;
    const char *field;
    for (size_t i = 0; i < s->n_materials; i++)
        if (split_named(path, "materials.", s->materials[i].name, &field) && material_field(&s->materials[i], field))
            return material_field(&s->materials[i], field);
    for (size_t i = 0; i < s->n_collectors; i++)
        if (split_named(path, "collectors.", s->collectors[i].name, &field)) {
            rf_traj_collector *c = &s->collectors[i];
            return !strcmp(field, "x") ? &c->x : !strcmp(field, "capacity") ? &c->capacity
                 : !strcmp(field, "height") ? &c->height : NULL;
        }
    size_t idx;
    char xy[3];
    int n = 0;
    if (sscanf(path, "profile.points.%zu.%2[xy]%n", &idx, xy, &n) == 2 && path[n] == '\0' && idx < s->n_points)
        return xy[0] == 'x' ? &s->px[idx] : &s->py[idx];
    return random_field(s, path);
}

static rf_status check_material(const rf_traj_material *m, rf_error *err)
{
    if (!(m->R_n >= 0 && m->R_n <= 1))
        return rf_fail(err, RF_EINVAL, "materials.%s.R_n = %g: must lie in [0, 1]", m->name, m->R_n);
    if (!(m->R_t >= 0 && m->R_t <= 1))
        return rf_fail(err, RF_EINVAL, "materials.%s.R_t = %g: must lie in [0, 1]", m->name, m->R_t);
    if (!(m->friction_angle >= 0 && m->friction_angle < 90))
        return rf_fail(err, RF_EINVAL, "materials.%s.friction_angle = %g: must lie in [0, 90) degrees", m->name,
                       m->friction_angle);
    if (!(m->rolling_resistance >= 0 && isfinite(m->rolling_resistance)))
        return rf_fail(err, RF_EINVAL, "materials.%s.rolling_resistance = %g: must be >= 0", m->name,
                       m->rolling_resistance);
    if (!(m->roughness >= 0 && m->roughness <= 45))
        return rf_fail(err, RF_EINVAL, "materials.%s.roughness = %g: must lie in [0, 45] degrees", m->name,
                       m->roughness);
    return RF_OK;
}

static rf_status check_block(const rf_traj_spec *s, rf_error *err)
{
    if (!(s->gravity > 0 && isfinite(s->gravity)))
        return rf_fail(err, RF_EINVAL, "gravity = %g: must be > 0", s->gravity);
    if (!s->sphere && !(s->mass > 0 && isfinite(s->mass)))
        return rf_fail(err, RF_EINVAL, "block.mass = %g: must be > 0", s->mass);
    if (s->sphere && !(s->radius > 0 && isfinite(s->radius)))
        return rf_fail(err, RF_EINVAL, "block.radius = %g: must be > 0", s->radius);
    if (s->sphere && !(s->density > 0 && isfinite(s->density)))
        return rf_fail(err, RF_EINVAL, "block.density = %g: must be > 0", s->density);
    if ((unsigned)s->law >= RF_BOUNCE_N_LAWS)
        return rf_fail(err, RF_EINVAL, "bounce.law = %d: not a bounce law", (int)s->law);
    if (!s->sphere && (s->law == RF_BOUNCE_RIGID_SPHERE || s->law == RF_BOUNCE_IMPACT_MODEL))
        return rf_fail(err, RF_EINVAL, "bounce.law = %s: needs block.shape: sphere", rf_traj_bounce_law_names[s->law]);
    double v[] = {s->x0, s->y0, s->vx0, s->vy0, s->omega0};
    const char *n[] = {"x", "y", "vx", "vy", "omega"};
    for (int i = 0; i < 5; i++)
        if (!isfinite(v[i]))
            return rf_fail(err, RF_EINVAL, "release.%s = %g: must be finite", n[i], v[i]);
    if (!(fabs(s->y0) <= RF_TRAJ_MAX_COORD))
        return rf_fail(err, RF_EINVAL, "release.y = %g: beyond %g m; heights must lie within +-%g m", s->y0,
                       RF_TRAJ_MAX_COORD, RF_TRAJ_MAX_COORD);
    if (!(s->scale_speed > 0))
        return rf_fail(err, RF_EINVAL, "bounce.scale_speed = %g: must be > 0", s->scale_speed);
    if (!(s->contact_speed >= 0))
        return rf_fail(err, RF_EINVAL, "bounce.contact_speed = %g: must be >= 0", s->contact_speed);
    if (!(s->v_stop >= 0))
        return rf_fail(err, RF_EINVAL, "stop.v_stop = %g: must be >= 0", s->v_stop);
    return RF_OK;
}

/* The release point must not lie under the ground. */
static rf_status check_release(const rf_traj_spec *s, const rf_traj_world *w, rf_error *err)
{
    size_t k;
    double gy = traj_ground_y(w, s->x0, &k);
    if (k == TRAJ_NONE)
        return rf_fail(err, RF_EINVAL, "release.x = %g: outside the profile's x-range [%g, %g]", s->x0, s->px[0],
                       s->px[s->n_points - 1]);
    if (s->y0 < gy - traj_tol(1e-9, s->x0, gy))
        return rf_fail(err, RF_EINVAL, "release.y = %g: under the ground (y = %g at x = %g)", s->y0, gy, s->x0);
    return RF_OK;
}

/* A list of n <= max finite values, increasing, each in [lo, hi]. */
static rf_status check_list(const char *path, const double *v, size_t n, size_t max, double lo, double hi,
                            rf_error *err)
{
    if (n > max)
        return rf_fail(err, RF_EINVAL, "%s: %zu values; at most %zu", path, n, max);
    for (size_t k = 0; k < n; k++) {
        if (!(v[k] >= lo && v[k] <= hi))
            return rf_fail(err, RF_EINVAL, "%s[%zu] = %g: must lie in [%g, %g]", path, k, v[k], lo, hi);
        if (k && !(v[k] > v[k - 1]))
            return rf_fail(err, RF_EINVAL, "%s[%zu] = %g: the values must increase", path, k, v[k]);
    }
    return RF_OK;
}

/* outputs: percentiles in (0, 100), thresholds finite and increasing, bins in range. */
static rf_status check_outputs(const rf_traj_spec *s, rf_error *err)
{
    const rf_traj_outputs *o = &s->outputs;
    rf_status st = check_list("outputs.percentiles", o->percentiles, o->n_percentiles, RF_TRAJ_MAX_PERCENTILES,
                              1e-9, 100 - 1e-9, err);
    if (st == RF_OK)
        st = check_list("outputs.runout_thresholds", o->runout_thresholds, o->n_runout_thresholds,
                        RF_TRAJ_MAX_THRESHOLDS, -HUGE_VAL, HUGE_VAL, err);
    if (st == RF_OK && o->runout_bins > RF_TRAJ_MAX_BINS)
        st = rf_fail(err, RF_EINVAL, "outputs.runout_bins = %zu: at most %d", o->runout_bins, RF_TRAJ_MAX_BINS);
    for (size_t c = 0; c < s->n_collectors && st == RF_OK; c++) {
        const rf_traj_collector *col = &s->collectors[c];
        char p[300];
        snprintf(p, sizeof p, "collectors.%s.energy_thresholds", col->name);
        st = check_list(p, col->energy_thresholds, col->n_energy_thresholds, RF_TRAJ_MAX_THRESHOLDS - 1, 0,
                        HUGE_VAL, err);
        snprintf(p, sizeof p, "collectors.%s.height_thresholds", col->name);
        if (st == RF_OK)
            st = check_list(p, col->height_thresholds, col->n_height_thresholds, RF_TRAJ_MAX_THRESHOLDS - 1, 0,
                            HUGE_VAL, err);
    }
    return st;
}

/* Everything but the ranges of the random inputs. */
static rf_status validate_values(const rf_traj_spec *s, rf_error *err)
{
    rf_status st;
    for (size_t i = 0; i < s->n_materials; i++)
        if ((st = check_material(&s->materials[i], err)) != RF_OK)
            return st;
    for (size_t i = 0; s->seg_material && i + 1 < s->n_points; i++)
        if (s->seg_material[i] >= s->n_materials)
            return rf_fail(err, RF_EINVAL, "profile.materials[%zu]: no such material", i);
    if ((st = check_block(s, err)) != RF_OK || (st = check_outputs(s, err)) != RF_OK)
        return st;
    for (size_t c = 0; c < s->n_collectors; c++) {
        if (!(s->collectors[c].capacity >= 0))
            return rf_fail(err, RF_EINVAL, "collectors.%s.capacity = %g: must be >= 0 [J] (0: a pure collector)",
                           s->collectors[c].name, s->collectors[c].capacity);
        if (!(s->collectors[c].height >= 0))
            return rf_fail(err, RF_EINVAL, "collectors.%s.height = %g: must be >= 0 [m] (0: unlimited)",
                           s->collectors[c].name, s->collectors[c].height);
    }
    rf_traj_world *w;
    rf_traj_spec probe = *s;
    probe.law = RF_BOUNCE_CONSTANT; /* geometry only: no impact table here */
    if ((st = rf_traj_world_create(&probe, &w, err)) != RF_OK)
        return st;
    st = check_release(s, w, err);
    rf_traj_world_free(w);
    return st;
}

/* Every end of a random input's range (uniform ends; normal truncation, or
 * mean +- 6 sd where it is not truncated) must be admissible too. */
static rf_status check_random_ranges(const rf_traj_spec *s, rf_error *err)
{
    rf_traj_spec probe = *s;
    rf_traj_material mats[64];
    if (s->n_materials > 64)
        return RF_OK; /* not checked for very many materials */
    memcpy(mats, s->materials, s->n_materials * sizeof *mats);
    probe.materials = mats;
    for (size_t i = 0; i < s->n_random; i++) {
        const rf_traj_random *r = &s->random[i];
        if (r->dist == RF_DIST_UNIFORM && !(r->a <= r->b))
            return rf_fail(err, RF_EINVAL, "%s: uniform [%g, %g] needs lo <= hi", r->path, r->a, r->b);
        if (r->dist == RF_DIST_NORMAL && !(r->b >= 0))
            return rf_fail(err, RF_EINVAL, "%s: normal sd = %g must be >= 0", r->path, r->b);
        double lo = r->dist == RF_DIST_UNIFORM ? r->a : fmax(r->lo, r->a - 6 * r->b);
        double hi = r->dist == RF_DIST_UNIFORM ? r->b : fmin(r->hi, r->a + 6 * r->b);
        double ends[2] = {lo, hi}, *f = rf_traj_spec_field(&probe, r->path);
        if (!f || f == &probe.px[0] || (f >= probe.px && f < probe.px + probe.n_points) ||
            (f >= probe.py && f < probe.py + probe.n_points))
            return rf_fail(err, RF_EINVAL, "%s: this input cannot be random", r->path);
        double keep = *f;
        for (int e = 0; e < 2; e++) {
            *f = ends[e];
            rf_error tmp;
            rf_status st = validate_values(&probe, &tmp);
            *f = keep;
            if (st != RF_OK)
                return rf_fail(err, st, "%s: the random value's range reaches %g (%s); narrow it or set min/max",
                               r->path, ends[e], tmp.msg);
        }
    }
    return RF_OK;
}

int rf_traj_name_valid(const char *name)
{
    size_t n = name ? strlen(name) : 0;
    if (n == 0 || n > RF_TRAJ_NAME_MAX)
        return 0;
    for (size_t i = 0; i < n; i++) {
        unsigned char ch = (unsigned char)name[i];
        if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
              ch == '-'))
            return 0;
    }
    return 1;
}

/* The first material or collector whose name breaks the rule, in msg. */
static rf_status names_valid(const rf_traj_spec *s, rf_error *err)
{
    for (size_t m = 0; m < s->n_materials; m++)
        if (!rf_traj_name_valid(s->materials[m].name))
            return rf_fail(err, RF_EINVAL, "materials.%s: %s", s->materials[m].name ? s->materials[m].name : "",
                           RF_TRAJ_NAME_RULE);
    for (size_t c = 0; c < s->n_collectors; c++)
        if (!rf_traj_name_valid(s->collectors[c].name))
            return rf_fail(err, RF_EINVAL, "collectors[%zu].name = %s: %s", c,
                           s->collectors[c].name ? s->collectors[c].name : "", RF_TRAJ_NAME_RULE);
    return RF_OK;
}

rf_status rf_traj_spec_validate(const rf_traj_spec *s, rf_error *err)
{
    rf_status st = names_valid(s, err);
    if (st == RF_OK)
        st = validate_values(s, err);
    return st != RF_OK ? st : check_random_ranges(s, err);
}
