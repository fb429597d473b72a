/* terrain_release.c - the release features of a terrain file as pieces a
 * point is drawn on: a point feature is one piece, a line its segments
 * (weighted by length), a polygon the triangles of its ear-clipping
 * triangulation (weighted by area; simple polygons, concave allowed, a
 * self-intersecting one refused).  The map point at uniforms u1, u2, u3: u1
 * picks the feature by weight (cumulative weights), the remainder of u1
 * rescaled to [0, 1) picks the piece by length or area, u2 (and u3 in a
 * triangle, by the square-root rule) the point in it. */
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct terrain_release_set {
    rf_terrain_feature_kind kind;
    size_t n_features;
    double *fcum;               /* n_features: cumulative weight share, the last 1 */
    size_t *pstart;             /* n_features + 1 offsets into the pieces */
    double *pcum;               /* per piece: cumulative share inside its feature, the feature's last 1 */
    double (*v)[6];             /* per piece: A, B, C (a point: A; a segment: A, B) */
    size_t n_pieces, cap_pieces;
};

static const char *const kind_name[] = {"points", "lines", "polygons"};

static int add_piece(terrain_release_set *r, const double v[6], double size)
{
    if (r->n_pieces == r->cap_pieces) {
        size_t cap = r->cap_pieces ? 2 * r->cap_pieces : 64;
        double (*nv)[6] = realloc(r->v, cap * sizeof *nv);
        double *nc = nv ? realloc(r->pcum, cap * sizeof *nc) : NULL;
        if (nv)
            r->v = nv;
        if (!nc)
            return 0;
        r->pcum = nc, r->cap_pieces = cap;
    }
    memcpy(r->v[r->n_pieces], v, sizeof *r->v);
    r->pcum[r->n_pieces++] = size; /* a size for now; made cumulative by finish_feature */
    return 1;
}

static double orient(double ax, double ay, double bx, double by, double cx, double cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

/* q on the segment p-r, given p, q, r collinear. */
static int on_segment(double px, double py, double qx, double qy, double rx, double ry)
{
    return qx >= fmin(px, rx) && qx <= fmax(px, rx) && qy >= fmin(py, ry) && qy <= fmax(py, ry);
}

static int segments_meet(const double *x, const double *y, size_t a, size_t b, size_t c, size_t d)
{
    double o1 = orient(x[a], y[a], x[b], y[b], x[c], y[c]), o2 = orient(x[a], y[a], x[b], y[b], x[d], y[d]);
    double o3 = orient(x[c], y[c], x[d], y[d], x[a], y[a]), o4 = orient(x[c], y[c], x[d], y[d], x[b], y[b]);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return 1;
    return (o1 == 0 && on_segment(x[a], y[a], x[c], y[c], x[b], y[b])) ||
           (o2 == 0 && on_segment(x[a], y[a], x[d], y[d], x[b], y[b])) ||
           (o3 == 0 && on_segment(x[c], y[c], x[a], y[a], x[d], y[d])) ||
           (o4 == 0 && on_segment(x[c], y[c], x[b], y[b], x[d], y[d]));
}

/* The first pair of non-adjacent edges of the ring that meet (edges i, j), or 0. */
static int ring_self_intersects(const double *x, const double *y, size_t n, size_t *ei, size_t *ej)
{
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1)
                continue; /* adjacent through the closing vertex */
            if (segments_meet(x, y, i, i + 1, j, (j + 1) % n)) {
                *ei = i, *ej = j;
                return 1;
            }
        }
    return 0;
}

/* (px, py) inside or on the triangle a, b, c (counter-clockwise). */
static int in_triangle(double px, double py, const double t[6])
{
    return orient(t[0], t[1], t[2], t[3], px, py) >= 0 && orient(t[2], t[3], t[4], t[5], px, py) >= 0 &&
           orient(t[4], t[5], t[0], t[1], px, py) >= 0;
}

/* Is vertex idx[k] of the remaining ring (m vertices, counter-clockwise) an
 * ear: convex with no other remaining vertex in its triangle?  *flat: it is
 * collinear with its neighbours (clipping it leaves the region unchanged). */
static int is_ear(const double *x, const double *y, const size_t *idx, size_t m, size_t k, double t[6], int *flat)
{
    size_t a = idx[(k + m - 1) % m], b = idx[k], c = idx[(k + 1) % m];
    double t0[6] = {x[a], y[a], x[b], y[b], x[c], y[c]};
    memcpy(t, t0, sizeof t0);
    double o = orient(x[a], y[a], x[b], y[b], x[c], y[c]);
    double scale = fabs(x[c] - x[a]) + fabs(y[c] - y[a]) + fabs(x[b] - x[a]) + fabs(y[b] - y[a]);
    *flat = fabs(o) <= 1e-14 * scale * scale;
    if (*flat)
        return 1;
    if (o < 0)
        return 0;
    for (size_t q = 0; q < m; q++) {
        size_t p = idx[q];
        if (p == a || p == b || p == c || (x[p] == x[a] && y[p] == y[a]) || (x[p] == x[b] && y[p] == y[b]) ||
            (x[p] == x[c] && y[p] == y[c]))
            continue;
        if (in_triangle(x[p], y[p], t))
            return 0;
    }
    return 1;
}

