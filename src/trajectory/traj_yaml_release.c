/* traj_yaml_release.c - the `release:` block of a trajectory file: a point
 * (x, y), or a polyline (`line`) or a zone (`zone`: an x-range or a polygon)
 * along which release.c draws the point of each trajectory; the velocity as
 * vx, vy or as speed and angle (one pair, not both); the spin omega. */
#include "trajectory/traj_yaml_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_POLYGON 64

/* [[x, y], ...] with min..max points into the release polyline. */
static rf_status read_points(ty_ctx *c, struct fy_node *n, const char *path, size_t min, size_t max)
{
    rf_traj_spec *s = c->spec;
    size_t cnt;
    rf_status st = yr_sequence(&c->sp, n, path, min, max, &cnt);
    if (st != RF_OK)
        return st;
    ty_remember(c, path, n);
    s->release_px = calloc(cnt, sizeof *s->release_px);
    s->release_py = calloc(cnt, sizeof *s->release_py);
    if (!s->release_px || !s->release_py)
        return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < cnt; i++) {
        char p[96];
        double xy[2];
        struct fy_node *e = fy_node_sequence_get_by_index(n, (int)i);
        yr_pathf(p, sizeof p, "%s[%zu]", path, i);
        if ((st = yr_numbers(&c->sp, e, p, 2, 2, xy, NULL)) != RF_OK)
            return st;
        if (!(fabs(xy[0]) <= RF_TRAJ_MAX_COORD && fabs(xy[1]) <= RF_TRAJ_MAX_COORD))
            return yr_fail(&c->sp, e, p, "coordinates must be finite and within +-1e+07 m");
        ty_remember(c, p, e);
        s->release_px[i] = xy[0], s->release_py[i] = xy[1];
        s->n_release = i + 1;
    }
    return RF_OK;
}

/* zone: {x: [x0, x1]} (the ground over that x-range) or {polygon: [[x, y], ...]}. */
static rf_status read_zone(ty_ctx *c, struct fy_node *n)
{
    rf_status st = yr_mapping(&c->sp, n, "release.zone");
    struct fy_node *x = fy_node_mapping_lookup_by_string(n, "x", FY_NT);
    struct fy_node *poly = fy_node_mapping_lookup_by_string(n, "polygon", FY_NT);
    if (st == RF_OK && (!x == !poly || fy_node_mapping_item_count(n) != 1))
        return yr_fail(&c->sp, n, "release.zone", "expected {x: [x0, x1]} or {polygon: [[x, y], ...]}");
    ty_remember(c, "release.zone", n);
    if (st != RF_OK || poly)
        return st != RF_OK ? st : read_points(c, poly, "release.zone.polygon", 3, MAX_POLYGON);
    double r[2];
    if ((st = yr_numbers(&c->sp, x, "release.zone.x", 2, 2, r, NULL)) != RF_OK)
        return st;
    if (!(isfinite(r[0]) && isfinite(r[1]) && r[0] < r[1]))
        return yr_fail(&c->sp, x, "release.zone.x", "expected [x0, x1] with x0 < x1 [m]");
    c->spec->zone_x0 = r[0], c->spec->zone_x1 = r[1];
    return RF_OK;
}

static struct fy_node *key_node(struct fy_node *n, const char *key)
{
    return fy_node_mapping_lookup_by_string(n, key, FY_NT);
}

rf_status ty_parse_release(ty_ctx *c, struct fy_node *n)
{
    rf_traj_spec *s = c->spec;
    rf_status st = yr_mapping(&c->sp, n, "release");
    if (st != RF_OK)
        return st;
    struct fy_node *line = key_node(n, "line"), *zone = key_node(n, "zone");
    int by_speed = key_node(n, "speed") || key_node(n, "angle");
    if (by_speed && (key_node(n, "vx") || key_node(n, "vy")))
        return yr_fail(&c->sp, n, "release", "the velocity is vx, vy or speed, angle: not both");
    if (line && zone)
        return yr_fail(&c->sp, n, "release", "a line or a zone: not both");
    if ((line || zone) && (key_node(n, "x") || key_node(n, "y")))
        return yr_fail(&c->sp, n, "release", "a point (x, y) or a line or zone: not both");
    s->release_by_speed = by_speed;
    if (line) {
        s->release_kind = RF_TRAJ_RELEASE_LINE;
        st = read_points(c, line, "release.line", 2, 1000000);
    } else if (zone) {
        s->release_kind = RF_TRAJ_RELEASE_ZONE;
        st = read_zone(c, zone);
    }
    if (st == RF_OK)
        st = ty_fields(c, n, "release", "line zone");
    if (st == RF_OK && by_speed && isnan(s->speed0))
        return yr_fail(&c->sp, n, "release", "speed [m/s] is required with angle");
    return st;
}

void ty_release_nominal(rf_traj_spec *s)
{
    if (s->release_kind == RF_TRAJ_RELEASE_POINT)
        return;
    rf_traj_spec probe = *s;
    probe.law = RF_BOUNCE_CONSTANT; /* geometry only */
    probe.n_collectors = 0;
    rf_traj_world *w;
    rf_error err;
    if (rf_traj_world_create(&probe, &w, &err) != RF_OK)
        return; /* the validation reports it */
    traj_release_point(w, 0.5, &s->x0, &s->y0);
    rf_traj_world_free(w);
}
