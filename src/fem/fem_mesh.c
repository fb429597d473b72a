/* fem_mesh.c - structured, graded quad meshes of the boulder and the slope.
 *
 * Both bodies are generated from one reference pattern: a quarter disc in
 * (x, y), x along the contact surface and y into the body, with the first
 * contact point at the origin (so a node sits exactly there).
 *   - core: n x n uniform squares of size h (the fine zone, ~2.5 a wide);
 *   - rings: the core square offset outward (grid lines continued, fanning at
 *     the corner), blending into circles of growing radius; the radial size
 *     grows geometrically (ratio `grading`) up to h_far, and the number of
 *     angular divisions is cut by three with a 4-quad 3:1 transition layer
 *     whenever the coarser divisions still fit the desired size.
 * Sizes are measured in physical space through the body's map.
 * Slope: the pattern mirrored (z = -y) out to the hemisphere radius L.
 * Boulder (sphere of radius c, scaled vertically by d/c for a spheroid): the
 * quarter plane is mapped onto the half disc by the Moebius map
 * w = 2ic z / (z + 2ic) (conformal: the surface line goes onto the sphere,
 * the axis onto the axis, infinity onto the north pole), preceded by a mild
 * stretch that undoes its (1 - y/c) compression near the contact.  The
 * pattern stops at reference radius 8c; the remaining cap around the north
 * pole is a second, small O-grid whose outer ring is the first one's
 * (reflection z = P^2 / conj(z')).  No degenerate elements anywhere. */
#include "fem_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double *x, *y;
    unsigned char *fl;
    long n, cap;
    int *conn;
    long ne, ecap;
} refmesh;

static int ref_node(refmesh *m, double x, double y, unsigned char fl)
{
    if (m->n == m->cap) {
        long cap = m->cap ? 2 * m->cap : 1024;
        double *x2 = realloc(m->x, (size_t)cap * sizeof *x2);
        if (!x2)
            return -1;
        m->x = x2;
        double *y2 = realloc(m->y, (size_t)cap * sizeof *y2);
        if (!y2)
            return -1;
        m->y = y2;
        unsigned char *f2 = realloc(m->fl, (size_t)cap);
        if (!f2)
            return -1;
        m->fl = f2;
        m->cap = cap;
    }
    m->x[m->n] = x;
    m->y[m->n] = y;
    m->fl[m->n] = fl;
    return (int)m->n++;
}

static int ref_elem(refmesh *m, int a, int b, int c, int d)
{
    if (a < 0 || b < 0 || c < 0 || d < 0)
        return -1;
    if (m->ne == m->ecap) {
        long cap = m->ecap ? 2 * m->ecap : 1024;
        int *c2 = realloc(m->conn, (size_t)cap * 4 * sizeof *c2);
        if (!c2)
            return -1;
        m->conn = c2;
        m->ecap = cap;
    }
    int *e = m->conn + 4 * m->ne++;
    e[0] = a, e[1] = b, e[2] = c, e[3] = d;
    return 0;
}

static void ref_free(refmesh *m)
{
    free(m->x), free(m->y), free(m->fl), free(m->conn);
    memset(m, 0, sizeof *m);
}

/* Map from the reference plane to physical (r, z). */
typedef void (*map_fn)(const void *ctx, double x, double y, double *r, double *z);

typedef struct {
    double s;          /* core size n*h (reference) */
    double blend_end;  /* square -> circle blending complete at this reference radius */
    double P;          /* reference outer radius */
    int n;             /* core divisions */
    double h;          /* physical core element size */
    double grading, h_far;
    int transitions;   /* allow 3:1 transition layers */
    int boulder;       /* sizing rules of the boulder main block */
    int corner_linear; /* blending rule of the cap (see ring_pos) */
    map_fn map;
    const void *mctx;
    const int *outer_ids; /* if set: ids of the outer ring nodes (already created) */
} pattern;

