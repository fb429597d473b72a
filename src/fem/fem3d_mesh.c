/* fem3d_mesh.c - structured hexahedral meshes of the slope and the boulder.
 *
 * Both bodies start from one block structure of the lower half-space z <= 0
 * around the first-contact point (an "O-grid"): a fine box of uniform cubes
 * (size h from the Hertz contact radius, elongated down-slope by the distance
 * the patch travels) surrounded by layers whose nodes lie on the rays from
 * the contact point through the box-surface nodes, spaced geometrically from
 * the box to a hemisphere of radius R, so element size grows in proportion to
 * the distance from the contact.  The flat face z = 0 stays flat, the plane
 * y = 0 stays a plane (half model).
 *
 * - Slope: the O-grid itself with R = domain radius.
 * - Boulder: the inversion x -> P + k^2 (x - P)/|x - P|^2 with P = (0,0,2r),
 *   k = 2r maps the half-space z <= 0 conformally onto the ball of radius r
 *   resting on the origin (scale 1 and orientation of the tangent plane kept
 *   at the contact point): the O-grid out to R = boulder_inner * r becomes
 *   the fine contact side of the ball, and a second, scaled copy of the same
 *   O-grid, mapped by the composition of an inversion about the contact point
 *   and the same inversion, fills the cap near the top pole and shares its
 *   outer layer node for node.  A spheroid is the affine image of the ball.
 * Conformal maps keep element shapes; sizes grow from h at the contact to
 * about r/10 near the centre.  Element orientation is fixed afterwards by
 * the sign of the Jacobian. */
#include "fem3d_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    int NX, NY, NZ;   /* core cells */
    int full;
    f3_box box;
    double R;
    int K;            /* layers */
    long ncore, nsurf, nquad;
    long *surf;       /* core node id of surface node s */
    long *quad;       /* 4 surface indices per shell quad */
    long n, ne;
} ogrid;

static long core_id(const ogrid *g, int i, int j, int k)
{
    return ((long)i * (g->NY + 1) + j) * (g->NZ + 1) + k;
}

static long layer_id(const ogrid *g, long s, int l)
{
    return l == 0 ? g->surf[s] : g->ncore + (long)(l - 1) * g->nsurf + s;
}

static int ogrid_layers(const f3_box *b, double R, double aspect)
{
    int nmin = b->nxm < b->ny ? b->nxm : b->ny;
    if (b->nz < nmin)
        nmin = b->nz;
    double c = nmin * b->h;
    int K = (int)ceil(log(R / c) / log(1 + aspect / nmin));
    return K < 1 ? 1 : K;
}

/* Topology and counts (no coordinates). */
static rf_status ogrid_init(ogrid *g, const f3_box *b, int full, double R, int K, rf_error *err)
{
    memset(g, 0, sizeof *g);
    g->box = *b, g->full = full, g->R = R, g->K = K;
    g->NX = b->nxm + b->nxp, g->NY = full ? 2 * b->ny : b->ny, g->NZ = b->nz;
    g->ncore = (long)(g->NX + 1) * (g->NY + 1) * (g->NZ + 1);
    long *sidx = malloc((size_t)g->ncore * sizeof *sidx);
    if (!sidx)
        return rf_fail(err, RF_ENOMEM, "fem3d mesh: out of memory");
    long ns = 0;
    for (int i = 0; i <= g->NX; i++)
        for (int j = 0; j <= g->NY; j++)
            for (int k = 0; k <= g->NZ; k++) {
                int on = i == 0 || i == g->NX || j == g->NY || (full && j == 0) || k == 0;
                sidx[core_id(g, i, j, k)] = on ? ns++ : -1;
            }
    g->nsurf = ns;
    long nq = 2L * g->NY * g->NZ + (long)g->NX * g->NZ * (full ? 2 : 1) + (long)g->NX * g->NY;
    g->surf = malloc((size_t)ns * sizeof *g->surf);
    g->quad = malloc((size_t)nq * 4 * sizeof *g->quad);
    if (!g->surf || !g->quad) {
        free(sidx);
        return rf_fail(err, RF_ENOMEM, "fem3d mesh: out of memory");
    }
    for (long c = 0; c < g->ncore; c++)
        if (sidx[c] >= 0)
            g->surf[sidx[c]] = c;
    long q = 0;
#define QUAD(a, b2, c2, d)                                                                                             \
    do {                                                                                                               \
        g->quad[4 * q] = sidx[a], g->quad[4 * q + 1] = sidx[b2], g->quad[4 * q + 2] = sidx[c2],                        \
        g->quad[4 * q + 3] = sidx[d];                                                                                  \
        q++;                                                                                                           \
    } while (0)
    for (int side = 0; side < 2; side++) {
        int i = side ? g->NX : 0;
        for (int j = 0; j < g->NY; j++)
            for (int k = 0; k < g->NZ; k++)
                QUAD(core_id(g, i, j, k), core_id(g, i, j + 1, k), core_id(g, i, j + 1, k + 1),
                     core_id(g, i, j, k + 1));
    }
    for (int side = full ? 0 : 1; side < 2; side++) {
        int j = side ? g->NY : 0;
        for (int i = 0; i < g->NX; i++)
            for (int k = 0; k < g->NZ; k++)
                QUAD(core_id(g, i, j, k), core_id(g, i + 1, j, k), core_id(g, i + 1, j, k + 1),
                     core_id(g, i, j, k + 1));
    }
    for (int i = 0; i < g->NX; i++)
        for (int j = 0; j < g->NY; j++)
            QUAD(core_id(g, i, j, 0), core_id(g, i + 1, j, 0), core_id(g, i + 1, j + 1, 0), core_id(g, i, j + 1, 0));
#undef QUAD
    g->nquad = q;
    free(sidx);
    g->n = g->ncore + (long)K * g->nsurf;
    g->ne = (long)g->NX * g->NY * g->NZ + (long)K * g->nquad;
    return RF_OK;
}