static double ring_area(const double *x, const double *y, size_t n)
{
    double a = 0;
    for (size_t i = 0; i < n; i++) {
        size_t j = (i + 1) % n;
        a += (x[i] - x[0]) * (y[j] - y[0]) - (x[j] - x[0]) * (y[i] - y[0]);
    }
    return 0.5 * a;
}

/* Ear clipping of the ring x, y (n >= 3, simple) into triangles of r. */
static rf_status triangulate(terrain_release_set *r, const double *x, const double *y, size_t n, size_t f,
                             rf_error *err)
{
    size_t *idx = malloc(n * sizeof *idx), m = n;
    if (!idx)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    int ccw = ring_area(x, y, n) > 0;
    for (size_t i = 0; i < n; i++)
        idx[i] = ccw ? i : n - 1 - i;
    size_t k = 0, tries = 0;
    while (m > 2) {
        double t[6];
        int flat;
        if (tries > m) {
            free(idx);
            return rf_fail(err, RF_EINVAL, "release.polygons[%zu]: no ear left to clip (a degenerate polygon)", f);
        }
        if (!is_ear(x, y, idx, m, k, t, &flat)) {
            k = (k + 1) % m, tries++;
            continue;
        }
        if (!flat && !add_piece(r, t, 0.5 * orient(t[0], t[1], t[2], t[3], t[4], t[5]))) {
            free(idx);
            return rf_fail(err, RF_ENOMEM, "out of memory");
        }
        memmove(idx + k, idx + k + 1, (m - k - 1) * sizeof *idx);
        m--, tries = 0;
        if (k >= m)
            k = 0;
    }
    free(idx);
    return RF_OK;
}

/* The pieces of feature f (its vertices x, y [0, n)). */
static rf_status feature_pieces(terrain_release_set *r, const rf_terrain_release *rel, size_t f, rf_error *err)
{
    const double *x = rel->x + rel->start[f], *y = rel->y + rel->start[f];
    size_t n = rel->start[f + 1] - rel->start[f];
    if (rel->kind == RF_TERRAIN_POINTS) {
        double v[6] = {x[0], y[0], x[0], y[0], x[0], y[0]};
        return add_piece(r, v, 1) ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory");
    }
    if (rel->kind == RF_TERRAIN_LINES) {
        for (size_t i = 0; i + 1 < n; i++) {
            double v[6] = {x[i], y[i], x[i + 1], y[i + 1], 0, 0};
            if (!add_piece(r, v, hypot(x[i + 1] - x[i], y[i + 1] - y[i])))
                return rf_fail(err, RF_ENOMEM, "out of memory");
        }
        return RF_OK;
    }
    size_t ei, ej;
    if (ring_self_intersects(x, y, n, &ei, &ej))
        return rf_fail(err, RF_EINVAL, "release.polygons[%zu]: edges %zu ([%g, %g]-[%g, %g]) and %zu ([%g, %g]-"
                       "[%g, %g]) meet: the polygon intersects itself (give a simple polygon)", f, ei, x[ei], y[ei],
                       x[ei + 1], y[ei + 1], ej, x[ej], y[ej], x[(ej + 1) % n], y[(ej + 1) % n]);
    return triangulate(r, x, y, n, f, err);
}

/* The sizes of feature f's pieces [from, n_pieces) made cumulative shares. */
static rf_status finish_feature(terrain_release_set *r, const rf_terrain_release *rel, size_t f, size_t from,
                                rf_error *err)
{
    double total = 0;
    for (size_t p = from; p < r->n_pieces; p++)
        total += r->pcum[p];
    if (r->n_pieces == from || !(total > 0)) {
        if (rel->kind == RF_TERRAIN_POLYGONS)
            return rf_fail(err, RF_EINVAL, "release.polygons[%zu]: the polygon has no area", f);
        /* a line of zero length: its first vertex */
        for (size_t p = from; p < r->n_pieces; p++)
            r->pcum[p] = 1;
        return RF_OK;
    }
    double acc = 0;
    for (size_t p = from; p < r->n_pieces; p++)
        acc += r->pcum[p], r->pcum[p] = acc / total;
    r->pcum[r->n_pieces - 1] = 1;
    return RF_OK;
}

