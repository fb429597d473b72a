/* block_shape.c - the block shapes of issue 30 and their exact mass
 * properties: sphere, ellipsoid (closed forms: V = 4/3 pi a b c,
 * I_a = m (b^2 + c^2) / 5), box and any convex polyhedron (the hull of a
 * point cloud, block_hull.c, with the tetrahedral integrals of
 * block_mass.c); stretching and scaling at constant volume; the support
 * point.  The body frame is the principal frame (I1 <= I2 <= I3) at the
 * centre of mass; for an ellipsoid that puts the longest semi-axis on body
 * x. */
#include "trajectory/block_internal.h"

#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static void identity(double a[9])
{
    for (int i = 0; i < 9; i++)
        a[i] = i % 4 == 0;
}

static rf_status check_positive(const char *what, double v, rf_error *err)
{
    if (!(v > 0) || !isfinite(v))
        return rf_fail(err, RF_EINVAL, "block: %s = %g; a positive finite number is needed", what, v);
    return RF_OK;
}

rf_status rf_block_sphere(double radius, double density, rf_block_shape *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    if (check_positive("radius [m]", radius, err) || check_positive("density [kg/m^3]", density, err))
        return RF_EINVAL;
    s->kind = RF_BLOCK_SPHERE;
    s->semi[0] = s->semi[1] = s->semi[2] = radius;
    s->density = density;
    s->volume = 4.0 / 3.0 * PI * radius * radius * radius;
    s->mass = density * s->volume;
    s->inertia[0] = s->inertia[1] = s->inertia[2] = 0.4 * s->mass * radius * radius;
    s->bound_radius = radius;
    identity(s->axes);
    return RF_OK;
}

/* Semi-axes sorted longest first (I ascending), axes the permutation (a
 * proper rotation) from the body to the given frame. */
static void ellipsoid_frame(rf_block_shape *s, const double given[3])
{
    int ord[3] = {0, 1, 2};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (given[ord[j]] < given[ord[j + 1]]) {
                int t = ord[j];
                ord[j] = ord[j + 1], ord[j + 1] = t;
            }
    memset(s->axes, 0, sizeof s->axes);
    for (int b = 0; b < 3; b++) {
        s->semi[b] = given[ord[b]];
        s->axes[3 * ord[b] + b] = 1;
    }
    double c0[3] = {s->axes[0], s->axes[3], s->axes[6]}, c1[3] = {s->axes[1], s->axes[4], s->axes[7]}, x[3];
    bk_cross(c0, c1, x);
    if (x[0] * s->axes[2] + x[1] * s->axes[5] + x[2] * s->axes[8] < 0)
        s->axes[2] = -s->axes[2], s->axes[5] = -s->axes[5], s->axes[8] = -s->axes[8];
}

static void ellipsoid_props(rf_block_shape *s)
{
    double a = s->semi[0], b = s->semi[1], c = s->semi[2];
    s->volume = 4.0 / 3.0 * PI * a * b * c;
    s->mass = s->density * s->volume;
    s->inertia[0] = s->mass * (b * b + c * c) / 5;
    s->inertia[1] = s->mass * (a * a + c * c) / 5;
    s->inertia[2] = s->mass * (a * a + b * b) / 5;
    s->bound_radius = a;
}

rf_status rf_block_ellipsoid(double a, double b, double c, double density, rf_block_shape *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    if (check_positive("semi-axis a [m]", a, err) || check_positive("semi-axis b [m]", b, err) ||
        check_positive("semi-axis c [m]", c, err) || check_positive("density [kg/m^3]", density, err))
        return RF_EINVAL;
    s->kind = RF_BLOCK_ELLIPSOID;
    s->density = density;
    double given[3] = {a, b, c};
    ellipsoid_frame(s, given);
    ellipsoid_props(s);
    return RF_OK;
}