static void ogrid_free(ogrid *g)
{
    free(g->surf), free(g->quad);
    g->surf = g->quad = NULL;
}

/* Half-space coordinates of local node id (core or layer). */
static void ogrid_point(const ogrid *g, long id, double p[3])
{
    const double h = g->box.h;
    if (id < g->ncore) {
        int k = (int)(id % (g->NZ + 1));
        long r = id / (g->NZ + 1);
        int j = (int)(r % (g->NY + 1)), i = (int)(r / (g->NY + 1));
        p[0] = (i - g->box.nxm) * h;
        p[1] = (j - (g->full ? g->box.ny : 0)) * h;
        p[2] = (k - g->NZ) * h;
        return;
    }
    long s = (id - g->ncore) % g->nsurf;
    int l = (int)((id - g->ncore) / g->nsurf) + 1;
    double b[3];
    ogrid_point(g, g->surf[s], b);
    double rb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double t = (double)l / g->K;
    double r = l == g->K ? g->R : pow(rb, 1 - t) * pow(g->R, t);
    for (int a = 0; a < 3; a++)
        p[a] = b[a] / rb * r;
    if (b[2] == 0)
        p[2] = 0; /* keep the flat face exactly flat */
    if (b[1] == 0)
        p[1] = 0;
}

/* Local flags: top face (z = 0), symmetry plane (y = 0, half model), outer layer. */
static unsigned char ogrid_flags(const ogrid *g, long id)
{
    long c = id < g->ncore ? id : g->surf[(id - g->ncore) % g->nsurf];
    int k = (int)(c % (g->NZ + 1));
    int j = (int)((c / (g->NZ + 1)) % (g->NY + 1));
    unsigned char f = 0;
    if (k == g->NZ)
        f |= F3_SURFACE;
    if (!g->full && j == 0)
        f |= F3_SYM;
    if (id >= g->ncore && (id - g->ncore) / g->nsurf == g->K - 1)
        f |= F3_OUTER;
    return f;
}

/* Element e's 8 local node ids. */
static void ogrid_elem(const ogrid *g, long e, long c[8])
{
    long ncoreel = (long)g->NX * g->NY * g->NZ;
    if (e < ncoreel) {
        int k = (int)(e % g->NZ);
        long r = e / g->NZ;
        int j = (int)(r % g->NY), i = (int)(r / g->NY);
        c[0] = core_id(g, i, j, k), c[1] = core_id(g, i + 1, j, k);
        c[2] = core_id(g, i + 1, j + 1, k), c[3] = core_id(g, i, j + 1, k);
        c[4] = core_id(g, i, j, k + 1), c[5] = core_id(g, i + 1, j, k + 1);
        c[6] = core_id(g, i + 1, j + 1, k + 1), c[7] = core_id(g, i, j + 1, k + 1);
        return;
    }
    e -= ncoreel;
    long q = e % g->nquad;
    int l = (int)(e / g->nquad);
    for (int a = 0; a < 4; a++) {
        c[a] = layer_id(g, g->quad[4 * q + a], l);
        c[4 + a] = layer_id(g, g->quad[4 * q + a], l + 1);
    }
}

void f3_mesh_free(f3_mesh *m)
{
    free(m->x), free(m->flags), free(m->conn), free(m->top_b), free(m->top_s), free(m->outer_quads);
    memset(m, 0, sizeof *m);
}

/* The three O-grids of a mesh: the boulder's part 1, its cap copy g2 (same box
 * counts, the box's farthest corner at 0.6 of its hemisphere's radius 1) and
 * the slope's. */
