/* block_traj_yaml.c - the rigid block of a trajectory file (docs/block-shape.md
 * "Wiring"): block: {shape: ellipsoid, axes: [a, b, c]} | {shape: box, edges:
 * [lx, ly, lz]} | {shape: polyhedron, points: [[x, y, z], ...] | points_file:
 * F} | {shape: eota_cube | eota_wheel, volume: V}, with density, volume,
 * axis_ratios: [1, b/a, c/a], orientation: [w, x, y, z] | {yaw, pitch, roll}
 * (deg) | random, spin: [wx, wy, wz] (rad/s).  The numeric rows (density,
 * volume, axis_ratio_b/c, time_step, ...) are read by ty_fields; the rest
 * here, with file:line messages. */
#include "trajectory/block_traj.h"
#include "trajectory/traj_yaml_internal.h"
#include "core/textfile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BLOCK_MAX_POINTS 100000

static const char *const kind_names[] = {"", "ellipsoid", "box", "polyhedron", "eota_cube", "eota_wheel"};

int traj_block_kind_of(const char *str, size_t len)
{
    for (int k = 1; k < (int)(sizeof kind_names / sizeof kind_names[0]); k++)
        if (strlen(kind_names[k]) == len && !strncmp(kind_names[k], str, len))
            return k;
    return 0;
}

static struct fy_node *key_of(struct fy_node *n, const char *k)
{
    return fy_node_mapping_lookup_by_string(n, k, FY_NT);
}

/* Three positive finite numbers under `path`. */
static rf_status positive3(ty_ctx *c, struct fy_node *v, const char *path, double out[3])
{
    size_t cnt = 0;
    rf_status st = yr_numbers(&c->sp, v, path, 3, 3, out, &cnt);
    for (int k = 0; st == RF_OK && k < 3; k++)
        if (!(out[k] > 0) || !isfinite(out[k]))
            return yr_fail(&c->sp, v, path, "every value must be a positive length in m (got %g)", out[k]);
    if (st == RF_OK)
        ty_remember(c, path, v);
    return st;
}

static rf_status add_point(ty_ctx *c, struct fy_node *at, const char *path, const double p[3], size_t *cap)
{
    rf_traj_spec *s = c->spec;
    for (int k = 0; k < 3; k++)
        if (!isfinite(p[k]) || fabs(p[k]) > RF_TRAJ_MAX_COORD)
            return yr_fail(&c->sp, at, path, "point %zu: coordinate %g is not a finite length within 1e7 m",
                           s->block_n_points + 1, p[k]);
    if (s->block_n_points >= BLOCK_MAX_POINTS)
        return yr_fail(&c->sp, at, path, "more than %d points", BLOCK_MAX_POINTS);
    if (s->block_n_points == *cap) {
        size_t nc = *cap ? 2 * *cap : 64;
        double *q = realloc(s->block_points, 3 * nc * sizeof *q);
        if (!q)
            return rf_fail(c->sp.err, RF_ENOMEM, "out of memory");
        s->block_points = q, *cap = nc;
    }
    memcpy(s->block_points + 3 * s->block_n_points++, p, 3 * sizeof *p);
    return RF_OK;
}

/* points: [[x, y, z], ...] */
static rf_status points_list(ty_ctx *c, struct fy_node *v)
{
    size_t cap = 0, i = 0, n = 0;
    rf_status st = yr_sequence(&c->sp, v, "block.points", 4, BLOCK_MAX_POINTS, &n);
    void *it = NULL;
    for (struct fy_node *e; st == RF_OK && (e = fy_node_sequence_iterate(v, &it)); i++) {
        char path[64];
        double p[3];
        size_t cnt;
        yr_pathf(path, sizeof path, "block.points[%zu]", i);
        if ((st = yr_numbers(&c->sp, e, path, 3, 3, p, &cnt)) == RF_OK)
            st = add_point(c, e, "block.points", p, &cap);
    }
    return st;
}