/* The hull's vertices only, faces renumbered. */
static rf_status compact(const double *points, int *faces, size_t n_faces, size_t n, rf_block_shape *s, rf_error *err)
{
    int *map = malloc(n * sizeof *map);
    if (!map)
        return rf_fail(err, RF_ENOMEM, "block: out of memory");
    for (size_t i = 0; i < n; i++)
        map[i] = -1;
    size_t m = 0;
    for (size_t k = 0; k < 3 * n_faces; k++)
        if (map[faces[k]] < 0)
            map[faces[k]] = (int)m++;
    s->vertices = malloc(3 * m * sizeof *s->vertices);
    if (!s->vertices) {
        free(map);
        return rf_fail(err, RF_ENOMEM, "block: out of memory");
    }
    for (size_t i = 0; i < n; i++)
        if (map[i] >= 0)
            memcpy(s->vertices + 3 * (size_t)map[i], points + 3 * i, 3 * sizeof *points);
    for (size_t k = 0; k < 3 * n_faces; k++)
        faces[k] = map[faces[k]];
    free(map);
    s->n_vertices = m, s->faces = faces, s->n_faces = n_faces;
    return RF_OK;
}

/* Mass properties, then the vertices into the principal frame. */
static void polyhedron_frame(rf_block_shape *s)
{
    double vol, c[3], in[9], val[3];
    rf_block_mesh_mass(s->vertices, s->n_faces, s->faces, &vol, c, in);
    rf_block_sym_eigen(in, val, s->axes);
    memcpy(s->centre, c, sizeof c);
    s->volume = vol;
    s->mass = s->density * vol;
    s->bound_radius = 0;
    for (int i = 0; i < 3; i++)
        s->inertia[i] = s->density * val[i];
    for (size_t i = 0; i < s->n_vertices; i++) {
        double *p = s->vertices + 3 * i, d[3];
        bk_sub(p, c, d);
        bk_mat_tvec(s->axes, d, p);
        s->bound_radius = fmax(s->bound_radius, bk_norm(p));
    }
}

rf_status rf_block_polyhedron(size_t n, const double *points, double density, rf_block_shape *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    if (check_positive("density [kg/m^3]", density, err))
        return RF_EINVAL;
    int *faces;
    size_t n_faces;
    rf_status rc = rf_block_hull(n, points, &faces, &n_faces, err);
    if (rc != RF_OK)
        return rc;
    s->kind = RF_BLOCK_POLYHEDRON;
    s->density = density;
    rc = compact(points, faces, n_faces, n, s, err);
    if (rc != RF_OK) {
        free(faces);
        return rc;
    }
    polyhedron_frame(s);
    return RF_OK;
}

rf_status rf_block_box(double lx, double ly, double lz, double density, rf_block_shape *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    if (check_positive("box edge lx [m]", lx, err) || check_positive("box edge ly [m]", ly, err) ||
        check_positive("box edge lz [m]", lz, err))
        return RF_EINVAL;
    double p[24];
    for (int i = 0; i < 8; i++) {
        p[3 * i] = (i & 1 ? 0.5 : -0.5) * lx;
        p[3 * i + 1] = (i & 2 ? 0.5 : -0.5) * ly;
        p[3 * i + 2] = (i & 4 ? 0.5 : -0.5) * lz;
    }
    return rf_block_polyhedron(8, p, density, s, err);
}

/* The EOTA stand-in: the cube [-1, 1]^3 with each corner cut by the plane
 * through the points a quarter edge (0.5) from it, stretched by str. */
static rf_status eota(const double str[3], double volume, double density, rf_block_shape *s, rf_error *err)
{
    double p[72];
    for (int k = 0; k < 8; k++)
        for (int a = 0; a < 3; a++)
            for (int c = 0; c < 3; c++) {
                double sign = (k >> c) & 1 ? 1 : -1;
                p[9 * k + 3 * a + c] = str[c] * sign * (c == a ? 0.5 : 1.0);
            }
    rf_status rc = rf_block_polyhedron(24, p, density, s, err);
    if (rc == RF_OK)
        rc = rf_block_scale_to_volume(s, volume, err);
    return rc;
}

rf_status rf_block_eota_cube(double volume, double density, rf_block_shape *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    double str[3] = {1, 1, 1};
    return check_positive("volume [m^3]", volume, err) ? RF_EINVAL : eota(str, volume, density, s, err);
}