static double blend_weight(const pattern *p, double rho)
{
    if (p->blend_end <= p->s)
        return 1;
    double t = (rho - p->s) / (p->blend_end - p->s);
    if (t <= 0)
        return 0;
    if (t >= 1)
        return 1;
    return t * t * (3 - 2 * t);
}

/* Reference position on ring rho at angular fraction t in [0, 1].  Near the
 * core the ring is the core square offset outward: each core boundary node
 * moves along a straight line, normal to its side, the fan to the diagonal
 * being confined to the last few nodes before the corner (u^32), so that the
 * first layers continue the core's grid lines; a smoother fan (u^3) sheared
 * the boulder's corner elements and cut the stable step by 22 %.  With
 * weight w the ring blends into the circle of radius rho with uniform angles.  The cap (corner_linear) blends
 * over a short distance and uses the superellipse rule instead. */
static void ring_pos(const pattern *p, double rho, double t, double *x, double *y)
{
    if (t <= 0) {
        *x = rho, *y = 0;
        return;
    }
    if (t >= 1) {
        *x = 0, *y = rho;
        return;
    }
    double w = blend_weight(p, rho);
    double th = t * RF_PI / 2, cx = rho * cos(th), cy = rho * sin(th);
    if (!p->corner_linear) {
        double u = t <= 0.5 ? 2 * t : 2 - 2 * t, phi = pow(u, 32), a = p->s * u + (rho - p->s) * phi;
        double ox = t <= 0.5 ? rho : a, oy = t <= 0.5 ? a : rho;
        *x = (1 - w) * ox + w * cx;
        *y = (1 - w) * oy + w * cy;
        return;
    }
    double bx, by;
    if (t <= 0.5)
        bx = 1, by = 2 * t;
    else
        bx = 2 - 2 * t, by = 1;
    double ex = (1 - w) * bx + w * cos(th), ey = (1 - w) * by + w * sin(th);
    double m = fmax(ex, ey), norm;
    /* superellipse exponent 1/q: the diagonal point moves linearly from the
       square's corner to the circle */
    double q = 0.5;
    if (rho < p->blend_end) {
        double f = M_SQRT2 * p->s + (p->blend_end - M_SQRT2 * p->s) * (rho - p->s) / (p->blend_end - p->s);
        q = 0.5 - log2(f / rho);
        q = q < 0 ? 0 : q > 0.5 ? 0.5 : q;
    }
    if (q < 1e-9)
        norm = m;
    else {
        double pe = 1 / q;
        norm = m * pow(pow(ex / m, pe) + pow(ey / m, pe), 1 / pe);
    }
    *x = rho * ex / norm;
    *y = rho * ey / norm;
}

static void phys_ring(const pattern *p, double rho, double t, double *r, double *z)
{
    double x, y;
    ring_pos(p, rho, t, &x, &y);
    p->map(p->mctx, x, y, r, z);
}

/* Physical length of ring rho. */
static double ring_length(const pattern *p, double rho)
{
    double len = 0, r0, z0;
    phys_ring(p, rho, 0, &r0, &z0);
    for (int k = 1; k <= 32; k++) {
        double r1, z1;
        phys_ring(p, rho, k / 32.0, &r1, &z1);
        len += hypot(r1 - r0, z1 - z0);
        r0 = r1, z0 = z1;
    }
    return len;
}

/* Mean physical length per unit reference radius on ring rho. */
static double radial_scale(const pattern *p, double rho)
{
    double eps = 1e-4 * rho + 1e-9, sum = 0;
    for (int k = 0; k <= 4; k++) {
        double t = k / 4.0, r0, z0, r1, z1;
        phys_ring(p, rho, t, &r0, &z0);
        phys_ring(p, rho + eps, t, &r1, &z1);
        sum += hypot(r1 - r0, z1 - z0) / eps;
    }
    return sum / 5;
}

static int add_node(refmesh *m, const pattern *p, double x, double y, unsigned char fl)
{
    double r, z;
    p->map(p->mctx, x, y, &r, &z);
    if (fl & FEM_AXIS)
        r = 0;
    return ref_node(m, r, z, fl);
}