/* points_file: a CSV of x,y,z lines (a header line and '#' comments allowed), relative to the trajectory file. */
static rf_status points_file(ty_ctx *c, struct fy_node *v)
{
    char *f = NULL, *buf = NULL, path[4096];
    size_t len, cap = 0;
    rf_status st = yr_string_dup(&c->sp, v, "block.points_file", &f);
    if (st != RF_OK)
        return st;
    snprintf(path, sizeof path, "%s%s%s", f[0] == '/' || !strcmp(c->sp.dir, ".") ? "" : c->sp.dir,
             f[0] == '/' || !strcmp(c->sp.dir, ".") ? "" : "/", f);
    free(f);
    if ((st = rf_read_text_file(path, "block.points_file", 64u << 20, &buf, &len, c->sp.err)) != RF_OK)
        return st;
    int line = 0;
    for (char *l = buf, *next; st == RF_OK && l && *l; l = next) {
        next = strchr(l, '\n');
        if (next)
            *next++ = '\0';
        line++;
        double p[3];
        char tail;
        if (l[strspn(l, " \t\r")] == '\0' || l[strspn(l, " \t")] == '#')
            continue;
        if (sscanf(l, " %lf , %lf , %lf %c", &p[0], &p[1], &p[2], &tail) == 3 ||
            sscanf(l, " %lf , %lf , %lf , %c", &p[0], &p[1], &p[2], &tail) >= 3)
            st = add_point(c, v, "block.points_file", p, &cap);
        else if (!(line == 1 && !c->spec->block_n_points)) /* a header line */
            st = rf_fail(c->sp.err, RF_EINVAL, "%s:%d: block.points_file: expected x,y,z [m], got \"%.60s\"", path,
                         line, l);
    }
    free(buf);
    if (st == RF_OK && c->spec->block_n_points < 4)
        return yr_fail(&c->sp, v, "block.points_file", "%s holds %zu points; a polyhedron needs at least 4", path,
                       c->spec->block_n_points);
    return st;
}

/* yaw (about z), pitch (about y), roll (about x) in degrees: q = q_z(yaw) q_y(pitch) q_x(roll). */
static void ypr_quat(double yaw, double pitch, double roll, double q[4])
{
    double cy = cos(yaw / 2), sy = sin(yaw / 2), cp = cos(pitch / 2), sp = sin(pitch / 2);
    double cr = cos(roll / 2), sr = sin(roll / 2);
    q[0] = cy * cp * cr + sy * sp * sr;
    q[1] = cy * cp * sr - sy * sp * cr;
    q[2] = cy * sp * cr + sy * cp * sr;
    q[3] = sy * cp * cr - cy * sp * sr;
}

static rf_status orientation(ty_ctx *c, struct fy_node *v)
{
    rf_traj_spec *s = c->spec;
    ty_remember(c, "block.orientation", v);
    if (fy_node_is_scalar(v)) {
        const char *str;
        size_t len;
        rf_status st = yr_string(&c->sp, v, "block.orientation", &str, &len);
        if (st == RF_OK && !(len == 6 && !strncmp(str, "random", 6)))
            return yr_fail(&c->sp, v, "block.orientation", "expected random, [w, x, y, z] or {yaw, pitch, roll} (deg)");
        s->block_random_orientation = 1;
        return st;
    }
    if (fy_node_is_sequence(v)) {
        size_t cnt;
        double q[4];
        rf_status st = yr_numbers(&c->sp, v, "block.orientation", 4, 4, q, &cnt);
        double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (st == RF_OK && !(n > 1e-12 && isfinite(n)))
            return yr_fail(&c->sp, v, "block.orientation", "the quaternion [w, x, y, z] has norm %g", n);
        for (int k = 0; st == RF_OK && k < 4; k++)
            s->block_q0[k] = q[k] / n;
        return st;
    }
    rf_status st = yr_mapping(&c->sp, v, "block.orientation");
    double a[3] = {0, 0, 0};
    const char *names[3] = {"yaw", "pitch", "roll"};
    yr_iter it = {v, NULL, 0, {0}};
    const char *key;
    struct fy_node *k, *x;
    while (st == RF_OK && (st = yr_next(&c->sp, &it, "block.orientation", &key, &k, &x)) == RF_OK && key) {
        int i = !strcmp(key, "yaw") ? 0 : !strcmp(key, "pitch") ? 1 : !strcmp(key, "roll") ? 2 : -1;
        char p[64];
        yr_pathf(p, sizeof p, "block.orientation.%s", key);
        if (i < 0)
            return yr_fail(&c->sp, k, p, "unknown key; block.orientation takes: yaw, pitch, roll (deg)");
        if ((st = yr_number(&c->sp, x, p, &a[i])) == RF_OK && !(fabs(a[i]) <= 360))
            return yr_fail(&c->sp, x, p, "%s = %g deg: must lie in [-360, 360]", names[i], a[i]);
    }
    if (st == RF_OK)
        ypr_quat(a[0] * RF_PI / 180, a[1] * RF_PI / 180, a[2] * RF_PI / 180, s->block_q0);
    return st;
}

/* axis_ratios: [1, b/a, c/a] into the rows axis_ratio_b, axis_ratio_c. */
static rf_status axis_ratios(ty_ctx *c, struct fy_node *v)
{
    double r[3];
    size_t cnt;
    rf_status st = yr_numbers(&c->sp, v, "block.axis_ratios", 3, 3, r, &cnt);
    if (st == RF_OK && r[0] != 1)
        return yr_fail(&c->sp, v, "block.axis_ratios", "the first ratio is a/a = 1 (got %g)", r[0]);
    if (st == RF_OK && (!(r[1] > 0) || !(r[2] > 0) || !isfinite(r[1]) || !isfinite(r[2])))
        return yr_fail(&c->sp, v, "block.axis_ratios", "b/a = %g and c/a = %g must be positive", r[1], r[2]);
    if (st == RF_OK)
        c->spec->block_ratio_b = r[1], c->spec->block_ratio_c = r[2], ty_remember(c, "block.axis_ratios", v);
    return st;
}