rf_status rf_block_eota_wheel(double volume, double density, rf_block_shape *s, rf_error *err)
{
    memset(s, 0, sizeof *s);
    double str[3] = {2, 2, 1};
    return check_positive("volume [m^3]", volume, err) ? RF_EINVAL : eota(str, volume, density, s, err);
}

rf_status rf_block_scale_to_volume(rf_block_shape *s, double volume, rf_error *err)
{
    if (check_positive("volume [m^3]", volume, err))
        return RF_EINVAL;
    double f = cbrt(volume / s->volume), f2 = f * f;
    for (size_t i = 0; i < 3 * s->n_vertices; i++)
        s->vertices[i] *= f;
    for (int i = 0; i < 3; i++)
        s->semi[i] *= f, s->inertia[i] *= f2 * f2 * f, s->centre[i] *= f;
    s->volume = volume;
    s->mass = s->density * volume;
    s->bound_radius *= f;
    return RF_OK;
}

rf_status rf_block_stretch(rf_block_shape *s, double sx, double sy, double sz, double volume, rf_error *err)
{
    if (check_positive("stretch sx", sx, err) || check_positive("stretch sy", sy, err) ||
        check_positive("stretch sz", sz, err))
        return RF_EINVAL;
    double str[3] = {sx, sy, sz};
    if (s->kind == RF_BLOCK_POLYHEDRON) {
        rf_block_shape t;
        for (size_t i = 0; i < s->n_vertices; i++)
            for (int c = 0; c < 3; c++)
                s->vertices[3 * i + c] *= str[c];
        rf_status rc = rf_block_polyhedron(s->n_vertices, s->vertices, s->density, &t, err);
        if (rc != RF_OK)
            return rc;
        rf_block_shape_free(s);
        *s = t;
    } else {
        double given[3] = {s->semi[0] * sx, s->semi[1] * sy, s->semi[2] * sz};
        s->kind = RF_BLOCK_ELLIPSOID;
        ellipsoid_frame(s, given);
        memset(s->centre, 0, sizeof s->centre);
        ellipsoid_props(s);
    }
    return volume > 0 ? rf_block_scale_to_volume(s, volume, err) : RF_OK;
}

rf_status rf_block_copy(const rf_block_shape *src, rf_block_shape *dst, rf_error *err)
{
    *dst = *src;
    dst->vertices = NULL, dst->faces = NULL;
    if (src->kind != RF_BLOCK_POLYHEDRON)
        return RF_OK;
    dst->vertices = malloc(3 * src->n_vertices * sizeof *dst->vertices);
    dst->faces = malloc(3 * src->n_faces * sizeof *dst->faces);
    if (!dst->vertices || !dst->faces) {
        rf_block_shape_free(dst);
        return rf_fail(err, RF_ENOMEM, "block: out of memory");
    }
    memcpy(dst->vertices, src->vertices, 3 * src->n_vertices * sizeof *dst->vertices);
    memcpy(dst->faces, src->faces, 3 * src->n_faces * sizeof *dst->faces);
    return RF_OK;
}

void rf_block_shape_free(rf_block_shape *s)
{
    free(s->vertices);
    free(s->faces);
    s->vertices = NULL, s->faces = NULL, s->n_vertices = s->n_faces = 0;
}

double rf_block_support(const rf_block_shape *s, const double d[3], double p[3])
{
    if (s->kind != RF_BLOCK_POLYHEDRON) {
        double a2[3] = {s->semi[0] * s->semi[0], s->semi[1] * s->semi[1], s->semi[2] * s->semi[2]};
        double den = sqrt(a2[0] * d[0] * d[0] + a2[1] * d[1] * d[1] + a2[2] * d[2] * d[2]);
        for (int i = 0; i < 3; i++)
            p[i] = den > 0 ? a2[i] * d[i] / den : 0;
        return bk_dot(d, p);
    }
    size_t best = 0;
    double hmax = -INFINITY;
    for (size_t i = 0; i < s->n_vertices; i++) {
        double h = bk_dot(d, s->vertices + 3 * i);
        if (h > hmax)
            hmax = h, best = i;
    }
    memcpy(p, s->vertices + 3 * best, 3 * sizeof *p);
    return hmax;
}