/* The core of a pattern: n x n squares of size s / n; its outer boundary
 * (2n + 1 nodes, from the surface to the axis) into ring.  -1: out of memory. */
static int pattern_core(const pattern *p, refmesh *m, int *ring)
{
    const int n = p->n;
    const double hr = p->s / n;
    int *grid = malloc((size_t)(n + 1) * (n + 1) * sizeof *grid);
    if (!grid)
        return -1;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            unsigned char fl = (i == 0 ? FEM_AXIS : 0) | (j == 0 ? FEM_SURFACE : 0);
            grid[j * (n + 1) + i] = add_node(m, p, i * hr, j * hr, fl);
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int a = grid[j * (n + 1) + i];
            if (ref_elem(m, a, grid[j * (n + 1) + i + 1], grid[(j + 1) * (n + 1) + i + 1],
                         grid[(j + 1) * (n + 1) + i]) < 0) {
                free(grid);
                return -1;
            }
        }
    for (int j = 0; j <= 2 * n; j++)
        ring[j] = j <= n ? grid[j * (n + 1) + n] : grid[n * (n + 1) + (2 * n - j)];
    free(grid);
    return 0;
}

/* A 3:1 transition layer: from ring *rho of N divisions (prev) out by two
 * angular spacings as (physical; sc the radial scale) to a ring of N / 3
 * (next), four quads per three.  -1: out of memory. */
static int pattern_transition(const pattern *p, refmesh *m, const int *prev, int *next, int N, double as, double sc,
                              double *rho)
{
    int Nc = N / 3;
    double dr = 2 * as / sc, rm = *rho + 0.5 * dr, ro = *rho + dr;
    for (int g = 0; g <= Nc; g++) {
        double x, y;
        ring_pos(p, ro, (double)g / Nc, &x, &y);
        next[g] = add_node(m, p, x, y, (g == 0 ? FEM_SURFACE : 0) | (g == Nc ? FEM_AXIS : 0));
    }
    for (int g = 0; g < Nc; g++) {
        double x, y;
        ring_pos(p, rm, (3.0 * g + 1) / N, &x, &y);
        int pn = add_node(m, p, x, y, 0);
        ring_pos(p, rm, (3.0 * g + 2) / N, &x, &y);
        int qn = add_node(m, p, x, y, 0);
        const int *f = prev + 3 * g;
        if (ref_elem(m, f[0], f[1], pn, next[g]) < 0 || ref_elem(m, f[1], f[2], qn, pn) < 0 ||
            ref_elem(m, f[2], f[3], next[g + 1], qn) < 0 || ref_elem(m, pn, qn, next[g + 1], next[g]) < 0)
            return -1;
    }
    *rho = ro;
    return 0;
}

/* A plain ring of N quads from ring *rho (prev) out by the desired size
 * *hdes (at most 3 as), which then grows by the grading; the last ring
 * (*last = 1) reaches P, onto the given outer nodes if any.  -1: out of memory. */
static int pattern_ring(const pattern *p, refmesh *m, const int *prev, int *next, int N, double as, double sc,
                        double *rho, double *hdes, int *last)
{
    double dphys = fmin(*hdes, 3 * as);
    double dr = dphys / sc;
    if (*rho + 1.5 * dr >= p->P)
        dr = p->P - *rho, *last = 1;
    double ro = *rho + dr;
    for (int j = 0; j <= N; j++) {
        if (*last && p->outer_ids) {
            next[j] = p->outer_ids[j];
            continue;
        }
        double x, y;
        ring_pos(p, ro, (double)j / N, &x, &y);
        unsigned char fl = (j == 0 ? FEM_SURFACE : 0) | (j == N ? FEM_AXIS : 0);
        next[j] = add_node(m, p, x, y, fl);
    }
    for (int j = 0; j < N; j++)
        if (ref_elem(m, prev[j], prev[j + 1], next[j + 1], next[j]) < 0)
            return -1;
    *rho = ro;
    *hdes = fmin(p->h_far, *hdes * p->grading);
    return 0;
}