static rf_status mesh_grids(const f3_mesh_spec *sp, ogrid *g1, ogrid *g2, ogrid *gs, rf_error *err)
{
    const double Rb = sp->boulder_inner * sp->radius, rho_h = 1.0;
    int K1 = ogrid_layers(&sp->boulder, Rb, sp->layer_aspect);
    f3_box b2 = sp->boulder;
    int nxx = b2.nxm > b2.nxp ? b2.nxm : b2.nxp;
    b2.h = 0.6 * rho_h / sqrt((double)nxx * nxx + (double)b2.ny * b2.ny + (double)b2.nz * b2.nz);
    int K2 = ogrid_layers(&b2, rho_h, sp->layer_aspect);
    int Ks = ogrid_layers(&sp->slope, sp->domain, sp->layer_aspect);
    rf_status st;
    if ((st = ogrid_init(g1, &sp->boulder, sp->full, Rb, K1, err)) != RF_OK ||
        (st = ogrid_init(g2, &b2, sp->full, rho_h, K2, err)) != RF_OK ||
        (st = ogrid_init(gs, &sp->slope, sp->full, sp->domain, Ks, err)) != RF_OK)
        return st;
    return RF_OK;
}

/* The mesh's counts and arrays (nb: the boulder's node count). */
static rf_status mesh_alloc(const f3_mesh_spec *sp, const ogrid *g1, const ogrid *g2, const ogrid *gs,
                            long max_elements, f3_mesh *m, rf_error *err)
{
    long nb = g1->n + g2->n - g2->nsurf, ns = gs->n;
    long neb = g1->ne + g2->ne, nes = gs->ne, noq = gs->nquad;
    if (sp->extruded) /* a layered slope: horizontal node planes (fem3d_layer.c) */
        f3_slab_counts(sp, &ns, &nes, &noq);
    if (neb + nes > max_elements)
        return rf_fail(err, RF_ECAP, "fem3d mesh: %ld elements exceed max_elements = %ld; lower the refinement",
                       neb + nes, max_elements);
    m->n_nodes = nb + ns, m->n_elems = neb + nes;
    m->boulder_nodes = nb, m->boulder_elems = neb;
    m->x = malloc((size_t)m->n_nodes * 3 * sizeof *m->x);
    m->flags = calloc((size_t)m->n_nodes, 1);
    m->conn = malloc((size_t)m->n_elems * 8 * sizeof *m->conn);
    m->nxt_b = g1->NX + 1, m->nyt_b = g1->NY + 1, m->nxt_s = gs->NX + 1, m->nyt_s = gs->NY + 1;
    m->top_b = malloc((size_t)m->nxt_b * m->nyt_b * sizeof *m->top_b);
    if (sp->extruded)
        m->nxt_s = sp->slope.nxm + sp->slope.nxp + 1, m->nyt_s = (sp->full ? 2 : 1) * sp->slope.ny + 1;
    m->top_s = malloc((size_t)m->nxt_s * m->nyt_s * sizeof *m->top_s);
    m->n_outer_quads = noq;
    m->outer_quads = malloc((size_t)noq * 4 * sizeof *m->outer_quads);
    if (!m->x || !m->flags || !m->conn || !m->top_b || !m->top_s || !m->outer_quads)
        return rf_fail(err, RF_ENOMEM, "fem3d mesh: out of memory for %ld elements", m->n_elems);
    return RF_OK;
}

/* Boulder, part 1: x -> P + k^2 (x - P)/|x - P|^2. */
static void boulder_part1(const f3_mesh_spec *sp, const ogrid *g1, f3_mesh *m)
{
    const double r = sp->radius, P[3] = {0, 0, 2 * r}, k2 = 4 * r * r;
    for (long id = 0; id < g1->n; id++) {
        double p[3];
        ogrid_point(g1, id, p);
        double d[3] = {p[0] - P[0], p[1] - P[1], p[2] - P[2]};
        double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        for (int a = 0; a < 3; a++)
            m->x[3 * id + a] = P[a] + k2 * d[a] / dd;
        m->flags[id] = ogrid_flags(g1, id) & (F3_SURFACE | F3_SYM);
    }
}

/* Boulder, part 2: inversion about the contact point (kappa^2 = Rb rho_h), then
 * the same map, in one closed form that is smooth at the copy's centre (which
 * lands on the top pole); map2: g2's node ids in the mesh. */