static rf_status check_counts(const rf_terrain_release *rel, rf_error *err)
{
    size_t need = rel->kind == RF_TERRAIN_POINTS ? 1 : rel->kind == RF_TERRAIN_LINES ? 2 : 3;
    double total = 0;
    if (rel->n_features == 0)
        return rf_fail(err, RF_EINVAL, "release: no release feature");
    for (size_t f = 0; f < rel->n_features; f++) {
        size_t n = rel->start[f + 1] - rel->start[f];
        if (n < need || (rel->kind == RF_TERRAIN_POINTS && n != 1))
            return rf_fail(err, RF_EINVAL, "release.%s[%zu]: %zu vertices; a %s needs %s%zu", kind_name[rel->kind], f,
                           n, rel->kind == RF_TERRAIN_POINTS ? "point" : rel->kind == RF_TERRAIN_LINES ? "line"
                           : "polygon", rel->kind == RF_TERRAIN_POINTS ? "" : "at least ", need);
        if (!(rel->weight[f] >= 0 && isfinite(rel->weight[f])))
            return rf_fail(err, RF_EINVAL, "release.blocks[%zu] = %g: must be finite and >= 0", f, rel->weight[f]);
        total += rel->weight[f];
    }
    if (!(total > 0 && isfinite(total)))
        return rf_fail(err, RF_EINVAL, "release.blocks: the weights sum to %g; at least one must be > 0", total);
    return RF_OK;
}

static rf_status build_set(terrain_release_set *r, const rf_terrain_release *rel, rf_error *err)
{
    rf_status st = check_counts(rel, err);
    if (st != RF_OK)
        return st;
    r->kind = rel->kind, r->n_features = rel->n_features;
    r->fcum = malloc(rel->n_features * sizeof *r->fcum);
    r->pstart = malloc((rel->n_features + 1) * sizeof *r->pstart);
    if (!r->fcum || !r->pstart)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    double total = 0, acc = 0;
    for (size_t f = 0; f < rel->n_features; f++)
        total += rel->weight[f];
    for (size_t f = 0; f < rel->n_features && st == RF_OK; f++) {
        r->pstart[f] = r->n_pieces;
        acc += rel->weight[f];
        r->fcum[f] = acc / total;
        if ((st = feature_pieces(r, rel, f, err)) == RF_OK)
            st = finish_feature(r, rel, f, r->pstart[f], err);
    }
    r->pstart[rel->n_features] = r->n_pieces;
    /* the last feature of positive weight ends at exactly 1 */
    for (size_t f = rel->n_features; f-- > 0;) {
        r->fcum[f] = 1;
        if (rel->weight[f] > 0)
            break;
    }
    return st;
}

rf_status terrain_release_prepare(const rf_traj_spec *s, terrain_release_set **set, rf_error *err)
{
    *set = NULL;
    if (!s->terrain)
        return rf_fail(err, RF_EINVAL, "release: not a terrain file");
    terrain_release_set *r = calloc(1, sizeof *r);
    if (!r)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    rf_status st = build_set(r, &s->terrain->release, err);
    if (st != RF_OK) {
        terrain_release_free(r);
        return st;
    }
    *set = r;
    return RF_OK;
}

void terrain_release_free(terrain_release_set *set)
{
    if (!set)
        return;
    free(set->fcum);
    free(set->pstart);
    free(set->pcum);
    free(set->v);
    free(set);
}

/* The first index in [lo, hi) with c[index] > u (hi - 1 if none: u rounds to 1). */
static size_t first_above(const double *c, size_t lo, size_t hi, double u)
{
    size_t a = lo, b = hi - 1;
    while (a < b) {
        size_t mid = a + (b - a) / 2;
        if (c[mid] > u)
            b = mid;
        else
            a = mid + 1;
    }
    return a;
}

void terrain_release_point(const terrain_release_set *set, double u1, double u2, double u3, double *x, double *y)
{
    size_t f = first_above(set->fcum, 0, set->n_features, u1);
    double lo = f ? set->fcum[f - 1] : 0, w = set->fcum[f] - lo;
    double r = w > 0 ? (u1 - lo) / w : 0; /* the remainder of u1, rescaled */
    r = fmin(fmax(r, 0), 1);
    size_t a = set->pstart[f], b = set->pstart[f + 1];
    size_t p = first_above(set->pcum, a, b, r);
    const double *v = set->v[p];
    if (set->kind == RF_TERRAIN_POINTS) {
        *x = v[0], *y = v[1];
    } else if (set->kind == RF_TERRAIN_LINES) {
        *x = v[0] + u2 * (v[2] - v[0]), *y = v[1] + u2 * (v[3] - v[1]);
    } else {
        double sq = sqrt(u2), wa = 1 - sq, wb = sq * (1 - u3), wc = sq * u3;
        *x = wa * v[0] + wb * v[2] + wc * v[4], *y = wa * v[1] + wb * v[3] + wc * v[5];
    }
}

/* For tests: the triangles (or segments) of feature f, and their count. */
size_t terrain_release_pieces(const terrain_release_set *set, size_t f, const double (**v)[6])
{
    *v = set->v + set->pstart[f];
    return set->pstart[f + 1] - set->pstart[f];
}
