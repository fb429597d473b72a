/* block_hull.c - the convex hull of a 3D point cloud (issue 30: polyhedral
 * blocks from scanned rocks or listed vertices).
 *
 * Incremental (Clarkson-Shor style without conflict lists, O(n F)): an
 * initial tetrahedron of four extreme points, then each further point p: the
 * faces that see it (signed distance of p above the face's plane > eps) are
 * removed and the horizon (the edges of seen faces whose other face is not
 * seen) is joined to p.  Robustness by a relative tolerance, not exact
 * predicates: eps = 1e-10 x the cloud's extent (largest coordinate range),
 * so a point within eps of the hull (on a face, a repeated vertex) is not a
 * vertex; coplanar input faces come out as several triangles, which the mass
 * properties do not mind.  A point added before the corners that later hide
 * it can stay a vertex on a face or an edge of the solid: a second pass
 * keeps only the extreme vertices (those whose face normals span space) and
 * takes their hull.  Faces are counter-clockwise seen from outside. */
#include "trajectory/block_internal.h"

#include <stdlib.h>
#include <string.h>

#define HULL_REL_EPS 1e-10

typedef struct {
    int v[3];
    double n[3]; /* unit outward normal */
    double d;    /* n . v0 */
} hull_face;

typedef struct {
    const double *p;
    double eps;
    hull_face *f;
    size_t n, cap;
} hull;

static const double *pt(const hull *h, int i)
{
    return h->p + 3 * (size_t)i;
}

/* Adds face (a, b, c); its normal from the winding. */
static int add_face(hull *h, int a, int b, int c)
{
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 64;
        hull_face *f = realloc(h->f, cap * sizeof *f);
        if (!f)
            return -1;
        h->f = f, h->cap = cap;
    }
    hull_face *f = &h->f[h->n++];
    f->v[0] = a, f->v[1] = b, f->v[2] = c;
    double e1[3], e2[3];
    bk_sub(pt(h, b), pt(h, a), e1);
    bk_sub(pt(h, c), pt(h, a), e2);
    bk_cross(e1, e2, f->n);
    double len = bk_norm(f->n);
    if (len > 0)
        f->n[0] /= len, f->n[1] /= len, f->n[2] /= len;
    f->d = bk_dot(f->n, pt(h, a));
    return 0;
}

static double dist_line(const double *a, const double *b, const double *p)
{
    double ab[3], ap[3], c[3];
    bk_sub(b, a, ab);
    bk_sub(p, a, ap);
    bk_cross(ab, ap, c);
    double l = bk_norm(ab);
    return l > 0 ? bk_norm(c) / l : bk_norm(ap);
}

static double dist_plane(const double *a, const double *b, const double *c, const double *p)
{
    double e1[3], e2[3], n[3], ap[3];
    bk_sub(b, a, e1);
    bk_sub(c, a, e2);
    bk_cross(e1, e2, n);
    bk_sub(p, a, ap);
    double l = bk_norm(n);
    return l > 0 ? bk_dot(n, ap) / l : 0;
}

/* Four points spanning a tetrahedron of extent > eps, or -1. */
static int initial_points(const hull *h, size_t n, int idx[4])
{
    idx[0] = idx[1] = idx[2] = idx[3] = 0;
    for (size_t i = 1; i < n; i++)
        if (pt(h, (int)i)[0] < pt(h, idx[0])[0])
            idx[0] = (int)i;
    double best = -1;
    for (size_t i = 0; i < n; i++) {
        double ap[3];
        bk_sub(pt(h, (int)i), pt(h, idx[0]), ap);
        if (bk_norm(ap) > best)
            best = bk_norm(ap), idx[1] = (int)i;
    }
    if (!(best > h->eps))
        return -1;
    best = -1;
    for (size_t i = 0; i < n; i++) {
        double d = dist_line(pt(h, idx[0]), pt(h, idx[1]), pt(h, (int)i));
        if (d > best)
            best = d, idx[2] = (int)i;
    }
    if (!(best > h->eps))
        return -1;
    best = -1;
    for (size_t i = 0; i < n; i++) {
        double d = fabs(dist_plane(pt(h, idx[0]), pt(h, idx[1]), pt(h, idx[2]), pt(h, (int)i)));
        if (d > best)
            best = d, idx[3] = (int)i;
    }
    return best > h->eps ? 0 : -1;
}