/* Build one graded quarter-disc pattern into m (physical coordinates): the
 * core, then rings out to P, a 3:1 transition wherever the coarser divisions
 * still fit the desired size; the outer ring's N + 1 node ids into *outer. */
static rf_status build_pattern(const pattern *p, refmesh *m, long max_elements, int **outer, int *nouter,
                               rf_error *err)
{
    const int n = p->n;
    if (n < 1 || n > 100000)
        return rf_fail(err, RF_EINVAL, "fem mesh: core divisions %d out of range", n);
    int N = 2 * n;
    size_t nring = (size_t)(unsigned)N + 1;
    int *prev = malloc(nring * sizeof *prev), *next = malloc(nring * sizeof *next);
    if (!prev || !next || pattern_core(p, m, prev) < 0) {
        free(prev), free(next);
        return rf_fail(err, RF_ENOMEM, "fem mesh: out of memory");
    }
    double rho = p->s, hdes = p->h;
    int last = 0;
    while (!last) {
        if (m->ne > max_elements) {
            free(prev), free(next);
            return rf_fail(err, RF_ECAP, "fem mesh: more than %ld elements; lower the refinement", max_elements);
        }
        double sc = radial_scale(p, rho);
        double as = ring_length(p, rho) / N; /* physical angular spacing */
        int can3 = p->transitions && N % 3 == 0 && N / 3 >= 2 && blend_weight(p, rho) >= 1 &&
                   3 * as <= 1.25 * hdes && rho + (4 * as + 2 * hdes) / sc < p->P;
        if (can3 && !p->boulder)
            can3 = ring_length(p, p->P) / (N / 3) <= 1.3 * p->h_far;
        int rc = can3 ? pattern_transition(p, m, prev, next, N, as, sc, &rho)
                      : pattern_ring(p, m, prev, next, N, as, sc, &rho, &hdes, &last);
        if (rc < 0) {
            free(prev), free(next);
            return rf_fail(err, RF_ENOMEM, "fem mesh: out of memory");
        }
        if (can3)
            N /= 3;
        int *tmp = prev;
        prev = next, next = tmp;
    }
    free(next);
    *outer = prev;
    *nouter = N;
    return RF_OK;
}

/* --- maps --- */

static void slope_map(const void *ctx, double x, double y, double *r, double *z)
{
    (void)ctx;
    *r = x, *z = -y;
}

typedef struct {
    double c, d, P;
} boulder_ctx;

/* Near-isometric correction before the conformal map: the Moebius map
 * compresses by ~(1 - y/c) at depth y; stretch by about the inverse near the
 * contact (saturating far away so that the map stays a bijection of the
 * quarter plane with bounded anisotropy). */
static void boulder_map(const void *vctx, double x, double y, double *r, double *z)
{
    const boulder_ctx *b = vctx;
    const double c = b->c, ys = 1.2 * c;
    double q2 = (x * x + y * y) / (ys * ys), damp = 1 / (1 + q2 * q2);
    double Y = y + (y * y / (2 * c) + y * y * y / (4 * c * c)) * damp;
    double al = (1 + Y / (2 * c)) * (1 + Y / (2 * c));
    double X = x * (1 + (al - 1) * damp);
    /* Moebius map of the quarter plane onto the half disc of radius c resting on the origin */
    double D = X * X + (Y + 2 * c) * (Y + 2 * c);
    double rr = 4 * c * c * X / D, zz = 2 * c * (X * X + Y * Y + 2 * c * Y) / D;
    *r = rr;
    *z = zz * b->d / c;
}

/* The cap around the north pole: reference z' inside the quarter disc of
 * radius P, reflected to z = P^2 / conj(z') outside it, then boulder_map. */