static void boulder_part2(const f3_mesh_spec *sp, const ogrid *g1, const ogrid *g2, long *map2, f3_mesh *m)
{
    const double r = sp->radius, P[3] = {0, 0, 2 * r}, k2 = 4 * r * r;
    const double Rb = sp->boulder_inner * r, rho_h = 1.0, kap2 = Rb * rho_h;
    long next = g1->n;
    for (long id = 0; id < g2->n; id++) {
        int outer = id >= g2->ncore && (id - g2->ncore) / g2->nsurf == g2->K - 1;
        if (outer) { /* shared with the last layer of part 1 */
            long s = (id - g2->ncore) % g2->nsurf;
            map2[id] = layer_id(g1, s, g1->K);
            continue;
        }
        map2[id] = next++;
        double y[3];
        ogrid_point(g2, id, y);
        double yy = y[0] * y[0] + y[1] * y[1] + y[2] * y[2], Py = P[2] * y[2];
        double den = kap2 * kap2 - 2 * kap2 * Py + P[2] * P[2] * yy;
        double *xo = m->x + 3 * map2[id];
        for (int a = 0; a < 3; a++)
            xo[a] = P[a] + k2 * (kap2 * y[a] - P[a] * yy) / den;
        m->flags[map2[id]] = ogrid_flags(g2, id) & (F3_SURFACE | F3_SYM);
    }
}

/* Grid g's elements from mesh element e on, its local node c mapped to
 * map[c] (map NULL: offset + c); returns the next element. */
static long grid_elements(const ogrid *g, const long *map, long offset, f3_mesh *m, long e)
{
    for (long q = 0; q < g->ne; q++, e++) {
        long c[8];
        ogrid_elem(g, q, c);
        for (int a = 0; a < 8; a++)
            m->conn[8 * e + a] = (int)(map ? map[c[a]] : offset + c[a]);
        f3_hex_orient(m->x, m->conn + 8 * e);
    }
    return e;
}

/* The boulder's nodes, elements and top grid; returns the next element. */
static rf_status mesh_boulder(const f3_mesh_spec *sp, const ogrid *g1, const ogrid *g2, f3_mesh *m, long *e,
                              rf_error *err)
{
    boulder_part1(sp, g1, m);
    long *map2 = malloc((size_t)g2->n * sizeof *map2);
    if (!map2)
        return rf_fail(err, RF_ENOMEM, "fem3d mesh: out of memory");
    boulder_part2(sp, g1, g2, map2, m);
    for (long i = 0; i < m->boulder_nodes; i++) { /* spheroid: affine map about the contact point */
        m->x[3 * i] *= sp->scale_xy;
        m->x[3 * i + 1] *= sp->scale_xy;
        m->x[3 * i + 2] *= sp->scale_z;
    }
    *e = grid_elements(g1, NULL, 0, m, 0);
    *e = grid_elements(g2, map2, 0, m, *e);
    free(map2);
    for (int i = 0; i <= g1->NX; i++)
        for (int j = 0; j <= g1->NY; j++)
            m->top_b[i * m->nyt_b + j] = (int)core_id(g1, i, j, g1->NZ);
    return RF_OK;
}

/* The slope as the O-grid itself, from node nb and element e on. */
static void mesh_slope(const ogrid *gs, long nb, long e, f3_mesh *m)
{
    for (long id = 0; id < gs->n; id++) {
        ogrid_point(gs, id, m->x + 3 * (nb + id));
        m->flags[nb + id] = ogrid_flags(gs, id);
    }
    grid_elements(gs, NULL, nb, m, e);
    for (int i = 0; i <= gs->NX; i++)
        for (int j = 0; j <= gs->NY; j++)
            m->top_s[i * m->nyt_s + j] = (int)(nb + core_id(gs, i, j, gs->NZ));
    for (long q = 0; q < gs->nquad; q++)
        for (int a = 0; a < 4; a++)
            m->outer_quads[4 * q + a] = (int)(nb + layer_id(gs, gs->quad[4 * q + a], gs->K));
}

rf_status f3_mesh_build(const f3_mesh_spec *sp, f3_mesh *m, long max_elements, rf_error *err)
{
    memset(m, 0, sizeof *m);
    ogrid g1, g2, gs;
    memset(&g1, 0, sizeof g1), memset(&g2, 0, sizeof g2), memset(&gs, 0, sizeof gs);
    long e = 0;
    rf_status st = mesh_grids(sp, &g1, &g2, &gs, err);
    if (st == RF_OK)
        st = mesh_alloc(sp, &g1, &g2, &gs, max_elements, m, err);
    if (st == RF_OK)
        st = mesh_boulder(sp, &g1, &g2, m, &e, err);
    if (st == RF_OK && sp->extruded)
        st = f3_slab_fill(sp, m, m->boulder_nodes, e, err);
    else if (st == RF_OK)
        mesh_slope(&gs, m->boulder_nodes, e, m);
    ogrid_free(&g1), ogrid_free(&g2), ogrid_free(&gs);
    if (st != RF_OK) {
        f3_mesh_free(m);
        return st;
    }
    m->h_s = sp->slope.h;
    m->x0_s = -sp->slope.nxm * sp->slope.h;
    m->y0_s = sp->full ? -sp->slope.ny * sp->slope.h : 0;
    return RF_OK;
}