/* The shape at the file's values, built once here: a shape that cannot be
 * built (coplanar points) is refused at load, and its mass becomes the
 * spec's mass (what the envelopes along x weigh; each trajectory builds its
 * own shape with its sample's values). */
static rf_status nominal_shape(ty_ctx *c, struct fy_node *n)
{
    rf_block_shape shape;
    rf_error e;
    if (!(c->spec->density > 0) || !(c->spec->block_ratio_b > 0) || !(c->spec->block_ratio_c > 0) ||
        !(c->spec->block_volume >= 0))
        return RF_OK; /* the validation names the row */
    if (traj_block_shape(c->spec, &shape, &e) != RF_OK)
        return yr_fail(&c->sp, n, "block", "shape %s: %s", kind_names[c->spec->block_kind], e.msg);
    c->spec->mass = shape.mass;
    rf_block_shape_free(&shape);
    return RF_OK;
}

/* The shape's own keys, after ty_fields read the rows. */
rf_status ty_parse_block_shape(ty_ctx *c, struct fy_node *n)
{
    rf_traj_spec *s = c->spec;
    struct fy_node *v;
    rf_status st = RF_OK;
    int kind = s->block_kind;
    const char *need = kind == RF_TRAJ_BLOCK_ELLIPSOID ? "axes" : kind == RF_TRAJ_BLOCK_BOX ? "edges" : NULL;
    const char *own[2] = {"axes", "edges"};
    for (int k = 0; k < 2; k++)
        if ((v = key_of(n, own[k])) && (!need || strcmp(need, own[k])))
            return yr_fail(&c->sp, v, own[k][0] == 'a' ? "block.axes" : "block.edges", "not used by shape %s",
                           kind_names[kind]);
    if (need && !(v = key_of(n, need)))
        return yr_fail(&c->sp, n, "block", "shape %s needs %s: [.., .., ..] (m)", kind_names[kind], need);
    if (need)
        st = positive3(c, v, kind == RF_TRAJ_BLOCK_ELLIPSOID ? "block.axes" : "block.edges", s->block_dims);
    struct fy_node *pl = key_of(n, "points"), *pf = key_of(n, "points_file");
    if (st == RF_OK && kind != RF_TRAJ_BLOCK_POLYHEDRON && (pl || pf))
        return yr_fail(&c->sp, pl ? pl : pf, pl ? "block.points" : "block.points_file", "only shape polyhedron has it");
    if (st == RF_OK && kind == RF_TRAJ_BLOCK_POLYHEDRON && !!pl == !!pf)
        return yr_fail(&c->sp, n, "block", "shape polyhedron needs exactly one of points or points_file");
    if (st == RF_OK && kind == RF_TRAJ_BLOCK_POLYHEDRON)
        st = pl ? points_list(c, pl) : points_file(c, pf);
    if (st == RF_OK && (kind == RF_TRAJ_BLOCK_EOTA_CUBE || kind == RF_TRAJ_BLOCK_EOTA_WHEEL) && !(s->block_volume > 0))
        return yr_fail(&c->sp, n, "block", "shape %s needs volume [m^3]", kind_names[kind]);
    if (st == RF_OK && (v = key_of(n, "axis_ratios"))) {
        if (key_of(n, "axis_ratio_b") || key_of(n, "axis_ratio_c"))
            return yr_fail(&c->sp, v, "block.axis_ratios", "give axis_ratios or axis_ratio_b/c, not both");
        st = axis_ratios(c, v);
    }
    if (st == RF_OK && (v = key_of(n, "orientation")))
        st = orientation(c, v);
    size_t cnt;
    if (st == RF_OK && (v = key_of(n, "spin")) &&
        (st = yr_numbers(&c->sp, v, "block.spin", 3, 3, s->block_spin0, &cnt)) == RF_OK) {
        s->block_spin_given = 1;
        for (int k = 0; k < 3; k++)
            if (!isfinite(s->block_spin0[k]))
                return yr_fail(&c->sp, v, "block.spin", "every component must be finite (rad/s)");
    }
    if (st == RF_OK && isnan(s->density))
        return yr_fail(&c->sp, n, "block", "shape %s needs density [kg/m^3]", kind_names[kind]);
    return st == RF_OK ? nominal_shape(c, n) : st;
}

const char *traj_block_kind_name(int kind)
{
    return kind > 0 && kind < (int)(sizeof kind_names / sizeof kind_names[0]) ? kind_names[kind] : "";
}