static void cap_map(const void *vctx, double x, double y, double *r, double *z)
{
    const boulder_ctx *b = vctx;
    double q = x * x + y * y;
    if (q == 0) {
        *r = 0, *z = 2 * b->d;
        return;
    }
    double P2 = b->P * b->P;
    boulder_map(vctx, P2 * x / q, P2 * y / q, r, z);
}

void fem_mesh_free(fem_mesh *mesh)
{
    free(mesh->r), free(mesh->z), free(mesh->flags), free(mesh->conn), free(mesh->ebody);
    free(mesh->bsurf), free(mesh->ssurf);
    memset(mesh, 0, sizeof *mesh);
}

typedef struct {
    const double *r;
    int id;
} surf_item;

static int cmp_surf(const void *a, const void *b)
{
    const surf_item *x = a, *y = b;
    double ra = x->r[x->id], rb = y->r[y->id];
    return ra < rb ? -1 : ra > rb ? 1 : x->id - y->id;
}

/* The reference patterns: the boulder's main block and its cap into rb, the
 * slope into rs (its outer ring flagged FEM_OUTER). */
static rf_status mesh_patterns(const fem_body_spec *boulder, const fem_body_spec *slope, long max_elements,
                               refmesh *rb, refmesh *rs, rf_error *err)
{
    int *outer = NULL, nouter = 0, *capouter = NULL, ncap = 0;
    boulder_ctx bc = {boulder->extent, boulder->height, 8 * boulder->extent};
    pattern pb = {.s = boulder->n * boulder->h, .n = boulder->n, .h = boulder->h, .grading = boulder->grading,
                  .h_far = boulder->h_far, .transitions = 1, .boulder = 1, .map = boulder_map, .mctx = &bc};
    pb.P = bc.P;
    pb.blend_end = 3 * pb.s;
    rf_status st = build_pattern(&pb, rb, max_elements, &outer, &nouter, err);
    if (st == RF_OK) {
        /* cap: an O-grid whose outer ring is the main block's outer ring */
        int nc = nouter / 2;
        pattern pc = {.s = 0.45 * bc.P, .n = nc, .grading = 1, .transitions = 0, .boulder = 1, .corner_linear = 1,
                      .map = cap_map, .mctx = &bc, .outer_ids = outer, .P = bc.P};
        pc.blend_end = bc.P;
        pc.h = ring_length(&pc, bc.P) / nouter;
        pc.h_far = pc.h;
        st = build_pattern(&pc, rb, max_elements, &capouter, &ncap, err);
        if (st == RF_OK && ncap != nouter)
            st = rf_fail(err, RF_EINTERNAL, "fem mesh: cap ring mismatch (%d vs %d)", ncap, nouter);
    }
    free(outer), free(capouter);
    outer = NULL;
    if (st == RF_OK) {
        pattern ps = {.s = slope->n * slope->h, .n = slope->n, .h = slope->h, .grading = slope->grading,
                      .h_far = slope->h_far, .transitions = 1, .boulder = 0, .map = slope_map, .P = slope->extent};
        ps.blend_end = 3 * ps.s;
        st = build_pattern(&ps, rs, max_elements - rb->ne, &outer, &nouter, err);
        if (st == RF_OK)
            for (int j = 0; j <= nouter; j++)
                rs->fl[outer[j]] |= FEM_OUTER;
        free(outer);
    }
    return st;
}

/* The mesh's arrays for nn nodes and ne elements (nonzero: out of memory). */
static int mesh_alloc(fem_mesh *mesh, long nn, long ne)
{
    mesh->n_nodes = nn, mesh->n_elems = ne;
    mesh->r = malloc((size_t)nn * sizeof *mesh->r);
    mesh->z = malloc((size_t)nn * sizeof *mesh->z);
    mesh->flags = malloc((size_t)nn);
    mesh->conn = malloc((size_t)ne * 4 * sizeof *mesh->conn);
    mesh->ebody = malloc((size_t)ne);
    mesh->bsurf = malloc((size_t)nn * sizeof *mesh->bsurf);
    mesh->ssurf = malloc((size_t)nn * sizeof *mesh->ssurf);
    return !mesh->r || !mesh->z || !mesh->flags || !mesh->conn || !mesh->ebody || !mesh->bsurf || !mesh->ssurf;
}