static int start_tetrahedron(hull *h, const int t[4])
{
    if (dist_plane(pt(h, t[0]), pt(h, t[1]), pt(h, t[2]), pt(h, t[3])) < 0) {
        /* t[3] below (t0, t1, t2): that face is outward as written */
        return add_face(h, t[0], t[1], t[2]) || add_face(h, t[0], t[3], t[1]) || add_face(h, t[1], t[3], t[2]) ||
               add_face(h, t[2], t[3], t[0]);
    }
    return add_face(h, t[0], t[2], t[1]) || add_face(h, t[0], t[1], t[3]) || add_face(h, t[1], t[2], t[3]) ||
           add_face(h, t[2], t[0], t[3]);
}

/* Is the directed edge (a, b) in one of the seen faces list[0 .. n_list)? */
static int edge_seen(const hull *h, const size_t *list, size_t n_list, int a, int b)
{
    for (size_t m = 0; m < n_list; m++) {
        const int *v = h->f[list[m]].v;
        for (int e = 0; e < 3; e++)
            if (v[e] == a && v[(e + 1) % 3] == b)
                return 1;
    }
    return 0;
}

/* Adds point i: the seen faces go, the horizon joins i.  seen has room for
 * h->n indices.  Returns -1 on allocation failure. */
static int add_point(hull *h, int i, size_t *seen)
{
    size_t n_seen = 0, n_old = h->n;
    for (size_t k = 0; k < n_old; k++)
        if (bk_dot(h->f[k].n, pt(h, i)) - h->f[k].d > h->eps)
            seen[n_seen++] = k;
    for (size_t m = 0; m < n_seen; m++)
        for (int e = 0; e < 3; e++) {
            int a = h->f[seen[m]].v[e], b = h->f[seen[m]].v[(e + 1) % 3];
            if (!edge_seen(h, seen, n_seen, b, a) && add_face(h, a, b, i))
                return -1;
        }
    /* remove the seen faces, from the back (seen is ascending), each replaced
     * by the last face (the faces after it are already free of seen ones) */
    for (size_t m = n_seen; m-- > 0;)
        h->f[seen[m]] = h->f[--h->n];
    return 0;
}

static double extent(size_t n, const double *p)
{
    double e = 0;
    for (int c = 0; c < 3; c++) {
        double lo = p[c], hi = p[c];
        for (size_t i = 1; i < n; i++)
            lo = fmin(lo, p[3 * i + c]), hi = fmax(hi, p[3 * i + c]);
        e = fmax(e, hi - lo);
    }
    return e;
}

static rf_status hull_points(hull *h, size_t n, rf_error *err)
{
    int t[4] = {0, 0, 0, 0};
    if (initial_points(h, n, t))
        return rf_fail(err, RF_EINVAL, "block hull: the %zu points are (nearly) coplanar: no solid", n);
    if (start_tetrahedron(h, t))
        return rf_fail(err, RF_ENOMEM, "block hull: out of memory");
    for (size_t i = 0; i < n; i++) {
        if ((int)i == t[0] || (int)i == t[1] || (int)i == t[2] || (int)i == t[3])
            continue;
        size_t *seen = malloc((h->n + 1) * sizeof *seen);
        int rc = seen ? add_point(h, (int)i, seen) : -1;
        free(seen);
        if (rc)
            return rf_fail(err, RF_ENOMEM, "block hull: out of memory");
    }
    return RF_OK;
}

/* A hull vertex is extreme (a corner of the solid) when the normals of its
 * faces span space; on a face or an edge of the solid (points added before
 * the corners that later hid them) they lie in a plane: the largest
 * |det(n_i, n_j, n_k)| over its faces is below FLAT_DET. */
