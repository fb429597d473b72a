/* spec.c - the trajectory spec as data: free, deep copy, and validation of
 * the values (each row of the input tables against its check, traj_fields.c;
 * the release above the ground, a release line above it; the profile's
 * geometry is checked in profile.c). */
#include "trajectory/terrain_internal.h"
#include "trajectory/traj_impact.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

double traj_spec_mass(const rf_traj_spec *s)
{
    return s->sphere ? 4.0 / 3.0 * RF_PI * s->radius * s->radius * s->radius * s->density : s->mass;
}

void rf_traj_spec_free(rf_traj_spec *s)
{
    if (!s)
        return;
    free(s->name);
    free(s->file);
    free(s->impact_cache);
    free(s->px);
    free(s->py);
    free(s->release_px);
    free(s->release_py);
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
    if (s->terrain)
        rf_terrain_def_free(s->terrain);
    free(s->terrain);
    free(s->block_points);
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
    d->release_px = dup_mem(src->release_px, src->n_release * sizeof *d->release_px);
    d->release_py = dup_mem(src->release_py, src->n_release * sizeof *d->release_py);
    d->seg_material = dup_mem(src->seg_material, (src->n_points ? src->n_points - 1 : 0) * sizeof *d->seg_material);
    d->materials = dup_mem(src->materials, src->n_materials * sizeof *d->materials);
    d->collectors = dup_mem(src->collectors, src->n_collectors * sizeof *d->collectors);
    d->random = dup_mem(src->random, src->n_random * sizeof *d->random);
    d->block_points = src->block_points ? dup_mem(src->block_points, 3 * src->block_n_points * sizeof(double)) : NULL;
    int ok = (d->impact_cache || !src->impact_cache) && d->px && d->py && d->release_px && d->release_py &&
             d->seg_material && d->materials && d->collectors && d->random && (d->block_points || !src->block_points);
    for (size_t i = 0; i < src->n_materials; i++)
        if (d->materials)
            ok &= (d->materials[i].name = rf_strdup(src->materials[i].name)) != NULL;
    for (size_t i = 0; i < src->n_collectors; i++)
        if (d->collectors)
            ok &= (d->collectors[i].name = rf_strdup(src->collectors[i].name)) != NULL;
    for (size_t i = 0; i < src->n_random; i++)
        if (d->random)
            ok &= (d->random[i].path = rf_strdup(src->random[i].path)) != NULL;
    d->terrain = NULL;
    if (ok && src->terrain) {
        rf_error e;
        ok = (d->terrain = malloc(sizeof *d->terrain)) != NULL;
        if (ok && rf_terrain_def_copy(src->terrain, d->terrain, &e) != RF_OK)
            free(d->terrain), d->terrain = NULL, ok = 0;
    }
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

/* The rows of one table over the object at base (the spec, a material or a
 * collector named `name`): each used row's value, as given, against its check. */
static rf_status check_rows(const rf_traj_spec *s, const rf_traj_field_table *tb, const void *base,
                            const char *name, rf_error *err)
{
    for (size_t k = 0; k < tb->n_rows; k++) {
        const rf_traj_field *f = &tb->rows[k];
        double x = *(const double *)((const char *)base + f->offset);
        const char *rule = traj_field_used(s, f) ? traj_field_rule_stored(f, x) : NULL;
        x = traj_field_given(f, x); /* the message names the value as given */
        if (!rule)
            continue;
        if (tb->owner == RF_TRAJ_OWNER_SPEC)
            return rf_fail(err, RF_EINVAL, "%s%s = %g: %s", tb->prefix, f->key, x, rule);
        return rf_fail(err, RF_EINVAL, "%s.%s.%s = %g: %s", tb->owner == RF_TRAJ_OWNER_MATERIAL ? "materials"
                       : "collectors", name, f->key, x, rule);
    }
    return RF_OK;
}

/* Every row of every table: the spec's own, each material's, each collector's. */
static rf_status check_all_rows(const rf_traj_spec *s, rf_error *err)
{
    rf_status st = RF_OK;
    for (size_t t = 0; t < rf_traj_n_field_tables && st == RF_OK; t++) {
        const rf_traj_field_table *tb = &rf_traj_field_tables[t];
        if (tb->owner == RF_TRAJ_OWNER_SPEC)
            st = check_rows(s, tb, s, "", err);
        for (size_t i = 0; tb->owner == RF_TRAJ_OWNER_MATERIAL && i < s->n_materials && st == RF_OK; i++)
            st = check_rows(s, tb, &s->materials[i], s->materials[i].name, err);
        for (size_t i = 0; tb->owner == RF_TRAJ_OWNER_COLLECTOR && i < s->n_collectors && st == RF_OK; i++)
            st = check_rows(s, tb, &s->collectors[i], s->collectors[i].name, err);
    }
    return st;
}

/* A release line lies on or above the ground: its vertices, and the profile's
 * vertices under each of its pieces. */
static rf_status check_release_line(const rf_traj_spec *s, const rf_traj_world *w, rf_error *err)
{
    if (s->release_kind != RF_TRAJ_RELEASE_LINE)
        return RF_OK;
    for (size_t i = 0; i < s->n_release; i++) {
        size_t k;
        double x = s->release_px[i], y = s->release_py[i], gy = traj_ground_y(w, x, &k);
        if (k == TRAJ_NONE)
            return rf_fail(err, RF_EINVAL, "release.line[%zu] = [%g, %g]: outside the profile's x-range [%g, %g]", i,
                           x, y, s->px[0], s->px[s->n_points - 1]);
        if (y < gy - traj_tol(1e-9, x, gy))
            return rf_fail(err, RF_EINVAL, "release.line[%zu] = [%g, %g]: under the ground (y = %g at x = %g)", i, x,
                           y, gy, x);
    }
    for (size_t i = 0; i + 1 < s->n_release; i++) {
        double ax = s->release_px[i], ay = s->release_py[i], bx = s->release_px[i + 1], by = s->release_py[i + 1];
        for (size_t p = 0; ax != bx && p < s->n_points; p++) {
            double x = s->px[p];
            if (!(x > fmin(ax, bx) && x < fmax(ax, bx)))
                continue;
            double y = ay + (x - ax) / (bx - ax) * (by - ay);
            if (y < s->py[p] - traj_tol(1e-9, x, y))
                return rf_fail(err, RF_EINVAL, "release.line[%zu]: passes under the ground at profile.points[%zu] = "
                               "[%g, %g]", i + 1, p, x, s->py[p]);
        }
    }
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

/* A terrain file's law, outputs and terrain part (terrain_spec.c). */
static rf_status validate_terrain(const rf_traj_spec *s, rf_error *err)
{
    rf_status st;
    if ((unsigned)s->law >= RF_BOUNCE_N_LAWS)
        return rf_fail(err, RF_EINVAL, "bounce.law = %d: not a bounce law", (int)s->law);
    if ((st = traj_bounce_law_validate(s, err)) != RF_OK || (st = check_outputs(s, err)) != RF_OK)
        return st;
    if (s->release_kind != RF_TRAJ_RELEASE_MAP)
        return rf_fail(err, RF_EINVAL, "release: a terrain file releases on the map (points, lines, polygons)");
    return terrain_spec_check(s, err);
}

/* Everything but the ranges of the random inputs. */
static rf_status validate_values(const rf_traj_spec *s, rf_error *err)
{
    rf_status st;
    if ((st = check_all_rows(s, err)) != RF_OK)
        return st;
    if (s->terrain) /* a terrain file: no profile, no release above it */
        return validate_terrain(s, err);
    for (size_t i = 0; s->seg_material && i + 1 < s->n_points; i++)
        if (s->seg_material[i] >= s->n_materials)
            return rf_fail(err, RF_EINVAL, "profile.materials[%zu]: no such material", i);
    if ((unsigned)s->law >= RF_BOUNCE_N_LAWS)
        return rf_fail(err, RF_EINVAL, "bounce.law = %d: not a bounce law", (int)s->law);
    if ((st = traj_bounce_law_validate(s, err)) != RF_OK || (st = check_outputs(s, err)) != RF_OK)
        return st;
    rf_traj_world *w;
    rf_traj_spec probe = *s;
    probe.law = RF_BOUNCE_CONSTANT; /* geometry only: no impact table here */
    if ((st = rf_traj_world_create(&probe, &w, err)) != RF_OK)
        return st;
    st = check_release(s, w, err);
    if (st == RF_OK)
        st = check_release_line(s, w, err);
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
        double ends[2] = {lo, hi}, *f;
        const rf_traj_field *row = rf_traj_field_at(&probe, r->path, &f);
        if (!row || !row->random)
            return rf_fail(err, RF_EINVAL, "%s: this input cannot be random", r->path);
        double keep = *f;
        for (int e = 0; e < 2; e++) {
            *f = traj_field_store(row, ends[e]);
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

/* Each material's own impact model (materials.NAME.impact) against the impact model and its solver. */
static rf_status check_impact_grounds(const rf_traj_spec *s, rf_error *err)
{
    for (size_t i = 0; i < s->n_materials; i++)
        if (s->materials[i].impact.given &&
            traj_impact_ground_check(&s->materials[i].impact, s->impact_solver, err) != RF_OK)
            return rf_error_prefix(err, "materials.%s.impact", s->materials[i].name);
    return RF_OK;
}

rf_status rf_traj_spec_validate(const rf_traj_spec *s, rf_error *err)
{
    rf_status st = names_valid(s, err);
    if (st == RF_OK)
        st = validate_values(s, err);
    if (st == RF_OK)
        st = check_impact_grounds(s, err);
    return st != RF_OK ? st : check_random_ranges(s, err);
}