/* The boulder's nodes and elements, then the slope's, each element
 * counter-clockwise in (r, z). */
static void mesh_fill(fem_mesh *mesh, const refmesh *rb, const refmesh *rs)
{
    mesh->boulder_nodes = rb->n, mesh->boulder_elems = rb->ne;
    for (long i = 0; i < rb->n; i++) {
        mesh->r[i] = rb->x[i];
        mesh->z[i] = rb->y[i];
        mesh->flags[i] = rb->fl[i];
    }
    for (long i = 0; i < rs->n; i++) {
        mesh->r[rb->n + i] = rs->x[i];
        mesh->z[rb->n + i] = rs->y[i];
        mesh->flags[rb->n + i] = rs->fl[i];
    }
    for (long e = 0; e < mesh->n_elems; e++) {
        int off = e < rb->ne ? 0 : (int)rb->n;
        const int *src = e < rb->ne ? rb->conn + 4 * e : rs->conn + 4 * (e - rb->ne);
        int *dst = mesh->conn + 4 * e;
        for (int k = 0; k < 4; k++)
            dst[k] = src[k] + off;
        mesh->ebody[e] = e < rb->ne ? FEM_BOULDER : FEM_SLOPE;
        /* orient counter-clockwise in (r, z) (mirror and reflection flip it) */
        double a2 = 0;
        for (int k = 0; k < 4; k++) {
            int p = dst[k], q = dst[(k + 1) % 4];
            a2 += mesh->r[p] * mesh->z[q] - mesh->r[q] * mesh->z[p];
        }
        if (a2 < 0) {
            int t = dst[1];
            dst[1] = dst[3], dst[3] = t;
        }
    }
}

/* The surface nodes of nodes [i0, i1) below height zmax, sorted by r, into
 * list (items: scratch of i1 - i0); returns their number. */
static long mesh_surface(const fem_mesh *mesh, long i0, long i1, double zmax, surf_item *items, int *list)
{
    long k = 0;
    for (long i = i0; i < i1; i++)
        if ((mesh->flags[i] & FEM_SURFACE) && mesh->z[i] < zmax)
            items[k++] = (surf_item){mesh->r, (int)i};
    qsort(items, (size_t)k, sizeof *items, cmp_surf);
    for (long i = 0; i < k; i++)
        list[i] = items[i].id;
    return k;
}

rf_status fem_mesh_build(const fem_body_spec *boulder, const fem_body_spec *slope, fem_mesh *mesh,
                         long max_elements, rf_error *err)
{
    memset(mesh, 0, sizeof *mesh);
    refmesh rb = {0}, rs = {0};
    rf_status st = mesh_patterns(boulder, slope, max_elements, &rb, &rs, err);
    if (st != RF_OK) {
        ref_free(&rb), ref_free(&rs);
        return st;
    }
    const long nn = rb.n + rs.n;
    surf_item *items = malloc((size_t)nn * sizeof *items);
    if (mesh_alloc(mesh, nn, rb.ne + rs.ne) || !items) {
        free(items);
        ref_free(&rb), ref_free(&rs);
        fem_mesh_free(mesh);
        return rf_fail(err, RF_ENOMEM, "fem mesh: out of memory");
    }
    mesh_fill(mesh, &rb, &rs);
    /* surface lists sorted by r (boulder: lower half only, z < d) */
    mesh->n_bsurf = mesh_surface(mesh, 0, rb.n, boulder->height, items, mesh->bsurf);
    mesh->n_ssurf = mesh_surface(mesh, rb.n, nn, INFINITY, items, mesh->ssurf);
    free(items);
    ref_free(&rb), ref_free(&rs);
    return RF_OK;
}