#define FLAT_DET 1e-9

static int extreme(const hull *h, const size_t *fl, size_t m)
{
    if (m > 64)
        m = 64;
    for (size_t i = 0; i < m; i++)
        for (size_t j = i + 1; j < m; j++) {
            double c[3];
            bk_cross(h->f[fl[i]].n, h->f[fl[j]].n, c);
            for (size_t k = j + 1; k < m; k++)
                if (fabs(bk_dot(c, h->f[fl[k]].n)) > FLAT_DET)
                    return 1;
        }
    return 0;
}

/* The indices of the extreme vertices of h (ids, *m of them): the faces of
 * each vertex listed once (counting sort), O(F). */
static void extreme_vertices(const hull *h, size_t n, int *ids, size_t *m)
{
    size_t *start = calloc(n + 1, sizeof *start), *fl = malloc(3 * h->n * sizeof *fl);
    *m = 0;
    if (!start || !fl) {
        free(start), free(fl);
        return;
    }
    for (size_t k = 0; k < h->n; k++)
        for (int e = 0; e < 3; e++)
            start[h->f[k].v[e] + 1]++;
    for (size_t i = 0; i < n; i++)
        start[i + 1] += start[i];
    for (size_t k = 0; k < h->n; k++)
        for (int e = 0; e < 3; e++)
            fl[start[h->f[k].v[e]]++] = k;
    for (size_t i = n; i > 0; i--) /* start[i] is now the end of vertex i's list: shift back */
        start[i] = start[i - 1];
    start[0] = 0;
    for (size_t i = 0; i < n; i++)
        if (start[i + 1] > start[i] && extreme(h, fl + start[i], start[i + 1] - start[i]))
            ids[(*m)++] = (int)i;
    free(start), free(fl);
}

static rf_status copy_faces(const hull *h, const int *ids, int **faces, size_t *n_faces, rf_error *err)
{
    *faces = malloc(3 * h->n * sizeof **faces);
    if (!*faces)
        return rf_fail(err, RF_ENOMEM, "block hull: out of memory");
    for (size_t k = 0; k < h->n; k++)
        for (int e = 0; e < 3; e++)
            (*faces)[3 * k + e] = ids[h->f[k].v[e]];
    *n_faces = h->n;
    return RF_OK;
}

/* The hull, then the hull of its extreme vertices only. */
static rf_status two_pass(size_t n, const double *points, double eps, int **faces, size_t *n_faces, rf_error *err)
{
    hull h = {.p = points, .eps = eps}, h2 = {.eps = eps};
    int *ids = malloc(n * sizeof *ids);
    double *q = malloc(3 * n * sizeof *q);
    size_t m = 0;
    rf_status rc = ids && q ? hull_points(&h, n, err) : rf_fail(err, RF_ENOMEM, "block hull: out of memory");
    if (rc == RF_OK)
        extreme_vertices(&h, n, ids, &m);
    for (size_t i = 0; rc == RF_OK && i < m; i++)
        memcpy(q + 3 * i, points + 3 * (size_t)ids[i], 3 * sizeof *q);
    h2.p = q;
    if (rc == RF_OK)
        rc = hull_points(&h2, m, err);
    if (rc == RF_OK)
        rc = copy_faces(&h2, ids, faces, n_faces, err);
    free(h.f), free(h2.f), free(ids), free(q);
    return rc;
}

rf_status rf_block_hull(size_t n, const double *points, int **faces, size_t *n_faces, rf_error *err)
{
    *faces = NULL, *n_faces = 0;
    if (n < 4 || n > (size_t)1 << 24)
        return rf_fail(err, RF_EINVAL, "block hull: %zu points; 4 to 16777216 are needed", n);
    for (size_t i = 0; i < 3 * n; i++)
        if (!isfinite(points[i]))
            return rf_fail(err, RF_EINVAL, "block hull: point %zu has a coordinate %g", i / 3, points[i]);
    return two_pass(n, points, HULL_REL_EPS * extent(n, points), faces, n_faces, err);
}
